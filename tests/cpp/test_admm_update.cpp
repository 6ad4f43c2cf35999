// AdmmSolver::update_dynamics (guidance/admm.hpp): overwriting A_k, B_k, c_k in place and refactoring
// the cached Riccati gains gives the same result as a freshly built solver (1e-12), allocates
// nothing, and rejects mismatched data.
#include <Eigen/Dense>
#include <atomic>
#include <cstdlib>
#include <random>

#include "admm_fixture.hpp"
#include "malloc_counter.hpp"
#include "satgnc/guidance/admm.hpp"
#include "testing.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using namespace satgnc::guidance;

namespace {
// Time-varying problem (N entries of A, B, c) with L1 weights, optional box / terminal constraint.
LtvProblem tv_problem(int nx, int nu, int N, unsigned seed, bool box, bool terminal) {
  return satgnc_test::random_ltv_problem(nx, nu, N, seed, box, terminal, satgnc_test::LtvDraw::kTimeVarying);
}
}  // namespace

TEST(AdmmUpdateDynamics, SameResultAsAFreshSolver) {
  for (int variant = 0; variant < 3; ++variant) {
    const bool box = variant == 1, terminal = variant == 2;
    const LtvProblem p1 = tv_problem(6, 3, 25, 3u, box, terminal);
    const LtvProblem p2 = tv_problem(6, 3, 25, 17u, box, terminal);
    LtvProblem p2x = p2;
    p2x.x0 = p1.x0;  // only the dynamics change
    AdmmSettings st;
    st.max_iterations = 400;
    // update_dynamics keeps the setup's equilibration; a fresh solver would scale for p2
    st.equilibrate = false;
    // the endgame after ADMM's certificate (at the default ipm_after = 8 the box variant is certified
    // by the IPM, whose plan agrees with the fresh solver's to 2e-11, not 1e-12)
    st.ipm_after = 35;
    AdmmSolver updated(p1, st);
    updated.solve();
    ASSERT_TRUE(updated.update_dynamics(p2.dynamics.A, p2.dynamics.B, p2.dynamics.c));
    const AdmmResult r1 = updated.solve();
    AdmmSolver fresh(p2x, st);
    const AdmmResult& r2 = fresh.solve();
    EXPECT_EQ(r1.info.iterations, r2.info.iterations) << "variant " << variant;
    EXPECT_LE((r1.Y - r2.Y).cwiseAbs().maxCoeff(), 1e-12) << "variant " << variant;
    EXPECT_LE((r1.X - r2.X).cwiseAbs().maxCoeff(), 1e-12) << "variant " << variant;
    EXPECT_LE(std::abs(r1.info.objective - r2.info.objective),
              1e-12 * std::max(1.0, std::abs(r2.info.objective)));
  }
}

TEST(AdmmUpdateDynamics, EquilibratedSolverReachesTheSameOptimum) {
  // with equilibration the updated solver keeps its scaling: other iterates, the same optimum
  const LtvProblem p1 = tv_problem(6, 3, 25, 3u, false, false);
  const LtvProblem p2 = tv_problem(6, 3, 25, 17u, false, false);
  LtvProblem p2x = p2;
  p2x.x0 = p1.x0;
  AdmmSolver updated(p1);
  updated.solve();
  ASSERT_TRUE(updated.update_dynamics(p2.dynamics.A, p2.dynamics.B, p2.dynamics.c));
  const AdmmResult r1 = updated.solve();
  AdmmSolver fresh(p2x);
  const AdmmResult& r2 = fresh.solve();
  ASSERT_EQ(r1.info.status, AdmmStatus::solved);
  ASSERT_EQ(r2.info.status, AdmmStatus::solved);
  EXPECT_LE(std::abs(r1.info.objective - r2.info.objective), 2e-5 * std::abs(r2.info.objective));
}

TEST(AdmmUpdateDynamics, DoesNotAllocate) {
  const LtvProblem p1 = tv_problem(12, 3, 40, 5u, true, false);
  const LtvProblem p2 = tv_problem(12, 3, 40, 6u, true, false);
  AdmmSolver s(p1);
  s.solve();
  g_mallocs = 0;
  g_count = true;
  const bool ok = s.update_dynamics(p2.dynamics.A, p2.dynamics.B, p2.dynamics.c);
  s.solve();
  g_count = false;
  EXPECT_TRUE(ok);
  EXPECT_EQ(g_mallocs.load(), 0);
}

