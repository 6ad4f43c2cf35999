// Linearization tools of satgnc/analysis/linearize.hpp: fd_jacobian against an analytic Jacobian,
// linearize / two_body_jacobian against central differences on seeded random orbits, the analysis
// range / range-rate partials as wrappers of dynamics::predict_measurement, analysis::cw_model as the
// Hill-frame permutation of dynamics::CwModel, and the deprecated RotatingStation as a dynamics::Station.
#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "satgnc/analysis/linearize.hpp"
#include "satgnc/analysis/od_gramian.hpp"
#include "satgnc/dynamics/cw.hpp"
#include "satgnc/dynamics/measurement.hpp"
#include "satgnc/dynamics/station.hpp"
#include "satgnc/guidance/nonlinear_model.hpp"
#include "satgnc/guidance/two_satellite_truth.hpp"
#include "satgnc/od/measurement.hpp"
#include "satgnc/od/station.hpp"
#include "satgnc/od/time.hpp"
#include "testing.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
namespace an = satgnc::analysis;
namespace dyn = satgnc::dynamics;

namespace {
constexpr double kMu = 398600.4418;  // km^3/s^2

// Random bound orbit: perigee radius 6600..42000 km, eccentricity 0..0.6, random orientation and anomaly.
satgnc::Vec6 random_orbit(std::mt19937& gen) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double rp = 6600.0 + u01(gen) * 35400.0, e = 0.6 * u01(gen), nu = 6.283185307179586 * u01(gen);
  const double p = rp * (1.0 + e), r = p / (1.0 + e * std::cos(nu));
  const double vr = std::sqrt(kMu / p) * e * std::sin(nu), vt = std::sqrt(kMu / p) * (1.0 + e * std::cos(nu));
  const Eigen::Vector3d r_pf(r * std::cos(nu), r * std::sin(nu), 0.0);
  const Eigen::Vector3d v_pf(vr * std::cos(nu) - vt * std::sin(nu), vr * std::sin(nu) + vt * std::cos(nu),
                             0.0);
  const Eigen::Matrix3d R =
      Eigen::Quaterniond::UnitRandom().toRotationMatrix();  // Eigen's rand(), seeded below
  satgnc::Vec6 x;
  x << R * r_pf, R * v_pf;
  return x;
}

VectorXd two_body(double, const VectorXd& x, const VectorXd&) {
  const Eigen::Vector3d r = x.head<3>();
  VectorXd f(6);
  f << x.tail<3>(), -kMu / std::pow(r.norm(), 3) * r;
  return f;
}
}  // namespace

// Old qualified names still name the moved types (forwarding headers, issue 12).
static_assert(std::is_same_v<satgnc::od::Station, dyn::Station>);
static_assert(std::is_same_v<satgnc::od::Measurement, dyn::Measurement>);
static_assert(std::is_same_v<satgnc::od::MeasurementType, dyn::MeasurementType>);
static_assert(std::is_same_v<satgnc::guidance::DiscreteModel, dyn::DiscreteModel>);
static_assert(std::is_same_v<satgnc::guidance::TwoSatelliteMap, satgnc::propagation::TwoSatelliteMap>);
static_assert(std::is_same_v<satgnc::guidance::PropagatedTwoSatelliteMap,
                             satgnc::propagation::PropagatedTwoSatelliteMap>);
static_assert(std::is_same_v<satgnc::guidance::TwoSatelliteTruth, satgnc::propagation::TwoSatelliteTruth>);

TEST(Linearize, OldNamesForwardToTheMovedFunctions) {
  EXPECT_EQ(satgnc::od::julian_date(2000, 1, 1, 12, 0, 0.0), 2451545.0);
  EXPECT_EQ(satgnc::od::gmst_iau1982(2451545.0), satgnc::core::gmst_iau1982(2451545.0));
  EXPECT_EQ(satgnc::od::ellipsoids::wgs84.a, 6378.137);
  EXPECT_STREQ(satgnc::od::measurement_type_name(satgnc::od::MeasurementType::range_rate), "range_rate");
}

TEST(Linearize, FdJacobianMatchesAnAnalyticJacobian) {
  // f(x, u) = [sin(x0) x1 + u0 u1, x0^2 - cos(u1), exp(0.3 x1) u0]
  auto f = [](double, const VectorXd& x, const VectorXd& u) {
    VectorXd y(3);
    y << std::sin(x(0)) * x(1) + u(0) * u(1), x(0) * x(0) - std::cos(u(1)), std::exp(0.3 * x(1)) * u(0);
    return y;
  };
  VectorXd x(2), u(2);
  x << 0.7, -1.3;
  u << 2.0, 0.4;
  MatrixXd A_exact(3, 2), B_exact(3, 2);
  A_exact << std::cos(x(0)) * x(1), std::sin(x(0)), 2.0 * x(0), 0.0, 0.0, 0.3 * std::exp(0.3 * x(1)) * u(0);
  B_exact << u(1), u(0), 0.0, std::sin(u(1)), std::exp(0.3 * x(1)), 0.0;
  MatrixXd A, B;
  an::fd_jacobian(f, 0.0, x, u, A, B);
  ASSERT_EQ(A.rows(), 3);
  ASSERT_EQ(A.cols(), 2);
  ASSERT_EQ(B.rows(), 3);
  ASSERT_EQ(B.cols(), 2);
  // central differences with h ~ cbrt(eps): error ~ eps^(2/3) ~ 4e-11 relative
  SATGNC_EXPECT_REL(A, A_exact, 1e-9);
  SATGNC_EXPECT_REL(B, B_exact, 1e-9);
}

