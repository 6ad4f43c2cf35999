// The atmosphere drag inside a ForceModel with the gravity branch's terms: the Cd partial covers
// both drag terms (against central differences in Cd), and the drag's Sun is the force model's.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "satgnc/dynamics/atmosphere.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/dynamics/third_body.hpp"
#include "satgnc/frames/earth_rotation.hpp"
#include "testing.hpp"

using satgnc::Vec3;
namespace dyn = satgnc::dynamics;

namespace {

dyn::AtmosphereDrag harris_priester_drag(double cd) {
  dyn::AtmosphereDrag d;
  d.atmosphere = std::make_shared<dyn::HarrisPriester>(6.0);
  d.earth_rotation = std::make_shared<satgnc::frames::UniformRotation>(0.4);
  d.sun = std::make_shared<dyn::FixedSun>(Vec3(0.3, -0.9, 0.2));
  d.cd = cd;
  d.area = 12.0;
  d.mass = 400.0;
  return d;
}

dyn::ExponentialDrag exponential_drag(double cd) {
  dyn::ExponentialDrag e;
  e.rho0 = 3.0e-12;
  e.h0 = 400.0;
  e.scale_height = 60.0;
  e.cd = cd;
  e.area = 12.0;
  e.mass = 400.0;
  return e;
}

// Inclined LEO point at ~400 km and a velocity of ~7.2 km/s.
const Vec3 kR = Vec3(-4502.0, 3870.0, 3420.0).normalized() * (6378.137 + 400.0);
const Vec3 kV(-2.1, -5.3, 4.4);

// Central difference of the total acceleration in a Cd shared by whichever drag terms are present.
Vec3 cd_difference(bool exponential, bool atmosphere, double cd, double h) {
  auto model = [&](double c) {
    dyn::ForceModel f;
    if (exponential) f.drag = exponential_drag(c);
    if (atmosphere) f.atmosphere_drag = harris_priester_drag(c);
    return f;
  };
  return (model(cd + h).acceleration(30.0, kR, kV) - model(cd - h).acceleration(30.0, kR, kV)) / (2.0 * h);
}

}  // namespace

TEST(ForceModelDrag, CdPartialCoversAtmosphereDrag) {
  // The acceleration is linear in Cd, so the central difference is exact up to rounding: |a_drag| ~
  // 1e-9 km/s^2 against |a| ~ 8e-3 km/s^2 gives a relative rounding of 1e-16 * 8e-3 / (1e-9 * 2h) ~
  // 4e-9 with h = 0.1; tolerance 1e-6 relative.
  for (const auto& [exponential, atmosphere] :
       {std::pair{false, true}, std::pair{true, true}, std::pair{true, false}}) {
    dyn::ForceModel f;
    if (exponential) f.drag = exponential_drag(2.2);
    if (atmosphere) f.atmosphere_drag = harris_priester_drag(2.2);
    const Vec3 partial = f.acceleration_partial(dyn::ForceParameter::cd, 30.0, kR, kV);
    const Vec3 fd = cd_difference(exponential, atmosphere, 2.2, 0.1);
    EXPECT_GT(partial.norm(), 1e-12);  // the drag is there: ~1e-9 km/s^2 per unit Cd at 400 km
    SATGNC_EXPECT_REL(partial, fd, 1e-6);
  }
  // Both terms: the partial is the sum of each term's a / Cd (exact, same evaluations).
  dyn::ForceModel both;
  both.drag = exponential_drag(2.2);
  both.atmosphere_drag = harris_priester_drag(2.2);
  const Vec3 sum = dyn::drag_acceleration(exponential_drag(1.0), kR, kV) +
                   dyn::atmosphere_drag_cd_partial(harris_priester_drag(2.2), 30.0, kR, kV);
  SATGNC_EXPECT_REL(both.acceleration_partial(dyn::ForceParameter::cd, 30.0, kR, kV), sum, 1e-15);
}

