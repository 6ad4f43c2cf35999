// OD solvers: the paper's six-point Newton-Raphson, batch least squares, LM, root search, statuses,
// the OD Jacobian against finite differences, and no heap allocation inside solve().
#include <cmath>
#include <random>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "../../cpp/src/od/detail/householder_qr.hpp"  // private to the od room: tested here
#include "malloc_counter.hpp"
#include "od_test_support.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/od/solver.hpp"
#include "testing.hpp"

// No heap in solve(), proved twice, as for the other solvers: malloc_counter.hpp counts every malloc
// of this binary (operator new, Eigen's aligned allocations, CVODES) in the release build (make
// test), and SATGNC_NO_MALLOC_SCOPE inside OdSolver::solve() forbids Eigen allocation in guarded
// builds (make sanitize: Debug, satgnc_core_guarded), which SolveRunsInsideTheNoMallocGuard checks
// from inside the propagator. Before the in-place QR (od/detail/householder_qr.hpp) the six-point
// problem made 15 / 15 / 42 mallocs per solve (newton / gauss_newton / LM) in Eigen's blocked
// HouseholderQR of the 6 x 7 [J | r].

using namespace satgnc;
using namespace satgnc::od;
using satgnc::od::testing::paper_station_r0;
using satgnc::od::testing::paper_truth;
using satgnc::od::testing::Rk4StmPropagator;

namespace {
constexpr double kMu = 398600.4418;
const double kTimes[6] = {0, 60, 120, 180, 240, 300};

std::shared_ptr<StmPropagator> prop() { return std::make_shared<Rk4StmPropagator>(kMu, 1.0); }
Station paper_station() { return Station::from_inertial(paper_station_r0(), dynamics::earth::omega); }

// Exact synthetic observations of the truth through the same propagator.
void observe(const Vec6& x0, const std::vector<Station>& st, const std::vector<double>& t, int station,
             std::vector<double>& rho, std::vector<double>& rhodot) {
  std::vector<Vec6> xs(t.size());
  std::vector<Mat6> ph(t.size());
  Rk4StmPropagator p(kMu, 1.0);
  p.propagate(x0, t.data(), static_cast<int>(t.size()), xs.data(), ph.data());
  rho.clear();
  rhodot.clear();
  for (std::size_t i = 0; i < t.size(); ++i) {
    double a = 0, b = 0;
    predict_measurement(MeasurementType::range, xs[i], st[static_cast<std::size_t>(station)].state(t[i]), a);
    predict_measurement(MeasurementType::range_rate, xs[i], st[static_cast<std::size_t>(station)].state(t[i]),
                        b);
    rho.push_back(a);
    rhodot.push_back(b);
  }
}

std::vector<BoundaryCondition> doppler_conditions() {
  std::vector<double> t(kTimes, kTimes + 6), rho, rhodot;
  observe(paper_truth(), {paper_station()}, t, 0, rho, rhodot);
  std::vector<BoundaryCondition> c;
  for (int i = 0; i < 6; ++i) c.push_back({t[i], ConditionType::doppler, rho[i], rhodot[i], 1e-3, 1e-6, 0});
  return c;
}

// The batch tests' data: the paper's station and a second one, exact range (sigma 1 m) and range-rate
// (1 mm/s) of the paper's truth from each every 10 s over 300 s.
struct TwoStationData {
  std::vector<Station> stations;
  std::vector<Measurement> measurements;
};

TwoStationData two_station_data() {
  TwoStationData d;
  d.stations = {paper_station(), Station::from_inertial(Vec3(5200.0, 3000.0, 1900.0))};
  std::vector<double> t;
  for (int i = 0; i <= 30; ++i) t.push_back(10.0 * i);
  for (int s = 0; s < 2; ++s) {
    std::vector<double> rho, rhodot;
    observe(paper_truth(), d.stations, t, s, rho, rhodot);
    for (std::size_t i = 0; i < t.size(); ++i) {
      d.measurements.push_back({t[i], MeasurementType::range, rho[i], 1e-3, s});
      d.measurements.push_back({t[i], MeasurementType::range_rate, rhodot[i], 1e-6, s});
    }
  }
  return d;
}
}  // namespace

