// The interior-point method of the L1 solver (AdmmSettings::method, admm_ipm.cpp) on small seeded
// random problems, checked independently: soft terminal state against a dense proximal-gradient
// (FISTA) optimum of the condensed problem; hard terminal state by the dense KKT conditions with the
// returned multiplier; the zero-L1 QP against its closed-form optimum. Also the endgame's statuses
// and the no-allocation guard of the IPM path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "malloc_counter.hpp"
#include "satgnc/dynamics/cw.hpp"
#include "satgnc/guidance/admm.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using satgnc::guidance::AdmmMethod;
using satgnc::guidance::AdmmResult;
using satgnc::guidance::AdmmSettings;
using satgnc::guidance::AdmmSolver;
using satgnc::guidance::AdmmStatus;
using satgnc::guidance::LtvProblem;

namespace {
constexpr int kNx = 4, kNu = 2, kN = 6;

struct Variant {
  bool box = false, terminal = false, stage_q = false, r = false, r_full = false, l1 = true;
};

LtvProblem random_problem(std::mt19937& gen, const Variant& v) {
  std::normal_distribution<double> nd(0.0, 1.0);
  std::uniform_real_distribution<double> ud(0.5, 2.0);
  LtvProblem p;
  MatrixXd A = MatrixXd::Identity(kNx, kNx), B(kNx, kNu);
  for (int i = 0; i < kNx; ++i)
    for (int j = 0; j < kNx; ++j) A(i, j) += 0.2 * nd(gen);
  for (int i = 0; i < kNx; ++i)
    for (int j = 0; j < kNu; ++j) B(i, j) = nd(gen);
  p.dynamics.A = {A};
  p.dynamics.B = {B};
  p.dynamics.horizon = kN;
  p.x0 = VectorXd(kNx);
  for (int i = 0; i < kNx; ++i) p.x0(i) = 3.0 * nd(gen);
  p.xf = VectorXd::Zero(kNx);
  p.Qf = 10.0 * ud(gen) * MatrixXd::Identity(kNx, kNx);
  p.l1_weights = v.l1 ? VectorXd(Eigen::Vector2d(ud(gen), ud(gen))) : VectorXd::Zero(kNu);
  if (v.box) {
    p.u_lower = VectorXd::Constant(kNu, -0.8);
    p.u_upper = VectorXd::Constant(kNu, 0.6);
  }
  if (v.stage_q) p.Q = 0.3 * MatrixXd::Identity(kNx, kNx);
  if (v.r) {
    p.R = Eigen::Vector2d(ud(gen), ud(gen)).asDiagonal();
    if (v.r_full) p.R(0, 1) = p.R(1, 0) = 0.3;
  }
  p.terminal_equality = v.terminal;
  return p;
}

// Condensed data: x_k = F_k x0 + G_k vec(U), k = 0..N (G_k nx x N nu).
struct Dense {
  std::vector<MatrixXd> G;
  std::vector<VectorXd> F;
};
Dense condense(const LtvProblem& p) {
  Dense d;
  const MatrixXd& A = p.dynamics.A[0];
  const MatrixXd& B = p.dynamics.B[0];
  d.G.assign(kN + 1, MatrixXd::Zero(kNx, kN * kNu));
  d.F.assign(kN + 1, p.x0);
  for (int k = 0; k < kN; ++k) {
    d.F[k + 1] = A * d.F[k];
    d.G[k + 1] = A * d.G[k];
    d.G[k + 1].middleCols(k * kNu, kNu) += B;
  }
  return d;
}

// Smooth part f(U) = 1/2 u' H u + h' u + const of the condensed problem.
void smooth_quadratic(const LtvProblem& p, const Dense& d, MatrixXd& H, VectorXd& h) {
  const int n = kN * kNu;
  H = d.G[kN].transpose() * p.Qf * d.G[kN];
  h = d.G[kN].transpose() * p.Qf * (d.F[kN] - p.xf);
  if (p.Q.size() != 0) {
    for (int k = 1; k < kN; ++k) {
      H += d.G[k].transpose() * p.Q * d.G[k];
      h += d.G[k].transpose() * p.Q * (d.F[k] - p.xf);
    }
  }
  if (p.R.size() != 0)
    for (int k = 0; k < kN; ++k) H.block(k * kNu, k * kNu, kNu, kNu) += p.R;
  (void)n;
}

double objective(const LtvProblem& p, const Dense& d, const VectorXd& u) {
  MatrixXd H;
  VectorXd h;
  smooth_quadratic(p, d, H, h);
  const VectorXd e = d.F[kN] - p.xf;
  double c = 0.5 * e.dot(p.Qf * e);
  if (p.Q.size() != 0)
    for (int k = 1; k < kN; ++k) c += 0.5 * (d.F[k] - p.xf).dot(p.Q * (d.F[k] - p.xf));
  double l1 = 0.0;
  for (int j = 0; j < u.size(); ++j) l1 += p.l1_weights(j % kNu) * std::abs(u(j));
  return 0.5 * u.dot(H * u) + h.dot(u) + c + l1;
}

// FISTA on the condensed soft-terminal problem: prox of w|.| + box in closed form.
VectorXd fista(const LtvProblem& p, const Dense& d) {
  MatrixXd H;
  VectorXd h;
  smooth_quadratic(p, d, H, h);
  const int n = static_cast<int>(h.size());
  const double L = Eigen::SelfAdjointEigenSolver<MatrixXd>(H).eigenvalues().maxCoeff();
  VectorXd x = VectorXd::Zero(n), y = x, xp = x;
  double t = 1.0;
  for (int it = 0; it < 200000; ++it) {
    const VectorXd g = H * y + h;
    for (int j = 0; j < n; ++j) {
      const double v = y(j) - g(j) / L, w = p.l1_weights(j % kNu) / L;
      double z = v > w ? v - w : (v < -w ? v + w : 0.0);
      if (p.u_lower.size() != 0) z = std::clamp(z, p.u_lower(j % kNu), p.u_upper(j % kNu));
      x(j) = z;
    }
    const double tn = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * t * t));
    y = x + (t - 1.0) / tn * (x - xp);
    if ((x - xp).cwiseAbs().maxCoeff() <= 1e-15 * std::max(1.0, x.cwiseAbs().maxCoeff()) && it > 10) break;
    xp = x;
    t = tn;
  }
  return x;
}

