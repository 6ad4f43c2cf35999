// Orbit EKF and RTS smoother (issue 15): convergence from a km-level initial error over two passes of
// two stations, an injected outlier rejected and listed, range biases estimated / considered, the
// allocation count of the stepping loop, and bad input.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "malloc_counter.hpp"
#include "orbit_filter_fixture.hpp"
#include "satgnc/filter/kalman_filter.hpp"

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using satgnc::Vec3;
using satgnc::Vec6;
using satgnc::filter::OrbitFilter;
using satgnc::filter::OrbitFilterResult;
using satgnc::filter::OrbitFilterSettings;
using satgnc::filter::OrbitMeasurement;
using satgnc::filter::OrbitMeasurementFunction;
using satgnc::filter::OrbitProcessModel;
using satgnc::filter::OrbitProcessSettings;
using satgnc::filter::OrbitStepStatus;
namespace fx = orbit_filter_fixture;

constexpr double kSpan = 6.0 * 3600.0;  // s: two passes over each station (counted below)

OrbitFilter make_filter(int parameters = 0, OrbitFilterSettings fs = {}) {
  OrbitProcessSettings ps;
  ps.snc_psd_ric = Vec3::Constant(1e-15);  // km^2/s^3: the filter model is the truth model; a trace of SNC
  ps.parameters = parameters;
  OrbitProcessModel pm(fx::truth_model(), ps);
  OrbitMeasurementFunction mf(fx::measurement_settings(parameters > 0 ? 6 : -1), pm.dimension());
  return OrbitFilter(std::move(pm), std::move(mf), fs);
}

// Number of passes (gaps > 10 min between consecutive measurements of a station).
int passes(const std::vector<OrbitMeasurement>& m, int station) {
  int n = 0;
  double last = -1e9;
  for (const auto& x : m) {
    if (x.station != station) continue;
    if (x.t - last > 600.0) ++n;
    last = x.t;
  }
  return n;
}

MatrixXd p0_km() {
  VectorXd d(6);
  d << 1.0, 1.0, 1.0, 1e-3, 1e-3, 1e-3;  // 1 km, 1 m/s (1-sigma)
  return d.cwiseAbs2().asDiagonal();
}

Vec6 initial_error() {
  Vec6 e;
  e << 0.8, -1.2, 0.5, 4e-4, -6e-4, 2e-4;  // km, km/s: ~1.5 km, ~0.75 m/s
  return e;
}

TEST(OrbitFilter, ConvergesFromKmErrorOverTwoPassesOfTwoStations) {
  std::vector<Vec6> truth;
  const auto meas = fx::simulate(kSpan, 20.0, 1234u, 0.0, 0.0, &truth);
  ASSERT_GE(passes(meas, 0), 2);
  ASSERT_GE(passes(meas, 1), 2);
  OrbitFilter f = make_filter();
  const VectorXd x0 = fx::truth_state() + initial_error();
  const OrbitFilterResult r = f.run(0.0, x0, p0_km(), meas);
  const std::size_t K = meas.size();
  ASSERT_EQ(r.steps_run, static_cast<int>(K));
  const VectorXd xf = Eigen::Map<const VectorXd>(r.state.data() + (K - 1) * 6, 6);
  const MatrixXd pf = Eigen::Map<const MatrixXd>(r.covariance.data() + (K - 1) * 36, 6, 6);
  const Vec6 err = xf - truth.back();
  // Final error within 3 sigma per component, and at the metre / mm/s level in absolute terms.
  for (int i = 0; i < 6; ++i) EXPECT_LT(std::abs(err[i]), 3.0 * std::sqrt(pf(i, i))) << "component " << i;
  EXPECT_LT(err.head<3>().norm(), 0.01);  // km: from 1.5 km to < 10 m
  EXPECT_LT(err.tail<3>().norm(), 1e-5);  // km/s
  // No good measurement is rejected after convergence with the 3-sigma-class gate at more than 1 %.
  EXPECT_LT(r.rejected, static_cast<int>(K / 100) + 3);
  // Post-fit residuals of the last pass are at the noise level: RMS of range within 2 sigma.
  double ss = 0;
  int cnt = 0;
  for (std::size_t k = K / 2; k < K; ++k)
    if (r.observable[k] == 0 && r.status[k] == OrbitStepStatus::updated) {
      ss += r.postfit[2 * k] * r.postfit[2 * k];
      ++cnt;
    }
  EXPECT_LT(std::sqrt(ss / cnt), 2.0 * fx::kSigmaRange);
  RecordProperty("final_pos_err_m", std::to_string(err.head<3>().norm() * 1e3));
  RecordProperty("final_pos_sigma_m", std::to_string(std::sqrt(pf.topLeftCorner<3, 3>().trace()) * 1e3));
  RecordProperty("measurements", std::to_string(K));

  // The RTS smoother: at the initial epoch it sees every pass; its error is below the filter's first-step
  // error and within 3 sigma of its own covariance.
  const auto s = OrbitFilter::smooth(r);
  const Vec6 e0 = s.initial_state - fx::truth_state();
  for (int i = 0; i < 6; ++i)
    EXPECT_LT(std::abs(e0[i]), 3.0 * std::sqrt(s.initial_covariance(i, i))) << "component " << i;
  EXPECT_LT(e0.head<3>().norm(), 0.02);  // km
  // The smoothed covariance is never larger than the filtered one (trace, position).
  for (std::size_t k = 0; k + 1 < K; k += 97) {
    const MatrixXd pfk = Eigen::Map<const MatrixXd>(r.covariance.data() + k * 36, 6, 6);
    const MatrixXd psk = Eigen::Map<const MatrixXd>(s.covariance.data() + k * 36, 6, 6);
    EXPECT_LE(psk.topLeftCorner(3, 3).trace(), pfk.topLeftCorner(3, 3).trace() * (1 + 1e-9)) << k;
  }
}

