// ADMM statuses that can be trusted (issue 11): the duality gap behind `solved`, rho adaptation
// with a zero dual residual, primal infeasibility with a checked Farkas certificate, time limit,
// workspace size check, equilibration returning unscaled results, and no allocation on these paths.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "malloc_counter.hpp"
#include "satgnc/dynamics/cw.hpp"
#include "satgnc/guidance/admm.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using satgnc::guidance::AdmmMethod;
using satgnc::guidance::AdmmResult;
using satgnc::guidance::AdmmSettings;
using satgnc::guidance::AdmmSolver;
using satgnc::guidance::AdmmStatus;
using satgnc::guidance::LtvProblem;

namespace {
LtvProblem cw_problem(double n, double dt, int N, const VectorXd& x0, double qf, const VectorXd& w) {
  const satgnc::dynamics::CwModel cw(n, 1.0);
  const auto d = satgnc::dynamics::cw_discretize_zoh(cw, dt);
  LtvProblem p;
  p.dynamics.A = {MatrixXd(d.Ad)};
  p.dynamics.B = {MatrixXd(d.Bd)};
  p.dynamics.horizon = N;
  p.x0 = x0;
  p.Qf = qf * MatrixXd::Identity(6, 6);
  p.l1_weights = w;
  return p;
}

// issue 11, first reproducer: Y stays 0, so the dual residual is exactly 0
LtvProblem zero_dual_residual_problem() {
  VectorXd x0(6);
  x0 << 0.3, -0.2, 0.1, 1e-4, -1e-4, 0.0;
  return cw_problem(0.00085, 60.0, 4, x0, 1.0, Eigen::Vector3d(3.0, 7.0, 7.0));
}

// issue 11, second reproducer: `solved` at 2.3x the optimum 0.02386 after 969 iterations
LtvProblem false_solved_problem() {
  VectorXd x0(6);
  x0 << -501, -412, 673, 0.664, -0.473, 0.0;
  return cw_problem(0.0011, 51.65, 25, x0, 9.68, Eigen::Vector3d(0.1, 0.1, 1.0));
}

// x_N = 0 from 1 km away with a bound far below what the horizon needs
LtvProblem infeasible_problem() {
  VectorXd x0(6);
  x0 << 1000.0, -500.0, 200.0, 0.0, 0.0, 0.0;
  LtvProblem p = cw_problem(0.0011, 30.0, 20, x0, 1.0, Eigen::Vector3d::Ones());
  p.terminal_equality = true;
  p.u_lower = VectorXd::Constant(3, -1e-4);
  p.u_upper = VectorXd::Constant(3, 1e-4);
  return p;
}
}  // namespace

TEST(AdmmHonest, SolvedMeansTheGapHolds) {
  for (const LtvProblem& p : {zero_dual_residual_problem(), false_solved_problem()}) {
    AdmmSolver s(p);
    const AdmmResult& r = s.solve();
    ASSERT_EQ(r.info.status, AdmmStatus::solved) << r.info.iterations;
    EXPECT_LE(r.info.duality_gap, s.settings().eps_gap);
    EXPECT_LE(r.info.dual_objective, r.info.primal_objective * (1.0 + 1e-12));
    EXPECT_DOUBLE_EQ(r.info.primal_objective, r.info.objective);
    EXPECT_TRUE(std::isfinite(r.info.objective));
  }
}

TEST(AdmmHonest, FalseSolvedReproducerReachesTheOptimum) {
  AdmmSolver s(false_solved_problem());
  const AdmmResult& r = s.solve();
  ASSERT_EQ(r.info.status, AdmmStatus::solved);
  EXPECT_NEAR(r.info.objective, 0.023865, 2e-6);  // Clarabel: 0.02386 (tests/python/test_l1_random.py)
}

TEST(AdmmHonest, ZeroDualResidualStillMovesRho) {
  AdmmSolver s(zero_dual_residual_problem());
  const AdmmResult& r = s.solve();
  EXPECT_EQ(r.info.status, AdmmStatus::solved);
  EXPECT_LT(r.info.iterations, 2000);
}

TEST(AdmmHonest, GapIsAValidLowerBoundAtEveryIterationCount) {
  // D <= optimum holds for any iterate: the bound of an early stop never exceeds the converged P
  AdmmSolver ref(false_solved_problem());
  const double opt = ref.solve().info.objective;
  for (int it : {1, 3, 10, 30, 100, 300}) {
    AdmmSettings st;
    st.max_iterations = it;
    st.polish = false;
    st.method = satgnc::guidance::AdmmMethod::kAdmm;  // ADMM's own iterates (no endgame)
    AdmmSolver s(false_solved_problem(), st);
    const AdmmResult& r = s.solve();
    EXPECT_LE(r.info.dual_objective, opt * (1.0 + 1e-9)) << it;
    EXPECT_GE(r.info.primal_objective, opt * (1.0 - 1e-9)) << it;
    EXPECT_GE(r.info.duality_gap, -1e-12) << it;
    EXPECT_NE(r.info.status, AdmmStatus::solved) << it;  // 300 iterations are not enough here
  }
}

