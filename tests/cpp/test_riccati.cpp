// Riccati step: cached-gain sweep and full recursion against a dense condensed KKT solve, with and
// without the exact terminal constraint, time-varying and time-invariant, fixed-size (6, 3) path.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "satgnc/guidance/riccati.hpp"
#include "testing.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using satgnc::guidance::LtvDynamics;
using satgnc::guidance::RiccatiSolver;
using satgnc::guidance::RiccatiStatus;

namespace {
struct Case {
  LtvDynamics dyn;
  MatrixXd Q, R, Qf, q, r;
  VectorXd x0, xf;
};

Case make_case(int nx, int nu, int N, bool tv, unsigned seed) {
  std::mt19937 g(seed);
  std::normal_distribution<double> nd;
  auto rnd = [&](int r, int c) { return MatrixXd(MatrixXd::NullaryExpr(r, c, [&]() { return nd(g); })); };
  Case cs;
  const int copies = tv ? N : 1;
  for (int k = 0; k < copies; ++k) {
    cs.dyn.A.push_back(MatrixXd::Identity(nx, nx) + 0.2 * rnd(nx, nx));
    cs.dyn.B.push_back(rnd(nx, nu));
    cs.dyn.c.push_back(0.1 * rnd(nx, 1));
  }
  cs.dyn.horizon = N;
  MatrixXd M = rnd(nx, nx);
  cs.Q = 0.1 * M * M.transpose();
  cs.R = 0.01 * MatrixXd::Identity(nu, nu);
  M = rnd(nx, nx);
  cs.Qf = M * M.transpose() + MatrixXd::Identity(nx, nx);
  cs.q = rnd(nx, N + 1);
  cs.r = rnd(nu, N);
  cs.x0 = rnd(nx, 1);
  cs.xf = rnd(nx, 1);
  return cs;
}

// Dense reference: condense x = Sx x0 + Su u + s, minimise, with optional terminal equality.
void dense_solve(const Case& cs, double rho, bool terminal, MatrixXd& X, MatrixXd& U) {
  const int nx = cs.dyn.nx(), nu = cs.dyn.nu(), N = cs.dyn.horizon;
  MatrixXd Su = MatrixXd::Zero(nx * (N + 1), nu * N);
  VectorXd s0 = VectorXd::Zero(nx * (N + 1));
  s0.head(nx) = cs.x0;
  for (int k = 0; k < N; ++k) {
    const MatrixXd& A = cs.dyn.A_at(k);
    const MatrixXd& B = cs.dyn.B_at(k);
    const VectorXd& c = cs.dyn.c.size() == 1 ? cs.dyn.c[0] : cs.dyn.c[k];
    Su.middleRows((k + 1) * nx, nx) = A * Su.middleRows(k * nx, nx);
    Su.block((k + 1) * nx, k * nu, nx, nu) += B;
    s0.segment((k + 1) * nx, nx) = A * s0.segment(k * nx, nx) + c;
  }
  MatrixXd Qb = MatrixXd::Zero(nx * (N + 1), nx * (N + 1));
  for (int k = 1; k < N; ++k) Qb.block(k * nx, k * nx, nx, nx) = cs.Q;
  if (!terminal) Qb.block(N * nx, N * nx, nx, nx) = cs.Qf;
  VectorXd qb = Eigen::Map<const VectorXd>(cs.q.data(), nx * (N + 1));
  if (terminal) qb.tail(nx).setZero();
  qb.head(nx).setZero();  // x0 fixed
  MatrixXd Rb = MatrixXd::Zero(nu * N, nu * N);
  for (int k = 0; k < N; ++k) Rb.block(k * nu, k * nu, nu, nu) = cs.R + rho * MatrixXd::Identity(nu, nu);
  const VectorXd rb = Eigen::Map<const VectorXd>(cs.r.data(), nu * N);
  MatrixXd H = Su.transpose() * Qb * Su + Rb;
  VectorXd gr = Su.transpose() * (Qb * s0 + qb) + rb;
  VectorXd u;
  if (terminal) {
    const MatrixXd E = Su.bottomRows(nx);
    const VectorXd e = cs.xf - s0.tail(nx);
    MatrixXd K = MatrixXd::Zero(nu * N + nx, nu * N + nx);
    K.topLeftCorner(nu * N, nu * N) = H;
    K.topRightCorner(nu * N, nx) = E.transpose();
    K.bottomLeftCorner(nx, nu * N) = E;
    VectorXd rhs(nu * N + nx);
    rhs << -gr, e;
    u = K.fullPivLu().solve(rhs).head(nu * N);
  } else {
    u = H.llt().solve(-gr);
  }
  U = Eigen::Map<const MatrixXd>(u.data(), nu, N);
  const VectorXd x = Su * u + s0;
  X = Eigen::Map<const MatrixXd>(x.data(), nx, N + 1);
}
}  // namespace

