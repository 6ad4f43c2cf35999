#pragma once
/// @file tracking_data.hpp
/// The tracking-data record that the batch estimator (od/batch.hpp) and the orbit filter consume:
/// one measurement = its reception epoch, its observable (observation::ObservableType), the index of
/// the station that received it, its value(s) and standard deviation(s), and flags of the
/// corrections already applied to the value. TrackingData holds them sorted by time, validated once.
///
/// Units: range km, range-rate km/s, angles rad (azimuth from north through east, elevation;
/// right ascension, declination in GCRF). Epochs are instants (core::Epoch, stored in TAI).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "satgnc/core/epoch.hpp"
#include "satgnc/io/tdm.hpp"
#include "satgnc/observation/measurement_model.hpp"

namespace satgnc::od {

/// Corrections already applied to a measured value (bit flags of TrackingMeasurement::corrections):
/// a model must not add them again (CCSDS TDM CORRECTION_* with CORRECTIONS_APPLIED = YES).
enum TrackingCorrection : std::uint8_t {
  kTroposphereApplied = 1,  ///< the tropospheric delay was removed from the value
  kShapiroApplied = 2,      ///< the Shapiro delay was removed from the value
};

/// One measurement.
struct TrackingMeasurement {
  core::Epoch epoch;                                                              ///< reception time tag
  observation::ObservableType type = observation::ObservableType::two_way_range;  ///< the observable
  int station = 0;                                  ///< index into the estimator's station list
  Eigen::Vector2d value = Eigen::Vector2d::Zero();  ///< km, km/s or rad; component 1 used by angle pairs only
  Eigen::Vector2d sigma = Eigen::Vector2d::Ones();  ///< standard deviation(s), same units, > 0 where used
  std::uint8_t corrections = 0;                     ///< TrackingCorrection flags
  /// Number of components: 2 for azimuth/elevation and RA/Dec, 1 otherwise.
  int size() const noexcept { return observation::observable_size(type); }
};

/// What TrackingData does with measurements that are not in time order.
enum class TrackingOrder {
  sort = 0,            ///< stable sort by epoch (measurements with equal epochs keep their input order)
  require_sorted = 1,  ///< throw std::invalid_argument naming the first out-of-order index
};

/// Measurements sorted by epoch (non-decreasing), validated at construction. Immutable.
class TrackingData {
 public:
  /// An empty set (no stations).
  TrackingData() = default;
  /// Validate and (order = sort) stable-sort the measurements. Throws std::invalid_argument naming
  /// the field and the input index: "measurements[i].value: must be finite", "measurements[i].sigma:
  /// must be finite and > 0", "measurements[i].station: unknown station k (n_stations = n)",
  /// "measurements[i].corrections: ... only for range observables", "measurements[i].epoch: not in
  /// time order (...)" (require_sorted), "n_stations: must be >= 1".
  TrackingData(std::vector<TrackingMeasurement> measurements, int n_stations,
               TrackingOrder order = TrackingOrder::sort);

  /// The measurements in time order.
  const std::vector<TrackingMeasurement>& measurements() const noexcept { return m_; }
  /// Number of measurements.
  int size() const noexcept { return static_cast<int>(m_.size()); }
  /// True when there is no measurement.
  bool empty() const noexcept { return m_.empty(); }
  /// Measurement i (time order), unchecked.
  const TrackingMeasurement& operator[](int i) const noexcept { return m_[static_cast<std::size_t>(i)]; }
  /// Number of stations the indices refer to.
  int n_stations() const noexcept { return n_stations_; }
  /// Scalar rows: the sum of the measurements' sizes.
  int rows() const noexcept { return rows_; }
  /// For measurement i (time order), its index in the input (the permutation of the stable sort).
  const std::vector<int>& input_index() const noexcept { return input_index_; }
  /// Number of measurements of station k whose observable is a range (one- or two-way).
  int range_count(int station) const;
  /// Number of measurements of station k (any observable).
  int count(int station) const;

 private:
  std::vector<TrackingMeasurement> m_;
  std::vector<int> input_index_;
  int n_stations_ = 0;
  int rows_ = 0;
};

/// Standard deviations given to TDM measurements (a TDM carries none).
struct TdmSigmas {
  double range = 1e-3;       ///< km (1 m)
  double range_rate = 1e-6;  ///< km/s (1 mm/s)
  double angle = 1e-4;       ///< rad (about 20 arcsec)
  /// Throws std::invalid_argument naming the field unless each is finite and > 0.
  void validate() const;
};

/// Measurements of a CCSDS TDM (io/tdm.hpp) as TrackingData. Per segment: the receiving station is
/// the participant PATH ends on (PATH `1,2,1` or any round trip `1,...,1`: two-way, PATH `2,1`: one-way
/// down-leg; without PATH,
/// PARTICIPANT_1), looked up in `stations` (participant name -> station index; a name not in it
/// throws std::invalid_argument("stations: participant 'NAME' of segment s is not in the station
/// map")). RANGE -> one/two-way range (km), DOPPLER_INSTANTANEOUS and DOPPLER_INTEGRATED -> one/two-way
/// range-rate (km/s), ANGLE_1 + ANGLE_2 at the same epoch -> azimuth/elevation (ANGLE_TYPE AZEL) or
/// RA/Dec (RADEC), converted from deg to rad (an ANGLE_1 without its ANGLE_2, or angles without
/// ANGLE_TYPE, throw naming the segment and the epoch). Other data keywords (frequencies, weather,
/// clock, ...) are not measurements here and are skipped; the metadata's CORRECTION_* values are not
/// applied (corrections = 0: the values are taken as measured). Sorted with TrackingOrder::sort.
TrackingData tracking_data_from_tdm(const io::Tdm& tdm, const std::map<std::string, int>& stations,
                                    int n_stations, const TdmSigmas& sigmas = {});

}  // namespace satgnc::od
