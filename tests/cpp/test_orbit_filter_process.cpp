// The orbit filter's process model (issue 15 items 2-3): state and STM against propagate_dop853 and
// central differences, SNC / DMC process noise against an independent integration of the covariance
// ODE dP/dt = A P + P A^T + G Qc G^T (fixed-step RK4, 0.25 s), the free-motion closed form, the DMC
// block's exact discretization, the allocation count of propagate(), and bad settings.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "malloc_counter.hpp"
#include "satgnc/filter/orbit_process_model.hpp"
#include "satgnc/propagation/dop853.hpp"

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using satgnc::Mat3;
using satgnc::Mat6;
using satgnc::Vec3;
using satgnc::Vec6;
using satgnc::dynamics::ForceModel;
using satgnc::dynamics::J2Gravity;
using satgnc::filter::OrbitProcessModel;
using satgnc::filter::OrbitProcessSettings;
using satgnc::propagation::Dop853Status;

ForceModel j2_model() {
  ForceModel fm;
  fm.j2 = J2Gravity{};
  return fm;
}

// A 500 km, 51.6 deg, slightly eccentric LEO state (km, km/s, GCRF).
Vec6 leo_state() {
  Vec6 x;
  x << 6878.0, 0.0, 0.0, 0.0, 4.737, 5.987;
  return x;
}

double rel_fro(const MatrixXd& a, const MatrixXd& b) { return (a - b).norm() / b.norm(); }

// Independent reference: [x, w] and the covariance ODE integrated with classical RK4 at step h, using the
// ForceModel's Jacobians: A = [0 I 0; da_dr da_dv I; 0 0 -1/tau], G Qc G^T = SNC (v rows, RIC PSD rotated
// at the current state) + DMC (w rows, 2 sigma^2 / tau). Starting from P = 0, P(t1) is Q.
struct LyapunovReference {
  const ForceModel& fm;
  Vec3 psd_ric = Vec3::Zero();
  bool dmc = false;
  Vec3 tau = Vec3::Constant(600.0);
  Vec3 sigma = Vec3::Zero();
  using Mat9 = Eigen::Matrix<double, 9, 9>;
  using Vec9 = Eigen::Matrix<double, 9, 1>;
  void deriv(double t, const Vec9& x, const Mat9& p, Vec9& dx, Mat9& dp) const {
    Vec3 a;
    Mat3 da_dr, da_dv;
    fm.acceleration_jacobians(t, x.head<3>(), x.segment<3>(3), a, da_dr, da_dv);
    Mat9 A = Mat9::Zero();
    A.block<3, 3>(0, 3).setIdentity();
    A.block<3, 3>(3, 0) = da_dr;
    A.block<3, 3>(3, 3) = da_dv;
    if (dmc) {
      A.block<3, 3>(3, 6).setIdentity();
      A.block<3, 3>(6, 6) = (-tau.cwiseInverse()).asDiagonal();
    }
    dx = A * x;
    dx.segment<3>(3) = a + (dmc ? Vec3(x.segment<3>(6)) : Vec3::Zero());
    const Mat3 ric = OrbitProcessModel::ric_rows(x.head<3>(), x.segment<3>(3));
    Mat9 gqg = Mat9::Zero();
    gqg.block<3, 3>(3, 3) = ric.transpose() * psd_ric.asDiagonal() * ric;
    if (dmc) gqg.block<3, 3>(6, 6) = (2.0 * sigma.array().square() / tau.array()).matrix().asDiagonal();
    dp = A * p + p * A.transpose() + gqg;
  }
  Mat9 run(double t0, double t1, Vec9& x, double h) const {
    Mat9 p = Mat9::Zero();
    const int n = static_cast<int>(std::lround((t1 - t0) / h));
    for (int i = 0; i < n; ++i) {
      const double t = t0 + i * h;
      Vec9 k1, k2, k3, k4;
      Mat9 l1, l2, l3, l4;
      deriv(t, x, p, k1, l1);
      deriv(t + h / 2, x + h / 2 * k1, p + h / 2 * l1, k2, l2);
      deriv(t + h / 2, x + h / 2 * k2, p + h / 2 * l2, k3, l3);
      deriv(t + h, x + h * k3, p + h * l3, k4, l4);
      x += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      p += h / 6 * (l1 + 2 * l2 + 2 * l3 + l4);
    }
    return p;
  }
};