TEST(AdmmHonest, SolvedInaccurateAtTheLimit) {
  AdmmSettings st;
  st.polish = false;
  st.eps_gap = 1e-12;  // unreachable tight tolerance: the loose one (1e-11) may pass
  st.eps_abs = 1e-12;
  st.eps_rel = 1e-12;
  st.inaccurate_factor = 1e9;
  st.max_iterations = 3000;
  st.method = satgnc::guidance::AdmmMethod::kAdmm;  // ADMM's limit (the IPM endgame reaches 1e-12)
  AdmmSolver s(false_solved_problem(), st);
  const AdmmResult& r = s.solve();
  EXPECT_EQ(r.info.status, AdmmStatus::solved_inaccurate);
  EXPECT_LE(r.info.duality_gap, 1e9 * st.eps_gap);
}

TEST(AdmmHonest, PrimalInfeasibleWithFarkasCertificate) {
  const LtvProblem p = infeasible_problem();
  AdmmSolver s(p);
  const AdmmResult& r = s.solve();
  ASSERT_EQ(r.info.status, AdmmStatus::primal_infeasible) << r.info.iterations;
  const VectorXd& y = r.infeasibility_certificate;
  ASSERT_NEAR(y.norm(), 1.0, 1e-12);
  // y' (x_f - x_N(0)) > max over the box of y' sum_k Phi(N, k+1) B u_k
  const MatrixXd& A = p.dynamics.A[0];
  const MatrixXd& B = p.dynamics.B[0];
  VectorXd xN0 = p.x0;
  for (int k = 0; k < p.dynamics.horizon; ++k) xN0 = (A * xN0).eval();
  VectorXd lam = y;
  double sigma = 0.0;
  for (int k = p.dynamics.horizon - 1; k >= 0; --k) {
    const VectorXd m = B.transpose() * lam;
    for (int i = 0; i < 3; ++i) sigma += std::max(m(i) * p.u_lower(i), m(i) * p.u_upper(i));
    lam = (A.transpose() * lam).eval();
  }
  EXPECT_GT(-y.dot(xN0), sigma);
  EXPECT_LT(r.info.iterations, 500);
  // the same target with a generous bound is feasible and solved
  LtvProblem q = p;
  q.u_lower *= 1e3;
  q.u_upper *= 1e3;
  AdmmSolver s2(q);
  EXPECT_EQ(s2.solve().info.status, AdmmStatus::solved);
}

TEST(AdmmHonest, TimeLimit) {
  AdmmSettings st;
  st.time_limit = 1e-9;
  st.polish = false;
  AdmmSolver s(false_solved_problem(), st);
  const AdmmResult& r = s.solve();
  EXPECT_EQ(r.info.status, AdmmStatus::time_limit);
  EXPECT_EQ(r.info.iterations, 1);
  EXPECT_TRUE(std::isfinite(r.info.objective));
  EXPECT_GT(r.info.objective, 0.0);
}

TEST(AdmmHonest, TimeLimitStopsTheInteriorPointMethod) {
  // the IPM checks the limit per iteration: alone (method ipm) it ends time_limit after at most one
  // iteration with its plan's true, finite objective; as the endgame it returns without running
  AdmmSettings st;
  st.time_limit = 1e-9;
  st.method = AdmmMethod::kIpm;
  AdmmSolver s(false_solved_problem(), st);
  const AdmmResult& r = s.solve();
  EXPECT_EQ(r.info.status, AdmmStatus::time_limit);
  EXPECT_FALSE(r.info.ipm_solved);
  EXPECT_LE(r.info.ipm_iterations, 1);
  EXPECT_TRUE(std::isfinite(r.info.objective));
  EXPECT_TRUE(r.U.allFinite());
  st.method = AdmmMethod::kAdmmIpm;
  st.ipm_after = 0;
  AdmmSolver s2(false_solved_problem(), st);
  EXPECT_EQ(s2.solve().info.status, AdmmStatus::time_limit);
  EXPECT_LE(s2.result().info.ipm_iterations, 1);
}

TEST(AdmmHonest, HugeHorizonIsRejectedWithItsMemory) {
  LtvProblem p = false_solved_problem();
  p.dynamics.horizon = 1000000;
  try {
    AdmmSolver s(p);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("horizon:", 0), 0u) << m;
    EXPECT_NE(m.find("bytes"), std::string::npos) << m;
    EXPECT_NE(m.find("MB"), std::string::npos) << m;
  }
  AdmmSolver ok(false_solved_problem());
  EXPECT_GT(ok.solve().info.workspace_bytes, 1e3);
  AdmmSettings st;
  st.max_workspace_bytes = 1e3;
  EXPECT_THROW(AdmmSolver(false_solved_problem(), st), std::invalid_argument);
}

