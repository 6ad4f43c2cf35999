// State-constrained L1 ADMM (guidance/state_constraints.hpp): no allocation in solve() and in
// set_half_space(), the polish certificate on a CW plan with an active half-space, and setup errors
// naming the field. The Clarabel comparisons are in tests/python/test_l1_state_constraints.py.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "malloc_counter.hpp"
#include "satgnc/dynamics/cw.hpp"
#include "satgnc/guidance/state_constraints.hpp"

namespace {
using satgnc::guidance::AdmmSettings;
using satgnc::guidance::AdmmStatus;
using satgnc::guidance::LtvProblem;
using satgnc::guidance::StateConstrainedAdmm;
using satgnc::guidance::StateConstraints;

LtvProblem cw_problem(int N) {
  const satgnc::dynamics::CwModel model(0.0011, 1.0);
  const auto d = satgnc::dynamics::cw_discretize_zoh(model, 30.0);
  LtvProblem p;
  p.dynamics.A = {Eigen::MatrixXd(d.Ad)};
  p.dynamics.B = {Eigen::MatrixXd(d.Bd)};
  p.dynamics.horizon = N;
  p.x0 = (Eigen::VectorXd(6) << 100.0, 20.0, -10.0, 0.01, 0.0, 0.005).finished();
  p.Qf = Eigen::MatrixXd::Identity(6, 6);
  p.l1_weights = Eigen::VectorXd::Constant(3, 0.5);
  p.u_lower = Eigen::VectorXd::Constant(3, -0.02);
  p.u_upper = Eigen::VectorXd::Constant(3, 0.02);
  return p;
}

StateConstraints half_spaces(int N, double b) {
  StateConstraints c;
  for (int k = N / 2; k <= N; ++k) {
    Eigen::VectorXd a = Eigen::VectorXd::Zero(6);
    a(0) = -1.0;  // x_k[0] >= -b
    c.half_spaces.push_back({k, a, b});
  }
  c.cones.push_back({{N}, Eigen::Vector3d(1.0, 0.0, 0.0), 0.7, -50.0, {0, 1, 2}});
  return c;
}
}  // namespace

TEST(StateAdmm, SolveAndHalfSpaceUpdateDoNotAllocate) {
  // both paths: the interior-point method first (default), and ADMM alone
  for (const auto method : {satgnc::guidance::AdmmMethod::kAdmmIpm, satgnc::guidance::AdmmMethod::kAdmm}) {
    const int N = 20;
    AdmmSettings st;
    st.method = method;
    st.max_iterations = 600;  // the count covers iterations, rho updates, polish attempts, gap checks
    StateConstrainedAdmm s(cw_problem(N), half_spaces(N, -2.0), st);
    Eigen::VectorXd a = Eigen::VectorXd::Zero(6);
    a(0) = -1.0;
    g_mallocs = 0;
    g_count = true;
    const int ipm1 = s.solve().info.ipm_iterations;
    const bool ok = s.set_half_space(0, N / 2, a, 1.0);
    const int ipm2 = s.solve().info.ipm_iterations;
    g_count = false;
    EXPECT_TRUE(ok);
    EXPECT_EQ(g_mallocs.load(), 0);
    if (method == satgnc::guidance::AdmmMethod::kAdmm) {
      EXPECT_EQ(ipm1 + ipm2, 0);
    } else {
      EXPECT_GT(ipm1, 0);
      EXPECT_GT(ipm2, 0);
    }
  }
}

TEST(StateAdmm, InteriorPointCertifiesWithTerminalState) {
  // hard terminal state (equality rows at node N through their multipliers), a cone and
  // half-spaces: the IPM alone ends `solved` by the independent violation and gap tests
  const int N = 30;
  auto p = cw_problem(N);
  p.terminal_equality = true;
  p.xf = Eigen::VectorXd::Zero(6);
  p.u_lower = Eigen::VectorXd::Constant(3, -0.05);
  p.u_upper = Eigen::VectorXd::Constant(3, 0.05);
  AdmmSettings st;
  st.method = satgnc::guidance::AdmmMethod::kIpm;
  st.eps_gap = 1e-8;
  StateConstrainedAdmm s(p, half_spaces(N, 2.0), st);  // x_k[0] >= -2 m: x_N = 0 is allowed
  const auto& r = s.solve();
  EXPECT_EQ(r.info.status, AdmmStatus::solved);
  EXPECT_TRUE(r.info.ipm_solved);
  EXPECT_EQ(r.info.iterations, 0);
  EXPECT_LE(r.info.ipm_iterations, 60);
  EXPECT_LE(std::abs(r.info.duality_gap), 1e-8);
  EXPECT_LE(r.max_violation, r.violation_tolerance);
  EXPECT_LE(r.info.terminal_miss, 1e-6);
}

