#pragma once
/// @file batch.hpp
/// Batch least-squares orbit determination on real tracking data (issue 13 item 6): the GCRF state
/// at an epoch plus per-station range and time biases, from one- and two-way range, range-rate,
/// azimuth/elevation and RA/Dec of several ground stations over several passes, with the light-time
/// measurement models of the observation room (observation/measurement_model.hpp), an
/// observation::StationEphemeris per station (e.g. a frames::GroundStation on the IAU 2006/2000A
/// chain with EOP) and any StmPropagator (Dop853StmPropagator below: satgnc's DOP853 on any
/// dynamics::ForceModel).
///
/// Contract (core/solver.hpp): BatchSettings::validate() and the problem's checks run in the
/// constructor, which also sizes the workspace (and the propagator's, StmPropagator::reserve);
/// solve() is noexcept, allocates nothing on the heap (SATGNC_NO_MALLOC_SCOPE; with
/// Dop853StmPropagator and a force model whose evaluation does not allocate, e.g. point mass + J2:
/// tests/cpp/test_od_batch.cpp counts 0 mallocs) and returns BatchResult + info.
///
/// Model of a measurement i (reception tag t_i = epoch_i - epoch, s) with parameters
/// p = [x0 (km, km/s), estimated biases]: x(t_i) = flow(x0, t_i) from the propagator, and
///   residual_i = observed_i - predicted_i(x(t_i), range bias, time bias)   (O - C)
/// with azimuth and right ascension residuals wrapped to (-pi, pi]. Rows are whitened by sigma.
/// Jacobian: d predicted / d x0 = (d predicted / d x(t_i)) Phi(t_i, 0) (the propagator's STM),
/// d predicted / d bias from the model (observation::Prediction::dbias).
///
/// Iteration: Gauss-Newton with a backtracking line search. At the iterate p, Householder QR of the
/// whitened [J | r] (src/od/detail/householder_qr.hpp, the OdSolver's) gives R and c = Q^T r; the
/// full step is dp = R^-1 c and |c| = |R dp| is its length in formal sigmas. Convergence test
/// (stated, checked at the returned iterate): |c| <= BatchSettings::sigma_tol, i.e. the iterate is
/// within sigma_tol formal standard deviations of the minimum of the local linear model. A step is
/// accepted when the cost 0.5 |r|^2 decreases (halving up to max_halvings times); otherwise the status
/// is stalled. With BatchMethod::levenberg_marquardt the step instead minimizes
/// |R dp - c|^2 + lambda |D dp|^2 (QR of [R c; sqrt(lambda) D 0], no normal equations) with Moré's
/// scaling D = diag(max over the iterations of the column norms of R); lambda starts at lm_lambda0,
/// follows the gain ratio rho = actual / predicted decrease (x lm_decrease when rho > 0.75 right away,
/// else Nielsen's max(1/3, 1 - (2 rho - 1)^3); x lm_increase after a rejected trial), and below 1e-12 is
/// 0 (pure Gauss-Newton end game). Same convergence test. The returned iterate is always the best (lowest
/// cost) one evaluated with a Jacobian, and the covariance (R^T R)^-1 (parameters' units), the correlation
/// and the residuals are those of that iterate.
#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

#include "satgnc/core/epoch.hpp"
#include "satgnc/core/solver.hpp"
#include "satgnc/core/status.hpp"
#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/observation/measurement_model.hpp"
#include "satgnc/observation/station_ephemeris.hpp"
#include "satgnc/od/propagator.hpp"
#include "satgnc/od/tracking_data.hpp"
#include "satgnc/propagation/dop853.hpp"

namespace satgnc::od {

using core::OdStatus;

namespace detail {
struct BatchWorkspace;  // src/od/detail/batch_workspace.hpp
}  // namespace detail

/// StmPropagator on satgnc's DOP853 (propagation/dop853.hpp) with any dynamics::ForceModel: states
/// and STMs at the requested ascending times (either side of t = 0: a forward arc over t >= 0 and a
/// backward arc over t < 0, as propagate_dop853 splits them, with the same arithmetic bit for bit).
/// The force model's epoch (for the Sun, Moon, SRP) is the caller's: set it to the estimator's epoch.
/// Allocation-free after reserve(n) (propagation/dop853_arc.hpp writes straight into the caller's
/// arrays; only the backward arc needs the reversed buffers sized by reserve); a call with more
/// backward times than reserved grows the buffers once. Not for concurrent use (one force-model
/// workspace).
class Dop853StmPropagator final : public StmPropagator {
 public:
  /// Validates the model and the settings (std::invalid_argument naming the field).
  explicit Dop853StmPropagator(const dynamics::ForceModel& model,
                               const propagation::Dop853Settings& settings = {});
  /// False when the input is invalid (non-finite, |r0| = 0, times not ascending), the propagation
  /// fails or the force model throws.
  bool propagate(const Vec6& x0, const double* times, int n, Vec6* states, Mat6* stms) override;
  /// Size the backward-arc buffers for up to max_times times (>= 0).
  void reserve(int max_times) override;
  /// The force model.
  const dynamics::ForceModel& model() const noexcept { return model_; }

