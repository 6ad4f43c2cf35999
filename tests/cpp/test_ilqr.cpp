// iLQR-in-ADMM (satgnc/guidance/ilqr_admm.hpp): on linear dynamics it is exactly ADMM with an LQR
// step (checked iterate by iterate against a dense reference written here), the scenario's nonlinear
// unconstrained case stops after exactly 60 ADMM iterations with the published settings, no heap
// allocation inside solve(), and bad input gives statuses or clear errors.
#include <Eigen/Dense>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "malloc_counter.hpp"
#include "satgnc/guidance/ilqr_admm.hpp"
#include "testing.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using namespace satgnc::guidance;

namespace {

// Discretized double integrator in 3 axes (nx = 6, nu = 3), exact zero-order hold.
void double_integrator(double dt, MatrixXd& A, MatrixXd& B) {
  A = MatrixXd::Identity(6, 6);
  A.topRightCorner(3, 3) = dt * MatrixXd::Identity(3, 3);
  B = MatrixXd::Zero(6, 3);
  B.topRows(3) = 0.5 * dt * dt * MatrixXd::Identity(3, 3);
  B.bottomRows(3) = dt * MatrixXd::Identity(3, 3);
}

// Reference ADMM with the x/u-step solved densely: x_N = Phi x0 + G u, minimize
// 1/2 (x_N - xf)' Qf (x_N - xf) + w sum [rho/2 |u|^2 + (lam - rho y)' u].
struct DenseAdmm {
  MatrixXd G, Phi;
  VectorXd x0, xf;
  MatrixXd Qf;
  double w, rho, alpha;
  int N, nu;
  MatrixXd U, Y, L;
  void setup(const MatrixXd& A, const MatrixXd& B, int horizon) {
    N = horizon;
    nu = static_cast<int>(B.cols());
    const int nx = static_cast<int>(A.rows());
    G = MatrixXd::Zero(nx, N * nu);
    MatrixXd P = MatrixXd::Identity(nx, nx);
    for (int k = N - 1; k >= 0; --k) {
      G.middleCols(k * nu, nu) = P * B;
      P = P * A;
    }
    Phi = P;
    U = MatrixXd::Zero(nu, N);
    Y = U;
    L = U;
  }
  void iterate() {
    const int n = N * nu;
    MatrixXd H = G.transpose() * Qf * G + w * rho * MatrixXd::Identity(n, n);
    const VectorXd e0 = Phi * x0 - xf;
    VectorXd lin = G.transpose() * Qf * e0;
    for (int k = 0; k < N; ++k) lin.segment(k * nu, nu) += w * (L.col(k) - rho * Y.col(k));
    const VectorXd u = H.ldlt().solve(-lin);
    for (int k = 0; k < N; ++k) U.col(k) = u.segment(k * nu, nu);
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < nu; ++i) {
        const double v = U(i, k) + L(i, k) / rho, t = alpha / rho;
        Y(i, k) = v > t ? v - t : (v < -t ? v + t : 0.0);
      }
    L += rho * (U - Y);
  }
};

NonlinearL1Problem di_problem(int N) {
  NonlinearL1Problem p;
  p.horizon = N;
  p.x0 = (VectorXd(6) << 10.0, -5.0, 2.0, 0.1, 0.3, -0.2).finished();
  p.x_target = VectorXd::Zero(6);
  p.Qf = 100.0 * MatrixXd::Identity(6, 6);
  p.alpha = VectorXd::Ones(3);
  p.stage_weight = 0.5;
  return p;
}

// A model that fails on one interval (or beyond a control magnitude), to test statuses; with
// `throws` it fails by throwing instead of returning false.
class FailingModel final : public DiscreteModel {
 public:
  FailingModel(int fail_at, double u_limit, bool throws = false)
      : fail_at_(fail_at), u_limit_(u_limit), throws_(throws) {
    double_integrator(1.0, A_, B_);
  }
  int state_dim() const override { return 6; }
  int control_dim() const override { return 3; }
  bool step(int k, const double* x, const double* u, double* xn, double* A, double* B) const override {
    Eigen::Map<const VectorXd> uv(u, 3);
    if (k == fail_at_ || uv.cwiseAbs().maxCoeff() > u_limit_) {
      if (throws_) throw std::runtime_error("FailingModel: step refused");
      return false;
    }
    // products in place: the solver's no-allocation guard (core/no_malloc.hpp) covers model steps
    Eigen::Map<VectorXd> xv(xn, 6);
    xv.noalias() = A_ * Eigen::Map<const VectorXd>(x, 6);
    xv.noalias() += B_ * uv;
    if (A) Eigen::Map<MatrixXd>(A, 6, 6) = A_;
    if (B) Eigen::Map<MatrixXd>(B, 6, 3) = B_;
    return true;
  }

