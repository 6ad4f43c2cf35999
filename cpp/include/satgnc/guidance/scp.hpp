#pragma once
/// @file scp.hpp
/// Sequential convex programming for the nonlinear L1 problem of ilqr_admm.hpp: linearize the
/// discrete dynamics along the current trajectory (the model's exact Jacobians: STM and control
/// sensitivity of each interval), solve the convex L1 subproblem
///   minimize 1/2 (x_N - x_f)' Qf (x_N - x_f) + sum_k w g(u_k)
///   s.t.     x_{k+1} = A_k x_k + B_k u_k + c_k,  c_k = f(xb_k, ub_k) - A_k xb_k - B_k ub_k
/// with IlqrAdmmSolver on the affine model or satgnc's linear ADMM solver (guidance/admm.hpp;
/// warm-started from the previous outer iterate). Globalization (ScpSettings::globalization):
///  * trust_region (default): the subproblem is solved within |U - U_k|_inf <= Delta (per-stage bounds
///    of the inner prox, intersected with the real bounds, for the ilqr_admm inner and L1 costs; else
///    the subproblem's step is scaled into the box), and the ratio rho = actual / predicted decrease of
///    the TRUE nonlinear cost decides: rho < tr_accept rejects the step (the iterate is unchanged) and
///    shrinks Delta, rho > tr_grow_ratio grows it;
///  * line_search: U + t (Y_sub - U) by Armijo backtracking on the true cost.
/// Every accepted step lowers the true cost J (ScpInfo::merit_history is non-increasing), so the
/// returned iterate is always the best one seen. docs/guidance_nonlinear.md tabulates the statuses.
///
/// Hard terminal state (NonlinearL1Problem::terminal_equality, linear_admm inner only): each
/// subproblem enforces the linearized x_N = x_f on the non-exogenous states, posed on those alone (the
/// exogenous trajectory, which no control changes, enters their affine term). Steps are judged on
/// the exact-penalty merit phi = J + mu ||e_c||_2, e_c = (x_N - x_f) on the non-exogenous states, mu
/// kept above the subproblem's terminal multiplier norm. An infeasible subproblem (target outside
/// what the box reaches on the linearization) first triggers feasibility restoration (a step that
/// lowers the true miss ||e_c||: box-constrained least squares on the linearization, backtracking on
/// the rollout); inner_infeasible is reported only where restoration predicts no decrease of the
/// miss, with the inner solver's Farkas certificate and its margin re-evaluated here
/// (ScpInfo::infeasibility_certificate / _margin).
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "satgnc/core/solver.hpp"
#include "satgnc/core/status.hpp"
#include "satgnc/guidance/admm.hpp"
#include "satgnc/guidance/ilqr_admm.hpp"