TEST(StateAdmm, HardTerminalInteriorPointDoesNotAllocate) {
  // the equality rows' Schur complement (ne = 6 <= nx) in a factor sized min(m, nx) at setup: two
  // solves (the second after a half-space update) allocate nothing and both are IPM-certified
  const int N = 30;
  auto p = cw_problem(N);
  p.terminal_equality = true;
  p.xf = Eigen::VectorXd::Zero(6);
  p.u_lower = Eigen::VectorXd::Constant(3, -0.05);
  p.u_upper = Eigen::VectorXd::Constant(3, 0.05);
  AdmmSettings st;
  st.eps_gap = 1e-8;
  StateConstrainedAdmm s(p, half_spaces(N, 2.0), st);
  Eigen::VectorXd a = Eigen::VectorXd::Zero(6);
  a(0) = -1.0;
  g_mallocs = 0;
  g_count = true;
  const bool solved1 = s.solve().info.ipm_solved;
  const bool ok = s.set_half_space(0, N / 2, a, 3.0);
  const auto& r = s.solve();
  g_count = false;
  EXPECT_TRUE(ok);
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_TRUE(solved1);
  EXPECT_EQ(r.info.status, AdmmStatus::solved);
  EXPECT_TRUE(r.info.ipm_solved);
  EXPECT_LE(std::abs(r.info.duality_gap), 1e-8);
  EXPECT_LE(r.info.terminal_miss, 1e-6);
}

TEST(StateAdmm, StatusIsHonest) {
  // whatever the outcome, "solved" only with the violation and gap tests holding on the result
  const int N = 20;
  AdmmSettings st;
  st.eps_gap = 1e-8;
  StateConstrainedAdmm s(cw_problem(N), half_spaces(N, -2.0), st);
  const auto& r = s.solve();
  EXPECT_TRUE(std::isfinite(r.info.objective));
  EXPECT_LE(r.info.dual_objective, r.info.objective + 1e-8 * std::abs(r.info.objective));
  if (r.info.status == AdmmStatus::solved) {
    EXPECT_LE(r.max_violation, r.violation_tolerance);
    EXPECT_LE(std::abs(r.info.duality_gap), 1e-8);
    EXPECT_NEAR(s.violation(r.X_flown), r.max_violation, 1e-12);
  }
}

