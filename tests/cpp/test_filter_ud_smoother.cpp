// RTS smoother on UD factors (issue 15): a UD run is smoothed on its factors (no P_k+1|k inverted,
// the smoothed covariance factored U D U' by MWGS). Checked against the covariance-form RTS over a
// Joseph run of the same problem (independent arithmetic) on seeded random problems with full
// process noise and simultaneous records; D >= 0 on every smoothed step; no heap allocation.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "filter_fixture.hpp"
#include "malloc_counter.hpp"
#include "satgnc/filter/kalman_filter.hpp"
#include "satgnc/filter/linear_models.hpp"
#include "satgnc/filter/rts.hpp"
#include "testing.hpp"

namespace f = satgnc::filter;
using satgnc::testing::rel_err;

namespace {

struct Case {
  satgnc::testing::LinearCase lin;
  Eigen::MatrixXd qd;
};

// make_linear_case plus a full random PSD Qd (scale q) and every third record repeated at its own
// time (zero-length steps: no process noise stored for them).
Case make_case(int n, int epochs, unsigned seed, double q) {
  Case c{satgnc::testing::make_linear_case(n, epochs, seed), Eigen::MatrixXd()};
  std::mt19937 gen(seed + 1000u);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd a(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) a(i, j) = g(gen);
  c.qd = q * (a * a.transpose() / n + 0.1 * Eigen::MatrixXd::Identity(n, n));
  std::vector<f::MeasurementRecord> recs;
  for (std::size_t k = 0; k < c.lin.problem.records.size(); ++k) {
    recs.push_back(c.lin.problem.records[k]);
    if (k % 3 == 0) recs.push_back(c.lin.problem.records[k]);
  }
  c.lin.problem.records = recs;
  return c;
}

f::FilterSettings settings(f::CovarianceForm form) {
  f::FilterSettings s;
  s.gating = false;
  s.form = form;
  return s;
}

}  // namespace

TEST(FilterUdSmoother, EqualsJosephRtsOnSeededRandomProblems) {
  // 24 seeded problems (n = 3, 6, 9; Qd full, scale 1e-3 .. 1e-1): the factored smoother of the UD
  // run equals the covariance-form RTS of the Joseph run, every step and t0, to 1e-10 relative.
  double worst_x = 0.0;
  double worst_p = 0.0;
  for (int n : {3, 6, 9}) {
    for (unsigned seed = 1; seed <= 8; ++seed) {
      const double q = std::pow(10.0, -1.0 - 2.0 * (seed % 3) / 2.0);
      const Case c = make_case(n, 30, 100u * static_cast<unsigned>(n) + seed, q);
      f::LinearProcessModel proc(c.lin.phi, c.qd);
      f::LinearMeasurementFunction meas(c.lin.h);
      f::KalmanFilter kj(proc, meas, c.lin.problem, settings(f::CovarianceForm::joseph));
      f::KalmanFilter ku(proc, meas, c.lin.problem, settings(f::CovarianceForm::ud));
      const auto& rj = kj.solve();
      const auto& ru = ku.solve();
      ASSERT_EQ(rj.info.status, f::FilterStatus::success);
      ASSERT_EQ(ru.info.status, f::FilterStatus::success);
      ASSERT_EQ(ru.ud_factors.cols(), static_cast<Eigen::Index>(n) * ru.steps);
      EXPECT_EQ(rj.ud_factors.size(), 0);  // only UD runs store factors
      f::RtsSmoother sj(n, rj.steps);
      f::RtsSmoother su(n, ru.steps);
      const auto& oj = sj.smooth(rj);
      const auto& ou = su.smooth(ru);
      ASSERT_EQ(oj.status, f::FilterStatus::success);
      ASSERT_EQ(ou.status, f::FilterStatus::success);
      EXPECT_FALSE(oj.factored);
      EXPECT_TRUE(ou.factored);
      worst_x =
          std::max({worst_x, rel_err(ou.states, oj.states), rel_err(ou.initial_state, oj.initial_state)});
      worst_p = std::max({worst_p, rel_err(ou.covariances, oj.covariances),
                          rel_err(ou.initial_covariance, oj.initial_covariance)});
      // Factors: D > 0 on every smoothed step (and t0), and U D U' is the reported covariance.
      for (int k = 0; k < ru.steps; ++k) {
        const Eigen::MatrixXd fk = ou.ud_factors.middleCols(static_cast<Eigen::Index>(k) * n, n);
        EXPECT_GT(fk.diagonal().minCoeff(), 0.0) << "step " << k;
      }
      EXPECT_GT(ou.initial_ud_factors.diagonal().minCoeff(), 0.0);
      Eigen::MatrixXd u = ou.initial_ud_factors.triangularView<Eigen::StrictlyUpper>();
      u.diagonal().setOnes();
      const Eigen::MatrixXd p = u * ou.initial_ud_factors.diagonal().asDiagonal() * u.transpose();
      EXPECT_LE(rel_err(p, ou.initial_covariance), 1e-14);
    }
  }
  EXPECT_LE(worst_x, 1e-10);
  EXPECT_LE(worst_p, 1e-10);
  std::printf("UD smoother vs Joseph RTS, 24 problems: states %.2e, covariances %.2e relative\n", worst_x,
              worst_p);
}

