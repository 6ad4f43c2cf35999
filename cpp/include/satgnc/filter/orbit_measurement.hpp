#pragma once
/// @file orbit_measurement.hpp
/// The orbit filter's measurement function (issue 15 item 1): ground-station observables of
/// observation::MeasurementModel (one- and two-way range and range-rate (Doppler), az/el, RA/Dec, with
/// light time) mapped onto the filter state of filter/orbit_process_model.hpp:
///   [ r, v (GCRF km, km/s) | w (DMC, optional) | parameters ]
/// with each station's range bias (km) and time bias (s) either a parameter state (its column of H is the
/// observation room's Biases partial) or a fixed value. Per-station, per-observable sigma (units of the
/// observable: km, km/s, rad). Angles: the residual of azimuth and right ascension is wrapped to
/// (-pi, pi] (OrbitMeasurementFunction::residual).
///
/// Time axis: measurement tags t (s) are on the stations' time axis, which must be the force model's
/// (s after the same epoch).
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "satgnc/core/types.hpp"
#include "satgnc/filter/measurement_function.hpp"
#include "satgnc/observation/measurement_model.hpp"
#include "satgnc/observation/station_ephemeris.hpp"

namespace satgnc::filter {

/// One measurement record (a TDM line or two for the angle pairs).
struct OrbitMeasurement {
  double t = 0.0;                                   ///< reception tag, s (stations' time axis)
  int station = 0;                                  ///< index into OrbitMeasurementSettings::stations
  int observable = 0;                               ///< index into OrbitMeasurementSettings::observables
  Eigen::Vector2d value = Eigen::Vector2d::Zero();  ///< km, km/s or rad (second component: angle pairs)
};

/// A station of the filter.
struct OrbitStation {
  std::shared_ptr<const observation::StationEphemeris> ephemeris;  ///< GCRF ephemeris (non-null)
  std::vector<double> sigma;  ///< 1-sigma noise per configured observable (its units), > 0
  int range_bias_state = -1;  ///< state index of this station's range bias (km), -1: fixed at range_bias
  int time_bias_state = -1;   ///< state index of this station's time bias (s), -1: fixed at time_bias
  double range_bias = 0.0;    ///< km, used when range_bias_state < 0
  double time_bias = 0.0;     ///< s, used when time_bias_state < 0
};

/// Settings of OrbitMeasurementFunction.
struct OrbitMeasurementSettings {
  std::vector<observation::MeasurementSettings> observables;  ///< the types the filter accepts (>= 1)
  std::vector<OrbitStation> stations;                         ///< >= 1
  /// Throws std::invalid_argument naming the field: no observables or stations, a null ephemeris,
  /// sigma of the wrong length or not > 0, a bias state index outside [6, state_dimension) or shared by
  /// two roles, an observable's own validate().
  void validate(int state_dimension) const;
};

/// Measurement function of the orbit filter: predict(), H and sigma of one record; noexcept and
/// allocation-free. Implements filter::MeasurementFunction (record.type = observable index,
/// record.station = station index; the generic filter takes sigma from the record).
class OrbitMeasurementFunction final : public MeasurementFunction {
 public:
  /// Validates the settings against the state dimension n (throws std::invalid_argument).
  OrbitMeasurementFunction(const OrbitMeasurementSettings& settings, int state_dimension);
  /// State dimension n.
  int dimension() const noexcept { return n_; }
  /// Number of components of a record's observable (1 or 2); 0 for an unknown observable index.
  int size(const OrbitMeasurement& m) const noexcept;
  /// The validated settings.
  const OrbitMeasurementSettings& settings() const noexcept { return settings_; }
  /// Predicted value (first size(m) entries), H (size(m) x n rows of h, the rest untouched) and the
  /// 1-sigma noise per component, for the state x (size n) at the tag m.t. Status: success, or the
  /// observation room's reason (no_convergence, degenerate_geometry), or invalid_input (unknown
  /// station / observable index, wrong sizes, non-finite state).
  core::ObservationStatus evaluate(const OrbitMeasurement& m, const Eigen::Ref<const Eigen::VectorXd>& x,
                                   Eigen::Vector2d& predicted, Eigen::Ref<Eigen::MatrixXd> h,
                                   Eigen::Vector2d& sigma) const noexcept;
  /// measured - predicted, the first component of azimuth / right ascension wrapped to (-pi, pi].
  Eigen::Vector2d residual(const OrbitMeasurement& m, const Eigen::Vector2d& predicted) const noexcept;
  /// MeasurementFunction: 1 or 2 for a configured observable index, else 0.
  int dimension(int type) const noexcept override;
  /// MeasurementFunction: z_pred (the angle of an az/el or RA/Dec pair shifted by a multiple of 2 pi
  /// so that value - z_pred is the wrapped residual) and H (m x n).
  ModelStatus measure(const Eigen::Ref<const Eigen::VectorXd>& x, const MeasurementRecord& record,
                      Eigen::Ref<Eigen::VectorXd> z_pred, Eigen::Ref<Eigen::MatrixXd> h,
                      bool with_jacobian) noexcept override;
  /// A generic record (value and the station's sigma of its observable) from an orbit measurement.
  MeasurementRecord record(const OrbitMeasurement& m) const noexcept;

 private:
  OrbitMeasurementSettings settings_;
  std::vector<observation::MeasurementModel> models_;
  int n_ = 6;
};

}  // namespace satgnc::filter
