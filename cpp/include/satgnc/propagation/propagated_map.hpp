#pragma once
/// @file propagated_map.hpp
/// The two-satellite rendezvous model as a dynamics::DiscreteModel whose map and Jacobians come from
/// adaptive DOP853 integration of the state, its state transition matrix and control sensitivity over
/// each interval. SI units: m, m/s, N, s.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "satgnc/dynamics/discrete_model.hpp"
#include "satgnc/dynamics/two_satellite.hpp"

namespace satgnc::propagation {

/// Settings of the propagated two-satellite map (adaptive DOP853 over each interval).
struct PropagatedMapSettings {
  double dt = 6000.0 / 99.0;  ///< interval length, s (SI)
  /// DOP853 tolerances on the solver's variables (scaled state, STM and control sensitivity when a
  /// scaling is given, else SI: m, m/s): error per component <= atol + rtol |y_i|.
  double rtol = 1e-10;
  double atol = 1e-10;
  long max_steps = 10000;  ///< DOP853 step budget per interval (accepted + rejected)
  /// Both bodies must stay above this geocentric radius, m (default: the Earth's equatorial radius);
  /// below it the right-hand side fails and step() returns false ("inside the Earth").
  double min_radius = 6378.1363e3;
  Eigen::VectorXd state_scale;    ///< 12 entries or empty (as TwoSatelliteMapSettings)
  Eigen::VectorXd control_scale;  ///< 3 entries or empty
};

/// Outcome of the last PropagatedTwoSatelliteMap::step() call (diagnostics).
struct PropagatedMapInfo {
  bool ok = true;
  int interval = -1;       ///< k of the last call
  int status = 0;          ///< propagation::Dop853Status as int (0 = success)
  long steps = 0;          ///< accepted DOP853 steps
  long rejected = 0;       ///< rejected steps
  long rhs_evals = 0;      ///< right-hand-side evaluations
  double t_reached = 0.0;  ///< s from the start of the interval
};

/// The two-satellite model as a DiscreteModel whose map and Jacobians come from integrating, over
/// each interval with u held constant, the 12-state together with its state transition matrix and
/// control sensitivity (satgnc's adaptive DOP853, propagation/dop853.hpp, one 192-dimensional
/// fixed-size system):
///   x' = f(x, u),  Phi' = A Phi,  Gamma' = A Gamma + B,  Phi(0) = I, Gamma(0) = 0,
/// with A = df/dx, B = df/du analytic (TwoSatelliteModel::rhs_jacobians). x_next = x(dt),
/// df_k/dx = Phi(dt), df_k/du = Gamma(dt): the exact derivatives of the flow (to the integrator
/// tolerance), not of a Runge-Kutta transcription. Calls without Jacobians integrate the 12-state
/// alone (own step-size sequence: agrees with the Jacobian call to the tolerance).
/// step() does not allocate; it keeps its integrator work in a mutable workspace, so one object must
/// not be stepped from two threads at once.
class PropagatedTwoSatelliteMap final : public dynamics::DiscreteModel {
 public:
  /// Throws std::invalid_argument on bad settings (dt, tolerances, max_steps <= 0, scale sizes).
  PropagatedTwoSatelliteMap(const dynamics::TwoSatelliteModel& model, const PropagatedMapSettings& settings);
  ~PropagatedTwoSatelliteMap() override;
  PropagatedTwoSatelliteMap(const PropagatedTwoSatelliteMap&) = delete;
  PropagatedTwoSatelliteMap& operator=(const PropagatedTwoSatelliteMap&) = delete;
  int state_dim() const override { return 12; }
  int control_dim() const override { return 3; }
  /// Returns false when the integration fails (non-finite input or derivative, a body below
  /// min_radius, step budget exhausted, step size underflow); last_info() says which.
  bool step(int k, const double* x, const double* u, double* x_next, double* A, double* B) const override;
  /// The target's position and velocity {3, 4, 5, 9, 10, 11} (as TwoSatelliteMap).
  std::vector<int> exogenous_states() const override { return {3, 4, 5, 9, 10, 11}; }
  const dynamics::TwoSatelliteModel& model() const { return model_; }
  const PropagatedMapSettings& settings() const { return s_; }
  const dynamics::Vec12& state_scale() const { return sx_; }
  const Vec3& control_scale() const { return su_; }
  /// Diagnostics of the last step() call.
  const PropagatedMapInfo& last_info() const { return info_; }

 private:
  struct Work;
  dynamics::TwoSatelliteModel model_;
  PropagatedMapSettings s_;
  dynamics::Vec12 sx_;
  Vec3 su_;
  std::unique_ptr<Work> work_;
  mutable PropagatedMapInfo info_;
};

}  // namespace satgnc::propagation
