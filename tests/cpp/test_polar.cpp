// Polar model (paper eqs. 3-4), its circular reference, analytic linearization for general sigma, the
// generic linearizer against central finite differences, CW and two-body / range partials.
#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "satgnc/analysis/linearize.hpp"
#include "satgnc/dynamics/polar.hpp"
#include "testing.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using satgnc::analysis::cw_model;
using satgnc::analysis::fd_jacobian;
using satgnc::analysis::linearize;
using satgnc::dynamics::PolarCoordinates;
using satgnc::dynamics::PolarModel;

namespace {
constexpr double kMu = 398600.4418;
struct Orbit {
  double sigma, omega;
};
// omega = 1 (paper), LEO 400 km altitude, GEO (km, rad/s).
const Orbit kOrbits[] = {{1.0, 1.0},
                         {6778.137, std::sqrt(kMu / (6778.137 * 6778.137 * 6778.137))},
                         {42164.17, std::sqrt(kMu / (42164.17 * 42164.17 * 42164.17))}};

MatrixXd paper_A(double w) {
  MatrixXd A(4, 4);
  A << 0, 1, 0, 0, 3 * w * w, 0, 0, 2 * w, 0, 0, 0, 1, 0, -2 * w, 0, 0;
  return A;
}
}  // namespace

TEST(Polar, CircularReferenceIsASolution) {
  for (const Orbit& o : kOrbits) {
    const PolarModel m(o.sigma, o.omega);
    EXPECT_NEAR(m.k(), o.sigma * o.sigma * o.sigma * o.omega * o.omega, 1e-12 * m.k());
    for (double t : {0.0, 10.0, 1234.5}) {
      const PolarModel::State f = m.rhs(t, m.reference(t), PolarModel::Input::Zero());
      // r' = 0, r'' = 0 (to rounding of sigma omega^2), theta' = omega, theta'' = 0
      EXPECT_EQ(f(0), 0.0);
      EXPECT_LE(std::abs(f(1)), 4e-16 * o.sigma * o.omega * o.omega);
      EXPECT_EQ(f(2), o.omega);
      EXPECT_EQ(f(3), 0.0);
      EXPECT_LE(m.deviation_rhs(t, PolarModel::State::Zero(), PolarModel::Input::Zero()).norm(),
                4e-16 * o.sigma * o.omega * o.omega);
    }
  }
}

TEST(Polar, FromMuGivesKeplerRate) {
  const PolarModel m = PolarModel::from_mu(42164.17, kMu);
  SATGNC_EXPECT_REL(m.omega(), 7.2921e-5, 1e-4);  // sidereal rate, 5 digits
  SATGNC_EXPECT_REL(m.k(), kMu, 1e-14);
}

TEST(Polar, AnalyticJacobiansMatchCentralDifferencesOffReference) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (const Orbit& o : kOrbits) {
    const PolarModel m(o.sigma, o.omega);
    const satgnc::analysis::ModelFn f = [&](double t, const VectorXd& s, const VectorXd& u) {
      return VectorXd(m.rhs(t, s, u));
    };
    const satgnc::analysis::JacobianFn jac = [&](double t, const VectorXd& s, const VectorXd& u, MatrixXd& A,
                                                 MatrixXd& B) {
      PolarModel::MatA a;
      PolarModel::MatB b;
      m.jacobians(t, s, u, a, b);
      A = a;
      B = b;
    };
    for (int trial = 0; trial < 5; ++trial) {
      VectorXd s(4), u(2);
      s << o.sigma * (1 + 0.1 * U(rng)), 0.1 * o.sigma * o.omega * U(rng), U(rng),
          o.omega * (1 + 0.2 * U(rng));
      u << 0.01 * o.sigma * o.omega * o.omega * U(rng), 0.01 * o.sigma * o.omega * o.omega * U(rng);
      satgnc::analysis::FdSettings fd;
      fd.x_scale = (VectorXd(4) << o.sigma, o.sigma * o.omega, 1.0, o.omega).finished();
      fd.u_scale = VectorXd::Constant(2, o.sigma * o.omega * o.omega);
      const auto L = linearize(f, jac, 0.0, s, u, fd);
      EXPECT_LE(L.rel_err_A, 1e-8);  // central differences: O(h^2) ~ 1e-10 plus cancellation
      EXPECT_LE(L.rel_err_B, 1e-8);
    }
  }
}

