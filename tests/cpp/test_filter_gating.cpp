// Filter engine: chi-square quantiles without scipy (tabulated values), the outlier gate with
// warm-up, and every bad input's message and per-step status.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "error_checks.hpp"
#include "filter_fixture.hpp"
#include "satgnc/filter/gating.hpp"
#include "satgnc/filter/kalman_filter.hpp"
#include "satgnc/filter/linear_models.hpp"

namespace f = satgnc::filter;

using satgnc::testing::message_of;

TEST(FilterGating, ChiSquareQuantilesMatchTables) {
  // Abramowitz & Stegun table 26.8 / NIST handbook 1.3.6.7.4 (6 decimals): tolerance 6e-7, the
  // tables' rounding (5e-7) plus margin.
  struct Row {
    int dof;
    double p, x;
  };
  const Row rows[] = {{1, 0.95, 3.841459}, {1, 0.99, 6.634897},  {1, 0.999, 10.827566},
                      {2, 0.95, 5.991465}, {2, 0.99, 9.210340},  {2, 0.999, 13.815511},
                      {3, 0.95, 7.814728}, {3, 0.99, 11.344867}, {3, 0.999, 16.266236}};
  for (const Row& r : rows) {
    EXPECT_NEAR(f::chi_square_quantile(r.dof, r.p), r.x, 6e-7) << r.dof << " " << r.p;
  }
  // dof 2 has the closed form -2 ln(1 - p): 1e-13 relative.
  for (double p : {1e-6, 0.1, 0.5, 0.9, 0.999999}) {
    EXPECT_NEAR(f::chi_square_quantile(2, p), -2.0 * std::log1p(-p), 1e-13 * (-2.0 * std::log1p(-p)));
  }
  // Round trip P(dof/2, x/2) = p to 1e-14 over dof 1..10.
  for (int dof = 1; dof <= 10; ++dof) {
    for (double p : {0.01, 0.5, 0.95, 0.9999}) {
      EXPECT_NEAR(f::regularized_gamma_p(0.5 * dof, 0.5 * f::chi_square_quantile(dof, p)), p, 1e-14);
    }
  }
  EXPECT_EQ(message_of([] { f::chi_square_quantile(1, 1.0); }),
            "probability: must be in (0, 1), got 1.000000");
  EXPECT_EQ(message_of([] { f::chi_square_quantile(0, 0.5); }), "dof: must be finite and > 0, got 0.000000");
}

TEST(FilterGating, InjectedOutlierIsRejectedAndListed) {
  // n = 6 linear case, gate p = 0.999; record 30 gets +50 sigma added: rejected (flag and status),
  // its normalized residual > 40 listed, state and covariance left at the prediction; every other
  // record accepted (their NIS below the 0.999 quantiles here). A warm-up over the outlier's
  // time accepts it instead (flag warm_up).
  auto c = satgnc::testing::make_linear_case(6, 40, 4u);
  f::LinearProcessModel proc(c.phi, Eigen::MatrixXd::Zero(6, 6));
  f::LinearMeasurementFunction meas(c.h);
  const int bad = 30;
  auto& rec = c.problem.records[bad];
  rec.value[0] += 50.0 * rec.sigma[0];
  f::FilterSettings s;
  f::KalmanFilter kf(proc, meas, c.problem, s);
  const auto& r = kf.solve();
  EXPECT_EQ(r.info.status, f::FilterStatus::success);  // a rejection is editing, not a failure
  EXPECT_EQ(r.info.rejected, 1);
  EXPECT_EQ(r.records[bad].flag, f::EditFlag::rejected);
  EXPECT_EQ(r.records[bad].status, f::FilterStatus::rejected);
  EXPECT_GT(std::abs(r.records[bad].normalized[0]), 40.0);
  EXPECT_GT(r.records[bad].nis, r.records[bad].gate);
  EXPECT_NEAR(r.records[bad].gate, f::chi_square_quantile(r.records[bad].dim, 0.999), 1e-12);
  EXPECT_EQ(r.states.col(bad), r.predicted_states.col(bad));
  for (int k = 0; k < r.steps; ++k) {
    if (k != bad) EXPECT_EQ(r.records[static_cast<std::size_t>(k)].flag, f::EditFlag::accepted) << k;
  }
  s.warm_up = rec.t + 1.0;
  f::KalmanFilter kw(proc, meas, c.problem, s);
  const auto& rw = kw.solve();
  EXPECT_EQ(rw.records[bad].flag, f::EditFlag::warm_up);
  EXPECT_EQ(rw.info.rejected, 0);
}