class RiccatiDense : public ::testing::TestWithParam<std::tuple<int, int, int, bool, bool>> {};

TEST_P(RiccatiDense, MatchesCondensedKkt) {
  const auto [nx, nu, N, tv, terminal] = GetParam();
  const Case cs = make_case(nx, nu, N, tv, 7u + nx * 13 + nu * 7 + N);
  RiccatiSolver ric({cs.dyn, cs.Q, cs.R, cs.Qf, terminal});
  const double rho = 0.7;
  ASSERT_TRUE(ric.factor(rho));
  MatrixXd X(nx, N + 1), U(nu, N), Xf(nx, N + 1), Uf(nu, N), Xd, Ud;
  ASSERT_EQ(ric.solve(cs.x0, cs.q, cs.r, cs.xf, X, U), RiccatiStatus::solved);
  ASSERT_EQ(ric.solve_full(rho, cs.x0, cs.q, cs.r, cs.xf, Xf, Uf), RiccatiStatus::solved);
  dense_solve(cs, rho, terminal, Xd, Ud);
  SATGNC_EXPECT_REL(U, Ud, 1e-9);
  SATGNC_EXPECT_REL(X, Xd, 1e-9);
  SATGNC_EXPECT_REL(Uf, U, 1e-10);
  if (terminal) EXPECT_LE((X.col(N) - cs.xf).norm(), 1e-10 * (1.0 + cs.xf.norm()));
}

INSTANTIATE_TEST_SUITE_P(
    Sizes, RiccatiDense,
    ::testing::Values(std::make_tuple(2, 1, 5, false, false), std::make_tuple(4, 2, 12, true, false),
                      std::make_tuple(4, 2, 12, true, true), std::make_tuple(6, 3, 10, false, false),
                      std::make_tuple(6, 3, 20, true, true), std::make_tuple(8, 3, 15, true, true)));

TEST(Riccati, UnreachableTerminalIsStatusNotNan) {
  // x2 is not actuated and has no dynamics: x_N(2) = x0(2) != xf(2)
  LtvDynamics d;
  MatrixXd A = MatrixXd::Identity(3, 3);
  A(0, 1) = 1.0;
  MatrixXd B = MatrixXd::Zero(3, 1);
  B(1, 0) = 1.0;
  d.A = {A};
  d.B = {B};
  d.horizon = 6;
  RiccatiSolver ric({d, MatrixXd(), MatrixXd(), MatrixXd::Identity(3, 3), true});
  ASSERT_TRUE(ric.factor(1.0));
  EXPECT_EQ(ric.terminal_rank(), 2);
  MatrixXd X(3, 7), U(1, 6);
  VectorXd x0 = VectorXd::Zero(3), xf(3);
  xf << 1.0, 0.0, 2.0;
  EXPECT_EQ(ric.solve(x0, MatrixXd::Zero(3, 7), MatrixXd::Zero(1, 6), xf, X, U),
            RiccatiStatus::terminal_unreachable);
  EXPECT_TRUE(X.allFinite());
  EXPECT_TRUE(U.allFinite());
  // reachable components are still met by the least-squares multiplier
  EXPECT_NEAR(X(0, 6), 1.0, 1e-10);
  // and a reachable target in the same subspace is solved
  xf(2) = 0.0;
  EXPECT_EQ(ric.solve(x0, MatrixXd::Zero(3, 7), MatrixXd::Zero(1, 6), xf, X, U), RiccatiStatus::solved);
  EXPECT_NEAR((X.col(6) - xf).norm(), 0.0, 1e-10);
}