TEST(Polar, LinearizationForGeneralSigmaEqualsDerivedMatrices) {
  for (const Orbit& o : kOrbits) {
    const PolarModel m(o.sigma, o.omega);
    // Derived (not copied): in the paper's scaled coordinates the sigma factors cancel exactly.
    SATGNC_EXPECT_REL(m.A(), paper_A(o.omega), 1e-15);
    MatrixXd Bp = MatrixXd::Zero(4, 2);
    Bp(1, 0) = 1;
    Bp(3, 1) = 1;
    SATGNC_EXPECT_REL(m.B(), Bp, 1e-15);
    // Raw coordinates keep sigma and are similar through T = diag(1, 1, sigma, sigma).
    const MatrixXd T = (VectorXd(4) << 1, 1, o.sigma, o.sigma).finished().asDiagonal();
    SATGNC_EXPECT_REL(MatrixXd(m.A(PolarCoordinates::raw)), MatrixXd(T.inverse() * m.A() * T), 1e-14);
    EXPECT_NEAR(m.A(PolarCoordinates::raw)(1, 3), 2 * o.sigma * o.omega, 1e-12 * o.sigma * o.omega);
    EXPECT_NEAR(m.B(PolarCoordinates::raw)(3, 1), 1.0 / o.sigma, 1e-15 / o.sigma);
    // Independent check: finite differences of the nonlinear deviation dynamics at x = 0, u = 0.
    for (PolarCoordinates c : {PolarCoordinates::scaled, PolarCoordinates::raw}) {
      const satgnc::analysis::ModelFn g = [&](double t, const VectorXd& x, const VectorXd& u) {
        return VectorXd(m.deviation_rhs(t, x, u, c));
      };
      MatrixXd Afd, Bfd;
      satgnc::analysis::FdSettings fd;
      const double a = c == PolarCoordinates::scaled ? o.sigma : 1.0;
      fd.x_scale = (VectorXd(4) << o.sigma, o.sigma * o.omega, a, a * o.omega).finished();
      fd.u_scale = VectorXd::Constant(2, o.sigma * o.omega * o.omega);
      fd_jacobian(g, 100.0, VectorXd::Zero(4), VectorXd::Zero(2), Afd, Bfd, fd);
      const MatrixXd A = m.A(c), B = m.B(c);
      EXPECT_LE((A - Afd).cwiseAbs().maxCoeff(), 1e-8 * A.cwiseAbs().maxCoeff());
      EXPECT_LE((B - Bfd).cwiseAbs().maxCoeff(), 1e-8 * B.cwiseAbs().maxCoeff());
    }
  }
}

TEST(Polar, LinearModelPredictsSmallDeviationsToSecondOrder) {
  const PolarModel m(6778.137, std::sqrt(kMu / std::pow(6778.137, 3)));
  VectorXd x(4);
  x << 1.0, 1e-3, 2.0, 1e-3;  // km, km/s
  double prev = 0;
  for (double eps : {1.0, 0.5, 0.25}) {
    const VectorXd e = m.deviation_rhs(0.0, eps * x, PolarModel::Input::Zero()) - m.A() * (eps * x);
    if (prev > 0) EXPECT_NEAR(prev / e.norm(), 4.0, 0.1);  // quadratic remainder halves twice
    prev = e.norm();
  }
}

TEST(Polar, DeviationRoundTrip) {
  const PolarModel m(42164.17, 7.2921e-5);
  const PolarModel::State s(42170.0, 0.01, 3.0, 7.3e-5);
  for (PolarCoordinates c : {PolarCoordinates::scaled, PolarCoordinates::raw})
    SATGNC_EXPECT_REL(m.from_deviation(500.0, m.to_deviation(500.0, s, c), c), s, 1e-15);
  EXPECT_NEAR(m.to_deviation(500.0, s)(2), 42164.17 * (3.0 - 7.2921e-5 * 500.0), 1e-9);
}

