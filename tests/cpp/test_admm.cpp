// ADMM L1 guidance: paper reproduction (43 iterations), allocation-free solve, cached-gain vs full
// Riccati iterates, statuses (unreachable terminal state, max iterations), warm start, bad input.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>
#include <random>

#include "admm_fixture.hpp"
#include "malloc_counter.hpp"
#include "satgnc/guidance/admm.hpp"
#include "testing.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using namespace satgnc::guidance;
using satgnc_test::admm_scenario;
using satgnc_test::admm_scenario_problem;
using satgnc_test::random_ltv_problem;

namespace {
AdmmSettings paper_settings(double rho, double eps) {
  AdmmSettings st;
  st.rho = rho;
  st.stopping = StoppingRule::kPaper;
  st.paper_eps = eps;
  st.relaxation = 1.0;
  st.adaptive_rho = false;
  st.paper_multiplier_rescale = true;
  return st;
}

}  // namespace

TEST(AdmmPaper, UnconstrainedStopsAfter43Iterations) {
  // Table 1, linear unconstrained: 86 LQR passes = 43 ADMM iterations (one rollout pass each),
  // rho = 1e-2, eps = 4.5e-3: an exact integer, so exact equality.
  AdmmSolver s(admm_scenario_problem(false, false), paper_settings(1e-2, 4.5e-3));
  const AdmmResult& r = s.solve();
  EXPECT_EQ(r.info.status, AdmmStatus::solved_paper_rule);
  EXPECT_EQ(r.info.iterations, 43);
  EXPECT_EQ(2 * r.info.iterations, 86);
  // flying the sparse iterate Y at that point misses the target by kilometres
  const double miss_m = r.info.terminal_miss * admm_scenario().l_ref;
  EXPECT_GT(miss_m, 5000.0);
}

TEST(AdmmPaper, WithoutRescaleTheRuleNeedsMoreIterations) {
  AdmmSettings st = paper_settings(1e-2, 4.5e-3);
  st.paper_multiplier_rescale = false;
  AdmmSolver s(admm_scenario_problem(false, false), st);
  EXPECT_GT(s.solve().info.iterations, 43);
}

TEST(Admm, SolveDoesNotAllocate) {
  for (bool terminal : {false, true}) {
    AdmmSettings st;
    st.max_iterations = 300;  // includes adaptive-rho refactorizations
    st.adaptive_rho_interval = 10;
    st.rho = 50.0;      // far from where adaptation takes it: refactorizations certainly happen
    st.ipm_after = 35;  // ADMM long enough for rho updates and polishes before the endgame
    AdmmSolver s(admm_scenario_problem(true, terminal), st);
    s.solve();                                                            // warm-up (first-touch)
    AdmmSolver s2(random_ltv_problem(5, 2, 30, 3u, true, terminal), st);  // dynamic-size path
    g_mallocs = 0;
    g_count = true;
    const AdmmResult& r = s.solve();
    const AdmmResult& r2 = s2.solve();
    g_count = false;
    EXPECT_EQ(g_mallocs.load(), 0) << "terminal=" << terminal;
    EXPECT_GT(r.info.iterations + r2.info.iterations, 2);
    EXPECT_GT(r.info.polish_attempts + r2.info.polish_attempts, 0) << "polish path exercised";
    EXPECT_GT(r.info.rho_updates + r2.info.rho_updates, 0) << "refactorization path exercised";
  }
}