TEST(Linearize, TwoBodyJacobianAgreesWithCentralDifferencesOnRandomOrbits) {
  std::mt19937 gen(12);
  std::srand(12);  // Quaterniond::UnitRandom draws from std::rand
  double worst = 0.0;
  for (int i = 0; i < 50; ++i) {
    const satgnc::Vec6 x = random_orbit(gen);
    const VectorXd xv = x;
    auto jac = [](double, const VectorXd& z, const VectorXd&, MatrixXd& A, MatrixXd& B) {
      A = an::two_body_jacobian(z.head<3>(), kMu);
      B.resize(6, 0);
    };
    an::FdSettings fd;
    fd.x_scale = (VectorXd(6) << 1e3, 1e3, 1e3, 1.0, 1.0, 1.0).finished();
    const an::Linearization L = an::linearize(two_body, jac, 0.0, xv, VectorXd(0), fd);
    ASSERT_EQ(L.A.rows(), 6);
    ASSERT_EQ(L.A_fd.cols(), 6);
    EXPECT_EQ(L.B.cols(), 0);
    EXPECT_EQ(L.rel_err_B, 0.0);
    EXPECT_LT(L.rel_err_A, 1e-7) << "orbit " << i;
    worst = std::max(worst, L.rel_err_A);
    // the upper-right block is exactly I, the lower-left block symmetric (a gravity gradient)
    EXPECT_EQ((L.A.topRightCorner<3, 3>()), Eigen::Matrix3d::Identity());
    const Eigen::Matrix3d G = L.A.bottomLeftCorner(3, 3);
    EXPECT_LE((G - G.transpose()).cwiseAbs().maxCoeff(), 1e-15 * G.cwiseAbs().maxCoeff());
  }
  EXPECT_GT(worst, 0.0);  // the check compares two different computations
}

