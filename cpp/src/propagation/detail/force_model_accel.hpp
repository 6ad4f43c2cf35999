#pragma once
// Private: the acceleration functors through which DOP853 sees a ForceModel, and the one dispatch
// that picks them (propagate_dop853 and the ensemble share it, so an ensemble member runs exactly
// the arithmetic of the single-arc call).
#include <cmath>
#include <type_traits>
#include <utility>

#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/force_model.hpp"

namespace satgnc::propagation::detail {

/// Any ForceModel, through its out-of-line acceleration / acceleration_jacobians.
struct ForceModelAccel {
  const dynamics::ForceModel& fm;
  void operator()(double t, const Vec3& r, const Vec3& v, Vec3& a) const { a = fm.acceleration(t, r, v); }
  void operator()(double t, const Vec3& r, const Vec3& v, Vec3& a, Mat3& da_dr, Mat3& da_dv) const {
    fm.acceleration_jacobians(t, r, v, a, da_dr, da_dv);
  }
};

/// Two-body fast path: the same formulas as the force model's point mass, inlined into the right-hand
/// side (saves ~25 % of a 2 h arc with STM against the out-of-line ForceModel call).
struct PointMassAccel {
  double mu;
  void operator()(double, const Vec3& r, const Vec3&, Vec3& a) const {
    const double r2 = r.squaredNorm();
    a = (-mu / (r2 * std::sqrt(r2))) * r;
  }
  void operator()(double, const Vec3& r, const Vec3&, Vec3& a, Mat3& da_dr, Mat3& da_dv) const {
    const double x = r[0], y = r[1], z = r[2];
    const double r2 = x * x + y * y + z * z;
    const double k = mu / (r2 * std::sqrt(r2));
    const double c = 3.0 * k / r2;
    a = Vec3(-k * x, -k * y, -k * z);
    da_dr << c * x * x - k, c * x * y, c * x * z,  //
        c * x * y, c * y * y - k, c * y * z,       //
        c * x * z, c * y * z, c * z * z - k;
    da_dv.setZero();
  }
};

/// True when fm holds nothing but the point mass and J2 (the terms the inlined and lane kernels know).
inline bool point_mass_j2_only(const dynamics::ForceModel& fm) {
  return !fm.drag && !fm.atmosphere_drag && !fm.gravity && !fm.third_body && !fm.srp;
}

/// Call f(accel, std::integral_constant<bool, VelocityDependent>{}) with the functor that serves
/// `fm`: the inlined point mass when the model has no perturbation, else the ForceModel itself;
/// velocity-dependent (the da/dv products of the variational equations) when it holds a drag term.
/// A new force term must make point_mass_j2_only false.
template <class F>
decltype(auto) with_force_model_accel(const dynamics::ForceModel& fm, F&& f) {
  if (!fm.j2 && point_mass_j2_only(fm)) return std::forward<F>(f)(PointMassAccel{fm.mu}, std::false_type{});
  // Only drag depends on v (an SRP shadow makes the model non-conservative but has no da/dv).
  if (fm.drag || fm.atmosphere_drag) return std::forward<F>(f)(ForceModelAccel{fm}, std::true_type{});
  return std::forward<F>(f)(ForceModelAccel{fm}, std::false_type{});
}

}  // namespace satgnc::propagation::detail
