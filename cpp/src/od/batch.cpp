#include "satgnc/od/batch.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "detail/householder_qr.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"
#include "satgnc/observation/light_time.hpp"
#include "satgnc/propagation/dop853_arc.hpp"

namespace satgnc::od {

using observation::Biases;
using observation::MeasurementModel;
using observation::MeasurementSettings;
using observation::ObservableType;
using observation::ObservationStatus;
using observation::Prediction;
using observation::StationEphemeris;
using observation::StationState;

// ------------------------------------------------------------------------------------------------
Dop853StmPropagator::Dop853StmPropagator(const dynamics::ForceModel& model,
                                         const propagation::Dop853Settings& settings)
    : model_(model), settings_(settings) {
  model_.validate();
  propagation::dop853_validate_settings(settings_);
}

void Dop853StmPropagator::reserve(int max_times) {
  core::require(max_times >= 0, "max_times", "must be >= 0");
  const auto m = static_cast<std::size_t>(max_times);
  if (back_t_.size() < m) {
    back_t_.resize(m);
    back_x_.resize(m);
    back_p_.resize(m);
  }
}

bool Dop853StmPropagator::propagate(const Vec6& x0, const double* times, int n, Vec6* states, Mat6* stms) {
  // The checks of propagate_dop853's validate_orbit_arc_input, as a status instead of an exception.
  if (n < 0 || !x0.allFinite() || !(x0.head<3>().norm() > 0.0)) return false;
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(times[i]) || (i > 0 && times[i] < times[i - 1])) return false;
  try {
    // Split as propagate_dop853 does: t >= 0 forward (ascending), t < 0 backward (descending), the
    // backward arc first when there is one (the first requested time is then negative).
    int k = 0;
    while (k < n && times[k] < 0.0) ++k;
    if (k > 0) {
      reserve(k);  // grows only when setup reserved fewer (then allocates once)
      for (int j = 0; j < k; ++j) back_t_[static_cast<std::size_t>(j)] = times[k - 1 - j];
      const propagation::Dop853Info info =
          propagation::propagate_dop853_arc(model_, x0, 0.0, back_t_.data(), static_cast<std::size_t>(k),
                                            settings_, back_x_.data(), back_p_.data());
      if (info.status != core::Dop853Status::success || info.outputs != static_cast<std::size_t>(k))
        return false;
      for (int j = 0; j < k; ++j) {
        states[k - 1 - j] = back_x_[static_cast<std::size_t>(j)];
        stms[k - 1 - j] = back_p_[static_cast<std::size_t>(j)];
      }
    }
    if (k < n) {
      const auto m = static_cast<std::size_t>(n - k);
      const propagation::Dop853Info info =
          propagation::propagate_dop853_arc(model_, x0, 0.0, times + k, m, settings_, states + k, stms + k);
      if (info.status != core::Dop853Status::success || info.outputs != m) return false;
    }
    return true;
  } catch (...) {
    return false;
  }
}

// ------------------------------------------------------------------------------------------------
void BatchSettings::validate() const {
  core::require(max_iterations >= 1, "max_iterations", "must be >= 1");
  core::require_positive(sigma_tol, "sigma_tol");
  core::require(max_halvings >= 0 && max_halvings <= 100, "max_halvings", "must be in [0, 100]");
  core::require(method == BatchMethod::gauss_newton || method == BatchMethod::levenberg_marquardt, "method",
                "must be gauss_newton or levenberg_marquardt");
  core::require_positive(lm_lambda0, "lm_lambda0");
  core::require(std::isfinite(lm_increase) && lm_increase > 1.0, "lm_increase", "must be > 1");
  core::require(std::isfinite(lm_decrease) && lm_decrease > 0.0 && lm_decrease < 1.0, "lm_decrease",
                "must be in (0, 1)");
  core::require(lm_max_rejections >= 1, "lm_max_rejections", "must be >= 1");
  core::require(std::isfinite(rank_tol) && rank_tol > 0.0 && rank_tol < 1.0, "rank_tol", "must be in (0, 1)");
  core::require_nonnegative(min_radius, "min_radius");
  observation::validate_troposphere_options(relative_humidity, troposphere_model, wavelength_um);
  core::require_positive(mu, "mu");
}

