#pragma once
/// @file scp.hpp
/// Sequential convex programming for the nonlinear L1 problem of ilqr_admm.hpp: linearize the
/// discrete dynamics along the current trajectory (the model's exact Jacobians: STM and control
/// sensitivity of each interval), solve the convex L1 subproblem
///   minimize 1/2 (x_N - x_f)' Qf (x_N - x_f) + sum_k w g(u_k)
///   s.t.     x_{k+1} = A_k x_k + B_k u_k + c_k,  c_k = f(xb_k, ub_k) - A_k xb_k - B_k ub_k
/// with satgnc's linear ADMM solver (guidance/admm.hpp; warm-started from the previous outer
/// iterate, adaptive rho), and accept U + t (Y_sub - U) by a backtracking (Armijo) line search on the
/// TRUE nonlinear cost (terminal miss included through Qf). Stops when the decrease the convex model
/// predicts falls below tol * max(1, J).
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "satgnc/guidance/admm.hpp"
#include "satgnc/guidance/ilqr_admm.hpp"

namespace satgnc::guidance {

/// Solver of the convex subproblem.
enum class ScpInner {
  ilqr_admm = 0,    ///< IlqrAdmmSolver on the affine model (exact LQR-ADMM there; allocation-free)
  linear_admm = 1,  ///< guidance/admm.hpp AdmmSolver (dynamics updated in place: allocation-free)
};

/// Settings (plain data).
struct ScpSettings {
  ScpInner inner_solver = ScpInner::ilqr_admm;
  IlqrAdmmSettings inner_ilqr = default_inner_ilqr();  ///< for ScpInner::ilqr_admm
  static IlqrAdmmSettings default_inner_ilqr() {
    IlqrAdmmSettings s;
    s.rho = 1.0;
    s.adaptive_rho = true;
    s.eps_abs = 1e-8;
    s.eps_rel = 1e-8;
    s.max_iter = 20000;
    return s;
  }
  int max_outer = 30;          ///< outer (re-linearization) iterations
  double tol = 1e-9;           ///< stop when predicted decrease <= tol * max(1, J)
  double armijo = 1e-4;        ///< sufficient-decrease fraction of the predicted decrease
  int line_search_iters = 30;  ///< halvings of t
  AdmmSettings inner;          ///< for ScpInner::linear_admm (defaults: residual rule, adaptive rho)
  void validate() const;
};

/// Outcome.
enum class ScpStatus {
  solved = 0,          ///< predicted decrease below tol
  max_outer,           ///< max_outer reached
  propagation_failed,  ///< the model failed on ScpInfo::failed_interval (initial rollout or linearization)
  inner_failed,        ///< the convex subproblem solver failed (ScpInfo::inner_status)
  line_search_failed,  ///< no step decreased the true cost; the current iterate is returned
  not_run,
};
const char* status_message(ScpStatus s);

struct ScpInfo {
  ScpStatus status = ScpStatus::not_run;
  int outer_iterations = 0;
  int inner_iterations = 0;         ///< total ADMM iterations over all subproblems
  double objective = 0.0;           ///< true cost of U (rolled out on the model)
  double predicted_decrease = 0.0;  ///< of the last subproblem
  double last_step = 0.0;           ///< accepted t of the last outer iteration
  int failed_interval = -1;
  AdmmStatus inner_status = AdmmStatus::kUnsolved;             ///< linear_admm inner
  IlqrAdmmStatus inner_ilqr_status = IlqrAdmmStatus::not_run;  ///< ilqr_admm inner
};

struct ScpResult {
  Eigen::MatrixXd X;       ///< nx x (N+1), rollout of U on the model
  Eigen::MatrixXd U;       ///< nu x N
  Eigen::MatrixXd Lambda;  ///< multipliers of the last subproblem
  ScpInfo info;
};

/// Sequential convex programming solver. solve() does not allocate with either inner solver (the
/// linear AdmmSolver is built once and re-linearized with AdmmSolver::update_dynamics).
class ScpSolver {
 public:
  /// Validates (std::invalid_argument) with the same rules as IlqrAdmmSolver.
  ScpSolver(const DiscreteModel& model, const NonlinearL1Problem& problem,
            const ScpSettings& settings = ScpSettings());
  /// Initial control guess (nu x N); default zeros.
  void set_initial_controls(const Eigen::Ref<const Eigen::MatrixXd>& U0);
  /// Initial state (receding horizon).
  void set_initial_state(const Eigen::Ref<const Eigen::VectorXd>& x0);
  /// Run SCP (never throws).
  ScpStatus solve() noexcept;
  const ScpResult& result() const { return res_; }

 private:
  int rollout(const Eigen::MatrixXd& U, Eigen::MatrixXd& X) const;
  double true_cost(const Eigen::MatrixXd& U, Eigen::MatrixXd& X) const;
  double control_cost(const Eigen::MatrixXd& U) const;

  const DiscreteModel& model_;
  NonlinearL1Problem prob_;
  ScpSettings set_;
  IlqrAdmmSolver checker_;  // validation; its model is the nonlinear one
  int nx_, nu_, N_;
  std::unique_ptr<LinearDiscreteModel> lin_;
  std::unique_ptr<IlqrAdmmSolver> inner_;
  std::unique_ptr<AdmmSolver> admm_;
  ScpResult res_;
  Eigen::MatrixXd Ytmp_, Utmp_, Xtmp_, Ywarm_, Lwarm_;
  LtvProblem sub_;
};

}  // namespace satgnc::guidance
