// Two-satellite discrete map: fixed-step Runge-Kutta with Jacobians by differentiating the stages.
#include "satgnc/propagation/two_satellite_map.hpp"

#include <cmath>
#include <string>

#include "detail/map_scaling.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::propagation {

using core::require;

TwoSatelliteMap::TwoSatelliteMap(const dynamics::TwoSatelliteModel& model,
                                 const TwoSatelliteMapSettings& settings)
    : model_(model), s_(settings) {
  core::require_positive(s_.dt, "dt");
  require(s_.scheme == 3 || s_.scheme == 4, "scheme", "must be 3 (Kutta RK3) or 4 (classic RK4)");
  require(s_.substeps >= 1, "substeps", "must be >= 1");
  detail::set_map_scaling(s_.state_scale, s_.control_scale, sx_, su_);
  inv_sx_ = sx_.cwiseInverse();
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 12; ++i) a_ratio_(i, j) = sx_(j) / sx_(i);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 12; ++i) b_ratio_(i, j) = su_(j) / sx_(i);
}

bool TwoSatelliteMap::step(int /*k*/, const double* x, const double* u, double* x_next, double* A,
                           double* B) const {
  using dynamics::Mat12;
  using dynamics::Mat12x3;
  using dynamics::Vec12;
  const Vec12 xs = Eigen::Map<const Vec12>(x).cwiseProduct(sx_);
  const Vec3 us = Eigen::Map<const Vec3>(u).cwiseProduct(su_);
  const double h = s_.dt / s_.substeps;
  Vec12 z = xs, zn;
  const bool jac = A != nullptr && B != nullptr;
  Mat12 Phi, Ak;  // no initialization needed: the first substep writes them
  Mat12x3 Gam, Bk;
  for (int i = 0; i < s_.substeps; ++i) {
    if (!jac) {
      if (!model_.rk_step(s_.scheme, h, z, us, zn)) return false;
    } else if (i == 0) {
      if (!model_.rk_step(s_.scheme, h, z, us, zn, &Phi, &Gam)) return false;
    } else {
      if (!model_.rk_step(s_.scheme, h, z, us, zn, &Ak, &Bk)) return false;
      Gam = Ak * Gam + Bk;
      Phi = Ak * Phi;
    }
    z = zn;
  }
  Eigen::Map<Vec12> xn_map(x_next);
  xn_map = z.cwiseProduct(inv_sx_);
  if (jac) {
    // scaled: A_s = Sx^-1 A Sx, B_s = Sx^-1 B Su (ratios precomputed: no division per entry)
    Eigen::Map<Mat12> a_map(A);
    Eigen::Map<Mat12x3> b_map(B);
    a_map = Phi.cwiseProduct(a_ratio_);
    b_map = Gam.cwiseProduct(b_ratio_);
  }
  return z.allFinite();
}

ReferenceScaling published_scaling(const dynamics::Vec12& x0, double mu, double mass_chaser) {
  core::require_finite(x0, "x0");
  core::require_positive(mu, "mu");
  core::require_positive(mass_chaser, "mass_chaser");
  const double l_ego = std::max(x0.head<3>().norm(), 1.0);
  const double l_t = x0.segment<3>(3).norm();
  core::require_positive(l_t, "|r_target|");
  const double v_t = 3.0 * std::sqrt(mu / l_t);
  const double t_ref = l_t / v_t;
  const double v_ego = l_ego / t_ref;
  ReferenceScaling s;
  s.state_scale.resize(12);
  s.state_scale << l_ego, l_ego, l_ego, l_t, l_t, l_t, v_ego, v_ego, v_ego, v_t, v_t, v_t;
  s.control_scale = Eigen::Vector3d::Constant(l_ego / (t_ref * t_ref) * mass_chaser);
  s.time_scale = t_ref;
  return s;
}

}  // namespace satgnc::propagation