 private:
  int fail_at_;
  double u_limit_;
  bool throws_;
  MatrixXd A_, B_;
};

}  // namespace

TEST(IlqrAdmm, LinearDynamicsMatchesDenseAdmmIterateByIterate) {
  const int N = 20;
  MatrixXd A, B;
  double_integrator(1.0, A, B);
  const LinearDiscreteModel model({A}, {B}, {});
  const NonlinearL1Problem prob = di_problem(N);
  DenseAdmm ref;
  ref.setup(A, B, N);
  ref.x0 = prob.x0;
  ref.xf = prob.x_target;
  ref.Qf = prob.Qf;
  ref.w = prob.stage_weight;
  ref.rho = 0.7;
  ref.alpha = 1.0;
  for (int iters : {1, 5, 40}) {
    IlqrAdmmSettings set;
    set.rho = ref.rho;
    set.max_iter = iters;
    set.stop = StopRule::paper;
    set.eps_paper = 0.0;  // never stop early
    set.return_best = false;
    IlqrAdmmSolver solver(model, prob, set);
    solver.set_initial_controls(MatrixXd::Zero(3, N));
    solver.solve();
    ref.U.setZero();
    ref.Y.setZero();
    ref.L.setZero();
    for (int i = 0; i < iters; ++i) ref.iterate();
    const auto& r = solver.result();
    // One Gauss-Newton step on linear dynamics is the exact LQR solution: agreement to rounding.
    EXPECT_LE((r.U - ref.U).cwiseAbs().maxCoeff(), 1e-8 * (1.0 + ref.U.cwiseAbs().maxCoeff())) << iters;
    EXPECT_LE((r.Y - ref.Y).cwiseAbs().maxCoeff(), 1e-8 * (1.0 + ref.Y.cwiseAbs().maxCoeff())) << iters;
    EXPECT_LE((r.Lambda - ref.L).cwiseAbs().maxCoeff(), 1e-8 * (1.0 + ref.L.cwiseAbs().maxCoeff())) << iters;
  }
}

TEST(IlqrAdmm, ConvergesOnLinearProblemToResidualTolerance) {
  const int N = 20;
  MatrixXd A, B;
  double_integrator(1.0, A, B);
  const LinearDiscreteModel model({A}, {B}, {});
  IlqrAdmmSettings set;
  set.rho = 1.0;
  set.max_iter = 20000;
  set.eps_abs = 1e-9;
  set.eps_rel = 1e-9;
  set.adaptive_rho = true;
  IlqrAdmmSolver solver(model, di_problem(N), set);
  solver.set_initial_controls(MatrixXd::Zero(3, N));
  const IlqrAdmmResult& res = solver.solve();
  EXPECT_EQ(&res, &solver.result());  // solve() returns the result (core/solver.hpp contract)
  EXPECT_EQ(res.info.status, IlqrAdmmStatus::solved);
  const auto& info = solver.result().info;
  EXPECT_LE(info.primal_residual, 1e-6);
  EXPECT_GT(info.iterations, 0);
  // objective at U and at Y agree once U = Y
  SATGNC_EXPECT_REL(info.objective_u, info.objective_y, 1e-6);
}

