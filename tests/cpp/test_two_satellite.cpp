// Two-satellite rendezvous model: analytic Jacobians against central finite differences, the RK3/RK4
// discrete maps and their exact Jacobians, and the scenario's 1 h drift (l1_scenario.md).
#include <cmath>
#include <stdexcept>

#include "satgnc/dynamics/two_satellite.hpp"
#include "testing.hpp"

using satgnc::Mat3;
using satgnc::Vec3;
using satgnc::Vec6;
using namespace satgnc::dynamics;

namespace {

constexpr double kMu = 3.99e14;
constexpr double kR = 7231.0e3;

Vec12 scenario_release_state() {
  Vec12 x;
  const double vc = std::sqrt(kMu / kR);
  x << 20.0, 30.0, 10.0, kR, 0.0, 0.0, 0.4, 0.6, -0.1, 0.0, vc, 0.0;
  return x;
}

// A state off the equatorial plane with a sizeable separation, to exercise every term.
Vec12 generic_state() {
  Vec12 x;
  x << 1200.0, -800.0, 300.0, 5.1e6, 3.9e6, 3.2e6, 1.1, -0.7, 0.4, -4.5e3, 2.9e3, 4.1e3;
  return x;
}

// Column-wise relative error of an analytic Jacobian against central differences.
template <typename F, int Rows, int Cols>
double jacobian_fd_error(F&& fun, const Eigen::Matrix<double, Cols, 1>& z,
                         const Eigen::Matrix<double, Rows, Cols>& J, double rel_step = 1e-6) {
  double worst = 0.0;
  for (int j = 0; j < Cols; ++j) {
    const double h = rel_step * std::max(std::abs(z(j)), 1.0);
    Eigen::Matrix<double, Cols, 1> zp = z, zm = z;
    zp(j) += h;
    zm(j) -= h;
    const Eigen::Matrix<double, Rows, 1> col = (fun(zp) - fun(zm)) / (2.0 * h);
    const double scale = std::max(J.col(j).cwiseAbs().maxCoeff(), 1e-300);
    worst = std::max(worst, (col - J.col(j)).cwiseAbs().maxCoeff() / scale);
  }
  return worst;
}

TwoSatelliteParams heavy_drag_j2_params(ControlFrame frame) {
  TwoSatelliteParams p;
  p.j2_on = true;
  p.rho0 = 1e-11;          // large density so drag's Jacobian is visible
  p.density_decay = 1e-6;  // and varies with altitude
  p.control_frame = frame;
  return p;
}

}  // namespace

TEST(TwoSatellite, RhsJacobiansMatchFiniteDifferences) {
  for (auto frame : {ControlFrame::inertial, ControlFrame::target_cw}) {
    for (auto atm : {AtmosphereRotation::co_rotating, AtmosphereRotation::published}) {
      auto p = heavy_drag_j2_params(frame);
      p.atmosphere = atm;
      const TwoSatelliteModel model(p);
      const Vec12 x = generic_state();
      const Vec3 u(0.3, -0.2, 0.1);
      Vec12 f;
      Mat12 A;
      Mat12x3 B;
      ASSERT_TRUE(model.rhs_jacobians(x, u, f, A, B));
      Vec12 f2;
      ASSERT_TRUE(model.rhs(x, u, f2));
      EXPECT_LE((f - f2).cwiseAbs().maxCoeff(), 1e-15 * f.cwiseAbs().maxCoeff());
      auto fx = [&](const Vec12& z) {
        Vec12 o;
        model.rhs(z, u, o);
        return o;
      };
      auto fu = [&](const Vec3& z) {
        Vec12 o;
        model.rhs(x, z, o);
        return o;
      };
      // Central differences, relative step 1e-4: truncation ~(h/|r|)^2 ~ 1e-8, rounding of the
      // differential acceleration (two ~8 m/s^2 terms) ~1e-15 / 0.2 m against entries ~1e-6 /s^2.
      EXPECT_LE(jacobian_fd_error(fx, x, A, 1e-4), 1e-7);
      EXPECT_LE(jacobian_fd_error(fu, u, B), 1e-7);
    }
  }
}