TEST(ForceModelDrag, CdPartialWithoutDragNamesBothTerms) {
  dyn::ForceModel f;
  try {
    (void)f.acceleration_partial(dyn::ForceParameter::cd, 0.0, kR, kV);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "parameter: cd needs a drag or atmosphere_drag term");
  }
}

TEST(ForceModelDrag, OneSunOneEpoch) {
  // With sun unset the drag's Sun is the ForceModel's ephemeris at the ForceModel's epoch: the same
  // cached ERFA Sun as the third body and SRP. Checked against the drag evaluated with that Sun
  // given, and against the drag with the Sun straight from ERFA (sun_position) to 1e-9
  // (the 1/8-day Hermite Sun is within 1e-13 rad of ERFA, measured).
  dyn::ForceModel fm;
  fm.epoch_jd1 = 2460000.5;
  fm.epoch_jd2 = 0.25;
  fm.atmosphere_drag = harris_priester_drag(2.2);
  fm.atmosphere_drag->sun = nullptr;
  fm.third_body = dyn::ThirdBodies{};
  ASSERT_NO_THROW(fm.validate());
  const Vec3 pm = dyn::point_mass_acceleration(fm.mu, kR);
  for (double t : {0.0, 5000.0, 86400.0 * 3.3}) {
    const Vec3 sun = fm.ephemeris.sun(fm.epoch_jd1, fm.epoch_jd2 + t / 86400.0);
    const Vec3 third =
        dyn::third_body_acceleration(fm.third_body->mu_sun, sun, kR) +
        dyn::third_body_acceleration(fm.third_body->mu_moon,
                                     fm.ephemeris.moon(fm.epoch_jd1, fm.epoch_jd2 + t / 86400.0), kR);
    const Vec3 drag = dyn::atmosphere_drag_acceleration(*fm.atmosphere_drag, t, kR, kV, sun);
    // The Cd partial is the drag term alone (a / Cd): same evaluation, exact to rounding.
    SATGNC_EXPECT_REL(Vec3(2.2 * fm.acceleration_partial(dyn::ForceParameter::cd, t, kR, kV)), drag, 1e-15);
    // The total minus the other terms: |a| ~ 8e-3 km/s^2 against a drag of 3e-9 km/s^2, so the
    // subtraction leaves ~1e-18 / 3e-9 ~ 4e-10 relative rounding (measured 3.6e-10); tolerance 1e-8.
    SATGNC_EXPECT_REL(Vec3(fm.acceleration(t, kR, kV) - pm - third), drag, 1e-8);
    const Vec3 erfa = dyn::sun_position(fm.epoch_jd1, fm.epoch_jd2 + t / 86400.0);
    SATGNC_EXPECT_REL(drag, dyn::atmosphere_drag_acceleration(*fm.atmosphere_drag, t, kR, kV, erfa), 1e-9);
    // The epoch matters: the Sun of 90 days later (~89 deg away) moves the diurnal bulge.
    EXPECT_GT(satgnc::testing::rel_err(drag, dyn::atmosphere_drag_acceleration(
                                                 *fm.atmosphere_drag, t, kR, kV,
                                                 dyn::sun_position(fm.epoch_jd1, 90.25 + t / 86400.0))),
              1e-3);
  }
  // An ErfaSun is accepted only at the ForceModel's epoch, and then gives the ForceModel's Sun.
  fm.atmosphere_drag->sun = std::make_shared<dyn::ErfaSun>(2460000.5, 0.25);
  ASSERT_NO_THROW(fm.validate());
  dyn::ForceModel unset = fm;
  unset.atmosphere_drag->sun = nullptr;
  SATGNC_EXPECT_REL(fm.acceleration(700.0, kR, kV), unset.acceleration(700.0, kR, kV), 1e-15);
  fm.atmosphere_drag->sun = std::make_shared<dyn::ErfaSun>(2451545.0);
  try {
    fm.validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("atmosphere_drag.sun: ErfaSun epoch must equal", 0), 0u)
        << e.what();
  }
}