TEST(FilterUdSmoother, FactoredAndCovarianceFormsOfOneUdRunAgree) {
  // The same UD run smoothed both ways (use_factors = false: Cholesky of the stored U D U').
  const Case c = make_case(9, 40, 77u, 0.01);
  f::LinearProcessModel proc(c.lin.phi, c.qd);
  f::LinearMeasurementFunction meas(c.lin.h);
  f::KalmanFilter ku(proc, meas, c.lin.problem, settings(f::CovarianceForm::ud));
  const auto& ru = ku.solve();
  f::RtsSmoother a(9, ru.steps);
  f::RtsSmoother b(9, ru.steps);
  const auto& oa = a.smooth(ru);
  const auto& ob = b.smooth(ru, false);
  ASSERT_TRUE(oa.factored);
  ASSERT_FALSE(ob.factored);
  EXPECT_LE(rel_err(oa.states, ob.states), 1e-10);
  EXPECT_LE(rel_err(oa.covariances, ob.covariances), 1e-10);
  EXPECT_LE(rel_err(oa.initial_covariance, ob.initial_covariance), 1e-10);
}

TEST(FilterUdSmoother, ZeroProcessNoiseSmoothedT0EqualsBatch) {
  // The smoother check on the factored path: with Qd = 0 the smoothed t0 equals batch least
  // squares in information form (1e-6 relative asserted, as for the covariance form).
  auto c = satgnc::testing::make_linear_case(6, 40, 11u);
  f::LinearProcessModel proc(c.phi, Eigen::MatrixXd::Zero(6, 6));
  f::LinearMeasurementFunction meas(c.h);
  const auto [xb, pb] = satgnc::testing::batch_information(c);
  f::KalmanFilter ku(proc, meas, c.problem, settings(f::CovarianceForm::ud));
  const auto& ru = ku.solve();
  f::RtsSmoother sm(6, ru.steps);
  const auto& out = sm.smooth(ru);
  ASSERT_EQ(out.status, f::FilterStatus::success);
  ASSERT_TRUE(out.factored);
  EXPECT_LE(rel_err(out.initial_state, xb), 1e-6);
  EXPECT_LE(rel_err(out.initial_covariance, pb), 1e-6);
}

TEST(FilterUdSmoother, SingularPredictionIsAStatus) {
  // A zero D in a stored predicted factor (P_k+1|k singular) is covariance_not_pd at that step.
  const Case c = make_case(3, 10, 5u, 0.01);
  f::LinearProcessModel proc(c.lin.phi, c.qd);
  f::LinearMeasurementFunction meas(c.lin.h);
  f::KalmanFilter ku(proc, meas, c.lin.problem, settings(f::CovarianceForm::ud));
  f::FilterResult r = ku.solve();
  r.predicted_ud_factors(1, 4 * 3 + 1) = 0.0;  // step 4, D_1
  f::RtsSmoother sm(3, r.steps);
  const auto& out = sm.smooth(r);
  EXPECT_EQ(out.status, f::FilterStatus::covariance_not_pd);
  EXPECT_EQ(out.failed_step, 4);
}

