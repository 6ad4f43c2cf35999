#pragma once
/// @file admm.hpp
/// Fuel-optimal (L1) guidance by ADMM with a Riccati step (l1_admm_rendezvous.md, Algorithm 1, and
/// an OSQP-style solver around it: residual stopping, adaptive rho, over-relaxation, warm start,
/// exact prox of L1 + box and of group-L2 + ball, exact hard terminal state).
///
/// Problem (units of the caller; the scenario uses the paper's scaled units or m, m/s, N):
///   minimize   1/2 (x_N - x_f)' Qf (x_N - x_f) + sum_{k=1}^{N-1} 1/2 (x_k - x_f)' Q (x_k - x_f)
///            + sum_{k=0}^{N-1} [ 1/2 u_k' R u_k + sum_i w_i |u_{k,i}| + w_g ||u_k||_2 ]
///   subject to x_{k+1} = A_k x_k + B_k u_k + c_k,  x_0 given,
///              u_lower <= u_k <= u_upper (per axis),  ||u_k||_2 <= u_norm_max,
///              x_N = x_f (if terminal_equality).
/// Splitting: U (dynamics side, Riccati step) = Y (sparse side, closed-form prox); Lambda is the
/// unscaled multiplier of U - Y = 0. Usage:
///   AdmmSolver s(problem, settings);  // validates, allocates (throws std::invalid_argument)
///   const AdmmResult& r = s.solve();  // never throws, never allocates; see r.info.status
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>
#include <type_traits>
#include <vector>

#include "satgnc/core/solver.hpp"
#include "satgnc/core/status.hpp"
#include "satgnc/guidance/riccati.hpp"

