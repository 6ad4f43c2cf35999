// Range-rate modifiers (issue 13 item 6): the rate of the tropospheric and Shapiro delays added to one-
// and two-way range-rate, checked against the time derivative of the range model's own delays and its
// partials against central differences.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "obs_fixture.hpp"
#include "satgnc/observation/light_time.hpp"
#include "satgnc/observation/measurement_model.hpp"

namespace {

namespace obs = satgnc::observation;
using obs::Biases;
using obs::MeasurementModel;
using obs::ObservableType;
using obs::Prediction;
using satgnc::Vec6;
using satgnc::core::ObservationStatus;

using obs_fixture::converged_model;

// The modifier of a range-rate equals d/dt of the one-way range's delay along the motion: a central
// difference over +-0.5 s of predict(one_way_range) with the state two-body-shifted to each tag. The two
// differ by the rate of the light time (|v|/c ~ 2.6e-5 relative) and the difference's truncation, so
// 1e-4 relative (plus 1e-12 km/s for the rounding of the differenced delays) is the stated tolerance.
TEST(RangeRateModifiers, ValueIsTheRateOfTheRangeDelay) {
  const obs::RotatingStationEphemeris st(obs_fixture::station());
  for (double offset : {0.05, 0.15, 0.25}) {
    const Vec6 x = obs_fixture::pass_state(7000.0, offset);
    for (ObservableType type : {ObservableType::one_way_range_rate, ObservableType::two_way_range_rate}) {
      Prediction plain, both;
      converged_model(type).predict(st, 0.0, x, Biases{}, plain);
      converged_model(type, true, true).predict(st, 0.0, x, Biases{}, both);
      ASSERT_EQ(both.status, ObservationStatus::success);
      EXPECT_NEAR(both.value(0) - plain.value(0), both.troposphere + both.shapiro, 1e-15);
      const MeasurementModel range = converged_model(ObservableType::one_way_range, true, true);
      const double d = 0.5;
      Vec6 xp, xm;
      obs::shift_state(x, d, obs_fixture::kMu, xp);
      obs::shift_state(x, -d, obs_fixture::kMu, xm);
      Prediction rp, rm;
      range.predict(st, d, xp, Biases{}, rp);
      range.predict(st, -d, xm, Biases{}, rm);
      const double tropo_rate = (rp.troposphere - rm.troposphere) / (2.0 * d);
      const double shapiro_rate = (rp.shapiro - rm.shapiro) / (2.0 * d);
      EXPECT_NEAR(both.troposphere, tropo_rate, 1e-4 * std::abs(tropo_rate) + 1e-12) << offset;
      EXPECT_NEAR(both.shapiro, shapiro_rate, 1e-4 * std::abs(shapiro_rate) + 1e-12) << offset;
      EXPECT_GT(std::abs(both.troposphere), 1e-7);  // km/s: the troposphere's rate is mm/s to dm/s
    }
  }
}

// Central differences in x (h = 1e-2 km, km/s) and the time bias (1e-3 s), the tolerance of
// test_observation_models (1e-7 relative + 4 eps |value| / h).
TEST(RangeRateModifiers, PartialsMatchCentralDifferences) {
  const obs::RotatingStationEphemeris st(obs_fixture::station());
  const Vec6 x = obs_fixture::pass_state(7000.0, 0.2);
  for (ObservableType type : {ObservableType::one_way_range_rate, ObservableType::two_way_range_rate})
    for (int mods = 1; mods <= 3; ++mods) {
      const MeasurementModel m = converged_model(type, mods & 1, mods & 2);
      const Biases b{0.0, 2e-3};
      obs_fixture::expect_dx_matches_central_difference(
          m, st, 30.0, x, b, std::string(obs::observable_name(type)) + " mods " + std::to_string(mods));
      Prediction p;
      m.predict(st, 30.0, x, b, p);
      const double h = 1e-3;
      Prediction pp, pm;
      m.predict(st, 30.0, x, Biases{0.0, b.time + h}, pp);
      m.predict(st, 30.0, x, Biases{0.0, b.time - h}, pm);
      const double fd = (pp.value(0) - pm.value(0)) / (2.0 * h);
      // the time-bias partial of a rate is itself this central difference: the wiring is checked
      EXPECT_NEAR(p.dbias(0, 1), fd, 1e-12);
    }
}

TEST(RangeRateModifiers, AnglesStillRefuseModifiers) {
  obs::MeasurementSettings s;
  s.type = ObservableType::azimuth_elevation;
  s.troposphere = true;
  try {
    s.validate();
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("troposphere: applies to range observables only", 0), 0u)
        << e.what();
  }
  s.type = ObservableType::two_way_range_rate;
  s.shapiro = true;
  EXPECT_NO_THROW(s.validate());
}

}  // namespace