 private:
  dynamics::ForceModel model_;
  propagation::Dop853Settings settings_;
  std::vector<double> back_t_;  // backward arc: times in decreasing order
  std::vector<Vec6> back_x_;
  std::vector<Mat6> back_p_;
};

/// A station of the batch problem: its ephemeris and its biases (each estimated or fixed).
struct BatchStation {
  /// GCRF ephemeris whose t = 0 is BatchProblem::epoch (e.g. an EarthFixedStationEphemeris on an
  /// frames::IauEarthRotation with that epoch). Must not be null.
  std::shared_ptr<const observation::StationEphemeris> ephemeris;
  bool estimate_range_bias = false;  ///< estimate the range bias (needs range data of this station)
  bool estimate_time_bias = false;   ///< estimate the time bias (needs data of this station)
  double range_bias = 0.0;           ///< km: the fixed value, or the initial guess when estimated
  double time_bias = 0.0;            ///< s: the fixed value, or the initial guess when estimated
  std::string name;                  ///< label (parameter names)
};

/// The estimation problem: epoch, stations, measurements.
struct BatchProblem {
  core::Epoch epoch;  ///< t = 0 of the state x0, of the station ephemerides and of the propagator
  std::vector<BatchStation> stations;  ///< index k is TrackingMeasurement::station = k
  TrackingData data;                   ///< the measurements (time order)
};

/// Iteration of BatchEstimator::solve() (see the file comment).
enum class BatchMethod {
  gauss_newton,        ///< Gauss-Newton with backtracking (default)
  levenberg_marquardt  ///< Levenberg-Marquardt with Moré scaling: robust from a far initial guess
};

/// Settings (defaults documented; validate() names the field).
struct BatchSettings {
  BatchMethod method = BatchMethod::gauss_newton;  ///< iteration
  int max_iterations = 25;                         ///< accepted steps, >= 1
  /// Convergence: the full Gauss-Newton step is at most this many formal sigmas long (|c| above), > 0.
  double sigma_tol = 1e-3;
  int max_halvings = 30;       ///< Gauss-Newton: line-search halvings before the status is stalled, [0, 100]
  double lm_lambda0 = 1e-3;    ///< LM: initial damping, relative to the Moré scaling, > 0
  double lm_increase = 10.0;   ///< LM: damping factor after a rejected trial, > 1
  double lm_decrease = 0.1;    ///< LM: damping factor after a very successful step (rho > 0.75), in (0, 1)
  int lm_max_rejections = 30;  ///< LM: rejected trials in a row before the status is stalled, >= 1
  double rank_tol = 1e-12;  ///< singular values of the column-scaled R below rank_tol * s_max count as zero
  double min_radius = dynamics::earth::radius;  ///< km: an iterate with |r0| below it is not tried (diverged)
  /// Light-time models (observation::MeasurementModel); false: the instantaneous geometry at the tag
  /// (no light time; the two-way observables then equal the one-way ones), for the effect-size study.
  bool light_time = true;
  bool troposphere = false;  ///< add the tropospheric delay to range observables (unless already applied)
  bool shapiro = false;      ///< add the Shapiro delay to range observables (unless already applied)
  /// Troposphere of this run: Saastamoinen (radio, default), Mendes-Pavlis or Marini-Murray (laser ranging).
  observation::TroposphereModel troposphere_model = observation::TroposphereModel::saastamoinen;
  /// Laser wavelength of Mendes-Pavlis / Marini-Murray, micrometres, [0.3, 1.7].
  double wavelength_um = 0.532;
  double relative_humidity = 0.5;   ///< standard atmosphere of the troposphere model, [0, 1]
  double mu = dynamics::earth::mu;  ///< km^3/s^2: light-time bounce shift and Shapiro delay
  /// Throws std::invalid_argument("field: rule") on a bad value.
  void validate() const;
};

/// Diagnostics. From core::InfoBase: status (od's OdStatus: converged, max_iterations, singular,
/// diverged, propagation_failed, degenerate_geometry, stalled), iterations (accepted steps),
/// primal_residual (RMS of the whitened residuals at the returned iterate), dual_residual (|c|: the
/// remaining Gauss-Newton step in formal sigmas), solve_time (s).
struct BatchInfo : core::InfoBase<OdStatus> {
  int evaluations = 0;  ///< propagations + model evaluations of all rows (trial points included)
};

/// Result of BatchEstimator::solve() (arrays sized at setup).
struct BatchResult {
  OdStatus status = OdStatus::unsolved;      ///< mirrors info.status
  int iterations = 0;                        ///< accepted steps
  Vec6 x0 = Vec6::Zero();                    ///< GCRF state at the epoch, km, km/s
  Eigen::VectorXd range_bias;                ///< per station, km (estimated or fixed)
  Eigen::VectorXd time_bias;                 ///< per station, s (estimated or fixed)
  Eigen::VectorXd parameters;                ///< [x0, estimated biases] (names in parameter_names)
  std::vector<std::string> parameter_names;  ///< "x", "y", "z", "vx", "vy", "vz", "range_bias[NAME]", ...
  Eigen::MatrixXd covariance;   ///< formal (J^T W J)^-1 of the parameters; +inf diagonal when rank-deficient
  Eigen::MatrixXd correlation;  ///< of covariance
  Eigen::VectorXd sigma;        ///< sqrt of the covariance diagonal
  int rank = 0;                 ///< numerical rank of the column-scaled Jacobian
  double condition_number = 0.0;  ///< of the column-scaled Jacobian
  double cost = 0.0;              ///< 0.5 |whitened residuals|^2
  double rms = 0.0;               ///< RMS of the whitened residuals
  /// Post-fit residuals O - C per measurement (time order, rows of TrackingData), n x 2: km, km/s
  /// or rad; column 1 is NaN for scalar observables.
  Eigen::MatrixXd residuals;
  Eigen::MatrixXd normalized;          ///< residuals / sigma, n x 2 (NaN where unused)
  Eigen::VectorXi measurement_status;  ///< core::ObservationStatus value per measurement
  Eigen::VectorXd history_cost;        ///< cost after k accepted steps (rows 0..iterations)
  BatchInfo info;                      ///< status, iterations, residuals, solve time
};

/// Batch least-squares estimator. Move-only; solve() does not throw.
class BatchEstimator {
 public:
  /// Validates the settings and the problem and sizes the workspace. Throws std::invalid_argument:
  /// "stations: must not be empty", "stations[k].ephemeris: must not be null", "data: refers to n
  /// stations but the problem has m", "data: r rows for p parameters (need at least p)",
  /// "stations[k].estimate_range_bias: station k has no range measurements",
  /// "stations[k].estimate_time_bias: station k has no measurements", "propagator: must not be null",
  /// the bias values finite.
  BatchEstimator(BatchProblem problem, std::shared_ptr<StmPropagator> propagator,
                 const BatchSettings& settings = {});
  ~BatchEstimator();
  BatchEstimator(BatchEstimator&&) noexcept;
  BatchEstimator& operator=(BatchEstimator&&) noexcept;
  BatchEstimator(const BatchEstimator&) = delete;
  BatchEstimator& operator=(const BatchEstimator&) = delete;

  /// Initial guess of x0 (km, km/s); the bias guesses are BatchStation's.
  void set_initial_guess(const Vec6& x0) noexcept;
  /// Iterate from the initial guess (see the file comment). The reference stays valid until the next solve().
  const BatchResult& solve() noexcept;
  /// Number of parameters (6 + estimated biases).
  int n_parameters() const noexcept;
  /// Scalar rows (TrackingData::rows()).
  int n_rows() const noexcept;
  /// Evaluate the whitened residuals r (O - C)/sigma and the whitened Jacobian J = d(predicted /
  /// sigma)/dp at parameters p (rows in time order, an angle pair's two rows consecutive). For tests
  /// and tools; allocates on first call. Returns false when the propagation or a prediction fails.
  bool evaluate(const Eigen::VectorXd& p, Eigen::VectorXd& r, Eigen::MatrixXd& J);
  /// The problem, settings and last result.
  const BatchProblem& problem() const noexcept;
  const BatchSettings& settings() const noexcept;  ///< the validated settings
  const BatchResult& result() const noexcept;      ///< the last result

 private:
  std::unique_ptr<detail::BatchWorkspace> w_;
};

}  // namespace satgnc::od