TEST(TwoSatellite, DragAndJ2AreActuallyExercised) {
  auto p = heavy_drag_j2_params(ControlFrame::inertial);
  const Vec3 r(5.1e6, 3.9e6, 3.2e6), v(-4.5e3, 2.9e3, 4.1e3);
  Vec3 a_all, a_none;
  const TwoSatelliteModel m_all(p);
  ASSERT_TRUE(m_all.body_acceleration(r, v, 0.01 / 4.6, a_all));
  p.j2_on = false;
  p.drag_on = false;
  const TwoSatelliteModel m_none(p);
  ASSERT_TRUE(m_none.body_acceleration(r, v, 0.01 / 4.6, a_none));
  // J2 is ~1e-3 of point mass at this radius.
  EXPECT_GT((a_all - a_none).norm(), 1e-4 * a_none.norm());
}

TEST(TwoSatellite, DiscreteMapJacobiansMatchFiniteDifferences) {
  for (int scheme : {3, 4}) {
    const TwoSatelliteModel model(heavy_drag_j2_params(ControlFrame::target_cw));
    const Vec12 x = generic_state();
    const Vec3 u(0.3, -0.2, 0.1);
    const double h = 6000.0 / 99.0;
    Vec12 xn;
    Mat12 A;
    Mat12x3 B;
    ASSERT_TRUE(model.rk_step(scheme, h, x, u, xn, &A, &B));
    Vec12 xn2;
    ASSERT_TRUE(model.rk_step(scheme, h, x, u, xn2));
    EXPECT_EQ((xn - xn2).cwiseAbs().maxCoeff(), 0.0);
    auto fx = [&](const Vec12& z) {
      Vec12 o;
      model.rk_step(scheme, h, z, u, o);
      return o;
    };
    auto fu = [&](const Vec3& z) {
      Vec12 o;
      model.rk_step(scheme, h, x, z, o);
      return o;
    };
    EXPECT_LE(jacobian_fd_error(fx, x, A), 1e-7) << "scheme " << scheme;
    EXPECT_LE(jacobian_fd_error(fu, u, B), 1e-7) << "scheme " << scheme;
  }
}

TEST(TwoSatellite, Rk3IsKuttaThirdOrder) {
  // Halving the step must reduce the one-step error of RK3 by ~2^4 (local order 4) on a Kepler arc.
  TwoSatelliteParams p;
  p.drag_on = false;
  const TwoSatelliteModel model(p);
  const Vec12 x = scenario_release_state();
  const Vec3 u = Vec3::Zero();
  auto run = [&](int scheme, int steps) {
    Vec12 z = x, zn;
    for (int i = 0; i < steps; ++i) {
      model.rk_step(scheme, 600.0 / steps, z, u, zn);
      z = zn;
    }
    return z;
  };
  const Vec12 ref = run(4, 4000);
  const double e1 = (run(3, 10) - ref).segment<3>(3).norm();
  const double e2 = (run(3, 20) - ref).segment<3>(3).norm();
  // global order 3: ratio 8 (between 6 and 10 allows for the pre-asymptotic regime)
  EXPECT_GT(e1 / e2, 6.0);
  EXPECT_LT(e1 / e2, 10.0);
}

TEST(TwoSatellite, ScenarioDriftReproducesPublishedRelativeState) {
  // l1_scenario.md: 3600 s of RK4 with 10000 nodes (9999 steps) on the published implementation's
  // model (drag sign as published), converted with its full_to_cw.
  TwoSatelliteParams p;
  p.atmosphere = AtmosphereRotation::published;
  const TwoSatelliteModel model(p);
  Vec12 x = scenario_release_state(), xn;
  const int steps = 9999;
  for (int i = 0; i < steps; ++i) {
    ASSERT_TRUE(model.rk_step(4, 3600.0 / steps, x, Vec3::Zero(), xn));
    x = xn;
  }
  const Vec6 cw = cw_relative_state_published(x, kMu);
  const Vec6 expected = (Vec6() << -9477.311, -1999.979, -43.046, -3.477486, 1.007149, -0.090170).finished();
  // Printed to 1e-3 m and 1e-6 m/s: half a unit in the last digit.
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(cw(i), expected(i), 0.5e-3) << i;
  for (int i = 3; i < 6; ++i) EXPECT_NEAR(cw(i), expected(i), 0.5e-6) << i;
  // The exact-frame conversion differs by ~1e-4 m/s in velocity (documented).
  const Vec6 cw_exact = cw_relative_state(x);
  EXPECT_LT((cw_exact.head<3>() - cw.head<3>()).norm(), 1e-6);
  // Round trip of the conversion.
  const Vec12 back = two_satellite_state(x.segment<3>(3), x.segment<3>(9), cw_exact);
  EXPECT_LT((back - x).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(TwoSatellite, BadInputs) {
  TwoSatelliteParams p;
  p.mu = -1.0;
  EXPECT_THROW({ TwoSatelliteModel m(p); }, std::invalid_argument);
  p = TwoSatelliteParams();
  p.mass_chaser = 0.0;
  try {
    TwoSatelliteModel m(p);
    FAIL() << "expected throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mass_chaser"), std::string::npos);
  }
  const TwoSatelliteModel model;
  Vec12 x = Vec12::Zero(), f;
  EXPECT_FALSE(model.rhs(x, Vec3::Zero(), f));  // zero radius: a failure, not a NaN
  x = scenario_release_state();
  x(0) = std::nan("");
  EXPECT_FALSE(model.rhs(x, Vec3::Zero(), f));
  EXPECT_FALSE(model.rk_step(5, 1.0, scenario_release_state(), Vec3::Zero(), f));
}