TEST(FilterGating, BadInputMessages) {
  auto c = satgnc::testing::make_linear_case(3, 5, 1u);
  f::LinearProcessModel proc(c.phi, Eigen::MatrixXd::Zero(3, 3));
  f::LinearMeasurementFunction meas(c.h);
  f::FilterSettings s;
  auto build = [&](const f::FilterProblem& p, const f::FilterSettings& st) {
    f::KalmanFilter kf(proc, meas, p, st);
  };
  f::FilterProblem p = c.problem;
  p.p0(2, 2) = -1.0;
  EXPECT_EQ(
      message_of([&] { build(p, s); }),
      "problem.p0: must be positive definite (Cholesky failed) (hint: a covariance with a zero or negative "
      "variance)");
  p = c.problem;
  p.p0(0, 1) = 0.5;
  EXPECT_EQ(message_of([&] { build(p, s); }), "problem.p0: must be symmetric (|P - P'| <= 1e-12 max|P|)");
  Eigen::MatrixXd qneg = Eigen::MatrixXd::Zero(3, 3);
  qneg(1, 1) = -1e-3;
  EXPECT_EQ(message_of([&] { f::LinearProcessModel bad(c.phi, qneg); })
                .rfind("qd: must be positive semidefinite "
                       "(negative process noise",
                       0),
            0u);
  for (double prob : {0.0, 1.0, 1.5, -0.1}) {
    f::FilterSettings sb;
    sb.gate_probability = prob;
    EXPECT_EQ(
        message_of([&] { sb.validate(); }).rfind("settings.gate_probability: must be in (0, 1), got", 0), 0u)
        << prob;
    EXPECT_NE(message_of([&] { build(c.problem, sb); }), "no exception");
  }
  p = c.problem;
  p.records[2].type = 7;
  EXPECT_EQ(message_of([&] { build(p, s); }),
            "problem.records[2].type: type 7 is not set up by the measurement function (dimension 0)");
  p = c.problem;
  std::swap(p.records[1], p.records[3]);
  EXPECT_EQ(message_of([&] { build(p, s); }).rfind("problem.records[2].t: records must be sorted by time", 0),
            0u);
  p = c.problem;
  p.records[0].t = -1.0;
  EXPECT_EQ(message_of([&] { build(p, s); }),
            "problem.records[0].t: must be >= t0 (records start at or after the initial time)");
  p = c.problem;
  p.records[1].sigma[0] = 0.0;
  EXPECT_EQ(message_of([&] { build(p, s); }),
            "problem.records[1].sigma: must be finite and > 0, got 0.000000");
  p = c.problem;
  p.x0.resize(2);
  EXPECT_EQ(message_of([&] { build(p, s); }),
            "problem.x0: must have the process model's state dimension 3, got 2");
  f::FilterSettings sc;
  sc.consider_count = 1;
  sc.form = f::CovarianceForm::ud;
  EXPECT_EQ(
      message_of([&] { sc.validate(); }),
      "settings.consider_count: consider parameters need the EKF with the Joseph form (any gain is valid "
      "there)");
  f::FilterSettings si;
  si.iterated = true;
  si.form = f::CovarianceForm::ud;
  EXPECT_EQ(message_of([&] { si.validate(); }),
            "settings.iterated: the iterated EKF needs algorithm ekf with the joseph or conventional form");
  f::FilterSettings sa;
  sa.ukf_alpha = 0.0;
  EXPECT_EQ(message_of([&] { sa.validate(); }),
            "settings.ukf_alpha: must be in (0, 1], got 0.000000 (hint: 1e-3 is the standard default)");
}

