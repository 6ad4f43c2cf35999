// Staircase, PBH and Kalman rank tests: the paper's six results at omega = 1, LEO and GEO, the paper's
// printed Kalman matrices, duality, similarity / scaling invariance, the ill-conditioned pair, planted
// random systems, loss tables, distance to uncontrollability, bad input.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <random>

#include "error_checks.hpp"
#include "satgnc/analysis/linearize.hpp"
#include "satgnc/analysis/rank.hpp"
#include "satgnc/dynamics/polar.hpp"
#include "testing.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using namespace satgnc::analysis;  // test TU only
using satgnc::dynamics::PolarModel;

namespace {
constexpr double kMu = 398600.4418;
struct Orbit {
  const char* name;
  double sigma, omega;
};
const Orbit kOrbits[] = {{"omega=1", 1.0, 1.0},
                         {"LEO", 6778.137, std::sqrt(kMu / (6778.137 * 6778.137 * 6778.137))},
                         {"GEO", 42164.17, std::sqrt(kMu / (42164.17 * 42164.17 * 42164.17))}};

MatrixXd cols(const MatrixXd& M, std::vector<int> idx) {
  MatrixXd out(M.rows(), idx.size());
  for (size_t i = 0; i < idx.size(); ++i) out.col(i) = M.col(idx[i]);
  return out;
}
MatrixXd rows(const MatrixXd& M, std::vector<int> idx) {
  MatrixXd out(idx.size(), M.cols());
  for (size_t i = 0; i < idx.size(); ++i) out.row(i) = M.row(idx[i]);
  return out;
}
MatrixXd random_orthogonal(int n, std::mt19937& rng) {
  std::normal_distribution<double> N;
  MatrixXd G(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) G(i, j) = N(rng);
  Eigen::HouseholderQR<MatrixXd> qr(G);
  return qr.householderQ();
}
MatrixXd randn(int r, int c, std::mt19937& rng) {
  std::normal_distribution<double> N;
  MatrixXd G(r, c);
  for (int j = 0; j < c; ++j)
    for (int i = 0; i < r; ++i) G(i, j) = N(rng);
  return G;
}
}  // namespace

TEST(Rank, PaperSixResultsAtOmegaOneLeoGeo) {
  // Paper section 4 (and paper_tables.json): ranks 4 / 3 / 4 (both / radial u1 only / tangential u2
  // only) and 4 / 3 / 4 (radius+angle / radius only / angle only). Exact integers: no rounding slack.
  for (const Orbit& o : kOrbits) {
    SCOPED_TRACE(o.name);
    const PolarModel m(o.sigma, o.omega);
    const MatrixXd A = m.A(), B = m.B();
    const MatrixXd C = rows(MatrixXd::Identity(4, 4), {0, 2});
    const std::vector<std::vector<int>> sets = {{0, 1}, {0}, {1}};
    const int expect[] = {4, 3, 4};
    RankSettings units;
    units.units = polar_units(o.sigma, o.omega);
    for (int i = 0; i < 3; ++i) {
      const Verdict v = expect[i] == 4 ? Verdict::full_rank : Verdict::rank_deficient;
      for (StairMethod sm : {StairMethod::svd, StairMethod::qrcp}) {
        RankSettings s;
        s.stair = sm;
        const auto c = staircase(A, cols(B, sets[i]), Property::controllability, s);
        EXPECT_EQ(c.summary.rank, expect[i]);
        EXPECT_EQ(c.summary.verdict, v) << c.summary.reason;
        const auto ob = staircase(A, rows(C, sets[i]), Property::observability, s);
        EXPECT_EQ(ob.summary.rank, expect[i]);
        EXPECT_EQ(ob.summary.verdict, v) << ob.summary.reason;
      }
      units.units->input =
          VectorXd::Constant(static_cast<Eigen::Index>(sets[i].size()), o.sigma * o.omega * o.omega);
      const auto cu = staircase(A, cols(B, sets[i]), Property::controllability, units);
      EXPECT_EQ(cu.summary.verdict, v);
      EXPECT_GE(cu.summary.margin, 1e12);  // dimensionless: every stair O(1)
      EXPECT_EQ(pbh(A, cols(B, sets[i]), Property::controllability).summary.verdict, v);
      EXPECT_EQ(pbh(A, rows(C, sets[i]), Property::observability).summary.verdict, v);
    }
    // Uncontrollable / unobservable mode: the zero eigenvalue (the along-track drift).
    const auto rad = staircase(A, cols(B, {0}), Property::controllability);
    ASSERT_EQ(rad.uncontrollable_modes.size(), 1);
    EXPECT_LE(std::abs(rad.uncontrollable_modes(0)), 1e-14);
    EXPECT_EQ(rad.stairs, (std::vector<int>{1, 1, 1}));
    EXPECT_EQ(staircase(A, B, Property::controllability).indices, (std::vector<int>{2, 2}));
    EXPECT_EQ(staircase(A, cols(B, {1}), Property::controllability).indices, (std::vector<int>{4}));
  }
}

