// filter::KalmanFilter: setup checks, the on-board predict / update, the EKF updates (Joseph,
// conventional, iterated) and the batch run. UD kernels: ud.cpp; UKF: ukf.cpp.
#include "satgnc/filter/kalman_filter.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "detail/filter_workspace.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"
#include "satgnc/filter/gating.hpp"

namespace satgnc::filter {

using core::require;

void FilterSettings::validate() const {
  require(algorithm == FilterAlgorithm::ekf || algorithm == FilterAlgorithm::ukf, "settings.algorithm",
          "must be ekf or ukf");
  require(
      form == CovarianceForm::joseph || form == CovarianceForm::ud || form == CovarianceForm::conventional,
      "settings.form", "must be joseph, ud or conventional");
  require(max_iterations >= 1, "settings.max_iterations",
          "must be >= 1, got " + std::to_string(max_iterations));
  core::require_positive(iteration_tolerance, "settings.iteration_tolerance");
  require(std::isfinite(ukf_alpha) && ukf_alpha > 0.0 && ukf_alpha <= 1.0, "settings.ukf_alpha",
          "must be in (0, 1], got " + std::to_string(ukf_alpha), "1e-3 is the standard default");
  core::require_nonnegative(ukf_beta, "settings.ukf_beta");
  core::require_finite(ukf_kappa, "settings.ukf_kappa");
  require(consider_count >= 0, "settings.consider_count",
          "must be >= 0, got " + std::to_string(consider_count));
  require(std::isfinite(gate_probability) && gate_probability > 0.0 && gate_probability < 1.0,
          "settings.gate_probability", "must be in (0, 1), got " + std::to_string(gate_probability),
          "e.g. 0.999; set gating = false to turn the gate off");
  core::require_nonnegative(warm_up, "settings.warm_up");
  require(warm_up_records >= 0, "settings.warm_up_records",
          "must be >= 0, got " + std::to_string(warm_up_records));
  for (std::size_t i = 0; i < consider_states.size(); ++i) {
    require(consider_states[i] >= 0, "settings.consider_states[" + std::to_string(i) + "]",
            "must be a state index >= 0, got " + std::to_string(consider_states[i]));
  }
  if (consider_count > 0 || !consider_states.empty()) {
    require(algorithm == FilterAlgorithm::ukf || form == CovarianceForm::joseph, "settings.consider_count",
            "consider parameters need the EKF with the Joseph form (any gain is valid there)");
  }
  if (iterated) {
    require(algorithm == FilterAlgorithm::ekf && form != CovarianceForm::ud, "settings.iterated",
            "the iterated EKF needs algorithm ekf with the joseph or conventional form");
  }
}

namespace detail {

void FilterWorkspace::allocate() {
  const int n2 = 2 * n + 1;
  x.setZero(n);
  cmask.setOnes(n);
  P.setZero(n, n);
  U.setIdentity(n, n);
  d.setZero(n);
  last_phi.setIdentity(n, n);
  x1.setZero(n);
  phi.setIdentity(n, n);
  qd.setZero(n, n);
  T.setZero(n, n);
  T2.setZero(n, n);
  W.setZero(n, 2 * n);
  dw.setZero(2 * n);
  G.setIdentity(n, n);
  dq.setZero(n);
  qc.setZero(n, n);
  z.setZero(kM);
  H.setZero(kM, n);
  for (Eigen::VectorXd* vec : {&xbar, &xi, &xn, &ph, &kv, &wv, &f, &v, &b}) vec->setZero(n);
  PHt.setZero(n, kM);
  K.setZero(n, kM);
  TH.setZero(n, kM);
  llt = Eigen::LLT<Eigen::MatrixXd>(
      Eigen::MatrixXd::Identity(n, n));  // computed: a sized-only LLT leaves info() unset (UBSan)
  llt.compute(Eigen::MatrixXd::Identity(n, n));
  X.setZero(n, n2);
  Xp.setZero(n, n2);
  Z.setZero(kM, n2);
  wm.setZero(n2);
  wc.setZero(n2);
}

void FilterWorkspace::symmetrize() noexcept {
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < j; ++i) {
      const double a = 0.5 * (P(i, j) + P(j, i));
      P(i, j) = a;
      P(j, i) = a;
    }
  }
}

