#pragma once
/// @file measurement_model.hpp
/// Ground-station measurement models with light time and analytic partials (issue 13 item 4),
/// after Orekit's estimation architecture: a model (the observable and its options) is built once,
/// then predict() maps a spacecraft state at reception to the predicted value and its partials.
///
/// Conventions (docs/observation.md has the equations):
/// - measurements are tagged at reception t (s on the station ephemeris' time axis); the state x
///   given to predict() is the spacecraft GCRF state at the tag, km and km/s;
/// - the spacecraft state at the bounce time t - tau_d is the two-body Taylor shift of x
///   (shift_state); the up leg uses the station at its transmit time t - tau_d - tau_u;
/// - two-way range = c (tau_d + tau_u) / 2; one-way range = c tau_d;
/// - leg range-rate = u . (v_sc(bounce) - V_station(leg time)), u the unit line of sight station ->
///   spacecraft of that leg; two-way range-rate = mean of the down and up legs (Orekit RangeRate,
///   two-way: the mean of the uplink and downlink one-way values);
/// - azimuth (from north through east, [0, 2 pi)) / elevation of the down-leg line of sight in the
///   station's topocentric (geodetic east-north-up) frame at reception; right ascension [0, 2 pi) /
///   declination of the down-leg line of sight in GCRF (topocentric). No aberration, no refraction;
/// - biases: a per-station range bias b (km, added to range types) and time bias dt (s): the true
///   reception is t + dt, the state there is shift_state(x, dt);
/// - modifiers (range and range-rate types): troposphere (Saastamoinen zenith delay in the standard
///   atmosphere at the station's height, Black-Eisner mapping at the down-leg elevation; or, for laser
///   ranging, Mendes-Pavlis at the laser wavelength with the FCULa mapping) and the Shapiro
///   delay of the down leg; in a two-way range both legs carry the same delay and the half round trip
///   carries it once. A range-rate carries the delays' rate along the down-leg geometry (central
///   difference over +-0.1 s of the reception time, the bounce state two-body-shifted; analytic partials
///   of that difference), once for two-way (the mean of the legs).
/// The instantaneous model of the Gao-Luo paper stays in dynamics/measurement.hpp (no light time).
#include <string>

#include "satgnc/core/constants.hpp"
#include "satgnc/core/epoch.hpp"
#include "satgnc/core/status.hpp"
#include "satgnc/core/types.hpp"
#include "satgnc/observation/light_time.hpp"
#include "satgnc/observation/modifiers.hpp"
#include "satgnc/observation/station_ephemeris.hpp"

namespace satgnc::observation {

using core::ObservationStatus;

/// Observable of a model.
enum class ObservableType {
  one_way_range = 0,                ///< km, down leg
  two_way_range = 1,                ///< km, half the round trip
  one_way_range_rate = 2,           ///< km/s, down leg
  two_way_range_rate = 3,           ///< km/s, mean of the legs
  azimuth_elevation = 4,            ///< rad, rad (topocentric)
  right_ascension_declination = 5,  ///< rad, rad (topocentric, GCRF)
};

/// "one_way_range", "two_way_range", ... (the enumerator's name).
const char* observable_name(ObservableType type) noexcept;
/// Parse the enumerator's name (case-insensitive, '-' or ' ' for '_', also "azel" and "radec");
/// throws std::invalid_argument("type: unknown observable '...' (hint: one of ...)").
ObservableType parse_observable(const std::string& text);
/// Number of components: 2 for the angle pairs, 1 otherwise.
int observable_size(ObservableType type) noexcept;

/// Settings of a measurement model.
struct MeasurementSettings {
  ObservableType type = ObservableType::two_way_range;  ///< the observable
  LightTimeSettings light_time{};                       ///< iteration tolerance and limit
  bool troposphere = false;  ///< add the tropospheric delay (range types) or its rate (range-rate types)
  /// Which troposphere: Saastamoinen (radio), Mendes-Pavlis or Marini-Murray (optical, at wavelength_um).
  TroposphereModel troposphere_model = TroposphereModel::saastamoinen;
  /// Laser wavelength of Mendes-Pavlis / Marini-Murray, micrometres, [0.3, 1.7].
  double wavelength_um = 0.532;
  double relative_humidity = 0.5;  ///< of the standard atmosphere, [0, 1]
  bool shapiro = false;            ///< add the Shapiro delay (range types) or its rate (range-rate types)
  double mu = core::earth::mu;     ///< km^3/s^2, for the bounce-time shift and the Shapiro delay
  double min_range = 1e-3;         ///< km: below it the geometry is degenerate
  bool time_bias_partials = true;  ///< compute d value / d time bias (range types: analytic; the
                                   ///< others: central difference of predict() over +-1 ms, 3 calls)

  /// Throws std::invalid_argument naming the field: a modifier on an angle observable, humidity
  /// outside [0, 1], an unknown troposphere_model, wavelength_um outside [0.3, 1.7], mu or min_range not
  /// finite and > 0, light_time.validate().
  void validate() const;
};

/// Estimable per-station parameters.
struct Biases {
  double range = 0.0;  ///< km, added to range observables
  double time = 0.0;   ///< s, true reception = tag + time
};

/// Value and partials of one prediction (fixed-size: no allocation).
struct Prediction {
  ObservationStatus status = ObservationStatus::unsolved;  ///< success or why not
  int size = 1;                                            ///< components used (1 or 2)
  Eigen::Vector2d value = Eigen::Vector2d::Zero();         ///< km, km/s or rad; includes biases and modifiers
  Eigen::Matrix<double, 2, 6> dx = Eigen::Matrix<double, 2, 6>::Zero();  ///< d value / d x at the tag
  Eigen::Matrix<double, 2, 2> dbias =
      Eigen::Matrix<double, 2, 2>::Zero();  ///< d value / d [range bias km, time bias s]
  double tau_down = 0.0;                    ///< s
  double tau_up = 0.0;                      ///< s (0 unless a two-way observable)
  int iterations = 0;                       ///< light-time updates, both legs
  double troposphere = 0.0;                 ///< km (range) or km/s (range-rate), included in value
  double shapiro = 0.0;                     ///< km (range) or km/s (range-rate), included in value
};

/// A measurement model: settings validated at construction; predict() is noexcept and allocates
/// nothing (a failure is a status).
class MeasurementModel {
 public:
  /// Validates the settings (throws std::invalid_argument naming the field).
  explicit MeasurementModel(const MeasurementSettings& settings);
  /// The validated settings.
  const MeasurementSettings& settings() const noexcept { return settings_; }
  /// Predict the observable of the spacecraft state x (GCRF km, km/s, at the tag t) seen from
  /// `station` with a measurement tagged at reception t (s, the station's time axis).
  void predict(const StationEphemeris& station, double t, const Vec6& x, const Biases& bias,
               Prediction& out) const noexcept;
  /// The same with the tag as an epoch: t = tag - epoch, where `epoch` is the epoch of t = 0 of the
  /// station ephemeris (e.g. frames::IauEarthRotation::epoch()); the difference is exact.
  void predict(const StationEphemeris& station, const core::Epoch& epoch, const core::Epoch& tag,
               const Vec6& x, const Biases& bias, Prediction& out) const noexcept {
    predict(station, tag - epoch, x, bias, out);
  }

 private:
  void evaluate(const StationEphemeris& station, double t, const Vec6& x, const Biases& bias, Prediction& out,
                bool want_partials) const noexcept;
  MeasurementSettings settings_;
};

}  // namespace satgnc::observation
