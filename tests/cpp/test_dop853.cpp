// Fixed-size DOP853: order, accuracy against the analytic Kepler propagator (state and STM), dense
// output, backward integration, statuses, bad input and a proof that the stepping loop never allocates.
#define EIGEN_RUNTIME_NO_MALLOC
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "derivative_checks.hpp"
#include "malloc_counter.hpp"
#include "satgnc/propagation/dop853.hpp"
#include "satgnc/propagation/kepler.hpp"

namespace {

using satgnc::Mat3;
using satgnc::Mat6;
using satgnc::Vec3;
using satgnc::Vec6;
using satgnc::propagation::Dop853;
using satgnc::propagation::Dop853Info;
using satgnc::propagation::Dop853Settings;
using satgnc::propagation::Dop853Status;
using satgnc::propagation::kepler_step;
using satgnc::propagation::KeplerStatus;
using satgnc::propagation::propagate_dop853_with;
using satgnc::propagation::PropagationStatus;
using satgnc::testing::block_rel_err;
using satgnc::testing::rel_err;

constexpr double kMu = 398600.4418;
constexpr double kPi = 3.14159265358979323846;

// Test-local point-mass gravity with its Jacobians (the force model proper is tested elsewhere).
struct PointMass {
  double mu = kMu;
  void operator()(double, const Vec3& r, const Vec3&, Vec3& a) const { a = -mu / std::pow(r.norm(), 3) * r; }
  void operator()(double, const Vec3& r, const Vec3&, Vec3& a, Mat3& da_dr, Mat3& da_dv) const {
    const double r2 = r.squaredNorm();
    const double rn = std::sqrt(r2);
    const double k = mu / (r2 * rn);
    a = -k * r;
    da_dr = (3.0 * k / r2) * (r * r.transpose()) - k * Mat3::Identity();
    da_dv.setZero();
  }
};

struct TwoBody6 {
  double mu = kMu;
  void operator()(double, const Vec6& y, Vec6& dy) const {
    const Vec3 r = y.head<3>();
    const double rn = r.norm();
    dy.head<3>() = y.tail<3>();
    dy.tail<3>() = -mu / (rn * rn * rn) * r;
  }
};

Vec6 leo_state() {  // ~7000 km, e ~ 0.01, inclined
  Vec6 x;
  x << 6524.834, 6862.875, 6448.296, 4.901327, 5.533756, -1.976341;
  x.head<3>() *= 7000.0 / x.head<3>().norm();
  x.tail<3>() *= 7.6 / x.tail<3>().norm();
  return x;
}

Vec6 kepler(const Vec6& x0, double dt, Mat6* stm = nullptr) {
  Vec6 x;
  EXPECT_EQ(kepler_step(x0, dt, kMu, x, stm), KeplerStatus::success);
  return x;
}

// Integrate the 6-state through `times` and return the states.
std::vector<Vec6> run6(const Vec6& x0, const std::vector<double>& times, const Dop853Settings& s,
                       Dop853Info* info_out = nullptr) {
  TwoBody6 rhs;
  Dop853<6, TwoBody6> integ(rhs, s);
  std::vector<Vec6> out(times.size());
  const Dop853Info info = integ.solve(0.0, x0, times.data(), times.size(),
                                      [&](std::size_t i, double, const Vec6& y) { out[i] = y; });
  EXPECT_EQ(info.status, Dop853Status::success);
  EXPECT_EQ(info.iterations, info.steps);  // core::InfoBase mirror
  EXPECT_GE(info.solve_time, 0.0);
  EXPECT_EQ(integ.workspace().nfev, info.rhs_evals);  // the named workspace holds the run's count
  if (info_out) *info_out = info;
  return out;
}

// Fixed steps of h0 s: controller frozen (fac_min = fac_max = 1) and a tolerance loose enough that
// every step is accepted.
Dop853Settings fixed_step_settings(double h0) {
  Dop853Settings s;
  s.rtol = 1.0;
  s.atol = 1e3;
  s.h0 = h0;
  s.fac_min = 1.0;
  s.fac_max = 1.0;
  return s;
}

}  // namespace