VectorXd vec(const MatrixXd& U) { return Eigen::Map<const VectorXd>(U.data(), U.size()); }

AdmmSettings ipm_settings() {
  AdmmSettings st;
  st.method = AdmmMethod::kIpm;
  return st;
}
}  // namespace

TEST(AdmmIpm, SoftTerminalMatchesDenseProximalGradient) {
  std::mt19937 gen(11);
  const Variant variants[] = {
      {false, false, false, false, false, true},  // plain L1
      {true, false, false, false, false, true},   // L1 + box
      {false, false, true, false, false, true},   // stage Q (Riccati recursion with Q)
      {true, false, false, true, false, true},    // R > 0 diagonal + L1 + box
      {false, false, true, true, true, true},     // general R + stage Q
      {true, false, false, true, false, false},   // zero-L1 QP with a box
  };
  int count = 0;
  for (const Variant& v : variants) {
    for (int rep = 0; rep < 4; ++rep, ++count) {
      const LtvProblem p = random_problem(gen, v);
      AdmmSolver s(p, ipm_settings());
      const AdmmResult& r = s.solve();
      const Dense d = condense(p);
      const double ref = objective(p, d, fista(p, d));
      ASSERT_EQ(r.info.status, AdmmStatus::solved) << count;
      EXPECT_TRUE(r.info.ipm_solved) << count;
      EXPECT_EQ(r.info.iterations, 0) << count;
      EXPECT_GT(r.info.ipm_iterations, 0) << count;
      EXPECT_LE(r.info.ipm_iterations, 40) << count;
      EXPECT_LE(r.info.duality_gap, 1e-5) << count;
      const double obj = objective(p, d, vec(r.Y));
      EXPECT_NEAR(obj, r.info.objective, 1e-9 * std::abs(ref)) << count;
      EXPECT_LE(std::abs(obj - ref), 1e-6 * std::abs(ref)) << count << " " << obj << " vs " << ref;
      if (v.box) {
        EXPECT_LE(r.Y.maxCoeff(), 0.6) << count;
        EXPECT_GE(r.Y.minCoeff(), -0.8) << count;
      }
    }
  }
}