TEST(OdSolver, PaperDopplerNewtonConvergesForAllOffsets) {
  OdSettings s;
  s.method = OdMethod::newton;
  auto solver = OdSolver::from_conditions({paper_station()}, doppler_conditions(), prop(), s);
  for (double dx1 : {10.0, 20.0, 30.0, 40.0}) {
    Vec6 guess = paper_truth();
    guess(0) += dx1;
    const OdResult& r = solver.solve(guess);
    EXPECT_EQ(r.status, OdStatus::converged) << status_message(r.status);
    EXPECT_LE(r.iterations, 5) << "offset " << dx1;         // the goal: <= 5 iterations
    EXPECT_LT(std::abs(r.x0(0) - paper_truth()(0)), 1e-4);  // < 10 cm in x1
    EXPECT_LT((r.x0 - paper_truth()).head<3>().norm(), 1e-4);
    EXPECT_EQ(r.rank, 6);
    EXPECT_GT(r.condition_number, 1e3);
  }
}

TEST(OdSolver, ShortArcStmOfEq19DoesNotConverge) {
  OdSettings s;
  s.method = OdMethod::newton;
  s.max_iterations = 10;
  auto solver = OdSolver::from_conditions({paper_station()}, doppler_conditions(),
                                          std::make_shared<ShortArcStmPropagator>(prop()), s);
  Vec6 guess = paper_truth();
  guess(0) += 10.0;
  const OdResult& r = solver.solve(guess);
  EXPECT_NE(r.status, OdStatus::converged);
}

TEST(OdSolver, JacobianMatchesFiniteDifferences) {
  std::vector<double> t(kTimes, kTimes + 6), rho, rhodot;
  const std::vector<Station> st{paper_station()};
  observe(paper_truth(), st, t, 0, rho, rhodot);
  std::vector<Measurement> m;
  for (int i = 0; i < 6; ++i) {
    m.push_back({t[i], MeasurementType::range, rho[i], 1e-3, 0});
    m.push_back({t[i], MeasurementType::range_rate, rhodot[i], 1e-6, 0});
  }
  auto solver = OdSolver::from_measurements(st, m, prop());
  auto csolver = OdSolver::from_conditions(st, doppler_conditions(), prop());
  for (OdSolver* sv : {&solver, &csolver}) {
    Vec6 x = paper_truth();
    x(0) += 5.0;
    Eigen::VectorXd r0, rp, rm;
    Eigen::MatrixXd J;
    ASSERT_EQ(sv->evaluate(x, r0, &J), OdStatus::converged);
    Eigen::MatrixXd fd(J.rows(), 6);
    for (int i = 0; i < 6; ++i) {
      const double h = i < 3 ? 1e-3 : 1e-6;
      Vec6 p = x, q = x;
      p(i) += h;
      q(i) -= h;
      sv->evaluate(p, rp, nullptr);
      sv->evaluate(q, rm, nullptr);
      fd.col(i) = (rp - rm) / (2 * h);
    }
    // The RK4 STM is the exact derivative of the RK4 map, so only differencing error remains.
    for (int i = 0; i < 6; ++i) SATGNC_EXPECT_REL(J.col(i), fd.col(i), 1e-6);
  }
}

TEST(OdSolver, BatchTwoStationsCovarianceAndLm) {
  const TwoStationData data = two_station_data();
  const std::vector<Station>& st = data.stations;
  const std::vector<Measurement>& m = data.measurements;
  for (auto method : {OdMethod::gauss_newton, OdMethod::levenberg_marquardt}) {
    OdSettings set;
    set.method = method;
    auto solver = OdSolver::from_measurements(st, m, prop(), set);
    // Undamped Gauss-Newton left the physical region from this 70 km / 37 m/s offset (measured:
    // below the surface after 5 steps); with the line search along the geodesic path it converges.
    Vec6 guess = paper_truth();
    guess.head<3>() += Vec3(50.0, -40.0, 30.0);
    guess.tail<3>() += Vec3(0.02, -0.01, 0.03);
    const OdResult& r = solver.solve(guess);
    EXPECT_EQ(r.status, OdStatus::converged) << status_message(r.status);
    // The cost never rises along the GN / LM iterations.
    for (int k = 1; k <= r.iterations; ++k) EXPECT_LE(r.history_cost(k), r.history_cost(k - 1));
    EXPECT_LT((r.x0 - paper_truth()).head<3>().norm(), 1e-6);
    EXPECT_TRUE(r.fits);
    // Covariance is symmetric positive definite and the correlation has a unit diagonal.
    EXPECT_LT((r.covariance - r.covariance.transpose()).norm(), 1e-12 * r.covariance.norm());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat6>(r.covariance).eigenvalues().minCoeff(), 0.0);
    EXPECT_NEAR(r.correlation.diagonal().minCoeff(), 1.0, 1e-12);
    EXPECT_LT(std::sqrt(r.covariance(0, 0)), 0.05);  // two stations, 1 m ranges: position to < 50 m
  }
}

