#pragma once
/// @file solver.hpp
/// Orbit determination of the initial state x0 = [r km, v km/s] at t = 0 from range / range-rate data.
///
/// One engine, three methods (OdSettings::method):
///  - newton: the paper's six-point Newton-Raphson on six implicit boundary conditions (eqs. 9-18),
///    or on six observations; the Jacobian is exact (measurement partials chained through the STM);
///  - newton is kept exactly as the paper has it (full undamped steps) so its tables reproduce;
///  - gauss_newton: weighted batch least squares for any number (>= 6) of mixed observations from
///    one or several stations, with the formal covariance (J^T W J)^-1 and correlation; globalized
///    by a backtracking line search along the second-order path x + t v + t^2 a / 2 with a valley
///    corrector and an extrapolation of accepted steps;
///  - levenberg_marquardt: the same cost, globalized by Moré-scaled damping.
/// GN and LM add the geodesic acceleration a (OdSettings::geodesic), reject trial points below the
/// surface, unbound or not propagatable, never raise the cost, and return the best iterate.
/// Statuses and their guarantees: docs/od.md.
/// Residual rows are either observations (predicted - observed, km or km/s, weight 1/sigma^2) or the
/// paper's implicit conditions:
///  - range:   q = |X1 - R1|^2 - rho_j^2                         (km^2),   sigma_q = 2 rho_j sigma_rho
///  - doppler: q = (X1 - R1)^T (X2 - R2) - rho_j rhodot_j        (km^2/s), with the OBSERVED rho_j
///             and rhodot_j; sigma_q = sqrt((rho_j s_rhodot)^2 + (rhodot_j s_rho)^2).
///    dq/dx(t_j) = [2 (X1-R1)^T, 0] for range, [(X2-R2)^T, (X1-R1)^T] for doppler; dq/dx0 = dq/dx Phi.
/// Linear algebra: QR of the row-normalized [J | r] then a 6x6 SVD of R, so the condition number
/// (up to ~1e9 here) is not squared; all buffers are sized at construction and solve() does not
/// allocate (if the propagator does not).
#include <Eigen/Dense>
#include <cstdint>
#include <memory>
#include <vector>

#include "satgnc/core/solver.hpp"
#include "satgnc/core/status.hpp"
#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/od/measurement.hpp"
#include "satgnc/od/propagator.hpp"
#include "satgnc/od/station.hpp"