TEST(Linearize, RangePartialsAreDynamicsPredictMeasurement) {
  std::mt19937 gen(7);
  std::srand(7);
  std::uniform_real_distribution<double> s(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const satgnc::Vec6 x = random_orbit(gen);
    satgnc::Vec6 st;
    st << 6378.0 * Eigen::Vector3d(s(gen), s(gen), s(gen)).normalized(),
        0.4 * Eigen::Vector3d(s(gen), s(gen), 0.0);
    Eigen::Matrix<double, 1, 6> Hr, Hd;
    dyn::Row6 Ga, Gr;
    double vr = 0.0, vd = 0.0;
    ASSERT_TRUE(dyn::predict_measurement(dyn::MeasurementType::range, x, st, vr, &Ga));
    ASSERT_TRUE(dyn::predict_measurement(dyn::MeasurementType::range_rate, x, st, vd, &Gr));
    const double rho = an::range_partial(x.head<3>(), st.head<3>(), Hr);
    const double rhod = an::range_rate_partial(x.head<3>(), x.tail<3>(), st.head<3>(), st.tail<3>(), Hd);
    // one implementation: equal to 1e-15 relative (bitwise in practice)
    EXPECT_LE(satgnc::testing::rel_err(rho, vr), 1e-15);
    EXPECT_LE(satgnc::testing::rel_err(rhod, vd), 1e-15);
    EXPECT_LE(satgnc::testing::rel_err(Hr, Ga), 1e-15);
    EXPECT_LE(satgnc::testing::rel_err(Hd, Gr), 1e-15);
    EXPECT_EQ(Hr.tail<3>(), Eigen::RowVector3d::Zero());
  }
  // rho = 0: the analysis wrappers throw (predict_measurement returns false), naming r
  Eigen::Matrix<double, 1, 6> H = Eigen::Matrix<double, 1, 6>::Constant(5.0);
  const Eigen::Vector3d R(7000.0, 0.0, 0.0);
  try {
    an::range_partial(R, R, H);
    FAIL() << "range_partial(R, R) did not throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("satellite coincides with the station (range 0)"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(an::range_rate_partial(R, R, R, R, H), std::invalid_argument);
  EXPECT_EQ(H, (Eigen::Matrix<double, 1, 6>::Constant(5.0)));  // untouched on failure
  // a tiny but positive range still works in analysis (min_range is the smallest positive double)
  const Eigen::Vector3d Rp(7000.0 + 1e-9, 0.0, 0.0);
  EXPECT_NEAR(an::range_partial(Rp, R, H), 1e-9, 1e-12);
}

TEST(Linearize, CwModelIsTheHillPermutationOfCwModel) {
  for (const double n : {1.1e-3, 7.2921e-5, 1.0, 0.37}) {
    const an::LinearModel hill = an::cw_model(n);
    const dyn::CwModel cw(n, 1.0);
    const satgnc::Mat6 Ap = cw.A();
    const dyn::Mat63 Bp = cw.B();
    // hill x = paper y (radial), hill y = -paper x (along-track), z unchanged
    const int perm[6] = {1, 0, 2, 4, 3, 5};
    const double sign[6] = {1, -1, 1, 1, -1, 1};
    ASSERT_EQ(hill.A.rows(), 6);
    ASSERT_EQ(hill.B.cols(), 3);
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) EXPECT_EQ(hill.A(i, j), sign[i] * sign[j] * Ap(perm[i], perm[j])) << i << j;
      for (int j = 0; j < 3; ++j) EXPECT_EQ(hill.B(i, j), sign[i] * sign[j] * Bp(perm[i], perm[j])) << i << j;
    }
    // the textbook Hill entries, exactly as analysis::cw_model wrote them before issue 12
    EXPECT_EQ(hill.A(3, 0), 3.0 * n * n);
    EXPECT_EQ(hill.A(3, 4), 2.0 * n);
    EXPECT_EQ(hill.A(4, 3), -2.0 * n);
    EXPECT_EQ(hill.A(5, 2), -n * n);
    EXPECT_EQ(hill.A.topRightCorner(3, 3), Eigen::Matrix3d::Identity());
    EXPECT_EQ(hill.B.bottomRows(3), Eigen::Matrix3d::Identity());
    EXPECT_EQ(hill.B.topRows(3), Eigen::Matrix3d::Zero());
    for (int k = 0; k < 36; ++k) EXPECT_FALSE(std::signbit(hill.A(k)) && hill.A(k) == 0.0);  // no -0.0
    EXPECT_EQ(hill.C, (MatrixXd(3, 6) << MatrixXd::Identity(3, 3), MatrixXd::Zero(3, 3)).finished());
    // the paper frame through the same function is CwModel's own matrices
    const dyn::CwMatrices paper = dyn::cw_linear_model(cw);
    EXPECT_EQ(paper.A, Ap);
    EXPECT_EQ(paper.B, Bp);
  }
  EXPECT_THROW(an::cw_model(0.0), std::invalid_argument);
  try {
    an::cw_model(-1.0);
    FAIL() << "cw_model(-1) did not throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("mean_motion", 0), 0u) << e.what();
  }
}

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif
TEST(Linearize, RotatingStationIsADynamicsStation) {
  const an::RotatingStation old{Eigen::Vector3d(-2681.1, -4307.5, 3851.8), 7.27e-5};
  EXPECT_EQ(an::RotatingStation{}.rate, 7.27e-5);  // the paper default stays with the old struct
  const dyn::Station st = old;
  EXPECT_EQ(st.r0, old.r0);
  EXPECT_EQ(st.omega, old.rate);
  for (const double t : {0.0, 10.0, -600.0, 3600.0}) {
    const satgnc::Vec6 s = st.state(t);
    EXPECT_EQ(s.head<3>(), old.position(t));
    // velocity: omega z x R, equal up to the sign of a zero
    EXPECT_EQ(s.tail<3>(), old.velocity(t));
  }
  // the Gramian is the same through both overloads (same partials, same station states)
  satgnc::Vec6 x0;
  x0 << 5836.8907, 1265.616, 3411.496, 0.3146, 6.9401, -3.1125;
  const std::vector<double> times = {0.0, 60.0, 120.0, 180.0, 240.0};
  const an::OdGramianReport a = an::od_observability_gramian(x0, old, times, an::OdMeasurement::both, kMu);
  const an::OdGramianReport b = an::od_observability_gramian(x0, st, times, an::OdMeasurement::both, kMu);
  EXPECT_EQ(a.gramian.W, b.gramian.W);
  EXPECT_EQ(a.singular_values, b.singular_values);
  EXPECT_GT(a.sensitivity_condition, 1.0);
  an::RotatingStation bad = old;
  bad.rate = std::nan("");
  try {
    an::od_observability_gramian(x0, bad, times, an::OdMeasurement::range, kMu);
    FAIL() << "a NaN rate did not throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("station.rate", 0), 0u) << e.what();  // the old field name
  }
  EXPECT_EQ(an::elevation(x0, old, 0.0, kMu), an::elevation(x0, st, 0.0, kMu));
}
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
