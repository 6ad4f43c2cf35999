// Universal-variable Kepler propagator: analytic STM against finite differences for every conic,
// group properties of the STM, conservation laws and published textbook examples.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "derivative_checks.hpp"
#include "satgnc/propagation/kepler.hpp"

namespace {

using satgnc::Mat3;
using satgnc::Mat6;
using satgnc::Vec3;
using satgnc::Vec6;
using satgnc::propagation::kepler_step;
using satgnc::propagation::KeplerInfo;
using satgnc::propagation::KeplerStatus;
using satgnc::propagation::propagate_kepler;
using satgnc::testing::block_rel_err;
using satgnc::testing::rel_err;

constexpr double kMu = 398600.4418;  // km^3/s^2
constexpr double kPi = 3.14159265358979323846;

// State from periapsis radius rp (km), eccentricity e (any conic), true anomaly nu and an inclined,
// rotated plane (so that no STM entry is structurally zero).
Vec6 conic_state(double rp, double e, double nu, double mu = kMu) {
  const double p = rp * (1.0 + e);
  const double r = p / (1.0 + e * std::cos(nu));
  const Vec3 rpf(r * std::cos(nu), r * std::sin(nu), 0.0);
  const Vec3 vpf = std::sqrt(mu / p) * Vec3(-std::sin(nu), e + std::cos(nu), 0.0);
  const Mat3 R = (Eigen::AngleAxisd(0.7, Vec3::UnitZ()) * Eigen::AngleAxisd(0.9, Vec3::UnitX()) *
                  Eigen::AngleAxisd(-1.1, Vec3::UnitZ()))
                     .toRotationMatrix();
  Vec6 x;
  x << R * rpf, R * vpf;
  return x;
}

Vec6 step(const Vec6& x0, double dt, double mu = kMu) {
  Vec6 x;
  const KeplerStatus st = kepler_step(x0, dt, mu, x, nullptr);
  EXPECT_EQ(st, KeplerStatus::success);
  return x;
}

// Central differences with steps relative to |r0| and |v0|.
Mat6 fd_stm(const Vec6& x0, double dt, double rel_step = 1e-6) {
  Mat6 J;
  const double hr = rel_step * x0.head<3>().norm();
  const double hv = rel_step * x0.tail<3>().norm();
  for (int k = 0; k < 6; ++k) {
    const double h = k < 3 ? hr : hv;
    Vec6 xp = x0, xm = x0;
    xp(k) += h;
    xm(k) -= h;
    J.col(k) = (step(xp, dt) - step(xm, dt)) / (2.0 * h);
  }
  return J;
}

Mat6 symplectic_J() {
  Mat6 J = Mat6::Zero();
  J.topRightCorner<3, 3>() = Mat3::Identity();
  J.bottomLeftCorner<3, 3>() = -Mat3::Identity();
  return J;
}

struct StmCase {
  const char* name;
  double rp, e, nu, dt;
};

double period(double rp, double e) {
  const double a = rp / (1.0 - e);
  return 2.0 * kPi * std::sqrt(a * a * a / kMu);
}

std::vector<StmCase> stm_cases() {
  const double P1 = period(7000.0, 0.01), P7 = period(7000.0, 0.7);
  return {
      {"ellipse_e0.01_forward", 7000.0, 0.01, 0.4, 0.37 * P1},
      {"ellipse_e0.01_backward", 7000.0, 0.01, 0.4, -0.37 * P1},
      {"ellipse_e0.01_5orbits", 7000.0, 0.01, 0.4, 5.3 * P1},
      {"ellipse_e0.7_forward", 7000.0, 0.7, 2.5, 0.61 * P7},
      {"ellipse_e0.7_backward", 7000.0, 0.7, 2.5, -0.61 * P7},
      {"ellipse_e0.7_3orbits", 7000.0, 0.7, 2.5, 3.2 * P7},
      {"near_parabolic_e1-1e-8_forward", 7000.0, 1.0 - 1e-8, -0.5, 4.0 * 3600.0},
      {"near_parabolic_e1-1e-8_backward", 7000.0, 1.0 - 1e-8, 0.5, -4.0 * 3600.0},
      {"near_parabolic_e1+1e-8_forward", 7000.0, 1.0 + 1e-8, -0.5, 4.0 * 3600.0},
      {"near_parabolic_e1+1e-8_backward", 7000.0, 1.0 + 1e-8, 0.5, -4.0 * 3600.0},
      {"parabola_forward", 7000.0, 1.0, -1.0, 6.0 * 3600.0},
      {"parabola_backward", 7000.0, 1.0, 1.0, -6.0 * 3600.0},
      {"hyperbola_e2_forward", 7000.0, 2.0, -1.2, 5.0 * 3600.0},
      {"hyperbola_e2_backward", 7000.0, 2.0, 1.2, -5.0 * 3600.0},
      {"short_arc_10s", 7000.0, 0.3, 1.0, 10.0},
  };
}

}  // namespace