TEST(AdmmHonest, EquilibrationReturnsUnscaledResults) {
  // the same physics in mm/s^2 (B / 1e3): the controls come back 1e3 larger, the cost is the same
  LtvProblem p = false_solved_problem();
  LtvProblem q = p;
  q.dynamics.B[0] /= 1e3;
  q.l1_weights /= 1e3;
  AdmmSolver a(p), b(q);
  const AdmmResult& ra = a.solve();
  const AdmmResult& rb = b.solve();
  ASSERT_EQ(ra.info.status, AdmmStatus::solved);
  ASSERT_EQ(rb.info.status, AdmmStatus::solved);
  // both within eps_gap (1e-5) of the same optimum
  EXPECT_NEAR(rb.info.objective, ra.info.objective, 2e-5 * ra.info.objective);
  EXPECT_LE(rb.info.dual_objective, ra.info.objective * (1.0 + 1e-12));
  EXPECT_LE(ra.info.dual_objective, rb.info.objective * (1.0 + 1e-12));
  EXPECT_NEAR(b.objective_of(rb.Y), rb.info.objective, 1e-12 * rb.info.objective);
  EXPECT_NE(b.control_scaling()(0), 1.0);
  EXPECT_EQ(b.problem().dynamics.B[0], q.dynamics.B[0]);  // problem() is as given
}

TEST(AdmmHonest, NewPathsDoNotAllocate) {
  AdmmSettings st;
  st.time_limit = 10.0;
  AdmmSolver a(false_solved_problem(), st);
  AdmmSolver b(infeasible_problem(), st);
  LtvProblem qp = false_solved_problem();
  qp.R = MatrixXd::Identity(3, 3);
  qp.R(0, 1) = qp.R(1, 0) = 0.2;  // non-diagonal: part of R stays in the smooth part
  AdmmSolver c(qp, st);
  a.solve();
  b.solve();
  c.solve();
  g_mallocs = 0;
  g_count = true;
  const AdmmStatus sa = a.solve().info.status;
  const AdmmStatus sb = b.solve().info.status;
  const AdmmStatus sc = c.solve().info.status;
  g_count = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_EQ(sa, AdmmStatus::solved);
  EXPECT_EQ(sb, AdmmStatus::primal_infeasible);
  EXPECT_EQ(sc, AdmmStatus::solved);
}

// fuzz pass: dynamics whose states overflow (x_N(0) ~ 1e180, P ~ 1e360) ended numerical_error with
// a NaN objective and a NaN plan; now the zero plan (no finite iterate exists) with the residuals,
// the objective and the gap at +inf, never NaN
TEST(AdmmHonest, NumericalErrorReturnsAFinitePlanAndNoNan) {
  LtvProblem p;
  p.dynamics.A = {1e3 * MatrixXd::Identity(6, 6)};
  MatrixXd B = MatrixXd::Zero(6, 3);
  B.bottomRows(3).setIdentity();
  p.dynamics.B = {B};
  p.dynamics.horizon = 60;
  p.x0 = VectorXd::Ones(6);
  p.Qf = MatrixXd::Identity(6, 6);
  p.l1_weights = VectorXd::Ones(3);
  for (const auto method : {satgnc::guidance::AdmmMethod::kAdmmIpm, satgnc::guidance::AdmmMethod::kAdmm,
                            satgnc::guidance::AdmmMethod::kIpm}) {
    SCOPED_TRACE(static_cast<int>(method));
    AdmmSettings s;
    s.method = method;
    AdmmSolver solver(p, s);
    const AdmmResult& r = solver.solve();
    EXPECT_EQ(r.info.status, AdmmStatus::numerical_error);
    EXPECT_TRUE(r.Y.allFinite());
    EXPECT_TRUE(r.U.allFinite());
    EXPECT_TRUE(r.Lambda.allFinite());
    EXPECT_EQ(r.Y.cwiseAbs().maxCoeff(), 0.0);
    EXPECT_FALSE(std::isnan(r.info.objective));
    EXPECT_EQ(r.info.objective, std::numeric_limits<double>::infinity());
    EXPECT_EQ(r.info.duality_gap, std::numeric_limits<double>::infinity());
    EXPECT_EQ(r.info.primal_residual, std::numeric_limits<double>::infinity());
    EXPECT_FALSE(std::isnan(r.info.dual_objective));
    EXPECT_FALSE(std::isnan(r.info.terminal_miss));
  }
}