TEST(AdmmUpdateDynamics, RejectsMismatchedData) {
  const LtvProblem p = tv_problem(4, 2, 10, 1u, false, false);
  AdmmSolver s(p);
  std::vector<MatrixXd> A = p.dynamics.A, B = p.dynamics.B;
  std::vector<VectorXd> c = p.dynamics.c;
  EXPECT_FALSE(s.update_dynamics({A[0]}, B, c));  // wrong count
  EXPECT_FALSE(s.update_dynamics(A, B, {}));      // c dropped
  std::vector<MatrixXd> A5 = A;
  A5[3] = MatrixXd::Identity(5, 5);
  EXPECT_FALSE(s.update_dynamics(A5, B, c));  // wrong size
  std::vector<MatrixXd> An = A;
  An[2](0, 0) = std::nan("");
  EXPECT_FALSE(s.update_dynamics(An, B, c));  // non-finite
  // nothing changed: the solve equals a fresh one on the original data
  const AdmmResult r1 = s.solve();
  AdmmSolver fresh(p);
  EXPECT_LE((r1.Y - fresh.solve().Y).cwiseAbs().maxCoeff(), 1e-12);
  // time-invariant storage cannot be updated per stage
  LtvProblem ti = p;
  ti.dynamics.A = {A[0]};
  ti.dynamics.B = {B[0]};
  ti.dynamics.c = {};
  AdmmSolver s2(ti);
  EXPECT_FALSE(s2.update_dynamics({A[1]}, {B[1]}, {}));
}

TEST(AdmmUpdateDynamics, CwBlocksOfTheInteriorPointFollowTheUpdate) {
  // A CW problem (one A, one B) takes the IPM's in-plane / out-of-plane block path; update_dynamics
  // accepts an LTI problem only at N = 1 (one step: the step is its own time-varying sequence). The
  // update to another mean motion must reach the block copies too, or the endgame solves the old one.
  const satgnc_test::AdmmScenario s = satgnc_test::admm_scenario();
  LtvProblem p1 = satgnc_test::admm_scenario_problem(true, false);
  p1.dynamics.horizon = 1;
  const auto d2 = satgnc::dynamics::cw_discretize_midpoint(satgnc::dynamics::CwModel(1.5 * s.n, 1.0), s.dt);
  LtvProblem p2 = p1;
  p2.dynamics.A = {MatrixXd(d2.Ad)};
  p2.dynamics.B = {MatrixXd(d2.Bd)};
  AdmmSettings st;
  st.method = AdmmMethod::kIpm;  // the IPM alone, on its block copies
  st.equilibrate = false;
  // the plans are compared at 1e-6: run the IPM to 1e-9 (the default trigger 1e-7 certifies the gap,
  // not the plan: with the adaptive fraction to the boundary a box entry stopped 6e-4 inside its bound)
  st.ipm_tolerance = 1e-9;
  AdmmSolver updated(p1, st);
  const double obj1 = updated.solve().info.objective;
  ASSERT_TRUE(updated.update_dynamics(p2.dynamics.A, p2.dynamics.B, p2.dynamics.c));
  const AdmmResult r1 = updated.solve();
  AdmmSolver fresh(p2, st);
  const AdmmResult& r2 = fresh.solve();
  ASSERT_EQ(r2.info.status, AdmmStatus::solved);
  EXPECT_EQ(r1.info.status, AdmmStatus::solved);
  EXPECT_GT(r1.info.ipm_iterations, 0);
  EXPECT_GT(std::abs(obj1 - r2.info.objective), 1e-3 * std::abs(r2.info.objective));  // a real change
  // both certified to the default tolerances (eps_gap 1e-4 relative): the same optimum
  EXPECT_LE(std::abs(r1.info.objective - r2.info.objective), 1e-6 * std::abs(r2.info.objective));
  EXPECT_LE((r1.X - r2.X).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, r2.X.cwiseAbs().maxCoeff()));
}
