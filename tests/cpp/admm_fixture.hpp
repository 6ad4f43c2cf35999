#pragma once
// Problem builders shared by the ADMM tests (test_admm.cpp, test_admm_golden.cpp,
// test_admm_update.cpp). The draws are pinned: test_admm_golden compares against
// tests/cpp/data/admm_golden.txt, so the order of the random draws below must not change.
#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "satgnc/dynamics/cw.hpp"
#include "satgnc/guidance/admm.hpp"

namespace satgnc_test {

/// The linear scenario of l1_scenario.md in the implementation's scaled units (lengths in l_ref m,
/// velocities in v_ref m/s, time in t_ref s, acceleration in u_ref m/s^2 before the 4.6 factor).
struct AdmmScenario {
  double l_ref, v_ref, t_ref, u_ref, dt, n;
  Eigen::VectorXd x0;
};

inline AdmmScenario admm_scenario() {
  AdmmScenario s;
  const Eigen::Vector3d p(-9477.311, -1999.979, -43.046), v(-3.477486, 1.007149, -0.090170);
  s.l_ref = p.norm();
  s.v_ref = v.norm();
  s.t_ref = s.l_ref / s.v_ref;
  s.u_ref = s.l_ref / (s.t_ref * s.t_ref) * 4.6;
  s.dt = 6000.0 / 99.0 / s.t_ref;
  s.n = std::sqrt(3.99e14 / std::pow(7231e3, 3)) * s.t_ref;
  s.x0.resize(6);
  s.x0 << p / s.l_ref, v / s.v_ref;
  return s;
}

/// The scenario as an LtvProblem (99 steps, midpoint-discretized CW). Qf / dt: the implementation
/// multiplies the ADMM penalty by dt inside the LQR step, which is the same as this terminal weight
/// with an unweighted penalty (see docs/guidance.md).
inline satgnc::guidance::LtvProblem admm_scenario_problem(bool box, bool terminal) {
  const AdmmScenario s = admm_scenario();
  const auto d = satgnc::dynamics::cw_discretize_midpoint(satgnc::dynamics::CwModel(s.n, 1.0), s.dt);
  satgnc::guidance::LtvProblem p;
  p.dynamics.A = {Eigen::MatrixXd(d.Ad)};
  p.dynamics.B = {Eigen::MatrixXd(d.Bd)};
  p.dynamics.horizon = 99;
  p.x0 = s.x0;
  p.xf = Eigen::VectorXd::Zero(6);
  p.Qf = 1000.0 / s.dt * Eigen::MatrixXd::Identity(6, 6);
  p.l1_weights = Eigen::VectorXd::Ones(3);
  if (box) {
    p.u_lower = Eigen::VectorXd::Constant(3, -5e-3 / s.u_ref);
    p.u_upper = Eigen::VectorXd::Constant(3, 5e-3 / s.u_ref);
  }
  p.terminal_equality = terminal;
  return p;
}

/// How random_ltv_problem draws the affine term and the stage cost.
enum class LtvDraw {
  /// one constant offset c drawn after the N (A_k, B_k); stage Q = 0.1 I
  kConstantOffset,
  /// (A_k, B_k, c_k) drawn together at each step; no stage Q
  kTimeVarying,
};

/// Seeded random LTV problem: A_k = I + 0.1 N(0,1), B_k = N(0,1), c = 0.01 N(0,1), x0 = N(0,1),
/// xf = 0, Qf = 100 I, L1 weights 1, optional box |u| <= 0.5, hard terminal state, and (group)
/// group-L2 weight 0.7 with the ball |u| <= 0.4 in place of the L1 weights.
inline satgnc::guidance::LtvProblem random_ltv_problem(int nx, int nu, int N, unsigned seed, bool box,
                                                       bool terminal, LtvDraw draw = LtvDraw::kConstantOffset,
                                                       bool group = false) {
  using Eigen::MatrixXd;
  using Eigen::VectorXd;
  std::mt19937 g(seed);
  std::normal_distribution<double> nd;
  auto rnd = [&](int r, int c) { return MatrixXd(MatrixXd::NullaryExpr(r, c, [&]() { return nd(g); })); };
  const bool time_varying = draw == LtvDraw::kTimeVarying;
  satgnc::guidance::LtvProblem p;
  for (int k = 0; k < N; ++k) {
    p.dynamics.A.push_back(MatrixXd::Identity(nx, nx) + 0.1 * rnd(nx, nx));
    p.dynamics.B.push_back(rnd(nx, nu));
    if (time_varying) p.dynamics.c.push_back(0.01 * rnd(nx, 1));
  }
  if (!time_varying) p.dynamics.c = {0.01 * rnd(nx, 1)};
  p.dynamics.horizon = N;
  p.x0 = rnd(nx, 1);
  p.xf = VectorXd::Zero(nx);
  p.Qf = 100.0 * MatrixXd::Identity(nx, nx);
  if (!time_varying) p.Q = 0.1 * MatrixXd::Identity(nx, nx);
  p.l1_weights = VectorXd::Constant(nu, 1.0);
  if (box) {
    p.u_lower = VectorXd::Constant(nu, -0.5);
    p.u_upper = VectorXd::Constant(nu, 0.5);
  }
  if (group) {
    p.l1_weights = VectorXd();
    p.group_l2_weight = 0.7;
    p.u_norm_max = 0.4;
  }
  p.terminal_equality = terminal;
  return p;
}

}  // namespace satgnc_test