TEST(Stumpff, SeriesAndClosedFormsAgreeAtTheSwitch) {
  // The series (|psi| < 4) and closed forms (|psi| >= 4) must agree where they meet.
  for (double psi : {4.0, -4.0}) {
    double a[6], b[6];
    satgnc::propagation::stumpff(std::nextafter(psi, 0.0), a);
    satgnc::propagation::stumpff(psi, b);
    for (int k = 0; k < 6; ++k) EXPECT_LE(rel_err(a[k], b[k]), 2e-14) << "psi " << psi << " k " << k;
  }
  double c[6];
  satgnc::propagation::stumpff(0.0, c);  // c_k(0) = 1/k!
  const double inv_fact[6] = {1.0, 1.0, 0.5, 1.0 / 6.0, 1.0 / 24.0, 1.0 / 120.0};
  for (int k = 0; k < 6; ++k) EXPECT_DOUBLE_EQ(c[k], inv_fact[k]);
  satgnc::propagation::stumpff(9.0, c);  // closed form: c2 = (1 - cos 3)/9
  EXPECT_LE(rel_err(c[2], (1.0 - std::cos(3.0)) / 9.0), 1e-15);
  satgnc::propagation::stumpff(-9.0, c);
  EXPECT_LE(rel_err(c[3], (std::sinh(3.0) - 3.0) / 27.0), 1e-15);
}

TEST(Kepler, AnalyticStmMatchesCentralDifferences) {
  for (const StmCase& cs : stm_cases()) {
    const Vec6 x0 = conic_state(cs.rp, cs.e, cs.nu);
    Vec6 x;
    Mat6 phi;
    KeplerInfo info;
    ASSERT_EQ(kepler_step(x0, cs.dt, kMu, x, &phi, &info), KeplerStatus::success) << cs.name;
    const double err = block_rel_err(phi, fd_stm(x0, cs.dt));
    EXPECT_LT(err, 1e-7) << cs.name;  // the acceptance threshold
    EXPECT_LE(info.iterations, 12) << cs.name;
    std::printf("[stm-fd] %-34s rel err %.2e, %d iterations\n", cs.name, err, info.iterations);
  }
}

TEST(Kepler, StmComposesDeterminantOneAndSymplectic) {
  const Mat6 J = symplectic_J();
  for (const StmCase& cs : stm_cases()) {
    const Vec6 x0 = conic_state(cs.rp, cs.e, cs.nu);
    const double t1 = 0.43 * cs.dt, t2 = cs.dt;
    Vec6 x1, x2, x2b;
    Mat6 p10, p20, p21;
    ASSERT_EQ(kepler_step(x0, t1, kMu, x1, &p10), KeplerStatus::success);
    ASSERT_EQ(kepler_step(x0, t2, kMu, x2, &p20), KeplerStatus::success);
    ASSERT_EQ(kepler_step(x1, t2 - t1, kMu, x2b, &p21), KeplerStatus::success);
    EXPECT_LT(block_rel_err(p21 * p10, p20), 1e-9) << cs.name;
    EXPECT_LT(rel_err(x2b.head<3>(), x2.head<3>()), 1e-12) << cs.name;
    EXPECT_LT(std::abs(p20.determinant() - 1.0), 1e-8) << cs.name;
    // Phi^T J Phi = J, relative to the size of Phi^T J Phi's terms.
    const double scale = (p20.transpose().cwiseAbs() * p20.cwiseAbs()).maxCoeff();
    EXPECT_LT((p20.transpose() * J * p20 - J).cwiseAbs().maxCoeff() / scale, 1e-13) << cs.name;
  }
}