TEST(Dop853, EighthOrderWithFixedSteps) {
  // Fixed steps (controller frozen: fac_min = fac_max = 1, loose tolerance so that every step is
  // accepted): halving h must divide the global error by about 2^8.
  const Vec6 x0 = leo_state();
  const double T = 5400.0;
  const Vec6 ref = kepler(x0, T);
  double errs[3];
  const double hs[3] = {T / 40.0, T / 80.0, T / 160.0};
  for (int i = 0; i < 3; ++i) {
    const Dop853Settings s = fixed_step_settings(hs[i]);
    Dop853Info info;
    errs[i] = (run6(x0, {T}, s, &info)[0] - ref).head<3>().norm();
    EXPECT_EQ(info.rejected, 0);
  }
  const double p1 = std::log2(errs[0] / errs[1]), p2 = std::log2(errs[1] / errs[2]);
  std::printf("[order] errors %.3e %.3e %.3e km, observed orders %.2f %.2f\n", errs[0], errs[1], errs[2], p1,
              p2);
  EXPECT_GT(p1, 7.5);
  EXPECT_LT(p1, 8.6);
  EXPECT_GT(p2, 7.5);
  EXPECT_LT(p2, 8.6);
}

TEST(Dop853, DenseOutputIsSeventhOrder) {
  // Dense output inside fixed steps: error ratio ~2^7 or better when h halves.
  const Vec6 x0 = leo_state();
  const double T = 5400.0;
  double errs[2];
  const double hs[2] = {T / 40.0, T / 80.0};
  for (int i = 0; i < 2; ++i) {
    const Dop853Settings s = fixed_step_settings(hs[i]);
    std::vector<double> times;
    for (int j = 0; j < 20; ++j)
      times.push_back((j + 0.37) * T / 20.0);  // h divides T / 20  // never on a step boundary
    times.push_back(T);
    const auto xs = run6(x0, times, s);
    errs[i] = 0.0;
    for (std::size_t j = 0; j + 1 < times.size(); ++j)
      errs[i] = std::max(errs[i], (xs[j] - kepler(x0, times[j])).head<3>().norm());
  }
  const double p = std::log2(errs[0] / errs[1]);
  std::printf("[dense order] errors %.3e %.3e km, observed order %.2f\n", errs[0], errs[1], p);
  EXPECT_GT(p, 6.5);
}

TEST(Dop853, ErrorScalesWithTolerance) {
  // Global error over one orbit decreases steadily with rtol (slope ~ 1 per decade for DOP853).
  const Vec6 x0 = leo_state();
  const double T = 5800.0;
  const Vec6 ref = kepler(x0, T);
  std::vector<double> errs;
  for (double tol : {1e-6, 1e-8, 1e-10, 1e-12}) {
    Dop853Settings s;
    s.rtol = tol;
    s.atol = tol;
    errs.push_back((run6(x0, {T}, s)[0] - ref).head<3>().norm());
  }
  for (std::size_t i = 0; i + 1 < errs.size(); ++i) {
    const double slope = std::log10(errs[i] / errs[i + 1]) / 2.0;
    std::printf("[tol] error %.3e -> %.3e km, slope %.2f per decade\n", errs[i], errs[i + 1], slope);
    EXPECT_GT(slope, 0.6);
    EXPECT_LT(slope, 1.4);
  }
}