// Plain QP (R diagonal > 0, no L1 weight, no stage Q): the QP polish eliminates every free entry
// through an nx x nx system; certified, allocation-free, and equal to the dense normal-equation
// optimum where no bound is active.
TEST(Admm, QpPolishCertifiesWithoutAllocating) {
  for (bool box : {false, true}) {
    for (bool terminal : {false, true}) {
      LtvProblem p = admm_scenario_problem(box, terminal);
      p.l1_weights = VectorXd::Zero(3);
      p.R = Eigen::Vector3d(0.5, 1.0, 2.0).asDiagonal();
      AdmmSettings st;
      st.method = satgnc::guidance::AdmmMethod::kAdmm;  // the polish path (the IPM endgame would solve it)
      AdmmSolver s(p, st);
      s.solve();  // warm-up (first-touch)
      g_mallocs = 0;
      g_count = true;
      const AdmmResult& r = s.solve();
      g_count = false;
      EXPECT_EQ(g_mallocs.load(), 0) << "box=" << box << " terminal=" << terminal;
      EXPECT_EQ(r.info.status, AdmmStatus::solved) << "box=" << box << " terminal=" << terminal;
      EXPECT_TRUE(r.info.polished) << "box=" << box << " terminal=" << terminal;
      EXPECT_LE(std::abs(r.info.duality_gap), 1e-5);
      if (box) {
        EXPECT_LE(r.Y.cwiseAbs().maxCoeff(), p.u_upper(0) * (1 + 1e-12));
        continue;
      }
      // independent optimum: dense condensed QP, x_N = A^N x0 + sum_k A^(N-1-k) B u_k
      const int N = p.dynamics.horizon, n = 3 * N;
      const MatrixXd& A = p.dynamics.A[0];
      const MatrixXd& B = p.dynamics.B[0];
      MatrixXd M(6, n);
      MatrixXd P = MatrixXd::Identity(6, 6);
      for (int k = N - 1; k >= 0; --k) {
        M.middleCols(3 * k, 3) = P * B;
        P = P * A;
      }
      const VectorXd e = P * p.x0;
      VectorXd U(n);
      if (terminal) {  // min 1/2 U' R U s.t. M U + e = 0: U = -R^-1 M' (M R^-1 M')^-1 e
        const VectorXd rinv = p.R.diagonal().replicate(N, 1).cwiseInverse();
        const MatrixXd H = M * rinv.asDiagonal() * M.transpose();
        U = -(rinv.asDiagonal() * M.transpose() * H.ldlt().solve(e));
      } else {
        MatrixXd H = M.transpose() * p.Qf * M;
        H.diagonal() += p.R.diagonal().replicate(N, 1);
        U = -H.ldlt().solve(M.transpose() * p.Qf * e);
      }
      const MatrixXd Uref = Eigen::Map<const MatrixXd>(U.data(), 3, N);
      const double J = s.objective_of(Uref);
      EXPECT_LE(std::abs(r.info.objective - J), 1e-8 * std::abs(J)) << "terminal=" << terminal;
      EXPECT_LE((r.Y - Uref).cwiseAbs().maxCoeff(), 1e-6 * Uref.cwiseAbs().maxCoeff());
    }
  }
}

// The smoothed-dual Newton candidate (tried at iterations 50, 100, 200, ...) runs without allocation,
// whether it certifies (soft terminal: the paper's unconstrained case stops at iteration 50) or not.
TEST(Admm, DualNewtonPathDoesNotAllocate) {
  AdmmSettings st;
  st.method = satgnc::guidance::AdmmMethod::kAdmm;  // the polish path (the IPM endgame would solve it)
  for (bool terminal : {false, true}) {
    AdmmSolver s(admm_scenario_problem(true, terminal), st);
    AdmmSolver s0(admm_scenario_problem(false, false), st);
    s.solve();  // warm-up (first-touch)
    s0.solve();
    g_mallocs = 0;
    g_count = true;
    const AdmmResult& r = s.solve();
    const AdmmResult& r0 = s0.solve();
    g_count = false;
    EXPECT_EQ(g_mallocs.load(), 0) << "terminal=" << terminal;
    EXPECT_GE(r.info.iterations, 50) << "the dual Newton call at iteration 50 is reached";
    EXPECT_EQ(r0.info.status, AdmmStatus::solved);
    EXPECT_TRUE(r0.info.polished);
    EXPECT_EQ(r0.info.iterations, 50);
  }
}

TEST(Admm, CachedGainsMatchFullRiccatiIterateByIterate) {
  for (bool terminal : {false, true}) {
    const LtvProblem p =
        terminal ? admm_scenario_problem(true, true) : random_ltv_problem(4, 2, 25, 11u, true, false);
    for (int it = 1; it <= 40; ++it) {
      AdmmSettings st;
      st.rho = 0.5;
      st.adaptive_rho = false;
      st.max_iterations = it;
      st.track_best = false;
      st.eps_abs = 0.0;
      st.eps_rel = 1e-300;
      st.condensed = false;  // the cached-gain Riccati step itself (the condensed step has its own test)
      AdmmSolver a(p, st);
      st.cache_gains = false;
      AdmmSolver b(p, st);
      const AdmmResult& ra = a.solve();
      const AdmmResult& rb = b.solve();
      const double scale = std::max(1.0, ra.U.cwiseAbs().maxCoeff());
      EXPECT_LE((ra.U - rb.U).cwiseAbs().maxCoeff(), 1e-10 * scale) << "iteration " << it;
      EXPECT_LE((ra.Y - rb.Y).cwiseAbs().maxCoeff(), 1e-10 * scale) << "iteration " << it;
      EXPECT_LE((ra.Lambda - rb.Lambda).cwiseAbs().maxCoeff(),
                1e-10 * std::max(1.0, ra.Lambda.cwiseAbs().maxCoeff()));
    }
  }
}