namespace satgnc::guidance {

namespace detail {
struct AdmmWorkspace;  // src/guidance/detail/admm_workspace.hpp: all private data and steps
}  // namespace detail

/// Constant problem data (see file comment). Time-invariant A, B: pass one matrix each.
struct LtvProblem {
  LtvDynamics dynamics;
  Eigen::VectorXd x0;              ///< initial state (nx)
  Eigen::VectorXd xf;              ///< target state (nx); zeros if empty
  Eigen::MatrixXd Qf;              ///< terminal weight nx x nx, PSD
  Eigen::MatrixXd Q;               ///< stage state weight nx x nx, PSD, or empty (none)
  Eigen::MatrixXd R;               ///< stage control weight nu x nu, PSD, or empty (none)
  Eigen::VectorXd l1_weights;      ///< per-axis L1 weights w_i >= 0 (nu), or empty (none)
  double group_l2_weight = 0.0;    ///< w_g >= 0: cost of one gimballed engine ||u_k||_2
  Eigen::VectorXd u_lower;         ///< per-axis lower bounds (nu, may be -inf) or empty
  Eigen::VectorXd u_upper;         ///< per-axis upper bounds (nu, may be +inf) or empty
  double u_norm_max = 0.0;         ///< ||u_k||_2 bound (> 0), 0 = none; only with group-L2 / no L1, no box
  bool terminal_equality = false;  ///< enforce x_N = x_f exactly
};

/// Stopping rule.
enum class StoppingRule {
  kResiduals = 0,  ///< OSQP-like: primal ||U-Y||_inf and dual rho ||Y-Y_prev||_inf residuals
  kPaper = 1,      ///< published implementation: ||U - Y||_F / (N nu) <= paper_eps
};

/// Solution method (AdmmSettings::method).
enum class AdmmMethod {
  kAdmm = 0,     ///< ADMM with its polishes only (the published algorithm's path)
  kAdmmIpm = 1,  ///< ADMM, and the interior-point endgame at iteration ipm_after if not yet solved
  kIpm = 2,      ///< the interior-point method alone (L1 + box problems; no ADMM iterations)
};

/// Solver settings (plain struct; defaults solve the scenario cases to ~1e-6 relative).
struct AdmmSettings {
  double rho = 0.2;            ///< initial penalty (> 0)
  int max_iterations = 10000;  ///< >= 1
  StoppingRule stopping = StoppingRule::kResiduals;
  double eps_abs = 1e-7;                  ///< absolute tolerance on both residuals (>= 0)
  double eps_rel = 1e-6;                  ///< relative tolerance (>= 0)
  double paper_eps = 1e-3;                ///< threshold of the paper's rule (> 0)
  double relaxation = 1.8;                ///< over-relaxation alpha in (0, 2); 1 = none (paper)
  bool adaptive_rho = true;               ///< residual balancing (OSQP rule)
  int adaptive_rho_interval = 25;         ///< iterations between rho checks
  double adaptive_rho_tolerance = 5.0;    ///< refactor only if rho changes by more than this factor
  double rho_min = 1e-12, rho_max = 1e6;  ///< bounds of adaptive rho (on the equilibrated problem)
  bool cache_gains = true;                ///< false: full Riccati recursion every iteration (reference)
  /// Condensed x/u step when the problem has no stage state cost (Q = 0) and R is empty or
  /// diagonal: x_N = x_N(U = 0) + M vec(U) with M = [Phi(N, k+1) B_k]_k, so the LQR step is two
  /// products with the stored nx x N nu matrix M and one cached nx x nx LU (refactored with rho).
  /// Same iterates as the cached-gain Riccati step (tested to 1e-10), but the work is independent
  /// across stages (vectorizable) instead of two serial recursions. Ignored with cache_gains = false
  /// and for a hard terminal state outside the reachable subspace (the Riccati step reports that).
  bool condensed = true;
  bool paper_multiplier_rescale = false;  ///< after iteration 1 scale row i of Lambda to max |.| = w_i
  int paper_global_rescale_iterations =
      0;                   ///< then scale all of Lambda to max |.| = max w up to this iteration
  bool track_best = true;  ///< keep the best iterate (returned on kMaxIterations)
  /// Active-set polish (residual rule only; problems without stage Q, group-L2 or ball): every
  /// polish_interval iterations, fix the zero and saturated entries of Y, solve the reduced KKT
  /// system for the others exactly and accept it if it satisfies the optimality conditions
  /// (a certificate: the result is then the exact optimum up to rounding).
  bool polish = true;
  int polish_interval = 5;         ///< >= 1
  int polish_max_free = 0;         ///< largest free set classified; 0 = 8 nx (capped at N nu)
  double polish_tolerance = 1e-7;  ///< relative tolerance of the optimality check
  /// Also guess the active set from the dual estimate -grad f(U) (L1 weights all > 0, no R): free
  /// where |grad_i| / w_i is nearest 1, zero / bound on either side; tried when the guess repeats or
  /// every polish_interval iterations; it identifies the optimum earlier than Y's sparsity pattern.
  bool polish_dual = true;
  int polish_swaps = 3;  ///< local repairs of a rejected dual guess (>= 0; one KKT solve each)
  /// Optimality test of kSolved (residual rule): besides the residuals, the relative duality gap
  /// (P - D) / max(|P|, |D|, gap_floor) of the flown plan Y must be in [-eps_gap, eps_gap] (P the
  /// objective of Y, D a Fenchel dual bound, see AdmmInfo::duality_gap; below -eps_gap the plan's
  /// terminal miss lowers its cost beyond the tolerance). 0 disables the gap test (not advised).
  double eps_gap = 1e-5;
  double gap_floor = 1e-300;  ///< denominator floor of the relative gap (objective units, >= 0)
  /// With a hard terminal state, kSolved also needs the flown plan's terminal miss
  /// ||x_N(Y) - x_f||_2 <= terminal_tolerance x ||x_N(0) - x_f||_2 (the miss of doing nothing).
  double terminal_tolerance = 1e-6;
  int gap_check_interval = 5;  ///< once the residuals pass, iterations between gap evaluations (>= 1)
  /// kSolvedInaccurate at a limit: residuals <= inaccurate_factor x their tolerances and |gap|
  /// <= inaccurate_factor x eps_gap on the returned (best) iterate.
  double inaccurate_factor = 10.0;
  double time_limit = 0.0;  ///< seconds of solve() wall time, 0 = none -> kTimeLimit
  /// Setup rejects (std::invalid_argument naming `horizon`) a workspace estimated above this.
  double max_workspace_bytes = 512.0 * 1024.0 * 1024.0;
  /// Primal infeasibility check (hard terminal state with box bounds) every this many iterations.
  int infeasibility_check_interval = 25;
  /// Equilibration (read at setup; off under the paper rule, which reproduces the published
  /// iterates): u = D_u u~ per axis and the cost times c, so that the largest scaled L1 weight is 1
  /// and the mean curvature of the smooth part along the axes is 256 (D_u shaped by 1 / w_i on L1
  /// axes, by 1 / sqrt(curvature) otherwise), both rounded to powers of two (exact; the published
  /// scenario is within sqrt 2 of that frame and is solved as given). States need no scaling: they
  /// are eliminated in the x/u step. Results are returned unscaled; the residuals and eps_primal /
  /// eps_dual in AdmmInfo are those of the scaled problem. See docs/guidance.md.
  bool equilibrate = true;
  /// Method (residual rule only; the paper rule always runs plain ADMM). The interior-point method
  /// (Mehrotra predictor-corrector on the equilibrated L1 + box problem, per-entry epigraph and box
  /// slacks eliminated into a diagonal added to R, one structured LQR solve per step: the condensed
  /// nx x nx system without stage Q and with diagonal R, a Riccati recursion otherwise) covers every
  /// problem without group-L2 or ball. Its plan is `solved` only through the same independent tests
  /// as ADMM's (relative duality gap <= eps_gap, terminal miss); otherwise ADMM goes on.
  AdmmMethod method = AdmmMethod::kAdmmIpm;
  /// ADMM iterations before the endgame (>= 0). Measured on the seeded random suite (docs/guidance.md):
  /// with the IPM's warm start floored at 0.3 of the multipliers' scale, 50 / 35 / 20 / 15 / 10 gave
  /// a median C++ solve time of 0.39 / 0.37 / 0.35 / 0.34 / 0.33 ms at 11-12 median IPM iterations.
  /// 2026-12-03 (after the block sweeps): 35 / 15 / 12 / 10 / 8 -> median thread CPU time 0.329 /
  /// 0.293 / 0.285 / 0.279 / 0.280 ms, solved 391 / 391 / 390 / 390 / 391 of 391; hence 8.
  int ipm_after = 8;
  int ipm_max_iterations = 60;  ///< interior-point iterations per run (>= 1)
  /// Interior-point stopping: complementarity sum s'z and the stationarity residuals below this
  /// (relative to the objective and the gradient scale) trigger the independent gap test (which
  /// alone decides `solved`). Measured on the suite: 1e-9 / 1e-7 / 1e-6 -> 390 / 391 / 389 of 391
  /// solved, median 11 / 10 / 10 IPM iterations.
  double ipm_tolerance = 1e-7;
  /// Validates ranges (std::invalid_argument naming the field).
  void validate() const;
};

/// Solver status (core/status.hpp: snake_case, `unsolved` first; the old kSolved.. spellings are
/// deprecated aliases); status_message() gives the text, status_name() the Python string.
using core::AdmmStatus;
using core::status_message;
using core::status_name;

/// Diagnostics of the last solve. From core::InfoBase: status, iterations, primal_residual
/// (||U - Y||_inf), dual_residual (rho ||Y - Y_prev||_inf) and solve_time (wall time of solve, s).
struct AdmmInfo : core::InfoBase<AdmmStatus> {
  double eps_primal = 0.0, eps_dual = 0.0;
  double paper_criterion = 0.0;  ///< ||U - Y||_F / (N nu)
  double objective = 0.0;      ///< objective of the flown sparse plan (Y rolled out), with its terminal cost
  double objective_u = 0.0;    ///< objective of the LQR iterate (X, U)
  double terminal_miss = 0.0;  ///< ||x_N - x_f||_2 when Y is flown
  double rho = 0.0;            ///< final penalty
  int factorizations = 0;      ///< Riccati factorizations in this solve (incl. the setup one if first)
  int rho_updates = 0;
  bool polished = false;  ///< the result is a certified active-set polish
  int polish_attempts = 0;
  bool condensed = false;  ///< the condensed x/u step was used (AdmmSettings::condensed)
  /// Objective P of the returned plan Y (= objective) and the Fenchel dual bound D <= optimum:
  /// smooth part f(U) = sum_j 1/2 ||A_j U + b_j||^2 (Qf, Q, R terms), hard terminal A_T U + b_T = 0,
  /// g = L1 + box (+ group-L2 / ball); D(nu) = sum_j [-1/2 ||nu_j||^2 + nu_j' b_j] + nu_T' b_T
  /// - g*(-sum_j A_j' nu_j - A_T' nu_T) with nu_j = s r_j(Y), nu_T = s p (p the terminal multiplier
  /// estimate) and s in [0, 1] maximizing D with g* finite. duality_gap = (P - D) / max(|P|, |D|,
  /// gap_floor), relative; with a hard terminal state P is that of Y, whose terminal miss is bounded
  /// by the primal residual.
  double primal_objective = 0.0;
  double dual_objective = 0.0;
  double duality_gap = 0.0;
  bool certified = false;        ///< the polish optimality certificate holds (same as polished)
  double workspace_bytes = 0.0;  ///< setup's estimate of the workspace (size check)
  int ipm_iterations = 0;        ///< interior-point iterations in this solve (0: the IPM did not run)
  bool ipm_solved = false;       ///< the returned plan is the interior-point method's (kSolved by its gap)
  /// State constraints: least-squares multiplier recoveries on the IPM's converged plan's active set
  /// (tried when its own multipliers do not certify it; each is checked by the same Fenchel bound)
  int dual_recoveries = 0;
};

/// Result (all arrays allocated at setup).
struct AdmmResult {
  Eigen::MatrixXd X;                    ///< LQR states nx x (N+1)
  Eigen::MatrixXd U;                    ///< LQR controls nu x N
  Eigen::MatrixXd Y;                    ///< sparse controls nu x N (the plan to fly)
  Eigen::MatrixXd Lambda;               ///< multipliers of U = Y, nu x N (unscaled)
  Eigen::MatrixXd X_flown;              ///< states when Y is flown, nx x (N+1)
  Eigen::VectorXd terminal_multiplier;  ///< nx (zeros without the terminal constraint)
  /// kPrimalInfeasible: y (nx, unit norm) with y' (x_f - x_N(0)) > max over the box of y' M U,
  /// M = dx_N/dU, so no U in the box reaches x_f (Farkas). Zeros otherwise.
  Eigen::VectorXd infeasibility_certificate;
  AdmmInfo info;
};

/// ADMM solver: setup in the constructor, solve() allocation-free and exception-free.
/// Move-only: its workspace (detail::AdmmWorkspace) is allocated once in the constructor; a
/// moved-from solver may only be destroyed or assigned to.
class AdmmSolver {
 public:
  /// Validate (std::invalid_argument "name: rule (hint: ...)") and allocate everything.
  AdmmSolver(const LtvProblem& problem, const AdmmSettings& settings = AdmmSettings());
  ~AdmmSolver();
  AdmmSolver(AdmmSolver&&) noexcept;
  AdmmSolver& operator=(AdmmSolver&&) noexcept;
  AdmmSolver(const AdmmSolver&) = delete;
  AdmmSolver& operator=(const AdmmSolver&) = delete;

