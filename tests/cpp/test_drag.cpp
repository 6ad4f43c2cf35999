// Drag through an AtmosphereModel (Harris-Priester): co-rotation, Jacobians and the Cd partial
// against 4th-order differences, the Sun from ERFA against the almanac, the ForceModel term and the
// STM of CVODES and DOP853 propagations against central differences of whole propagations.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "derivative_checks.hpp"
#include "error_checks.hpp"
#include "malloc_counter.hpp"
#include "satgnc/dynamics/atmosphere.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/frames/earth_rotation.hpp"
#include "satgnc/propagation/cvodes.hpp"
#include "satgnc/propagation/dop853.hpp"

using satgnc::Mat3;
using satgnc::Mat6;
using satgnc::Vec3;
using satgnc::Vec6;
using satgnc::testing::fd4;
namespace dyn = satgnc::dynamics;
namespace prop = satgnc::propagation;

namespace {

dyn::AtmosphereDrag make_drag(double theta0 = 0.7) {
  dyn::AtmosphereDrag d;
  d.atmosphere = std::make_shared<dyn::HarrisPriester>(6.0);
  d.earth_rotation = std::make_shared<satgnc::frames::UniformRotation>(theta0);
  d.sun = std::make_shared<dyn::ErfaSun>(2460000.5);  // 2023-02-24 00:00 TT
  d.cd = 2.3;
  d.area = 12.0;
  d.mass = 400.0;
  return d;
}

// Inclined LEO point at ~405 km geodetic height (latitude 30 deg), off every symmetry plane, and a
// velocity of ~7.2 km/s.
const Vec3 kR = Vec3(-4502.0, 3870.0, 3420.0).normalized() * (6378.137 + 400.0);
const Vec3 kV(-2.1, -5.3, 4.4);

}  // namespace

TEST(AtmosphereDrag, AtRestInItrfFeelsNoDrag) {
  // v = omega x r is the velocity of a point fixed in ITRF: v_rel = 0 exactly, so a = 0 exactly
  // (the null rotation, i.e. UniformRotation(0, omega), and an explicit one with another start).
  for (double theta0 : {0.0, 2.1}) {
    dyn::AtmosphereDrag d = make_drag(theta0);
    if (theta0 == 0.0) d.earth_rotation = nullptr;
    const Vec3 v = Vec3(0.0, 0.0, satgnc::core::earth::omega).cross(kR);
    EXPECT_EQ(dyn::atmosphere_drag_acceleration(d, 100.0, kR, v), Vec3::Zero());
    Vec3 a;
    Mat3 gr, gv;
    dyn::atmosphere_drag_jacobians(d, 100.0, kR, v, a, gr, gv);
    EXPECT_EQ(a, Vec3::Zero());
    EXPECT_EQ(gv, Mat3::Zero());  // da/dw -> 0 as w -> 0
  }
  // And a satellite moving with the inertial frame feels the wind of the rotating atmosphere: its
  // acceleration is along +omega x r (the air pushes it eastwards).
  const dyn::AtmosphereDrag d = make_drag();
  const Vec3 a = dyn::atmosphere_drag_acceleration(d, 0.0, kR, Vec3::Zero());
  EXPECT_GT(a.normalized().dot(Vec3::UnitZ().cross(kR).normalized()), 1.0 - 1e-15);
}

TEST(AtmosphereDrag, MagnitudeIsHalfCdAOverMRhoV2) {
  // |a| = 0.5 Cd A/m rho |v_rel|^2 with rho from the model at the rotated point, units: 1/m -> 1/km.
  const dyn::AtmosphereDrag d = make_drag();
  const double t = 1234.0;
  const double rho = dyn::atmosphere_drag_density(d, t, kR);
  EXPECT_GT(rho, 1e-12);  // ~400 km: a few 1e-12 kg/m^3 (M&G Table 3.8)
  EXPECT_LT(rho, 1e-11);
  const Vec3 w = kV - Vec3(0.0, 0.0, satgnc::core::earth::omega).cross(kR);
  const double expect = 0.5 * d.cd * d.area / d.mass * rho * w.squaredNorm() * 1e3;
  SATGNC_EXPECT_REL(dyn::atmosphere_drag_acceleration(d, t, kR, kV).norm(), expect, 1e-14);
}