TEST(AdmmIpm, HardTerminalSatisfiesDenseKkt) {
  std::mt19937 gen(12);
  const Variant variants[] = {
      {false, true, false, false, false, true},
      {true, true, false, false, false, true},
      {false, true, true, false, false, true},
      {false, true, false, true, true, true},
  };
  int count = 0, infeasible = 0;
  for (const Variant& v : variants) {
    for (int rep = 0; rep < 4; ++rep, ++count) {
      LtvProblem p = random_problem(gen, v);
      if (v.box) {
        p.u_lower = VectorXd::Constant(kNu, -5.0);
        p.u_upper = VectorXd::Constant(kNu, 5.0);
      }
      // a random unstable A may put x_f out of reach of the box: ADMM's Farkas check says so
      if (v.box && AdmmSolver(p).solve().info.status == AdmmStatus::primal_infeasible) {
        ++infeasible;
        continue;
      }
      // the dense KKT conditions at 1e-5 and x_N = x_f at 1e-8 |x0| test the IPM's converged point:
      // run to the former default ipm_tolerance 1e-9 (the default 1e-7 stops once the independent
      // gap test certifies eps_gap, with entries of order 1e-7 |U| where the optimum has zeros)
      AdmmSettings st = ipm_settings();
      st.ipm_tolerance = 1e-9;
      AdmmSolver s(p, st);
      const AdmmResult& r = s.solve();
      ASSERT_EQ(r.info.status, AdmmStatus::solved)
          << count << " ipm iterations " << r.info.ipm_iterations << " gap " << r.info.duality_gap << " miss "
          << r.info.terminal_miss;
      EXPECT_TRUE(r.info.ipm_solved) << count;
      const Dense d = condense(p);
      const VectorXd u = vec(r.Y);
      // terminal state met
      EXPECT_LE((d.F[kN] + d.G[kN] * u - p.xf).norm(), 1e-8 * p.x0.norm()) << count;
      // stationarity: grad f + G_N' p in -(w d|u| + normal cone of the box), entry by entry
      MatrixXd H;
      VectorXd h;
      smooth_quadratic(p, d, H, h);
      const VectorXd g = H * u + h + d.G[kN].transpose() * r.terminal_multiplier;
      const double umax = u.cwiseAbs().maxCoeff(), gmax = std::max(g.cwiseAbs().maxCoeff(), 1.0);
      for (int j = 0; j < u.size(); ++j) {
        const double w = p.l1_weights(j % kNu);
        const double tol = 1e-5 * gmax;
        const bool at_hi = v.box && u(j) >= p.u_upper(j % kNu) - 1e-7 * umax;
        const bool at_lo = v.box && u(j) <= p.u_lower(j % kNu) + 1e-7 * umax;
        if (at_hi) {
          EXPECT_LE(g(j) + w, tol) << count << " j " << j;
        } else if (at_lo) {
          EXPECT_GE(g(j) - w, -tol) << count << " j " << j;
        } else if (std::abs(u(j)) <= 1e-7 * umax) {
          EXPECT_LE(std::abs(g(j)), w + tol) << count << " j " << j;
        } else {
          EXPECT_NEAR(g(j), -w * (u(j) > 0.0 ? 1.0 : -1.0), tol) << count << " j " << j;
        }
      }
    }
  }
  EXPECT_LE(infeasible, 2);  // most box cases are feasible and checked
}

