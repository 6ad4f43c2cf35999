// Solar radiation pressure: magnitude at 1 AU, shadow functions (cylindrical, conical: umbra,
// penumbra, annular), the Jacobian (penumbra's d nu/dr included) against 4th-order differences,
// the Cr partial, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "derivative_checks.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/dynamics/srp.hpp"

namespace {
using satgnc::Mat3;
using satgnc::Vec3;
using satgnc::testing::fd4;
namespace dy = satgnc::dynamics;

const Vec3 kSun(dy::kAstronomicalUnitKm, 0.0, 0.0);

TEST(Srp, MagnitudeAtOneAuIsPressureTimesCrAreaOverMass) {
  dy::SolarRadiationPressure p;
  p.area = 20.0;
  p.mass = 1000.0;
  p.cr = 1.5;
  p.shadow = dy::ShadowModel::none;
  // Satellite 1 AU from the Sun (placed so that |r - s| = 1 AU): a = 4.56e-6 * 1.5 * 0.02 m/s^2.
  const Vec3 r(0.0, 0.0, 0.0);
  const Vec3 a = dy::srp_acceleration(p, kSun, r);
  EXPECT_NEAR(a.norm(), 4.56e-6 * 1.5 * 20.0 / 1000.0 * 1e-3, 1e-24);  // exact formula, rounding only
  EXPECT_LT(a.x(), 0.0);                                               // pushed away from the Sun
}

TEST(Srp, ShadowFunctions) {
  dy::SolarRadiationPressure p;
  const double R = p.occulting_radius;
  // Sunlit side and far behind the Earth off-axis: lit.
  p.shadow = dy::ShadowModel::cylindrical;
  EXPECT_EQ(dy::srp_shadow(p, kSun, Vec3(7000.0, 0.0, 0.0)), 1.0);
  EXPECT_EQ(dy::srp_shadow(p, kSun, Vec3(-7000.0, 0.0, 0.0)), 0.0);
  EXPECT_EQ(dy::srp_shadow(p, kSun, Vec3(-7000.0, R + 1.0, 0.0)), 1.0);
  p.shadow = dy::ShadowModel::conical;
  EXPECT_EQ(dy::srp_shadow(p, kSun, Vec3(7000.0, 0.0, 0.0)), 1.0);
  EXPECT_EQ(dy::srp_shadow(p, kSun, Vec3(-7000.0, 0.0, 0.0)), 0.0);  // umbra
  // The umbra cone converges: at 7000 km behind the Earth its radius is R - 7000 tan(a_sun) ~ R - 32.6 km,
  // and the penumbra extends to ~R + 32.6 km. At y = R the satellite sees half the Sun: nu ~ 0.5.
  const double nu_mid = dy::srp_shadow(p, kSun, Vec3(-7000.0, std::sqrt(R * R), 0.0));
  EXPECT_GT(nu_mid, 0.3);
  EXPECT_LT(nu_mid, 0.7);
  EXPECT_EQ(dy::srp_shadow(p, kSun, Vec3(-7000.0, R + 200.0, 0.0)), 1.0);
  EXPECT_EQ(dy::srp_shadow(p, kSun, Vec3(-7000.0, R - 200.0, 0.0)), 0.0);
  // Monotone across the penumbra.
  double prev = -1.0;
  for (double y = R - 60.0; y <= R + 60.0; y += 5.0) {
    const double nu = dy::srp_shadow(p, kSun, Vec3(-7000.0, y, 0.0));
    EXPECT_GE(nu, prev);
    prev = nu;
  }
  // Annular: far beyond the umbra's tip (1.4e6 km) on the axis the Earth's disc sits inside the Sun's:
  // nu = 1 - (b/a)^2 with the apparent radii b (Earth) and a (Sun).
  const Vec3 far(-3.0e6, 0.0, 0.0);
  const double a = std::asin(p.sun_radius / (kSun - far).norm()), b = std::asin(R / far.norm());
  EXPECT_NEAR(dy::srp_shadow(p, kSun, far), 1.0 - b * b / (a * a), 1e-14);
}

TEST(Srp, JacobianMatchesFourthOrderDifferencesLitAndInPenumbra) {
  dy::SolarRadiationPressure p;
  p.area = 10.0;
  p.mass = 500.0;
  const double R = p.occulting_radius;
  for (const Vec3& r : {Vec3(7000.0, 300.0, -200.0), Vec3(-7000.0, R - 10.0, 5.0),
                        Vec3(-7000.0, 3.0, R + 15.0), Vec3(-3.0e6, 100.0, 50.0)}) {
    Vec3 a;
    Mat3 G;
    dy::srp_jacobian(p, kSun, r, a, G);
    SATGNC_EXPECT_REL(dy::srp_acceleration(p, kSun, r), a, 1e-15);
    // h = 0.05 km inside a penumbra ~65 km wide: nu is smooth there (truncation (h/65)^4 ~ 3e-13);
    // rounding 1e-16 |a| / h. Tolerance 1e-6 of the largest entry.
    const Mat3 Gfd = fd4([&](const Vec3& x) { return dy::srp_acceleration(p, kSun, x); }, r, 0.05);
    SATGNC_EXPECT_REL(G, Gfd, 1e-6);
  }
}

TEST(Srp, ForceModelCrPartialAndBadInput) {
  dy::ForceModel fm;
  fm.srp = dy::SolarRadiationPressure{};
  fm.srp->cr = 1.8;
  fm.validate();
  EXPECT_FALSE(fm.conservative());
  const Vec3 r(7000.0, 0.0, 0.0), v(0.0, 7.5, 0.0);
  const Vec3 a_srp = fm.acceleration(0.0, r, v) - dy::point_mass_acceleration(fm.mu, r);
  // d a / d Cr = a_srp / Cr (linear), to the rounding of the subtraction above (|a_pm| / |a_srp| ~ 1e12).
  SATGNC_EXPECT_REL(fm.acceleration_partial(dy::ForceParameter::cr, 0.0, r, v), (a_srp / 1.8).eval(), 1e-3);
  EXPECT_THROW(fm.acceleration_partial(dy::ForceParameter::cd, 0.0, r, v), std::invalid_argument);
  for (auto [field, value] :
       {std::pair<const char*, double>{"area", -1.0}, {"mass", 0.0}, {"mass", -5.0}, {"cr", -0.1}}) {
    dy::ForceModel bad = fm;
    if (std::string(field) == "area") bad.srp->area = value;
    if (std::string(field) == "mass") bad.srp->mass = value;
    if (std::string(field) == "cr") bad.srp->cr = value;
    try {
      bad.validate();
      FAIL() << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind(std::string("srp.") + field + ": must be finite and", 0), 0u)
          << e.what();
    }
  }
}

}  // namespace