namespace {

constexpr double kPi = 3.14159265358979323846;

bool is_range(ObservableType t) {
  return t == ObservableType::one_way_range || t == ObservableType::two_way_range;
}
bool is_range_rate(ObservableType t) {
  return t == ObservableType::one_way_range_rate || t == ObservableType::two_way_range_rate;
}

double wrap_pi(double a) {
  a = std::fmod(a, 2.0 * kPi);
  if (a > kPi) a -= 2.0 * kPi;
  if (a <= -kPi) a += 2.0 * kPi;
  return a;
}

// Value (and d value / d rho, d value / d rhodot) of the instantaneous geometry: rho = r - R,
// rhodot = v - V at one instant; enu rows east/north/up in GCRF.
bool instantaneous_value(ObservableType type, const Vec3& rho, const Vec3& rhodot, const Mat3& enu,
                         Eigen::Vector2d& value, Eigen::Matrix<double, 2, 3>* d_rho,
                         Eigen::Matrix<double, 2, 3>* d_rhodot) {
  const double range = rho.norm();
  if (!(range > 1e-6)) return false;
  const Vec3 u = rho / range;
  if (d_rho) d_rho->setZero();
  if (d_rhodot) d_rhodot->setZero();
  switch (type) {
    case ObservableType::one_way_range:
    case ObservableType::two_way_range:
      value[0] = range;
      if (d_rho) d_rho->row(0) = u.transpose();
      return true;
    case ObservableType::one_way_range_rate:
    case ObservableType::two_way_range_rate: {
      const double rr = u.dot(rhodot);
      value[0] = rr;
      if (d_rho) d_rho->row(0) = ((rhodot - u * rr) / range).transpose();
      if (d_rhodot) d_rhodot->row(0) = u.transpose();
      return true;
    }
    case ObservableType::azimuth_elevation:
    case ObservableType::right_ascension_declination: {
      const bool azel = type == ObservableType::azimuth_elevation;
      const Mat3 M = azel ? enu : Mat3::Identity();
      const Vec3 l = M * rho;
      // azel: l = (e, n, u), az = atan2(e, n); radec: l = (x, y, z), ra = atan2(y, x).
      const double a = azel ? l[0] : l[1];
      const double b = azel ? l[1] : l[0];
      const double h2 = l[0] * l[0] + l[1] * l[1];
      const double h = std::sqrt(h2);
      if (!(h > 1e-9 * range)) return false;
      double ang = std::atan2(a, b);
      if (ang < 0.0) ang += 2.0 * kPi;
      value[0] = ang;
      value[1] = std::atan2(l[2], h);
      if (d_rho) {
        Eigen::Matrix<double, 2, 3> dl;
        // d atan2(a, b) = (b da - a db) / h2
        if (azel)
          dl.row(0) << b / h2, -a / h2, 0.0;
        else
          dl.row(0) << -a / h2, b / h2, 0.0;
        const double r2 = range * range;
        dl.row(1) << -l[0] * l[2] / (r2 * h), -l[1] * l[2] / (r2 * h), h / r2;
        *d_rho = dl * M;
      }
      return true;
    }
  }
  return false;
}

// The instantaneous prediction (no light time) at reception t + time bias: the spacecraft state
// two-body-shifted by the time bias, the station at t + time bias. Time-bias partial by a central
// difference over +-1 ms (as MeasurementModel does for non-range observables).
void predict_instantaneous(ObservableType type, const StationEphemeris& st, double t, const Vec6& x,
                           const Biases& b, double mu, bool time_partial, Prediction& out) noexcept {
  out.size = observation::observable_size(type);
  out.value.setZero();
  out.dx.setZero();
  out.dbias.setZero();
  out.tau_down = out.tau_up = 0.0;
  out.iterations = 0;
  out.troposphere = out.shapiro = 0.0;
  auto value_at = [&](double dt, Eigen::Vector2d& v, Mat6* dxs_dx, Eigen::Matrix<double, 2, 3>* dr,
                      Eigen::Matrix<double, 2, 3>* dv) {
    Vec6 xs;
    observation::shift_state(x, dt, mu, xs, dxs_dx);
    StationState s;
    st.state(t + dt, s);
    return instantaneous_value(type, xs.head<3>() - s.r, xs.tail<3>() - s.v, s.enu, v, dr, dv);
  };
  Mat6 dxs;
  Eigen::Matrix<double, 2, 3> dr, dv;
  Eigen::Vector2d v;
  if (!x.allFinite() || !std::isfinite(t) || !std::isfinite(b.time) || !std::isfinite(b.range)) {
    out.status = ObservationStatus::invalid_input;
    return;
  }
  if (!value_at(b.time, v, &dxs, &dr, &dv)) {
    out.status = ObservationStatus::degenerate_geometry;
    return;
  }
  out.value = v;
  Eigen::Matrix<double, 2, 6> dxsh;
  dxsh.leftCols<3>() = dr;
  dxsh.rightCols<3>() = dv;
  out.dx = dxsh * dxs;
  if (is_range(type)) {
    out.value[0] += b.range;
    out.dbias(0, 0) = 1.0;
  }
  if (time_partial) {
    constexpr double h = 1e-3;
    Eigen::Vector2d vp, vm;
    if (value_at(b.time + h, vp, nullptr, nullptr, nullptr) &&
        value_at(b.time - h, vm, nullptr, nullptr, nullptr)) {
      Eigen::Vector2d d = vp - vm;
      if (type == ObservableType::azimuth_elevation || type == ObservableType::right_ascension_declination)
        d[0] = wrap_pi(d[0]);
      out.dbias.col(1) = d / (2.0 * h);
    }
  }
  out.status = ObservationStatus::success;
}

}  // namespace