TEST(OrbitProcess, StateAndStmEqualPropagateDop853) {
  const ForceModel fm = j2_model();
  OrbitProcessSettings s;
  s.parameters = 2;
  OrbitProcessModel pm(fm, s);
  ASSERT_EQ(pm.dimension(), 8);
  VectorXd x = VectorXd::Zero(8);
  x.head<6>() = leo_state();
  x[6] = 0.003;  // a range bias, km: constant
  x[7] = 1e-4;   // a time bias, s: constant
  MatrixXd phi(8, 8), q(8, 8);
  const auto info = pm.propagate(0.0, 1500.0, x, phi, q);
  ASSERT_EQ(info.status, Dop853Status::success);
  const auto tr = satgnc::propagation::propagate_dop853(fm, leo_state(), 0.0, {1500.0}, s.integrator, true);
  // Five 300 s sub-intervals restart DOP853 against one 1500 s run: both meet the default tolerance
  // (1 mm per day class), so they agree to 1e-8 km / 1e-8 relative, not to the last bit.
  EXPECT_LT((x.head<6>() - tr.states[0]).head<3>().norm(), 1e-8);
  EXPECT_LT((x.head<6>() - tr.states[0]).tail<3>().norm(), 1e-11);
  EXPECT_LT((phi.topLeftCorner<6, 6>() - tr.stms[0]).norm() / tr.stms[0].norm(), 1e-8);
  EXPECT_EQ(x[6], 0.003);  // parameters are constants: bit-identical
  EXPECT_EQ(x[7], 1e-4);
  EXPECT_TRUE((phi.bottomRightCorner(2, 2).isIdentity(0.0)));
  EXPECT_EQ(phi.topRightCorner(6, 2).norm(), 0.0);
  EXPECT_EQ(q.norm(), 0.0);  // no SNC, no DMC: Q is exactly zero
  EXPECT_GT(info.steps, 5);
}

TEST(OrbitProcess, DmcTransitionMatrixMatchesCentralDifferences) {
  const ForceModel fm = j2_model();
  OrbitProcessSettings s;
  s.dmc = true;
  s.dmc_tau = Vec3(300.0, 600.0, 900.0);
  s.integrator.rtol = 1e-13;
  s.integrator.atol = 1e-15;
  OrbitProcessModel pm(fm, s);
  ASSERT_EQ(pm.dimension(), 9);
  VectorXd x0(9);
  x0 << leo_state(), 1e-8, -2e-8, 3e-8;
  MatrixXd phi(9, 9), q(9, 9), dummy(9, 9), dq(9, 9);
  VectorXd x = x0;
  ASSERT_EQ(pm.propagate(0.0, 900.0, x, phi, q).status, Dop853Status::success);
  // w decays exactly: w(t) = w0 exp(-t / tau).
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(x[6 + i], x0[6 + i] * std::exp(-900.0 / s.dmc_tau[i]), 1e-22);
  // Central differences, steps 1e-3 km, 1e-6 km/s, 1e-9 km/s^2: truncation ~ h^2 * third derivative,
  // rounding ~ 1e-16 |x| / h; the columns agree to 1e-5 relative (measured 1e-7 .. 3e-6).
  const double steps[9] = {1e-3, 1e-3, 1e-3, 1e-6, 1e-6, 1e-6, 1e-9, 1e-9, 1e-9};
  for (int j = 0; j < 9; ++j) {
    VectorXd xp = x0, xm = x0;
    xp[j] += steps[j];
    xm[j] -= steps[j];
    ASSERT_EQ(pm.propagate(0.0, 900.0, xp, dummy, dq).status, Dop853Status::success);
    ASSERT_EQ(pm.propagate(0.0, 900.0, xm, dummy, dq).status, Dop853Status::success);
    const VectorXd col = (xp - xm) / (2 * steps[j]);
    EXPECT_LT((col - phi.col(j)).norm() / phi.col(j).norm(), 1e-5) << "column " << j;
  }
}

