#include "satgnc/frames/earth_rotation.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "satgnc/core/validate.hpp"

namespace satgnc::frames {

UniformRotation::UniformRotation(double theta0, double omega) : theta0_(theta0), omega_(omega) {
  core::require_finite(theta0, "theta0");
  core::require_finite(omega, "omega");
}

void UniformRotation::rotation(double t, Mat3& gcrf_to_itrf, Vec3& omega_gcrf) const noexcept {
  const double th = theta0_ + omega_ * t;
  const double c = std::cos(th);
  const double s = std::sin(th);
  // r_itrf = R_z(-theta) r_gcrf.
  gcrf_to_itrf << c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0;
  omega_gcrf = Vec3(0.0, 0.0, omega_);
}

}  // namespace satgnc::frames
