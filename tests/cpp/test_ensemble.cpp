// Ensemble propagation: member-by-member identity with propagate_dop853, thread-count independence,
// per-member statuses (one bad member never poisons the others), bad input naming the argument, no
// allocation in a reused propagate(), and the default tolerances' 1 mm per LEO day.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "error_checks.hpp"
#include "malloc_counter.hpp"
#include "satgnc/propagation/dop853.hpp"
#include "satgnc/propagation/ensemble.hpp"
#include "satgnc/propagation/kepler.hpp"

namespace {

using satgnc::Mat6;
using satgnc::Vec6;
using satgnc::dynamics::ForceModel;
using satgnc::dynamics::J2Gravity;
using satgnc::propagation::EnsemblePropagator;
using satgnc::propagation::EnsembleResult;
using satgnc::propagation::EnsembleSettings;
using satgnc::propagation::PropagationStatus;
using satgnc::testing::message_of;

constexpr double kRe = 6378.1363;

Vec6 leo(double da, double dv) {  // 400 km, e ~ 0.001, i = 51.6 deg, dispersed in r_x and v_y
  Vec6 x;
  x << 6778.137 + da, 0.0, 0.0, 0.0, 4.7302 + dv, 6.0354;
  return x;
}

std::vector<Vec6> dispersed(int K) {
  std::vector<Vec6> xs;
  for (int k = 0; k < K; ++k) xs.push_back(leo(0.7 * k - 5.0, 1e-4 * ((k * 7) % 11 - 5)));
  return xs;
}

ForceModel j2_model() {
  ForceModel fm;
  fm.j2 = J2Gravity();
  return fm;
}

bool same_bits(const double* a, const double* b, std::size_t n) {
  return std::memcmp(a, b, n * sizeof(double)) == 0;
}

std::vector<double> arc_times() { return {0.0, 1800.0, 3600.0, 7200.0}; }

// Without SIMD lanes each member runs propagate_dop853's exact arithmetic (same functor, same
// run_arc): bitwise equal.
TEST(Ensemble, ScalarMembersEqualSingleArcsBitwise) {
  for (const bool j2 : {false, true}) {
    const ForceModel fm = j2 ? j2_model() : ForceModel();
    const auto xs = dispersed(9);
    EnsembleSettings s;
    s.surface_radius = kRe;
    s.simd = false;
    EnsemblePropagator p(fm, s);
    const EnsembleResult r = p.propagate(xs, 0.0, arc_times());
    ASSERT_EQ(r.succeeded(), xs.size());
    const std::size_t n = arc_times().size();
    for (std::size_t k = 0; k < xs.size(); ++k) {
      const auto tr =
          satgnc::propagation::propagate_dop853(fm, xs[k], 0.0, arc_times(), s.integrator, true, kRe);
      ASSERT_EQ(tr.status, PropagationStatus::success);
      for (std::size_t i = 0; i < n; ++i) {
        EXPECT_TRUE(same_bits(r.states[k * n + i].data(), tr.states[i].data(), 6))
            << "member " << k << " t " << i;
        EXPECT_TRUE(same_bits(r.stms[k * n + i].data(), tr.stms[i].data(), 36))
            << "member " << k << " t " << i;
      }
      EXPECT_EQ(r.stats[k].steps, tr.stats.steps);
      EXPECT_EQ(r.outputs[k], n);
      EXPECT_TRUE(r.messages[k].empty());
    }
  }
}

// SIMD lanes: each lane runs Hairer's algorithm on its own member with its own step control; only the
// order of the error-norm sums and fused multiply-adds differ from the scalar path. Those last-bit
// differences can flip an accept/reject decision of the step-size controller (so can moving x0 by one
// ulp in the scalar path itself: measured 5.8e-9 km after 2 h, below), after which the two runs carry
// different truncation errors of the size of the integration error (~1e-8 km over 2 h at the default
// tolerances; measured up to 1.3e-8 km apart, both 8e-9 km from an rtol 1e-13 run). Bars: 5e-8 km,
// 5e-11 km/s, 1e-6 of the largest STM entry, accepted steps within 2. Covers the vectorized
// point-mass / J2 kernel and the generic lane-by-lane ForceModel call (drag).
TEST(Ensemble, SimdLanesAgreeWithSingleArcs) {
  satgnc::dynamics::ExponentialDrag drag;
  drag.rho0 = 3.725e-12;
  drag.h0 = 400.0;
  drag.scale_height = 58.515;
  drag.area = 10.0;
  drag.mass = 500.0;
  ForceModel with_drag = j2_model();
  with_drag.drag = drag;
  const std::vector<double> ts{0.0, 100.0, 1800.0, 3600.0, 5000.0, 7200.0};  // dense outputs too
  for (const ForceModel& fm : {ForceModel(), j2_model(), with_drag}) {
    for (const int variant : {0, 1, 2}) {  // STM + best kernel, no STM, STM + baseline (portable) kernel
      const bool stm = variant != 1;
      const auto xs = dispersed(13);  // one full batch of 8 and a partial one of 5
      EnsembleSettings s;
      s.with_stm = stm;
      s.simd_portable = variant == 2;
      const EnsembleResult r = EnsemblePropagator(fm, s).propagate(xs, 0.0, ts);
      ASSERT_EQ(r.succeeded(), xs.size());
      const std::size_t n = ts.size();
      for (std::size_t k = 0; k < xs.size(); ++k) {
        const auto tr = satgnc::propagation::propagate_dop853(fm, xs[k], 0.0, ts, s.integrator, stm, 0.0);
        for (std::size_t i = 0; i < n; ++i) {
          EXPECT_LT((r.states[k * n + i].head<3>() - tr.states[i].head<3>()).norm(), 5e-8) << k << " " << i;
          EXPECT_LT((r.states[k * n + i].tail<3>() - tr.states[i].tail<3>()).norm(), 5e-11) << k << " " << i;
          if (stm) {
            const double scale = tr.stms[i].cwiseAbs().maxCoeff();
            EXPECT_LT((r.stms[k * n + i] - tr.stms[i]).cwiseAbs().maxCoeff(), 1e-6 * scale) << k << " " << i;
          }
        }
        EXPECT_LE(std::abs(r.stats[k].steps - tr.stats.steps), 2) << k;
        EXPECT_EQ(r.outputs[k], n);
      }
    }
  }
}

// The yardstick of the test above: the scalar path itself, x0 moved by one ulp, over the same 2 h.
TEST(Ensemble, OneUlpSensitivityOfTheScalarPath) {
  EnsembleSettings s;
  s.simd = false;
  auto xs = dispersed(16);
  auto ys = xs;
  for (Vec6& y : ys) y[0] = std::nextafter(y[0], 1e300);
  EnsemblePropagator p(j2_model(), s);
  const EnsembleResult a = p.propagate(xs, 0.0, arc_times()), b = p.propagate(ys, 0.0, arc_times());
  double worst = 0.0;
  for (std::size_t i = 0; i < a.states.size(); ++i)
    worst = std::max(worst, (a.states[i].head<3>() - b.states[i].head<3>()).norm());
  // Not rounding-level (1e-12 km): a flipped step rejection changes the truncation errors.
  EXPECT_GT(worst, 1e-10);
  EXPECT_LT(worst, 5e-8);
}

// Threads only change which thread runs a member (or a batch of 8), never its arithmetic: 1 vs 2
// threads bitwise equal, with and without SIMD lanes.
TEST(Ensemble, OneAndTwoThreadsGiveTheSameNumbers) {
  for (const bool simd : {true, false}) {
    const auto xs = dispersed(33);
    EnsembleSettings s1, s2;
    s1.simd = simd;
    s2.simd = simd;
    s2.threads = 2;
    EnsemblePropagator p1(j2_model(), s1), p2(j2_model(), s2);
    EXPECT_EQ(p2.threads(), 2);
    const EnsembleResult a = p1.propagate(xs, 0.0, arc_times());
    const EnsembleResult b = p2.propagate(xs, 0.0, arc_times());
    ASSERT_EQ(a.states.size(), b.states.size());
    EXPECT_TRUE(same_bits(a.states[0].data(), b.states[0].data(), 6 * a.states.size()));
    EXPECT_TRUE(same_bits(a.stms[0].data(), b.stms[0].data(), 36 * a.stms.size()));
    // And a second call on the same pool (workers reused) gives them again.
    const EnsembleResult c = p2.propagate(xs, 0.0, arc_times());
    EXPECT_TRUE(same_bits(a.states[0].data(), c.states[0].data(), 6 * a.states.size()));
  }
}

// Bad members get their own status and message; the good ones are untouched (bitwise as alone).
TEST(Ensemble, BadMemberGetsItsOwnStatus) {
  auto xs = dispersed(6);
  Vec6 zero_r = xs[1];
  zero_r.head<3>().setZero();
  xs[1] = zero_r;                             // |r0| = 0
  xs[3] << 6000.0, 0.0, 0.0, 0.0, 7.0, 0.0;   // starts below the surface
  xs[4] << 6600.0, 0.0, 0.0, -3.0, 5.0, 1.0;  // perigee below the surface: impact
  for (const bool simd : {true, false}) {
    EnsembleSettings s;
    s.surface_radius = kRe;
    s.threads = 2;
    s.simd = simd;
    EnsemblePropagator p(j2_model(), s);
    const std::vector<double> ts{0.0, 30.0, 7200.0};
    const EnsembleResult r = p.propagate(xs, 0.0, ts);
    EXPECT_EQ(r.status[1], PropagationStatus::rhs_failure);
    EXPECT_NE(r.messages[1].find("member 1: |r0| = 0"), std::string::npos) << r.messages[1];
    EXPECT_EQ(r.outputs[1], 0u);
    EXPECT_TRUE(std::isnan(r.states[1 * 3 + 0][0]));
    EXPECT_EQ(r.status[3], PropagationStatus::impact);
    EXPECT_NE(r.messages[3].find("starts at or below the surface"), std::string::npos) << r.messages[3];
    EXPECT_EQ(r.status[4], PropagationStatus::impact);
    EXPECT_NE(r.messages[4].find("member 4: impact at t = "), std::string::npos) << r.messages[4];
    // Impact after 30 s (measured 69.7 s for this dive): the outputs at 0 s and 30 s are kept.
    EXPECT_EQ(r.outputs[4], 2u);
    EXPECT_GT(r.t_reached[4], 30.0);
    EXPECT_LT(r.t_reached[4], 100.0);
    EXPECT_TRUE(std::isnan(r.states[4 * 3 + 2][0]));
    EXPECT_EQ(r.succeeded(), 3u);
    // The failed members were re-run by the scalar path: the impact time is the single arc's, exactly.
    const auto dive =
        satgnc::propagation::propagate_dop853(j2_model(), xs[4], 0.0, ts, s.integrator, true, kRe);
    EXPECT_EQ(r.t_reached[4], dive.t_reached);
    for (std::size_t k : {0u, 2u, 5u}) {
      EXPECT_EQ(r.status[k], PropagationStatus::success);
      const auto tr =
          satgnc::propagation::propagate_dop853(j2_model(), xs[k], 0.0, ts, s.integrator, true, kRe);
      if (!simd) EXPECT_TRUE(same_bits(r.states[k * 3 + 2].data(), tr.states[2].data(), 6)) << k;
      EXPECT_LT((r.states[k * 3 + 2] - tr.states[2]).norm(), 5e-8) << k;  // km; see SimdLanesAgree...
    }
    // A member running out of its step budget: too_much_work, the others still succeed.
    EnsembleSettings tight = s;
    tight.integrator.max_steps = 40;  // a 2 h J2 arc needs ~100 steps at the default tolerances
    const EnsembleResult q = EnsemblePropagator(j2_model(), tight).propagate(dispersed(2), 0.0, {0.0, 60.0});
    EXPECT_EQ(q.succeeded(), 2u);
    const EnsembleResult w = EnsemblePropagator(j2_model(), tight).propagate(dispersed(2), 0.0, ts);
    EXPECT_EQ(w.status[0], PropagationStatus::too_much_work);
    EXPECT_NE(w.messages[0].find("step budget"), std::string::npos) << w.messages[0];
  }
}

TEST(Ensemble, BadInputNamesTheArgument) {
  EnsemblePropagator p(ForceModel{}, EnsembleSettings{});
  const auto ts = arc_times();
  EXPECT_EQ(
      message_of([&] { p.propagate(std::vector<Vec6>{}, 0.0, ts); }).rfind("x0: must hold at least one", 0),
      0u);
  auto xs = dispersed(3);
  xs[2][4] = NAN;
  EXPECT_EQ(message_of([&] { p.propagate(xs, 0.0, ts); }).rfind("x0[2]: must be finite", 0), 0u);
  xs[2][4] = 1e200;
  EXPECT_EQ(message_of([&] { p.propagate(xs, 0.0, ts); }).rfind("x0[2]: every component", 0), 0u);
  EXPECT_EQ(message_of([&] { p.propagate(dispersed(2), NAN, ts); }).rfind("t0: must be finite", 0), 0u);
  EXPECT_EQ(message_of([&] { p.propagate(dispersed(2), 0.0, {}); }).rfind("times: must not be empty", 0), 0u);
  EXPECT_EQ(message_of([&] { p.propagate(dispersed(2), 0.0, {10.0, 5.0}); }).rfind("times:", 0), 0u);
  EnsembleSettings s;
  s.threads = 0;
  EXPECT_EQ(
      message_of([&] { EnsemblePropagator(ForceModel{}, s); }).rfind("threads: must lie in [1, 256]", 0), 0u);
  s.threads = 1;
  s.integrator.rtol = -1.0;
  EXPECT_EQ(message_of([&] { EnsemblePropagator(ForceModel{}, s); }).rfind("rtol:", 0), 0u);
  s.integrator.rtol = 1e-10;
  s.surface_radius = -1.0;
  EXPECT_EQ(message_of([&] { EnsemblePropagator(ForceModel{}, s); }).rfind("surface_radius:", 0), 0u);
}

// A reused propagate() into a result with capacity allocates nothing (threads = 1 and 2).
TEST(Ensemble, ReusedPropagateDoesNotAllocate) {
  const auto xs = dispersed(8);
  for (int threads : {1, 2}) {
    for (const bool simd : {true, false}) {
      EnsembleSettings s;
      s.threads = threads;
      s.simd = simd;
      EnsemblePropagator p(j2_model(), s);
      EnsembleResult out;
      const auto ts = arc_times();
      p.propagate(xs.data(), xs.size(), 0.0, ts, out);
      g_mallocs = 0;
      g_count = true;
      p.propagate(xs.data(), xs.size(), 0.0, ts, out);
      g_count = false;
      EXPECT_EQ(g_mallocs.load(), 0) << threads << " threads, simd " << simd;
      EXPECT_EQ(out.succeeded(), xs.size());
    }
  }
}

// The default tolerances (kDefaultOrbitRtol / kDefaultOrbitAtol) meet 1 mm per day on LEO orbits
// against the analytic two-body solution, with and without the STM (bench/propagation_defaults.py
// measures 0.2-0.75 mm on these orbits; the bar is the 1 mm).
TEST(Ensemble, DefaultTolerancesMeetOneMillimetrePerLeoDay) {
  std::vector<Vec6> xs;
  xs.push_back(leo(0.0, 0.0));
  Vec6 x;
  x << 6678.137, 0.0, 0.0, 0.0, 1.0, 7.66;  // ~300 km, near-polar
  xs.push_back(x);
  std::vector<double> ts;
  for (int h = 0; h <= 24; ++h) ts.push_back(3600.0 * h);
  for (const bool stm : {true, false}) {
    EnsembleSettings s;
    s.with_stm = stm;
    const EnsembleResult r = EnsemblePropagator(ForceModel{}, s).propagate(xs, 0.0, ts);
    ASSERT_EQ(r.succeeded(), xs.size());
    for (std::size_t k = 0; k < xs.size(); ++k) {
      double worst = 0.0;
      for (std::size_t i = 0; i < ts.size(); ++i) {
        Vec6 ref;
        ASSERT_EQ(satgnc::propagation::kepler_step(xs[k], ts[i], satgnc::dynamics::earth::mu, ref, nullptr),
                  satgnc::propagation::KeplerStatus::success);
        worst = std::max(worst, (r.states[k * ts.size() + i].head<3>() - ref.head<3>()).norm());
      }
      EXPECT_LT(worst, 1e-6) << "member " << k << " stm " << stm;  // km: 1 mm per day
    }
  }
}

}  // namespace