namespace satgnc::guidance {

/// Solver of the convex subproblem.
enum class ScpInner {
  ilqr_admm = 0,    ///< IlqrAdmmSolver on the affine model (exact LQR-ADMM there; allocation-free)
  linear_admm = 1,  ///< guidance/admm.hpp AdmmSolver (dynamics updated in place: allocation-free)
};

/// How SCP makes its steps safe on the nonlinear model.
enum class ScpGlobalization {
  trust_region = 0,  ///< ratio test on the true cost, box trust region (default)
  line_search = 1,   ///< Armijo backtracking along the subproblem's step
};

/// Settings (plain data).
struct ScpSettings {
  /// Default linear_admm: on random rendezvous problems it solves every subproblem to 1e-9 in a few
  /// hundred iterations, where the iLQR-ADMM inner often stops at max_iter (docs/guidance_nonlinear.md).
  ScpInner inner_solver = ScpInner::linear_admm;
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
  double tol = 1e-9;           ///< solved when predicted decrease <= tol * max(1, J) (and see ScpStatus)
  double armijo = 1e-4;        ///< sufficient-decrease fraction of the predicted decrease (line search)
  int line_search_iters = 30;  ///< halvings of t
  /// For ScpInner::linear_admm (AdmmSettings defaults: residual rule, adaptive rho), except
  /// terminal_tolerance = 1e-10 = 0.1 tol: with a hard terminal state the subproblem's plan must
  /// reach x_f finer than the outer test resolves (1e-6 left predicted decreases of -1e-8 on
  /// random rendezvous: solved_inaccurate where one more inner iteration gives solved), and
  /// eps_gap = 1e-8: the interior-point endgame's plan is accepted at the inner gap test; 1e-5 left
  /// 2 of 25 reachable hard-terminal rendezvous (tests/python/test_scp_terminal.py) at
  /// solved_inaccurate, 1e-7 and 1e-8 solve all, 1e-10 sends the hard-terminal paper case to the
  /// endgame in every outer iteration (200 instead of 55 inner iterations). ipm_after = 35 (the
  /// AdmmSettings default was 35 until 2026-12-03, now 8): with 8 the subproblems' plans come from the
  /// endgame more often and test_scp_matches_independent_slsqp_on_small_horizon[True] ended
  /// solved_inaccurate (predicted decrease above tol = 1e-10 after 3 outer iterations).
  AdmmSettings inner = default_inner();
  static AdmmSettings default_inner() {
    AdmmSettings s;
    s.terminal_tolerance = 1e-10;
    s.eps_gap = 1e-8;
    s.ipm_after = 35;
    return s;
  }
  ScpGlobalization globalization = ScpGlobalization::trust_region;
  /// Initial trust radius Delta on max |U - U_k| (units of the controls); 0 = the first step is
  /// unrestricted and Delta then follows the accepted step lengths.
  double trust_radius = 0.0;
  double tr_accept = 0.1;       ///< accept a step when actual / predicted decrease >= this (in (0, 1))
  double tr_grow_ratio = 0.75;  ///< grow Delta when the ratio exceeds this (in [tr_accept, 1))
  double tr_shrink = 0.25;      ///< Delta *= tr_shrink (times the step length) on a rejection (in (0, 1))
  double tr_grow = 2.0;         ///< Delta = max(Delta, tr_grow * step length) on a very good step (> 1)
  /// No acceptable step (status line_search_failed) once Delta < tr_min * max(1, max |U|).
  double tr_min = 1e-12;
  /// At a limit (max_outer, time_limit, no acceptable step): solved_inaccurate when the last
  /// subproblem was solved (accurately or inaccurately) and predicted <= tol_inaccurate * max(1, J).
  double tol_inaccurate = 1e-5;
  /// Wall-clock budget of solve(), s (0 = none). Checked before each outer iteration, after each
  /// linearization and each line-search trial, and passed to the inner solver as the remaining time
  /// (the smaller of that and the inner settings' own limit), so a solve overruns it by at most one
  /// inner iteration plus one rollout.
  double time_limit = 0.0;
  /// Hard terminal state: solved needs ||e_c||_2 <= terminal_tol * r on the returned iterate, with
  /// r = max(||e_c(x0)||, ||e_c(initial guess)||), e_c(x) = (x - x_f) on the non-exogenous states;
  /// solved_inaccurate needs terminal_tol_inaccurate * r.
  double terminal_tol = 1e-6;
  double terminal_tol_inaccurate = 1e-4;
  /// Throw std::invalid_argument naming the field on a bad value.
  void validate() const;
};

/// Outcome (core/status.hpp). Whatever the status, the returned U is the iterate of lowest true cost
/// seen (never NaN; ScpInfo::objective is its true cost, +inf only when even the initial guess does
/// not roll out). `solved`: predicted decrease <= tol * max(1, J) on a subproblem that was solved
/// (inner solved status), not limited by the trust region, at an iterate inside the bounds that
/// rolls out on the model (hard terminal state: and ||e_c|| <= terminal_tol * r, see
/// ScpSettings::terminal_tol). `unsolved` (solve() not called) was `not_run`, kept as a deprecated
/// alias.
using core::ScpStatus;
using core::status_message;
using core::status_name;

/// Diagnostics of the last solve. From core::InfoBase: status, iterations (= outer_iterations,
/// mirrored), primal_residual (= terminal_constraint_miss, mirrored), dual_residual
/// (= predicted_decrease, mirrored) and solve_time (wall time of solve(), s).
struct ScpInfo : core::InfoBase<ScpStatus> {
  int outer_iterations = 0;
  int inner_iterations = 0;         ///< total ADMM iterations over all subproblems
  double objective = 0.0;           ///< true cost of U (rolled out on the model)
  double predicted_decrease = 0.0;  ///< of the last subproblem
  double last_step = 0.0;           ///< accepted t of the last outer iteration
  int failed_interval = -1;
  AdmmStatus inner_status = AdmmStatus::unsolved;               ///< linear_admm inner, last subproblem
  IlqrAdmmStatus inner_ilqr_status = IlqrAdmmStatus::unsolved;  ///< ilqr_admm inner, last subproblem
  bool inner_solved = false;   ///< the last subproblem's inner status was an accurate "solved"
  double terminal_miss = 0.0;  ///< ||x_N - x_f||_2 of the returned iterate (model units)
  /// ||e_c||_2: x_N - x_f on the non-exogenous states (what a hard terminal state constrains)
  double terminal_constraint_miss = 0.0;
  double terminal_reference = 0.0;  ///< r of ScpSettings::terminal_tol (hard terminal state)
  double penalty = 0.0;             ///< final merit penalty mu (hard terminal state, else 0)
  int penalty_updates = 0;          ///< increases of mu after the first one (each may raise the merit)
  /// inner_infeasible: the inner solver's certificate y (nx, unit norm; zeros otherwise) and the
  /// margin y'(x_f - x_N(0)) - max over the box of y' M U on the last linearization (> 0 proves that
  /// no control inside the box reaches x_f on it). Capacity reserved at setup.
  Eigen::VectorXd infeasibility_certificate;
  double infeasibility_margin = 0.0;
  double bound_violation = 0.0;  ///< max violation of the control bounds by the returned U (0 inside)
  int rejected_steps = 0;        ///< trust-region rejections / failed line searches
  /// Hard terminal state: accepted feasibility-restoration steps (each lowers the true miss
  /// ||e_c||; the merit may rise).
  int restoration_steps = 0;
  double trust_radius = 0.0;  ///< final Delta (+inf while unrestricted)
  /// True cost J of the iterate: entry 0 the initial guess, entry i after outer iteration i
  /// (unchanged by a rejected step). Non-increasing. Capacity reserved at setup. With a hard
  /// terminal state the merit J + mu ||e_c||_2 at the mu of that iteration: non-increasing when
  /// penalty_updates == 0 and restoration_steps == 0 (an increase of mu raises the merit of the same
  /// iterate; a restoration step lowers the miss, not the merit).
  std::vector<double> merit_history;
};

/// Solution and info (arrays sized at setup).
struct ScpResult {
  Eigen::MatrixXd X;       ///< nx x (N+1), rollout of U on the model
  Eigen::MatrixXd U;       ///< nu x N
  Eigen::MatrixXd Lambda;  ///< multipliers of the last subproblem
  ScpInfo info;
  /// Old shape of ScpSolver::solve(), which returned the status.
  [[deprecated("use solve().info.status")]] operator ScpStatus() const noexcept { return info.status; }
};

namespace detail {
struct ScpWorkspace;  // src/guidance/detail/scp_workspace.hpp: the scratch buffers of ScpSolver
}  // namespace detail

/// Sequential convex programming solver. solve() does not allocate with either inner solver (the
/// linear AdmmSolver is built once and re-linearized with AdmmSolver::update_dynamics).
class ScpSolver {
 public:
  /// Validates (std::invalid_argument) with the same rules as IlqrAdmmSolver.
  ScpSolver(const DiscreteModel& model, const NonlinearL1Problem& problem,
            const ScpSettings& settings = ScpSettings());
  ~ScpSolver();
  ScpSolver(const ScpSolver&) = delete;
  ScpSolver& operator=(const ScpSolver&) = delete;
  /// Initial control guess (nu x N); default zeros.
  void set_initial_controls(const Eigen::Ref<const Eigen::MatrixXd>& U0);
  /// Initial state (receding horizon).
  void set_initial_state(const Eigen::Ref<const Eigen::VectorXd>& x0);
  /// Run SCP (never throws). The reference stays valid until the next solve().
  const ScpResult& solve() noexcept;
  const ScpResult& result() const noexcept { return res_; }