TEST(Kepler, ConservesEnergyAngularMomentumAndEccentricityVector) {
  for (const StmCase& cs : stm_cases()) {
    const Vec6 x0 = conic_state(cs.rp, cs.e, cs.nu);
    auto invariants = [](const Vec6& x, double& energy, Vec3& h, Vec3& ecc) {
      const Vec3 r = x.head<3>(), v = x.tail<3>();
      energy = 0.5 * v.squaredNorm() - kMu / r.norm();
      h = r.cross(v);
      ecc = v.cross(h) / kMu - r / r.norm();
    };
    double E0;
    Vec3 h0, e0;
    invariants(x0, E0, h0, e0);
    for (int k = 1; k <= 7; ++k) {
      double E;
      Vec3 h, e;
      invariants(step(x0, cs.dt * k / 7.0), E, h, e);
      // Energy is compared with v^2/2 (E0 is ~0 for parabolas); e-vector with max(|e|, 1).
      EXPECT_LT(std::abs(E - E0) / (0.5 * x0.tail<3>().squaredNorm()), 1e-13) << cs.name;
      EXPECT_LT(rel_err(h, h0), 1e-13) << cs.name;
      EXPECT_LT((e - e0).norm() / std::max(1.0, e0.norm()), 1e-12) << cs.name;
    }
  }
}

TEST(Kepler, ForwardThenBackwardReturnsToStart) {
  for (const StmCase& cs : stm_cases()) {
    const Vec6 x0 = conic_state(cs.rp, cs.e, cs.nu);
    const Vec6 back = step(step(x0, cs.dt), -cs.dt);
    EXPECT_LT(rel_err(back.head<3>(), x0.head<3>()), 1e-11) << cs.name;
    EXPECT_LT(rel_err(back.tail<3>(), x0.tail<3>()), 1e-11) << cs.name;
  }
}

TEST(Kepler, CircularOrbitClosedForm) {
  // Circular orbit: the state rotates uniformly at n = sqrt(mu/r^3).
  const double r = 7000.0, n = std::sqrt(kMu / (r * r * r));
  Vec6 x0;
  x0 << r, 0.0, 0.0, 0.0, r * n, 0.0;
  for (double t : {100.0, 3000.0, -2000.0, 86400.0}) {
    const Vec6 x = step(x0, t);
    Vec6 ref;
    ref << r * std::cos(n * t), r * std::sin(n * t), 0.0, -r * n * std::sin(n * t), r * n * std::cos(n * t),
        0.0;
    EXPECT_LT(rel_err(x, ref), 1e-12) << "t = " << t;
  }
}

// Vallado, "Fundamentals of Astrodynamics and Applications", 4th ed. (2013), Example 2-4 (KEPLER),
// p. 96 (same problem and answer in the 5th ed., 2022, Example 2-4). mu = 398600.4418 km^3/s^2.
TEST(KeplerTextbook, ValladoExample2_4) {
  Vec6 x0;
  x0 << 1131.340, -2282.343, 6672.423, -5.64305, 4.30333, 2.42879;
  const Vec6 x = step(x0, 40.0 * 60.0);
  const Vec3 r_book(-4219.7527, 4363.0292, -3958.7666);  // km, printed to 1e-4 km
  const Vec3 v_book(3.689866, -1.916735, -6.112511);     // km/s, printed to 1e-6 km/s
  // Tolerance: half a unit in the last printed digit (5e-5 km, 5e-7 km/s) plus margin for the
  // book's own rounding chain -> 2e-4 km and 2e-6 km/s.
  EXPECT_LT((x.head<3>() - r_book).cwiseAbs().maxCoeff(), 2e-4);
  EXPECT_LT((x.tail<3>() - v_book).cwiseAbs().maxCoeff(), 2e-6);
  std::printf("[vallado 2-4] |dr| = %.2e km, |dv| = %.2e km/s\n", (x.head<3>() - r_book).norm(),
              (x.tail<3>() - v_book).norm());
}

