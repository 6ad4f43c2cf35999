// od/tracking_data.hpp: the tracking-data record shared by the batch estimator and the orbit filter.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "error_checks.hpp"
#include "satgnc/io/tdm.hpp"
#include "satgnc/od/tracking_data.hpp"

namespace {

using satgnc::core::Epoch;
using satgnc::core::TimeScale;
using satgnc::observation::ObservableType;
using satgnc::od::TrackingData;
using satgnc::od::TrackingMeasurement;
using satgnc::od::TrackingOrder;
using satgnc::testing::expect_error;

const Epoch kT0 = Epoch::from_calendar(2016, 12, 10, 0, 0, 0.0, TimeScale::utc);

TrackingMeasurement meas(double dt, ObservableType type, int station, double v0, double v1 = 0.0) {
  TrackingMeasurement m;
  m.epoch = kT0 + dt;
  m.type = type;
  m.station = station;
  m.value = Eigen::Vector2d(v0, v1);
  m.sigma = Eigen::Vector2d(1e-3, 1e-3);
  return m;
}

TEST(TrackingData, StableSortKeepsInputOrderOfEqualEpochs) {
  std::vector<TrackingMeasurement> in = {
      meas(20.0, ObservableType::two_way_range, 0, 1000.0),
      meas(10.0, ObservableType::two_way_range, 1, 1001.0),
      meas(10.0, ObservableType::two_way_range_rate, 0, 0.5),  // equal epoch: stays after input 1
      meas(0.0, ObservableType::azimuth_elevation, 1, 1.0, 0.3),
  };
  const TrackingData d(in, 2);
  ASSERT_EQ(d.size(), 4);
  EXPECT_EQ(d.rows(), 5);  // three scalars + one pair
  const std::vector<int> expected_order = {3, 1, 2, 0};
  EXPECT_EQ(d.input_index(), expected_order);
  EXPECT_EQ(d[1].value[0], 1001.0);
  EXPECT_EQ(d[2].type, ObservableType::two_way_range_rate);
  for (int i = 1; i < d.size(); ++i) EXPECT_LE(d[i - 1].epoch, d[i].epoch);
  EXPECT_EQ(d.range_count(0), 1);
  EXPECT_EQ(d.range_count(1), 1);
  EXPECT_EQ(d.count(1), 2);
  // The unused second component of a scalar is normalised to value 0, sigma 1.
  EXPECT_EQ(d[1].sigma[1], 1.0);
  EXPECT_EQ(d[3].value[1], 0.0);
}

TEST(TrackingData, BadInputNamesFieldAndIndex) {
  auto one = [](TrackingMeasurement m) {
    return std::vector<TrackingMeasurement>{meas(0.0, ObservableType::two_way_range, 0, 1.0), m};
  };
  TrackingMeasurement m = meas(1.0, ObservableType::two_way_range, 0, std::nan(""));
  expect_error([&] { TrackingData(one(m), 1); }, "measurements[1].value: must be finite");
  m = meas(1.0, ObservableType::azimuth_elevation, 0, 1.0, 0.2);
  m.sigma[1] = 0.0;
  expect_error([&] { TrackingData(one(m), 1); }, "measurements[1].sigma: must be finite and > 0");
  m = meas(1.0, ObservableType::two_way_range, 3, 1.0);
  expect_error([&] { TrackingData(one(m), 2); },
               "measurements[1].station: unknown station 3 (n_stations = 2)");
  m = meas(1.0, ObservableType::two_way_range, -1, 1.0);
  expect_error([&] { TrackingData(one(m), 2); }, "measurements[1].station: unknown station -1");
  m = meas(1.0, ObservableType::azimuth_elevation, 0, 1.0, 0.5);
  m.corrections = satgnc::od::kTroposphereApplied;
  expect_error([&] { TrackingData(one(m), 1); }, "measurements[1].corrections");
  m = meas(-5.0, ObservableType::two_way_range, 0, 1.0);
  expect_error([&] { TrackingData(one(m), 1, TrackingOrder::require_sorted); },
               "measurements[1].epoch: not in time order (-5.000000 s before measurements[0])");
  EXPECT_NO_THROW(TrackingData(one(m), 1, TrackingOrder::sort));
  expect_error([&] { TrackingData({}, 0); }, "n_stations: must be >= 1");
}

// The JAXA example of CCSDS 503.0 (PATH 1,2,3,2,1: a round trip received by NORTH): two-way range,
// azimuth/elevation pairs merged from ANGLE_1 / ANGLE_2, frequencies skipped.
TEST(TrackingData, FromTdmJaxaExample) {
  const satgnc::io::Tdm tdm = satgnc::io::read_tdm(std::string(SATGNC_CCSDS_DATA_DIR) + "/tdm_jaxa.kvn");
  const TrackingData d = satgnc::od::tracking_data_from_tdm(tdm, {{"NORTH", 1}}, 2);
  ASSERT_EQ(d.size(), 8);  // 4 epochs x (RANGE + AZEL pair)
  EXPECT_EQ(d.rows(), 12);
  EXPECT_EQ(d[0].type, ObservableType::two_way_range);
  EXPECT_EQ(d[0].station, 1);
  EXPECT_EQ(d[0].value[0], 80452.7542);  // km, copied exactly
  EXPECT_EQ(d[0].sigma[0], 1e-3);        // default TdmSigmas::range
  EXPECT_EQ(d[1].type, ObservableType::azimuth_elevation);
  EXPECT_NEAR(d[1].value[0], 256.64002393 * M_PI / 180.0, 1e-15);  // deg -> rad, 1 ulp
  EXPECT_NEAR(d[1].value[1], 13.38100016 * M_PI / 180.0, 1e-15);
  EXPECT_EQ(d[7].epoch, Epoch::parse("1998-06-10T00:57:44", TimeScale::utc));
  expect_error([&] { satgnc::od::tracking_data_from_tdm(tdm, {{"SOUTH", 0}}, 2); },
               "stations: participant 'NORTH' of segment 0 is not in the station map");
  expect_error([&] { satgnc::od::tracking_data_from_tdm(tdm, {{"NORTH", 2}}, 2); },
               "stations: participant 'NORTH' maps to index 2, outside [0, 2)");
  satgnc::od::TdmSigmas bad;
  bad.angle = -1.0;
  expect_error([&] { satgnc::od::tracking_data_from_tdm(tdm, {{"NORTH", 0}}, 1, bad); }, "sigmas.angle");
}

TEST(TrackingData, FromTdmOneWayAndUnpairedAngle) {
  const std::string text =
      "CCSDS_TDM_VERS = 2.0\nCREATION_DATE = 2016-12-10T00:00:00\nORIGINATOR = SATGNC\n"
      "META_START\nTIME_SYSTEM = UTC\nPARTICIPANT_1 = DSS-25\nPARTICIPANT_2 = SC\nMODE = SEQUENTIAL\n"
      "PATH = 2,1\nANGLE_TYPE = RADEC\nMETA_STOP\nDATA_START\n"
      "DOPPLER_INSTANTANEOUS = 2016-12-10T00:00:10 -1.5\nRANGE = 2016-12-10T00:00:00 2000.0\n"
      "ANGLE_1 = 2016-12-10T00:00:20 10.0\nDATA_STOP\n";
  const satgnc::io::Tdm tdm = satgnc::io::parse_tdm(text, "oneway.tdm");
  expect_error([&] { satgnc::od::tracking_data_from_tdm(tdm, {{"DSS-25", 0}}, 1); },
               "ANGLE_1 at 2016-12-10T00:00:20.000 UTC has no matching ANGLE_2");
  const std::string ok = text.substr(0, text.find("ANGLE_1")) + "DATA_STOP\n";
  const TrackingData d =
      satgnc::od::tracking_data_from_tdm(satgnc::io::parse_tdm(ok, "oneway.tdm"), {{"DSS-25", 0}}, 1);
  ASSERT_EQ(d.size(), 2);
  EXPECT_EQ(d[0].type, ObservableType::one_way_range);  // sorted: the range (t = 0) first
  EXPECT_EQ(d[1].type, ObservableType::one_way_range_rate);
  EXPECT_EQ(d[1].value[0], -1.5);
  EXPECT_EQ(d.input_index()[0], 1);
}

}  // namespace