namespace satgnc::od {

namespace detail {
struct OdWorkspace;  // src/od/detail/od_workspace.hpp: the buffers of OdSolver
}  // namespace detail

/// Iteration scheme.
enum class OdMethod { newton = 0, gauss_newton = 1, levenberg_marquardt = 2 };

/// Outcome of a solve (core/status.hpp; guarantees: docs/od.md, "Statuses"). Values are stable:
/// new statuses are appended. converged: the convergence test of the method holds at x0 (see
/// OdSettings) and rank = 6; max_iterations: budget exhausted, x0 is the best iterate; singular:
/// Jacobian rank < 6 at x0 (OdResult::rank); diverged: an iterate left the physical region;
/// propagation_failed; degenerate_geometry: zero range; unsolved: not solved yet; stalled: no trial
/// step lowered the cost and the convergence test does not hold.
using core::OdStatus;
using core::status_message;
using core::status_name;

/// Message for a status.
[[deprecated("use status_message")]] inline const char* od_status_message(OdStatus s) {
  return core::status_message(s);
}

/// The paper's implicit boundary condition kind (eqs. 9 and 11).
enum class ConditionType { range = 0, doppler = 1 };

/// One implicit condition at time t (s): observed range (km) and, for doppler, range-rate (km/s),
/// with their standard deviations (km, km/s; > 0) and the station index.
struct BoundaryCondition {
  double t = 0.0;
  ConditionType type = ConditionType::doppler;
  double range = 0.0;
  double range_rate = 0.0;
  double sigma_range = 1e-3;
  double sigma_range_rate = 1e-6;
  int station = 0;
};

/// Settings (plain struct, defaults documented).
///
/// Convergence test of gauss_newton and levenberg_marquardt, evaluated at the current iterate x from
/// the QR factor R and c = Q^T r_n of the row-normalized Jacobian and residuals (r_n = r / sigma), with
/// the full Gauss-Newton step dx = -R^-1 c (numerical rank 6 required, else the status is singular):
///  - gradient: |c| <= step_sigma_tol. |c| = |R dx| is the Mahalanobis length of dx under the formal
///    covariance, i.e. x is within step_sigma_tol formal sigmas of the minimum of the local model;
///  - step:     |dx_i| <= step_tol (1 + |x_i|) for every component (km, km/s; the round-off floor);
///  - cost:     0.5 |c|^2 <= cost_tol * cost, the model's predicted decrease of the full step.
/// A step that only lowers the cost a little (a crawl) is never taken as convergence by itself.
/// newton (the paper's method, kept exactly) tests the step just taken instead: |R dx| <= step_sigma_tol,
/// the step test above, or an accepted step that lowered the cost by <= cost_tol * cost.
struct OdSettings {
  OdMethod method = OdMethod::gauss_newton;
  int max_iterations = 100;      ///< accepted steps (the history holds max_iterations + 1 rows)
  double step_tol = 1e-10;       ///< relative step test (see above)
  double step_sigma_tol = 1e-6;  ///< gradient test: formal sigmas (see above)
  double cost_tol = 1e-6;        ///< relative predicted cost decrease (see above)
  double residual_tol = 0.0;  ///< also converged when max |normalized residual| <= this (paper's xi); 0 = off
  double rank_tol = 1e-13;    ///< singular values below rank_tol * s_max count as zero (numerical rank)
  double min_radius = dynamics::earth::radius;  ///< km; any state closer to the centre => diverged
  double mu = dynamics::earth::mu;              ///< km^3/s^2, for the unbound test (specific energy >= 0)
  double fit_sigma = 3.0;    ///< a solution fits when the RMS normalized residual <= fit_sigma
  double min_range = 1e-6;   ///< km; smaller predicted range => degenerate_geometry
  int gn_max_halvings = 40;  ///< GN line search: step halvings (decrease test) before status stalled
  /// GN and LM add the geodesic acceleration (second-order correction along the step, one extra
  /// residual evaluation per trial; Transtrum & Sethna 2012) so steps follow curved valleys.
  bool geodesic = true;
  /// GN and LM: valley corrector steps per poor trial point (0 = off). A one-station pass has a
  /// long, curved valley of nearly equal cost (Gao-Luo 300 s pass: formal sigmas 35 km and 0.25 km
  /// along it, 0.13 m and less across it): a step along its tangent leaves the floor (the cost
  /// rises by 2e10 at the full 28 km GN step and still by 2e4 at 1/32 of it), so the line search
  /// crawled at t ~ 1/1000. A trial xt that fails the decrease test (GN) or does worse than the
  /// model predicted (LM) is pulled back to the floor by up to this many Gauss-Newton steps
  /// restricted to the complement of the step direction (orthonormal in Moré-scaled coordinates,
  /// so the progress along the valley is kept), each kept only if it lowers the cost; the trial is
  /// then judged at the corrected point (a predictor-corrector, as in continuation methods).
  int valley_corrections = 3;
  /// GN and LM: after an accepted step d, fit the cost along x + t d by a parabola (cost at x, its
  /// slope, cost at the new point) and try its minimizer t* when t* >= 2 (at most 10), kept only if
  /// lower. Gauss-Newton converges only linearly where the residuals' curvature along the weak
  /// direction rivals J^T J (measured 0.95 per step on a noisy one-station pass); this finishes it.
  bool extrapolate = true;
  double lm_lambda0 = 1e-3;    ///< initial LM damping (relative to the Moré scaling)
  double lm_increase = 10.0;   ///< damping factor after a rejected step
  double lm_decrease = 0.1;    ///< damping factor after a very successful step (gain ratio > 0.75)
  int lm_max_rejections = 30;  ///< rejected trials in a row before giving up (then status stalled)
  double lm_stall_tol =
      0.1;  ///< after 3 LM steps each lowering the cost by < this fraction, try a Newton polish
  int lm_polish_iterations =
      10;  ///< undamped Newton steps tried when LM creeps (kept only if they end lower and converge)
  /// Throw std::invalid_argument naming the field on a bad value.
  void validate() const;
};

/// Result with per-iteration history. History row k holds the iterate after k accepted steps
/// (row 0 = the guess); rows 0..iterations are used and finite (range / range-rate residual rows hold
/// NaN only for rows without that observable), later rows are unused (NaN). Residual rows follow the
/// input order. Whatever the status, x0 is the best (lowest-cost) iterate (newton's converged and
/// singular: its last iterate) and cost, residuals,
/// covariance and rank are evaluated at it; when not even the guess can be evaluated (diverged,
/// propagation_failed or degenerate_geometry with iterations = 0) cost and max_abs_normalized are +inf.
/// Diagnostics of the last solve. From core::InfoBase: status, iterations (accepted steps),
/// primal_residual (RMS of the normalized residuals at x0, sqrt(2 cost / rows)), dual_residual
/// (|x0 - previous iterate|_2 of the last accepted step, km/km/s mixed; 0 without a step) and
/// solve_time (wall time of solve(), s).
struct OdInfo : core::InfoBase<OdStatus> {};

struct OdResult {
  OdStatus status = OdStatus::unsolved;  ///< mirrors info.status
  int iterations = 0;                    ///< accepted steps (mirrors info.iterations)
  int evaluations = 0;                   ///< propagations (LM counts rejected trials)
  Vec6 x0 = Vec6::Zero();                ///< final estimate at t = 0
  Mat6 covariance = Mat6::Zero();        ///< formal (J^T W J)^-1 at x0 (km, km/s); +inf diagonal if rank < 6
  Mat6 correlation = Mat6::Zero();
  Vec6 singular_values = Vec6::Zero();  ///< of the row-normalized Jacobian dr/dx0 (km, km/s columns)
  int rank = 0;                         ///< numerical rank of that Jacobian
  double condition_number = 0.0;        ///< s_max / s_min (inf if s_min = 0)
  double cost = 0.0;                    ///< 0.5 sum normalized^2
  double max_abs_normalized = 0.0;      ///< max |residual / sigma|
  bool fits = false;                ///< RMS of normalized residuals <= fit_sigma (and the state is physical)
  Eigen::VectorXd residuals;        ///< raw residual rows (km, km/s, km^2 or km^2/s)
  Eigen::VectorXd normalized;       ///< residuals / sigma
  Eigen::VectorXd range_residuals;  ///< predicted - observed range per row, km (NaN if none)
  Eigen::VectorXd range_rate_residuals;     ///< predicted - observed range-rate per row, km/s (NaN if none)
  Eigen::MatrixXd history_x0;               ///< (max_iterations+1) x 6 (rows > iterations unused)
  Eigen::MatrixXd history_residuals;        ///< (max_iterations+1) x rows, raw
  Eigen::MatrixXd history_range_residuals;  ///< km
  Eigen::MatrixXd history_range_rate_residuals;  ///< km/s
  Eigen::VectorXd history_cost;                  ///< 0.5 sum normalized^2
  Eigen::VectorXd history_lambda;                ///< LM damping used for the step into the row (0 otherwise)
  OdInfo info;                                   ///< status, iterations, residuals, solve time
};

/// The solver: constant problem (stations, rows, unique times) + workspace (detail::OdWorkspace)
/// sized once. Move-only.
class OdSolver {
 public:
  ~OdSolver();
  OdSolver(OdSolver&&) noexcept;
  OdSolver& operator=(OdSolver&&) noexcept;
  OdSolver(const OdSolver&) = delete;
  OdSolver& operator=(const OdSolver&) = delete;

