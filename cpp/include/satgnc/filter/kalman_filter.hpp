#pragma once
/// @file kalman_filter.hpp
/// The generic sequential filter of the filter room: EKF (Joseph or UD / Bierman-Thornton, optional
/// iterated update), UKF (scaled sigma points), Schmidt-Kalman consider parameters and a
/// chi-square gate per measurement. It follows the solver contract (core/solver.hpp):
///
/// ```cpp
/// FilterSettings s;  s.validate();                // throws std::invalid_argument("name: rule")
/// KalmanFilter kf(process, measurement, problem, s);  // validates, sizes the workspace once
/// const FilterResult& r = kf.solve();             // noexcept, no heap allocation
/// ```
/// or, on board, step by step after the same setup: `initialize()`, then `predict(t)` and
/// `update(record)` (both noexcept and allocation-free), reading `state()`, `covariance()` and
/// `last_step()`.
///
/// What each covariance form guarantees (docs/filter.md):
/// - `joseph`: P+ = (I - K H) P (I - K H)' + K R K', computed as that product and symmetrized:
///   symmetric by construction, PSD up to rounding for ANY gain K (hence valid for the consider
///   gain); conditioning is that of P (sqrt-free, so an ill-conditioned P can still lose PD).
/// - `ud` (Bierman scalar update, Thornton MWGS time update): P = U D U' with U unit upper
///   triangular; symmetric exactly and PSD as long as D >= 0, which both algorithms keep by
///   construction (they work on the factors, whose condition number is the square root of P's).
/// - `conventional`: P+ = P - K H P (the textbook short form): neither symmetry nor PSD is
///   guaranteed; kept only to show the difference (tests).
///
/// Time: s, on the ProcessModel's origin. The state and measurement units are the models'.
#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "satgnc/core/solver.hpp"
#include "satgnc/filter/measurement_function.hpp"
#include "satgnc/filter/process_model.hpp"
#include "satgnc/filter/status.hpp"

namespace satgnc::filter {

/// Filter algorithm.
enum class FilterAlgorithm : int {
  ekf = 0,  ///< extended Kalman filter (linearized; a plain KF on a linear model)
  ukf = 1,  ///< unscented Kalman filter (Wan / van der Merwe scaled sigma points, additive noise)
};

/// Covariance representation and update of the EKF (ignored by the UKF, which uses `joseph`-style
/// symmetrized storage: P - K S K').
enum class CovarianceForm : int {
  joseph = 0,        ///< Joseph product form (default)
  ud = 1,            ///< UD factors: Bierman scalar update, Thornton MWGS time update
  conventional = 2,  ///< P - K H P (no guarantee; for comparisons only)
};

/// Filter settings (plain fields, documented defaults; `validate()` throws on a bad value).
struct FilterSettings {
  FilterAlgorithm algorithm = FilterAlgorithm::ekf;  ///< ekf or ukf
  CovarianceForm form = CovarianceForm::joseph;      ///< EKF covariance form
  /// Process the m components of a record one scalar at a time (valid since R is diagonal).
  /// The UD form is always sequential; the iterated EKF and the UKF always use the vector form.
  bool sequential = true;
  /// Iterated EKF (Gauss-Newton on the MAP cost of one record, Bell & Cathey 1993): relinearize
  /// at the updated state until ||dx|| <= iteration_tolerance * (1 + ||x||) or max_iterations.
  bool iterated = false;
  int max_iterations = 20;             ///< iterated EKF: maximum iterations (>= 1)
  double iteration_tolerance = 1e-10;  ///< iterated EKF: relative step tolerance (> 0)
  double ukf_alpha = 1e-3;             ///< UKF spread (0 < alpha <= 1; 1e-3 is Wan & van der Merwe's default)
  double ukf_beta = 2.0;               ///< UKF prior knowledge (>= 0; 2 is optimal for a Gaussian)
  double ukf_kappa = 0.0;              ///< UKF secondary scaling (n + kappa > 0; default 0)
  /// The last `consider_count` state components are consider parameters (Schmidt-Kalman): their
  /// gain rows are zero, so they are never estimated, but their covariance and cross-covariance are
  /// propagated and updated: the estimated block of P is the consider covariance. Joseph form only.
  int consider_count = 0;
  /// Further consider parameters by state index (any position, each in [0, n), none repeated), in
  /// addition to the last `consider_count`; same rules (EKF Joseph, or the UKF, whose update then
  /// uses the general form P - K Pxz' - Pxz K' + K S K', valid for any gain).
  std::vector<int> consider_states;
  bool gating = true;               ///< apply the chi-square gate per record (after the warm-up)
  double gate_probability = 0.999;  ///< gate: accept when y' S^-1 y <= chi2_m^-1(p), p in (0, 1)
  /// Warm-up, s: records with t < t_first + warm_up (t_first: the first record's time after
  /// initialize()) are used without gating (flag `warm_up`).
  double warm_up = 0.0;
  /// Warm-up by count: the first `warm_up_records` update() calls after initialize() (failed ones
  /// included) are used without gating (flag `warm_up`); >= 0. Both warm-ups apply.
  int warm_up_records = 0;
  /// Check positive definiteness after every step (Cholesky of P, or D > 0 for UD); status
  /// covariance_not_pd on failure. Costs one n x n Cholesky per step.
  bool check_covariance = true;
  /// Keep what the RTS smoother needs (predicted states and covariances, transition matrices) in
  /// the FilterResult of solve().
  bool store_smoother_data = true;