TEST(Polar, BadInputThrows) {
  EXPECT_THROW(PolarModel(0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(PolarModel(1.0, -1.0), std::invalid_argument);
  EXPECT_THROW(PolarModel(NAN, 1.0), std::invalid_argument);
  EXPECT_THROW(PolarModel::from_mu(7000.0, 0.0), std::invalid_argument);
  try {
    PolarModel(-1.0, 1.0);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sigma"), std::string::npos);
  }
  EXPECT_THROW(satgnc::analysis::polar_linear_model(PolarModel(1, 1), {0, 4}), std::invalid_argument);
}

TEST(Cw, MatchesLinearizedRelativeTwoBodyInHillFrame) {
  // Nonlinear relative motion in the rotating Hill frame of a circular target (x radial, y along-track,
  // z normal): rho'' = -mu (R + rho)/|R + rho|^3 + mu R/|R|^3 - 2 w x rho' - w x (w x rho) + u.
  const double a = 6778.137e3, mu = kMu * 1e9, n = std::sqrt(mu / (a * a * a));
  const Eigen::Vector3d w(0, 0, n), R(a, 0, 0);
  const satgnc::analysis::ModelFn f = [&](double, const VectorXd& x, const VectorXd& u) {
    const Eigen::Vector3d rho = x.head<3>(), v = x.tail<3>();
    const Eigen::Vector3d p = R + rho;
    VectorXd d(6);
    d.head<3>() = v;
    d.tail<3>() = -mu * p / std::pow(p.norm(), 3) + mu * R / std::pow(a, 3) - 2 * w.cross(v) -
                  w.cross(w.cross(rho)) + u.head<3>();
    return d;
  };
  MatrixXd Afd, Bfd;
  satgnc::analysis::FdSettings fd;
  fd.x_scale = (VectorXd(6) << 100, 100, 100, 0.1, 0.1, 0.1).finished();
  fd_jacobian(f, 0.0, VectorXd::Zero(6), VectorXd::Zero(3), Afd, Bfd, fd);
  const auto cw = cw_model(n);
  EXPECT_LE((cw.A - Afd).cwiseAbs().maxCoeff(), 1e-9 * cw.A.cwiseAbs().maxCoeff());
  EXPECT_LE((cw.B - Bfd).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(cw.C.rows(), 3);
  EXPECT_THROW(cw_model(0.0), std::invalid_argument);
  EXPECT_THROW(cw_model(1.0, {6}), std::invalid_argument);
}

TEST(OdModel, TwoBodyJacobianAndMeasurementPartialsMatchFiniteDifferences) {
  const Eigen::Vector3d r(5836.89070, 1265.61600, 3411.49600), v(0.31460, 6.94010, -3.11250);
  const Eigen::Vector3d R(5463.14996, 2139.12637, 2493.77850), V(-0.15551, 0.39717, 0.0);
  const satgnc::analysis::ModelFn f = [&](double, const VectorXd& x, const VectorXd&) {
    VectorXd d(6);
    d.head<3>() = x.tail<3>();
    d.tail<3>() = -kMu * x.head<3>() / std::pow(x.head<3>().norm(), 3);
    return d;
  };
  VectorXd x(6);
  x << r, v;
  MatrixXd Afd, Bfd;
  fd_jacobian(f, 0.0, x, VectorXd(0), Afd, Bfd);
  const MatrixXd A = satgnc::analysis::two_body_jacobian(r, kMu);
  EXPECT_LE((A - Afd).cwiseAbs().maxCoeff(), 1e-8 * A.cwiseAbs().maxCoeff());
  EXPECT_EQ(Bfd.cols(), 0);

  Eigen::Matrix<double, 1, 6> H1, H2;
  const double rho = satgnc::analysis::range_partial(r, R, H1);
  const double rhod = satgnc::analysis::range_rate_partial(r, v, R, V, H2);
  EXPECT_NEAR(rho, (r - R).norm(), 1e-12);
  const double h = 1e-4;
  for (int j = 0; j < 6; ++j) {
    VectorXd xp = x, xm = x;
    xp(j) += h;
    xm(j) -= h;
    Eigen::Matrix<double, 1, 6> dummy;
    const double d1 = (satgnc::analysis::range_partial(xp.head<3>(), R, dummy) -
                       satgnc::analysis::range_partial(xm.head<3>(), R, dummy)) /
                      (2 * h);
    const double d2 = (satgnc::analysis::range_rate_partial(xp.head<3>(), xp.tail<3>(), R, V, dummy) -
                       satgnc::analysis::range_rate_partial(xm.head<3>(), xm.tail<3>(), R, V, dummy)) /
                      (2 * h);
    EXPECT_NEAR(H1(j), d1, 1e-8);
    EXPECT_NEAR(H2(j), d2, 1e-8);
  }
  EXPECT_LT(std::abs(rhod), 10.0);
  EXPECT_THROW(satgnc::analysis::range_partial(R, R, H1), std::invalid_argument);
  EXPECT_THROW(satgnc::analysis::two_body_jacobian(r, -1.0), std::invalid_argument);
}

TEST(Linearize, RejectsBadShapesAndNonFinite) {
  const satgnc::analysis::ModelFn f = [](double, const VectorXd& x, const VectorXd&) { return x; };
  const satgnc::analysis::JacobianFn bad = [](double, const VectorXd&, const VectorXd&, MatrixXd& A,
                                              MatrixXd& B) {
    A = MatrixXd::Identity(3, 3);
    B = MatrixXd::Zero(2, 1);
  };
  EXPECT_THROW(linearize(f, bad, 0.0, VectorXd::Zero(2), VectorXd::Zero(1)), std::invalid_argument);
  VectorXd xn = VectorXd::Zero(2);
  xn(0) = NAN;
  MatrixXd A, B;
  EXPECT_THROW(fd_jacobian(f, 0.0, xn, VectorXd::Zero(1), A, B), std::invalid_argument);
  satgnc::analysis::FdSettings fd;
  fd.rel_step = -1;
  EXPECT_THROW(fd_jacobian(f, 0.0, VectorXd::Zero(2), VectorXd::Zero(1), A, B, fd), std::invalid_argument);
}