TEST(IlqrAdmm, SolveDoesNotAllocate) {
  const int N = 30;
  MatrixXd A, B;
  double_integrator(1.0, A, B);
  const LinearDiscreteModel model({A}, {B}, {});
  NonlinearL1Problem prob = di_problem(N);
  for (ControlCost cost : {ControlCost::l1, ControlCost::l1_box, ControlCost::group_l2}) {
    prob.cost = cost;
    prob.u_min = VectorXd::Constant(3, -0.5);
    prob.u_max = VectorXd::Constant(3, 0.5);
    IlqrAdmmSettings set;
    set.max_iter = 50;
    set.adaptive_rho = true;
    set.rho_update_every = 5;
    set.time_limit = 10.0;                             // the clock is read, never allocated
    set.ilqr_iters = cost == ControlCost::l1 ? 3 : 1;  // the per-iLQR-iteration time check too
    IlqrAdmmSolver solver(model, prob, set);
    solver.set_initial_controls(MatrixXd::Zero(3, N));
    solver.solve();  // warm-up
    g_mallocs = 0;
    g_count = true;
    solver.solve();
    g_count = false;
    EXPECT_EQ(g_mallocs.load(), 0) << "cost " << static_cast<int>(cost);
    if (cost == ControlCost::group_l2) continue;
    // with per-stage bounds (SCP's trust region), set and warm-started inside the counted region
    const MatrixXd lo = MatrixXd::Constant(3, N, -0.2), hi = MatrixXd::Constant(3, N, 0.3);
    const MatrixXd U = solver.result().U, Y = solver.result().Y, L = solver.result().Lambda;
    g_mallocs = 0;
    g_count = true;
    solver.set_stage_bounds(lo, hi);
    solver.warm_start(U, Y, L);
    solver.solve();
    g_count = false;
    EXPECT_EQ(g_mallocs.load(), 0) << "stage bounds, cost " << static_cast<int>(cost);
    solver.clear_stage_bounds();
  }
  // sanity: the counter works
  g_mallocs = 0;
  g_count = true;
  void* volatile p = std::malloc(64);
  g_count = false;
  std::free(p);
#if !defined(__SANITIZE_ADDRESS__)
  EXPECT_EQ(g_mallocs.load(), 1);
#endif
}

TEST(IlqrAdmm, PropagationFailureNamesTheInterval) {
  const FailingModel model(7, 1e9);
  IlqrAdmmSolver solver(model, di_problem(20));
  solver.set_initial_controls(MatrixXd::Zero(3, 20));
  EXPECT_EQ(solver.solve().info.status, IlqrAdmmStatus::propagation_failed);
  EXPECT_EQ(solver.result().info.failed_interval, 7);
  EXPECT_NE(std::string(status_message(IlqrAdmmStatus::propagation_failed)).find("failed_interval"),
            std::string::npos);
}

TEST(IlqrAdmm, SolveIsNoexceptAndAThrowingModelIsAFailedStep) {
  static_assert(noexcept(std::declval<IlqrAdmmSolver&>().solve()), "IlqrAdmmSolver::solve() is noexcept");
  // Each failure mode of FailingModel, by `return false` and by throwing: the same status, interval,
  // iteration counts and iterates (exact equality: the exception takes the same branch).
  struct Case {
    int fail_at;
    double u_limit;
    int N;
    IlqrAdmmStatus expected;  // as the tests above establish for the returning model
  };
  const Case cases[] = {{7, 1e9, 20, IlqrAdmmStatus::propagation_failed},  // initial rollout
                        {-1, 1e-300, 10, IlqrAdmmStatus::ilqr_failed},     // every trial step
                        {-1, 0.05, 20, IlqrAdmmStatus::unsolved}};         // line search (any status)
  for (const Case& c : cases) {
    IlqrAdmmSettings set;
    set.max_iter = 30;
    set.reg_max = 1e2;
    const FailingModel returning(c.fail_at, c.u_limit, false), throwing(c.fail_at, c.u_limit, true);
    IlqrAdmmSolver a(returning, di_problem(c.N), set), b(throwing, di_problem(c.N), set);
    a.set_initial_controls(MatrixXd::Zero(3, c.N));
    b.set_initial_controls(MatrixXd::Zero(3, c.N));
    const IlqrAdmmResult& ra = a.solve();
    const IlqrAdmmResult& rb = b.solve();
    if (c.expected != IlqrAdmmStatus::unsolved) EXPECT_EQ(rb.info.status, c.expected);
    EXPECT_EQ(rb.info.status, ra.info.status) << "fail_at " << c.fail_at;
    EXPECT_EQ(rb.info.failed_interval, ra.info.failed_interval);
    EXPECT_EQ(rb.info.iterations, ra.info.iterations);
    EXPECT_EQ(rb.info.ilqr_iterations, ra.info.ilqr_iterations);
    EXPECT_EQ(rb.U, ra.U);
    EXPECT_EQ(rb.Y, ra.Y);
    MatrixXd Xa(6, c.N + 1), Xb(6, c.N + 1);
    EXPECT_EQ(b.rollout(rb.U, Xb), a.rollout(ra.U, Xa));  // public rollout: a throw is the failing interval
  }
}

