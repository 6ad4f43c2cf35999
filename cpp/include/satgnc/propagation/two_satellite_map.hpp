#pragma once
/// @file two_satellite_map.hpp
/// The two-satellite rendezvous model (satgnc/dynamics/two_satellite.hpp) discretized by an explicit
/// Runge-Kutta rule (with optional diagonal scaling of state, control and time), as a
/// dynamics::DiscreteModel, and the published implementation's reference scaling. SI units: m, m/s, N, s.
#include <Eigen/Core>
#include <vector>

#include "satgnc/dynamics/discrete_model.hpp"
#include "satgnc/dynamics/two_satellite.hpp"

namespace satgnc::propagation {

/// Settings of the two-satellite discrete map.
struct TwoSatelliteMapSettings {
  double dt = 6000.0 / 99.0;  ///< interval length, s (SI)
  int scheme = 3;             ///< 3 = Kutta RK3 (published implementation), 4 = classic RK4
  int substeps = 1;           ///< RK steps per interval (control held constant)
  /// Diagonal scaling: the solver sees x_s = x / state_scale and u_s = u / control_scale.
  /// Empty = no scaling (SI units: m, m/s, N).
  Eigen::VectorXd state_scale;    ///< 12 entries (m or m/s per unit)
  Eigen::VectorXd control_scale;  ///< 3 entries (N per unit)
};

/// The two-satellite model (satgnc/dynamics/two_satellite.hpp) as a DiscreteModel: fixed-step
/// Runge-Kutta with u held constant over each interval, Jacobians by differentiating the stages.
class TwoSatelliteMap final : public dynamics::DiscreteModel {
 public:
  /// Throws std::invalid_argument on bad settings (dt <= 0, scheme not 3/4, wrong scale sizes).
  TwoSatelliteMap(const dynamics::TwoSatelliteModel& model, const TwoSatelliteMapSettings& settings);
  int state_dim() const override { return 12; }
  int control_dim() const override { return 3; }
  bool step(int k, const double* x, const double* u, double* x_next, double* A, double* B) const override;
  /// The target's position and velocity {3, 4, 5, 9, 10, 11}: it moves independently of the chaser
  /// and the control.
  std::vector<int> exogenous_states() const override { return {3, 4, 5, 9, 10, 11}; }
  const dynamics::TwoSatelliteModel& model() const { return model_; }
  const TwoSatelliteMapSettings& settings() const { return s_; }
  /// Scaling factors (ones when none were given).
  const dynamics::Vec12& state_scale() const { return sx_; }
  const Vec3& control_scale() const { return su_; }

 private:
  dynamics::TwoSatelliteModel model_;
  TwoSatelliteMapSettings s_;
  dynamics::Vec12 sx_;
  Vec3 su_;
  dynamics::Vec12 inv_sx_;     // 1 / sx_
  dynamics::Mat12 a_ratio_;    // sx_(j) / sx_(i): A_s = A .* a_ratio_
  dynamics::Mat12x3 b_ratio_;  // su_(j) / sx_(i)
};

/// Reference scaling of the published implementation for the nonlinear cases (l1_scenario.md):
/// l_ego = max(|d0|, 1) m, l_target = |r_t0|, t_ref = l_target / (3 sqrt(mu / l_target)) s,
/// velocities l/t_ref, force unit l_ego / t_ref^2 * mass_chaser. Returns (state_scale, control_scale,
/// time_scale) for x0 (SI 12-state).
struct ReferenceScaling {
  Eigen::VectorXd state_scale;    ///< 12
  Eigen::VectorXd control_scale;  ///< 3, N per unit
  double time_scale = 1.0;        ///< s per unit
};
ReferenceScaling published_scaling(const dynamics::Vec12& x0, double mu, double mass_chaser);

}  // namespace satgnc::propagation