// ------------------------------------------------------------------------------------------------
namespace detail {

struct BatchWorkspace {
  BatchProblem problem;
  BatchSettings settings;
  std::shared_ptr<StmPropagator> propagator;
  // models[type * 4 + 2 * tropo + shapiro] (range types only carry modifiers)
  std::vector<std::optional<MeasurementModel>> models;
  bool time_partials = false;
  int n_meas = 0, rows = 0, n_par = 6;
  std::vector<int> col_range, col_time;  // per station: parameter column or -1
  std::vector<int> row0;                 // per measurement: first row
  std::vector<int> time_index;           // per measurement: index into times
  std::vector<int> model_index;          // per measurement
  std::vector<double> times;             // unique tags, s after the epoch
  std::vector<Vec6> states;
  std::vector<Mat6> stms;
  Eigen::VectorXd p, p_best, p_trial, dp;
  Eigen::VectorXd r, r_trial;      // whitened residuals
  Eigen::MatrixXd J, J_trial;      // whitened Jacobian
  Eigen::MatrixXd raw, raw_trial;  // n x 2 raw residuals
  Eigen::VectorXi ostat, ostat_trial;
  Eigen::MatrixXd A;  // [J | r]
  HouseholderQrWorkspace qr;
  Eigen::MatrixXd R, Rinv, Rs;
  Eigen::VectorXd c, colscale;
  Eigen::MatrixXd L;             // LM: [R c; sqrt(lambda) D 0], 2P x (P + 1)
  HouseholderQrWorkspace qr_lm;  // its QR
  Eigen::VectorXd diag, Rdp;     // LM: Moré scaling D; R dp
  Eigen::JacobiSVD<Eigen::MatrixXd> svd;
  Vec6 guess = Vec6::Zero();
  BatchResult result;

