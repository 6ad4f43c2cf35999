// Measurement model: analytic partials against central differences, degenerate geometry, validation.
#include <cmath>

#include "satgnc/od/measurement.hpp"
#include "testing.hpp"

using namespace satgnc;
using namespace satgnc::od;

namespace {
Vec6 sat() {
  Vec6 x;
  x << 5836.8907, 1265.616, 3411.496, 0.3146, 6.9401, -3.1125;
  return x;
}
Vec6 sta() {
  Vec6 r;
  r << 5463.14996, 2139.12637, 2493.7785, -0.15551, 0.39717, 0.0;
  return r;
}
}  // namespace

TEST(Measurement, PartialsMatchFiniteDifferences) {
  for (auto type : {MeasurementType::range, MeasurementType::range_rate}) {
    Row6 g;
    double v = 0;
    ASSERT_TRUE(predict_measurement(type, sat(), sta(), v, &g));
    Row6 fd;
    for (int i = 0; i < 6; ++i) {
      const double h = i < 3 ? 1e-3 : 1e-6;
      Vec6 p = sat(), m = sat();
      p(i) += h;
      m(i) -= h;
      double vp = 0, vm = 0;
      predict_measurement(type, p, sta(), vp);
      predict_measurement(type, m, sta(), vm);
      fd(i) = (vp - vm) / (2 * h);
    }
    // Central differences: truncation ~h^2 |h'''| and rounding ~1e-16 |h| / step; 1e-7 relative.
    SATGNC_EXPECT_REL(g, fd, 1e-7);
  }
}

TEST(Measurement, ValuesAndDegenerateGeometry) {
  double rho = 0;
  ASSERT_TRUE(predict_measurement(MeasurementType::range, sat(), sta(), rho));
  EXPECT_NEAR(rho, (sat().head<3>() - sta().head<3>()).norm(), 1e-12);
  double v = 42.0;
  EXPECT_FALSE(
      predict_measurement(MeasurementType::range_rate, sta(), sta(), v));  // station at the satellite
  EXPECT_EQ(v, 42.0);
}

TEST(Measurement, ParseType) {
  EXPECT_EQ(parse_measurement_type("RANGE"), MeasurementType::range);
  EXPECT_EQ(parse_measurement_type("doppler_instantaneous"), MeasurementType::range_rate);
  EXPECT_EQ(parse_measurement_type("range-rate"), MeasurementType::range_rate);
  try {
    parse_measurement_type("azimuth");
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("azimuth"), std::string::npos);
  }
}

TEST(Measurement, Validation) {
  std::vector<Measurement> ok{{0.0, MeasurementType::range, 1000.0, 1e-3, 0},
                              {0.0, MeasurementType::range_rate, 1.0, 1e-6, 0}};
  EXPECT_NO_THROW(validate_measurements(ok, 1));
  auto expect_msg = [](const std::vector<Measurement>& m, int ns, const std::string& piece) {
    try {
      validate_measurements(m, ns);
      FAIL() << "no throw for " << piece;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(piece), std::string::npos) << e.what();
    }
  };
  auto bad = ok;
  bad[1].sigma = -1.0;
  expect_msg(bad, 1, "measurements[1].sigma");
  bad = ok;
  bad[0].sigma = NAN;
  expect_msg(bad, 1, "measurements[0].sigma");
  bad = ok;
  bad[0].value = 0.0;
  expect_msg(bad, 1, "zero range");
  bad = ok;
  bad[1].station = 3;
  expect_msg(bad, 1, "measurements[1].station");
  bad = ok;
  bad.push_back(ok[0]);
  expect_msg(bad, 1, "duplicate time");
  bad = ok;
  bad[0].t = INFINITY;
  expect_msg(bad, 1, "measurements[0].t");
  expect_msg(ok, 0, "stations");
}