TEST(AtmosphereDrag, JacobiansAgainstFourthOrderDifferences) {
  // Steps 1e-2 km and 1e-5 km/s; 4th-order truncation (h/H)^4 ~ 1e-9 with H ~ 60 km. Tolerance 1e-6
  // relative to the largest entry (the one-sided kinks of Harris-Priester sit at table heights: the
  // point is 20 km away from the nearest).
  for (bool erfa_sun : {true, false}) {
    dyn::AtmosphereDrag d = make_drag();
    if (!erfa_sun) d.sun = std::make_shared<dyn::FixedSun>(Vec3(1.0, -2.0, 0.5));
    const double t = 3000.0;
    Vec3 a;
    Mat3 gr, gv;
    dyn::atmosphere_drag_jacobians(d, t, kR, kV, a, gr, gv);
    SATGNC_EXPECT_REL(a, dyn::atmosphere_drag_acceleration(d, t, kR, kV), 1e-15);
    const Mat3 fr =
        fd4([&](const Vec3& r) { return dyn::atmosphere_drag_acceleration(d, t, r, kV); }, kR, 1e-2);
    const Mat3 fv =
        fd4([&](const Vec3& v) { return dyn::atmosphere_drag_acceleration(d, t, kR, v); }, kV, 1e-5);
    SATGNC_EXPECT_REL(gr, fr, 1e-6);
    SATGNC_EXPECT_REL(gv, fv, 1e-8);
    // Cd: the acceleration is linear in Cd, so the partial equals a / Cd (1e-15) and the difference
    // quotient of Cd +- 0.1 (1e-12, rounding of the difference).
    const Vec3 pc = dyn::atmosphere_drag_cd_partial(d, t, kR, kV);
    SATGNC_EXPECT_REL(pc, Vec3(a / d.cd), 1e-15);
    dyn::AtmosphereDrag up = d, dn = d;
    up.cd += 0.1;
    dn.cd -= 0.1;
    const Vec3 fc = (dyn::atmosphere_drag_acceleration(up, t, kR, kV) -
                     dyn::atmosphere_drag_acceleration(dn, t, kR, kV)) /
                    0.2;
    SATGNC_EXPECT_REL(pc, fc, 1e-12);
  }
}

TEST(AtmosphereDrag, SunFromErfaAgainstTheAlmanac) {
  // 2000-01-01 12:00 TT: the Sun's apparent RA 18h 45m 09s, Dec -23 deg 01' 59" (Astronomical
  // Almanac 2000, p. C5). Tolerance 0.01 deg: aberration (20") and nutation (17") are neglected by
  // design (geometric Sun, GCRF axes).
  const dyn::ErfaSun sun(2451545.0);
  const Vec3 s = sun.direction(0.0);
  const double ra = std::atan2(s.y(), s.x()) * 180.0 / M_PI + 360.0;
  const double dec = std::asin(s.z()) * 180.0 / M_PI;
  EXPECT_NEAR(ra, (18.0 + 45.0 / 60.0 + 9.0 / 3600.0) * 15.0, 0.01);
  EXPECT_NEAR(dec, -(23.0 + 1.0 / 60.0 + 59.0 / 3600.0), 0.01);
  EXPECT_NEAR(s.norm(), 1.0, 1e-15);
  // The Hermite table against eraEpv00 itself, at mid-nodes and arbitrary times over the table:
  // 1e-11 rad (the interpolation bound is 4e-12 rad for 6 h nodes).
  double worst = 0.0;
  for (double t = -80000.0; t < 31.0 * 86400.0; t += 7777.7) {
    Vec3 p, v;
    sun.erfa_state(t, p, v);
    worst = std::max(worst, (sun.direction(t) - p.normalized()).norm());
  }
  EXPECT_LT(worst, 1e-11);
  // Outside the table: ERFA directly (half a year later the Sun is on the other side, > 170 deg).
  EXPECT_LT(s.dot(sun.direction(182.6 * 86400.0)), std::cos(170.0 * M_PI / 180.0));
  // Bad input names the argument.
  auto message = [](auto make) { return satgnc::testing::message_of(make, "no throw"); };
  EXPECT_EQ(message([] { dyn::ErfaSun(NAN); }).rfind("epoch_jd1: ", 0), 0u);
  EXPECT_EQ(message([] { dyn::ErfaSun(2451545.0, 0.0, 10.0, 5.0); }).rfind("t_end: must be > t_begin", 0),
            0u);
  EXPECT_EQ(message([] { dyn::ErfaSun(2451545.0, 0.0, 0.0, 1e9, 1.0); }).rfind("node_spacing: ", 0), 0u);
  EXPECT_EQ(message([] { dyn::FixedSun(Vec3::Zero()); }).rfind("direction: must be non-zero", 0), 0u);
}

