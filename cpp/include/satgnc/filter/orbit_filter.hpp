#pragma once
/// @file orbit_filter.hpp
/// Sequential orbit determination (issue 15): the orbit front end of the generic filter engine.
/// OrbitFilter takes orbit measurements (station / observable indices, Vector2d values), turns them
/// into the engine's records (OrbitMeasurementFunction::record) and runs filter::KalmanFilter
/// (kalman_filter.hpp) on OrbitProcessModel (DOP853, STM, SNC / DMC noise) and
/// OrbitMeasurementFunction (light time, biases); the smoother is filter::RtsSmoother (rts.hpp). It
/// has no update, sigma-point, gate or smoother code of its own: it maps settings in and the
/// engine's time-major result out (OrbitFilterResult: K x 2 residual rows, statuses, editing).
///
/// - method = ekf: the engine's EKF, Joseph form, vector update of each record (2 components for
///   angle pairs). Joseph keeps P symmetric PSD for ANY gain (Bucy & Joseph 1968), hence valid with
///   the consider rows of K zeroed (Schmidt-Kalman: P carries the consider covariance).
/// - method = ukf: the engine's UKF (2n + 1 scaled sigma points; the central point's STM and Q serve
///   the smoother and the additive noise); with consider states its update uses the general form
///   P - K Pxz' - Pxz K' + K S K'.
///
/// Editing: NIS = y' S^-1 y of each measurement against the chi-square quantile of probability
/// `gate_probability` for its dimension; above it the measurement is rejected (state and covariance
/// unchanged) and reported with sqrt(NIS); the first `warmup` measurements are never rejected (the
/// engine's warm_up_records).
///
/// Solver contract: settings validated at construction (throws std::invalid_argument naming the
/// field); run() validates the measurement list (sorted times, known stations / observables), sets up
/// the engine (sized once per run) and steps noexcept and allocation-free: a step that fails is a
/// status in the result (OrbitStepStatus), never an exception. After a propagation failure or a
/// covariance that lost positive definiteness the filter stops (later steps: not_run).
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <vector>

#include "satgnc/filter/orbit_measurement.hpp"
#include "satgnc/filter/orbit_process_model.hpp"
#include "satgnc/filter/status.hpp"