  void biases(const Eigen::VectorXd& par, int k, Biases& b) const {
    const BatchStation& s = problem.stations[static_cast<std::size_t>(k)];
    b.range = col_range[static_cast<std::size_t>(k)] >= 0 ? par[col_range[static_cast<std::size_t>(k)]]
                                                          : s.range_bias;
    b.time =
        col_time[static_cast<std::size_t>(k)] >= 0 ? par[col_time[static_cast<std::size_t>(k)]] : s.time_bias;
  }

  // Residuals and Jacobian at par. Returns success or the failure status.
  OdStatus eval(const Eigen::VectorXd& par, Eigen::VectorXd& rr, Eigen::MatrixXd& JJ, Eigen::MatrixXd& rw,
                Eigen::VectorXi& os, double& cost) noexcept {
    const Vec6 x0 = par.head<6>();
    if (!x0.allFinite()) return OdStatus::diverged;
    if (x0.head<3>().norm() <= settings.min_radius) return OdStatus::diverged;
    bool ok = false;
    try {
      ok =
          propagator->propagate(x0, times.data(), static_cast<int>(times.size()), states.data(), stms.data());
    } catch (...) {
      ok = false;
    }
    ++result.info.evaluations;
    if (!ok) return OdStatus::propagation_failed;
    JJ.setZero();
    rw.setConstant(std::numeric_limits<double>::quiet_NaN());
    Prediction pr;
    Biases b;
    for (int i = 0; i < n_meas; ++i) {
      const TrackingMeasurement& m = problem.data[i];
      const std::size_t k = static_cast<std::size_t>(m.station);
      const StationEphemeris& st = *problem.stations[k].ephemeris;
      const double t = m.epoch - problem.epoch;
      const std::size_t ti = static_cast<std::size_t>(time_index[static_cast<std::size_t>(i)]);
      biases(par, m.station, b);
      if (settings.light_time)
        models[static_cast<std::size_t>(model_index[static_cast<std::size_t>(i)])]->predict(st, t, states[ti],
                                                                                            b, pr);
      else
        predict_instantaneous(m.type, st, t, states[ti], b, settings.mu, time_partials, pr);
      os[i] = static_cast<int>(pr.status);
      if (pr.status != ObservationStatus::success) return OdStatus::degenerate_geometry;
      const int size = m.size();
      const bool angle = size == 2;
      const Eigen::Matrix<double, 2, 6> dx0 = pr.dx * stms[ti];
      for (int j = 0; j < size; ++j) {
        const int row = row0[static_cast<std::size_t>(i)] + j;
        double res = m.value[j] - pr.value[j];
        if (angle && j == 0) res = wrap_pi(res);
        rw(i, j) = res;
        const double w = 1.0 / m.sigma[j];
        rr[row] = res * w;
        JJ.row(row).head<6>() = dx0.row(j) * w;
        if (col_range[k] >= 0) JJ(row, col_range[k]) = pr.dbias(j, 0) * w;
        if (col_time[k] >= 0) JJ(row, col_time[k]) = pr.dbias(j, 1) * w;
      }
    }
    cost = 0.5 * rr.squaredNorm();
    return std::isfinite(cost) ? OdStatus::converged : OdStatus::diverged;
  }

  // QR of [J | r] at the current point: R, c, rank, condition; returns |c|.
  double factor(const Eigen::MatrixXd& JJ, const Eigen::VectorXd& rr, int& rank, double& cond) {
    A.leftCols(n_par) = JJ;
    A.col(n_par) = rr;
    householder_qr_inplace(A, qr);
    R = A.topLeftCorner(n_par, n_par).triangularView<Eigen::Upper>();
    c = A.col(n_par).head(n_par);
    for (int j = 0; j < n_par; ++j) {
      const double s = R.col(j).norm();
      colscale[j] = s > 0.0 ? s : 1.0;
    }
    Rs = R * colscale.cwiseInverse().asDiagonal();
    svd.compute(Rs);
    const Eigen::VectorXd& sv = svd.singularValues();
    const double smax = sv[0];
    rank = 0;
    for (int j = 0; j < n_par; ++j)
      if (sv[j] > settings.rank_tol * smax) ++rank;
    cond = sv[n_par - 1] > 0.0 ? smax / sv[n_par - 1] : std::numeric_limits<double>::infinity();
    return c.norm();
  }