namespace {
// A process model that fails after t = 2, or returns negative process noise.
class FailingProcess : public f::ProcessModel {
 public:
  explicit FailingProcess(bool negative_q) : negative_q_(negative_q) {}
  int state_dimension() const noexcept override { return 2; }
  f::ModelStatus propagate(const Eigen::Ref<const Eigen::VectorXd>& x0, double, double t1,
                           Eigen::Ref<Eigen::VectorXd> x1, Eigen::Ref<Eigen::MatrixXd> phi,
                           Eigen::Ref<Eigen::MatrixXd> qd, bool) noexcept override {
    x1 = x0;
    phi.setIdentity();
    qd.setZero();
    if (negative_q_) qd(1, 1) = -1.0;
    return t1 > 2.0 ? f::ModelStatus::failed : f::ModelStatus::success;
  }

 private:
  bool negative_q_;
};
}  // namespace

TEST(FilterGating, PerStepStatuses) {
  // Statuses, never exceptions, inside solve() / update(): a process failure stops the run (later
  // steps unsolved); negative process noise is process_failed; a beacon record at zero range is
  // measurement_failed (no update, flag failed); an unknown type in update() is
  // unknown_measurement_type; a record before the filter time is invalid_time.
  Eigen::MatrixXd beacons(2, 1);
  beacons << 0.0, 0.0;
  f::BeaconRangeFunction meas(beacons, 2);
  f::FilterProblem p;
  p.x0 = Eigen::VectorXd::Ones(2);
  p.p0 = Eigen::MatrixXd::Identity(2, 2);
  for (int k = 1; k <= 4; ++k) {
    f::MeasurementRecord r;
    r.t = k;
    r.value[0] = std::sqrt(2.0);
    r.sigma[0] = 0.1;
    p.records.push_back(r);
  }
  FailingProcess proc(false);
  f::KalmanFilter kf(proc, meas, p, f::FilterSettings{});
  const auto& r = kf.solve();
  EXPECT_EQ(r.records[0].status, f::FilterStatus::success);
  EXPECT_EQ(r.records[2].status, f::FilterStatus::process_failed);
  EXPECT_EQ(r.records[3].status, f::FilterStatus::unsolved);
  EXPECT_EQ(r.info.status, f::FilterStatus::process_failed);
  EXPECT_EQ(r.info.first_failure, 2);
  FailingProcess negq(true);
  f::KalmanFilter kn(negq, meas, p, f::FilterSettings{});
  EXPECT_EQ(kn.solve().records[0].status, f::FilterStatus::process_failed);
  // zero range at the state (0, 0)
  f::FilterProblem pz = p;
  pz.x0 = Eigen::VectorXd::Zero(2);
  f::LinearProcessModel still(Eigen::MatrixXd::Identity(2, 2), Eigen::MatrixXd::Zero(2, 2));
  f::KalmanFilter kz(still, meas, pz, f::FilterSettings{});
  const auto& rz = kz.solve();
  EXPECT_EQ(rz.records[0].status, f::FilterStatus::measurement_failed);
  EXPECT_EQ(rz.records[0].flag, f::EditFlag::failed);
  EXPECT_EQ(rz.info.failed, 4);
  f::KalmanFilter ku(still, meas, p, f::FilterSettings{});
  f::MeasurementRecord unknown = p.records[0];
  unknown.type = 3;
  EXPECT_EQ(ku.update(unknown), f::FilterStatus::unknown_measurement_type);
  EXPECT_EQ(ku.update(p.records[1]), f::FilterStatus::success);
  EXPECT_EQ(ku.update(p.records[0]), f::FilterStatus::invalid_time);
  EXPECT_EQ(ku.last_step().status, f::FilterStatus::invalid_time);
}
