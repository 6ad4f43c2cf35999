#pragma once
// Checks shared by the troposphere-model tests (Mendes-Pavlis, Marini-Murray): the same range and
// range-rate partials and range-rate counterpart, run for one TroposphereModel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "obs_fixture.hpp"
#include "satgnc/observation/light_time.hpp"
#include "satgnc/observation/measurement_model.hpp"
#include "satgnc/observation/modifiers.hpp"

namespace obs_fixture {

// A measurement model of `type` with the troposphere `tm` (on unless `tropo` is false), light time
// converged to rounding (converged_model).
inline satgnc::observation::MeasurementModel troposphere_model(satgnc::observation::ObservableType type,
                                                               satgnc::observation::TroposphereModel tm,
                                                               bool tropo = true) {
  return converged_model(type, tropo, false, tm);
}

// On the shared pass (offset 0.15 rad, t = 0): the one-way range predictions with troposphere models
// `a` and `b`, and the azimuth / elevation without troposphere.
struct PassDelays {
  satgnc::observation::Prediction a, b, look;
};
inline PassDelays pass_delays(const satgnc::observation::StationEphemeris& st,
                              satgnc::observation::TroposphereModel a,
                              satgnc::observation::TroposphereModel b) {
  namespace obs = satgnc::observation;
  const satgnc::Vec6 x = pass_state(7000.0, 0.15);
  PassDelays p;
  troposphere_model(obs::ObservableType::one_way_range, a).predict(st, 0.0, x, obs::Biases{}, p.a);
  troposphere_model(obs::ObservableType::one_way_range, b).predict(st, 0.0, x, obs::Biases{}, p.b);
  troposphere_model(obs::ObservableType::azimuth_elevation, obs::TroposphereModel::saastamoinen, false)
      .predict(st, 0.0, x, obs::Biases{}, p.look);
  return p;
}

// Range and range-rate partials with `tm` against central differences (h = 1e-2 km, km/s; the
// tolerance of test_observation_models: 1e-7 relative + 4 eps |value| / h), at two points of the pass;
// and the range-rate's modifier equals d/dt of the one-way range delay along the motion to 1e-4 (the
// light time's own rate left out, as for Saastamoinen: test_range_rate_modifiers).
inline void expect_troposphere_partials_and_rate(satgnc::observation::TroposphereModel tm) {
  namespace obs = satgnc::observation;
  using obs::ObservableType;
  using obs::Prediction;
  using satgnc::Vec6;
  const obs::RotatingStationEphemeris st(station());
  for (double offset : {0.05, 0.2}) {
    const Vec6 x = pass_state(7000.0, offset);
    for (ObservableType type : {ObservableType::one_way_range, ObservableType::two_way_range,
                                ObservableType::one_way_range_rate, ObservableType::two_way_range_rate}) {
      const obs::MeasurementModel m = troposphere_model(type, tm);
      const obs::Biases b{0.0, 2e-3};
      Prediction p;
      m.predict(st, 30.0, x, b, p);
      EXPECT_NE(p.troposphere, 0.0);
      expect_dx_matches_central_difference(
          m, st, 30.0, x, b, std::string(obs::observable_name(type)) + " offset " + std::to_string(offset));
    }
    Prediction rr;
    troposphere_model(ObservableType::two_way_range_rate, tm).predict(st, 0.0, x, obs::Biases{}, rr);
    const obs::MeasurementModel range = troposphere_model(ObservableType::one_way_range, tm);
    const double d = 0.5;
    Vec6 xp, xm;
    obs::shift_state(x, d, kMu, xp);
    obs::shift_state(x, -d, kMu, xm);
    Prediction rp, rm;
    range.predict(st, d, xp, obs::Biases{}, rp);
    range.predict(st, -d, xm, obs::Biases{}, rm);
    const double rate = (rp.troposphere - rm.troposphere) / (2.0 * d);
    EXPECT_NEAR(rr.troposphere, rate, 1e-4 * std::abs(rate) + 1e-12) << offset;
    EXPECT_GT(std::abs(rr.troposphere), 1e-7);  // km/s
  }
}

}  // namespace obs_fixture