TEST(FilterUdSmoother, SmoothAllocatesNothing) {
  const Case c = make_case(9, 20, 9u, 0.01);
  f::LinearProcessModel proc(c.lin.phi, c.qd);
  f::LinearMeasurementFunction meas(c.lin.h);
  f::KalmanFilter ku(proc, meas, c.lin.problem, settings(f::CovarianceForm::ud));
  const auto& ru = ku.solve();
  f::RtsSmoother sm(9, ru.steps);
  sm.smooth(ru);  // warm
  g_mallocs = 0;
  g_count = true;
  ku.solve();
  const auto& out = sm.smooth(ru);
  g_count = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_TRUE(out.factored);
  EXPECT_EQ(out.status, f::FilterStatus::success);
}

TEST(FilterUdSmoother, IllConditionedCaseSmoothsOnFactors) {
  // The classic ill-conditioned pair (P0 = I3, h = [1 1 1] and [1 1 1+d], sigma = d = 1e-9, both at
  // t = 1; docs/filter.md) then a record [1 0 0] at t = 2, Phi = I, Qd = 0: P after the pair has an
  // eigenvalue ~d^2 = 1e-18 against 1, below what a Cholesky of the formed P can resolve. With Phi = I
  // and no noise the smoother gain is I, so the smoothed state at record 1 equals the filtered state at
  // record 2. The factored smoother gets it exactly (measured 0 relative; D > 0 everywhere). The
  // covariance form's Cholesky of the formed P_k+1|k fails on the same run (measured: status
  // covariance_not_pd, GCC 12 -O3); printed, not asserted, as it depends on rounding.
  const double d = 1e-9;
  std::vector<Eigen::MatrixXd> h(3, Eigen::MatrixXd(1, 3));
  h[0] << 1.0, 1.0, 1.0;
  h[1] << 1.0, 1.0, 1.0 + d;
  h[2] << 1.0, 0.0, 0.0;
  f::LinearProcessModel proc(Eigen::MatrixXd::Identity(3, 3), Eigen::MatrixXd::Zero(3, 3));
  f::LinearMeasurementFunction meas(h);
  f::FilterProblem pb;
  pb.x0 = Eigen::VectorXd::Zero(3);
  pb.p0 = Eigen::MatrixXd::Identity(3, 3);
  pb.t0 = 0.0;
  const double value[3] = {3.0, 3.0, 1.0};
  const double sigma[3] = {d, d, 1.0};
  const double time[3] = {1.0, 1.0, 2.0};
  for (int k = 0; k < 3; ++k) {
    f::MeasurementRecord r;
    r.t = time[k];
    r.type = k;
    r.value[0] = value[k];
    r.sigma[0] = sigma[k];
    pb.records.push_back(r);
  }
  f::KalmanFilter ku(proc, meas, pb, settings(f::CovarianceForm::ud));
  const auto& ru = ku.solve();
  ASSERT_EQ(ru.info.status, f::FilterStatus::success);
  f::RtsSmoother a(3, ru.steps);
  const auto& oa = a.smooth(ru);
  ASSERT_EQ(oa.status, f::FilterStatus::success);
  ASSERT_TRUE(oa.factored);
  for (int k = 0; k < ru.steps; ++k) {
    EXPECT_GT(oa.ud_factors.middleCols(3 * k, 3).diagonal().minCoeff(), 0.0) << "step " << k;
  }
  EXPECT_LE(rel_err(oa.states.col(1), ru.states.col(2)), 1e-6);
  f::RtsSmoother b(3, ru.steps);
  const auto& ob = b.smooth(ru, false);
  std::printf("covariance-form RTS on the same run: %s, |x_s(1) - x_f(2)| rel %.2e; factored %.2e\n",
              f::status_name(ob.status), rel_err(ob.states.col(1), ru.states.col(2)),
              rel_err(oa.states.col(1), ru.states.col(2)));
}