TEST(OdSolver, LmRecoversFromFarGuessWhereNewtonFails) {
  OdSettings s;
  s.method = OdMethod::newton;
  s.max_iterations = 40;
  auto newton = OdSolver::from_conditions({paper_station()}, doppler_conditions(), prop(), s);
  s.method = OdMethod::levenberg_marquardt;
  s.max_iterations = 200;
  auto lm = OdSolver::from_conditions({paper_station()}, doppler_conditions(), prop(), s);
  Vec6 guess = paper_truth();
  guess.head<3>() += Vec3(150.0, -120.0, 100.0);
  guess.tail<3>() += Vec3(-0.15, 0.12, 0.1);
  const OdResult& rl = lm.solve(guess);
  EXPECT_EQ(rl.status, OdStatus::converged) << status_message(rl.status);
  EXPECT_TRUE(rl.fits);
  const OdResult& rn = newton.solve(guess);
  // Newton may or may not converge from here; if it does, it must also fit.
  if (rn.status == OdStatus::converged) EXPECT_TRUE(rn.fits);
}

TEST(OdSolver, StatusesSingularDivergedDegenerate) {
  // Six ranges at t = 0 from six stations: velocity unobservable -> rank 3.
  std::vector<Station> st;
  std::vector<Measurement> m;
  for (int i = 0; i < 6; ++i) {
    st.push_back(Station::from_inertial(paper_station_r0() + Vec3(100.0 * i, -50.0 * i * i, 30.0 * i)));
    double rho = 0;
    predict_measurement(MeasurementType::range, paper_truth(), st.back().state(0.0), rho);
    m.push_back({0.0, MeasurementType::range, rho, 1e-3, i});
  }
  auto solver = OdSolver::from_measurements(st, m, prop());
  const OdResult& r = solver.solve(paper_truth() + Vec6::Constant(0.001));
  EXPECT_EQ(r.status, OdStatus::singular);
  EXPECT_EQ(r.rank, 3);

  OdSettings s;
  s.method = OdMethod::newton;
  auto nr = OdSolver::from_conditions({paper_station()}, doppler_conditions(), prop(), s);
  Vec6 inside = paper_truth();
  inside.head<3>() *= 0.5;  // below the surface
  EXPECT_EQ(nr.solve(inside).status, OdStatus::diverged);
  Vec6 unbound = paper_truth();
  unbound.tail<3>() *= 2.0;  // hyperbolic
  EXPECT_EQ(nr.solve(unbound).status, OdStatus::diverged);
  // Satellite exactly at the station at t = 0 (zero range).
  Vec6 at_station = paper_truth();
  at_station.head<3>() = paper_station_r0();
  at_station.head<3>() *= 1.2;  // lift above the surface, put the station there too
  auto st2 = Station::from_inertial(at_station.head<3>());
  auto nr2 = OdSolver::from_conditions({st2}, doppler_conditions(), prop(), s);
  EXPECT_EQ(nr2.solve(at_station).status, OdStatus::degenerate_geometry);
}

TEST(OdSolver, BadInput) {
  OdSettings s;
  s.method = OdMethod::newton;
  auto c = doppler_conditions();
  auto five = c;
  five.pop_back();
  try {
    OdSolver::from_conditions({paper_station()}, five, prop(), s);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("exactly 6"), std::string::npos);
  }
  auto dup = c;
  dup[3].t = dup[2].t;
  EXPECT_THROW(OdSolver::from_conditions({paper_station()}, dup, prop(), s), std::invalid_argument);
  auto neg = c;
  neg[0].sigma_range_rate = -1.0;
  EXPECT_THROW(OdSolver::from_conditions({paper_station()}, neg, prop(), s), std::invalid_argument);
  auto zero = c;
  zero[0].range = 0.0;
  EXPECT_THROW(OdSolver::from_conditions({paper_station()}, zero, prop(), s), std::invalid_argument);
  EXPECT_THROW(OdSolver::from_conditions({paper_station()}, c, nullptr, s), std::invalid_argument);
  OdSettings bad;
  bad.rank_tol = 2.0;
  EXPECT_THROW(OdSolver::from_conditions({paper_station()}, c, prop(), bad), std::invalid_argument);
  std::vector<Measurement> m(5, Measurement{0.0, MeasurementType::range, 1000.0, 1e-3, 0});
  for (int i = 0; i < 5; ++i) m[i].t = i;
  EXPECT_THROW(OdSolver::from_measurements({paper_station()}, m, prop()), std::invalid_argument);
}

