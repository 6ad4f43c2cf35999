#pragma once
/// @file measurement.hpp
/// Range and range-rate from a ground station and their analytic partials.
/// Model: instantaneous geometry, no light-time, no aberration, no refraction, no relativistic terms:
/// rho = |r - R|, rhodot = (r - R).(v - V) / rho, both at the same epoch t. At LEO ranges (< 3000 km)
/// the neglected light time (< 10 ms) shifts the range by up to ~70 m; simulate and fit with the same
/// model, or correct the data before fitting.
#include <string>
#include <vector>

#include "satgnc/core/types.hpp"

namespace satgnc::dynamics {

/// Observable kind.
enum class MeasurementType {
  range = 0,       ///< km
  range_rate = 1,  ///< km/s (instantaneous Doppler)
};

/// "range" or "range_rate".
const char* measurement_type_name(MeasurementType t);
/// Parse "range"/"rho" or "range_rate"/"rangerate"/"doppler"/"rhodot" (case-insensitive); throws
/// std::invalid_argument naming the text and the choices.
MeasurementType parse_measurement_type(const std::string& text);

/// One observation: time t (s from the epoch t0 = 0), kind, value (km or km/s), standard deviation
/// sigma (same unit, > 0) and the index of the station in the station list.
struct Measurement {
  double t = 0.0;
  MeasurementType type = MeasurementType::range;
  double value = 0.0;
  double sigma = 1.0;
  int station = 0;
};

/// Row vector d h / d x (1 x 6).
using Row6 = Eigen::Matrix<double, 1, 6>;

/// Predicted observable of satellite state x = [r km, v km/s] seen from station state R = [R, V].
/// If dh_dx is non-null it receives the partials with respect to x (range: [u^T, 0]; range-rate:
/// [(dv - rhodot u)^T / rho, u^T], u = (r - R) / rho). Returns false (and leaves the outputs unchanged)
/// when rho is below min_range (km): the geometry is degenerate. No allocation.
bool predict_measurement(MeasurementType type, const Vec6& x, const Vec6& station_state, double& value,
                         Row6* dh_dx = nullptr, double min_range = 1e-6);

/// Validate a measurement list for n_stations stations: finite times and values, finite sigma > 0,
/// station indices in range, range values > 0, no two measurements of the same type and station at
/// the same time. Throws std::invalid_argument naming "measurements[i].<field>".
void validate_measurements(const std::vector<Measurement>& meas, int n_stations);

}  // namespace satgnc::dynamics