TEST(OrbitProcess, SncNoiseMatchesCovarianceOdeIntegration) {
  const ForceModel fm = j2_model();
  OrbitProcessSettings s;
  s.snc_psd_ric = Vec3(1e-12, 4e-12, 2e-12);  // km^2/s^3: (1, 2, 1.4) mm/s^2 per sqrt(Hz)-class
  s.integrator.rtol = 1e-12;
  s.integrator.atol = 1e-14;
  for (double span : {60.0, 600.0, 3600.0}) {
    OrbitProcessModel pm(fm, s);
    VectorXd x = leo_state();
    MatrixXd phi(6, 6), q(6, 6);
    ASSERT_EQ(pm.propagate(0.0, span, x, phi, q).status, Dop853Status::success);
    LyapunovReference ref{fm, s.snc_psd_ric};
    LyapunovReference::Vec9 xr = LyapunovReference::Vec9::Zero();
    xr.head<6>() = leo_state();
    const MatrixXd qr = ref.run(0.0, span, xr, 0.25).topLeftCorner<6, 6>();
    // 5 Gauss-Legendre nodes (the default) per 300 s sub-interval against RK4 at 0.25 s (RK4 error
    // ~ (n h)^4 ~ 1e-13): measured 1.1e-12 (60 s), 4.9e-13 (600 s), 3.8e-14 (3600 s) relative
    // (Frobenius); bound 1e-11.
    const double e = rel_fro(q, qr);
    // 3 nodes per sub-interval against the same reference: the cheaper rule, still far below any
    // process-noise tuning accuracy (measured 9.2e-9, 1.3e-6, 1.5e-9 relative).
    OrbitProcessSettings s3 = s;
    s3.quadrature_nodes = 3;
    OrbitProcessModel pm3(fm, s3);
    VectorXd x3 = leo_state();
    MatrixXd q3(6, 6);
    ASSERT_EQ(pm3.propagate(0.0, span, x3, phi, q3).status, Dop853Status::success);
    EXPECT_LT(rel_fro(q3, qr), 3e-6) << "span " << span << " s";
    EXPECT_LT(e, 1e-11) << "span " << span << " s";
    // Q is symmetric positive definite (Cholesky succeeds) for a non-zero PSD.
    EXPECT_EQ(Eigen::LLT<MatrixXd>(q).info(), Eigen::Success);
    RecordProperty("snc_rel_err_" + std::to_string(static_cast<int>(span)),
                   std::to_string(e * 1e12) + "e-12");
  }
}

TEST(OrbitProcess, SncIsExactForFreeMotionWithIsotropicPsd) {
  // mu -> 1e-9 km^3/s^2 leaves force-free motion: Phi = [I dt I; 0 I], and an isotropic PSD q makes
  // Q = q [dt^3/3 I, dt^2/2 I; dt^2/2 I, dt I] (Tapley, Schutz & Born 2004, eq. 4.9.50). Three (and
  // more) Gauss-Legendre nodes integrate the degree-2 integrand exactly: agreement to rounding (1e-12).
  ForceModel fm;
  fm.mu = 1e-9;
  OrbitProcessSettings s;
  s.snc_psd_ric = Vec3::Constant(3e-12);
  s.noise_step = 1000.0;
  s.quadrature_nodes = 3;
  OrbitProcessModel pm(fm, s);
  VectorXd x = leo_state();
  MatrixXd phi(6, 6), q(6, 6);
  const double dt = 800.0, qc = 3e-12;
  ASSERT_EQ(pm.propagate(0.0, dt, x, phi, q).status, Dop853Status::success);
  MatrixXd qe = MatrixXd::Zero(6, 6);
  qe.topLeftCorner(3, 3) = qc * dt * dt * dt / 3 * Mat3::Identity();
  qe.topRightCorner(3, 3) = qc * dt * dt / 2 * Mat3::Identity();
  qe.bottomLeftCorner(3, 3) = qc * dt * dt / 2 * Mat3::Identity();
  qe.bottomRightCorner(3, 3) = qc * dt * Mat3::Identity();
  EXPECT_LT(rel_fro(q, qe), 1e-12);
  // A single node (the midpoint rule) is not exact: dt^3/4 instead of dt^3/3 in the position block.
  s.quadrature_nodes = 1;
  OrbitProcessModel pm1(fm, s);
  x = leo_state();
  ASSERT_EQ(pm1.propagate(0.0, dt, x, phi, q).status, Dop853Status::success);
  EXPECT_NEAR(q(0, 0) / qe(0, 0), 0.75, 1e-12);
}