void FilterWorkspace::form_covariance() noexcept {
  if (settings.form != CovarianceForm::ud || settings.algorithm != FilterAlgorithm::ekf) return;
  T.noalias() = U * d.asDiagonal();
  P.noalias() = T * U.transpose();
}

bool FilterWorkspace::covariance_pd() noexcept {
  if (!settings.check_covariance) return true;
  if (settings.algorithm == FilterAlgorithm::ekf && settings.form == CovarianceForm::ud) {
    return d.allFinite() && d.minCoeff() > 0.0 && U.allFinite();
  }
  // Unblocked Cholesky of P's lower triangle into T (cheaper than Eigen's LLT set-up at small n).
  const double* p = P.data();
  double* l = T.data();
  for (int c = 0; c < n; ++c) {
    double dgl = p[c * n + c];
    for (int k = 0; k < c; ++k) dgl -= l[k * n + c] * l[k * n + c];
    if (!(dgl > 0.0) || !std::isfinite(dgl)) return false;
    const double lc = std::sqrt(dgl);
    l[c * n + c] = lc;
    for (int i = c + 1; i < n; ++i) {
      double lic = p[c * n + i];
      for (int k = 0; k < c; ++k) lic -= l[k * n + i] * l[k * n + c];
      l[c * n + i] = lic / lc;
    }
  }
  return true;
}

FilterStatus FilterWorkspace::innovation(const MeasurementRecord& rec, int m, StepRecord& out) noexcept {
  const ModelStatus ms = measurement->measure(x, rec, z.head(m), H.topRows(m), true);
  if (ms != ModelStatus::success || !z.head(m).allFinite() || !H.topRows(m).allFinite()) {
    return FilterStatus::measurement_failed;
  }
  for (int i = 0; i < m; ++i) {
    y(i) = rec.value[static_cast<std::size_t>(i)] - z(i);
    r(i) = rec.sigma[static_cast<std::size_t>(i)] * rec.sigma[static_cast<std::size_t>(i)];
  }
  if (settings.form == CovarianceForm::ud) {
    // S = (H U) D (H U)' + R
    TH.leftCols(m).noalias() = U.transpose() * H.topRows(m).transpose();
    PHt.leftCols(m).noalias() = d.asDiagonal() * TH.leftCols(m);
    S.noalias() = TH.leftCols(m).transpose() * PHt.leftCols(m);
  } else {
    PHt.leftCols(m).noalias() = P * H.topRows(m).transpose();
    S.noalias() = H.topRows(m) * PHt.leftCols(m);
  }
  for (int i = 0; i < m; ++i) S(i, i) += r(i);
  return innovation_statistics(m, out);
}

FilterStatus FilterWorkspace::innovation_statistics(int m, StepRecord& out) noexcept {
  sllt.compute(S);
  if (sllt.info() != Eigen::Success || !S.allFinite()) return FilterStatus::innovation_not_pd;
  SmallVec sy = sllt.solve(y);
  out.nis = y.dot(sy);
  for (int i = 0; i < m; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    out.prefit[iu] = y(i);
    out.postfit[iu] = y(i);
    out.innovation_sigma[iu] = std::sqrt(S(i, i));
    out.normalized[iu] = y(i) / std::sqrt(S(i, i));
  }
  return FilterStatus::success;
}

EditFlag FilterWorkspace::gate_decision(const MeasurementRecord& rec, int m, StepRecord& out) noexcept {
  if (!settings.gating || rec.t < t_first + settings.warm_up || seen <= settings.warm_up_records) {
    return EditFlag::warm_up;
  }
  out.gate = gate[static_cast<std::size_t>(m - 1)];
  return out.nis <= out.gate ? EditFlag::accepted : EditFlag::rejected;
}

