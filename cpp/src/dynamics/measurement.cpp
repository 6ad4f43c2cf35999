#include "satgnc/dynamics/measurement.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numeric>

#include "satgnc/core/validate.hpp"

namespace satgnc::dynamics {

const char* measurement_type_name(MeasurementType t) {
  switch (t) {
    case MeasurementType::range:
      return "range";
    case MeasurementType::range_rate:
      return "range_rate";
  }
  return "unknown";
}

MeasurementType parse_measurement_type(const std::string& text) {
  std::string n;
  for (char c : text)
    if (std::isalnum(static_cast<unsigned char>(c))) n += static_cast<char>(std::tolower(c));
  if (n == "range" || n == "rho") return MeasurementType::range;
  if (n == "rangerate" || n == "doppler" || n == "rhodot" || n == "dopplerinstantaneous")
    return MeasurementType::range_rate;
  throw std::invalid_argument("type: unknown measurement type '" + text + "' (hint: range or range_rate)");
}

bool predict_measurement(MeasurementType type, const Vec6& x, const Vec6& R, double& value, Row6* dh_dx,
                         double min_range) {
  const Vec3 d = x.head<3>() - R.head<3>();
  const double rho = d.norm();
  if (!(rho >= min_range)) return false;
  if (type == MeasurementType::range) {
    value = rho;
    if (dh_dx) {
      dh_dx->head<3>() = d.transpose() / rho;
      dh_dx->tail<3>().setZero();
    }
    return true;
  }
  const Vec3 dv = x.tail<3>() - R.tail<3>();
  const double rhodot = d.dot(dv) / rho;
  value = rhodot;
  if (dh_dx) {
    dh_dx->head<3>() = (dv - rhodot * d / rho).transpose() / rho;
    dh_dx->tail<3>() = d.transpose() / rho;
  }
  return true;
}

void validate_measurements(const std::vector<Measurement>& meas, int n_stations) {
  using core::require;
  require(n_stations >= 1, "stations", "need at least one station");
  for (std::size_t i = 0; i < meas.size(); ++i) {
    const auto& m = meas[i];
    const std::string p = "measurements[" + std::to_string(i) + "]";
    require(std::isfinite(m.t), p + ".t", "must be finite");
    require(std::isfinite(m.value), p + ".value", "must be finite");
    require(std::isfinite(m.sigma) && m.sigma > 0.0, p + ".sigma",
            "must be finite and > 0, got " + std::to_string(m.sigma));
    require(m.station >= 0 && m.station < n_stations, p + ".station",
            "index must be in [0, " + std::to_string(n_stations) + ")");
    require(m.type == MeasurementType::range || m.type == MeasurementType::range_rate, p + ".type",
            "unknown measurement type");
    if (m.type == MeasurementType::range)
      require(m.value > 0.0, p + ".value", "a range must be > 0 km",
              "a zero range puts the station at the satellite");
  }
  std::vector<std::size_t> idx(meas.size());
  std::iota(idx.begin(), idx.end(), 0);
  auto key_less = [&](std::size_t a, std::size_t b) {
    const auto &x = meas[a], &y = meas[b];
    if (x.station != y.station) return x.station < y.station;
    if (x.type != y.type) return x.type < y.type;
    return x.t < y.t;
  };
  std::sort(idx.begin(), idx.end(), key_less);
  for (std::size_t k = 1; k < idx.size(); ++k) {
    const auto &a = meas[idx[k - 1]], &b = meas[idx[k]];
    require(!(a.station == b.station && a.type == b.type && a.t == b.t),
            "measurements[" + std::to_string(idx[k]) + "].t",
            "duplicate time " + std::to_string(b.t) + " s for the same type and station (also measurements[" +
                std::to_string(idx[k - 1]) + "])");
  }
}

}  // namespace satgnc::dynamics
