// Finite-horizon Gramians: Van Loan vs direct quadrature and closed forms, duality, LTV sums,
// minimum energy, bad input.
#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "satgnc/analysis/gramian.hpp"
#include "satgnc/analysis/linearize.hpp"
#include "satgnc/dynamics/polar.hpp"
#include "testing.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using namespace satgnc::analysis;  // test TU only

namespace {
// Composite Simpson with n (even) panels of e^{A t} Q e^{A^T t}.
MatrixXd simpson(const MatrixXd& A, const MatrixXd& Q, double T, int n) {
  MatrixXd W = MatrixXd::Zero(A.rows(), A.rows());
  const double h = T / n;
  for (int i = 0; i <= n; ++i) {
    const MatrixXd E = expm(A * (i * h));
    const double c = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    W += c * E * Q * E.transpose();
  }
  return W * h / 3.0;
}
}  // namespace

TEST(Gramian, DoubleIntegratorClosedForm) {
  MatrixXd A(2, 2), B(2, 1);
  A << 0, 1, 0, 0;
  B << 0, 1;
  for (double T : {0.1, 1.0, 300.0}) {
    MatrixXd W(2, 2);
    W << T * T * T / 3, T * T / 2, T * T / 2, T;
    const auto g = controllability_gramian(A, B, T);
    SATGNC_EXPECT_REL(g.W, W, 1e-12);
    // Minimum energy to reach (1, 0): x^T W^-1 x = 12 / T^3.
    SATGNC_EXPECT_REL(minimum_energy(g, VectorXd::Unit(2, 0)), 12.0 / (T * T * T), 1e-10);
    EXPECT_NEAR(g.condition, g.eigenvalues(1) / g.eigenvalues(0), 1e-9 * g.condition);
  }
}

TEST(Gramian, VanLoanMatchesQuadratureOnOrbitalModels) {
  const double mu = 398600.4418, s = 6778.137, w = std::sqrt(mu / (s * s * s));
  const satgnc::dynamics::PolarModel m(s, w);
  const MatrixXd A = m.A(), B = m.B();
  const double T = 2 * M_PI / w;  // one orbit
  const auto g = controllability_gramian(A, B, T);
  SATGNC_EXPECT_REL(g.W, simpson(A, B * B.transpose(), T, 2000), 1e-10);  // Simpson error ~h^4
  MatrixXd C = MatrixXd::Zero(1, 4);
  C(0, 2) = 1;
  const auto o = observability_gramian(A, C, T);
  SATGNC_EXPECT_REL(o.W, simpson(A.transpose(), C.transpose() * C, T, 2000), 1e-10);
  // Duality: W_o(A, C) = W_c(A^T, C^T).
  SATGNC_EXPECT_REL(o.W, controllability_gramian(A.transpose(), C.transpose(), T).W, 1e-12);
  // CW out-of-plane only: z, z' controllable, in-plane not: rank-2 Gramian (condition inf-like).
  const auto cw = cw_model(w);
  const auto gz = controllability_gramian(cw.A, cw.B.col(2), T);
  EXPECT_LE(gz.eigenvalues(3) / gz.eigenvalues(5), 1e-14);
  EXPECT_GT(gz.eigenvalues(4) / gz.eigenvalues(5), 1e-9);
  EXPECT_EQ(minimum_energy(gz, VectorXd::Unit(6, 0)), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isfinite(minimum_energy(gz, VectorXd::Unit(6, 2))));
}

TEST(Gramian, TangentialOnlyPolarIsControllableButIllConditioned) {
  const double mu = 398600.4418, s = 42164.17, w = std::sqrt(mu / (s * s * s));
  const satgnc::dynamics::PolarModel m(s, w);
  const auto g = controllability_gramian(m.A(), m.B().col(1), 2 * M_PI / w);
  EXPECT_GT(g.eigenvalues(0), 0.0);
  EXPECT_GT(g.condition, 1e6);  // units mix km and km/s over a day-long horizon
  // Radial only: not controllable. Radial thrust cannot change the angular momentum r^2 theta', whose
  // linearization is 2 omega x1 + x4: the Gramian is singular exactly along (2 omega, 0, 0, 1).
  const auto gr = controllability_gramian(m.A(), m.B().col(0), 2 * M_PI / w);
  Eigen::Vector4d h(2 * w, 0, 0, 1);
  EXPECT_GT(std::abs(gr.weakest.dot(h.normalized())), 1 - 1e-9);
  EXPECT_LE(gr.eigenvalues(0), 1e-12 * gr.eigenvalues(3));
}