TEST(IlqrAdmm, LineSearchBacktracksWhenTheFullStepFails) {
  // The model refuses |u| > 0.05: the full LQR step does, the line search must shorten it.
  const FailingModel model(-1, 0.05);
  IlqrAdmmSettings set;
  set.max_iter = 30;
  IlqrAdmmSolver solver(model, di_problem(20), set);
  solver.set_initial_controls(MatrixXd::Zero(3, 20));
  const auto st = solver.solve().info.status;
  EXPECT_TRUE(st == IlqrAdmmStatus::max_iterations || st == IlqrAdmmStatus::solved ||
              st == IlqrAdmmStatus::ilqr_failed);
  EXPECT_TRUE(solver.result().U.allFinite());
  EXPECT_LE(solver.result().U.cwiseAbs().maxCoeff(), 0.05);
  EXPECT_LT(solver.result().info.objective_u, 0.5 * 100.0 * di_problem(20).x0.squaredNorm());
}

TEST(IlqrAdmm, MaxIterationsReturnsBestIterate) {
  MatrixXd A, B;
  double_integrator(1.0, A, B);
  const LinearDiscreteModel model({A}, {B}, {});
  IlqrAdmmSettings set;
  set.max_iter = 3;
  IlqrAdmmSolver solver(model, di_problem(20), set);
  solver.set_initial_controls(MatrixXd::Zero(3, 20));
  EXPECT_EQ(solver.solve().info.status, IlqrAdmmStatus::max_iterations);
  const auto& r = solver.result();
  EXPECT_EQ(r.info.iterations, 3);
  EXPECT_NEAR(r.info.primal_residual, (r.U - r.Y).norm(), 1e-12);
  EXPECT_TRUE(std::isfinite(r.info.objective_u));
}

