// Orbit front end of filter::KalmanFilter and filter::RtsSmoother: settings and measurements in,
// the engine's result out as OrbitFilterResult (see satgnc/filter/orbit_filter.hpp).
#include "satgnc/filter/orbit_filter.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "satgnc/core/validate.hpp"
#include "satgnc/filter/gating.hpp"
#include "satgnc/filter/kalman_filter.hpp"
#include "satgnc/filter/rts.hpp"

namespace satgnc::filter {

using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {
template <class M>
void put(std::vector<double>& dst, std::size_t k, const M& m) {
  // Row-major copy of m into slot k of a time-major array.
  const std::size_t sz = static_cast<std::size_t>(m.size());
  double* d = dst.data() + k * sz;
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) *d++ = m(i, j);
}

// The engine's settings of an orbit filter: EKF Joseph (vector update of each record) or UKF, the
// gate, the count warm-up and the consider states by index.
FilterSettings engine_settings(const OrbitFilterSettings& o) {
  FilterSettings s;
  s.algorithm = o.method == OrbitFilterMethod::ukf ? FilterAlgorithm::ukf : FilterAlgorithm::ekf;
  s.form = CovarianceForm::joseph;
  s.sequential = false;
  s.ukf_alpha = o.ukf_alpha;
  s.ukf_beta = o.ukf_beta;
  s.ukf_kappa = o.ukf_kappa;
  s.gating = o.gating;
  s.gate_probability = o.gate_probability;
  s.warm_up_records = o.warmup;
  s.consider_states = o.consider;
  s.store_smoother_data = true;
  return s;
}
}  // namespace

double chi2_quantile(int dof, double p) {
  core::require(dof == 1 || dof == 2, "dof", "must be 1 or 2, got " + std::to_string(dof));
  core::require(std::isfinite(p) && p > 0.0 && p < 1.0, "gate_probability",
                "must be in (0, 1), got " + std::to_string(p));
  return chi_square_quantile(dof, p);
}

void OrbitFilterSettings::validate(int n) const {
  core::require(std::isfinite(gate_probability) && gate_probability > 0.0 && gate_probability < 1.0,
                "gate_probability", "must be in (0, 1), got " + std::to_string(gate_probability));
  core::require(warmup >= 0, "warmup", "must be >= 0, got " + std::to_string(warmup));
  core::require(method == OrbitFilterMethod::ekf || method == OrbitFilterMethod::ukf, "method",
                "must be ekf or ukf");
  core::require_positive(ukf_alpha, "ukf_alpha");
  core::require_finite(ukf_beta, "ukf_beta");
  core::require(std::isfinite(ukf_kappa) && n + ukf_kappa > 0.0, "ukf_kappa",
                "must be finite with n + kappa > 0, got " + std::to_string(ukf_kappa));
  std::vector<int> seen(static_cast<std::size_t>(n), 0);
  for (std::size_t i = 0; i < consider.size(); ++i) {
    const int c = consider[i];
    const std::string name = "consider[" + std::to_string(i) + "]";
    core::require(c >= 6 && c < n, name,
                  "must be a parameter index in [6, " + std::to_string(n) + "), got " + std::to_string(c));
    core::require(seen[static_cast<std::size_t>(c)] == 0, name, "index " + std::to_string(c) + " repeated");
    seen[static_cast<std::size_t>(c)] = 1;
  }
}

OrbitFilter::OrbitFilter(OrbitProcessModel process, OrbitMeasurementFunction measurement,
                         const OrbitFilterSettings& settings)
    : process_(std::move(process)), measurement_(std::move(measurement)), settings_(settings) {
  n_ = process_.dimension();
  core::require(measurement_.dimension() == n_, "measurement",
                "state dimension " + std::to_string(measurement_.dimension()) +
                    " differs from the process model's " + std::to_string(n_));
  settings_.validate(n_);
  engine_settings(settings_).validate();
  gate1_ = chi2_quantile(1, settings_.gate_probability);
  gate2_ = chi2_quantile(2, settings_.gate_probability);
}

OrbitFilter::~OrbitFilter() = default;
OrbitFilter::OrbitFilter(OrbitFilter&&) noexcept = default;
OrbitFilter& OrbitFilter::operator=(OrbitFilter&&) noexcept = default;

