// The Fenchel dual bound of AdmmSolver (admm_gap.cpp): its exact maximizer over s (the concave
// piecewise quadratic D of L1 + box, detail/quadratic.hpp) against the optimality conditions of D and
// against the golden-section search it replaced, on seeded random CW problems and iterates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "../../cpp/src/guidance/detail/admm_workspace.hpp"  // private to the guidance room: tested here
#include "satgnc/dynamics/cw.hpp"
#include "satgnc/guidance/admm.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using satgnc::guidance::AdmmMethod;
using satgnc::guidance::AdmmSettings;
using satgnc::guidance::LtvProblem;
using satgnc::guidance::detail::AdmmWorkspace;
using satgnc::guidance::detail::concave_pwq_argmax;
using satgnc::guidance::detail::PwlBreak;

namespace {

// D'(s) just below (right = false) or above (right = true) s.
double derivative(double c, double e, double a, double b, const std::vector<PwlBreak>& br, double s,
                  bool right) {
  double g = a + b * s;
  for (const PwlBreak& x : br)
    if (x.t < s || (right && x.t == s)) g += x.da + x.db * s;
  return c - e * s - g;
}

// Seeded CW problem like the Python suite's families: per-axis weights, a box (symmetric, one-sided,
// or excluding 0), a hard terminal state, R (QP or L1 + R), stage Q, an axis of zero weight.
LtvProblem cw_problem(std::mt19937& gen, int family) {
  std::uniform_real_distribution<double> ud(0.0, 1.0);
  const auto lu = [&](double lo, double hi) { return lo * std::pow(hi / lo, ud(gen)); };
  const double n = std::sqrt(3.986004418e14 / std::pow(6378.137e3 + lu(300e3, 36000e3), 3));
  const double dt = lu(10.0, 300.0);
  const int N = 3 + static_cast<int>(ud(gen) * 60.0);
  const auto d = satgnc::dynamics::cw_discretize_zoh(satgnc::dynamics::CwModel(n, 1.0), dt);
  LtvProblem p;
  p.dynamics.A = {MatrixXd(d.Ad)};
  p.dynamics.B = {MatrixXd(d.Bd)};
  p.dynamics.horizon = N;
  const double pos = lu(0.1, 1e4), T = N * dt;
  p.x0 = VectorXd(6);
  for (int i = 0; i < 3; ++i) p.x0(i) = pos * (2.0 * ud(gen) - 1.0);
  for (int i = 3; i < 6; ++i) p.x0(i) = pos / T * lu(0.1, 3.0) * (2.0 * ud(gen) - 1.0);
  p.xf = VectorXd::Zero(6);
  p.Qf = lu(1e-3, 1e3) * MatrixXd::Identity(6, 6);
  p.l1_weights = VectorXd(3);
  for (int i = 0; i < 3; ++i) p.l1_weights(i) = lu(0.1, 10.0);
  const double umag = pos / (T * T);
  switch (family) {
    case 0:  // plain L1
      break;
    case 1:  // symmetric box
      p.u_lower = VectorXd::Constant(3, -lu(0.3, 30.0) * umag);
      p.u_upper = -p.u_lower;
      break;
    case 2:  // one-sided thrusters and a box that excludes 0 on one axis
      p.u_lower = VectorXd::Constant(3, -lu(0.3, 30.0) * umag);
      p.u_upper = VectorXd::Constant(3, lu(0.3, 30.0) * umag);
      p.u_lower(0) = 0.0;
      p.u_lower(2) = 0.1 * p.u_upper(2);
      break;
    case 3:  // hard terminal state, box
      p.terminal_equality = true;
      p.u_lower = VectorXd::Constant(3, -lu(3.0, 30.0) * umag);
      p.u_upper = -p.u_lower;
      break;
    case 4:  // QP: R > 0, no L1, with a box
      p.l1_weights.setZero();
      p.R = (lu(1e-3, 1e3) * VectorXd::Ones(3)).asDiagonal();
      p.u_lower = VectorXd::Constant(3, -lu(0.3, 30.0) * umag);
      p.u_upper = -p.u_lower;
      break;
    case 5:  // L1 + R, one axis of zero weight with a box
      p.R = (lu(1e-3, 1e3) * VectorXd::Ones(3)).asDiagonal();
      p.l1_weights(1) = 0.0;
      p.u_lower = VectorXd::Constant(3, -lu(0.3, 30.0) * umag);
      p.u_upper = VectorXd::Constant(3, std::numeric_limits<double>::infinity());
      break;
    default:  // stage Q, hard terminal state, no box
      p.Q = lu(1e-6, 1e-2) * MatrixXd::Identity(6, 6);
      p.terminal_equality = true;
      break;
  }
  return p;
}

}  // namespace