TEST(IlqrAdmm, BadInputThrowsNamingTheArgument) {
  MatrixXd A, B;
  double_integrator(1.0, A, B);
  const LinearDiscreteModel model({A}, {B}, {});
  auto expect_throw = [&](NonlinearL1Problem p, IlqrAdmmSettings s, const std::string& name) {
    try {
      IlqrAdmmSolver solver(model, p, s);
      ADD_FAILURE() << "no throw for " << name;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  const NonlinearL1Problem ok = di_problem(10);
  NonlinearL1Problem p = ok;
  p.x0 = VectorXd::Zero(5);
  expect_throw(p, {}, "x0");
  p = ok;
  p.Qf = MatrixXd::Identity(4, 4);
  expect_throw(p, {}, "Qf");
  p = ok;
  p.alpha = VectorXd::Ones(2);
  expect_throw(p, {}, "alpha");
  p = ok;
  p.alpha(1) = -1.0;
  expect_throw(p, {}, "alpha");
  p = ok;
  p.x0(2) = std::nan("");
  expect_throw(p, {}, "x0");
  p = ok;
  p.cost = ControlCost::l1_box;
  p.u_min = VectorXd::Constant(3, 0.1);
  p.u_max = VectorXd::Constant(3, 1.0);
  expect_throw(p, {}, "u_min");
  p.u_min = VectorXd::Constant(3, 1.0);
  p.u_max = VectorXd::Constant(3, -1.0);
  expect_throw(p, {}, "u_min");
  IlqrAdmmSettings s;
  s.rho = 0.0;
  expect_throw(ok, s, "rho");
  s = IlqrAdmmSettings();
  s.time_limit = -1.0;
  expect_throw(ok, s, "time_limit");
  s = IlqrAdmmSettings();
  s.inaccurate_factor = 0.5;
  expect_throw(ok, s, "inaccurate_factor");
  p = ok;
  p.horizon = 0;
  expect_throw(p, {}, "horizon");
  IlqrAdmmSolver solver(model, ok);
  EXPECT_THROW(solver.set_initial_controls(MatrixXd::Zero(3, 9)), std::invalid_argument);
  EXPECT_THROW(solver.warm_start(MatrixXd::Zero(3, 10), MatrixXd::Zero(2, 10), MatrixXd::Zero(3, 10)),
               std::invalid_argument);
  EXPECT_THROW(LinearDiscreteModel({A}, {MatrixXd::Zero(5, 3)}, {}), std::invalid_argument);
}

TEST(IlqrAdmm, PaperNonlinearUnconstrainedStopsAfter60Iterations) {
  // l1_scenario.md: 1 h RK4 drift (9999 steps), published scaling (time 324.48 s, force 0.42318 N),
  // RK3 map, rho = 0.1, eps = 6e-5 on ||U - Y||_2 / 297, row rescaling of the multipliers after
  // iteration 1, one iLQR iteration per ADMM iteration.
  using namespace satgnc::dynamics;
  TwoSatelliteParams tp;
  tp.atmosphere = AtmosphereRotation::published;
  const TwoSatelliteModel ts(tp);
  const double mu = 3.99e14, R = 7231.0e3;
  Vec12 x;
  x << 20.0, 30.0, 10.0, R, 0.0, 0.0, 0.4, 0.6, -0.1, 0.0, std::sqrt(mu / R), 0.0;
  Vec12 xn;
  for (int i = 0; i < 9999; ++i) {
    ts.rk_step(4, 3600.0 / 9999, x, satgnc::Vec3::Zero(), xn);
    x = xn;
  }
  const ReferenceScaling sc = published_scaling(x, mu, 4.6);
  EXPECT_NEAR(sc.time_scale, 324.48, 0.005);            // printed to 0.01 s
  EXPECT_NEAR(sc.control_scale(0), 0.42318, 0.000005);  // printed to 1e-5 N
  TwoSatelliteMapSettings ms;
  ms.dt = 6000.0 / 99.0;
  ms.scheme = 3;
  ms.state_scale = sc.state_scale;
  ms.control_scale = sc.control_scale;
  const TwoSatelliteMap map(ts, ms);
  NonlinearL1Problem p;
  p.horizon = 99;
  p.x0 = x.cwiseQuotient(sc.state_scale);
  p.x_target = VectorXd::Zero(12);
  VectorXd q(12);
  q << 1, 1, 1, 0, 0, 0, 1, 1, 1, 0, 0, 0;
  p.Qf = 1000.0 * q.asDiagonal();
  p.alpha = VectorXd::Ones(3);
  p.stage_weight = ms.dt / sc.time_scale;
  IlqrAdmmSettings s;
  s.rho = 0.1;
  s.stop = StopRule::paper;
  s.eps_paper = 6e-5;
  s.paper_multiplier_rescale = true;
  s.max_iter = 300;
  IlqrAdmmSolver solver(map, p, s);
  solver.set_initial_controls(MatrixXd::Zero(3, 99));
  EXPECT_EQ(solver.solve().info.status, IlqrAdmmStatus::solved);
  EXPECT_EQ(solver.result().info.iterations, 60);  // Table 1: 120 LQR passes = 2 x 60
  EXPECT_EQ(solver.result().info.lqr_passes, 120);
}

namespace {
// Forwards to a model but declares given exogenous states (none = the full 12x12 Riccati sweep).
class ExogenousOverride final : public DiscreteModel {
 public:
  ExogenousOverride(const DiscreteModel& m, std::vector<int> exo) : m_(m), exo_(std::move(exo)) {}
  int state_dim() const override { return m_.state_dim(); }
  int control_dim() const override { return m_.control_dim(); }
  bool step(int k, const double* x, const double* u, double* xn, double* A, double* B) const override {
    return m_.step(k, x, u, xn, A, B);
  }
  std::vector<int> exogenous_states() const override { return exo_; }

 private:
  const DiscreteModel& m_;
  std::vector<int> exo_;
};
}  // namespace

TEST(IlqrAdmm, ExogenousTargetSweepEqualsFullSweep) {
  // The two-satellite map declares the target's states exogenous, and the solver then carries only
  // the chaser rows of the value function. Same iterates as the full 12x12 sweep (to rounding), with
  // J2 on, strong drag, a target term in the terminal cost, the box prox and the CW-frame control;
  // 30 ADMM iterations of one Gauss-Newton step.
  using namespace satgnc::dynamics;
  TwoSatelliteParams tp;
  tp.j2_on = true;
  tp.rho0 = 1e-9;  // strong drag, so the drag Jacobian blocks matter
  const TwoSatelliteModel ts(tp);
  const double mu = tp.mu, R = 6900.0e3;
  Vec12 x0;
  const double vc = std::sqrt(mu / R) * std::sqrt(0.5);  // inclined 45 degrees
  x0 << 300.0, -200.0, 100.0, R, 0.0, 0.0, 0.3, -0.2, 0.1, 0.0, vc, vc;
  const ReferenceScaling sc = published_scaling(x0, mu, tp.mass_chaser);
  TwoSatelliteMapSettings ms;
  ms.dt = 60.0;
  ms.state_scale = sc.state_scale;
  ms.control_scale = sc.control_scale;
  const TwoSatelliteMap map(ts, ms);
  ASSERT_EQ(map.exogenous_states(), (std::vector<int>{3, 4, 5, 9, 10, 11}));
  const ExogenousOverride full(map, {});
  NonlinearL1Problem p;
  p.horizon = 30;
  p.x0 = x0.cwiseQuotient(sc.state_scale);
  p.x_target = VectorXd::Zero(12);
  VectorXd q(12);
  q << 1000, 1000, 1000, 1, 1, 1, 1000, 1000, 1000, 1, 1, 1;  // t weights too: S_tt is dropped
  p.Qf = q.asDiagonal();
  p.x_target.segment<3>(3) = p.x0.segment<3>(3);  // a target term in the cost (constant in u)
  p.x_target.segment<3>(9) = p.x0.segment<3>(9);
  p.alpha = VectorXd::Ones(3);
  p.stage_weight = ms.dt / sc.time_scale;
  p.cost = ControlCost::l1_box;
  p.u_min = VectorXd::Constant(3, -0.05);
  p.u_max = VectorXd::Constant(3, 0.05);
  IlqrAdmmSettings s;
  s.rho = 1.0;
  s.max_iter = 30;
  s.return_best = false;
  IlqrAdmmSolver reduced_solver(map, p, s), full_solver(full, p, s);
  reduced_solver.set_initial_controls(MatrixXd::Zero(3, p.horizon));
  full_solver.set_initial_controls(MatrixXd::Zero(3, p.horizon));
  g_mallocs = 0;
  g_count = true;
  reduced_solver.solve();  // the reduced sweep and the RK3 map do not allocate either
  g_count = false;
#if !defined(__SANITIZE_ADDRESS__)
  EXPECT_EQ(g_mallocs.load(), 0);
#endif
  full_solver.solve();
  const auto& a = reduced_solver.result();
  const auto& b = full_solver.result();
  EXPECT_EQ(a.info.iterations, b.info.iterations);
  EXPECT_EQ(a.info.ilqr_iterations, b.info.ilqr_iterations);
  EXPECT_GT(a.Y.cwiseAbs().maxCoeff(), 0.04);  // the sparse controls are not trivially zero
  // rounding differs (other summation order): 1e-10 relative after 30 Gauss-Newton steps
  EXPECT_LT((a.U - b.U).norm(), 1e-10 * b.U.norm());
  EXPECT_LT((a.Y - b.Y).norm(), 1e-10 * b.Y.norm());
  EXPECT_LT((a.X - b.X).norm(), 1e-12 * b.X.norm());
}

TEST(IlqrAdmm, BadExogenousIndicesThrow) {
  MatrixXd A, B;
  double_integrator(1.0, A, B);
  const LinearDiscreteModel lin({A}, {B}, {});
  const ExogenousOverride bad(lin, {3, 2});
  const ExogenousOverride out(lin, {6});
  const NonlinearL1Problem p = di_problem(10);
  for (const DiscreteModel* m : std::vector<const DiscreteModel*>{&bad, &out}) {
    try {
      IlqrAdmmSolver solver(*m, p);
      ADD_FAILURE() << "no throw";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("exogenous_states"), std::string::npos) << e.what();
    }
  }
}

TEST(IlqrAdmm, StageBoundsEqualTheProblemBoxWhenConstant) {
  // The per-stage bounds enter the prox exactly: constant stage bounds on the L1 problem give the
  // iterates of the l1_box problem with that box.
  MatrixXd A, B;
  double_integrator(1.0, A, B);
  const LinearDiscreteModel model({A}, {B}, {});
  const int N = 20;
  NonlinearL1Problem p = di_problem(N);
  IlqrAdmmSettings set;
  set.max_iter = 200;
  IlqrAdmmSolver a(model, p, set);
  a.set_initial_controls(MatrixXd::Zero(3, N));
  a.set_stage_bounds(MatrixXd::Constant(3, N, -0.05), MatrixXd::Constant(3, N, 0.08));
  a.solve();
  NonlinearL1Problem pb = p;
  pb.cost = ControlCost::l1_box;
  pb.u_min = VectorXd::Constant(3, -0.05);
  pb.u_max = VectorXd::Constant(3, 0.08);
  IlqrAdmmSolver b(model, pb, set);
  b.set_initial_controls(MatrixXd::Zero(3, N));
  b.solve();
  EXPECT_EQ(a.result().info.iterations, b.result().info.iterations);
  EXPECT_LE((a.result().Y - b.result().Y).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LE(a.result().Y.maxCoeff(), 0.08);
  EXPECT_GE(a.result().Y.minCoeff(), -0.05);
  // group_l2 has no closed-form prox with a box: refused
  NonlinearL1Problem pg = p;
  pg.cost = ControlCost::group_l2;
  IlqrAdmmSolver g(model, pg, set);
  EXPECT_THROW(g.set_stage_bounds(MatrixXd::Zero(3, N), MatrixXd::Zero(3, N)), std::invalid_argument);
  EXPECT_THROW(a.set_stage_bounds(MatrixXd::Ones(3, N), MatrixXd::Zero(3, N)), std::invalid_argument);
}

TEST(IlqrAdmm, LimitsReturnTheBestIterateWithAnHonestStatus) {
  MatrixXd A, B;
  double_integrator(1.0, A, B);
  const LinearDiscreteModel model({A}, {B}, {});
  const NonlinearL1Problem p = di_problem(20);
  IlqrAdmmSettings set;
  set.eps_abs = set.eps_rel = 1e-9;
  IlqrAdmmSolver full(model, p, set);
  full.set_initial_controls(MatrixXd::Zero(3, 20));
  ASSERT_EQ(full.solve().info.status, IlqrAdmmStatus::solved);
  const int n = full.result().info.iterations;
  // stopped before convergence: solved_inaccurate when the loose test holds, else max_iterations
  set.max_iter = n / 2;
  set.inaccurate_factor = 1e9;
  IlqrAdmmSolver loose(model, p, set);
  loose.set_initial_controls(MatrixXd::Zero(3, 20));
  EXPECT_EQ(loose.solve().info.status, IlqrAdmmStatus::solved_inaccurate);
  set.inaccurate_factor = 1.0;
  IlqrAdmmSolver strict(model, p, set);
  strict.set_initial_controls(MatrixXd::Zero(3, 20));
  EXPECT_EQ(strict.solve().info.status, IlqrAdmmStatus::max_iterations);
  EXPECT_TRUE(std::isfinite(strict.result().info.objective_y));
  EXPECT_GT(strict.result().info.objective_y, 0.0);
  // time limit: stops after the first iteration, best iterate with its true cost
  IlqrAdmmSettings t;
  t.time_limit = 1e-12;
  IlqrAdmmSolver timed(model, p, t);
  timed.set_initial_controls(MatrixXd::Zero(3, 20));
  EXPECT_EQ(timed.solve().info.status, IlqrAdmmStatus::time_limit);
  EXPECT_EQ(timed.result().info.iterations, 1);
  EXPECT_TRUE(std::isfinite(timed.result().info.objective_u));
  EXPECT_TRUE(std::isfinite(timed.result().info.terminal_miss));
  EXPECT_NEAR(timed.result().info.primal_residual, (timed.result().U - timed.result().Y).norm(), 1e-12);
}

TEST(IlqrAdmm, IlqrFailureReturnsAFiniteIterateWithItsTrueCost) {
  // The model refuses any nonzero control: iLQR cannot move (every trial step fails).
  const FailingModel model(-1, 1e-300);
  IlqrAdmmSettings set;
  set.reg_max = 1e2;
  IlqrAdmmSolver solver(model, di_problem(10), set);
  solver.set_initial_controls(MatrixXd::Zero(3, 10));
  EXPECT_EQ(solver.solve().info.status, IlqrAdmmStatus::ilqr_failed);
  const auto& r = solver.result();
  EXPECT_TRUE(r.U.allFinite());
  const double J0 = r.info.objective_u;
  EXPECT_TRUE(std::isfinite(J0));
  EXPECT_GT(J0, 0.0);
  EXPECT_EQ(J0, solver.true_cost(MatrixXd::Zero(3, 10)));
  EXPECT_TRUE(std::isfinite(r.info.objective_y));
}