TEST(Admm, CondensedStepMatchesRiccatiIterateByIterate) {
  // No stage state cost: the condensed step (x_N = x_N0 + M U, one nx x nx LU) and the cached-gain
  // Riccati step solve the same x/u subproblem, so every iterate agrees to rounding.
  LtvProblem rp = random_ltv_problem(4, 2, 25, 11u, true, false);
  rp.Q = MatrixXd();
  rp.R = Eigen::Vector2d(0.3, 0.05).asDiagonal();
  LtvProblem rpt = random_ltv_problem(4, 2, 25, 12u, false, true);
  rpt.Q = MatrixXd();
  for (const LtvProblem& p :
       {admm_scenario_problem(true, false), admm_scenario_problem(true, true), rp, rpt}) {
    for (int it : {1, 2, 7, 40, 120}) {
      AdmmSettings st;
      st.rho = 0.5;
      st.adaptive_rho_interval = 10;  // refactorizations at both sides within the budget
      st.polish = false;
      st.max_iterations = it;
      st.track_best = false;
      st.eps_abs = 0.0;
      st.eps_rel = 1e-300;
      AdmmSolver a(p, st);
      st.condensed = false;
      AdmmSolver b(p, st);
      const AdmmResult& ra = a.solve();
      const AdmmResult& rb = b.solve();
      ASSERT_TRUE(ra.info.condensed);
      ASSERT_FALSE(rb.info.condensed);
      EXPECT_EQ(ra.info.rho_updates, rb.info.rho_updates);
      const double su = std::max(1.0, ra.U.cwiseAbs().maxCoeff());
      const double sx = std::max(1.0, ra.X.cwiseAbs().maxCoeff());
      EXPECT_LE((ra.U - rb.U).cwiseAbs().maxCoeff(), 1e-10 * su) << "iteration " << it;
      EXPECT_LE((ra.Y - rb.Y).cwiseAbs().maxCoeff(), 1e-10 * su) << "iteration " << it;
      EXPECT_LE((ra.X - rb.X).cwiseAbs().maxCoeff(), 1e-10 * sx) << "iteration " << it;
      EXPECT_LE((ra.Lambda - rb.Lambda).cwiseAbs().maxCoeff(),
                1e-10 * std::max(1.0, ra.Lambda.cwiseAbs().maxCoeff()));
      EXPECT_LE((ra.terminal_multiplier - rb.terminal_multiplier).cwiseAbs().maxCoeff(),
                1e-9 * std::max(1.0, rb.terminal_multiplier.cwiseAbs().maxCoeff()))
          << "iteration " << it;
    }
  }
}

TEST(Admm, CondensedStepOnlyWhereItApplies) {
  AdmmSettings st;
  st.max_iterations = 5;
  EXPECT_TRUE(AdmmSolver(admm_scenario_problem(false, false), st).solve().info.condensed);
  // a stage state cost (Q != 0) needs the Riccati step
  EXPECT_FALSE(AdmmSolver(random_ltv_problem(4, 2, 10, 1u, true, false), st).solve().info.condensed);
  LtvProblem p = random_ltv_problem(4, 2, 10, 1u, true, false);
  p.Q = MatrixXd();
  p.R = (MatrixXd(2, 2) << 1.0, 0.2, 0.2, 1.0).finished();  // non-diagonal R
  EXPECT_FALSE(AdmmSolver(p, st).solve().info.condensed);
  st.condensed = false;
  EXPECT_FALSE(AdmmSolver(admm_scenario_problem(false, false), st).solve().info.condensed);
}

TEST(Admm, BoxAndTerminalAreSatisfied) {
  AdmmSolver s(admm_scenario_problem(true, true));
  const AdmmResult& r = s.solve();
  const double ub = 5e-3 / admm_scenario().u_ref;
  EXPECT_LE(r.Y.cwiseAbs().maxCoeff(), ub * (1 + 1e-15));
  EXPECT_LE((r.X.col(99)).norm(), 1e-9);                         // LQR iterate meets x_N = 0 exactly
  EXPECT_LT(r.info.terminal_miss * admm_scenario().l_ref, 5.0);  // flown Y: metres (reported)
}

TEST(Admm, MaxIterationsReturnsBestIterateAndResiduals) {
  AdmmSettings st;
  st.max_iterations = 5;
  AdmmSolver s(admm_scenario_problem(false, false), st);
  const AdmmResult& r = s.solve();
  EXPECT_EQ(r.info.status, AdmmStatus::max_iterations);
  EXPECT_EQ(r.info.iterations, 5);
  EXPECT_GT(r.info.primal_residual, 0.0);
  EXPECT_GT(r.info.dual_residual, 0.0);
  EXPECT_TRUE(r.Y.allFinite());
  EXPECT_TRUE(std::isfinite(r.info.objective));
  EXPECT_STREQ(status_message(r.info.status),
               "maximum iterations reached: best iterate returned, check the residuals");
}