TEST(Dop853, AgreesWithKeplerOverOneDay) {
  const Vec6 x0 = leo_state();
  std::vector<double> times;
  for (int h = 1; h <= 24; ++h) times.push_back(3600.0 * h);
  Dop853Settings s;
  s.rtol = 3e-14;  // 1e-13 gives 0.6 mm but 1.5 um/s after 15 orbits; 3e-14 meets both bounds
  s.atol = 3e-14;
  Dop853Info info;
  const auto xs = run6(x0, times, s, &info);
  double dr = 0.0, dv = 0.0;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const Vec6 ref = kepler(x0, times[i]);
    dr = std::max(dr, (xs[i] - ref).head<3>().norm());
    dv = std::max(dv, (xs[i] - ref).tail<3>().norm());
  }
  std::printf("[1 day] max |dr| = %.3e km, |dv| = %.3e km/s, %ld steps\n", dr, dv, info.steps);
  EXPECT_LT(dr, 1e-6);  // < 1 mm
  EXPECT_LT(dv, 1e-9);  // < 1 um/s
}

TEST(Dop853, StmMatchesKeplerAnalyticStm) {
  const Vec6 x0 = leo_state();
  const std::vector<double> times = {1800.0, 3600.0, 7200.0};
  Dop853Settings s;
  s.rtol = 1e-12;
  s.atol = 1e-12;
  const auto tr = propagate_dop853_with<false>(PointMass{}, x0, 0.0, times, s, true);
  ASSERT_EQ(tr.status, PropagationStatus::success) << tr.message;
  ASSERT_EQ(tr.stms.size(), 3u);
  for (std::size_t i = 0; i < times.size(); ++i) {
    Mat6 phi;
    const Vec6 ref = kepler(x0, times[i], &phi);
    const double e = block_rel_err(tr.stms[i], phi);
    std::printf("[stm] t = %.0f s: STM block rel err %.2e, |dr| %.2e km\n", times[i], e,
                (tr.states[i] - ref).head<3>().norm());
    EXPECT_LT(e, 1e-8);
    EXPECT_LT((tr.states[i] - ref).head<3>().norm(), 1e-6);
  }
  // Velocity-dependent path (da/dv = 0 here) gives the same numbers.
  const auto tr2 = propagate_dop853_with<true>(PointMass{}, x0, 0.0, times, s, true);
  EXPECT_EQ(tr2.stms.back(), tr.stms.back());
  EXPECT_EQ(tr.stats.steps, tr2.stats.steps);
  EXPECT_GT(tr.stats.rhs_evals, 12 * tr.stats.steps);
}

TEST(Dop853, DenseOutputEqualsHittingTheTimeExactly) {
  const Vec6 x0 = leo_state();
  Dop853Settings s;
  s.rtol = 1e-12;
  s.atol = 1e-12;
  const std::vector<double> many = {700.0, 1234.5, 2000.0, 3333.3, 5000.0};
  const auto dense = run6(x0, many, s);
  for (std::size_t i = 0; i < many.size(); ++i) {
    const Vec6 exact = run6(x0, {many[i]}, s)[0];  // last step lands on the time itself
    const Vec6 ref = kepler(x0, many[i]);
    EXPECT_LT((dense[i] - exact).head<3>().norm(), 1e-7) << many[i];
    EXPECT_LT((dense[i] - ref).head<3>().norm(), 1e-7) << many[i];
  }
}

TEST(Dop853, BackwardAndBothSidesOfEpoch) {
  const Vec6 x0 = leo_state();
  Dop853Settings s;
  s.rtol = 1e-12;
  s.atol = 1e-12;
  const std::vector<double> times = {-7200.0, -100.0, 0.0, 50.0, 3600.0};
  const auto tr = propagate_dop853_with<false>(PointMass{}, x0, 0.0, times, s, true);
  ASSERT_EQ(tr.status, PropagationStatus::success) << tr.message;
  ASSERT_EQ(tr.states.size(), times.size());
  EXPECT_EQ(tr.times, times);
  EXPECT_EQ(tr.states[2], x0);
  EXPECT_EQ(tr.stms[2], Mat6::Identity());
  for (std::size_t i = 0; i < times.size(); ++i) {
    Mat6 phi;
    const Vec6 ref = kepler(x0, times[i], &phi);
    EXPECT_LT((tr.states[i] - ref).head<3>().norm(), 1e-6) << times[i];
    if (times[i] != 0.0) EXPECT_LT(block_rel_err(tr.stms[i], phi), 1e-8) << times[i];
  }
  EXPECT_DOUBLE_EQ(tr.t_reached, 3600.0);
  // Decreasing request order (as satgnc.propagate allows): same numbers, same order as requested.
  const std::vector<double> desc(times.rbegin(), times.rend());
  const auto trd = propagate_dop853_with<false>(PointMass{}, x0, 0.0, desc, s, true);
  ASSERT_EQ(trd.status, PropagationStatus::success) << trd.message;
  EXPECT_EQ(trd.times, desc);
  for (std::size_t i = 0; i < times.size(); ++i) EXPECT_EQ(trd.states[i], tr.states[times.size() - 1 - i]);
  EXPECT_DOUBLE_EQ(trd.t_reached, -7200.0);
  // Purely backward.
  const auto back = run6(x0, {-1000.0, -5000.0}, s);
  EXPECT_LT((back[1] - kepler(x0, -5000.0)).head<3>().norm(), 1e-6);
}