// Curtis, "Orbital Mechanics for Engineering Students", 3rd ed. (2014), Example 3.7: universal
// Lagrange coefficients, 60 min, mu = 398600 km^3/s^2. Printed: chi = 253.53 km^0.5,
// r = -3297.8 i + 7413.4 j km, v = -8.2977 i - 0.96309 j km/s.
TEST(KeplerTextbook, CurtisExample3_7) {
  const double mu = 398600.0;
  Vec6 x0;
  x0 << 7000.0, -12124.0, 0.0, 2.6679, 4.6210, 0.0;
  Vec6 x;
  KeplerInfo info;
  ASSERT_EQ(kepler_step(x0, 3600.0, mu, x, nullptr, &info), KeplerStatus::success);
  // chi printed to 5 significant digits: half a unit = 0.005 km^0.5 (we get 253.5345).
  EXPECT_NEAR(info.chi, 253.53, 0.005);
  // r printed to 0.1 km: half a unit, 0.05 km (we get -3297.769, 7413.397).
  EXPECT_NEAR(x(0), -3297.8, 0.05);
  EXPECT_NEAR(x(1), 7413.4, 0.05);
  // v_x printed to 5 digits; the book forms v from f-dot and g-dot rounded to 5 digits (-0.00055298,
  // -1.6593), which moves v by up to 5e-9 * 12124 + 5e-5 * 4.621 = 3e-4 km/s: tolerance 3e-4.
  EXPECT_NEAR(x(3), -8.2977, 3e-4);
  // v_y: the exact solution of the printed inputs is -0.964045 km/s. The printed -0.96309 is 9.6e-4 off,
  // more than the 3e-4 the book's rounding explains (a transcription of the example elsewhere prints
  // -0.96404). We assert the exact value's distance from the printed one instead of bending the test.
  EXPECT_NEAR(x(4), -0.96309, 1e-3);
  EXPECT_GT(std::abs(x(4) - (-0.96309)), 3e-4);
  std::printf("[curtis 3.7] chi = %.4f, r = (%.3f, %.3f), v = (%.6f, %.6f)\n", info.chi, x(0), x(1), x(3),
              x(4));
}

// Curtis, 3rd ed., Example 3.6: hyperbolic orbit, r0 = 10000 km, v0 = 10 km/s, vr0 = 3.0752 km/s
// (true anomaly 30 deg); universal anomaly after one hour printed as chi = 128.5 km^0.5.
TEST(KeplerTextbook, CurtisExample3_6Hyperbolic) {
  const double mu = 398600.0;
  const double vr = 3.0752, vt = std::sqrt(100.0 - vr * vr);
  Vec6 x0;
  x0 << 10000.0, 0.0, 0.0, vr, vt, 0.0;
  Vec6 x;
  KeplerInfo info;
  ASSERT_EQ(kepler_step(x0, 3600.0, mu, x, nullptr, &info), KeplerStatus::success);
  EXPECT_LT(info.alpha, 0.0);
  // Printed to 4 significant digits (0.05) plus the rounding of vr0 to 5 digits: tolerance 0.05.
  EXPECT_NEAR(info.chi, 128.5, 0.05);
  std::printf("[curtis 3.6] chi = %.4f\n", info.chi);
}