TEST(OdSolver, RootSearchFindsTruth) {
  OdSettings s;
  s.method = OdMethod::levenberg_marquardt;
  s.max_iterations = 100;
  auto lm = OdSolver::from_conditions({paper_station()}, doppler_conditions(), prop(), s);
  Vec6 hw;
  hw << 50, 50, 50, 0.05, 0.05, 0.05;
  const auto guesses = box_guesses(paper_truth(), hw, 8, 7);
  const RootSearchResult rs = root_search(lm, guesses);
  ASSERT_GE(rs.roots.size(), 1u);
  EXPECT_TRUE(rs.roots[0].fits);
  bool truth_found = false;
  for (const auto& r : rs.roots)
    if ((r.x0 - paper_truth()).head<3>().norm() < 1e-3) truth_found = true;
  EXPECT_TRUE(truth_found);
  EXPECT_EQ(rs.guess_root.size(), 8u);
}

TEST(OdSolver, SolveDoesNotAllocate) {
  for (auto method : {OdMethod::newton, OdMethod::gauss_newton, OdMethod::levenberg_marquardt}) {
    OdSettings s;
    s.method = method;
    auto solver = OdSolver::from_conditions({paper_station()}, doppler_conditions(), prop(), s);
    Vec6 guess = paper_truth();
    guess(0) += 10.0;
    solver.solve(guess);  // warm-up
    g_mallocs = 0;
    g_count = true;
    const OdResult& r = solver.solve(guess);
    g_count = false;
    EXPECT_EQ(g_mallocs.load(), 0) << "method " << static_cast<int>(method);
    EXPECT_EQ(r.status, OdStatus::converged);
  }
}

namespace {
// Wraps the RK4 propagator: records whether Eigen may allocate while solve() calls it, or throws.
class SpyPropagator final : public StmPropagator {
 public:
  explicit SpyPropagator(bool throws) : throws_(throws) {}
  bool propagate(const Vec6& x0, const double* times, int n, Vec6* states, Mat6* stms) override {
    ++calls;
    if (!core::malloc_allowed()) ++calls_guarded;
    if (throws_) throw std::runtime_error("spy propagator failure");
    return inner_.propagate(x0, times, n, states, stms);
  }
  int calls = 0;
  int calls_guarded = 0;

 private:
  bool throws_;
  Rk4StmPropagator inner_{kMu, 1.0};
};
}  // namespace

TEST(OdSolver, SolveRunsInsideTheNoMallocGuard) {
  // Every propagation inside solve() runs with Eigen's malloc switch off in guarded builds
  // (kNoMallocGuard: satgnc_core_guarded, make sanitize), and on in the others (the release library
  // compiles the guard out). Exact counts, no tolerance.
  for (auto method : {OdMethod::newton, OdMethod::gauss_newton, OdMethod::levenberg_marquardt}) {
    OdSettings s;
    s.method = method;
    auto spy = std::make_shared<SpyPropagator>(false);
    auto solver = OdSolver::from_conditions({paper_station()}, doppler_conditions(), spy, s);
    Vec6 guess = paper_truth();
    guess(0) += 10.0;
    const OdResult& r = solver.solve(guess);
    EXPECT_EQ(r.status, OdStatus::converged) << "method " << static_cast<int>(method);
    EXPECT_EQ(spy->calls, r.evaluations);
    EXPECT_EQ(spy->calls_guarded, core::kNoMallocGuard ? spy->calls : 0);
    EXPECT_TRUE(core::malloc_allowed());  // the scope ended with solve()
  }
}

