#include "satgnc/od/tracking_data.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "satgnc/core/validate.hpp"

namespace satgnc::od {

namespace {

using observation::ObservableType;

bool is_range(ObservableType t) {
  return t == ObservableType::one_way_range || t == ObservableType::two_way_range;
}

std::string at(std::size_t i) { return "measurements[" + std::to_string(i) + "]"; }

}  // namespace

TrackingData::TrackingData(std::vector<TrackingMeasurement> measurements, int n_stations, TrackingOrder order)
    : n_stations_(n_stations) {
  core::require(n_stations >= 1, "n_stations", "must be >= 1, got " + std::to_string(n_stations));
  const std::size_t n = measurements.size();
  for (std::size_t i = 0; i < n; ++i) {
    const TrackingMeasurement& m = measurements[i];
    const int type = static_cast<int>(m.type);
    core::require(type >= 0 && type <= 5, at(i) + ".type", "unknown observable " + std::to_string(type));
    const int size = m.size();
    for (int k = 0; k < size; ++k) {
      core::require(std::isfinite(m.value[k]), at(i) + ".value", "must be finite");
      core::require(std::isfinite(m.sigma[k]) && m.sigma[k] > 0.0, at(i) + ".sigma",
                    "must be finite and > 0");
    }
    core::require(m.station >= 0 && m.station < n_stations, at(i) + ".station",
                  "unknown station " + std::to_string(m.station) +
                      " (n_stations = " + std::to_string(n_stations) + ")");
    core::require(m.corrections == 0 || is_range(m.type), at(i) + ".corrections",
                  "troposphere / Shapiro flags apply only to range observables");
    core::require((m.corrections & ~(kTroposphereApplied | kShapiroApplied)) == 0, at(i) + ".corrections",
                  "unknown flag bits");
    if (order == TrackingOrder::require_sorted && i > 0 && m.epoch < measurements[i - 1].epoch)
      throw std::invalid_argument(
          at(i) + ".epoch: not in time order (" + std::to_string(m.epoch - measurements[i - 1].epoch) +
          " s before measurements[" + std::to_string(i - 1) + "]) (hint: TrackingOrder::sort sorts them)");
  }
  input_index_.resize(n);
  std::iota(input_index_.begin(), input_index_.end(), 0);
  std::stable_sort(input_index_.begin(), input_index_.end(), [&](int a, int b) {
    return measurements[static_cast<std::size_t>(a)].epoch < measurements[static_cast<std::size_t>(b)].epoch;
  });
  m_.reserve(n);
  for (int i : input_index_) {
    m_.push_back(measurements[static_cast<std::size_t>(i)]);
    TrackingMeasurement& m = m_.back();
    if (m.size() == 1) {  // the unused component is defined: value 0, sigma 1
      m.value[1] = 0.0;
      m.sigma[1] = 1.0;
    }
    rows_ += m.size();
  }
}

int TrackingData::range_count(int station) const {
  return static_cast<int>(std::count_if(m_.begin(), m_.end(), [station](const TrackingMeasurement& m) {
    return m.station == station && is_range(m.type);
  }));
}

int TrackingData::count(int station) const {
  return static_cast<int>(std::count_if(
      m_.begin(), m_.end(), [station](const TrackingMeasurement& m) { return m.station == station; }));
}

void TdmSigmas::validate() const {
  core::require_positive(range, "sigmas.range");
  core::require_positive(range_rate, "sigmas.range_rate");
  core::require_positive(angle, "sigmas.angle");
}

TrackingData tracking_data_from_tdm(const io::Tdm& tdm, const std::map<std::string, int>& stations,
                                    int n_stations, const TdmSigmas& sigmas) {
  sigmas.validate();
  core::require(n_stations >= 1, "n_stations", "must be >= 1, got " + std::to_string(n_stations));
  for (const auto& [name, index] : stations)
    core::require(index >= 0 && index < n_stations, "stations",
                  "participant '" + name + "' maps to index " + std::to_string(index) + ", outside [0, " +
                      std::to_string(n_stations) + ")");
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  std::vector<TrackingMeasurement> out;
  for (std::size_t s = 0; s < tdm.segments.size(); ++s) {
    const io::TdmSegment& seg = tdm.segments[s];
    const io::TdmMetadata& md = seg.metadata;
    const std::string where = "segment " + std::to_string(s);
    core::require(!md.participants.empty(), "tdm", where + " has no PARTICIPANT_1");
    // The receiving participant: where PATH ends (PATH 1,2,1: two-way; 2,1: one-way down-leg).
    int receiver = 1;
    bool two_way = false;
    if (!md.path.empty()) {
      receiver = md.path.back();
      two_way = md.path.size() >= 3 && md.path.front() == md.path.back();
      core::require(md.path.size() == 2 || two_way, "tdm",
                    where + ": PATH of " + std::to_string(md.path.size()) +
                        " participants is neither one-way (2) nor a round trip (ending where it starts)");
    }
    core::require(receiver >= 1 && receiver <= static_cast<int>(md.participants.size()), "tdm",
                  where + ": PATH names participant " + std::to_string(receiver) + " that is not listed");
    const std::string& name = md.participants[static_cast<std::size_t>(receiver - 1)];
    const auto it = stations.find(name);
    if (it == stations.end())
      throw std::invalid_argument("stations: participant '" + name + "' of " + where +
                                  " is not in the station map (hint: map every receiving participant to a "
                                  "station index)");
    const int station = it->second;
    const std::size_t first = out.size();
    for (std::size_t k = 0; k < seg.observations.size(); ++k) {
      const io::TdmObservation& o = seg.observations[k];
      TrackingMeasurement m;
      m.epoch = o.time;
      m.station = station;
      if (o.keyword == "RANGE") {
        m.type = two_way ? ObservableType::two_way_range : ObservableType::one_way_range;
        m.value[0] = o.value;
        m.sigma[0] = sigmas.range;
      } else if (o.keyword == "DOPPLER_INSTANTANEOUS" || o.keyword == "DOPPLER_INTEGRATED") {
        m.type = two_way ? ObservableType::two_way_range_rate : ObservableType::one_way_range_rate;
        m.value[0] = o.value;
        m.sigma[0] = sigmas.range_rate;
      } else if (o.keyword == "ANGLE_1" || o.keyword == "ANGLE_2") {
        core::require(md.angle_type == "AZEL" || md.angle_type == "RADEC", "tdm",
                      where + ": ANGLE data without ANGLE_TYPE AZEL or RADEC");
        m.type = md.angle_type == "AZEL" ? ObservableType::azimuth_elevation
                                         : ObservableType::right_ascension_declination;
        const int comp = o.keyword == "ANGLE_1" ? 0 : 1;
        // Pair with an angle of the other component at the same epoch in this segment.
        bool merged = false;
        for (std::size_t j = first; j < out.size(); ++j) {
          TrackingMeasurement& p = out[j];
          if (p.type == m.type && p.epoch == m.epoch && std::isnan(p.value[comp])) {
            p.value[comp] = o.value * kDeg;
            merged = true;
            break;
          }
        }
        if (merged) continue;
        m.value = Eigen::Vector2d::Constant(std::nan(""));
        m.value[comp] = o.value * kDeg;
        m.sigma = Eigen::Vector2d::Constant(sigmas.angle);
      } else {
        continue;  // frequencies, weather, clock, ...: not measurements here
      }
      out.push_back(m);
    }
    for (std::size_t j = first; j < out.size(); ++j)
      if (out[j].size() == 2 && (std::isnan(out[j].value[0]) || std::isnan(out[j].value[1])))
        throw std::invalid_argument(
            "tdm: " + where + ": " +
            (std::isnan(out[j].value[1]) ? std::string("ANGLE_1") : std::string("ANGLE_2")) + " at " +
            out[j].epoch.to_iso(core::TimeScale::utc) + " UTC has no matching " +
            (std::isnan(out[j].value[1]) ? std::string("ANGLE_2") : std::string("ANGLE_1")));
  }
  return TrackingData(std::move(out), n_stations, TrackingOrder::sort);
}

}  // namespace satgnc::od
