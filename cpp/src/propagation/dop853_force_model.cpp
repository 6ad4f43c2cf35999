// DOP853 propagation with the satgnc ForceModel (point mass + optional J2 and drag).
#include "satgnc/core/validate.hpp"
#include "satgnc/propagation/dop853.hpp"

namespace satgnc::propagation {

namespace {
struct Accel {
  const dynamics::ForceModel& fm;
  void operator()(double t, const Vec3& r, const Vec3& v, Vec3& a) const { a = fm.acceleration(t, r, v); }
  void operator()(double t, const Vec3& r, const Vec3& v, Vec3& a, Mat3& da_dr, Mat3& da_dv) const {
    fm.acceleration_jacobians(t, r, v, a, da_dr, da_dv);
  }
};
}  // namespace

Trajectory propagate_dop853(const dynamics::ForceModel& force_model, const Vec6& x0, double t0,
                            const std::vector<double>& times, const Dop853Settings& settings,
                            bool with_stm) {
  force_model.validate();
  const Accel accel{force_model};
  // Without drag nothing depends on v: skip the da/dv * Phi_v products in the variational equations.
  if (force_model.drag.has_value())
    return propagate_dop853_with<true>(accel, x0, t0, times, settings, with_stm);
  return propagate_dop853_with<false>(accel, x0, t0, times, settings, with_stm);
}

}  // namespace satgnc::propagation