 private:
  int rollout(const Eigen::MatrixXd& U, Eigen::MatrixXd& X) const;
  double true_cost(const Eigen::MatrixXd& U, Eigen::MatrixXd& X) const;
  double control_cost(const Eigen::MatrixXd& U) const;
  double terminal_cost(const Eigen::Ref<const Eigen::VectorXd>& xN) const;
  double model_cost(const Eigen::MatrixXd& U);  // convex model (affine rollout) at U, merit with mu_
  // Feasibility restoration at the current iterate (hard terminal state, infeasible subproblem):
  // 1 = step accepted, 0 = no predicted decrease of the miss (stationary), 2 = rejected, -1 = failed,
  // -2 = out of time (time_left > 0: the remaining time, passed to the restoration solver).
  int restore(double& J, double time_left);
  double constraint_miss(const Eigen::Ref<const Eigen::VectorXd>& xN) const;  // ||e_c||_2
  double infeasibility_margin(const Eigen::VectorXd& y);  // on the inner's current linearization
  void reduce_linearization();  // sub_ (full) -> red_ (non-exogenous states), hard terminal only
  ScpStatus solve_impl();

  const DiscreteModel& model_;
  NonlinearL1Problem prob_;
  ScpSettings set_;
  IlqrAdmmSolver checker_;  // validation; its model is the nonlinear one
  int nx_, nu_, N_;
  std::unique_ptr<LinearDiscreteModel> lin_;
  std::unique_ptr<IlqrAdmmSolver> inner_;
  std::unique_ptr<AdmmSolver> admm_;
  std::unique_ptr<AdmmSolver> elastic_;  // restoration: min 1/2 ||e_c||^2 on the linearization, box
  ScpResult res_;
  Eigen::VectorXd lo_, hi_;  // real bounds (+-inf without a box)
  bool hard_ = false;        // hard terminal state
  double mu_ = 0.0;          // merit penalty
  std::vector<char> is_exo_;
  bool has_exo_ = false;
  bool reduced_ = false;   // hard terminal with exogenous states: the inner sees red_
  std::vector<int> endo_;  // non-exogenous state indices
  LtvProblem red_;         // the subproblem on the non-exogenous states
  LtvProblem sub_;
  std::unique_ptr<detail::ScpWorkspace> ws_;  // scratch buffers, sized in the constructor
};

}  // namespace satgnc::guidance