TEST(OdSolver, SolveIsNoexceptAndAThrowingPropagatorIsAStatus) {
  static_assert(noexcept(std::declval<OdSolver&>().solve()), "OdSolver::solve() is noexcept");
  static_assert(noexcept(std::declval<OdSolver&>().solve(std::declval<const Vec6&>())),
                "OdSolver::solve(x0) is noexcept");
  for (auto method : {OdMethod::newton, OdMethod::gauss_newton, OdMethod::levenberg_marquardt}) {
    OdSettings s;
    s.method = method;
    auto spy = std::make_shared<SpyPropagator>(true);
    auto solver = OdSolver::from_conditions({paper_station()}, doppler_conditions(), spy, s);
    const OdResult& r = solver.solve(paper_truth());
    EXPECT_EQ(r.status, OdStatus::propagation_failed) << "method " << static_cast<int>(method);
    EXPECT_EQ(r.info.status, OdStatus::propagation_failed);
    EXPECT_EQ(r.iterations, 0);
    EXPECT_EQ(spy->calls, 1);  // the guess's evaluation failed: nothing else was tried
    EXPECT_TRUE(std::isinf(r.cost));
  }
}

TEST(OdQr, BitIdenticalToEigenHouseholderQrWithoutAllocation) {
  // The solver's in-place QR (od/detail/householder_qr.hpp) against Eigen's HouseholderQR::compute,
  // which OdSolver used before: every entry of the factor and every coefficient equal (==, no
  // tolerance: the OD results stay bit-identical), for every shape the solver meets (rows >= 6,
  // 6 or 7 columns) and the wide ones below it, with no malloc after resize (malloc_counter.hpp).
  std::mt19937 gen(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  int compared = 0;
  for (int cols : {6, 7})
    for (int rows = 1; rows <= 40; ++rows) {
      Eigen::MatrixXd a(rows, cols);
      for (Eigen::Index i = 0; i < a.size(); ++i)  // column scales 1e-3 .. 1e3, as in [J | r]
        a.data()[i] = normal(gen) * std::pow(10.0, static_cast<double>(i / rows % 7) - 3.0);
      const Eigen::HouseholderQR<Eigen::MatrixXd> ref(a);
      od::detail::HouseholderQrWorkspace w;
      w.resize(rows, cols);
      g_mallocs = 0;
      g_count = true;
      od::detail::householder_qr_inplace(a, w);
      g_count = false;
      EXPECT_EQ(g_mallocs.load(), 0) << rows << " x " << cols;
      EXPECT_TRUE((a.array() == ref.matrixQR().array()).all()) << rows << " x " << cols;
      EXPECT_TRUE((w.tau.array() == ref.hCoeffs().array()).all()) << rows << " x " << cols;
      ++compared;
    }
  EXPECT_EQ(compared, 80);
}

TEST(OdSolver, KeplerAndCvodesPropagatorsAgreeWithRk4) {
  const double t[3] = {0.0, 150.0, 300.0};
  Vec6 xk[3], xc[3], xr[3];
  Mat6 pk[3], pc[3], pr[3];
  KeplerStmPropagator kep(kMu);
  dynamics::ForceModel fm;
  fm.mu = kMu;
  CvodesStmPropagator cv(fm);
  Rk4StmPropagator rk(kMu, 0.5);
  ASSERT_TRUE(kep.propagate(paper_truth(), t, 3, xk, pk));
  ASSERT_TRUE(cv.propagate(paper_truth(), t, 3, xc, pc));
  ASSERT_TRUE(rk.propagate(paper_truth(), t, 3, xr, pr));
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT((xk[i] - xr[i]).head<3>().norm(), 1e-7);  // RK4 with 0.5 s steps: ~1e-9 relative
    EXPECT_LT((xk[i] - xc[i]).head<3>().norm(), 1e-5);  // CVODES rtol 1e-10
    SATGNC_EXPECT_REL(pk[i], pr[i], 1e-7);
  }
  // Newton on the paper's conditions with the exact Kepler STM: same convergence as with RK4.
  OdSettings s;
  s.method = OdMethod::newton;
  auto solver = OdSolver::from_conditions({paper_station()}, doppler_conditions(),
                                          std::make_shared<KeplerStmPropagator>(kMu), s);
  Vec6 guess = paper_truth();
  guess(0) += 40.0;
  const OdResult& r = solver.solve(guess);
  EXPECT_EQ(r.status, OdStatus::converged);
  EXPECT_LE(r.iterations, 5);
  // The data come from RK4 (h = 1 s), so the Kepler solution differs by the RK4 error (< 1 m).
  EXPECT_LT((r.x0 - paper_truth()).head<3>().norm(), 1e-3);
}