TEST(Riccati, BadInput) {
  Case cs = make_case(3, 2, 4, false, 1u);
  LtvDynamics bad = cs.dyn;
  bad.B[0] = MatrixXd::Zero(2, 2);
  EXPECT_THROW((RiccatiSolver({bad, cs.Q, cs.R, cs.Qf, false})), std::invalid_argument);
  bad = cs.dyn;
  bad.A[0](0, 0) = std::nan("");
  EXPECT_THROW((RiccatiSolver({bad, cs.Q, cs.R, cs.Qf, false})), std::invalid_argument);
  MatrixXd negQf = -cs.Qf;
  EXPECT_THROW((RiccatiSolver({cs.dyn, cs.Q, cs.R, negQf, false})), std::invalid_argument);
  bad = cs.dyn;
  bad.horizon = 0;
  EXPECT_THROW((RiccatiSolver({bad, cs.Q, cs.R, cs.Qf, false})), std::invalid_argument);
  RiccatiSolver ric({cs.dyn, cs.Q, MatrixXd(), cs.Qf, false});
  EXPECT_FALSE(ric.factor(-1.0));
  MatrixXd X(3, 5), U(2, 4);
  EXPECT_EQ(ric.solve(cs.x0, cs.q, cs.r, cs.xf, X, U), RiccatiStatus::unsolved);
}

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif
TEST(Riccati, DeprecatedTwoStepSetupStillWorks) {
  const Case cs = make_case(4, 2, 6, false, 3u);
  RiccatiSolver old_style;
  old_style.setup(cs.dyn, cs.Q, cs.R, cs.Qf, true);
  RiccatiSolver new_style({cs.dyn, cs.Q, cs.R, cs.Qf, true});
  ASSERT_TRUE(old_style.factor(0.5));
  ASSERT_TRUE(new_style.factor(0.5));
  MatrixXd X1(4, 7), U1(2, 6), X2(4, 7), U2(2, 6);
  EXPECT_EQ(old_style.solve(cs.x0, cs.q, cs.r, cs.xf, X1, U1), RiccatiStatus::solved);
  EXPECT_EQ(new_style.solve(cs.x0, cs.q, cs.r, cs.xf, X2, U2), RiccatiStatus::solved);
  EXPECT_EQ((U1 - U2).norm(), 0.0);  // same code path, same numbers
  EXPECT_EQ((X1 - X2).norm(), 0.0);
}
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

// The named workspace (issue 12): sized once by the constructor for (nx, nu, N), then only written.
TEST(Riccati, WorkspaceIsSizedAtSetupAndHoldsTheFactorization) {
  LtvDynamics d;
  d.A = {MatrixXd::Identity(3, 3)};
  d.B = {MatrixXd::Identity(3, 2)};
  d.horizon = 5;
  const MatrixXd Qf = 2.0 * MatrixXd::Identity(3, 3);
  RiccatiSolver ric({d, MatrixXd(), MatrixXd(), Qf, true});
  const auto& ws = ric.workspace();
  EXPECT_EQ(ws.P.rows(), 3);
  EXPECT_EQ(ws.P.cols(), 3 * 6);  // P_0..P_N side by side
  EXPECT_EQ(ws.K.rows(), 2);
  EXPECT_EQ(ws.K.cols(), 3 * 5);
  EXPECT_EQ(ws.Z.cols(), 3 * 6);  // terminal responses exist with the terminal constraint
  const double* p_before = ws.P.data();
  ASSERT_TRUE(ric.factor(1.0));
  EXPECT_EQ(ws.P.data(), p_before);               // no reallocation by factor()
  EXPECT_TRUE(ws.P.rightCols(3).isZero(0.0));     // P_N: x_N = x_f makes the terminal cost constant
  EXPECT_EQ(&ric.terminal_sensitivity(), &ws.S);  // the accessors read the workspace
  EXPECT_EQ(&ric.terminal_multiplier(), &ws.nu_term);
}
