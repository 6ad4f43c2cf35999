#pragma once
// Scenario of the orbit-filter tests: a 500 km, 51.6 deg LEO (J2 truth) tracked by two stations (the
// paper's rotating-Earth model: 40 N 105 W 1.6 km, and 35 S 149 E 0.7 km) with two-way range (5 m) and
// two-way range-rate (1 mm/s) every 20 s above 10 deg elevation. Measurements are simulated with the
// observation room's model on the true state plus seeded Gaussian noise.
#include <memory>
#include <random>
#include <vector>

#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/filter/orbit_filter.hpp"
#include "satgnc/propagation/dop853.hpp"

namespace orbit_filter_fixture {

using satgnc::Vec6;
using satgnc::filter::OrbitMeasurement;
using satgnc::filter::OrbitMeasurementSettings;
using satgnc::filter::OrbitStation;
using satgnc::observation::ObservableType;

inline constexpr double kJdEpoch = 2460000.5;
inline constexpr double kSigmaRange = 0.005;     // km
inline constexpr double kSigmaRate = 1e-6;       // km/s
inline constexpr double kMinElevation = 0.1745;  // rad (10 deg)

inline satgnc::dynamics::ForceModel truth_model() {
  satgnc::dynamics::ForceModel fm;
  fm.j2 = satgnc::dynamics::J2Gravity{};
  return fm;
}

inline Vec6 truth_state() {
  Vec6 x;
  x << 6878.0, 0.0, 0.0, 0.0, 4.737, 5.987;  // km, km/s (GCRF)
  return x;
}

inline OrbitMeasurementSettings measurement_settings(int state_dimension_bias_offset = -1) {
  OrbitMeasurementSettings ms;
  satgnc::observation::MeasurementSettings range, rate, azel;
  range.type = ObservableType::two_way_range;
  rate.type = ObservableType::two_way_range_rate;
  azel.type = ObservableType::azimuth_elevation;
  ms.observables = {range, rate, azel};
  const satgnc::dynamics::Station s1 = satgnc::dynamics::Station::from_geodetic(40.0, -105.0, 1.6, kJdEpoch);
  const satgnc::dynamics::Station s2 = satgnc::dynamics::Station::from_geodetic(-35.0, 149.0, 0.7, kJdEpoch);
  for (const auto& s : {s1, s2}) {
    OrbitStation st;
    st.ephemeris = std::make_shared<satgnc::observation::RotatingStationEphemeris>(s);
    st.sigma = {kSigmaRange, kSigmaRate, 1e-4};
    ms.stations.push_back(st);
  }
  if (state_dimension_bias_offset >= 0) {
    ms.stations[0].range_bias_state = state_dimension_bias_offset;
    ms.stations[1].range_bias_state = state_dimension_bias_offset + 1;
  }
  return ms;
}

/// Simulated tracking over [0, span] s: every `step` s each station above 10 deg gives a range and a
/// range-rate (observables 0, 1). range_bias (km) per station added to the range. Seeded noise.
inline std::vector<OrbitMeasurement> simulate(double span, double step, unsigned seed, double bias0 = 0.0,
                                              double bias1 = 0.0, std::vector<Vec6>* truth_at = nullptr) {
  const auto fm = truth_model();
  std::vector<double> times;
  for (double t = step; t <= span; t += step) times.push_back(t);
  satgnc::propagation::Dop853Settings ds;
  ds.rtol = 1e-12;
  ds.atol = 1e-14;
  const auto tr = satgnc::propagation::propagate_dop853(fm, truth_state(), 0.0, times, ds, false);
  const auto ms = measurement_settings();
  satgnc::observation::MeasurementModel range(ms.observables[0]), rate(ms.observables[1]),
      azel(ms.observables[2]);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<OrbitMeasurement> out;
  for (std::size_t i = 0; i < tr.times.size(); ++i) {
    for (int s = 0; s < 2; ++s) {
      const auto& eph = *ms.stations[static_cast<std::size_t>(s)].ephemeris;
      satgnc::observation::Prediction p;
      azel.predict(eph, tr.times[i], tr.states[i], {}, p);
      if (p.status != satgnc::core::ObservationStatus::success || p.value[1] < kMinElevation) continue;
      satgnc::observation::Biases b;
      b.range = s == 0 ? bias0 : bias1;
      range.predict(eph, tr.times[i], tr.states[i], b, p);
      out.push_back({tr.times[i], s, 0, Eigen::Vector2d(p.value[0] + kSigmaRange * g(rng), 0.0)});
      if (truth_at) truth_at->push_back(tr.states[i]);
      rate.predict(eph, tr.times[i], tr.states[i], {}, p);
      out.push_back({tr.times[i], s, 1, Eigen::Vector2d(p.value[0] + kSigmaRate * g(rng), 0.0)});
      if (truth_at) truth_at->push_back(tr.states[i]);
    }
  }
  return out;
}

}  // namespace orbit_filter_fixture