TEST(OdSolver, ResultDefaultsToUnsolvedAndStatusesKeepTheirValues) {
  EXPECT_EQ(OdResult{}.status, OdStatus::unsolved);
  // Appended statuses: the existing values keep their numbers.
  EXPECT_EQ(static_cast<int>(OdStatus::degenerate_geometry), 5);
  EXPECT_EQ(static_cast<int>(OdStatus::unsolved), 6);
  EXPECT_EQ(static_cast<int>(OdStatus::stalled), 7);
  EXPECT_EQ(std::string(status_message(OdStatus::unsolved)), "not solved yet");
  auto solver = OdSolver::from_conditions({paper_station()}, doppler_conditions(), prop());
  EXPECT_EQ(solver.result().status, OdStatus::unsolved);
}

// The solver contract (core/solver.hpp): set_initial_guess + solve() is solve(guess); info mirrors
// the result and carries the residuals and the run time.
TEST(OdSolver, SetInitialGuessThenSolveIsSolveOfTheGuess) {
  OdSettings s;
  s.method = OdMethod::newton;
  auto a = OdSolver::from_conditions({paper_station()}, doppler_conditions(), prop(), s);
  auto b = OdSolver::from_conditions({paper_station()}, doppler_conditions(), prop(), s);
  EXPECT_EQ(a.result().info.status, OdStatus::unsolved);
  Vec6 guess = paper_truth();
  guess(0) += 20.0;
  const OdResult& ra = a.solve(guess);
  b.set_initial_guess(guess);
  const OdResult& rb = b.solve();
  EXPECT_EQ(&rb, &b.result());
  ASSERT_EQ(rb.status, OdStatus::converged);
  EXPECT_EQ(ra.iterations, rb.iterations);
  EXPECT_EQ((ra.x0 - rb.x0).norm(), 0.0);  // same iterates
  EXPECT_EQ(rb.info.status, rb.status);
  EXPECT_EQ(rb.info.iterations, rb.iterations);
  EXPECT_NEAR(rb.info.primal_residual, std::sqrt(2.0 * rb.cost / b.rows()), 1e-15);
  EXPECT_GT(rb.info.dual_residual, 0.0);  // the last Newton step
  EXPECT_LT(rb.info.dual_residual, 1e-3);
  EXPECT_GT(rb.info.solve_time, 0.0);
}

TEST(OdSolver, RankDeficientIsSingularForEveryMethod) {
  // One station listed three times, range and range-rate at t = 0: rank 2, condition ~1e32.
  const Station st = paper_station();
  std::vector<Measurement> m;
  for (int i = 0; i < 3; ++i) {
    double rho = 0, rhodot = 0;
    predict_measurement(MeasurementType::range, paper_truth(), st.state(0.0), rho);
    predict_measurement(MeasurementType::range_rate, paper_truth(), st.state(0.0), rhodot);
    m.push_back({0.0, MeasurementType::range, rho, 1e-3, i});
    m.push_back({0.0, MeasurementType::range_rate, rhodot, 1e-6, i});
  }
  for (auto method : {OdMethod::newton, OdMethod::gauss_newton, OdMethod::levenberg_marquardt}) {
    OdSettings s;
    s.method = method;
    auto solver = OdSolver::from_measurements({st, st, st}, m, prop(), s);
    const OdResult& r = solver.solve(paper_truth() + Vec6::Constant(1e-3));
    EXPECT_EQ(r.status, OdStatus::singular) << "method " << static_cast<int>(method);
    EXPECT_EQ(r.rank, 2);
    EXPECT_TRUE(std::isfinite(r.cost));
    EXPECT_TRUE(std::isinf(r.covariance(0, 0)));
  }
}

TEST(OdSolver, FailedNewtonReturnsTheBestIterateWithFiniteHistory) {
  OdSettings s;
  s.method = OdMethod::newton;
  auto solver = OdSolver::from_conditions({paper_station()}, doppler_conditions(), prop(), s);
  Vec6 guess = paper_truth();
  guess.head<3>() += Vec3(200.0, -200.0, 200.0);
  guess.tail<3>() += Vec3(0.2, -0.2, 0.2);
  const OdResult& r = solver.solve(guess);
  ASSERT_NE(r.status, OdStatus::converged);
  double best = r.history_cost(0);
  for (int k = 0; k <= r.iterations; ++k) {
    EXPECT_TRUE(r.history_x0.row(k).allFinite()) << "row " << k;
    EXPECT_TRUE(std::isfinite(r.history_cost(k)));
    best = std::min(best, r.history_cost(k));
  }
  EXPECT_DOUBLE_EQ(r.cost, best);
  EXPECT_GT(r.cost, 0.0);
  // A guess below the surface has no residuals at all: cost +inf, never 0.
  Vec6 inside = paper_truth();
  inside.head<3>() *= 0.5;
  const OdResult& ri = solver.solve(inside);
  EXPECT_EQ(ri.status, OdStatus::diverged);
  EXPECT_EQ(ri.iterations, 0);
  EXPECT_TRUE(std::isinf(ri.cost));
  EXPECT_TRUE(ri.history_x0.row(0).isApprox(inside.transpose()));
}

