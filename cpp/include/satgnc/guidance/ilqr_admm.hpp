#pragma once
/// @file ilqr_admm.hpp
/// Fuel-optimal (L1) trajectory optimization on nonlinear discrete dynamics by ADMM whose x/u-step is
/// iterative LQR (Le Cleac'h & Manchester, "Fast solution of optimal control problems with L1 cost",
/// Algorithm 1 with the LQR step replaced by Gauss-Newton iLQR).
///
/// Problem (units are those of the DiscreteModel, e.g. scaled or SI):
///   minimize  1/2 (x_N - x_f)^T Q_f (x_N - x_f) + w sum_k g(u_k)
///   s.t.      x_{k+1} = f_k(x_k, u_k),  x_0 given,
/// with g(u) = sum_i alpha_i |u_i| (L1), L1 plus the box lo <= u <= hi, or alpha_0 ||u||_2 (group),
/// and w the stage weight (the published implementation uses w = dt: the cost is an integral).
///
/// ADMM splits u = y: the x/u-step minimizes the smooth augmented Lagrangian
///   1/2 (x_N - x_f)^T Q_f (x_N - x_f) + w sum_k [rho/2 |u_k|^2 + (lambda_k - rho y_k)^T u_k]
/// by iLQR (Gauss-Newton Riccati backward pass with affine terms, Levenberg regularization on Quu,
/// backtracking line search on that augmented Lagrangian), warm-started at the previous U; the y-step
/// is the exact prox of g (soft threshold, soft threshold then clip, block soft threshold); then
/// lambda += rho (U - Y). One iLQR iteration per ADMM iteration reproduces the paper.
#include <Eigen/Core>
#include <chrono>
#include <memory>
#include <vector>

#include "satgnc/core/solver.hpp"
#include "satgnc/core/status.hpp"
#include "satgnc/guidance/nonlinear_model.hpp"

namespace satgnc::guidance {

/// Non-smooth control cost.
enum class ControlCost {
  l1 = 0,       ///< sum_i alpha_i |u_i|
  l1_box = 1,   ///< L1 plus per-axis bounds u_min <= u <= u_max (u_min <= 0 <= u_max)
  group_l2 = 2  ///< alpha_0 ||u||_2 (one gimballed engine)
};

/// Problem data (constant). Dimensions: nx, nu of the model, N intervals.
struct NonlinearL1Problem {
  int horizon = 0;            ///< N, number of control intervals
  Eigen::VectorXd x0;         ///< initial state (nx)
  Eigen::VectorXd x_target;   ///< x_f (nx)
  Eigen::MatrixXd Qf;         ///< terminal weight (nx x nx, symmetric positive semidefinite)
  Eigen::VectorXd alpha;      ///< per-axis L1 weights (nu, >= 0); group_l2 uses alpha(0)
  double stage_weight = 1.0;  ///< w > 0 multiplying the control cost (dt for an integral cost)
  ControlCost cost = ControlCost::l1;
  Eigen::VectorXd u_min, u_max;  ///< bounds (nu) for l1_box
  /// Hard terminal state x_N = x_f on every state except the model's exogenous ones
  /// (DiscreteModel::exogenous_states(), e.g. the target's orbit, which no control changes).
  /// Default false: the soft terminal cost alone. Only ScpSolver with ScpInner::linear_admm
  /// supports it; IlqrAdmmSolver rejects it at setup (std::invalid_argument naming ScpSolver).
  bool terminal_equality = false;
};

/// Stopping rule.
enum class StopRule {
  residuals = 0,  ///< primal ||U - Y|| and dual rho ||Y - Y_prev|| with eps_abs / eps_rel (OSQP style)
  paper = 1,      ///< ||U - Y||_2 / (N nu) <= eps_paper (the published implementation)
};

/// Solver settings (plain data; defaults documented).
struct IlqrAdmmSettings {
  double rho = 0.1;         ///< ADMM penalty (> 0)
  int max_iter = 4000;      ///< ADMM iterations
  int ilqr_iters = 1;       ///< iLQR iterations per ADMM iteration (1 = paper)
  double ilqr_tol = 1e-10;  ///< inner stop: relative decrease of the subproblem cost (ilqr_iters > 1)
  StopRule stop = StopRule::residuals;
  double eps_paper = 6e-5;                ///< paper rule threshold
  double eps_abs = 1e-7;                  ///< residual rule, absolute (per sqrt(N nu))
  double eps_rel = 1e-5;                  ///< residual rule, relative
  bool paper_multiplier_rescale = false;  ///< after iteration 1 scale row i of lambda to max |.| = alpha_i
  bool adaptive_rho = false;   ///< residual balancing (rho *= or /= rho_factor when residuals differ by mu)
  double rho_factor = 5.0;     ///< adaptive rho multiplier
  double rho_balance = 10.0;   ///< adaptive rho triggers when primal/dual ratio exceeds this
  int rho_update_every = 25;   ///< check residual balance every this many iterations
  double reg_init = 0.0;       ///< initial Levenberg term on Quu
  double reg_min = 1e-8;       ///< first nonzero regularization
  double reg_max = 1e10;       ///< give up (status ilqr_failed) beyond this
  double reg_factor = 10.0;    ///< regularization growth
  int line_search_iters = 20;  ///< backtracking halvings
  double ls_lower = 1e-8;      ///< accept when actual/expected decrease lies in [ls_lower, ls_upper]
  double ls_upper = 10.0;
  bool return_best = true;  ///< on max_iter, return the iterate with the smallest ||U - Y|| (else the last)
  /// Wall-clock budget of one solve(), s (0 = none); status time_limit. Checked before every ADMM
  /// iteration and every iLQR iteration / regularization retry inside it, so a solve overruns it by at
  /// most one iLQR iteration (backward pass + line search).
  double time_limit = 0.0;
  /// solved_inaccurate at a limit when the residual rule holds with eps_abs and eps_rel multiplied
  /// by this factor (>= 1) at the returned iterate.
  double inaccurate_factor = 1e3;