  /// Run ADMM from the warm start (if set) or from Y = Lambda = 0. Never throws.
  const AdmmResult& solve() noexcept;

  /// Later solves start from these (nu x N each) until cold_start(); e.g. the previous result
  /// shifted by one step for receding-horizon use.
  /// @throws std::invalid_argument on wrong sizes or non-finite values
  void warm_start(const Eigen::Ref<const Eigen::MatrixXd>& Y,
                  const Eigen::Ref<const Eigen::MatrixXd>& Lambda);
  /// Drop the warm start (next solve from zeros).
  void cold_start() noexcept;
  /// Change the initial state (receding horizon); gains are reused. Throws on wrong size / NaN.
  void set_x0(const Eigen::Ref<const Eigen::VectorXd>& x0);
  /// Change the target state; gains are reused. Throws on wrong size / NaN.
  void set_xf(const Eigen::Ref<const Eigen::VectorXd>& xf);
  /// Replace the settings (validated); a new rho refactors at the next solve.
  void update_settings(const AdmmSettings& settings);
  /// Set AdmmSettings::time_limit (s, 0 = none) without allocating (SCP passes its remaining time);
  /// a negative or non-finite value is ignored (returns false).
  bool set_time_limit(double seconds) noexcept;

  /// The result of the last solve() (arrays sized at setup).
  const AdmmResult& result() const;
  /// The settings in force (the last update_settings / set_time_limit included).
  const AdmmSettings& settings() const;
  /// The problem as given (unscaled; the solver works on an equilibrated copy).
  const LtvProblem& problem() const;
  /// Control scaling D_u (nu; u = D_u u~) and cost scaling c of the equilibration (ones / 1 if off).
  const Eigen::VectorXd& control_scaling() const;
  double cost_scaling() const;
  /// The Riccati kernel (on the equilibrated problem).
  const RiccatiSolver& riccati() const;
  /// Dual estimate -grad f(U) of the last iteration (nu x N, scaled problem; used by the polish).
  const Eigen::MatrixXd& dual_estimate() const;
  int nx() const;       ///< state dimension
  int nu() const;       ///< control dimension
  int horizon() const;  ///< N (control steps)

  /// Objective of a control sequence (nu x N) flown from x0 (no constraint checks); allocates.
  double objective_of(const Eigen::Ref<const Eigen::MatrixXd>& U) const;

  /// Overwrite the dynamics in place (A, B, c with the counts and sizes given at construction:
  /// N time-varying entries each, c empty if none was given) and refactor the cached Riccati gains
  /// at settings().rho, without allocation (sequential convex programming re-linearizes this way).
  /// The warm start is kept. Returns false on mismatched sizes or non-finite data (nothing changed)
  /// or a failed factorization (solve() then reports kNumericalError).
  bool update_dynamics(const std::vector<Eigen::MatrixXd>& A, const std::vector<Eigen::MatrixXd>& B,
                       const std::vector<Eigen::VectorXd>& c) noexcept;

 private:
  std::unique_ptr<detail::AdmmWorkspace> ws_;
};

}  // namespace satgnc::guidance