TEST(Rank, KalmanLooseToleranceFailsAtOrbitalRatesStaircaseDoesNot) {
  // Tangential-only: sigma_min / sigma_max of the Kalman matrix is 8.7e-9 at LEO and 2.3e-12 at GEO.
  const double ratio_expect[] = {0.0905, 8.69e-9, 2.33e-12};
  for (int i = 0; i < 3; ++i) {
    const Orbit& o = kOrbits[i];
    SCOPED_TRACE(o.name);
    const PolarModel m(o.sigma, o.omega);
    const MatrixXd K = kalman_controllability_matrix(m.A(), cols(m.B(), {1}));
    const VectorXd sv = Eigen::JacobiSVD<MatrixXd>(K).singularValues();
    SATGNC_EXPECT_REL(sv(3) / sv(0), ratio_expect[i], 2e-3);  // 3 printed digits
    RankSettings loose;
    loose.rtol = 1e-8;
    const RankReport kr = kalman_rank(m.A(), cols(m.B(), {1}), Property::controllability, loose);
    EXPECT_EQ(kr.rank, i == 0 ? 4 : 3);  // wrong (3) at LEO and GEO
    const auto st = staircase(m.A(), cols(m.B(), {1}), Property::controllability, loose);
    EXPECT_EQ(st.summary.rank, 4);  // right: the per-stair values are 1, 2 omega, 3 omega^2
    // In km / km/s at GEO, 3 omega^2 / ||A|| = 1.1e-8 is only 1.1 x the loose tolerance: the staircase
    // says so instead of guessing; in dimensionless units every stair is O(1).
    EXPECT_EQ(st.summary.verdict, i == 2 ? Verdict::not_robustly_decidable : Verdict::full_rank);
    loose.units = polar_units(o.sigma, o.omega);
    loose.units->input = VectorXd::Constant(1, o.sigma * o.omega * o.omega);
    const auto sd = staircase(m.A(), cols(m.B(), {1}), Property::controllability, loose);
    EXPECT_EQ(sd.summary.verdict, Verdict::full_rank);
    EXPECT_GE(sd.summary.margin, 1e6);
  }
}

