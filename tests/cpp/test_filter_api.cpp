// Filter room API (issue 15, parcel KF15A): the status tables, the settings checks and a trivial
// one-record run through the interfaces, in the allocation-free scope.
#include <gtest/gtest.h>

#include <string>

#include "filter_fixture.hpp"
#include "malloc_counter.hpp"
#include "satgnc/filter/kalman_filter.hpp"
#include "satgnc/filter/linear_models.hpp"

namespace f = satgnc::filter;
namespace core = satgnc::core;

TEST(FilterApi, StatusTablesAreStableAndUnsolvedFirst) {
  const auto t = core::status_table<f::FilterStatus>();
  ASSERT_EQ(t.size(), 10u);  // unsolved + 9 outcomes; values never change (Python keys by them)
  EXPECT_STREQ(t[0].name, "unsolved");
  EXPECT_EQ(t[0].value, 9);
  EXPECT_EQ(static_cast<int>(f::FilterStatus::success), 0);
  EXPECT_EQ(static_cast<int>(f::FilterStatus::rejected), 1);
  EXPECT_EQ(static_cast<int>(f::FilterStatus::covariance_not_pd), 2);
  EXPECT_EQ(static_cast<int>(f::FilterStatus::innovation_not_pd), 3);
  EXPECT_EQ(static_cast<int>(f::FilterStatus::process_failed), 4);
  EXPECT_EQ(static_cast<int>(f::FilterStatus::measurement_failed), 5);
  EXPECT_STREQ(f::status_name(f::FilterStatus::covariance_not_pd), "covariance_not_pd");
  EXPECT_STREQ(f::status_name(f::EditFlag::rejected), "rejected");
  EXPECT_EQ(core::status_table<f::EditFlag>().size(), 5u);
  EXPECT_EQ(core::status_table<f::ModelStatus>().size(), 3u);
  f::FilterInfo info;
  EXPECT_EQ(info.status, f::FilterStatus::unsolved);
}

TEST(FilterApi, ScalarOneRecordRunIsTheTextbookUpdate) {
  // x = 0, P = 4, one direct measurement z = 2 with sigma 1: K = 4/5, x+ = 1.6, P+ = 0.8 (exact
  // to rounding: 1e-15), NIS = 4/5, normalized residual 2/sqrt(5).
  f::LinearProcessModel proc(Eigen::MatrixXd::Identity(1, 1), Eigen::MatrixXd::Zero(1, 1));
  f::LinearMeasurementFunction meas({Eigen::MatrixXd::Identity(1, 1)});
  f::FilterProblem p;
  p.x0 = Eigen::VectorXd::Zero(1);
  p.p0 = 4.0 * Eigen::MatrixXd::Identity(1, 1);
  f::MeasurementRecord r;
  r.t = 1.0;
  r.value[0] = 2.0;
  r.sigma[0] = 1.0;
  p.records = {r};
  f::KalmanFilter kf(proc, meas, p, f::FilterSettings{});
  const f::FilterResult& res = kf.solve();
  ASSERT_EQ(res.info.status, f::FilterStatus::success);
  EXPECT_NEAR(res.states(0, 0), 1.6, 1e-15);
  EXPECT_NEAR(res.covariances(0, 0), 0.8, 1e-15);
  EXPECT_NEAR(res.records[0].nis, 0.8, 1e-15);
  EXPECT_NEAR(res.records[0].normalized[0], 2.0 / std::sqrt(5.0), 1e-15);
  EXPECT_NEAR(res.records[0].postfit[0], 0.4, 1e-15);
  EXPECT_EQ(res.records[0].flag, f::EditFlag::accepted);
  EXPECT_EQ(res.info.accepted, 1);
}

TEST(FilterApi, SolvePredictUpdateAllocateNothing) {
  // Every form and the UKF, n = 9: zero heap allocations counted in solve() and in predict/update
  // (malloc interposer; the Eigen guard is also active in Debug builds).
  auto c = satgnc::testing::make_linear_case(9, 20, 7u);
  f::LinearProcessModel proc(c.phi, 1e-4 * Eigen::MatrixXd::Identity(9, 9));
  f::LinearMeasurementFunction meas(c.h);
  for (int variant = 0; variant < 5; ++variant) {
    f::FilterSettings s;
    if (variant == 1) s.form = f::CovarianceForm::ud;
    if (variant == 2) s.iterated = true;
    if (variant == 3) s.algorithm = f::FilterAlgorithm::ukf;
    if (variant == 4) s.sequential = false;
    f::KalmanFilter kf(proc, meas, c.problem, s);
    kf.solve();  // warm
    g_mallocs = 0;
    g_count = true;
    const f::FilterResult& r = kf.solve();
    kf.initialize();
    for (const auto& rec : c.problem.records) kf.update(rec);
    g_count = false;
    EXPECT_EQ(g_mallocs.load(), 0) << "variant " << variant;
    EXPECT_EQ(r.info.status, f::FilterStatus::success) << "variant " << variant;
    EXPECT_EQ(r.info.accepted + r.info.rejected, static_cast<int>(c.problem.records.size()));
  }
}