TEST(Gramian, LtvSumEqualsLtiIntegralForConstantSystem) {
  const auto cw = cw_model(1.1e-3);
  const double T = 600.0;
  const int N = 600;  // trapezoid
  std::vector<MatrixXd> stms, H;
  std::vector<double> wts;
  for (int i = 0; i <= N; ++i) {
    stms.push_back(expm(cw.A * (T * i / N)));
    H.push_back(cw.C.topRows(1));
    wts.push_back((i == 0 || i == N ? 0.5 : 1.0) * T / N);
  }
  const auto ltv = ltv_observability_gramian(stms, H, wts);
  const auto lti = observability_gramian(cw.A, cw.C.topRows(1), T);
  SATGNC_EXPECT_REL(ltv.W, lti.W, 1e-5);  // trapezoid O(h^2)
}

TEST(Gramian, BadInputThrows) {
  const MatrixXd A = MatrixXd::Identity(2, 2), B = MatrixXd::Ones(2, 1);
  EXPECT_THROW(controllability_gramian(A, B, 0.0), std::invalid_argument);
  EXPECT_THROW(controllability_gramian(A, B, -1.0), std::invalid_argument);
  EXPECT_THROW(controllability_gramian(MatrixXd::Ones(2, 3), B, 1.0), std::invalid_argument);
  EXPECT_THROW(controllability_gramian(A, MatrixXd::Ones(3, 1), 1.0), std::invalid_argument);
  EXPECT_THROW(observability_gramian(A, MatrixXd::Ones(1, 3), 1.0), std::invalid_argument);
  MatrixXd An = A;
  An(0, 0) = NAN;
  EXPECT_THROW(observability_gramian(An, MatrixXd::Ones(1, 2), 1.0), std::invalid_argument);
  EXPECT_THROW(ltv_observability_gramian({}, {}), std::invalid_argument);
  EXPECT_THROW(ltv_observability_gramian({A}, {}), std::invalid_argument);
  EXPECT_THROW(ltv_observability_gramian({A}, {MatrixXd::Ones(1, 3)}), std::invalid_argument);
  EXPECT_THROW(ltv_observability_gramian({A}, {MatrixXd::Ones(1, 2)}, {-1.0}), std::invalid_argument);
  MatrixXd W(2, 2);
  W << 1, 2, 0, 1;
  EXPECT_THROW(analyze_gramian(W), std::invalid_argument);
  EXPECT_THROW(minimum_energy(analyze_gramian(MatrixXd::Identity(2, 2)), VectorXd::Ones(3)),
               std::invalid_argument);
}

TEST(Gramian, HugeHorizonOfUnstableModelIsAnErrorNamingT) {
  MatrixXd A(2, 2);
  A << 1.0, 0.0, 0.0, -1.0;
  const MatrixXd B = MatrixXd::Ones(2, 1);
  for (double T : {1e3, 1e6}) {
    try {
      controllability_gramian(A, B, T);
      ADD_FAILURE() << "T = " << T << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind("T: ", 0), 0u) << e.what();
    }
  }
  // A moderate horizon of the same model is a valid PSD Gramian.
  const auto g = controllability_gramian(A, B, 5.0);
  EXPECT_GE(g.eigenvalues(0), 0.0);
}

TEST(Gramian, LongHorizonOfUnstableModelReportsItsRoundingFloor) {
  // Random unstable 5x5 over T = 50: Van Loan's product cancels; the small eigenvalues are noise.
  MatrixXd A(3, 3);
  A << 0.9, 1.0, 0.0, -0.3, 0.8, 2.0, 0.1, 0.0, -0.5;
  const MatrixXd B = MatrixXd::Ones(3, 1);
  const auto g = controllability_gramian(A, B, 50.0);
  EXPECT_GT(g.rounding_floor, 0.0);
  EXPECT_GE(g.eigenvalues(0), -g.rounding_floor);
  EXPECT_EQ(g.resolved, g.eigenvalues(0) > g.rounding_floor);
  // A short horizon of a stable model is resolved to rounding.
  const auto s = controllability_gramian(-MatrixXd::Identity(3, 3), MatrixXd::Identity(3, 3), 1.0);
  EXPECT_TRUE(s.resolved);
  EXPECT_LT(s.rounding_floor, 1e-12 * s.eigenvalues(2));
}