  /// Throw std::invalid_argument naming the field on a bad value.
  void validate() const;
};

/// Outcome (core/status.hpp; docs/guidance_nonlinear.md has the table of what each status
/// guarantees). `unsolved` (solve() not called) was `not_run`, kept as a deprecated alias.
using core::IlqrAdmmStatus;
using core::status_message;
using core::status_name;

/// Iteration statistics.
/// From core::InfoBase: status, iterations (ADMM iterations), primal_residual (||U - Y||_2),
/// dual_residual (w rho ||Y - Y_prev||_2) and solve_time (wall time of solve(), s).
struct IlqrAdmmInfo : core::InfoBase<IlqrAdmmStatus> {
  int ilqr_iterations = 0;  ///< total iLQR (backward + forward) iterations
  int lqr_passes = 0;       ///< the implementation's count: ilqr_iterations + one rollout per ADMM iteration
  double paper_criterion = 0;  ///< ||U - Y||_2 / (N nu)
  double objective_u = 0;      ///< true cost at the dense iterate U (rolled out)
  double objective_y = 0;      ///< true cost at the sparse iterate Y (rolled out; +inf if that fails)
  double rho = 0;              ///< final rho
  int rho_updates = 0;
  int failed_interval = -1;  ///< interval k where the model failed (propagation_failed), else -1
  double max_regularization = 0;
  double terminal_miss = 0;  ///< ||x_N - x_f||_2 when Y is flown on the model (+inf if that fails)
};

/// Solution (iterates) and info.
struct IlqrAdmmResult {
  Eigen::MatrixXd X;       ///< nx x (N+1), rollout of U
  Eigen::MatrixXd U;       ///< nu x N, dense (iLQR) iterate
  Eigen::MatrixXd Y;       ///< nu x N, sparse (prox) iterate
  Eigen::MatrixXd Lambda;  ///< nu x N, multipliers of u = y
  IlqrAdmmInfo info;
  /// Old shape of IlqrAdmmSolver::solve(), which returned the status.
  [[deprecated("use solve().info.status")]] operator IlqrAdmmStatus() const noexcept { return info.status; }
};

namespace detail {
struct IlqrAdmmWorkspace;  // src/guidance/detail/ilqr_admm_workspace.hpp: the buffers of IlqrAdmmSolver
}  // namespace detail

/// ADMM with an iLQR step. Workspace (detail::IlqrAdmmWorkspace) allocated in the constructor;
/// solve() does not allocate. Move-only.
class IlqrAdmmSolver {
 public:
  ~IlqrAdmmSolver();
  IlqrAdmmSolver(IlqrAdmmSolver&&) noexcept;
  IlqrAdmmSolver(const IlqrAdmmSolver&) = delete;
  IlqrAdmmSolver& operator=(const IlqrAdmmSolver&) = delete;
  IlqrAdmmSolver& operator=(IlqrAdmmSolver&&) = delete;  // holds a reference to its model