OrbitFilterResult OrbitFilter::run(double t0, const VectorXd& x0, const MatrixXd& p0,
                                   const std::vector<OrbitMeasurement>& meas) {
  const int n = n_;
  core::require_finite(t0, "t0");
  core::require(x0.size() == n, "x0",
                "must have " + std::to_string(n) + " entries, got " + std::to_string(x0.size()));
  core::require_finite(x0, "x0");
  core::require(p0.rows() == n && p0.cols() == n, "P0",
                "must be " + std::to_string(n) + " x " + std::to_string(n));
  core::require_finite(p0, "P0");
  core::require((p0 - p0.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * p0.cwiseAbs().maxCoeff(), "P0",
                "must be symmetric");
  core::require(Eigen::LLT<MatrixXd>(p0).info() == Eigen::Success, "P0",
                "must be positive definite (Cholesky failed)");
  double prev = t0;
  const int n_stations = static_cast<int>(measurement_.settings().stations.size());
  for (std::size_t i = 0; i < meas.size(); ++i) {
    const auto& m = meas[i];
    // Messages are built only on failure: validation allocates nothing per good measurement.
    const bool t_ok = std::isfinite(m.t) && m.t >= prev;
    const bool s_ok = m.station >= 0 && m.station < n_stations;
    const int sz = measurement_.size(m);
    const bool v_ok = sz > 0 && m.value.head(sz).allFinite();
    if (t_ok && s_ok && v_ok) {
      prev = m.t;
      continue;
    }
    const std::string name = "measurements[" + std::to_string(i) + "]";
    core::require(t_ok, name + ".t",
                  "tags must be finite, non-decreasing and >= t0 (sort the measurements), got " +
                      std::to_string(m.t) + " after " + std::to_string(prev));
    core::require(s_ok, name + ".station", "unknown station index " + std::to_string(m.station));
    core::require(sz > 0, name + ".observable",
                  "observable index " + std::to_string(m.observable) + " was not set up (the filter knows " +
                      std::to_string(measurement_.settings().observables.size()) + ")");
    core::require_finite(m.value.head(sz), name + ".value");
  }
  const std::size_t K = meas.size();
  const std::size_t nu = static_cast<std::size_t>(n);
  const std::size_t nn = nu * nu;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto start = std::chrono::steady_clock::now();
  FilterProblem prob;
  prob.x0 = x0;
  prob.p0 = p0;
  prob.t0 = t0;
  prob.records.resize(K);
  for (std::size_t k = 0; k < K; ++k) prob.records[k] = measurement_.record(meas[k]);
  const long steps_before = process_.total_steps();
  KalmanFilter kf(process_, measurement_, prob, engine_settings(settings_));
  const FilterResult& e = kf.solve();

  OrbitFilterResult r;
  r.n = n;
  r.t.resize(K);
  r.station.resize(K);
  r.observable.resize(K);
  r.size.resize(K);
  r.status.assign(K, OrbitStepStatus::not_run);
  r.state.assign(K * nu, nan);
  r.covariance.assign(K * nn, nan);
  r.prefit.assign(2 * K, nan);
  r.postfit.assign(2 * K, nan);
  r.sigma.assign(2 * K, nan);
  r.nis.assign(K, nan);
  r.normalized_residual.assign(K, nan);
  r.gate.assign(K, 0.0);
  r.predicted_state.assign(K * nu, nan);
  r.predicted_covariance.assign(K * nn, nan);
  r.transition.assign(K * nn, nan);
  r.t0 = t0;
  r.consider = settings_.consider;
  r.initial_state = x0;
  r.initial_covariance = p0;
  bool stopped = false;
  for (std::size_t k = 0; k < K; ++k) {
    const StepRecord& s = e.records[k];
    const auto ki = static_cast<Eigen::Index>(k);
    r.t[k] = meas[k].t;
    r.station[k] = meas[k].station;
    r.observable[k] = meas[k].observable;
    const int sz = measurement_.size(meas[k]);
    r.size[k] = sz;
    if (stopped || s.status == FilterStatus::unsolved) {
      stopped = true;
      continue;
    }
    OrbitStepStatus st = OrbitStepStatus::measurement_failed;
    switch (s.status) {
      case FilterStatus::success:
        st = OrbitStepStatus::updated;
        break;
      case FilterStatus::rejected:
        st = OrbitStepStatus::rejected;
        ++r.rejected;
        break;
      case FilterStatus::process_failed:
        st = OrbitStepStatus::propagation_failed;
        break;
      case FilterStatus::covariance_not_pd:
        st = OrbitStepStatus::not_positive_definite;
        break;
      default:
        break;
    }
    r.status[k] = st;
    r.steps_run = static_cast<int>(k) + 1;
    if (st == OrbitStepStatus::propagation_failed) {
      stopped = true;
      continue;
    }
    put(r.predicted_state, k, e.predicted_states.col(ki).transpose());
    put(r.predicted_covariance, k, e.predicted_covariances.middleCols(ki * n, n));
    put(r.transition, k, e.transitions.middleCols(ki * n, n));
    put(r.state, k, e.states.col(ki).transpose());
    put(r.covariance, k, e.covariances.middleCols(ki * n, n));
    if (std::isfinite(s.nis)) {
      const MeasurementRecord& rec = prob.records[k];
      for (int i = 0; i < sz; ++i) {
        const auto iu = static_cast<std::size_t>(i);
        r.prefit[2 * k + iu] = s.prefit[iu];
        r.postfit[2 * k + iu] = s.postfit[iu];
        r.sigma[2 * k + iu] = rec.sigma[iu];
      }
      r.nis[k] = s.nis;
      r.normalized_residual[k] = std::sqrt(s.nis);
      r.gate[k] = s.gate;
    }
    if (st == OrbitStepStatus::not_positive_definite) stopped = true;
  }
  r.propagation_steps = process_.total_steps() - steps_before;
  r.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

OrbitSmootherResult OrbitFilter::smooth(const OrbitFilterResult& f) {
  const int n = f.n;
  core::require(n >= 6 && f.initial_state.size() == n, "result", "is not a filter result (state dimension)");
  const int K = f.steps_run;
  core::require(K >= 1, "result", "has no step to smooth (steps_run = 0)");
  // The orbit result (row-major, time-major) as the engine's FilterResult, then RtsSmoother.
  using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const std::size_t nu = static_cast<std::size_t>(n);
  const std::size_t nn = nu * nu;
  FilterResult run;
  run.n = n;
  run.steps = K;
  run.t0 = f.t0;
  run.initial_state = f.initial_state;
  run.initial_covariance = f.initial_covariance;
  run.states.resize(n, K);
  run.predicted_states.resize(n, K);
  run.covariances.resize(n, static_cast<Eigen::Index>(n) * K);
  run.predicted_covariances.resize(n, static_cast<Eigen::Index>(n) * K);
  run.transitions.resize(n, static_cast<Eigen::Index>(n) * K);
  run.consider = f.consider;
  for (int k = 0; k < K; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    const Eigen::Index c = static_cast<Eigen::Index>(k) * n;
    run.states.col(k) = Eigen::Map<const VectorXd>(f.state.data() + ku * nu, n);
    run.predicted_states.col(k) = Eigen::Map<const VectorXd>(f.predicted_state.data() + ku * nu, n);
    run.covariances.middleCols(c, n) = Eigen::Map<const RowMat>(f.covariance.data() + ku * nn, n, n);
    run.predicted_covariances.middleCols(c, n) =
        Eigen::Map<const RowMat>(f.predicted_covariance.data() + ku * nn, n, n);
    run.transitions.middleCols(c, n) = Eigen::Map<const RowMat>(f.transition.data() + ku * nn, n, n);
  }
  RtsSmoother rts(n, K);
  const SmootherResult& sm = rts.smooth(run);
  core::require(sm.status == FilterStatus::success, "result",
                "the RTS smoother failed at step " + std::to_string(sm.failed_step) +
                    " (predicted covariance not positive definite)");
  OrbitSmootherResult s;
  s.n = n;
  s.t.assign(f.t.begin(), f.t.begin() + K);
  s.state.resize(static_cast<std::size_t>(K) * nu);
  s.covariance.resize(static_cast<std::size_t>(K) * nn);
  for (int k = 0; k < K; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    put(s.state, ku, sm.states.col(k).transpose());
    put(s.covariance, ku, sm.covariances.middleCols(static_cast<Eigen::Index>(k) * n, n));
  }
  s.initial_state = sm.initial_state;
  s.initial_covariance = sm.initial_covariance;
  return s;
}

}  // namespace satgnc::filter
