// The atmosphere drag inside a ForceModel with the gravity branch's terms: the Cd partial covers
// both drag terms (against central differences in Cd), and the drag's Sun is the force model's.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "satgnc/dynamics/atmosphere.hpp"
#include "satgnc/dynamics/force_model.hpp"
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
