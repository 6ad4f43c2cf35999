// Filter engine features the orbit front end needs (issue 15, one filter engine): consider
// parameters at any state index (consider_states), the warm-up by record count (warm_up_records),
// the UKF with consider parameters (general-form update) and the RTS smoother keeping them.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <stdexcept>
#include <string>
#include <vector>

#include "error_checks.hpp"
#include "filter_fixture.hpp"
#include "satgnc/filter/kalman_filter.hpp"
#include "satgnc/filter/linear_models.hpp"
#include "satgnc/filter/rts.hpp"

namespace f = satgnc::filter;

namespace {

using satgnc::testing::message_of;

// Reverse the state order of a linear case: state i becomes n - 1 - i.
satgnc::testing::LinearCase reversed(const satgnc::testing::LinearCase& c) {
  const int n = c.n;
  Eigen::MatrixXd perm = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) perm(n - 1 - i, i) = 1.0;
  satgnc::testing::LinearCase r = c;
  r.phi = perm * c.phi * perm.transpose();
  for (auto& h : r.h) h = h * perm.transpose();
  r.problem.x0 = perm * c.problem.x0;
  r.problem.p0 = perm * c.problem.p0 * perm.transpose();
  return r;
}

// A linear case whose state `c` is a constant parameter (row c of Phi = e_c'): a consider
// parameter then keeps its prior value exactly. Process noise 1e-2 (state units^2) off it.
satgnc::testing::LinearCase with_constant(satgnc::testing::LinearCase c, int k, Eigen::MatrixXd& qd) {
  c.phi.row(k).setZero();
  c.phi(k, k) = 1.0;
  qd = 1e-2 * Eigen::MatrixXd::Identity(c.n, c.n);
  qd(k, k) = 0.0;
  return c;
}

TEST(FilterConsiderStates, ConsiderAtIndexZeroEqualsTheLastStateOfThePermutedProblem) {
  // The same Schmidt-Kalman run twice: consider_count = 1 (the last state) and, on the state-reversed
  // problem, consider_states = {0}. States and covariances agree to 1e-12 relative (same arithmetic
  // in another order: rounding only).
  Eigen::MatrixXd qd;
  const auto c = with_constant(satgnc::testing::make_linear_case(5, 30, 11u), 4, qd);
  const auto cr = reversed(c);
  const Eigen::MatrixXd qr = qd.reverse();  // the reversal permutation applied to both sides
  f::LinearProcessModel pa(c.phi, qd);
  f::LinearProcessModel pb(cr.phi, qr);
  f::LinearMeasurementFunction ma(c.h), mb(cr.h);
  f::FilterSettings sa, sb;
  sa.consider_count = 1;
  sb.consider_states = {0};
  sa.gating = sb.gating = false;
  f::KalmanFilter ka(pa, ma, c.problem, sa), kb(pb, mb, cr.problem, sb);
  const auto& ra = ka.solve();
  const auto& rb = kb.solve();
  ASSERT_EQ(ra.info.status, f::FilterStatus::success);
  ASSERT_EQ(rb.info.status, f::FilterStatus::success);
  EXPECT_EQ(ra.consider, std::vector<int>{4});
  EXPECT_EQ(rb.consider, std::vector<int>{0});
  const int N = ra.steps;
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(rb.states(4 - i, N - 1), ra.states(i, N - 1), 1e-12 * (1.0 + std::abs(ra.states(i, N - 1))));
    for (int j = 0; j < 5; ++j) {
      const double pa_ij = ra.covariances(i, (N - 1) * 5 + j);
      EXPECT_NEAR(rb.covariances(4 - i, (N - 1) * 5 + 4 - j), pa_ij,
                  1e-12 * ra.covariances.cwiseAbs().maxCoeff());
    }
  }
  // The consider state is never updated (exactly its prior value).
  EXPECT_EQ(rb.states(0, N - 1), cr.problem.x0(0));
}