  // LM step: dp = argmin |R dp - c|^2 + lambda |D dp|^2 by QR of [R c; sqrt(lambda) D 0].
  void damped_step(double lambda) {
    L.setZero();
    L.topLeftCorner(n_par, n_par) = R;
    L.col(n_par).head(n_par) = c;
    L.bottomLeftCorner(n_par, n_par).diagonal() = std::sqrt(lambda) * diag;
    householder_qr_inplace(L, qr_lm);
    dp = L.col(n_par).head(n_par);
    L.topLeftCorner(n_par, n_par).triangularView<Eigen::Upper>().solveInPlace(dp);
  }
};

}  // namespace detail

// ------------------------------------------------------------------------------------------------
BatchEstimator::BatchEstimator(BatchProblem problem, std::shared_ptr<StmPropagator> propagator,
                               const BatchSettings& settings)
    : w_(std::make_unique<detail::BatchWorkspace>()) {
  settings.validate();
  core::require(propagator != nullptr, "propagator", "must not be null");
  const std::size_t ns = problem.stations.size();
  core::require(ns > 0, "stations", "must not be empty");
  const TrackingData& data = problem.data;
  core::require(data.n_stations() == static_cast<int>(ns), "data",
                "refers to " + std::to_string(data.n_stations()) + " stations but the problem has " +
                    std::to_string(ns));
  detail::BatchWorkspace& w = *w_;
  w.col_range.assign(ns, -1);
  w.col_time.assign(ns, -1);
  w.result.parameter_names = {"x", "y", "z", "vx", "vy", "vz"};
  int np = 6;
  for (std::size_t k = 0; k < ns; ++k) {
    const BatchStation& s = problem.stations[k];
    const std::string at = "stations[" + std::to_string(k) + "]";
    const std::string label = s.name.empty() ? std::to_string(k) : s.name;
    core::require(s.ephemeris != nullptr, at + ".ephemeris", "must not be null");
    core::require_finite(s.range_bias, at + ".range_bias");
    core::require_finite(s.time_bias, at + ".time_bias");
    if (s.estimate_range_bias) {
      core::require(data.range_count(static_cast<int>(k)) > 0, at + ".estimate_range_bias",
                    "station " + label + " has no range measurements (hint: fix its range bias)");
      w.col_range[k] = np++;
      w.result.parameter_names.push_back("range_bias[" + label + "]");
    }
    if (s.estimate_time_bias) {
      core::require(data.count(static_cast<int>(k)) > 0, at + ".estimate_time_bias",
                    "station " + label + " has no measurements (hint: fix its time bias)");
      w.col_time[k] = np++;
      w.result.parameter_names.push_back("time_bias[" + label + "]");
      w.time_partials = true;
    }
  }
  core::require(data.rows() >= np, "data",
                std::to_string(data.rows()) + " rows for " + std::to_string(np) +
                    " parameters (need at least " + std::to_string(np) + ")");
  w.n_par = np;
  w.n_meas = data.size();
  w.rows = data.rows();
  w.settings = settings;
  w.propagator = std::move(propagator);
  // Measurement models: one per (observable, troposphere, shapiro) in use.
  w.models.resize(24);
  w.row0.resize(static_cast<std::size_t>(w.n_meas));
  w.time_index.resize(static_cast<std::size_t>(w.n_meas));
  w.model_index.resize(static_cast<std::size_t>(w.n_meas));
  int row = 0;
  for (int i = 0; i < w.n_meas; ++i) {
    const TrackingMeasurement& m = data[i];
    const bool delayed = is_range(m.type) || is_range_rate(m.type);  // range: delay; range-rate: its rate
    const bool tropo = delayed && settings.troposphere && !(m.corrections & kTroposphereApplied);
    const bool shap = delayed && settings.shapiro && !(m.corrections & kShapiroApplied);
    const int mi = static_cast<int>(m.type) * 4 + 2 * (tropo ? 1 : 0) + (shap ? 1 : 0);
    if (!w.models[static_cast<std::size_t>(mi)]) {
      MeasurementSettings ms;
      ms.type = m.type;
      ms.troposphere = tropo;
      ms.shapiro = shap;
      ms.troposphere_model = settings.troposphere_model;
      ms.wavelength_um = settings.wavelength_um;
      ms.relative_humidity = settings.relative_humidity;
      ms.mu = settings.mu;
      ms.time_bias_partials = w.time_partials;
      w.models[static_cast<std::size_t>(mi)].emplace(ms);
    }
    w.model_index[static_cast<std::size_t>(i)] = mi;
    const double t = m.epoch - problem.epoch;
    if (w.times.empty() || t != w.times.back()) w.times.push_back(t);
    w.time_index[static_cast<std::size_t>(i)] = static_cast<int>(w.times.size()) - 1;
    w.row0[static_cast<std::size_t>(i)] = row;
    row += m.size();
  }
  w.problem = std::move(problem);
  const std::size_t nt = w.times.size();
  w.states.resize(nt);
  w.stms.resize(nt);
  w.propagator->reserve(static_cast<int>(nt));  // propagate() allocation-free inside solve()
  const Eigen::Index R_ = w.rows, P = np, N = w.n_meas;
  for (Eigen::VectorXd* v : {&w.p, &w.p_best, &w.p_trial, &w.dp, &w.c, &w.colscale}) v->setZero(P);
  w.r.setZero(R_);
  w.r_trial.setZero(R_);
  w.J.setZero(R_, P);
  w.J_trial.setZero(R_, P);
  w.raw.setZero(N, 2);
  w.raw_trial.setZero(N, 2);
  w.ostat.setZero(N);
  w.ostat_trial.setZero(N);
  w.A.setZero(R_, P + 1);
  w.qr.resize(R_, P + 1);
  w.R.setZero(P, P);
  w.Rinv.setZero(P, P);
  w.Rs.setZero(P, P);
  w.svd = Eigen::JacobiSVD<Eigen::MatrixXd>(P, P);
  w.L.setZero(2 * P, P + 1);
  w.qr_lm.resize(2 * P, P + 1);
  w.diag.setZero(P);
  w.Rdp.setZero(P);
  BatchResult& res = w.result;
  res.range_bias.setZero(static_cast<Eigen::Index>(ns));
  res.time_bias.setZero(static_cast<Eigen::Index>(ns));
  res.parameters.setZero(P);
  res.covariance.setZero(P, P);
  res.correlation.setZero(P, P);
  res.sigma.setZero(P);
  res.residuals.setZero(N, 2);
  res.normalized.setZero(N, 2);
  res.measurement_status.setZero(N);
  res.history_cost.setConstant(settings.max_iterations + 1, std::numeric_limits<double>::quiet_NaN());
}