  /// Throw std::invalid_argument("settings.<field>: rule") on a bad value.
  void validate() const;
};

/// The problem of a batch run: initial state and covariance at t0 and the records, sorted by time.
struct FilterProblem {
  Eigen::VectorXd x0;                      ///< initial state (n)
  Eigen::MatrixXd p0;                      ///< initial covariance (n x n, symmetric positive definite)
  double t0 = 0.0;                         ///< initial time, s
  std::vector<MeasurementRecord> records;  ///< sorted by t (non-decreasing), every t >= t0
};

/// What one step did with its record (fixed size: no allocation). Residuals are observed minus
/// predicted, in the measurement's units; entries past `dim` are NaN.
struct StepRecord {
  double t = 0.0;                                ///< record time, s
  int type = 0;                                  ///< record type id
  int station = 0;                               ///< record station id
  int dim = 0;                                   ///< measurement dimension m
  FilterStatus status = FilterStatus::unsolved;  ///< step status
  EditFlag flag = EditFlag::unsolved;  ///< editing decision (rejected records are listed, never dropped)
  int iterations = 0;                  ///< update iterations (1; iterated EKF: its count)
  std::array<double, kMaxMeasurementDim> prefit{};   ///< z - h(x-) (pre-fit residual)
  std::array<double, kMaxMeasurementDim> postfit{};  ///< z - h(x+) (post-fit; = prefit when not updated)
  std::array<double, kMaxMeasurementDim> innovation_sigma{};  ///< sqrt(S_ii), S = H P- H' + R
  std::array<double, kMaxMeasurementDim> normalized{};        ///< prefit_i / sqrt(S_ii) (normalized residual)
  double nis = 0.0;   ///< normalized innovation squared y' S^-1 y (Mahalanobis distance squared)
  double gate = 0.0;  ///< chi-square threshold used (chi2_m^-1(p)); 0 when not gated
};

/// Info of a run: `iterations` = steps processed; `primal_residual` = RMS of the accepted normalized
/// pre-fit residuals; `dual_residual` = 0; `solve_time` in s.
struct FilterInfo : core::InfoBase<FilterStatus> {
  int accepted = 0;        ///< records accepted (gated or warm-up)
  int rejected = 0;        ///< records rejected by the gate
  int failed = 0;          ///< records not used for another reason (see their status)
  int first_failure = -1;  ///< first step whose status is neither success nor rejected (-1: none)
};

/// Result of solve(): everything time-major (step k's data contiguous in memory), N = records.
struct FilterResult {
  int n = 0;                              ///< state dimension
  int steps = 0;                          ///< N: one step per record
  double t0 = 0.0;                        ///< initial time, s
  Eigen::VectorXd initial_state;          ///< x0 (n)
  Eigen::MatrixXd initial_covariance;     ///< P0 (n x n)
  Eigen::VectorXd times;                  ///< record times (N), s
  Eigen::MatrixXd states;                 ///< n x N: column k = updated state after step k
  Eigen::MatrixXd covariances;            ///< n x (n N): block k (columns k n .. k n + n - 1) = updated P
  Eigen::MatrixXd predicted_states;       ///< n x N: state predicted to step k's time (smoother data)
  Eigen::MatrixXd predicted_covariances;  ///< n x (n N): predicted P (smoother data)
  Eigen::MatrixXd transitions;  ///< n x (n N): Phi from the previous step's time (t0 for k = 0) to step k
  std::vector<int> consider;    ///< consider state indices, ascending (the RTS smoother keeps them)
  /// UD runs with smoother data only (else empty): the factors P = U D U' the RTS smoother works on,
  /// packed per n x n block (strict upper triangle = U, diagonal = D; U's unit diagonal implied):
  /// filtered (block k), predicted (block k), of the process noise Qd of the step to k (zero when the
  /// step did not move), and of P0 (n x n).
  Eigen::MatrixXd ud_factors;
  Eigen::MatrixXd predicted_ud_factors;      ///< n x (n N), see ud_factors
  Eigen::MatrixXd process_noise_ud_factors;  ///< n x (n N), see ud_factors
  Eigen::MatrixXd initial_ud_factors;        ///< n x n, see ud_factors
  std::vector<StepRecord> records;           ///< N step records
  FilterInfo info;                           ///< run info
};

namespace detail {
struct FilterWorkspace;
}

/// Generic sequential filter over a ProcessModel and a MeasurementFunction (both held by reference:
/// the caller keeps them alive for the filter's lifetime).
class KalmanFilter {
 public:
  /// Validate settings, problem (x0 finite; P0 symmetric positive definite; records sorted, t >= t0,
  /// types set up, values finite, sigmas > 0) and model dimensions; size the workspace and result.
  /// Throws std::invalid_argument("<name>: <rule>").
  KalmanFilter(ProcessModel& process, MeasurementFunction& measurement, const FilterProblem& problem,
               const FilterSettings& settings);
  ~KalmanFilter();
  KalmanFilter(KalmanFilter&&) noexcept;             ///< move
  KalmanFilter& operator=(KalmanFilter&&) noexcept;  ///< move
  KalmanFilter(const KalmanFilter&) = delete;
  KalmanFilter& operator=(const KalmanFilter&) = delete;