  /// Validates and allocates. Throws std::invalid_argument on inconsistent dimensions, non-finite
  /// data, rho <= 0, negative weights, u_min > u_max or a box excluding 0. The model must outlive
  /// the solver.
  IlqrAdmmSolver(const DiscreteModel& model, const NonlinearL1Problem& problem,
                 const IlqrAdmmSettings& settings = IlqrAdmmSettings());

  /// Initial controls (nu x N) for the next solve; resets Y and Lambda to zero (cold start).
  void set_initial_controls(const Eigen::Ref<const Eigen::MatrixXd>& U0);
  /// Warm start from a previous solution (U, Y, Lambda; nu x N each).
  void warm_start(const Eigen::Ref<const Eigen::MatrixXd>& U, const Eigen::Ref<const Eigen::MatrixXd>& Y,
                  const Eigen::Ref<const Eigen::MatrixXd>& Lambda);
  /// Replace x0 (receding horizon). Throws on wrong size or non-finite values.
  void set_initial_state(const Eigen::Ref<const Eigen::VectorXd>& x0);
  /// Change rho between solves (> 0).
  void set_rho(double rho);
  /// Change IlqrAdmmSettings::time_limit between solves (s, finite, >= 0; 0 = none). No allocation
  /// when the value is valid (SCP passes its remaining time before each subproblem).
  void set_time_limit(double seconds);
  /// Per-stage bounds lo <= y_k <= hi (nu x N each, lo <= hi, may be +-inf), intersected with the
  /// problem's box in the prox (exact for l1 and l1_box; rejected for group_l2). Sequential convex
  /// programming puts its trust region here. The bounds need not contain 0. No allocation.
  void set_stage_bounds(const Eigen::Ref<const Eigen::MatrixXd>& lo,
                        const Eigen::Ref<const Eigen::MatrixXd>& hi);
  /// Drop the per-stage bounds.
  void clear_stage_bounds() { stage_bounds_ = false; }

  /// Run ADMM. No heap allocation, never throws: an exception thrown by the model's step() counts
  /// as a failed step (status propagation_failed with info.failed_interval, or ilqr_failed when a
  /// linearization fails), as a step returning false does. The reference stays valid until the
  /// next solve().
  const IlqrAdmmResult& solve() noexcept;

  const IlqrAdmmResult& result() const noexcept { return res_; }
  const NonlinearL1Problem& problem() const { return prob_; }
  const IlqrAdmmSettings& settings() const { return set_; }

  /// True (nonlinear) cost of a control sequence: rollout + terminal + control cost (box violation
  /// is not penalized here). Returns +inf if the rollout fails. Uses workspace buffers (no allocation).
  double true_cost(const Eigen::Ref<const Eigen::MatrixXd>& U);
  /// Rollout of U into Xout (nx x (N+1)); returns -1 on success or the failing interval (a step
  /// that returned false or threw).
  int rollout(const Eigen::Ref<const Eigen::MatrixXd>& U, Eigen::Ref<Eigen::MatrixXd> Xout) const;

 private:
  double control_cost(const Eigen::Ref<const Eigen::MatrixXd>& U) const;
  double terminal_cost(const Eigen::Ref<const Eigen::VectorXd>& xN) const;
  double subproblem_cost(const Eigen::MatrixXd& X, const Eigen::MatrixXd& U) const;
  bool linearize();
  bool backward_pass(double reg, double& dv1, double& dv2);
  // Forward pass with line search; returns true and updates X, U on acceptance.
  bool forward_pass(double dv1, double dv2, double& J);
  int ilqr_step(double& J);  // 0 = progress, 1 = converged (no decrease), 2 = failed, 3 = out of time
  bool out_of_time() const;  // time_limit set and reached (since solve_start_)
  void prox(const Eigen::MatrixXd& V, Eigen::MatrixXd& Yout) const;

  const DiscreteModel& model_;
  NonlinearL1Problem prob_;
  IlqrAdmmSettings set_;
  int nx_, nu_, N_;
  double rho_;
  IlqrAdmmResult res_;
  bool warm_ = false;
  double reg_ = 0.0;
  std::chrono::steady_clock::time_point solve_start_{};
  bool jac_valid_ = false;  // A_, B_ hold the Jacobians along (X, U)
  int n_exo_ = 0;           // number of exogenous states (DiscreteModel::exogenous_states)
  std::vector<int> exo_idx_, endo_idx_;
  bool stage_bounds_ = false;
  Eigen::MatrixXd Slo_, Shi_;                      // per-stage bounds (set_stage_bounds), nu x N
  std::unique_ptr<detail::IlqrAdmmWorkspace> ws_;  // every buffer, sized in the constructor
};

}  // namespace satgnc::guidance