BatchEstimator::~BatchEstimator() = default;
BatchEstimator::BatchEstimator(BatchEstimator&&) noexcept = default;
BatchEstimator& BatchEstimator::operator=(BatchEstimator&&) noexcept = default;

void BatchEstimator::set_initial_guess(const Vec6& x0) noexcept { w_->guess = x0; }
int BatchEstimator::n_parameters() const noexcept { return w_->n_par; }
int BatchEstimator::n_rows() const noexcept { return w_->rows; }
const BatchProblem& BatchEstimator::problem() const noexcept { return w_->problem; }
const BatchSettings& BatchEstimator::settings() const noexcept { return w_->settings; }
const BatchResult& BatchEstimator::result() const noexcept { return w_->result; }

bool BatchEstimator::evaluate(const Eigen::VectorXd& p, Eigen::VectorXd& r, Eigen::MatrixXd& J) {
  detail::BatchWorkspace& w = *w_;
  core::require(p.size() == w.n_par, "p", "must have n_parameters() entries");
  r.setZero(w.rows);
  J.setZero(w.rows, w.n_par);
  Eigen::MatrixXd raw(w.n_meas, 2);
  Eigen::VectorXi os(w.n_meas);
  double cost = 0.0;
  return w.eval(p, r, J, raw, os, cost) == OdStatus::converged;
}