TEST(Rank, KalmanMatricesMatchPaperPrintedExceptTheCA2Slip) {
  for (double w : {1.0, 2.0, 0.37}) {
    const PolarModel m(1.0, w);
    const MatrixXd A = m.A(), B = m.B();
    const double w2 = w * w, w3 = w2 * w;
    MatrixXd K(4, 8), K1(4, 4), K2(4, 4), O(8, 4), O1(4, 4), O2(4, 4), A2(4, 4), A3(4, 4);
    // As printed in section 4.1 / 4.2.
    K << 0, 0, 1, 0, 0, 2 * w, -w2, 0, 1, 0, 0, 2 * w, -w2, 0, 0, -2 * w3, 0, 0, 0, 1, -2 * w, 0, 0, -4 * w2,
        0, 1, -2 * w, 0, 0, -4 * w2, 2 * w3, 0;
    K1 << 0, 1, 0, -w2, 1, 0, -w2, 0, 0, 0, -2 * w, 0, 0, -2 * w, 0, 2 * w3;
    K2 << 0, 0, 2 * w, 0, 0, 2 * w, 0, -2 * w3, 0, 1, 0, -4 * w2, 1, 0, -4 * w2, 0;
    O << 1, 0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 3 * w2, 0, 0, 2 * w, 0, -2 * w, 0, 0, 0, -w2, 0, 0,
        -6 * w3, 0, 0, -4 * w2;
    O1 << 1, 0, 0, 0, 0, 1, 0, 0, 3 * w2, 0, 0, 2 * w, 0, -w2, 0, 0;
    O2 << 0, 0, 1, 0, 0, 0, 0, 1, 0, -2 * w, 0, 0, -6 * w3, 0, 0, -4 * w2;
    A2 << 3 * w2, 0, 0, 2 * w, 0, -w2, 0, 0, 0, -2 * w, 0, 0, -6 * w3, 0, 0, -4 * w2;
    A3 << 0, -w2, 0, 0, -3 * w2 * w2, 0, 0, -2 * w3, -6 * w3, 0, 0, -4 * w2, 0, 2 * w3, 0, 0;
    const double tol = 1e-14;
    SATGNC_EXPECT_REL(MatrixXd(A * A), A2, tol);
    SATGNC_EXPECT_REL(MatrixXd(A * A * A), A3, tol);
    SATGNC_EXPECT_REL(kalman_controllability_matrix(A, B), K, tol);
    SATGNC_EXPECT_REL(kalman_controllability_matrix(A, cols(B, {0})), K1, tol);
    SATGNC_EXPECT_REL(kalman_controllability_matrix(A, cols(B, {1})), K2, tol);
    const MatrixXd C = rows(MatrixXd::Identity(4, 4), {0, 2});
    // Paper stacks [C; CA; CA^2; CA^3] output-block by output-block, as we do.
    SATGNC_EXPECT_REL(kalman_observability_matrix(A, C), O, tol);
    SATGNC_EXPECT_REL(kalman_observability_matrix(A, rows(C, {0})), O1, tol);
    SATGNC_EXPECT_REL(kalman_observability_matrix(A, rows(C, {1})), O2, tol);
    // The separately printed CA^2 = [[-3w^2, 0, 0, 2w], [0, -2w, 0, 0]] has a sign slip in (0, 0):
    MatrixXd CA2_paper(2, 4);
    CA2_paper << -3 * w2, 0, 0, 2 * w, 0, -2 * w, 0, 0;
    const MatrixXd diff = C * A * A - CA2_paper;
    EXPECT_DOUBLE_EQ(diff(0, 0), 6 * w2);  // algebra gives +3w^2
    EXPECT_EQ((diff.array().abs() > 0).count(), 1);
  }
}

TEST(Rank, DualityAndSimilarityAndScalingInvariance) {
  std::mt19937 rng(11);
  for (const Orbit& o : kOrbits) {
    SCOPED_TRACE(o.name);
    const PolarModel m(o.sigma, o.omega);
    const MatrixXd A = m.A(), B = m.B();
    for (std::vector<int> s : {std::vector<int>{0, 1}, {0}, {1}}) {
      const auto ref = staircase(A, cols(B, s), Property::controllability);
      const auto dual = staircase(A.transpose(), cols(B, s).transpose(), Property::observability);
      EXPECT_EQ(dual.summary.rank, ref.summary.rank);
      EXPECT_EQ(dual.summary.verdict, ref.summary.verdict);
      for (int trial = 0; trial < 3; ++trial) {
        const MatrixXd U = random_orthogonal(4, rng);
        const auto sim = staircase(U * A * U.transpose(), U * cols(B, s), Property::controllability);
        EXPECT_EQ(sim.summary.rank, ref.summary.rank);
        EXPECT_EQ(sim.summary.verdict, ref.summary.verdict);
        const auto p = pbh(U * A * U.transpose(), U * cols(B, s), Property::controllability);
        EXPECT_EQ(p.summary.verdict, ref.summary.verdict);
      }
      for (double ts : {1e-4, 1e3}) {  // time unit change: A, B -> ts A, ts B; input unit 1e6
        const auto sc = staircase(ts * A, 1e6 * ts * cols(B, s), Property::controllability);
        EXPECT_EQ(sc.summary.verdict, ref.summary.verdict);
        EXPECT_EQ(sc.summary.rank, ref.summary.rank);
      }
      // The raw polar coordinates are a diagonal (non-orthogonal) similarity; same verdict.
      EXPECT_EQ(staircase(m.A(satgnc::dynamics::PolarCoordinates::raw),
                          cols(m.B(satgnc::dynamics::PolarCoordinates::raw), s), Property::controllability)
                    .summary.verdict,
                ref.summary.verdict);
    }
  }
}