TEST(Dop853, ConservesEnergyAndAngularMomentumOverTenOrbits) {
  const Vec6 x0 = leo_state();
  const double P = 2.0 * kPi * std::sqrt(std::pow(7000.0, 3) / kMu);
  Dop853Settings s;
  s.rtol = 1e-12;
  s.atol = 1e-12;
  const Vec6 x = run6(x0, {10.0 * P}, s)[0];
  auto energy = [](const Vec6& y) { return 0.5 * y.tail<3>().squaredNorm() - kMu / y.head<3>().norm(); };
  auto hvec = [](const Vec6& y) { return Vec3(y.head<3>().cross(y.tail<3>())); };
  EXPECT_LT(rel_err(energy(x), energy(x0)), 1e-11);
  EXPECT_LT(rel_err(hvec(x), hvec(x0)), 1e-11);
}

TEST(Dop853, MaxStepsStatusKeepsReachedOutputs) {
  const Vec6 x0 = leo_state();
  Dop853Settings s;
  s.rtol = 1e-12;
  s.atol = 1e-12;
  s.max_steps = 5;
  const auto tr = propagate_dop853_with<false>(PointMass{}, x0, 0.0, {1.0, 86400.0}, s, false);
  EXPECT_EQ(tr.status, PropagationStatus::too_much_work);
  EXPECT_EQ(tr.states.size(), 1u);
  EXPECT_EQ(tr.times.size(), 1u);
  EXPECT_GT(tr.t_reached, 1.0);
  EXPECT_LT(tr.t_reached, 86400.0);
  EXPECT_NE(tr.message.find("max_steps"), std::string::npos) << tr.message;
  EXPECT_NE(tr.message.find("reached t ="), std::string::npos) << tr.message;
}

TEST(Dop853, RhsFailureIsReported) {
  // Collision course: radial fall into the centre; the derivative becomes non-finite at r = 0.
  Vec6 x0;
  x0 << 7000.0, 0.0, 0.0, 0.0, 0.0, 0.0;
  Dop853Settings s;
  const auto tr = propagate_dop853_with<false>(PointMass{}, x0, 0.0, {3000.0}, s, false);
  EXPECT_NE(tr.status, PropagationStatus::success);
  EXPECT_LT(tr.t_reached, 3000.0);
  EXPECT_FALSE(tr.message.empty());
  for (const auto& x : tr.states) EXPECT_TRUE(x.allFinite());
}