void FilterWorkspace::postfit(const MeasurementRecord& rec, int m, StepRecord& out) noexcept {
  const ModelStatus ms = measurement->measure(x, rec, z.head(m), H.topRows(m), false);
  for (int i = 0; i < m; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    out.postfit[iu] =
        ms == ModelStatus::success ? rec.value[iu] - z(i) : std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace detail

namespace {

bool bad_qd(const Eigen::MatrixXd& qd) noexcept {
  if (!qd.allFinite()) return true;
  for (Eigen::Index i = 0; i < qd.rows(); ++i) {
    if (qd(i, i) < 0.0) return true;
  }
  return false;
}

void fill_nan(StepRecord& s) noexcept {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  s.prefit.fill(nan);
  s.postfit.fill(nan);
  s.innovation_sigma.fill(nan);
  s.normalized.fill(nan);
  s.nis = nan;
  s.gate = 0.0;
}

// Scalar Joseph (or conventional) update with row j of H, variance rv, residual res. When
// ph_ready, w.ph already holds P h' (the first component: computed for the gate).
FilterStatus scalar_update(detail::FilterWorkspace& w, int j, double rv, double res, bool ph_ready) noexcept {
  const int n = w.n;
  w.f = w.H.row(j).transpose();  // contiguous copy of h
  if (!ph_ready) w.ph.noalias() = w.P * w.f;
  const double s = w.f.dot(w.ph) + rv;
  if (!(s > 0.0) || !std::isfinite(s)) return FilterStatus::innovation_not_pd;
  w.kv = w.ph / s;
  if (w.has_consider) w.kv.array() *= w.cmask.array();
  w.x.noalias() += w.kv * res;
  if (w.settings.form == CovarianceForm::conventional) {
    w.P.noalias() -= w.kv * w.ph.transpose();
    return FilterStatus::success;
  }
  // Joseph as the product: T = (I - k h) P = P - k (P h)'; w = T h'; P+ = T (I - k h)' + r k k'
  // = T - w k' + r k k', both triangles formed and averaged (symmetric by construction).
  double* t = w.T.data();
  const double* p = w.P.data();
  const double* k = w.kv.data();
  const double* ph = w.ph.data();
  for (int c = 0; c < n; ++c) {
    for (int i = 0; i < n; ++i) t[c * n + i] = p[c * n + i] - k[i] * ph[c];
  }
  w.wv.noalias() = w.T * w.f;
  const double* wv = w.wv.data();
  double* po = w.P.data();
  for (int c = 0; c < n; ++c) {
    for (int i = 0; i < c; ++i) {
      const double a = t[c * n + i] - wv[i] * k[c] + rv * k[i] * k[c];
      const double b = t[i * n + c] - wv[c] * k[i] + rv * k[c] * k[i];
      po[c * n + i] = 0.5 * (a + b);
      po[i * n + c] = 0.5 * (a + b);
    }
    po[c * n + c] = t[c * n + c] - wv[c] * k[c] + rv * k[c] * k[c];
  }
  return FilterStatus::success;
}

// Vector Joseph (or conventional) covariance update with gain K and H (m rows) at the current P.
void vector_covariance(detail::FilterWorkspace& w, int m) noexcept {
  auto Hm = w.H.topRows(m);
  auto Km = w.K.leftCols(m);
  if (w.settings.form == CovarianceForm::conventional) {
    w.P.noalias() -= Km * w.PHt.leftCols(m).transpose();
    return;
  }
  w.T = w.P;
  w.T.noalias() -= Km * w.PHt.leftCols(m).transpose();
  w.TH.leftCols(m).noalias() = w.T * Hm.transpose();
  w.P = w.T;
  w.P.noalias() -= w.TH.leftCols(m) * Km.transpose();
  w.TH.leftCols(m).noalias() = Km * w.r.asDiagonal();
  w.P.noalias() += w.TH.leftCols(m) * Km.transpose();
  w.symmetrize();
}

// K = P H' S^-1 from PHt and the factored S, consider rows zeroed.
void vector_gain(detail::FilterWorkspace& w, int m) noexcept {
  w.Sinv.setIdentity(m, m);
  w.sllt.solveInPlace(w.Sinv);
  w.K.leftCols(m).noalias() = w.PHt.leftCols(m) * w.Sinv;
  if (w.has_consider) w.K.leftCols(m).array().colwise() *= w.cmask.array();
}

// Iterated EKF (Gauss-Newton on the MAP cost); on entry xbar = x, H, PHt, S factored at xbar.
FilterStatus iterated_update(detail::FilterWorkspace& w, const MeasurementRecord& rec, int m,
                             StepRecord& out) noexcept {
  const FilterSettings& s = w.settings;
  w.xi = w.xbar;
  bool converged = false;
  int it = 0;
  while (it < s.max_iterations) {
    ++it;
    if (it > 1) {
      const ModelStatus ms = w.measurement->measure(w.xi, rec, w.z.head(m), w.H.topRows(m), true);
      if (ms != ModelStatus::success || !w.z.head(m).allFinite() || !w.H.topRows(m).allFinite()) {
        out.iterations = it;
        return FilterStatus::measurement_failed;
      }
      w.PHt.leftCols(m).noalias() = w.P * w.H.topRows(m).transpose();
      w.S.noalias() = w.H.topRows(m) * w.PHt.leftCols(m);
      for (int i = 0; i < m; ++i) w.S(i, i) += w.r(i);
      w.sllt.compute(w.S);
      if (w.sllt.info() != Eigen::Success) {
        out.iterations = it;
        return FilterStatus::innovation_not_pd;
      }
    }
    vector_gain(w, m);
    // residual linearized at xi: z - h(xi) - H (xbar - xi)
    for (int i = 0; i < m; ++i) w.y(i) = rec.value[static_cast<std::size_t>(i)] - w.z(i);
    w.wv = w.xbar - w.xi;
    w.y.noalias() -= w.H.topRows(m) * w.wv;
    w.xn = w.xbar;
    w.xn.noalias() += w.K.leftCols(m) * w.y;
    const double step = (w.xn - w.xi).norm();
    w.xi = w.xn;
    if (step <= s.iteration_tolerance * (1.0 + w.xi.norm())) {
      converged = true;
      break;
    }
  }
  out.iterations = it;
  w.x = w.xi;
  vector_covariance(w, m);  // Joseph with the last K, H (linearized at the last iterate)
  return converged ? FilterStatus::success : FilterStatus::not_converged;
}

}  // namespace

KalmanFilter::KalmanFilter(ProcessModel& process, MeasurementFunction& measurement,
                           const FilterProblem& problem, const FilterSettings& settings)
    : ws_(std::make_unique<detail::FilterWorkspace>()) {
  settings.validate();
  detail::FilterWorkspace& w = *ws_;
  const int n = process.state_dimension();
  require(n >= 1, "process.state_dimension()", "must be >= 1, got " + std::to_string(n));
  require(problem.x0.size() == n, "problem.x0",
          "must have the process model's state dimension " + std::to_string(n) + ", got " +
              std::to_string(problem.x0.size()));
  core::require_finite(problem.x0, "problem.x0");
  require(problem.p0.rows() == n && problem.p0.cols() == n, "problem.p0",
          "must be " + std::to_string(n) + " x " + std::to_string(n));
  core::require_finite(problem.p0, "problem.p0");
  const double scale = problem.p0.cwiseAbs().maxCoeff();
  require((problem.p0 - problem.p0.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * scale, "problem.p0",
          "must be symmetric (|P - P'| <= 1e-12 max|P|)");
  Eigen::LLT<Eigen::MatrixXd> chol(problem.p0);
  require(chol.info() == Eigen::Success && problem.p0.diagonal().minCoeff() > 0.0, "problem.p0",
          "must be positive definite (Cholesky failed)", "a covariance with a zero or negative variance");
  core::require_finite(problem.t0, "problem.t0");
  require(settings.consider_count < n, "settings.consider_count",
          "must be < the state dimension " + std::to_string(n));
  if (settings.algorithm == FilterAlgorithm::ukf) {
    require(n + settings.ukf_kappa > 0.0, "settings.ukf_kappa", "n + kappa must be > 0");
  }
  double prev = problem.t0;
  for (std::size_t i = 0; i < problem.records.size(); ++i) {
    const MeasurementRecord& rec = problem.records[i];
    const int m = measurement.dimension(rec.type);
    bool ok =
        std::isfinite(rec.t) && rec.t >= problem.t0 && rec.t >= prev && m >= 1 && m <= kMaxMeasurementDim;
    for (int j = 0; ok && j < m; ++j) {
      const auto ju = static_cast<std::size_t>(j);
      ok = std::isfinite(rec.value[ju]) && std::isfinite(rec.sigma[ju]) && rec.sigma[ju] > 0.0;
    }
    if (ok) {  // messages are built only on failure: no allocation per good record
      prev = rec.t;
      continue;
    }
    const std::string name = "problem.records[" + std::to_string(i) + "]";
    require(std::isfinite(rec.t), name + ".t", "must be finite");
    require(rec.t >= problem.t0, name + ".t", "must be >= t0 (records start at or after the initial time)");
    require(rec.t >= prev, name + ".t",
            "records must be sorted by time (non-decreasing): " + std::to_string(rec.t) + " after " +
                std::to_string(prev),
            "sort the records by t first (a stable sort keeps the order of simultaneous records)");
    require(m >= 1 && m <= kMaxMeasurementDim, name + ".type",
            "type " + std::to_string(rec.type) + " is not set up by the measurement function (dimension " +
                std::to_string(m) + ")");
    for (int j = 0; j < m; ++j) {
      const auto ju = static_cast<std::size_t>(j);
      require(std::isfinite(rec.value[ju]), name + ".value", "must be finite");
      require(std::isfinite(rec.sigma[ju]) && rec.sigma[ju] > 0.0, name + ".sigma",
              "must be finite and > 0, got " + std::to_string(rec.sigma[ju]));
    }
  }
  std::vector<int> consider;
  for (int i = n - settings.consider_count; i < n; ++i) consider.push_back(i);
  for (std::size_t i = 0; i < settings.consider_states.size(); ++i) {
    const int c = settings.consider_states[i];
    const std::string name = "settings.consider_states[" + std::to_string(i) + "]";
    require(c < n, name, "must be a state index < " + std::to_string(n) + ", got " + std::to_string(c));
    require(std::find(consider.begin(), consider.end(), c) == consider.end(), name,
            "state " + std::to_string(c) + " is already a consider parameter");
    consider.push_back(c);
  }
  std::sort(consider.begin(), consider.end());
  require(static_cast<int>(consider.size()) < n, "settings.consider_states",
          "at least one state must be estimated");

  w.process = &process;
  w.measurement = &measurement;
  w.settings = settings;
  w.problem = problem;
  w.n = n;
  w.nc = settings.consider_count;
  for (int m = 1; m <= kMaxMeasurementDim; ++m) {
    w.gate[static_cast<std::size_t>(m - 1)] = chi_square_quantile(m, settings.gate_probability);
  }
  w.allocate();
  w.has_consider = !consider.empty();
  for (int c : consider) w.cmask(c) = 0.0;
  if (settings.algorithm == FilterAlgorithm::ukf) {
    const double lambda = settings.ukf_alpha * settings.ukf_alpha * (n + settings.ukf_kappa) - n;
    w.ukf_c = std::sqrt(n + lambda);
    w.wm.setConstant(0.5 / (n + lambda));
    w.wc = w.wm;
    w.wm(0) = lambda / (n + lambda);
    w.wc(0) = w.wm(0) + 1.0 - settings.ukf_alpha * settings.ukf_alpha + settings.ukf_beta;
  }

  const auto N = static_cast<Eigen::Index>(problem.records.size());
  FilterResult& r = w.result;
  r.n = n;
  r.steps = static_cast<int>(N);
  r.t0 = problem.t0;
  r.initial_state = problem.x0;
  r.initial_covariance = problem.p0;
  r.times.setZero(N);
  r.states.setZero(n, N);
  r.covariances.setZero(n, n * N);
  if (settings.store_smoother_data) {
    r.predicted_states.setZero(n, N);
    r.predicted_covariances.setZero(n, n * N);
    r.transitions.setZero(n, n * N);
    if (settings.algorithm == FilterAlgorithm::ekf && settings.form == CovarianceForm::ud) {
      r.ud_factors.setZero(n, n * N);
      r.predicted_ud_factors.setZero(n, n * N);
      r.process_noise_ud_factors.setZero(n, n * N);
      r.initial_ud_factors.setZero(n, n);
    }
  }
  r.records.assign(problem.records.size(), StepRecord{});
  r.consider = consider;
  initialize();
}

KalmanFilter::~KalmanFilter() = default;
KalmanFilter::KalmanFilter(KalmanFilter&&) noexcept = default;
KalmanFilter& KalmanFilter::operator=(KalmanFilter&&) noexcept = default;

void KalmanFilter::initialize() noexcept {
  detail::FilterWorkspace& w = *ws_;
  w.x = w.problem.x0;
  w.P = w.problem.p0;
  w.t = w.problem.t0;
  w.have_first = false;
  w.seen = 0;
  w.last_phi.setIdentity();
  if (w.settings.algorithm == FilterAlgorithm::ekf && w.settings.form == CovarianceForm::ud) {
    w.ud_factor(w.P, w.U, w.d, w.qc);
  }
}

FilterStatus KalmanFilter::predict(double t1) noexcept {
  SATGNC_NO_MALLOC_SCOPE;
  detail::FilterWorkspace& w = *ws_;
  if (!std::isfinite(t1)) return FilterStatus::invalid_time;
  if (t1 == w.t) {
    w.last_phi.setIdentity();
    w.dq.setZero();  // no process noise over a zero step (stored for the UD smoother)
    return FilterStatus::success;
  }
  if (w.settings.algorithm == FilterAlgorithm::ukf) return w.ukf_predict(t1);
  const ModelStatus ms = w.process->propagate(w.x, w.t, t1, w.x1, w.phi, w.qd, true);
  if (ms != ModelStatus::success || !w.x1.allFinite() || !w.phi.allFinite() || bad_qd(w.qd)) {
    return FilterStatus::process_failed;
  }
  w.x = w.x1;
  w.t = t1;
  w.last_phi = w.phi;
  if (w.settings.form == CovarianceForm::ud) {
    return w.thornton();
  }
  w.T.noalias() = w.phi * w.P;
  w.P.noalias() = w.T * w.phi.transpose();
  w.P += w.qd;
  if (w.settings.form == CovarianceForm::joseph) w.symmetrize();
  return w.covariance_pd() ? FilterStatus::success : FilterStatus::covariance_not_pd;
}

FilterStatus KalmanFilter::update(const MeasurementRecord& rec) noexcept {
  SATGNC_NO_MALLOC_SCOPE;
  detail::FilterWorkspace& w = *ws_;
  StepRecord& out = w.last;
  out = StepRecord{};
  fill_nan(out);
  out.t = rec.t;
  out.type = rec.type;
  out.station = rec.station;
  out.flag = EditFlag::failed;
  ++w.seen;
  auto finish = [&out](FilterStatus st) {
    out.status = st;
    return st;
  };
  if (!std::isfinite(rec.t) || rec.t < w.t) return finish(FilterStatus::invalid_time);
  const int m = w.measurement->dimension(rec.type);
  out.dim = m;
  if (m < 1 || m > kMaxMeasurementDim) return finish(FilterStatus::unknown_measurement_type);
  for (int i = 0; i < m; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    if (!std::isfinite(rec.value[iu]) || !(rec.sigma[iu] > 0.0) || !std::isfinite(rec.sigma[iu])) {
      return finish(FilterStatus::measurement_failed);
    }
  }
  if (rec.t > w.t) {
    const FilterStatus ps = predict(rec.t);
    if (ps != FilterStatus::success) return finish(ps);
  }
  if (!w.have_first) {
    w.have_first = true;
    w.t_first = rec.t;
  }
  w.y.resize(m);
  w.r.resize(m);
  w.z.setZero();
  if (w.settings.algorithm == FilterAlgorithm::ukf) return finish(w.ukf_update(rec, m, out));

  out.iterations = 1;
  const FilterStatus is = w.innovation(rec, m, out);
  if (is != FilterStatus::success) return finish(is);
  out.flag = w.gate_decision(rec, m, out);
  if (out.flag == EditFlag::rejected) return finish(FilterStatus::rejected);

  FilterStatus st = FilterStatus::success;
  w.xbar = w.x;
  if (w.settings.iterated) {
    st = iterated_update(w, rec, m, out);
  } else if (w.settings.form == CovarianceForm::ud) {
    for (int j = 0; j < m && st == FilterStatus::success; ++j) {
      const double res = w.y(j) - w.H.row(j).dot(w.x - w.xbar);
      st = w.bierman(j, w.r(j), res);
    }
  } else if (w.settings.sequential) {
    for (int j = 0; j < m && st == FilterStatus::success; ++j) {
      double res = w.y(j);
      if (j == 0) {
        w.ph = w.PHt.col(0);  // P h' of the gate's innovation
      } else {
        w.wv = w.x - w.xbar;
        res -= w.H.row(j).dot(w.wv);
      }
      st = scalar_update(w, j, w.r(j), res, j == 0);
    }
  } else {
    vector_gain(w, m);
    w.x.noalias() += w.K.leftCols(m) * w.y;
    vector_covariance(w, m);
  }
  w.postfit(rec, m, out);
  if (st == FilterStatus::success && !w.covariance_pd()) st = FilterStatus::covariance_not_pd;
  return finish(st);
}

namespace {
// Packed UD block: strict upper triangle = U, diagonal = D (U's unit diagonal implied).
template <class Out>
void pack_ud(const Eigen::MatrixXd& u, const Eigen::VectorXd& d, Out&& out) noexcept {
  out = u.triangularView<Eigen::StrictlyUpper>();
  out.diagonal() = d;
}
}  // namespace

const FilterResult& KalmanFilter::solve() noexcept {
  const auto start = std::chrono::steady_clock::now();
  SATGNC_NO_MALLOC_SCOPE;
  detail::FilterWorkspace& w = *ws_;
  FilterResult& r = w.result;
  const bool store = w.settings.store_smoother_data;
  const int n = w.n;
  r.info = FilterInfo{};
  initialize();
  const bool store_ud = store && r.initial_ud_factors.cols() == n;
  if (store_ud) {
    w.dq.setZero();
    w.G.setIdentity();
    pack_ud(w.U, w.d, r.initial_ud_factors.middleCols(0, n));
  }
  double sum2 = 0.0;
  long count = 0;
  for (StepRecord& s : r.records) s = StepRecord{};
  for (int k = 0; k < r.steps; ++k) {
    const MeasurementRecord& rec = w.problem.records[static_cast<std::size_t>(k)];
    r.times(k) = rec.t;
    const FilterStatus ps = predict(rec.t);
    if (store) {
      r.predicted_states.col(k) = w.x;
      r.predicted_covariances.middleCols(static_cast<Eigen::Index>(k) * n, n) = covariance();
      r.transitions.middleCols(static_cast<Eigen::Index>(k) * n, n) = w.last_phi;
      if (store_ud) {
        pack_ud(w.U, w.d, r.predicted_ud_factors.middleCols(static_cast<Eigen::Index>(k) * n, n));
        pack_ud(w.G, w.dq, r.process_noise_ud_factors.middleCols(static_cast<Eigen::Index>(k) * n, n));
      }
    }
    FilterStatus st = ps;
    if (ps == FilterStatus::success) {
      st = update(rec);
    } else {
      w.last = StepRecord{};
      fill_nan(w.last);
      w.last.t = rec.t;
      w.last.type = rec.type;
      w.last.station = rec.station;
      w.last.dim = w.measurement->dimension(rec.type);
      w.last.flag = EditFlag::failed;
      w.last.status = ps;
      ++w.seen;  // a record, for the count warm-up
    }
    r.records[static_cast<std::size_t>(k)] = w.last;
    r.states.col(k) = w.x;
    r.covariances.middleCols(static_cast<Eigen::Index>(k) * n, n) = covariance();
    if (store_ud) pack_ud(w.U, w.d, r.ud_factors.middleCols(static_cast<Eigen::Index>(k) * n, n));
    ++r.info.iterations;
    const EditFlag fl = w.last.flag;
    if (fl == EditFlag::accepted || fl == EditFlag::warm_up) {
      ++r.info.accepted;
      for (int i = 0; i < w.last.dim; ++i) {
        sum2 +=
            w.last.normalized[static_cast<std::size_t>(i)] * w.last.normalized[static_cast<std::size_t>(i)];
        ++count;
      }
    } else if (fl == EditFlag::rejected) {
      ++r.info.rejected;
    } else {
      ++r.info.failed;
    }
    if (st != FilterStatus::success && st != FilterStatus::rejected && r.info.first_failure < 0) {
      r.info.first_failure = k;
      r.info.status = st;
    }
    if (st == FilterStatus::process_failed) break;
  }
  if (r.info.first_failure < 0) r.info.status = FilterStatus::success;
  r.info.primal_residual = count > 0 ? std::sqrt(sum2 / static_cast<double>(count)) : 0.0;
  r.info.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

const Eigen::VectorXd& KalmanFilter::state() const noexcept { return ws_->x; }
const Eigen::MatrixXd& KalmanFilter::covariance() noexcept {
  ws_->form_covariance();
  return ws_->P;
}
double KalmanFilter::time() const noexcept { return ws_->t; }
const StepRecord& KalmanFilter::last_step() const noexcept { return ws_->last; }
const Eigen::MatrixXd& KalmanFilter::last_transition() const noexcept { return ws_->last_phi; }
const FilterResult& KalmanFilter::result() const noexcept { return ws_->result; }
const FilterSettings& KalmanFilter::settings() const noexcept { return ws_->settings; }
const std::array<double, kMaxMeasurementDim>& KalmanFilter::gate_thresholds() const noexcept {
  return ws_->gate;
}

}  // namespace satgnc::filter