TEST(OrbitProcess, DmcNoiseMatchesCovarianceOdeAndExactBlock) {
  const ForceModel fm = j2_model();
  OrbitProcessSettings s;
  s.dmc = true;
  s.dmc_tau = Vec3(200.0, 600.0, 1800.0);     // s
  s.dmc_sigma = Vec3(2e-9, 5e-9, 1e-9);       // km/s^2 (2, 5, 1 um/s^2... x1e3: nm-class accelerations)
  s.snc_psd_ric = Vec3(1e-14, 1e-14, 1e-14);  // km^2/s^3, both noises together
  s.integrator.rtol = 1e-12;
  s.integrator.atol = 1e-16;
  OrbitProcessModel pm(fm, s);
  VectorXd x(9);
  x << leo_state(), 1e-8, 0.0, -1e-8;
  MatrixXd phi(9, 9), q(9, 9);
  const double span = 1200.0;
  ASSERT_EQ(pm.propagate(0.0, span, x, phi, q).status, Dop853Status::success);
  // The w block equals sigma^2 (1 - exp(-2 dt / tau)) exactly (to rounding).
  for (int i = 0; i < 3; ++i) {
    const double exact = s.dmc_sigma[i] * s.dmc_sigma[i] * (1.0 - std::exp(-2.0 * span / s.dmc_tau[i]));
    EXPECT_NEAR(q(6 + i, 6 + i) / exact, 1.0, 1e-12) << "axis " << i;
  }
  LyapunovReference ref{fm, s.snc_psd_ric, true, s.dmc_tau, s.dmc_sigma};
  LyapunovReference::Vec9 xr;
  xr << leo_state(), 1e-8, 0.0, -1e-8;
  const MatrixXd qr = ref.run(0.0, span, xr, 0.25);
  // Whole 9x9 noise, 5 nodes per 300 s against RK4 at 0.25 s: measured 1.2e-10 relative (Frobenius);
  // bound 1e-9.
  const double e = rel_fro(q, qr);
  EXPECT_LT(e, 1e-9);
  // The final state agrees with the reference's (RK4 at 0.25 s over 1200 s: < 1e-7 km).
  EXPECT_LT((x.head<3>() - xr.head<3>()).norm(), 1e-7);
  RecordProperty("dmc_rel_err", std::to_string(e * 1e12) + "e-12");
}

TEST(OrbitProcess, CdAndCrColumnsMatchCentralDifferences) {
  // 350 km LEO with exponential drag (rho0 at 350 km, 50 km scale height, A/m = 0.02 m^2/kg) and
  // cannonball SRP (shadowless, A/m = 0.02): the Cd and Cr columns of the STM (sensitivities integrated
  // with it) against central differences of the propagated state over 1200 s.
  ForceModel fm = j2_model();
  satgnc::dynamics::ExponentialDrag d;
  d.rho0 = 1e-11;
  d.h0 = 350.0;
  d.scale_height = 50.0;
  d.area = 2.0;
  d.mass = 100.0;
  fm.drag = d;
  satgnc::dynamics::SolarRadiationPressure srp;
  srp.area = 2.0;
  srp.mass = 100.0;
  srp.shadow = satgnc::dynamics::ShadowModel::none;
  fm.srp = srp;
  for (bool dmc : {false, true}) {
    OrbitProcessSettings s;
    s.dmc = dmc;
    s.dmc_sigma = Vec3::Constant(1e-9);
    const int o = dmc ? 9 : 6;
    s.parameters = 2;
    s.cd_state = o;
    s.cr_state = o + 1;
    s.integrator.rtol = 1e-13;
    s.integrator.atol = 1e-16;
    OrbitProcessModel pm(fm, s);
    const int n = pm.dimension();
    VectorXd x0 = VectorXd::Zero(n);
    x0.head<6>() << 6728.0, 0.0, 0.0, 0.0, 4.83, 6.1;
    if (dmc) x0.segment<3>(6) << 1e-9, -2e-9, 1e-9;
    x0[o] = 2.2;
    x0[o + 1] = 1.3;
    VectorXd x = x0;
    MatrixXd phi(n, n), q(n, n), dq(n, n), dphi(n, n);
    ASSERT_EQ(pm.propagate(0.0, 1200.0, x, phi, q).status, Dop853Status::success);
    EXPECT_EQ(x[o], 2.2);  // constants
    EXPECT_EQ(x[o + 1], 1.3);
    for (int j : {o, o + 1}) {
      VectorXd xp = x0, xm = x0;
      xp[j] += 0.01;
      xm[j] -= 0.01;
      ASSERT_EQ(pm.propagate(0.0, 1200.0, xp, dphi, dq).status, Dop853Status::success);
      ASSERT_EQ(pm.propagate(0.0, 1200.0, xm, dphi, dq).status, Dop853Status::success);
      const VectorXd col = (xp - xm) / 0.02;
      // The state is linear in Cd and Cr to first order; the central difference over +-0.01 has a
      // truncation ~ 1e-4 of the column (second order in the drag's effect on the orbit): bound 1e-4.
      EXPECT_GT(phi.col(j).head(6).norm(), 0.0);
      EXPECT_LT((col.head(6) - phi.col(j).head(6)).norm() / phi.col(j).head(6).norm(), 1e-4)
          << "dmc " << dmc << " column " << j;
    }
  }
  // A model without the term is a named error at setup.
  OrbitProcessSettings bad;
  bad.parameters = 1;
  bad.cd_state = 6;
  try {
    OrbitProcessModel p2(j2_model(), bad);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cd_state: the force model has no drag term"), std::string::npos);
  }
}