TEST(StateAdmm, SetupErrorsNameTheField) {
  const int N = 10;
  auto expect_msg = [&](StateConstraints c, const std::string& what) {
    try {
      StateConstrainedAdmm s(cw_problem(N), c);
      ADD_FAILURE() << "no throw for " << what;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  StateConstraints c1;
  c1.cones.push_back({{1}, Eigen::Vector3d(1, 0, 0), 2.0, 0.0, {0, 1, 2}});
  expect_msg(c1, "cones[0].half_angle");
  StateConstraints c2;
  c2.half_spaces.push_back({0, Eigen::VectorXd::Ones(6), 1.0});
  expect_msg(c2, "half_spaces[0].node");
  StateConstraints c3;
  c3.boxes.push_back({{1}, Eigen::VectorXd::Ones(6), Eigen::VectorXd::Zero(6)});
  expect_msg(c3, "boxes[0].lower");
}

namespace {
// the cone bench's shape at N = 40 (CW, 20 deg approach cone at every node, apex 20 m behind the
// target) with x_N = 0; nu_pad > 3 appends controls with a zero column of B (L1-weighted, so 0 at the
// optimum): the same problem through the dynamic-size path of the IPM instead of the (6, 3) one
LtvProblem cone_problem(int N, int nu_pad) {
  auto p = cw_problem(N);
  p.x0 = (Eigen::VectorXd(6) << 150.0, 25.0, -10.0, -0.08, 0.0, 0.01).finished();
  p.terminal_equality = true;
  p.Qf = Eigen::MatrixXd::Zero(6, 6);
  p.xf = Eigen::VectorXd::Zero(6);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(6, nu_pad);
  B.leftCols(3) = p.dynamics.B[0];
  p.dynamics.B = {B};
  p.l1_weights = Eigen::VectorXd::Ones(nu_pad);
  p.u_lower = Eigen::VectorXd::Constant(nu_pad, -0.05);
  p.u_upper = Eigen::VectorXd::Constant(nu_pad, 0.05);
  return p;
}
StateConstraints approach_cone(int N) {
  StateConstraints c;
  std::vector<int> nodes;
  for (int k = 1; k <= N; ++k) nodes.push_back(k);
  c.cones.push_back({nodes, Eigen::Vector3d(1.0, 0.0, 0.0), 20.0 * M_PI / 180.0, -20.0, {0, 1, 2}});
  return c;
}
}  // namespace

TEST(StateAdmm, FixedSizeIpmPathEqualsDynamicPath) {
  // (nx, nu) = (6, 3) runs the IPM's fixed-size stage kernels, (6, 4) the dynamic ones: both
  // IPM-certified (gap <= 1e-8) on the same plan (the padded control stays 0)
  const int N = 40;
  AdmmSettings st;
  st.method = satgnc::guidance::AdmmMethod::kIpm;
  st.eps_gap = 1e-8;
  StateConstrainedAdmm s3(cone_problem(N, 3), approach_cone(N), st);
  StateConstrainedAdmm s4(cone_problem(N, 4), approach_cone(N), st);
  g_mallocs = 0;
  g_count = true;  // neither path allocates
  const auto& r3 = s3.solve();
  const auto& r4 = s4.solve();
  g_count = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  ASSERT_EQ(r3.info.status, AdmmStatus::solved);
  ASSERT_EQ(r4.info.status, AdmmStatus::solved);
  EXPECT_TRUE(r3.info.ipm_solved && r4.info.ipm_solved);
  // both within eps_gap = 1e-8 of the optimum: the objectives agree to 2e-8 relative (measured 2.6e-9;
  // plans 2.2e-9 apart, the padded control exactly 0)
  EXPECT_LE(std::abs(r3.info.objective - r4.info.objective), 2e-8 * std::abs(r3.info.objective));
  EXPECT_LE(r4.Y.row(3).cwiseAbs().maxCoeff(), 1e-9 * 0.05);
  // the plans: equal to the IPM's accuracy (1e-6 of the box; the L1 optimum is unique here)
  EXPECT_LE((r3.Y - r4.Y.topRows(3)).cwiseAbs().maxCoeff(), 1e-6 * 0.05);
  EXPECT_LE(r3.info.terminal_miss, 1e-6);
  EXPECT_LE(r4.info.terminal_miss, 1e-6);
}

TEST(StateAdmm, HalfSpaceUpdateRefactorsOnlyWhenAdmmRuns) {
  // set_half_space marks the ADMM's Riccati gains stale; a solve that the IPM certifies never
  // refactors them, a solve by ADMM refactors once before iterating
  const int N = 20;
  Eigen::VectorXd a = Eigen::VectorXd::Zero(6);
  a(0) = -1.0;
  AdmmSettings st;
  st.eps_gap = 1e-8;
  StateConstrainedAdmm s(cw_problem(N), half_spaces(N, 2.0), st);
  ASSERT_TRUE(s.set_half_space(0, N / 2, a, 3.0));
  const auto& r = s.solve();
  EXPECT_TRUE(r.info.ipm_solved);
  EXPECT_EQ(r.info.factorizations, 0);
  AdmmSettings st2 = st;
  st2.method = satgnc::guidance::AdmmMethod::kAdmm;
  st2.adaptive_rho = false;
  StateConstrainedAdmm s2(cw_problem(N), half_spaces(N, 2.0), st2);
  ASSERT_TRUE(s2.set_half_space(0, N / 2, a, 3.0));
  const auto& r2 = s2.solve();
  EXPECT_EQ(r2.info.ipm_iterations, 0);
  EXPECT_EQ(r2.info.factorizations, 1);
}