TEST(AdmmIpm, ZeroL1QpEqualsClosedForm) {
  std::mt19937 gen(13);
  for (bool terminal : {false, true}) {
    Variant v;
    v.l1 = false;
    v.r = true;
    v.terminal = terminal;
    const LtvProblem p = random_problem(gen, v);
    AdmmSolver s(p, ipm_settings());
    const AdmmResult& r = s.solve();
    ASSERT_EQ(r.info.status, AdmmStatus::solved);
    const Dense d = condense(p);
    MatrixXd H;
    VectorXd h;
    smooth_quadratic(p, d, H, h);
    VectorXd u;
    if (terminal) {  // [H G'; G 0] [u; p] = [-h; -(F_N - x_f)]
      const int n = static_cast<int>(h.size());
      MatrixXd K = MatrixXd::Zero(n + kNx, n + kNx);
      K.topLeftCorner(n, n) = H - d.G[kN].transpose() * p.Qf * d.G[kN];  // Qf e = 0 at x_N = x_f
      K.topRightCorner(n, kNx) = d.G[kN].transpose();
      K.bottomLeftCorner(kNx, n) = d.G[kN];
      VectorXd rhs(n + kNx);
      rhs << -(h - d.G[kN].transpose() * p.Qf * (d.F[kN] - p.xf)), -(d.F[kN] - p.xf);
      u = K.fullPivLu().solve(rhs).head(n);
    } else {
      u = -H.ldlt().solve(h);
    }
    EXPECT_LE((vec(r.Y) - u).cwiseAbs().maxCoeff(), 1e-7 * u.cwiseAbs().maxCoeff()) << terminal;
  }
}

TEST(AdmmIpm, EndgameStatusesAndMethods) {
  std::mt19937 gen(14);
  Variant v;
  v.box = true;
  const LtvProblem p = random_problem(gen, v);
  // ADMM alone never runs the IPM
  AdmmSettings st;
  st.method = AdmmMethod::kAdmm;
  AdmmSolver a(p, st);
  EXPECT_EQ(a.solve().info.ipm_iterations, 0);
  EXPECT_FALSE(a.result().info.ipm_solved);
  // the endgame at iteration 0 of a tiny budget: solved by the IPM, the gap test holds
  st.method = AdmmMethod::kAdmmIpm;
  st.ipm_after = 1;
  st.polish = false;
  AdmmSolver b(p, st);
  const AdmmResult& rb = b.solve();
  EXPECT_EQ(rb.info.status, AdmmStatus::solved);
  EXPECT_TRUE(rb.info.ipm_solved);
  EXPECT_EQ(rb.info.iterations, 1);
  EXPECT_LE(rb.info.duality_gap, st.eps_gap);
  // an IPM that cannot certify within its budget: ADMM goes on from where it was
  st.ipm_max_iterations = 1;
  st.max_iterations = 3;
  AdmmSolver c(p, st);
  const AdmmResult& rc = c.solve();
  EXPECT_FALSE(rc.info.ipm_solved);
  EXPECT_EQ(rc.info.ipm_iterations, 1);
  EXPECT_EQ(rc.info.iterations, 3);
  EXPECT_NE(rc.info.status, AdmmStatus::solved);
  // the IPM alone with too small a budget: not solved, a finite plan with its true objective
  st.method = AdmmMethod::kIpm;
  AdmmSolver d(p, st);
  const AdmmResult& rd = d.solve();
  EXPECT_EQ(rd.info.status, AdmmStatus::max_iterations);
  EXPECT_TRUE(std::isfinite(rd.info.objective) && rd.info.objective > 0.0);
  EXPECT_NEAR(rd.info.objective, d.objective_of(rd.Y), 1e-12 * rd.info.objective);
  EXPECT_GE(rd.info.duality_gap, 0.0);
  // the paper rule never runs the endgame
  AdmmSettings paper;
  paper.stopping = satgnc::guidance::StoppingRule::kPaper;
  paper.ipm_after = 0;
  AdmmSolver e(p, paper);
  EXPECT_EQ(e.solve().info.ipm_iterations, 0);
  // second-order cones stay ADMM-only: method ipm is a setup error naming `method`
  LtvProblem q = p;
  q.u_lower.resize(0);
  q.u_upper.resize(0);
  q.l1_weights = VectorXd::Zero(kNu);
  q.group_l2_weight = 1.0;
  try {
    AdmmSolver f(q, ipm_settings());
    FAIL() << "group-L2 with method ipm accepted";
  } catch (const std::invalid_argument& ex) {
    EXPECT_NE(std::string(ex.what()).find("method"), std::string::npos) << ex.what();
  }
  AdmmSettings bad;
  bad.ipm_after = -1;
  EXPECT_THROW(AdmmSolver(p, bad), std::invalid_argument);
  bad = AdmmSettings();
  bad.ipm_tolerance = 0.0;
  EXPECT_THROW(AdmmSolver(p, bad), std::invalid_argument);
}