TEST(Admm, UnreachableTerminalStateIsAStatus) {
  LtvProblem p;
  MatrixXd A = MatrixXd::Identity(3, 3);
  A(0, 1) = 0.1;
  MatrixXd B = MatrixXd::Zero(3, 1);
  B(1, 0) = 0.1;
  p.dynamics.A = {A};
  p.dynamics.B = {B};
  p.dynamics.horizon = 10;
  p.x0 = VectorXd::Zero(3);
  p.xf = VectorXd::Ones(3);  // x2 is neither actuated nor driven
  p.Qf = MatrixXd::Identity(3, 3);
  p.l1_weights = VectorXd::Ones(1);
  p.terminal_equality = true;
  AdmmSolver s(p);
  const AdmmResult& r = s.solve();
  EXPECT_EQ(r.info.status, AdmmStatus::terminal_unreachable);
  EXPECT_FALSE(r.info.condensed);  // the Riccati step reports the unreachable target
  EXPECT_TRUE(r.Y.allFinite());
  EXPECT_TRUE(r.X.allFinite());
  EXPECT_TRUE(std::isfinite(r.info.objective));
}

TEST(Admm, WarmStartFromSolutionConvergesQuickly) {
  AdmmSettings st;
  st.ipm_after = 35;  // the ADMM warm start (the default endgame at 8 ends both runs early)
  AdmmSolver s(random_ltv_problem(4, 2, 30, 5u, true, false), st);
  const AdmmResult& r = s.solve();
  ASSERT_EQ(r.info.status, AdmmStatus::solved);
  const int cold = r.info.iterations;
  const MatrixXd Y = r.Y, L = r.Lambda;
  s.warm_start(Y, L);
  const AdmmResult& r2 = s.solve();
  EXPECT_EQ(r2.info.status, AdmmStatus::solved);
  EXPECT_LT(r2.info.iterations, cold / 5 + 2);
}

TEST(Admm, BadInputThrowsWithHint) {
  const LtvProblem good = random_ltv_problem(3, 2, 5, 2u, true, false);
  auto expect_msg = [](const LtvProblem& p, const AdmmSettings& st, const std::string& key) {
    try {
      AdmmSolver s(p, st);
      ADD_FAILURE() << "no throw for " << key;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  AdmmSettings st;
  LtvProblem p = good;
  p.dynamics.B[2] = MatrixXd::Zero(3, 3);
  expect_msg(p, st, "B[2]");
  p = good;
  p.x0 = VectorXd::Zero(4);
  expect_msg(p, st, "x0");
  p = good;
  p.x0(1) = std::numeric_limits<double>::infinity();
  expect_msg(p, st, "x0");
  p = good;
  p.dynamics.A[1](0, 0) = std::nan("");
  expect_msg(p, st, "A[1]");
  p = good;
  p.l1_weights(0) = -1.0;
  expect_msg(p, st, "l1_weights");
  p = good;
  p.u_lower(1) = 1.0;
  expect_msg(p, st, "u_lower");
  p = good;
  p.group_l2_weight = 1.0;  // with a box: no exact prox
  expect_msg(p, st, "group_l2_weight");
  AdmmSettings bad = st;
  bad.rho = 0.0;
  expect_msg(good, bad, "rho");
  bad = st;
  bad.polish_swaps = -1;
  expect_msg(good, bad, "polish_swaps");
  bad = st;
  bad.rho = -1.0;
  expect_msg(good, bad, "rho");
  bad = st;
  bad.relaxation = 2.0;
  expect_msg(good, bad, "relaxation");
  AdmmSolver s(good, st);
  EXPECT_THROW(s.warm_start(MatrixXd::Zero(2, 4), MatrixXd::Zero(2, 5)), std::invalid_argument);
  EXPECT_THROW(s.set_x0(VectorXd::Zero(2)), std::invalid_argument);
}

TEST(Admm, GroupL2WithNormBound) {
  // one gimballed engine: the plan uses whole-vector burns with ||u|| <= u_norm_max
  LtvProblem p = random_ltv_problem(4, 2, 30, 9u, false, false);
  p.l1_weights.resize(0);
  p.group_l2_weight = 1.0;
  p.u_norm_max = 0.4;
  AdmmSolver s(p);
  const AdmmResult& r = s.solve();
  EXPECT_EQ(r.info.status, AdmmStatus::solved);
  for (int k = 0; k < 30; ++k) EXPECT_LE(r.Y.col(k).norm(), 0.4 * (1 + 1e-12));
}