TEST(FilterConsiderStates, UkfWithConsiderEqualsJosephEkfOnALinearModel) {
  // Linear model: the UKF's sigma-point moments are exact, so its general-form consider update
  // equals the EKF's Joseph consider update (vector form) to rounding (1e-9 relative: the UKF's weighted sums
  // with alpha = 1 lose a few digits).
  Eigen::MatrixXd qd;
  const auto c = with_constant(satgnc::testing::make_linear_case(4, 25, 3u), 1, qd);
  f::LinearProcessModel p(c.phi, qd);
  f::LinearMeasurementFunction m(c.h);
  f::FilterSettings se, su;
  se.consider_states = su.consider_states = {1};
  su.algorithm = f::FilterAlgorithm::ukf;
  su.ukf_alpha = 1.0;
  se.gating = su.gating = false;
  se.sequential = false;  // Schmidt-Kalman: scalar-by-scalar processing is not the vector update
  f::KalmanFilter ke(p, m, c.problem, se);
  const f::FilterResult re = ke.solve();
  f::KalmanFilter ku(p, m, c.problem, su);
  const auto& ru = ku.solve();
  ASSERT_EQ(ru.info.status, f::FilterStatus::success);
  const int N = re.steps;
  const double ps = re.covariances.cwiseAbs().maxCoeff();
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(ru.states(i, N - 1), re.states(i, N - 1), 1e-9 * (1.0 + std::abs(re.states(i, N - 1)))) << i;
    for (int j = 0; j < 4; ++j)
      EXPECT_NEAR(ru.covariances(i, (N - 1) * 4 + j), re.covariances(i, (N - 1) * 4 + j), 1e-9 * ps);
  }
  // consider: never updated (the sigma-point mean of a constant: rounding only, 1e-12 relative)
  EXPECT_NEAR(ru.states(1, N - 1), c.problem.x0(1), 1e-12 * std::abs(c.problem.x0(1)));
  // RTS: the consider state keeps its value and its variance at every step and at t0 (exactly: the
  // gain's consider row is zero, and its filtered variance never changes).
  f::RtsSmoother rts(4, N);
  const auto& sm = rts.smooth(re);
  ASSERT_EQ(sm.status, f::FilterStatus::success);
  EXPECT_EQ(sm.initial_state(1), c.problem.x0(1));
  EXPECT_EQ(sm.initial_covariance(1, 1), c.problem.p0(1, 1));
  for (int k = 0; k < N; ++k) EXPECT_EQ(sm.states(1, k), c.problem.x0(1)) << k;
}

TEST(FilterConsiderStates, WarmUpByRecordCount) {
  // Outlier (+50 sigma) at record 30: gated (rejected) with warm_up_records = 30 (records 0..29
  // ungated), accepted as warm_up with 31.
  auto c = satgnc::testing::make_linear_case(6, 40, 4u);
  f::LinearProcessModel proc(c.phi, Eigen::MatrixXd::Zero(6, 6));
  f::LinearMeasurementFunction meas(c.h);
  const int bad = 30;
  c.problem.records[bad].value[0] += 50.0 * c.problem.records[bad].sigma[0];
  f::FilterSettings s;
  s.warm_up_records = bad;
  f::KalmanFilter k1(proc, meas, c.problem, s);
  const auto& r1 = k1.solve();
  EXPECT_EQ(r1.records[bad].flag, f::EditFlag::rejected);
  EXPECT_EQ(r1.records[bad - 1].flag, f::EditFlag::warm_up);
  EXPECT_EQ(r1.records[0].gate, 0.0);
  s.warm_up_records = bad + 1;
  f::KalmanFilter k2(proc, meas, c.problem, s);
  const auto& r2 = k2.solve();
  EXPECT_EQ(r2.records[bad].flag, f::EditFlag::warm_up);
  EXPECT_EQ(r2.info.rejected, 0);
}

TEST(FilterConsiderStates, BadInputMessages) {
  const auto c = satgnc::testing::make_linear_case(3, 5, 1u);
  f::LinearProcessModel proc(c.phi, Eigen::MatrixXd::Zero(3, 3));
  f::LinearMeasurementFunction meas(c.h);
  f::FilterSettings s;
  s.warm_up_records = -1;
  EXPECT_EQ(message_of([&] { s.validate(); }), "settings.warm_up_records: must be >= 0, got -1");
  s = f::FilterSettings{};
  s.consider_states = {3};
  EXPECT_EQ(message_of([&] { f::KalmanFilter kf(proc, meas, c.problem, s); }),
            "settings.consider_states[0]: must be a state index < 3, got 3");
  s.consider_states = {1, 1};
  EXPECT_EQ(message_of([&] { f::KalmanFilter kf(proc, meas, c.problem, s); }),
            "settings.consider_states[1]: state 1 is already a consider parameter");
  s.consider_states = {-2};
  EXPECT_EQ(message_of([&] { s.validate(); }),
            "settings.consider_states[0]: must be a state index >= 0, got -2");
  s.consider_states = {0, 1, 2};
  EXPECT_EQ(message_of([&] { f::KalmanFilter kf(proc, meas, c.problem, s); }),
            "settings.consider_states: at least one state must be estimated");
}

}  // namespace