TEST(OrbitFilter, InjectedOutlierIsRejectedAndListed) {
  auto meas = fx::simulate(kSpan, 20.0, 99u);
  // A 2 km range outlier in the second pass (the filter has converged by then).
  std::size_t bad = 0;
  for (std::size_t k = meas.size() / 2; k < meas.size(); ++k)
    if (meas[k].observable == 0) {
      bad = k;
      break;
    }
  meas[bad].value[0] += 2.0;
  OrbitFilter f = make_filter();
  const OrbitFilterResult r = f.run(0.0, fx::truth_state() + initial_error(), p0_km(), meas);
  EXPECT_EQ(r.status[bad], OrbitStepStatus::rejected);
  // Listed with its normalized residual: 2 km over a few-metre innovation sigma is > 100 sigma.
  EXPECT_GT(r.normalized_residual[bad], 100.0);
  EXPECT_GT(r.nis[bad], r.gate[bad]);
  EXPECT_NEAR(r.gate[bad], 9.0, 0.01);                      // chi-square(1) at 0.9973 = 3^2
  EXPECT_NEAR(r.prefit[2 * bad], r.postfit[2 * bad], 0.0);  // state unchanged: the same residual
  // State and covariance are those before the measurement.
  for (int i = 0; i < 6; ++i) EXPECT_EQ(r.state[bad * 6 + i], r.predicted_state[bad * 6 + i]);
  // Without the gate the outlier is used: the next range residuals are pulled off by > 10 sigma.
  OrbitFilterSettings fs;
  fs.gating = false;
  OrbitFilter f2 = make_filter(0, fs);
  const OrbitFilterResult r2 = f2.run(0.0, fx::truth_state() + initial_error(), p0_km(), meas);
  EXPECT_EQ(r2.status[bad], OrbitStepStatus::updated);
  EXPECT_EQ(r2.rejected, 0);
}

TEST(OrbitFilter, RangeBiasesEstimatedAndConsidered) {
  const double b0 = 0.012, b1 = -0.008;  // km
  std::vector<Vec6> truth;
  const auto meas = fx::simulate(kSpan, 20.0, 7u, b0, b1, &truth);
  VectorXd x0(8);
  x0 << fx::truth_state() + initial_error(), 0.0, 0.0;
  MatrixXd p0 = MatrixXd::Zero(8, 8);
  p0.topLeftCorner(6, 6) = p0_km();
  p0(6, 6) = p0(7, 7) = 0.02 * 0.02;  // 20 m a priori
  OrbitFilter f = make_filter(2);
  const auto r = f.run(0.0, x0, p0, meas);
  const std::size_t K = meas.size();
  const double e0 = r.state[(K - 1) * 8 + 6] - b0, e1 = r.state[(K - 1) * 8 + 7] - b1;
  const double s0 = std::sqrt(r.covariance[(K - 1) * 64 + 6 * 8 + 6]);
  const double s1 = std::sqrt(r.covariance[(K - 1) * 64 + 7 * 8 + 7]);
  EXPECT_LT(std::abs(e0), 3 * s0);
  EXPECT_LT(std::abs(e1), 3 * s1);
  EXPECT_LT(s0, 0.005);  // observed: sigma well below the 20 m a priori
  // As consider parameters the biases keep their a-priori value and variance, and the orbit covariance
  // grows (it carries the consider term).
  OrbitFilterSettings fs;
  fs.consider = {6, 7};
  OrbitFilter fc = make_filter(2, fs);
  const auto rc = fc.run(0.0, x0, p0, meas);
  EXPECT_EQ(rc.state[(K - 1) * 8 + 6], 0.0);
  EXPECT_NEAR(rc.covariance[(K - 1) * 64 + 6 * 8 + 6], p0(6, 6), 1e-18);
  double tr_est = 0, tr_con = 0;
  for (int i = 0; i < 3; ++i) {
    tr_est += r.covariance[(K - 1) * 64 + i * 8 + i];
    tr_con += rc.covariance[(K - 1) * 64 + i * 8 + i];
  }
  EXPECT_GT(tr_con, tr_est);
  // Cross-covariance orbit / consider bias is non-zero (the consider covariance is reported).
  EXPECT_GT(std::abs(rc.covariance[(K - 1) * 64 + 0 * 8 + 6]), 0.0);
}