namespace {

// Accept a trial: the trial buffers become the current ones.
void accept_trial(detail::BatchWorkspace& w, double& cost, double ct) {
  w.p.swap(w.p_trial);
  w.r.swap(w.r_trial);
  w.J.swap(w.J_trial);
  w.raw.swap(w.raw_trial);
  w.ostat.swap(w.ostat_trial);
  cost = ct;
}

// Full Gauss-Newton step dp = R^-1 c, then backtracking on the cost. True when a step was taken.
bool gauss_newton_step(detail::BatchWorkspace& w, double& cost) {
  w.dp = w.R.triangularView<Eigen::Upper>().solve(w.c);
  double t = 1.0;
  for (int h = 0; h <= w.settings.max_halvings; ++h, t *= 0.5) {
    w.p_trial = w.p + t * w.dp;
    double ct = 0.0;
    const OdStatus st = w.eval(w.p_trial, w.r_trial, w.J_trial, w.raw_trial, w.ostat_trial, ct);
    if (st == OdStatus::converged && ct < cost) {
      accept_trial(w, cost, ct);
      return true;
    }
  }
  return false;
}

// One Levenberg-Marquardt iteration (file comment of batch.hpp). True when a step was taken.
bool lm_step(detail::BatchWorkspace& w, double& cost, double& lambda, int P) {
  constexpr double kLambdaFloor = 1e-12;  // below: pure Gauss-Newton steps
  for (int j = 0; j < P; ++j) w.diag[j] = std::max(w.diag[j], w.R.col(j).norm());
  for (int rej = 0; rej < w.settings.lm_max_rejections; ++rej) {
    w.damped_step(lambda);
    if (!w.dp.allFinite()) {
      lambda = std::max(lambda * w.settings.lm_increase, kLambdaFloor);
      continue;
    }
    w.Rdp.noalias() = w.R.triangularView<Eigen::Upper>() * w.dp;
    const double pred = 0.5 * (w.c.squaredNorm() - (w.c - w.Rdp).squaredNorm());
    w.p_trial = w.p + w.dp;
    double ct = 0.0;
    const OdStatus st = w.eval(w.p_trial, w.r_trial, w.J_trial, w.raw_trial, w.ostat_trial, ct);
    if (st == OdStatus::converged && ct < cost) {
      const double rho = pred > 0.0 ? (cost - ct) / pred : 0.0;
      if (rho > 0.75 && rej == 0) {
        lambda *= w.settings.lm_decrease;
      } else {
        const double q = 2.0 * rho - 1.0;
        lambda *= std::max(1.0 / 3.0, 1.0 - q * q * q);
      }
      if (lambda < kLambdaFloor) lambda = 0.0;
      accept_trial(w, cost, ct);
      return true;
    }
    lambda = std::max(lambda * w.settings.lm_increase, kLambdaFloor);
  }
  return false;
}

}  // namespace

