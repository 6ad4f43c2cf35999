// Orbit measurement function of the filter room (see satgnc/filter/orbit_measurement.hpp).
#include "satgnc/filter/orbit_measurement.hpp"

#include <cmath>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::filter {

using observation::ObservableType;

void OrbitMeasurementSettings::validate(int n) const {
  core::require(!observables.empty(), "observables", "must hold at least one observable");
  core::require(!stations.empty(), "stations", "must hold at least one station");
  for (std::size_t k = 0; k < observables.size(); ++k) observables[k].validate();
  std::vector<int> used(static_cast<std::size_t>(n > 0 ? n : 0), 0);
  for (std::size_t i = 0; i < stations.size(); ++i) {
    const std::string name = "stations[" + std::to_string(i) + "]";
    const OrbitStation& s = stations[i];
    core::require(s.ephemeris != nullptr, name + ".ephemeris", "must not be null");
    core::require(s.sigma.size() == observables.size(), name + ".sigma",
                  "needs one value per observable (" + std::to_string(observables.size()) + "), got " +
                      std::to_string(s.sigma.size()));
    for (std::size_t k = 0; k < s.sigma.size(); ++k)
      core::require_positive(s.sigma[k], name + ".sigma[" + std::to_string(k) + "]");
    core::require_finite(s.range_bias, name + ".range_bias");
    core::require_finite(s.time_bias, name + ".time_bias");
    for (const auto& [idx, field] : {std::pair<int, const char*>{s.range_bias_state, ".range_bias_state"},
                                     std::pair<int, const char*>{s.time_bias_state, ".time_bias_state"}}) {
      if (idx < 0) continue;
      core::require(
          idx >= 6 && idx < n, name + field,
          "must be -1 or a parameter index in [6, " + std::to_string(n) + "), got " + std::to_string(idx));
      core::require(used[static_cast<std::size_t>(idx)] == 0, name + field,
                    "state " + std::to_string(idx) + " is already a bias of another role or station");
      used[static_cast<std::size_t>(idx)] = 1;
    }
  }
}

OrbitMeasurementFunction::OrbitMeasurementFunction(const OrbitMeasurementSettings& settings, int n)
    : settings_(settings), n_(n) {
  core::require(n >= 6, "state_dimension", "must be >= 6, got " + std::to_string(n));
  settings_.validate(n);
  models_.reserve(settings_.observables.size());
  for (const auto& o : settings_.observables) models_.emplace_back(o);
}

int OrbitMeasurementFunction::size(const OrbitMeasurement& m) const noexcept {
  if (m.observable < 0 || m.observable >= static_cast<int>(models_.size())) return 0;
  return observation::observable_size(settings_.observables[static_cast<std::size_t>(m.observable)].type);
}

core::ObservationStatus OrbitMeasurementFunction::evaluate(const OrbitMeasurement& m,
                                                           const Eigen::Ref<const Eigen::VectorXd>& x,
                                                           Eigen::Vector2d& predicted,
                                                           Eigen::Ref<Eigen::MatrixXd> h,
                                                           Eigen::Vector2d& sigma) const noexcept {
  const int p = size(m);
  if (p == 0 || m.station < 0 || m.station >= static_cast<int>(settings_.stations.size()) || x.size() != n_ ||
      h.cols() != n_ || h.rows() < p || !std::isfinite(m.t))
    return core::ObservationStatus::invalid_input;
  const OrbitStation& st = settings_.stations[static_cast<std::size_t>(m.station)];
  observation::Biases b;
  b.range = st.range_bias_state >= 0 ? x[st.range_bias_state] : st.range_bias;
  b.time = st.time_bias_state >= 0 ? x[st.time_bias_state] : st.time_bias;
  observation::Prediction pr;
  const Vec6 xs = x.head<6>();
  models_[static_cast<std::size_t>(m.observable)].predict(*st.ephemeris, m.t, xs, b, pr);
  if (pr.status != core::ObservationStatus::success) return pr.status;
  h.topRows(p).setZero();
  h.topLeftCorner(p, 6) = pr.dx.topRows(p);
  if (st.range_bias_state >= 0) h.col(st.range_bias_state).head(p) = pr.dbias.col(0).head(p);
  if (st.time_bias_state >= 0) h.col(st.time_bias_state).head(p) = pr.dbias.col(1).head(p);
  predicted = pr.value;
  sigma.setConstant(st.sigma[static_cast<std::size_t>(m.observable)]);
  return pr.status;
}

Eigen::Vector2d OrbitMeasurementFunction::residual(const OrbitMeasurement& m,
                                                   const Eigen::Vector2d& predicted) const noexcept {
  Eigen::Vector2d r = m.value - predicted;
  if (size(m) == 2) {
    constexpr double kTwoPi = 6.283185307179586476925;
    r[0] = std::remainder(r[0], kTwoPi);  // (-pi, pi]
  }
  if (size(m) == 1) r[1] = 0.0;
  return r;
}

int OrbitMeasurementFunction::dimension(int type) const noexcept {
  if (type < 0 || type >= static_cast<int>(models_.size())) return 0;
  return observation::observable_size(settings_.observables[static_cast<std::size_t>(type)].type);
}

ModelStatus OrbitMeasurementFunction::measure(const Eigen::Ref<const Eigen::VectorXd>& x,
                                              const MeasurementRecord& record,
                                              Eigen::Ref<Eigen::VectorXd> z_pred,
                                              Eigen::Ref<Eigen::MatrixXd> h, bool with_jacobian) noexcept {
  OrbitMeasurement m;
  m.t = record.t;
  m.station = record.station;
  m.observable = record.type;
  m.value = Eigen::Vector2d(record.value[0], record.value[1]);
  const int p = size(m);
  if (p == 0 || z_pred.size() < p || (with_jacobian && (h.rows() < p || h.cols() != n_)))
    return ModelStatus::failed;
  // evaluate() writes a 2 x n H: a stack buffer (fixed capacity, no allocation), n <= 64.
  if (n_ > 64) return ModelStatus::failed;
  Eigen::Vector2d pred, sig;
  Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, 64> hb(2, n_);
  if (evaluate(m, x, pred, hb, sig) != core::ObservationStatus::success) return ModelStatus::failed;
  const Eigen::Vector2d y = residual(m, pred);
  for (int i = 0; i < p; ++i) z_pred[i] = m.value[i] - y[i];
  if (with_jacobian) h.topRows(p) = hb.topRows(p);
  return ModelStatus::success;
}

MeasurementRecord OrbitMeasurementFunction::record(const OrbitMeasurement& m) const noexcept {
  MeasurementRecord r;
  r.t = m.t;
  r.type = m.observable;
  r.station = m.station;
  r.value = {m.value[0], m.value[1], 0.0};
  const int p = size(m);
  const bool ok = p > 0 && m.station >= 0 && m.station < static_cast<int>(settings_.stations.size());
  const double s = ok ? settings_.stations[static_cast<std::size_t>(m.station)]
                            .sigma[static_cast<std::size_t>(m.observable)]
                      : 0.0;
  r.sigma = {s, p == 2 ? s : 0.0, 0.0};
  return r;
}

}  // namespace satgnc::filter