  /// Batch problem on observations. Needs >= 6 measurements (exactly 6 for method newton).
  /// Throws std::invalid_argument naming the argument on bad input.
  static OdSolver from_measurements(std::vector<Station> stations, const std::vector<Measurement>& meas,
                                    std::shared_ptr<StmPropagator> propagator,
                                    const OdSettings& settings = {});
  /// The paper's problem on implicit boundary conditions (exactly 6 for method newton, >= 6 otherwise).
  static OdSolver from_conditions(std::vector<Station> stations, const std::vector<BoundaryCondition>& conds,
                                  std::shared_ptr<StmPropagator> propagator, const OdSettings& settings = {});

  /// Initial guess x0 (km, km/s) of the next solve() (default: zeros). Not checked here, as before:
  /// a guess without residuals (non-finite, inside the body) ends in a failure status, not a throw.
  void set_initial_guess(const Vec6& x0_guess) noexcept;

  /// Iterate from the initial guess; never throws (an exception from the propagator ends the
  /// evaluation as propagation_failed), never allocates after setup (given a non-allocating
  /// propagator; SATGNC_NO_MALLOC_SCOPE guards it in guarded builds). The returned reference stays
  /// valid until the next solve().
  const OdResult& solve() noexcept;

  /// set_initial_guess(x0_guess), then solve() (the old shape, kept).
  const OdResult& solve(const Vec6& x0_guess) noexcept {
    set_initial_guess(x0_guess);
    return solve();
  }