TEST(Rank, IllConditionedPairIsNotRobustlyDecidable) {
  for (double d : {1e-17, 1e-20, 1e-300}) {
    MatrixXd A(2, 2), B(2, 1);
    A << 1, d, 0, 1;
    B << 1, d;
    // Exactly: det [B, AB] = -d^3 != 0 (controllable), but at distance d from A = I, B = e1.
    for (StairMethod sm : {StairMethod::svd, StairMethod::qrcp}) {
      RankSettings s;
      s.stair = sm;
      const auto r = staircase(A, B, Property::controllability, s);
      EXPECT_EQ(r.summary.verdict, Verdict::not_robustly_decidable) << d;
      EXPECT_FALSE(r.summary.reason.empty());
    }
    EXPECT_EQ(pbh(A, B, Property::controllability).summary.verdict, Verdict::not_robustly_decidable);
    EXPECT_LE(distance_to_uncontrollability(A, B).refined, 1e-15);
  }
  MatrixXd A(2, 2), B(2, 1);
  A << 1, 0.5, 0, 1;
  B << 1, 0.5;
  EXPECT_EQ(staircase(A, B, Property::controllability).summary.verdict, Verdict::full_rank);
  // In the fuzz band: sigma at 10 x rtol.
  MatrixXd A2 = MatrixXd::Zero(2, 2), B2(2, 1);
  B2 << 1, 0;
  RankSettings s;
  s.rtol = 1e-10;
  A2(1, 0) = 1e-9;
  A2(0, 0) = 1.0;
  const auto band = staircase(A2, B2, Property::controllability, s);
  EXPECT_EQ(band.summary.rank, 2);
  EXPECT_EQ(band.summary.verdict, Verdict::not_robustly_decidable);
  EXPECT_NEAR(band.summary.margin, 10.0, 1e-6);
}

TEST(Rank, PlantedRandomSystemsUpTo50States) {
  std::mt19937 rng(2024);
  int checked = 0;
  for (int n : {3, 5, 8, 13, 21, 34, 50}) {
    for (int trial = 0; trial < 4; ++trial) {
      const int m = 1 + trial % 3;
      const int r = 1 + static_cast<int>(rng() % static_cast<unsigned>(n));  // planted rank 1..n
      MatrixXd At = MatrixXd::Zero(n, n), Bt = MatrixXd::Zero(n, m);
      At.topLeftCorner(r, r) = randn(r, r, rng);
      At.topRightCorner(r, n - r) = randn(r, n - r, rng);
      At.bottomRightCorner(n - r, n - r) = randn(n - r, n - r, rng);
      Bt.topRows(r) = randn(r, m, rng);
      const double ts = std::pow(10.0, -4.0 * (trial % 2));  // time scale 1 or 1e-4
      const MatrixXd U = random_orthogonal(n, rng);
      const MatrixXd A = ts * U * At * U.transpose(), B = U * Bt;
      for (StairMethod sm : {StairMethod::svd, StairMethod::qrcp}) {
        RankSettings s;
        s.stair = sm;
        const auto st = staircase(A, B, Property::controllability, s);
        EXPECT_EQ(st.summary.rank, r) << "n=" << n << " m=" << m;
        EXPECT_EQ(st.summary.verdict, r == n ? Verdict::full_rank : Verdict::rank_deficient)
            << st.summary.reason;
        // Controllable subspace = range(U[:, :r]), to the subspace's own sensitivity (rounding over
        // sep(A11, A22), which for Gaussian blocks reaches 1e-9 at 50 states).
        const MatrixXd Qc = st.Q.leftCols(r), Up = U.leftCols(r);
        EXPECT_LE((Qc - Up * (Up.transpose() * Qc)).norm(), 1e-8);
        if (r < n && sm == StairMethod::svd) {
          // Uncontrollable modes = eig(A22) (each matched to the nearest).
          const Eigen::VectorXcd planted =
              Eigen::EigenSolver<MatrixXd>(ts * MatrixXd(At.bottomRightCorner(n - r, n - r))).eigenvalues();
          ASSERT_EQ(st.uncontrollable_modes.size(), planted.size());
          for (Eigen::Index i = 0; i < planted.size(); ++i) {
            double best = 1e300;
            for (Eigen::Index j = 0; j < planted.size(); ++j)
              best = std::min(best, std::abs(planted(i) - st.uncontrollable_modes(j)));
            EXPECT_LE(best, 1e-8 * ts * std::sqrt(n));
          }
        }
      }
      // Orthogonal staircase form reproduces A up to the zeroed (rejected) mass below the stairs.
      const auto st = staircase(A, B, Property::controllability);
      EXPECT_LE((st.Q * st.A_staircase * st.Q.transpose() - A).norm(),
                10.0 * std::sqrt(n) * std::max(st.summary.sigma_next, 1e-14) * A.norm());
      ++checked;
    }
  }
  EXPECT_EQ(checked, 28);
}