TEST(KeplerPropagate, TimesOnBothSidesOfEpochAndStats) {
  const Vec6 x0 = conic_state(7000.0, 0.1, 0.3);
  const double t0 = 1000.0;
  const std::vector<double> times = {-500.0, 1000.0, 2000.0, 9000.0};
  const auto tr = propagate_kepler(x0, t0, times, kMu, true);
  ASSERT_EQ(tr.status, satgnc::propagation::PropagationStatus::success);
  ASSERT_EQ(tr.states.size(), 4u);
  ASSERT_EQ(tr.stms.size(), 4u);
  EXPECT_EQ(tr.times, times);
  EXPECT_EQ(tr.stats.steps, 4);
  EXPECT_GT(tr.stats.nonlin_iters, 0);
  EXPECT_EQ(tr.states[1], x0);
  EXPECT_EQ(tr.stms[1], Mat6::Identity());
  for (std::size_t i = 0; i < times.size(); ++i)
    EXPECT_LT(rel_err(tr.states[i], step(x0, times[i] - t0)), 1e-15);
  EXPECT_DOUBLE_EQ(tr.t_reached, 9000.0);
  EXPECT_TRUE(propagate_kepler(x0, t0, times, kMu, false).stms.empty());
  // Decreasing times are accepted and keep their order.
  const std::vector<double> desc(times.rbegin(), times.rend());
  const auto trd = propagate_kepler(x0, t0, desc, kMu, true);
  ASSERT_EQ(trd.states.size(), 4u);
  EXPECT_EQ(trd.times, desc);
  EXPECT_EQ(trd.states[0], tr.states[3]);
}