TEST(OdSolver, LineSearchAndGeodesicPathsDoNotAllocate) {
  // Two stations, far guess: GN halves steps and uses the geodesic probe, LM rejects trials.
  const TwoStationData data = two_station_data();
  const std::vector<Station>& st = data.stations;
  const std::vector<Measurement>& m = data.measurements;
  Vec6 guess = paper_truth();
  guess.head<3>() += Vec3(50.0, -40.0, 30.0);
  guess.tail<3>() += Vec3(0.02, -0.01, 0.03);
  for (auto method : {OdMethod::gauss_newton, OdMethod::levenberg_marquardt}) {
    OdSettings s;
    s.method = method;
    auto solver = OdSolver::from_measurements(st, m, prop(), s);
    solver.solve(guess);  // warm-up
    g_mallocs = 0;
    g_count = true;
    const OdResult& r = solver.solve(guess);
    g_count = false;
    EXPECT_EQ(g_mallocs.load(), 0) << "method " << static_cast<int>(method);
    EXPECT_EQ(r.status, OdStatus::converged);
    EXPECT_GT(r.evaluations, r.iterations + 1);  // trials beyond the accepted steps happened
  }
}

TEST(OdSolver, ValleyCorrectorPathDoesNotAllocateAndFinishesTheOneStationPass) {
  // The paper's 300 s pass from one station with deterministic 1 m / 1 mm/s "noise": from the truth
  // the minimum lies kilometres away along a curved valley. The corrector runs (evaluations differ
  // from valley_corrections = 0), allocates nothing, and both methods end converged below the cost
  // at the truth.
  std::vector<Station> st{paper_station()};
  std::vector<double> t;
  for (int i = 0; i <= 30; ++i) t.push_back(10.0 * i);
  std::vector<double> rho, rhodot;
  observe(paper_truth(), st, t, 0, rho, rhodot);
  std::vector<Measurement> m;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double k = static_cast<double>(i);
    m.push_back({t[i], MeasurementType::range, rho[i] + 1e-3 * std::sin(1.7 * k + 0.3), 1e-3, 0});
    m.push_back({t[i], MeasurementType::range_rate, rhodot[i] + 1e-6 * std::cos(2.3 * k), 1e-6, 0});
  }
  for (auto method : {OdMethod::gauss_newton, OdMethod::levenberg_marquardt}) {
    OdSettings s;
    s.method = method;
    auto solver = OdSolver::from_measurements(st, m, prop(), s);
    Eigen::VectorXd r;
    ASSERT_EQ(solver.evaluate(paper_truth(), r, nullptr), OdStatus::converged);
    const double cost_truth = 0.5 * r.cwiseQuotient(solver.row_sigmas()).squaredNorm();
    solver.solve(paper_truth());  // warm-up
    g_mallocs = 0;
    g_count = true;
    const OdResult& res = solver.solve(paper_truth());
    g_count = false;
    EXPECT_EQ(g_mallocs.load(), 0) << "method " << static_cast<int>(method);
    EXPECT_EQ(res.status, OdStatus::converged) << "method " << static_cast<int>(method);
    EXPECT_LE(res.cost, cost_truth);
    const int evals = res.evaluations;
    s.valley_corrections = 0;
    solver.set_settings(s);
    EXPECT_NE(solver.solve(paper_truth()).evaluations, evals);
  }
}

TEST(OdSolver, ValleyCorrectionsSettingIsValidated) {
  OdSettings s;
  s.valley_corrections = -1;
  EXPECT_THROW(s.validate(), std::invalid_argument);
  s.valley_corrections = 101;
  EXPECT_THROW(s.validate(), std::invalid_argument);
}