  /// Run over the problem's records from (x0, P0, t0): one step per record, stored time-major.
  /// A process failure stops the run (later steps stay `unsolved`); other failures are per-step
  /// statuses. info.status: success (rejections included), or the first failure's status.
  /// noexcept; no heap allocation.
  const FilterResult& solve() noexcept;

  /// Reset the on-board state to (x0, P0, t0) of the problem. noexcept.
  void initialize() noexcept;
  /// Propagate the state and covariance to t (s). noexcept; no heap allocation.
  FilterStatus predict(double t) noexcept;
  /// Predict to record.t (if needed), then gate and update with the record. noexcept; no heap
  /// allocation. A type with dimension(type) == 0 gives `unknown_measurement_type`.
  FilterStatus update(const MeasurementRecord& record) noexcept;

  /// Current state (n).
  const Eigen::VectorXd& state() const noexcept;
  /// Current covariance (n x n; for the UD form, U D U' formed on the call). noexcept.
  const Eigen::MatrixXd& covariance() noexcept;
  /// Current time, s.
  double time() const noexcept;
  /// The record of the last update().
  const StepRecord& last_step() const noexcept;
  /// Transition matrix of the last predict() (identity when it did not move).
  const Eigen::MatrixXd& last_transition() const noexcept;
  /// The last result of solve().
  const FilterResult& result() const noexcept;
  /// The settings (validated).
  const FilterSettings& settings() const noexcept;
  /// Chi-square gate thresholds chi2_m^-1(gate_probability) for m = 1..kMaxMeasurementDim.
  const std::array<double, kMaxMeasurementDim>& gate_thresholds() const noexcept;

 private:
  std::unique_ptr<detail::FilterWorkspace> ws_;
};

}  // namespace satgnc::filter