const BatchResult& BatchEstimator::solve() noexcept {
  SATGNC_NO_MALLOC_SCOPE;  // every buffer was sized at setup (the propagator's by reserve())
  const auto start = std::chrono::steady_clock::now();
  detail::BatchWorkspace& w = *w_;
  BatchResult& res = w.result;
  const int P = w.n_par;
  res.info = BatchInfo{};
  res.history_cost.setConstant(std::numeric_limits<double>::quiet_NaN());
  // Initial parameters: the guess and the bias guesses.
  w.p.head<6>() = w.guess;
  for (std::size_t k = 0; k < w.problem.stations.size(); ++k) {
    if (w.col_range[k] >= 0) w.p[w.col_range[k]] = w.problem.stations[k].range_bias;
    if (w.col_time[k] >= 0) w.p[w.col_time[k]] = w.problem.stations[k].time_bias;
  }
  double cost = std::numeric_limits<double>::infinity();
  OdStatus status = w.eval(w.p, w.r, w.J, w.raw, w.ostat, cost);
  int iterations = 0;
  int rank = 0;
  double cond = std::numeric_limits<double>::infinity();
  double cnorm = std::numeric_limits<double>::infinity();
  bool have_point = status == OdStatus::converged;
  double lambda = w.settings.lm_lambda0;
  w.diag.setZero();
  if (have_point) {
    res.history_cost[0] = cost;
    for (;;) {
      cnorm = w.factor(w.J, w.r, rank, cond);
      if (rank < P) {
        status = OdStatus::singular;
        break;
      }
      if (cnorm <= w.settings.sigma_tol) {
        status = OdStatus::converged;
        break;
      }
      if (iterations >= w.settings.max_iterations) {
        status = OdStatus::max_iterations;
        break;
      }
      const bool accepted = w.settings.method == BatchMethod::levenberg_marquardt
                                ? lm_step(w, cost, lambda, P)
                                : gauss_newton_step(w, cost);
      if (!accepted) {  // no trial point lowered the cost (or none could be evaluated)
        status = OdStatus::stalled;
        break;
      }
      ++iterations;
      res.history_cost[iterations] = cost;
    }
  }
  // Result at the current (best) iterate.
  res.status = status;
  res.iterations = iterations;
  res.parameters = w.p;
  res.x0 = w.p.head<6>();
  for (std::size_t k = 0; k < w.problem.stations.size(); ++k) {
    Biases b;
    w.biases(w.p, static_cast<int>(k), b);
    res.range_bias[static_cast<Eigen::Index>(k)] = b.range;
    res.time_bias[static_cast<Eigen::Index>(k)] = b.time;
  }
  res.rank = rank;
  res.condition_number = cond;
  res.measurement_status = w.ostat;
  if (have_point) {
    res.cost = cost;
    res.rms = std::sqrt(2.0 * cost / w.rows);
    res.residuals = w.raw;
    for (int i = 0; i < w.n_meas; ++i)
      for (int j = 0; j < 2; ++j) res.normalized(i, j) = w.raw(i, j) / w.problem.data[i].sigma[j];
    if (rank == P) {
      w.Rinv.setIdentity();
      w.R.triangularView<Eigen::Upper>().solveInPlace(w.Rinv);
      res.covariance.noalias() = w.Rinv * w.Rinv.transpose();
    } else {
      res.covariance.setZero();
      res.covariance.diagonal().setConstant(std::numeric_limits<double>::infinity());
    }
    for (int a = 0; a < P; ++a) res.sigma[a] = std::sqrt(res.covariance(a, a));
    for (int a = 0; a < P; ++a)
      for (int b = 0; b < P; ++b)
        res.correlation(a, b) = res.covariance(a, b) / (res.sigma[a] * res.sigma[b]);
  } else {
    res.cost = res.rms = std::numeric_limits<double>::infinity();
    res.residuals.setConstant(std::numeric_limits<double>::quiet_NaN());
    res.normalized.setConstant(std::numeric_limits<double>::quiet_NaN());
    res.covariance.setConstant(std::numeric_limits<double>::quiet_NaN());
    res.correlation.setConstant(std::numeric_limits<double>::quiet_NaN());
    res.sigma.setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  res.info.status = status;
  res.info.iterations = iterations;
  res.info.primal_residual = res.rms;
  res.info.dual_residual = cnorm;
  res.info.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return res;
}

}  // namespace satgnc::od
