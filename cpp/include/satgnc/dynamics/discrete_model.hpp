#pragma once
/// @file nonlinear_model.hpp
/// Discrete dynamics x_{k+1} = f_k(x_k, u_k) with Jacobians, the interface the nonlinear guidance
/// solvers (iLQR inside ADMM, sequential convex programming) are written against, and its
/// implementations: linear time-varying, and the two-satellite rendezvous model discretized by an
/// explicit Runge-Kutta rule (with optional diagonal scaling of state, control and time).
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "satgnc/dynamics/two_satellite.hpp"

namespace satgnc::guidance {

/// Discrete dynamics with Jacobians. Implementations must not allocate in step() and must return
/// false (not NaN) when the step fails (model failure, non-finite result).
class DiscreteModel {
 public:
  virtual ~DiscreteModel() = default;
  /// State dimension nx.
  virtual int state_dim() const = 0;
  /// Control dimension nu.
  virtual int control_dim() const = 0;
  /// x_next = f_k(x, u) for interval k (0-based). When A and B are non-null they receive the
  /// Jacobians df/dx (nx x nx) and df/du (nx x nu), column-major. Pointers are to contiguous
  /// arrays of length nx, nu, nx, nx*nx, nx*nu.
  virtual bool step(int k, const double* x, const double* u, double* x_next, double* A, double* B) const = 0;
  /// Indices (0-based, ascending) of exogenous states t: their next value depends neither on the
  /// other states nor on the control (df_t/dx_c = 0 and df_t/du = 0 for every k; e.g. the target's
  /// orbit in the two-satellite model). Solvers may then skip the t-t block of the value function,
  /// which does not enter the gains. Default: none. Called at solver setup only (may allocate).
  virtual std::vector<int> exogenous_states() const { return {}; }
};

/// x_{k+1} = A_k x_k + B_k u_k + c_k. A single (A, B, c) is used for every k when one is given.
class LinearDiscreteModel final : public DiscreteModel {
 public:
  /// Throws std::invalid_argument on inconsistent or non-finite data.
  LinearDiscreteModel(std::vector<Eigen::MatrixXd> A, std::vector<Eigen::MatrixXd> B,
                      std::vector<Eigen::VectorXd> c);
  int state_dim() const override { return nx_; }
  int control_dim() const override { return nu_; }
  bool step(int k, const double* x, const double* u, double* x_next, double* A, double* B) const override;
  /// Number of intervals the model was given data for (1 = time-invariant).
  int intervals() const { return static_cast<int>(A_.size()); }
  /// Overwrite interval k's data in place (no allocation; sizes must match, c only if the model
  /// was built with c). Returns false on a size mismatch or a bad k.
  bool set(int k, const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& B,
           const Eigen::Ref<const Eigen::VectorXd>& c);

 private:
  std::vector<Eigen::MatrixXd> A_, B_;
  std::vector<Eigen::VectorXd> c_;
  int nx_ = 0, nu_ = 0;
};

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
class TwoSatelliteMap final : public DiscreteModel {
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
class PropagatedTwoSatelliteMap final : public DiscreteModel {
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

}  // namespace satgnc::guidance