TEST(OrbitFilter, SteppingLoopAllocatesNothingPerStep) {
  // run() allocates its result once; the loop allocates nothing per step: the count does not grow with K.
  const auto meas = fx::simulate(kSpan, 20.0, 5u);
  OrbitFilter f = make_filter();
  const VectorXd x0 = fx::truth_state() + initial_error();
  const std::vector<OrbitMeasurement> few(meas.begin(), meas.begin() + 4);
  g_mallocs = 0;
  g_count = true;
  auto r1 = f.run(0.0, x0, p0_km(), few);
  g_count = false;
  const long a_few = g_mallocs.load();
  g_mallocs = 0;
  g_count = true;
  auto r2 = f.run(0.0, x0, p0_km(), meas);
  g_count = false;
  const long a_all = g_mallocs.load();
  EXPECT_EQ(a_all, a_few) << "K = 4 vs K = " << meas.size();
  EXPECT_EQ(r2.steps_run, static_cast<int>(meas.size()));
}

TEST(OrbitFilter, BadInputIsNamed) {
  const auto meas = fx::simulate(3600.0, 20.0, 5u);
  OrbitFilter f = make_filter();
  const VectorXd x0 = fx::truth_state();
  auto msg = [&](auto&& fn) -> std::string {
    try {
      fn();
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  MatrixXd notpd = p0_km();
  notpd(0, 0) = -1.0;
  EXPECT_NE(msg([&] { f.run(0.0, x0, notpd, meas); }).find("P0: must be positive definite"),
            std::string::npos);
  auto unsorted = meas;
  std::swap(unsorted[0], unsorted[3]);
  EXPECT_NE(msg([&] { f.run(0.0, x0, p0_km(), unsorted); }).find("measurements[1].t"), std::string::npos);
  auto unknown = meas;
  unknown[2].observable = 7;
  EXPECT_NE(msg([&] { f.run(0.0, x0, p0_km(), unknown); }).find("measurements[2].observable"),
            std::string::npos);
  OrbitFilterSettings fs;
  fs.gate_probability = 1.0;
  EXPECT_NE(msg([&] { make_filter(0, fs); }).find("gate_probability: must be in (0, 1)"), std::string::npos);
  fs.gate_probability = 0.0;
  EXPECT_NE(msg([&] { make_filter(0, fs); }).find("gate_probability"), std::string::npos);
  OrbitProcessSettings ps;
  ps.snc_psd_ric[0] = -1e-12;
  EXPECT_NE(
      msg([&] { OrbitProcessModel(fx::truth_model(), ps); }).find("snc_psd_ric[0]: must be finite and >= 0"),
      std::string::npos);
  // The chi-square quantiles: 3 sigma in one dimension, and -2 ln(1 - p) in two.
  EXPECT_NEAR(satgnc::filter::chi2_quantile(1, 0.9973002039367398), 9.0, 1e-9);
  EXPECT_NEAR(satgnc::filter::chi2_quantile(1, 0.95), 3.841458820694124, 1e-9);  // scipy.stats.chi2.ppf
  EXPECT_NEAR(satgnc::filter::chi2_quantile(2, 0.95), 5.991464547107979, 1e-12);
}

}  // namespace

// The orbit models behind the generic engine (filter::KalmanFilter through the ProcessModel /
// MeasurementFunction interfaces) with its default scalar-sequential Joseph update, against
// OrbitFilter (the engine's vector Joseph update of each record, through the orbit front end).
namespace {

TEST(OrbitFilter, GenericKalmanFilterOnTheOrbitModelsMatchesOrbitFilter) {
  const auto meas = fx::simulate(kSpan, 20.0, 1234u);
  OrbitProcessSettings ps;
  ps.snc_psd_ric = Vec3::Constant(1e-15);
  OrbitProcessModel pm(fx::truth_model(), ps);
  OrbitMeasurementFunction mf(fx::measurement_settings(), pm.dimension());
  satgnc::filter::FilterProblem prob;
  prob.x0 = fx::truth_state() + initial_error();
  prob.p0 = p0_km();
  prob.t0 = 0.0;
  for (const auto& m : meas) prob.records.push_back(mf.record(m));
  satgnc::filter::FilterSettings ks;
  ks.gate_probability = 0.9973;
  satgnc::filter::KalmanFilter kf(pm, mf, prob, ks);
  const auto& kr = kf.solve();
  OrbitFilter f = make_filter();
  const OrbitFilterResult r = f.run(0.0, prob.x0, prob.p0, meas);
  const std::size_t K = meas.size();
  ASSERT_EQ(kr.steps, static_cast<int>(K));
  int kf_rejected = 0;
  for (const auto& s : kr.records) kf_rejected += s.flag == satgnc::filter::EditFlag::rejected;
  EXPECT_EQ(kf_rejected, r.rejected);
  // Same models, the Joseph update scalar by scalar vs as a vector (equal in exact arithmetic, R
  // diagonal): the final states agree to 1e-6 of the 1-sigma (rounding through 1000+ steps).
  const VectorXd xf = Eigen::Map<const VectorXd>(r.state.data() + (K - 1) * 6, 6);
  const MatrixXd pf = Eigen::Map<const MatrixXd>(r.covariance.data() + (K - 1) * 36, 6, 6);
  for (int i = 0; i < 6; ++i) {
    EXPECT_LT(std::abs(kr.states(i, static_cast<Eigen::Index>(K) - 1) - xf[i]), 1e-6 * std::sqrt(pf(i, i)))
        << i;
    EXPECT_NEAR(kr.covariances(i, 6 * (static_cast<Eigen::Index>(K) - 1) + i) / pf(i, i), 1.0, 1e-6) << i;
  }
}

}  // namespace

// The measurement function's H (state and bias columns) against central differences of its own
// prediction, for every observable the filter accepts, with range and time biases as states.
namespace {

TEST(OrbitFilter, MeasurementJacobianMatchesCentralDifferencesForEveryObservable) {
  using satgnc::observation::ObservableType;
  const ObservableType types[] = {
      ObservableType::one_way_range,      ObservableType::two_way_range,
      ObservableType::one_way_range_rate, ObservableType::two_way_range_rate,
      ObservableType::azimuth_elevation,  ObservableType::right_ascension_declination};
  auto ms = fx::measurement_settings(6);  // range biases at 6, 7
  ms.observables.clear();
  for (auto ty : types) {
    satgnc::observation::MeasurementSettings o;
    o.type = ty;
    ms.observables.push_back(o);
  }
  for (auto& st : ms.stations) st.sigma.assign(6, 1e-3);
  ms.stations[0].time_bias_state = 8;
  ms.stations[1].time_bias_state = 9;
  OrbitMeasurementFunction mf(ms, 10);
  // A state seen by station 0 at high elevation (the first simulated record's truth).
  std::vector<Vec6> truth;
  const auto meas = fx::simulate(3600.0, 20.0, 1u, 0.0, 0.0, &truth);
  ASSERT_FALSE(meas.empty());
  VectorXd x = VectorXd::Zero(10);
  x.head<6>() = truth[0];
  x[6] = 0.01;
  x[8] = 2e-3;
  const double steps[10] = {1e-3, 1e-3, 1e-3, 1e-6, 1e-6, 1e-6, 1e-4, 1e-4, 1e-5, 1e-5};
  for (int o = 0; o < 6; ++o) {
    OrbitMeasurement m{meas[0].t, meas[0].station, o, Eigen::Vector2d::Zero()};
    Eigen::Vector2d z, s, zp, zm;
    MatrixXd h(2, 10), dummy(2, 10);
    ASSERT_EQ(mf.evaluate(m, x, z, h, s), satgnc::core::ObservationStatus::success) << o;
    const int p = mf.size(m);
    for (int j = 0; j < 10; ++j) {
      VectorXd xp = x, xm = x;
      xp[j] += steps[j];
      xm[j] -= steps[j];
      ASSERT_EQ(mf.evaluate(m, xp, zp, dummy, s), satgnc::core::ObservationStatus::success);
      ASSERT_EQ(mf.evaluate(m, xm, zm, dummy, s), satgnc::core::ObservationStatus::success);
      for (int i = 0; i < p; ++i) {
        const double fd = (zp[i] - zm[i]) / (2 * steps[j]);
        // Central-difference truncation ~ h^2 f''' and rounding ~ 1e-16 |z| / h: agreement to 1e-5 of
        // the row's largest partial (the time-bias partials of the non-range types are themselves
        // central differences over +-1 ms inside the observation room).
        const double scale = h.row(i).cwiseAbs().maxCoeff();
        EXPECT_NEAR(h(i, j), fd, 1e-5 * scale) << "observable " << o << " row " << i << " column " << j;
      }
    }
    // Station 1's bias columns stay zero for a station-0 record.
    EXPECT_EQ(h(0, 7), 0.0);
    EXPECT_EQ(h(0, 9), 0.0);
  }
}

}  // namespace