TEST(Rank, PbhHandlesDefectiveZeroPairAndStabilizability) {
  const Orbit& leo = kOrbits[1];
  const PolarModel m(leo.sigma, leo.omega);
  const auto p = pbh(m.A(), cols(m.B(), {0}), Property::controllability);
  int zero_mult = 0;
  for (const auto& md : p.modes)
    if (std::abs(md.lambda) < 1e-6) {
      zero_mult = md.multiplicity;
      EXPECT_FALSE(md.controllable);
      EXPECT_EQ(md.deficiency, 1);
    } else {
      EXPECT_TRUE(md.controllable);
    }
  EXPECT_EQ(zero_mult, 2);  // the Jordan pair 0, 0 split by rounding and merged again
  EXPECT_FALSE(p.stabilizable_ct);
  EXPECT_EQ(p.summary.rank, 3);
  const auto p2 = pbh(m.A(), cols(m.B(), {1}), Property::controllability);
  EXPECT_TRUE(p2.stabilizable_ct);
  EXPECT_EQ(p2.summary.verdict, Verdict::full_rank);
  // Discrete-time notion: A_d = 0.5 I with an uncontrollable stable mode is DT-stabilizable.
  MatrixXd Ad = 0.5 * MatrixXd::Identity(2, 2), Bd(2, 1);
  Bd << 1, 0;
  const auto pd = pbh(Ad, Bd, Property::controllability);
  EXPECT_TRUE(pd.stabilizable_dt);
  EXPECT_FALSE(pd.stabilizable_ct);  // 0.5 > 0 as a continuous-time eigenvalue
  // CW: the zero pair and the two +-in pairs.
  const auto cw = cw_model(1.1e-3);
  const auto pc = pbh(cw.A, cols(cw.B, {0}), Property::controllability);
  int total = 0;
  for (const auto& md : pc.modes) total += md.multiplicity;
  EXPECT_EQ(total, 6);
  EXPECT_EQ(pc.summary.rank, 3);  // radial only: along-track drift and both out-of-plane modes lost
}

TEST(Rank, LossTablesPolarAndCw) {
  const Orbit& geo = kOrbits[2];
  const PolarModel m(geo.sigma, geo.omega);
  const auto lt = loss_table(m.A(), m.B(), Property::controllability);
  ASSERT_EQ(lt.size(), 3u);
  EXPECT_EQ(lt[0].channels, (std::vector<int>{0, 1}));
  EXPECT_EQ(lt[1].channels, (std::vector<int>{0}));
  EXPECT_EQ(lt[2].channels, (std::vector<int>{1}));
  EXPECT_EQ(lt[0].rank, 4);
  EXPECT_EQ(lt[1].rank, 3);
  EXPECT_EQ(lt[2].rank, 4);
  EXPECT_EQ(lt[2].verdict, Verdict::full_rank);
  SATGNC_EXPECT_REL(lt[2].kalman_ratio, 2.33e-12, 2e-3);
  const auto lo = loss_table(m.A(), rows(MatrixXd::Identity(4, 4), {0, 2}), Property::observability);
  EXPECT_EQ(lo[0].rank, 4);
  EXPECT_EQ(lo[1].rank, 3);
  EXPECT_EQ(lo[2].rank, 4);

  // CW (x radial, y along-track, z normal), LEO mean motion, SI units.
  const auto cw = cw_model(1.13e-3);
  const auto ct = loss_table(cw.A, cw.B, Property::controllability);
  const auto ot = loss_table(cw.A, cw.C, Property::observability);
  ASSERT_EQ(ct.size(), 7u);
  // Order: {x,y,z}, {x,y}, {x,z}, {y,z}, {x}, {y}, {z}.
  const int ranks[] = {6, 4, 5, 6, 3, 4, 2};
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(ct[i].rank, ranks[i]) << i;
    EXPECT_EQ(ot[i].rank, ranks[i]) << i;  // the same pattern for position sensors
    EXPECT_NE(ct[i].verdict, Verdict::not_robustly_decidable);
  }
  EXPECT_EQ(ct[3].channels, (std::vector<int>{1, 2}));  // along-track + normal suffice
}