TEST(TwoSatellite, StructuredRkJacobianEqualsDenseStageChainRule) {
  // rk_step differentiates the stages in 3x3 blocks (target autonomous, position rows = velocities).
  // Reference: the dense chain rule D_i = J(x_i) (I + h sum_j a_ij D_j) with the full 12x12 and 12x3
  // rhs_jacobians, written out here for Kutta's RK3 and classic RK4.
  struct Tab {
    int scheme, s;
    double a[4][4], b[4];
  };
  const Tab tabs[2] = {
      {3, 3, {{0, 0, 0, 0}, {0.5, 0, 0, 0}, {-1, 2, 0, 0}, {0, 0, 0, 0}}, {1 / 6.0, 4 / 6.0, 1 / 6.0, 0}},
      {4,
       4,
       {{0, 0, 0, 0}, {0.5, 0, 0, 0}, {0, 0.5, 0, 0}, {0, 0, 1, 0}},
       {1 / 6.0, 2 / 6.0, 2 / 6.0, 1 / 6.0}}};
  for (ControlFrame frame : {ControlFrame::target_cw, ControlFrame::inertial}) {
    const TwoSatelliteModel model(heavy_drag_j2_params(frame));
    const Vec12 x = generic_state();
    const Vec3 u(0.3, -0.2, 0.1);
    const double h = 6000.0 / 99.0;
    for (const Tab& t : tabs) {
      Vec12 k[4], xn;
      Mat12 D[4], A, Aref = Mat12::Identity();
      Mat12x3 Du[4], B, Bref = Mat12x3::Zero();
      for (int i = 0; i < t.s; ++i) {
        Vec12 xs = x;
        Mat12 M = Mat12::Identity();
        Mat12x3 Mu = Mat12x3::Zero();
        for (int j = 0; j < i; ++j) {
          xs += h * t.a[i][j] * k[j];
          M += h * t.a[i][j] * D[j];
          Mu += h * t.a[i][j] * Du[j];
        }
        Mat12 J;
        Mat12x3 Ju;
        ASSERT_TRUE(model.rhs_jacobians(xs, u, k[i], J, Ju));
        D[i] = J * M;
        Du[i] = J * Mu + Ju;
        Aref += h * t.b[i] * D[i];
        Bref += h * t.b[i] * Du[i];
      }
      ASSERT_TRUE(model.rk_step(t.scheme, h, x, u, xn, &A, &B));
      EXPECT_LE((A - Aref).cwiseAbs().maxCoeff(), 1e-14 * Aref.cwiseAbs().maxCoeff()) << t.scheme;
      EXPECT_LE((B - Bref).cwiseAbs().maxCoeff(), 1e-14 * Bref.cwiseAbs().maxCoeff()) << t.scheme;
      // the target block does not depend on the chaser or the control: exact zeros
      for (int r : {3, 4, 5, 9, 10, 11}) {
        for (int c : {0, 1, 2, 6, 7, 8}) EXPECT_EQ(A(r, c), 0.0);
        EXPECT_EQ(B.row(r).cwiseAbs().maxCoeff(), 0.0);
      }
    }
  }
}