TEST(Dop853, SteppingLoopDoesNotAllocate) {
  using Rhs = satgnc::propagation::detail::OrbitRhs<true, false, PointMass>;
  const PointMass pm;
  Rhs rhs{pm};
  Dop853Settings s;
  s.rtol = 1e-10;
  s.atol = 1e-10;
  Dop853<42, Rhs> integ(rhs, s);
  Eigen::Matrix<double, 42, 1> y0;
  y0.head<6>() = leo_state();
  Eigen::Map<Mat6>(y0.data() + 6).setIdentity();
  std::array<double, 4> times = {600.0, 1800.0, 3600.0, 7200.0};
  std::array<Vec6, 4> out;
  g_mallocs = 0;
  g_count = true;
  Eigen::internal::set_is_malloc_allowed(false);
  const Dop853Info info = integ.solve(
      0.0, y0, times.data(), times.size(),
      [&](std::size_t i, double, const Eigen::Matrix<double, 42, 1>& y) { out[i] = y.head<6>(); });
  Eigen::internal::set_is_malloc_allowed(true);
  g_count = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_EQ(info.status, Dop853Status::success);
  EXPECT_GT(info.steps, 10);
  EXPECT_LT((out[3] - kepler(leo_state(), 7200.0)).head<3>().norm(), 1e-4);
  // The counter does count: a std::vector allocation is seen.
  g_mallocs = 0;
  g_count = true;
  std::vector<double> probe(10);
  g_count = false;
#if !defined(__SANITIZE_ADDRESS__)
  EXPECT_GT(g_mallocs.load(), 0);
#endif
}

TEST(Dop853BadInput, CoreReturnsStatus) {
  TwoBody6 rhs;
  const Vec6 x0 = leo_state();
  const double t1 = 100.0;
  auto status_with = [&](Dop853Settings s, double t0, const Vec6& y0, std::vector<double> ts) {
    Dop853<6, TwoBody6> integ(rhs, s);
    return integ.solve(t0, y0, ts.data(), ts.size(), [](std::size_t, double, const Vec6&) {}).status;
  };
  // invalid settings throw at setup (the constructor), naming the field; solve() never sees them
  auto throws_naming = [&](Dop853Settings s, const std::string& field) {
    try {
      Dop853<6, TwoBody6> integ(rhs, s);
      ADD_FAILURE() << "no throw for " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind(field + ": ", 0), 0u) << e.what();
    }
  };
  Dop853Settings bad;
  bad.rtol = 0.0;
  throws_naming(bad, "rtol");
  bad.rtol = -1e-9;
  throws_naming(bad, "rtol");
  bad = Dop853Settings{};
  bad.atol = -1.0;
  throws_naming(bad, "atol");
  bad = Dop853Settings{};
  bad.max_steps = 0;
  throws_naming(bad, "max_steps");
  bad = Dop853Settings{};
  bad.beta = 0.5;
  throws_naming(bad, "beta");
  bad = Dop853Settings{};
  bad.rtol = 1.0;  // the integrator's own range allows a fixed-step run (the order test uses it)
  EXPECT_NO_THROW((Dop853<6, TwoBody6>(rhs, bad)));
  EXPECT_EQ(status_with(Dop853Settings{}, 0.0, x0, {t1}), Dop853Status::success);
  Vec6 nan_state = x0;
  nan_state(2) = NAN;
  EXPECT_EQ(status_with(Dop853Settings{}, 0.0, nan_state, {t1}), Dop853Status::invalid_input);
  EXPECT_EQ(status_with(Dop853Settings{}, 0.0, x0, {NAN}), Dop853Status::invalid_input);
  EXPECT_EQ(status_with(Dop853Settings{}, 0.0, x0, {100.0, 50.0}), Dop853Status::invalid_input);
  EXPECT_EQ(status_with(Dop853Settings{}, 0.0, x0, {100.0, -50.0}), Dop853Status::invalid_input);
  EXPECT_STREQ(satgnc::propagation::status_message(Dop853Status::max_steps),
               "step budget (max_steps) exhausted before the last output time");
}