TEST(KeplerBadInput, PropagateThrowsNamingTheArgument) {
  const Vec6 good = conic_state(7000.0, 0.1, 0.3);
  const std::vector<double> times = {0.0, 60.0};
  auto expect_throw = [&](const Vec6& x0, double t0, const std::vector<double>& ts, double mu,
                          const std::string& needle) {
    try {
      propagate_kepler(x0, t0, ts, mu, true);
      ADD_FAILURE() << "no throw, expected " << needle;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  Vec6 nan_state = good;
  nan_state(4) = std::nan("");
  Vec6 zero_r = good;
  zero_r.head<3>().setZero();
  expect_throw(nan_state, 0.0, times, kMu, "x0: must be finite");
  expect_throw(zero_r, 0.0, times, kMu, "x0: position must be non-zero");
  expect_throw(good, 0.0, times, 0.0, "mu: must be finite and > 0");
  expect_throw(good, 0.0, times, -1.0, "mu: must be finite and > 0");
  expect_throw(good, 0.0, times, INFINITY, "mu: must be finite and > 0");
  expect_throw(good, NAN, times, kMu, "t0: must be finite");
  expect_throw(good, 0.0, {0.0, NAN}, kMu, "times: must be finite");
  expect_throw(good, 0.0, {0.0, INFINITY}, kMu, "times: must be finite");
  expect_throw(good, 0.0, {0.0, 60.0, 30.0}, kMu, "times: must be monotone");
}

TEST(KeplerBadInput, StepReturnsStatusWithoutThrowing) {
  const Vec6 good = conic_state(7000.0, 0.1, 0.3);
  Vec6 x;
  Mat6 phi;
  Vec6 zero_r = good;
  zero_r.head<3>().setZero();
  EXPECT_EQ(kepler_step(zero_r, 10.0, kMu, x, &phi), KeplerStatus::invalid_input);
  EXPECT_EQ(kepler_step(good, 10.0, 0.0, x, &phi), KeplerStatus::invalid_input);
  EXPECT_EQ(kepler_step(good, 10.0, -kMu, x, &phi), KeplerStatus::invalid_input);
  EXPECT_EQ(kepler_step(good, NAN, kMu, x, &phi), KeplerStatus::invalid_input);
  Vec6 inf_state = good;
  inf_state(0) = INFINITY;
  EXPECT_EQ(kepler_step(inf_state, 10.0, kMu, x, &phi), KeplerStatus::invalid_input);
  EXPECT_STREQ(satgnc::propagation::status_message(KeplerStatus::invalid_input),
               "invalid input: non-finite state, time or mu, mu <= 0, or |r0| = 0");
}

TEST(KeplerFailure, NonConvergenceIsReportedAsStatus) {
  // One iteration cannot solve a multi-revolution eccentric case.
  const Vec6 x0 = conic_state(7000.0, 0.7, 2.5);
  Vec6 x;
  KeplerInfo info;
  EXPECT_EQ(kepler_step(x0, 3.2 * period(7000.0, 0.7), kMu, x, nullptr, &info, 1),
            KeplerStatus::no_convergence);
  EXPECT_EQ(info.iterations, 1);
}

TEST(KeplerInfoStatus, UnsolvedUntilAStepRunsThenWhatTheStepReturned) {
  KeplerInfo info;
  EXPECT_EQ(info.status, KeplerStatus::unsolved);
  const Vec6 x0 = conic_state(7000.0, 0.1, 0.3);
  Vec6 x;
  EXPECT_EQ(kepler_step(x0, 600.0, kMu, x, nullptr, &info), KeplerStatus::success);
  EXPECT_EQ(info.status, KeplerStatus::success);
  EXPECT_GT(info.iterations, 0);
  EXPECT_EQ(kepler_step(x0, 600.0, -1.0, x, nullptr, &info), KeplerStatus::invalid_input);
  EXPECT_EQ(info.status, KeplerStatus::invalid_input);
  EXPECT_EQ(kepler_step(conic_state(7000.0, 0.7, 2.5), 3.2 * period(7000.0, 0.7), kMu, x, nullptr, &info, 1),
            KeplerStatus::no_convergence);
  EXPECT_EQ(info.status, KeplerStatus::no_convergence);
}

TEST(KeplerFailure, HyperbolicOverflowIsReportedAsStatus) {
  // A hyperbola with |a| ~ 4e-5 km (v0 = 1e5 km/s) needs cosh(s > 710) for dt = 1e300 s: no finite
  // double represents the answer, and the step says so instead of returning Inf/NaN.
  Vec6 x0;
  x0 << 7000.0, 0.0, 0.0, 0.0, 1e5, 0.0;
  Vec6 x;
  EXPECT_EQ(kepler_step(x0, 1e300, kMu, x, nullptr), KeplerStatus::overflow);
  const auto tr = propagate_kepler(x0, 0.0, {10.0, 1e300}, kMu, false);
  EXPECT_EQ(tr.status, satgnc::propagation::PropagationStatus::convergence_failures);
  EXPECT_EQ(tr.states.size(), 1u);
  EXPECT_DOUBLE_EQ(tr.t_reached, 10.0);
  EXPECT_NE(tr.message.find("overflow"), std::string::npos) << tr.message;
}

TEST(KeplerSweep, RandomConicsConvergeFastAndRoundTrip) {
  // Deterministic sweep over e in [0, 3) (with a cluster at e = 1), anomalies inside the asymptotes and
  // times up to several periods / days, both directions.
  unsigned s = 12345u;
  auto uni = [&s]() {
    s = 1664525u * s + 1013904223u;
    return (s >> 8) * (1.0 / 16777216.0);
  };
  int worst_it = 0;
  double worst_rt = 0.0;
  for (int k = 0; k < 3000; ++k) {
    double e = 3.0 * uni();
    if (k % 5 == 0) e = 1.0 + (uni() - 0.5) * 1e-6;
    const double rp = 6600.0 + 40000.0 * uni();
    const double nu_max = e < 1.0 ? kPi : std::acos(-1.0 / e) - 1e-3;
    const double nu = (2.0 * uni() - 1.0) * 0.95 * nu_max;
    const double dt = (2.0 * uni() - 1.0) * (e < 0.95 ? 5.0 * period(rp, e) : 2.0 * 86400.0);
    const Vec6 x0 = conic_state(rp, e, nu);
    Vec6 x, back;
    KeplerInfo info;
    ASSERT_EQ(kepler_step(x0, dt, kMu, x, nullptr, &info), KeplerStatus::success) << "case " << k;
    worst_it = std::max(worst_it, info.iterations);
    ASSERT_EQ(kepler_step(x, -dt, kMu, back, nullptr), KeplerStatus::success) << "case " << k;
    worst_rt = std::max(worst_rt, rel_err(back.head<3>(), x0.head<3>()));
  }
  std::printf("[sweep] worst iterations %d, worst round-trip position rel err %.2e\n", worst_it, worst_rt);
  EXPECT_LE(worst_it, 20);
  EXPECT_LT(worst_rt, 1e-9);
}

namespace {
double radius_after(const Vec6& x0, double dt) {
  Vec6 x;
  EXPECT_EQ(kepler_step(x0, dt, kMu, x, nullptr), KeplerStatus::success);
  return x.head<3>().norm();
}
}  // namespace

TEST(KeplerImpact, SurfaceCrossingTimeIsTheFirstOneForEveryConic) {
  using satgnc::propagation::kepler_time_to_radius;
  using satgnc::propagation::PropagationStatus;
  const double R = 6378.137;
  const std::vector<Vec6> cases = {
      (Vec6() << 7000.0, 0, 0, 0, 5.0, 0).finished(),     // ellipse at apoapsis, periapsis inside the body
      (Vec6() << 7000.0, 0, 0, 1.0, 4.0, 0).finished(),   // ascending first: the descent follows apoapsis
      (Vec6() << 7000.0, 0, 0, -11.0, 1.0, 0).finished()  // hyperbola falling onto the body
  };
  for (const Vec6& x0 : cases) {
    const double s = kepler_time_to_radius(x0, 2e4, kMu, R);
    ASSERT_GT(s, 0.0);
    EXPECT_NEAR(radius_after(x0, s), R, 1e-7 * R);
    for (int k = 0; k < 200; ++k) EXPECT_GT(radius_after(x0, s * k / 200.0), R);
    const auto tr = propagate_kepler(x0, 100.0, {100.0, 100.0 + 0.5 * s, 100.0 + 2e4}, kMu, true, R);
    EXPECT_EQ(tr.status, PropagationStatus::impact);
    EXPECT_NEAR(tr.t_reached, 100.0 + s, 1e-9 * s);
    EXPECT_EQ(tr.states.size(), 2u);
    EXPECT_NE(tr.message.find("impact"), std::string::npos);
  }
  // Backward in time: the crossing of the past arc.
  const double sb = kepler_time_to_radius(cases[1], -2e4, kMu, R);
  ASSERT_GT(sb, 0.0);
  EXPECT_NEAR(radius_after(cases[1], -sb), R, 1e-7 * R);
  // An orbit above the surface never impacts; a circular LEO takes a few arithmetic operations.
  const Vec6 leo = (Vec6() << 7000.0, 0, 0, 0, std::sqrt(kMu / 7000.0), 0).finished();
  EXPECT_LT(kepler_time_to_radius(leo, 1e6, kMu, R), 0.0);
  EXPECT_EQ(propagate_kepler(leo, 0.0, {1e5}, kMu, false, R).status, PropagationStatus::success);
}

TEST(KeplerImpact, CollisionOrbitThroughTheCentreIsAnImpactWithoutASurface) {
  using satgnc::propagation::PropagationStatus;
  const Vec6 radial = (Vec6() << 7000.0, 0, 0, -1.0, 0, 0).finished();
  const auto tr = propagate_kepler(radial, 0.0, {100.0, 1e4}, kMu, false);
  EXPECT_EQ(tr.status, PropagationStatus::impact);
  EXPECT_GT(tr.t_reached, 100.0);
  EXPECT_LT(tr.t_reached, 1e4);
  EXPECT_LT(radius_after(radial, tr.t_reached * (1.0 - 1e-9)), 1e-3 * 7000.0);
  EXPECT_THROW(propagate_kepler(radial, 0.0, {1.0}, kMu, false, 8000.0), std::invalid_argument);
  EXPECT_THROW(propagate_kepler(radial, 0.0, {1.0}, kMu, false, -1.0), std::invalid_argument);
}
