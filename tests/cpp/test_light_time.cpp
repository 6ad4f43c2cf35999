// Light-time equations of observation/light_time.hpp: the bounce-time shift against the Kepler
// propagator (LEO and GEO), the down and up legs against their own equations and an independent
// bisection on Kepler positions, the iteration count, settings checks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "obs_fixture.hpp"
#include "satgnc/observation/light_time.hpp"
#include "satgnc/propagation/kepler.hpp"

namespace {

using obs_fixture::kMu;
using satgnc::Mat6;
using satgnc::Vec3;
using satgnc::Vec6;
using satgnc::observation::LightTimeSettings;
using satgnc::observation::RotatingStationEphemeris;
using satgnc::observation::shift_state;
using satgnc::observation::solve_down_leg;
using satgnc::observation::solve_up_leg;
using satgnc::observation::speed_of_light;
using satgnc::observation::StationState;
using satgnc::propagation::kepler_step;

Vec6 kepler(const Vec6& x, double dt) {
  Vec6 out;
  EXPECT_EQ(kepler_step(x, dt, kMu, out, nullptr), satgnc::propagation::KeplerStatus::success);
  return out;
}

// Largest position error (km) and velocity error (km/s) of the Taylor shift against Kepler.
void shift_error(const Vec6& x, double dt, double& dr, double& dv) {
  Vec6 taylor;
  shift_state(x, dt, kMu, taylor);
  const Vec6 exact = kepler(x, dt);
  dr = (taylor.head<3>() - exact.head<3>()).norm();
  dv = (taylor.tail<3>() - exact.tail<3>()).norm();
}

TEST(LightTime, TaylorShiftAgainstKeplerLeoAndGeo) {
  double dr = 0.0, dv = 0.0;
  // LEO, 7000 km: the down-leg light time of a pass is below 10 ms (3000 km); both signs.
  for (double dt : {-0.01, 0.01, -0.02}) {
    shift_error(obs_fixture::pass_state(7000.0), dt, dr, dv);
    std::printf("LEO shift %+.3f s: |dr| = %.2e km, |dv| = %.2e km/s\n", dt, dr, dv);
    // tolerance: the 4th-order remainder is ~dt^4/24 n^2 |a| ~ 1e-17 km; what is left is the
    // rounding of two 7000 km vectors (~1e-12 km).
    EXPECT_LT(dr, 1e-11);
    EXPECT_LT(dv, 1e-13);
  }
  // GEO: up to 0.13 s of light time (station to a GEO satellite, each leg).
  for (double dt : {-0.13, -0.26}) {
    shift_error(obs_fixture::pass_state(42164.0), dt, dr, dv);
    std::printf("GEO shift %+.3f s: |dr| = %.2e km, |dv| = %.2e km/s\n", dt, dr, dv);
    EXPECT_LT(dr, 1e-10);  // rounding of 42164 km vectors; remainder ~dt^4/24 n^2 |a| ~ 1e-15 km
    EXPECT_LT(dv, 1e-13);
  }
  // Beyond light-time spans the series degrades as dt^4: 30 s in LEO is metres (documented limit).
  shift_error(obs_fixture::pass_state(7000.0), 30.0, dr, dv);
  std::printf("LEO shift 30 s: |dr| = %.2e km\n", dr);
  EXPECT_GT(dr, 1e-6);
}

TEST(LightTime, ShiftJacobianAgainstCentralDifferences) {
  const Vec6 x = obs_fixture::pass_state();
  const double dt = -0.013;
  Vec6 y;
  Mat6 J;
  Vec6 ydt;
  shift_state(x, dt, kMu, y, &J, &ydt);
  for (int k = 0; k < 6; ++k) {
    const double h = k < 3 ? 1e-2 : 1e-4;  // km, km/s
    Vec6 xp = x, xm = x, yp, ym;
    xp(k) += h;
    xm(k) -= h;
    shift_state(xp, dt, kMu, yp);
    shift_state(xm, dt, kMu, ym);
    const Vec6 fd = (yp - ym) / (2.0 * h);
    // tolerance: central-difference truncation h^2/6 |f'''| < 1e-12; rounding 4 eps |r| / h
    // (7000 km): 6e-10 for h = 1e-2 km, 6e-8 for h = 1e-4 km/s
    EXPECT_LT((J.col(k) - fd).norm(), 4 * 2.2e-16 * 7000.0 / h) << "column " << k;
  }
  Vec6 yp, ym;
  shift_state(x, dt + 1e-4, kMu, yp);
  shift_state(x, dt - 1e-4, kMu, ym);
  EXPECT_LT((ydt - (yp - ym) / 2e-4).norm(), 4 * 2.2e-16 * 7000.0 / 1e-4);  // rounding bound as above
}

// Independent down leg: bisection on f(tau) = c tau - |r_kepler(-tau) - R| (exact two-body motion).
double down_leg_bisection(const Vec6& x, const Vec3& R) {
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 200 && hi - lo > 1e-16; ++i) {
    const double mid = 0.5 * (lo + hi);
    const double f = speed_of_light * mid - (kepler(x, -mid).head<3>() - R).norm();
    (f > 0.0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(LightTime, DownLegSolvesItsEquationAndMatchesKeplerBisection) {
  const RotatingStationEphemeris st(obs_fixture::station());
  StationState sr;
  st.state(0.0, sr);
  for (double radius : {7000.0, 42164.0}) {
    const Vec6 x = obs_fixture::pass_state(radius, radius > 10000.0 ? 0.02 : 0.2);
    const LightTimeSettings s;
    const auto leg = solve_down_leg(x, sr.r, kMu, s);
    ASSERT_TRUE(leg.converged);
    Vec6 xb;
    shift_state(x, -leg.tau, kMu, xb);
    const double residual = speed_of_light * leg.tau - (xb.head<3>() - sr.r).norm();
    const double bisect = down_leg_bisection(x, sr.r);
    std::printf(
        "r = %.0f km: tau_d = %.15f s, %d iterations, residual %.1e km, |c dtau| vs bisection %.1e km\n",
        radius, leg.tau, leg.iterations, residual, speed_of_light * std::abs(leg.tau - bisect));
    EXPECT_LT(std::abs(residual), 1e-9);                           // km: the equation holds
    EXPECT_LT(speed_of_light * std::abs(leg.tau - bisect), 1e-9);  // km: vs exact two-body motion
    EXPECT_LE(leg.iterations, 4);  // |v|/c contraction: 4.6 digits per update from the instantaneous guess
  }
}

TEST(LightTime, UpLegUsesTheStationAtTransmitTime) {
  const RotatingStationEphemeris st(obs_fixture::station());
  StationState sr, stx;
  st.state(0.0, sr);
  const Vec6 x = obs_fixture::pass_state();
  const LightTimeSettings s;
  const auto down = solve_down_leg(x, sr.r, kMu, s);
  Vec6 xb;
  shift_state(x, -down.tau, kMu, xb);
  const auto up = solve_up_leg(xb.head<3>(), st, -down.tau, down.tau, s, stx);
  ASSERT_TRUE(up.converged);
  StationState check;
  st.state(-down.tau - up.tau, check);
  EXPECT_LT((check.r - stx.r).norm(), 1e-12);  // km: the returned station is at t_b - tau_u
  EXPECT_LT(std::abs(speed_of_light * up.tau - (xb.head<3>() - stx.r).norm()), 1e-9);  // km
  // The station moves ~0.36 km/s * 2 tau between transmit and reception: the legs differ.
  EXPECT_GT(std::abs(up.tau - down.tau), 1e-9);
  EXPECT_LE(up.iterations, 3);
}

TEST(LightTime, NoConvergenceIsReportedNotThrown) {
  const RotatingStationEphemeris st(obs_fixture::station());
  StationState sr;
  st.state(0.0, sr);
  LightTimeSettings s;
  s.max_iterations = 1;
  s.tolerance = 1e-18;
  const auto leg = solve_down_leg(obs_fixture::pass_state(), sr.r, kMu, s);
  EXPECT_FALSE(leg.converged);
  EXPECT_EQ(leg.iterations, 1);
}

TEST(LightTime, SettingsAreChecked) {
  LightTimeSettings s;
  s.tolerance = 0.0;
  try {
    s.validate();
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("light_time.tolerance"), std::string::npos) << e.what();
  }
  s = LightTimeSettings{};
  s.max_iterations = 0;
  EXPECT_THROW(s.validate(), std::invalid_argument);
}

}  // namespace
