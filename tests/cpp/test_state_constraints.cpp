// State-constrained L1 ADMM (guidance/state_constraints.hpp): no allocation in solve() and in
// set_half_space(), the polish certificate on a CW plan with an active half-space, and setup errors
// naming the field. The Clarabel comparisons are in tests/python/test_l1_state_constraints.py.
#include <gtest/gtest.h>
#include <malloc.h>

#include <cmath>
#include <limits>
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

namespace {
// the CW problem with x_N = 0 and |u| <= 0.05 per axis
LtvProblem boxed_terminal_problem(int N) {
  auto p = cw_problem(N);
  p.terminal_equality = true;
  p.xf = Eigen::VectorXd::Zero(6);
  p.u_lower = Eigen::VectorXd::Constant(3, -0.05);
  p.u_upper = Eigen::VectorXd::Constant(3, 0.05);
  return p;
}
}  // namespace

TEST(StateAdmm, InteriorPointCertifiesWithTerminalState) {
  // hard terminal state (equality rows at node N through their multipliers), a cone and
  // half-spaces: the IPM alone ends `solved` by the independent violation and gap tests
  const int N = 30;
  const auto p = boxed_terminal_problem(N);
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
  const auto p = boxed_terminal_problem(N);
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

TEST(StateAdmm, SetupMemoryIsBoundedByThePolishActiveSet) {
  // the heap the constructor keeps (glibc's in-use bytes, mmapped blocks included) for the N = 100
  // cone bench with x_N = 0 (m = 306 rows, N nu = 300): the polish's two dense KKT matrices are sized
  // min(N nu, nx + m) + m = 606 (5.9 MB), no longer N nu + 4 m + nx = 1530 (37.5 MB; 39.7 MB in all)
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "ASan owns malloc: glibc's mallinfo2 does not see the engine's blocks";
#else
  const int N = 100;
  const auto p = cone_problem(N, 3);
  const auto c = approach_cone(N);
  const auto in_use = [] {
    const struct mallinfo2 mi = mallinfo2();
    return static_cast<double>(mi.uordblks + mi.hblkhd);
  };
  const double before = in_use();
  StateConstrainedAdmm s(p, c);
  const double bytes = in_use() - before;
  RecordProperty("setup_bytes", std::to_string(bytes));
  EXPECT_EQ(s.rows(), 306);
  EXPECT_GT(bytes, 6.0e6);  // the KKT pair alone is 5.9 MB: the measure sees the engine
  EXPECT_LT(bytes, 9.0e6);  // measured 8.07 MB (main before: 39.66 MB)
#endif
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

namespace {
// Two problems of the box + closing-velocity family of tests/python/test_l1_state_constraints.py (seed
// 2, cases 0 and 4; generated there, copied here with 17 digits): the IPM's plan converges but its
// multipliers do not certify it (degenerate active rows: a wedge pinned by box rows); the least-squares
// dual / the active-set polish of the IPM's plan then certify it (Clarabel: 12.210361083 for case 4)
struct BoxCase {
  double n, dt;
  int N;
  std::vector<double> x0;
  double qf;
  std::vector<double> w;
  double umax;
  std::vector<int> nodes;
  std::vector<double> lower, upper, axis, intercept, slope;
};
constexpr double kInf = std::numeric_limits<double>::infinity();
const BoxCase kBoxCases[] = {
    // box family seed 2, case 0
    BoxCase{
        0.0003092950149333078,
        49.84911434141233,
        17,
        {63.414354203114854, 37.61325732609805, -16.77444097731593, -0.04886106011758275,
         -0.029090618503532784, 0.012263266066504696},
        0.6335512148748423,
        {2.9120770717329267, 2.1442750202359884, 1.3573870493160707},
        0.001716079543950025,
        {1, 4, 6, 9, 10, 12, 14},
        {-kInf,
         29.456074462651923,
         -18.46766747068402,
         -0.05084192270004655,
         -0.03190165172954954,
         -kInf,
         -kInf,
         26.53571013365529,
         -16.346958628052498,
         -0.05310440817949979,
         -0.024627157163012482,
         -kInf,
         -kInf,
         25.00868188564678,
         -14.913519427654572,
         -0.05428743839375431,
         -0.019747352224447706,
         -kInf,
         -kInf,
         23.351590890863037,
         -12.737317648145183,
         -0.05557123174672921,
         -0.012394030230175022,
         -kInf,
         -kInf,
         22.968692907162577,
         -12.005661206977354,
         -0.05586787320328742,
         -0.00993628866259014,
         -kInf,
         -kInf,
         22.457671785429678,
         -10.534006960080239,
         -0.056263775131048535,
         -0.0050143583370780885,
         -kInf,
         -kInf,
         22.28672170142677,
         -9.052398009911386,
         -0.05639621479925279,
         -8.7732331178488e-05,
         -kInf},
        {kInf, 42.9722009516514,   -13.854649523235336, -0.04861116042886097,  -0.0221832504780531,   kInf,
         kInf, 38.72740399791512,  -12.250738301327427, -0.05078097228129259,  -0.01709551073223941,  kInf,
         kInf, 36.50784365366081,  -11.166615307532561, -0.05191554441622382,  -0.01368260316723003,  kInf,
         kInf, 34.09923499587098,  -9.520734277037164,  -0.05314675233276305,  -0.008539731970910396, kInf,
         kInf, 33.542686561600135, -8.967375912616848,  -0.05343124306395578,  -0.006820801625445502, kInf,
         kInf, 32.799909066583965, -7.854350534537241,  -0.053810928459976176, -0.003378431806595792, kInf,
         kInf, 32.55143034473017,  -6.733796324603239,  -0.05393794326931371,  6.722214416478196e-05, kInf},
        {0.8342389657617681, 0.5303683048214033, -0.15084697294147595},
        {-0.0023357443981592576, -0.016628737646266427},
        {0.001520910304483643, 0.0020042513701460994}},
    // box family seed 2, case 4
    BoxCase{8.177925496189832e-05,
            87.09043150358274,
            18,
            {-14.494094822438958, 4.9807431434483815, -86.82320374632623, 0.007595050730337501,
             -0.003543401385841011, 0.03986217402081568},
            0.5889023128864037,
            {1.9914844869966435, 2.1705477802632207, 2.7067297071027165},
            0.0012236778442549312,
            {3, 4, 5, 7, 8, 11, 13, 16, 17},
            {-kInf, -kInf, -kInf, -kInf, -0.004132041547663753, 0.03754943048036024,
             -kInf, -kInf, -kInf, -kInf, -0.004235993322870671, 0.03759033940842535,
             -kInf, -kInf, -kInf, -kInf, -0.004339734877253572, 0.037629336900502054,
             -kInf, -kInf, -kInf, -kInf, -0.004546566285156829, 0.0377015897610978,
             -kInf, -kInf, -kInf, -kInf, -0.00464964564707448,  0.0377348414645627,
             -kInf, -kInf, -kInf, -kInf, -0.004957475655786998, 0.03782307771940235,
             -kInf, -kInf, -kInf, -kInf, -0.005161470245427832, 0.03787228816733012,
             -kInf, -kInf, -kInf, -kInf, -0.005465520531747068, 0.037931658294844586,
             -kInf, -kInf, -kInf, -kInf, -0.005566332290303364, 0.03794759207901779},
            {kInf, kInf, kInf, kInf, -0.0035500006063068227, 0.042460116590666085,
             kInf, kInf, kInf, kInf, -0.003643696009857529,  0.042506163199821353,
             kInf, kInf, kInf, kInf, -0.003737201933960657,  0.04255005831906853,
             kInf, kInf, kInf, kInf, -0.003923626381180359,  0.04263138529069946,
             kInf, kInf, kInf, kInf, -0.004016535447845157,  0.04266881301774131,
             kInf, kInf, kInf, kInf, -0.004293993498310633,  0.04276813071028656,
             kInf, kInf, kInf, kInf, -0.004477861021116409,  0.042823521412738604,
             kInf, kInf, kInf, kInf, -0.004751912274398832,  0.042890347731257786,
             kInf, kInf, kInf, kInf, -0.004842777470128168,  0.04290828261165896},
            {-0.23322739993548205, 0.21454400480362132, -0.9484597249868644},
            {0.02228045976121695, 0.013346148733758056},
            {0.0008306862112396915, 0.001214209062654839}},
};

// nu = 4: a fourth thruster with a zero column of B (its control stays 0, the optimum is the same) runs
// the IPM's dynamic-size path (factor_stages) instead of the (6, 3) kernels
StateConstrainedAdmm box_case(const BoxCase& c, const AdmmSettings& st, int nu = 3) {
  const satgnc::dynamics::CwModel model(c.n, 1.0);
  const auto d = satgnc::dynamics::cw_discretize_zoh(model, c.dt);
  LtvProblem p;
  p.dynamics.A = {Eigen::MatrixXd(d.Ad)};
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(6, nu);
  B.leftCols(3) = d.Bd;
  p.dynamics.B = {B};
  p.dynamics.horizon = c.N;
  p.x0 = Eigen::Map<const Eigen::VectorXd>(c.x0.data(), 6);
  p.Qf = c.qf * Eigen::MatrixXd::Identity(6, 6);
  p.l1_weights = Eigen::VectorXd::Ones(nu);
  p.l1_weights.head(3) = Eigen::Map<const Eigen::VectorXd>(c.w.data(), 3);
  p.u_lower = Eigen::VectorXd::Constant(nu, -c.umax);
  p.u_upper = Eigen::VectorXd::Constant(nu, c.umax);
  StateConstraints sc;
  for (std::size_t i = 0; i < c.nodes.size(); ++i)
    sc.boxes.push_back({{c.nodes[i]},
                        Eigen::Map<const Eigen::VectorXd>(c.lower.data() + 6 * i, 6),
                        Eigen::Map<const Eigen::VectorXd>(c.upper.data() + 6 * i, 6)});
  satgnc::guidance::ClosingVelocityLimit cv;
  for (int k = 1; k <= c.N; ++k) cv.nodes.push_back(k);
  cv.axis = Eigen::Map<const Eigen::Vector3d>(c.axis.data());
  cv.intercept = Eigen::Map<const Eigen::VectorXd>(c.intercept.data(), 2);
  cv.slope = Eigen::Map<const Eigen::VectorXd>(c.slope.data(), 2);
  sc.closing_velocity.push_back(cv);
  return StateConstrainedAdmm(p, sc, st);
}

// the tight tolerances of the Python family test, the IPM alone (no ADMM fallback)
AdmmSettings tight_ipm() {
  AdmmSettings st;
  st.method = satgnc::guidance::AdmmMethod::kIpm;
  st.eps_abs = 1e-10;
  st.eps_rel = 1e-8;
  st.eps_gap = 1e-8;
  return st;
}
}  // namespace

TEST(StateAdmm, DegenerateRowsCertifiedByTheIpmDualRecoveryWithoutAllocation) {
  // tight tolerances of the Python family test; method ipm alone (no ADMM fallback): both solved by
  // the interior-point method's plan, certified by the Fenchel gap, and nothing allocated in solve()
  // (the least-squares dual and the polish work in buffers sized at setup)
  for (const auto& c : kBoxCases) {
    const AdmmSettings st = tight_ipm();
    auto s = box_case(c, st);
    g_mallocs = 0;
    g_count = true;
    const auto& r = s.solve();
    g_count = false;
    EXPECT_EQ(g_mallocs.load(), 0);
    EXPECT_EQ(r.info.status, AdmmStatus::solved);
    EXPECT_TRUE(r.info.ipm_solved);
    EXPECT_LE(std::abs(r.info.duality_gap), 1e-8);
    EXPECT_LE(r.max_violation, r.violation_tolerance);
    EXPECT_TRUE(r.info.dual_recoveries > 0 || r.info.polished);
  }
  // case 4 against Clarabel's optimum 12.210361083170412 (run at 1e-10 tolerances): 1e-8 relative
  const AdmmSettings st = tight_ipm();
  auto s = box_case(kBoxCases[1], st);
  EXPECT_NEAR(s.solve().info.objective, 12.210361083170412, 1e-8 * 12.210361083170412);
}

TEST(StateAdmm, DegenerateRowsDynamicSizePathEqualsFixedSize) {
  // the same two degenerate box + closing-velocity cases through the dynamic-size IPM path (a fourth,
  // zero-column thruster): PSD Riccati form and the debiased row directions there too; certified by
  // the IPM alone, the objective of the (6, 3) path to 1e-8 relative, nothing allocated in solve()
  for (const auto& c : kBoxCases) {
    const AdmmSettings st = tight_ipm();
    auto s3 = box_case(c, st);
    auto s4 = box_case(c, st, 4);
    const double obj3 = s3.solve().info.objective;
    g_mallocs = 0;
    g_count = true;
    const auto& r = s4.solve();
    g_count = false;
    EXPECT_EQ(g_mallocs.load(), 0);
    EXPECT_EQ(r.info.status, AdmmStatus::solved);
    EXPECT_TRUE(r.info.ipm_solved);
    EXPECT_LE(std::abs(r.info.objective - obj3), 1e-8 * std::abs(obj3));
    EXPECT_EQ(r.Y.row(3).cwiseAbs().maxCoeff(), 0.0);
  }
}