TEST(AdmmIpm, InfeasibleTerminalIsNotSolved) {
  // x_N = 0 out of reach of a tight box: the IPM cannot certify; the endgame leaves ADMM's Farkas
  // check to report it
  const satgnc::dynamics::CwModel cw(0.0011, 1.0);
  const auto dd = satgnc::dynamics::cw_discretize_zoh(cw, 30.0);
  LtvProblem p;
  p.dynamics.A = {MatrixXd(dd.Ad)};
  p.dynamics.B = {MatrixXd(dd.Bd)};
  p.dynamics.horizon = 20;
  p.x0 = VectorXd::Zero(6);
  p.x0.head(3) << 1000.0, -500.0, 200.0;
  p.Qf = MatrixXd::Identity(6, 6);
  p.l1_weights = VectorXd::Ones(3);
  p.terminal_equality = true;
  p.u_lower = VectorXd::Constant(3, -1e-4);
  p.u_upper = VectorXd::Constant(3, 1e-4);
  AdmmSolver a(p, ipm_settings());
  EXPECT_NE(a.solve().info.status, AdmmStatus::solved);
  AdmmSettings st;
  st.ipm_after = 1;
  AdmmSolver b(p, st);
  EXPECT_EQ(b.solve().info.status, AdmmStatus::primal_infeasible);
  EXPECT_GT(b.result().info.ipm_iterations, 0);
}

TEST(AdmmIpm, IpmPathDoesNotAllocate) {
  std::mt19937 gen(15);
  const Variant variants[] = {
      {true, false, false, false, false, true},
      {true, true, false, false, false, true},
      {false, false, true, true, true, true},
  };
  for (const Variant& v : variants) {
    LtvProblem p = random_problem(gen, v);
    if (v.terminal) {
      p.u_lower = VectorXd::Constant(kNu, -50.0);
      p.u_upper = VectorXd::Constant(kNu, 50.0);
    }
    AdmmSolver s(p, ipm_settings());
    AdmmSettings st;
    st.ipm_after = 1;
    st.polish = false;
    AdmmSolver e(p, st);  // the endgame
    s.solve();            // warm-up (first-touch)
    e.solve();
    g_mallocs = 0;
    g_count = true;
    const AdmmStatus ss = s.solve().info.status;
    const AdmmStatus se = e.solve().info.status;
    g_count = false;
    EXPECT_EQ(g_mallocs.load(), 0);
    EXPECT_EQ(ss, AdmmStatus::solved);
    EXPECT_EQ(se, AdmmStatus::solved);
    EXPECT_TRUE(s.result().info.ipm_solved && e.result().info.ipm_solved);
  }
}