  /// Residual rows and, if jac is non-null, their Jacobian w.r.t. x0 (rows x 6, raw units) at x0.
  /// Returns converged when the evaluation is valid, otherwise the failure status.
  OdStatus evaluate(const Vec6& x0, Eigen::VectorXd& residuals, Eigen::MatrixXd* jac);

  int rows() const { return static_cast<int>(rows_.size()); }
  const OdSettings& settings() const { return settings_; }
  /// Change settings between solves (validated; max_iterations may not exceed the one at setup).
  void set_settings(const OdSettings& s);
  const OdResult& result() const { return res_; }
  /// Row standard deviations (km, km/s, km^2, km^2/s).
  const Eigen::VectorXd& row_sigmas() const { return sigma_; }

 private:
  enum class RowKind { obs_range, obs_range_rate, cond_range, cond_doppler };
  struct Row {
    RowKind kind;
    int time_index;
    int station;
    double range;       // observed (NaN if none)
    double range_rate;  // observed (NaN if none)
  };
  OdSolver();
  void setup(std::vector<Station> stations, std::vector<Row> rows, std::vector<double> row_times,
             Eigen::VectorXd sigma, std::shared_ptr<StmPropagator> propagator, const OdSettings& settings);
  void solve_iterate(const Vec6& guess);             // solve() without the timing and info mirrors
  OdStatus eval_at(const Vec6& x0, bool with_jac);   // fills r_, rn_, jn_, range/rate residuals
  bool propagate_noexcept(const Vec6& x0) noexcept;  // states_/stms_ at times_; false on failure or throw
  bool physical(const Vec6& x) const;
  void factor();  // QR of [jn_ | rn_] -> R_, c_, SVD
  void record(int k, double lambda);
  // End of a GN / LM iteration k: stalled (false) without an accepted trial, else x = xt as iterate k.
  bool take_step(bool accepted, const Vec6& xt, int k, double lambda, Vec6& x);
  void finish(const Vec6& x, bool buffers_valid);
  bool small_step(const Vec6& dx, const Vec6& x) const;
  bool residual_small() const;
  bool converged_here(const Vec6& x) const;  // after factor(): the GN/LM convergence test at x
  Vec6 gn_step() const;                      // after factor(): -R^+ c, truncated at the rank
  Vec6 solve_r(const Vec6& b) const;         // after factor(): -R^+ b
  Vec6 damped_solve(const Vec6& b, double lambda, const Vec6& diag) const;
  bool second_derivative(const Vec6& x, const Vec6& v, Vec6& qt_rvv);
  // Each method iterates from x (buffers current) and leaves x at the iterate to report; returns
  // whether the buffers still belong to x.
  bool solve_newton(Vec6& x);
  bool solve_gauss_newton(Vec6& x);
  bool solve_lm(Vec6& x);
  bool polish(Vec6& x);  // undamped steps from the LM point; true if kept (buffers at x)
  // Valley corrector: xt (buffers current, cost ct) -> lower point on the valley floor reached by
  // Gauss-Newton steps in the complement of the step direction dir (scaled by diag); buffers stay
  // at the returned xt.
  void valley_correct(Vec6& xt, double& ct, const Vec6& dir, const Vec6& diag);
  // After an accepted step x -> xt (cost ct): try the parabola's minimizer along xt - x (see
  // OdSettings::extrapolate); xt, ct and the buffers end at the kept point.
  void extrapolate(const Vec6& x, double cost, Vec6& xt, double& ct, const Vec6& diag);
  void save_buffers();
  void restore_buffers();