namespace satgnc::filter {

// OrbitStepStatus and its status_name / status_message: filter/status.hpp.

/// Settings of OrbitFilter.
/// Filter kind.
enum class OrbitFilterMethod : int {
  ekf = 0,  ///< extended Kalman filter: STM covariance propagation, Joseph-form update
  ukf = 1,  ///< unscented Kalman filter: 2n + 1 sigma points through DOP853 and the measurement model
};

struct OrbitFilterSettings {
  OrbitFilterMethod method = OrbitFilterMethod::ekf;  ///< EKF (default) or UKF
  /// UKF scaling (Wan & van der Merwe 2000): lambda = alpha^2 (n + kappa) - n; weights W0m = lambda /
  /// (n + lambda), W0c = W0m + 1 - alpha^2 + beta, Wi = 1 / (2 (n + lambda)). Defaults alpha = 1,
  /// beta = 2, kappa = 0: lambda = 0, every weight >= 0 (the covariance stays positive semi-definite).
  /// alpha in (0, 1] (the engine's rule, checked at construction).
  double ukf_alpha = 1.0;
  double ukf_beta = 2.0;   ///< UKF: prior-distribution parameter (2: Gaussian)
  double ukf_kappa = 0.0;  ///< UKF: secondary scaling, n + kappa > 0
  bool gating = true;      ///< apply the chi-square gate
  double gate_probability =
      0.9973;                 ///< probability of the gate, in (0, 1) (0.9973: 3 sigma in one dimension)
  int warmup = 0;             ///< the first `warmup` measurements are used ungated, >= 0
  std::vector<int> consider;  ///< state indices held as consider parameters (not updated), >= 6
  /// Throws std::invalid_argument naming the field: gate_probability outside (0, 1), warmup < 0, a
  /// consider index outside [6, n) or repeated.
  void validate(int state_dimension) const;
};

/// Time-major result of OrbitFilter::run (K measurements, n states). Rows follow the measurements.
struct OrbitFilterResult {
  int n = 0;                                ///< state dimension
  std::vector<double> t;                    ///< K tags, s
  std::vector<int> station;                 ///< K station indices
  std::vector<int> observable;              ///< K observable indices
  std::vector<int> size;                    ///< K measurement dimensions (1 or 2)
  std::vector<OrbitStepStatus> status;      ///< K step statuses
  std::vector<double> state;                ///< K x n posterior states (row-major)
  std::vector<double> covariance;           ///< K x n x n posterior covariances
  std::vector<double> prefit;               ///< K x 2 pre-fit residuals (measured - predicted; NaN if unused)
  std::vector<double> postfit;              ///< K x 2 post-fit residuals
  std::vector<double> sigma;                ///< K x 2 measurement sigmas
  std::vector<double> nis;                  ///< K normalized innovation squared (NaN if not evaluated)
  std::vector<double> normalized_residual;  ///< K sqrt(NIS), the editing statistic
  std::vector<double> gate;  ///< K chi-square thresholds applied (0 during warm-up / no gating)
  // For the smoother: a-priori (propagated) state / covariance at each tag and the STM from the
  // previous tag (the first: from the initial epoch).
  std::vector<double> predicted_state;       ///< K x n
  std::vector<double> predicted_covariance;  ///< K x n x n
  std::vector<double> transition;            ///< K x n x n
  double t0 = 0.0;                           ///< initial epoch, s
  std::vector<int> consider;                 ///< consider state indices (the smoother keeps them)
  Eigen::VectorXd initial_state;             ///< n
  Eigen::MatrixXd initial_covariance;        ///< n x n
  int steps_run = 0;                         ///< steps before a stop (K when none)
  int rejected = 0;                          ///< measurements the gate rejected
  long propagation_steps = 0;                ///< DOP853 steps, all intervals
  double solve_time = 0.0;                   ///< wall time of run(), s
};

/// RTS-smoothed states (same rows as the filter result, plus the initial epoch).
struct OrbitSmootherResult {
  int n = 0;                           ///< state dimension
  std::vector<double> t;               ///< K tags, s
  std::vector<double> state;           ///< K x n smoothed states
  std::vector<double> covariance;      ///< K x n x n smoothed covariances
  Eigen::VectorXd initial_state;       ///< n, smoothed at t0
  Eigen::MatrixXd initial_covariance;  ///< n x n, smoothed at t0
};

/// Extended Kalman filter for orbits (see the file doc).
class OrbitFilter {
 public:
  /// Takes the models (moved in), validates the settings, sizes the workspace.
  OrbitFilter(OrbitProcessModel process, OrbitMeasurementFunction measurement,
              const OrbitFilterSettings& settings);
  ~OrbitFilter();
  OrbitFilter(OrbitFilter&&) noexcept;             ///< movable
  OrbitFilter& operator=(OrbitFilter&&) noexcept;  ///< movable

  /// State dimension.
  int dimension() const noexcept { return n_; }

  /// Run the filter from (t0, x0, P0) over the measurements. Throws std::invalid_argument naming the
  /// argument: x0 / P0 of the wrong size or not finite, P0 not symmetric positive definite, unsorted
  /// tags (non-decreasing required) or tags before t0, unknown station or observable index.
  OrbitFilterResult run(double t0, const Eigen::VectorXd& x0, const Eigen::MatrixXd& p0,
                        const std::vector<OrbitMeasurement>& measurements);

  /// The chi-square quantile used by the gate for a measurement of dimension dof (1 or 2).
  double gate_threshold(int dof) const noexcept { return dof == 2 ? gate2_ : gate1_; }

  /// Rauch-Tung-Striebel smoother over a filter result (steps up to steps_run). Throws
  /// std::invalid_argument("result: ...") on a result of another dimension or with no step.
  static OrbitSmootherResult smooth(const OrbitFilterResult& result);

 private:
  OrbitProcessModel process_;
  OrbitMeasurementFunction measurement_;
  OrbitFilterSettings settings_;
  int n_ = 6;
  double gate1_ = 0.0, gate2_ = 0.0;
};

/// Chi-square quantile: x with P(chi2_dof <= x) = p, dof 1 or 2, p in (0, 1) (dof 2: -2 ln(1 - p);
/// dof 1: bisection on erf(sqrt(x / 2)) to 1e-14 relative).
double chi2_quantile(int dof, double p);

}  // namespace satgnc::filter