TEST(Rank, DistanceToUncontrollability) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 3; ++trial) {
    const MatrixXd A = randn(4, 4, rng), B = randn(4, 1, rng);
    const auto d = distance_to_uncontrollability(A, B);
    EXPECT_LE(d.refined, d.upper_bound);
    EXPECT_GT(d.refined, 0.0);
    // Brute-force grid over the eigenvalue box: the refinement is within 1% of the grid minimum.
    const Eigen::VectorXcd ev = Eigen::EigenSolver<MatrixXd>(A).eigenvalues();
    double grid = 1e300;
    const double R = ev.cwiseAbs().maxCoeff() * 1.5 + 1.0;
    for (int i = 0; i <= 300; ++i)
      for (int j = 0; j <= 150; ++j) {
        const std::complex<double> l(-R + 2 * R * i / 300.0, R * j / 150.0);
        Eigen::MatrixXcd M(4, 5);
        M.leftCols(4) = A.cast<std::complex<double>>() - l * Eigen::MatrixXcd::Identity(4, 4);
        M.col(4) = B.cast<std::complex<double>>();
        grid = std::min(grid, Eigen::JacobiSVD<Eigen::MatrixXcd>(M).singularValues()(3));
      }
    EXPECT_LE(d.refined, grid * 1.01);
  }
  const PolarModel m(1.0, 1.0);
  EXPECT_LE(distance_to_uncontrollability(m.A(), cols(m.B(), {0})).refined, 1e-15);
}

TEST(Rank, BadInputThrowsNamingTheArgument) {
  const MatrixXd A = MatrixXd::Identity(3, 3), B = MatrixXd::Ones(3, 1), C = MatrixXd::Ones(1, 3);
  auto msg = [](auto fn) { return satgnc::testing::message_of(fn, "no throw"); };
  EXPECT_EQ(msg([&] { staircase(MatrixXd::Ones(3, 2), B, Property::controllability); }).rfind("A:", 0), 0u);
  EXPECT_EQ(msg([&] { staircase(A, MatrixXd::Ones(2, 1), Property::controllability); }).rfind("B:", 0), 0u);
  EXPECT_EQ(msg([&] { staircase(A, MatrixXd::Ones(1, 2), Property::observability); }).rfind("C:", 0), 0u);
  EXPECT_EQ(msg([&] { staircase(A, MatrixXd(3, 0), Property::controllability); }).rfind("B:", 0), 0u);
  EXPECT_EQ(msg([&] { pbh(A, MatrixXd(0, 3), Property::observability); }).rfind("C:", 0), 0u);
  MatrixXd An = A;
  An(1, 1) = NAN;
  EXPECT_EQ(msg([&] { staircase(An, B, Property::controllability); }).rfind("A:", 0), 0u);
  MatrixXd Bn = B;
  Bn(0, 0) = INFINITY;
  EXPECT_EQ(msg([&] { kalman_rank(A, Bn, Property::controllability); }).rfind("B:", 0), 0u);
  RankSettings s;
  s.rtol = -1e-12;
  EXPECT_EQ(msg([&] { staircase(A, B, Property::controllability, s); }).rfind("rtol:", 0), 0u);
  s.rtol = 0;
  s.fuzz = 0.5;
  EXPECT_EQ(msg([&] { pbh(A, B, Property::controllability, s); }).rfind("fuzz:", 0), 0u);
  s.fuzz = 100;
  s.cluster_rtol = -1;
  EXPECT_EQ(msg([&] { pbh(A, B, Property::controllability, s); }).rfind("cluster_rtol:", 0), 0u);
  EXPECT_EQ(msg([&] { loss_table(A, MatrixXd::Ones(3, 17), Property::controllability); }).rfind("B:", 0), 0u);
  EXPECT_EQ(msg([&] { staircase(MatrixXd(0, 0), MatrixXd(0, 1), Property::controllability); }).rfind("A:", 0),
            0u);
  RankSettings u;
  u.units = Units{1.0, VectorXd::Ones(2), {}, {}};
  EXPECT_EQ(msg([&] { staircase(A, B, Property::controllability, u); }).rfind("units.state:", 0), 0u);
  EXPECT_EQ(msg([&] {
              distance_to_uncontrollability(A, B, Property::controllability, {}, -1);
            }).rfind("max_iter", 0),
            0u);
  (void)C;
}