TEST(AtmosphereDrag, ForceModelTermAndBadInput) {
  dyn::ForceModel fm;
  fm.epoch_jd1 = 2460000.5;  // make_drag's ErfaSun epoch: one epoch (validate refuses another)
  fm.atmosphere_drag = make_drag();
  EXPECT_NO_THROW(fm.validate());
  EXPECT_FALSE(fm.conservative());
  const double t = 50.0;
  // Inside the ForceModel the drag's Sun is the ForceModel's ephemeris (the third body's and SRP's).
  const Vec3 sun = fm.ephemeris.sun(fm.epoch_jd1, fm.epoch_jd2 + t / 86400.0);
  SATGNC_EXPECT_REL(fm.acceleration(t, kR, kV),
                    Vec3(dyn::point_mass_acceleration(fm.mu, kR) +
                         dyn::atmosphere_drag_acceleration(*fm.atmosphere_drag, t, kR, kV, sun)),
                    1e-15);
  // ErfaSun's own table is the same Sun to 1.2e-12 rad (measured over 30 days): the drag alone with it
  // agrees to 1e-9 relative (Harris-Priester's cos^6(psi/2) turns 1e-12 rad into ~1e-11).
  SATGNC_EXPECT_REL(Vec3(fm.acceleration(t, kR, kV) - dyn::point_mass_acceleration(fm.mu, kR)),
                    dyn::atmosphere_drag_acceleration(*fm.atmosphere_drag, t, kR, kV), 1e-9);
  Vec3 a;
  Mat3 gr, gv;
  fm.acceleration_jacobians(t, kR, kV, a, gr, gv);
  Vec3 ad;
  Mat3 dr, dv;
  dyn::atmosphere_drag_jacobians(*fm.atmosphere_drag, t, kR, kV, sun, ad, dr, dv);
  SATGNC_EXPECT_REL(gv, dv, 1e-15);
  auto message = [&](auto edit) {
    dyn::ForceModel f = fm;
    edit(*f.atmosphere_drag);
    try {
      f.validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no throw");
  };
  EXPECT_EQ(message([](dyn::AtmosphereDrag& d) {
              d.atmosphere = nullptr;
            }).rfind("atmosphere_drag.atmosphere: must be set", 0),
            0u);
  EXPECT_EQ(message([](dyn::AtmosphereDrag& d) { d.area = -1.0; }).rfind("atmosphere_drag.area: ", 0), 0u);
  EXPECT_EQ(message([](dyn::AtmosphereDrag& d) { d.mass = 0.0; }).rfind("atmosphere_drag.mass: ", 0), 0u);
  EXPECT_EQ(message([](dyn::AtmosphereDrag& d) { d.cd = -2.0; }).rfind("atmosphere_drag.cd: ", 0), 0u);
  // A null Sun is the force model's Sun; an ErfaSun at another epoch than the ForceModel's is refused.
  EXPECT_EQ(message([](dyn::AtmosphereDrag& d) { d.sun = nullptr; }), "no throw");
  EXPECT_EQ(message([](dyn::AtmosphereDrag& d) {
              d.sun = std::make_shared<dyn::ErfaSun>(2460001.5);
            }).rfind("atmosphere_drag.sun: ErfaSun epoch must equal the force model's epoch", 0),
            0u);
  // Below the ellipsoid: refused by validate_position, naming the argument.
  try {
    fm.validate_position(Vec3(0.0, 0.0, 6300.0), "r");
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("r: is below the WGS-84 ellipsoid", 0), 0u) << e.what();
  }
  EXPECT_NO_THROW(fm.validate_position(Vec3(0.0, 0.0, 6400.0), "r"));  // 43 km above the pole
}