  std::vector<Station> stations_;
  std::vector<Row> rows_;
  std::vector<double> times_;  // unique ascending
  Eigen::VectorXd sigma_;
  std::shared_ptr<StmPropagator> prop_;
  OdSettings settings_;
  int max_iter_cap_ = 0;
  std::unique_ptr<detail::OdWorkspace> ws_;  // every buffer, sized in setup()
  OdResult res_;
  Vec6 guess_ = Vec6::Zero();  // set_initial_guess
};

/// Distinct-root search settings.
struct RootSearchSettings {
  double distinct_position_km = 1e-3;   ///< two solutions closer than this in position ...
  double distinct_velocity_kms = 1e-6;  ///< ... and in velocity are the same root, and so are two
  double distinct_sigma = 0.1;          ///< solutions within this many formal sigmas (Mahalanobis distance
                                ///< under the first one's covariance): stalled LM runs end at slightly
                                ///< different points of one flat valley
};

/// One distinct converged solution.
struct Root {
  Vec6 x0 = Vec6::Zero();
  Mat6 covariance = Mat6::Zero();
  Eigen::VectorXd residuals;   ///< raw rows
  Eigen::VectorXd normalized;  ///< rows / sigma
  double max_abs_normalized = 0.0;
  double condition_number = 0.0;
  bool fits = false;       ///< fits the data to fit_sigma
  bool converged = false;  ///< solver status converged (else stalled at max_iterations but fitting)
  int hits = 0;            ///< guesses that converged to it
  int first_guess = -1;
};

/// Outcome of a root search: distinct roots (fitting ones first, then by max |normalized residual|),
/// per-guess status, iterations and root index (-1 when the run did not converge).
struct RootSearchResult {
  std::vector<Root> roots;
  std::vector<int> guess_root;
  std::vector<OdStatus> guess_status;
  std::vector<int> guess_iterations;
  int fitting_roots = 0;
  bool ambiguous = false;  ///< two or more distinct roots fit the data to measurement precision
};

/// Solve from every guess with the solver's settings and cluster the converged solutions (and the
/// stalled ones that fit the data).
/// Allocates (collects roots); not for on-board loops.
RootSearchResult root_search(OdSolver& solver, const std::vector<Vec6>& guesses,
                             const RootSearchSettings& settings = {});

/// n guesses uniform in the box center +- half_width (km, km/s), reproducible from seed.
std::vector<Vec6> box_guesses(const Vec6& center, const Vec6& half_width, int n, std::uint64_t seed);

}  // namespace satgnc::od