// The event (surface) path: the same impact as the analytic Kepler room's root search, the outputs
// before it only, and no allocation in the stepping loop with the event either.
TEST(Dop853, SurfaceEventStopsAtTheKeplerImpactTime) {
  Vec6 x0;
  x0 << 6600.0, 0, 0, -3.0, 5.0, 1.0;  // perigee below the surface
  const double R = 6378.1363, mu = 398600.4418;
  const std::vector<double> times = {30.0, 60.0, 3000.0};
  const auto ref = satgnc::propagation::propagate_kepler(x0, 0.0, times, mu, true, R);
  ASSERT_EQ(ref.status, satgnc::propagation::PropagationStatus::impact);
  for (bool stm : {true, false}) {
    const auto tr = propagate_dop853_with<false>(PointMass{}, x0, 0.0, times, Dop853Settings{}, stm, R);
    EXPECT_EQ(tr.status, satgnc::propagation::PropagationStatus::impact);
    EXPECT_NEAR(tr.t_reached, ref.t_reached, 1e-6);  // bisection on the 7th-order dense output
    ASSERT_EQ(tr.states.size(), 2u);
    EXPECT_LT((tr.states[1] - ref.states[1]).norm(), 1e-6);
    EXPECT_NE(tr.message.find("impact at t = "), std::string::npos);
  }
  using Rhs = satgnc::propagation::detail::OrbitRhs<false, false, PointMass>;
  const PointMass pm;
  Rhs rhs{pm};
  Dop853<6, Rhs> integ(rhs, Dop853Settings{});
  std::array<double, 2> ts = {60.0, 3000.0};
  g_mallocs = 0;
  g_count = true;
  Eigen::internal::set_is_malloc_allowed(false);
  const Dop853Info info = integ.solve(
      0.0, x0, ts.data(), ts.size(), [](std::size_t, double, const Vec6&) {},
      [R](double, const Vec6& y) { return y.head<3>().squaredNorm() - R * R; });
  Eigen::internal::set_is_malloc_allowed(true);
  g_count = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_EQ(info.status, Dop853Status::event);
  EXPECT_EQ(info.outputs, 1u);
  EXPECT_NEAR(info.t_reached, ref.t_reached, 1e-6);
  // Starting at or below the surface, and a negative radius, are errors naming the argument.
  Vec6 inside = x0;
  inside.head<3>() *= 0.9;
  for (auto [x, r, needle] : {std::tuple<Vec6, double, std::string>{inside, R, "x0: starts at or below"},
                              std::tuple<Vec6, double, std::string>{x0, -1.0, "surface_radius:"}}) {
    try {
      propagate_dop853_with<false>(PointMass{}, x, 0.0, times, Dop853Settings{}, true, r);
      ADD_FAILURE() << "no throw, expected " << needle;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  }
}

TEST(Dop853BadInput, OrbitalWrapperThrowsNamingTheArgument) {
  const Vec6 good = leo_state();
  auto expect_throw = [&](const Vec6& x0, double t0, const std::vector<double>& ts, const Dop853Settings& s,
                          const std::string& needle) {
    try {
      propagate_dop853_with<false>(PointMass{}, x0, t0, ts, s, true);
      ADD_FAILURE() << "no throw, expected " << needle;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  const Dop853Settings ok;
  Vec6 zero_r = good;
  zero_r.head<3>().setZero();
  Vec6 inf_v = good;
  inf_v(5) = INFINITY;
  expect_throw(zero_r, 0.0, {60.0}, ok, "x0: position must be non-zero");
  expect_throw(inf_v, 0.0, {60.0}, ok, "x0: must be finite");
  expect_throw(good, NAN, {60.0}, ok, "t0: must be finite");
  expect_throw(good, 0.0, {60.0, NAN}, ok, "times: must be finite");
  expect_throw(good, 0.0, {60.0, 30.0, 90.0}, ok, "times: must be monotone");
  Dop853Settings s = ok;
  s.rtol = 0.0;
  expect_throw(good, 0.0, {60.0}, s, "rtol: must be finite and > 0");
  s.rtol = -1.0;
  expect_throw(good, 0.0, {60.0}, s, "rtol: must be finite and > 0");
  s.rtol = 1e-16;
  expect_throw(good, 0.0, {60.0}, s, "rtol: must exceed 10 machine epsilons");
  s = ok;
  s.atol = -1e-9;
  expect_throw(good, 0.0, {60.0}, s, "atol: must be finite and >= 0");
  s = ok;
  s.max_steps = 0;
  expect_throw(good, 0.0, {60.0}, s, "max_steps: must be > 0");
  s = ok;
  s.h0 = NAN;
  expect_throw(good, 0.0, {60.0}, s, "h0: must be finite and >= 0");
}

namespace {

satgnc::dynamics::ForceModel j2_drag_model() {
  satgnc::dynamics::ForceModel fm;
  fm.j2 = satgnc::dynamics::J2Gravity{};
  satgnc::dynamics::ExponentialDrag d;
  d.rho0 = 1e-11;  // kg/m^3 near 600 km (exaggerated area/mass so that drag shows in the STM)
  d.h0 = 600.0;
  d.scale_height = 70.0;
  d.area = 10.0;
  d.mass = 100.0;
  fm.drag = d;
  return fm;
}

}  // namespace

TEST(Dop853ForceModel, PointMassModelEqualsTestLocalGravity) {
  const Vec6 x0 = leo_state();
  Dop853Settings s;
  s.rtol = 1e-11;
  s.atol = 1e-11;
  const std::vector<double> times = {-600.0, 3000.0, 7200.0};
  const auto a =
      satgnc::propagation::propagate_dop853(satgnc::dynamics::ForceModel{}, x0, 0.0, times, s, true);
  const auto b = propagate_dop853_with<false>(PointMass{}, x0, 0.0, times, s, true);
  ASSERT_EQ(a.status, PropagationStatus::success) << a.message;
  for (std::size_t i = 0; i < times.size(); ++i) {
    EXPECT_LT(rel_err(a.states[i], b.states[i]), 1e-13);
    EXPECT_LT(block_rel_err(a.stms[i], b.stms[i]), 1e-11);
  }
  EXPECT_EQ(a.stats.steps, b.stats.steps);
}

TEST(Dop853ForceModel, J2DragStmMatchesCentralDifferences) {
  // Variational equations with the force model's analytic Jacobians (da/dr and the drag's da/dv)
  // against central differences of the integrated state (tight tolerance keeps the FD noise low).
  const auto fm = j2_drag_model();
  const Vec6 x0 = leo_state();
  Dop853Settings s;
  s.rtol = 1e-13;
  s.atol = 1e-13;
  const double T = 3600.0;
  const auto tr = satgnc::propagation::propagate_dop853(fm, x0, 0.0, {T}, s, true);
  ASSERT_EQ(tr.status, PropagationStatus::success) << tr.message;
  Mat6 fd;
  for (int k = 0; k < 6; ++k) {
    const double h = k < 3 ? 1e-3 : 1e-6;  // 1 m, 1 mm/s
    Vec6 xp = x0, xm = x0;
    xp(k) += h;
    xm(k) -= h;
    const auto p = satgnc::propagation::propagate_dop853(fm, xp, 0.0, {T}, s, false);
    const auto m = satgnc::propagation::propagate_dop853(fm, xm, 0.0, {T}, s, false);
    fd.col(k) = (p.states[0] - m.states[0]) / (2.0 * h);
  }
  const double e = block_rel_err(tr.stms[0], fd);
  std::printf("[j2+drag stm] block rel err vs FD %.2e\n", e);
  EXPECT_LT(e, 1e-7);
  // With drag the flow is not symplectic but still invertible; det(Phi) = exp(int tr(da/dv)) < 1.
  EXPECT_LT(tr.stms[0].determinant(), 1.0);
  EXPECT_GT(tr.stms[0].determinant(), 0.9);
}

TEST(Dop853ForceModel, InvalidForceModelThrows) {
  satgnc::dynamics::ForceModel fm;
  fm.mu = -1.0;
  try {
    satgnc::propagation::propagate_dop853(fm, leo_state(), 0.0, {60.0}, Dop853Settings{}, true);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mu"), std::string::npos) << e.what();
  }
}