namespace {
// Circular orbit at 300 km (inclined ~50 deg): the velocity is kV's component normal to r, scaled to
// sqrt(mu / |r|).
Vec6 circular_300km() {
  const Vec3 r = kR.normalized() * (6378.137 + 300.0);
  const Vec3 u = (kV - kV.dot(r.normalized()) * r.normalized()).normalized();
  return (Vec6() << r, u * std::sqrt(satgnc::core::earth::mu / r.norm())).finished();
}
const Vec6 kX0 = circular_300km();

// Reference STM: central differences of DOP853 state runs at rtol 1e-14 with steps capped at 2 s,
// steps 0.02 km and 2e-5 km/s. Harris-Priester's gradient jumps at its table heights make the flow only
// piecewise smooth in x0, so differences need small steps (measured against the STM: 2.8e-6 with
// 0.5 km / 5e-4 km/s, 1.1e-7 with 0.1 km, 6e-9 with 0.02 km), and the runs need the capped step:
// state-only runs at a free step lose accuracy across the jumps (docs/atmosphere.md: 2.4e-6 km for
// DOP853 and 2.7e-7 km for CVODES at rtol 1e-13 after 1 h, against 1.3e-10 km for the capped runs).
// Error measured on D^-1 Phi D with D = diag(|r0|, |v0|) so that km and km/s entries weigh alike.
Mat6 fd_stm(const dyn::ForceModel& fm, double t) {
  prop::Dop853Settings s;
  s.rtol = 1e-14;
  s.atol = 1e-15;
  s.h_max = 2.0;
  s.max_steps = 1000000;
  Mat6 fd;
  for (int k = 0; k < 6; ++k) {
    const double h = k < 3 ? 0.02 : 2e-5;
    Vec6 xp = kX0, xm = kX0;
    xp[k] += h;
    xm[k] -= h;
    fd.col(k) = (prop::propagate_dop853(fm, xp, 0.0, {t}, s, false).states.back() -
                 prop::propagate_dop853(fm, xm, 0.0, {t}, s, false).states.back()) /
                (2.0 * h);
  }
  return fd;
}

double stm_error(const Mat6& stm, const Mat6& fd) {
  Vec6 d;
  d << Vec3::Constant(kX0.head<3>().norm()), Vec3::Constant(kX0.tail<3>().norm());
  return satgnc::testing::rel_err(Mat6(d.cwiseInverse().asDiagonal() * stm * d.asDiagonal()),
                                  Mat6(d.cwiseInverse().asDiagonal() * fd * d.asDiagonal()));
}
}  // namespace

TEST(AtmosphereDrag, StmOfCvodesAndDop853AgainstWholePropagations) {
  // Circular 300 km, A/m = 0.5 m^2/kg, Harris-Priester n = 6 with the ERFA Sun, J2, one hour (the
  // orbit stays between 290 and 320 km). Tolerance 5e-8 against the differences (measured 6e-9). The
  // drag's share of the STM is far larger: without the drag the STM differs by more than 1e-5.
  dyn::ForceModel fm;
  fm.epoch_jd1 = 2460000.5;  // make_drag's ErfaSun epoch: one epoch (validate refuses another)
  fm.j2 = dyn::J2Gravity{};
  fm.atmosphere_drag = make_drag();
  fm.atmosphere_drag->area = 200.0;
  const std::vector<double> times = {3600.0};
  auto cvodes = [&](const dyn::ForceModel& m) {
    prop::CvodesSettings s;
    s.rtol = 1e-13;
    s.atol = 1e-15;
    return prop::propagate_cvodes(m, kX0, 0.0, times, s);
  };
  auto dop853 = [&](const dyn::ForceModel& m) {
    prop::Dop853Settings s;
    s.rtol = 1e-13;
    s.atol = 1e-15;
    return prop::propagate_dop853(m, kX0, 0.0, times, s, true);
  };
  const Mat6 fd = fd_stm(fm, times.back());
  EXPECT_LT(stm_error(cvodes(fm).stms.back(), fd), 5e-8);  // measured 6.1e-9
  EXPECT_LT(stm_error(dop853(fm).stms.back(), fd), 5e-8);  // measured 4.5e-9
  // The two integrators' STMs agree far better than the differences can tell (measured 1.2e-9).
  EXPECT_LT(stm_error(cvodes(fm).stms.back(), dop853(fm).stms.back()), 1e-8);
  dyn::ForceModel no_drag = fm;
  no_drag.atmosphere_drag.reset();
  const Mat6 with = dop853(fm).stms.back();
  const Mat6 without = dop853(no_drag).stms.back();
  EXPECT_GT(satgnc::testing::rel_err(without, with), 1e-5);
}

TEST(AtmosphereDrag, EvaluationAllocatesNothing) {
  // The right-hand side of a propagation calls these at every stage: no heap allocation (the ERFA Sun
  // table, inside and outside its span, Harris-Priester, the geodetic point, the ForceModel term).
  dyn::ForceModel fm;
  fm.epoch_jd1 = 2460000.5;  // make_drag's ErfaSun epoch: one epoch (validate refuses another)
  fm.atmosphere_drag = make_drag();
  Vec3 a, sum = Vec3::Zero();
  Mat3 gr, gv;
  g_mallocs = 0;
  g_count = true;
  for (int i = 0; i < 100; ++i) {
    const double t = i * 600.0 + (i % 2 == 0 ? 0.0 : 1e8);  // odd i: outside the table (eraEpv00)
    sum += fm.acceleration(t, kR, kV);
    fm.acceleration_jacobians(t, kR, kV, a, gr, gv);
    sum += a + dyn::atmosphere_drag_cd_partial(*fm.atmosphere_drag, t, kR, kV);
  }
  g_count = false;
  EXPECT_EQ(g_mallocs.load(), 0) << "heap allocations in the drag evaluation";
  EXPECT_TRUE(sum.allFinite());
}