TEST(OrbitProcess, PropagateAllocatesNothing) {
  const ForceModel fm = j2_model();
  OrbitProcessSettings s;
  s.dmc = true;
  s.dmc_sigma = Vec3::Constant(1e-9);
  s.snc_psd_ric = Vec3::Constant(1e-12);
  s.parameters = 4;
  OrbitProcessModel pm(fm, s);
  VectorXd x = VectorXd::Zero(pm.dimension());
  x.head<6>() = leo_state();
  MatrixXd phi(pm.dimension(), pm.dimension()), q(pm.dimension(), pm.dimension());
  g_mallocs = 0;
  g_count = true;
  const auto info = pm.propagate(0.0, 1000.0, x, phi, q);
  g_count = false;
  EXPECT_EQ(info.status, Dop853Status::success);
  EXPECT_EQ(g_mallocs.load(), 0);
}

TEST(OrbitProcess, BadInputIsNamedOrAStatus) {
  const ForceModel fm = j2_model();
  auto msg = [&](OrbitProcessSettings s) -> std::string {
    try {
      OrbitProcessModel pm(fm, s);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  OrbitProcessSettings s;
  s.snc_psd_ric[1] = -1e-12;
  EXPECT_NE(msg(s).find("snc_psd_ric[1]"), std::string::npos) << msg(s);
  s = {};
  s.dmc_tau[2] = 0.0;
  EXPECT_NE(msg(s).find("dmc_tau[2]"), std::string::npos);
  s = {};
  s.dmc_sigma[0] = -1.0;
  EXPECT_NE(msg(s).find("dmc_sigma[0]"), std::string::npos);
  s = {};
  s.quadrature_nodes = 6;
  EXPECT_NE(msg(s).find("quadrature_nodes"), std::string::npos);
  s = {};
  s.noise_step = 0.0;
  EXPECT_NE(msg(s).find("noise_step"), std::string::npos);
  s = {};
  s.parameters = -1;
  EXPECT_NE(msg(s).find("parameters"), std::string::npos);
  // Wrong sizes and non-finite input are a status, never a throw.
  OrbitProcessModel pm(fm, OrbitProcessSettings{});
  VectorXd x = leo_state();
  MatrixXd phi(6, 6), q(6, 6), small(5, 5);
  EXPECT_EQ(pm.propagate(0.0, 10.0, x, small, q).status, Dop853Status::invalid_input);
  x[0] = std::nan("");
  EXPECT_EQ(pm.propagate(0.0, 10.0, x, phi, q).status, Dop853Status::invalid_input);
  // Zero span: identity and zero noise.
  x = leo_state();
  EXPECT_EQ(pm.propagate(5.0, 5.0, x, phi, q).status, Dop853Status::success);
  EXPECT_TRUE(phi.isIdentity(0.0));
  EXPECT_EQ(x, VectorXd(leo_state()));
}

}  // namespace