TEST(PwqArgmax, SatisfiesTheOptimalityConditionsOfD) {
  std::mt19937 gen(41);
  std::uniform_real_distribution<double> ud(0.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = static_cast<int>(ud(gen) * 40.0);
    const double smax = 0.5 + 2.0 * ud(gen);
    std::vector<PwlBreak> br;
    for (int j = 0; j < n; ++j) {
      // a jump, or a ramp of slope k over [t1, t2] (its end a break of negative slope change)
      double t1 = smax * ud(gen);
      if (trial % 5 == 0) t1 = 0.25 * smax * std::floor(4.0 * ud(gen) + 0.5);  // ties
      if (t1 <= 0.0 || t1 >= smax) continue;
      if (ud(gen) < 0.5) {
        br.push_back({t1, 3.0 * ud(gen), 0.0});
      } else {
        const double k = 5.0 * ud(gen), t2 = t1 + smax * ud(gen);
        br.push_back({t1, -k * t1, k});
        if (t2 < smax) br.push_back({t2, k * t2, -k});
      }
    }
    const double e = trial % 3 == 0 ? 0.0 : 4.0 * ud(gen), a = 2.0 * ud(gen) - 1.0;
    const double b = trial % 4 == 0 ? 2.0 * ud(gen) : 0.0, c = 10.0 * ud(gen) - 2.0;
    std::vector<PwlBreak> work = br;
    const double s = concave_pwq_argmax(c, e, a, b, work.data(), static_cast<int>(work.size()), smax);
    ASSERT_GE(s, 0.0);
    ASSERT_LE(s, smax);
    const double tol = 1e-9 * (std::abs(c) + 1.0 + 100.0 * (e + b + 10.0));
    if (s > 0.0) {
      EXPECT_GE(derivative(c, e, a, b, br, s, false), -tol) << trial;  // no ascent to the left
    }
    if (s < smax) {
      EXPECT_LE(derivative(c, e, a, b, br, s, true), tol) << trial;  // nor to the right
    }
  }
}

TEST(AdmmDualBound, ExactMaximizerIsAtLeastTheGoldenSection) {
  // D(s) is concave for any plan (X, U) and multiplier p: both maximizers are compared on ADMM's
  // iterates after 1-40 iterations (near the optimum, where s ~ 1 and the bound certifies), on
  // random plans and on the certified plan, in the solver's scaled units.
  std::mt19937 gen(43);
  std::normal_distribution<double> nd(0.0, 1.0);
  int compared = 0, better = 0;
  for (int trial = 0; trial < 140; ++trial) {
    const LtvProblem p = cw_problem(gen, trial % 7);
    for (int budget : {1, 4, 15, 40, 1000}) {
      AdmmSettings st;
      st.max_iterations = budget;
      st.method = budget == 1000 ? AdmmMethod::kAdmmIpm : AdmmMethod::kAdmm;
      AdmmWorkspace ws(p, st);
      ws.solve();
      const int N = p.dynamics.horizon;
      MatrixXd U = ws.du_.cwiseInverse().asDiagonal() * ws.res_.U, X(6, N + 1);
      for (int variant = 0; variant < 2; ++variant) {
        if (variant == 1)
          for (int j = 0; j < U.size(); ++j) U.data()[j] *= 1.0 + 0.3 * nd(gen);
        ws.rollout(U, X);
        VectorXd pm = VectorXd::Zero(6);
        if (p.terminal_equality)
          for (int i = 0; i < 6; ++i) pm(i) = nd(gen) * ws.prob_.Qf(i, i) * (X(i, N) - ws.prob_.xf(i));
        const double golden = ws.dual_bound(X, U, pm, true);
        const double exact = ws.dual_bound(X, U, pm, false);
        const double P = ws.trajectory_objective(X, U);
        ASSERT_TRUE(std::isfinite(exact) || exact == golden) << trial;
        EXPECT_GE(exact, golden - 1e-13 * std::max({std::abs(golden), std::abs(P), 1e-300}))
            << "trial " << trial << " budget " << budget << " variant " << variant;
        if (p.R.size() != 0) EXPECT_EQ(exact, golden) << trial;  // R in g keeps the golden section
        ++compared;
        better += exact > golden;
      }
    }
  }
  EXPECT_EQ(compared, 140 * 5 * 2);
  EXPECT_GT(better, 100);  // 197 of the 1400: where the search stopped short of the maximum
}
