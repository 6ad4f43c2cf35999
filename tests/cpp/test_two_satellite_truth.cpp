// CVODES truth flight of the two-satellite model (guidance/two_satellite_truth.hpp) and the generic
// CVODES integrator under it (propagation/cvodes_ode.hpp): analytic check (harmonic oscillator), the
// truth against a fine-step RK4 integration of the same controlled arc, failure statuses naming the
// interval, and bad input.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "satgnc/guidance/two_satellite_truth.hpp"
#include "satgnc/propagation/cvodes_ode.hpp"
#include "satgnc/propagation/kepler.hpp"
#include "testing.hpp"
#include "two_satellite_fixture.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using satgnc::Vec3;
using satgnc::dynamics::TwoSatelliteModel;
using satgnc::dynamics::TwoSatelliteParams;
using satgnc::dynamics::Vec12;
using satgnc::propagation::CvodesOde;
using satgnc::propagation::CvodesOdeSettings;
using satgnc::propagation::PropagationStatus;
using namespace satgnc::guidance;

namespace {
using satgnc::testing::kMu;
using satgnc::testing::kR;
using satgnc::testing::release_state;
TwoSatelliteParams truth_params() {
  TwoSatelliteParams p;
  p.mu = kMu;
  p.j2_on = true;
  p.drag_on = true;
  return p;
}
}  // namespace

TEST(CvodesOde, HarmonicOscillatorMatchesTheAnalyticSolution) {
  const double w = 0.7;
  auto f = [w](double, const double* y, double* yd) {
    yd[0] = y[1];
    yd[1] = -w * w * y[0];
    return true;
  };
  auto jac = [w](double, const double*, double* J) {
    J[0] = 0.0;
    J[1] = -w * w;
    J[2] = 1.0;
    J[3] = 0.0;
    return true;
  };
  CvodesOdeSettings s;
  s.rtol = 1e-12;
  s.atol = 1e-12;
  for (bool newton : {false, true}) {
    CvodesOde ode(2, f, s, newton ? CvodesOde::Jacobian(jac) : CvodesOde::Jacobian());
    VectorXd y(2);
    y << 1.0, 0.0;
    // two arcs with a re-initialisation in between, as the truth does at interval boundaries
    ASSERT_EQ(ode.integrate(0.0, y, 5.0), PropagationStatus::success) << ode.message();
    ASSERT_EQ(ode.integrate(5.0, y, 10.0), PropagationStatus::success) << ode.message();
    EXPECT_NEAR(y(0), std::cos(w * 10.0), 1e-9) << "newton " << newton;
    EXPECT_NEAR(y(1), -w * std::sin(w * 10.0), 1e-9);
    EXPECT_GT(ode.stats().steps, 0);
    EXPECT_EQ(ode.stats().lin_setups > 0, newton);
  }
}

TEST(CvodesOde, FailuresAreStatusesNotExceptions) {
  auto f = [](double t, const double* y, double* yd) {
    yd[0] = y[0];
    return t < 1.0;  // the right-hand side fails from t = 1 on
  };
  CvodesOde ode(1, f);
  VectorXd y = VectorXd::Ones(1);
  // failing at the start: rhs_failure
  EXPECT_EQ(ode.integrate(1.5, y, 2.0), PropagationStatus::rhs_failure);
  EXPECT_NE(ode.message().find("right-hand side failed"), std::string::npos) << ode.message();
  // failing on the way: CVODES shrinks the step towards t = 1 (a status, never a crash or NaN)
  y = VectorXd::Ones(1);
  EXPECT_NE(ode.integrate(0.0, y, 2.0), PropagationStatus::success);
  EXPECT_NE(ode.message().find("right-hand side failed"), std::string::npos) << ode.message();
  EXPECT_LE(ode.t_reached(), 1.0);
  EXPECT_TRUE(y.allFinite());
  VectorXd bad(1);
  bad(0) = std::nan("");
  EXPECT_EQ(ode.integrate(0.0, bad, 0.5), PropagationStatus::solver_failure);
  EXPECT_NE(ode.message().find("invalid input"), std::string::npos);
  VectorXd y2 = VectorXd::Ones(2);  // wrong size
  EXPECT_EQ(ode.integrate(0.0, y2, 0.5), PropagationStatus::solver_failure);
  VectorXd y3 = VectorXd::Ones(1);
  EXPECT_EQ(ode.integrate(0.0, y3, 0.0), PropagationStatus::solver_failure);  // t1 == t0
  // budget
  CvodesOdeSettings s;
  s.max_steps = 3;
  CvodesOde small(
      1,
      [](double, const double* v, double* yd) {
        yd[0] = std::cos(50.0 * v[0]);
        return true;
      },
      s);
  VectorXd z = VectorXd::Zero(1);
  EXPECT_EQ(small.integrate(0.0, z, 100.0), PropagationStatus::too_much_work);
  EXPECT_NE(small.message().find("max_steps"), std::string::npos);
}

TEST(CvodesOde, BadSettingsThrowNamingTheField) {
  auto f = [](double, const double*, double* yd) {
    yd[0] = 0.0;
    return true;
  };
  auto throws_with = [&](int n, const CvodesOdeSettings& s, const std::string& name) {
    try {
      CvodesOde ode(n, f, s);
      ADD_FAILURE() << "no throw for " << name;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  CvodesOdeSettings s;
  throws_with(0, s, "n");
  s.rtol = 0.0;
  throws_with(1, s, "rtol");
  s = CvodesOdeSettings();
  s.atol_components = {1e-9, 1e-9};
  throws_with(1, s, "atol_components");
  s = CvodesOdeSettings();
  s.max_order = 13;
  throws_with(1, s, "max_order");
  EXPECT_THROW(CvodesOde(1, CvodesOde::Rhs()), std::invalid_argument);
}

TEST(TwoSatelliteTruth, AgreesWithFineStepRk4OnAControlledArc) {
  const TwoSatelliteModel model(truth_params());
  TwoSatelliteTruth truth(model);
  const int N = 20;
  const double dt = 6000.0 / 99.0;
  MatrixXd U(3, N);
  for (int k = 0; k < N; ++k)
    U.col(k) << 4e-3 * std::sin(0.3 * k), -3e-3 * ((k % 3) == 0), 2e-3 * ((k % 5) - 2);
  const Vec12 x0 = release_state();
  const TruthFlight fl = truth.fly(x0, U, dt);
  ASSERT_EQ(fl.status, PropagationStatus::success) << fl.message;
  // reference: RK4 at dt / 600 (0.1 s), error far below a micrometre over the arc
  Vec12 x = x0, xn;
  const int sub = 600;
  double max_d = 0.0, max_w = 0.0, max_rt = 0.0;
  for (int k = 0; k < N; ++k) {
    for (int i = 0; i < sub; ++i) {
      ASSERT_TRUE(model.rk_step(4, dt / sub, x, U.col(k), xn));
      x = xn;
    }
    max_d = std::max(max_d, (fl.X.col(k + 1).head<3>() - x.head<3>()).norm());
    max_rt = std::max(max_rt, (fl.X.col(k + 1).segment<3>(3) - x.segment<3>(3)).norm());
    max_w = std::max(max_w, (fl.X.col(k + 1).segment<3>(6) - x.segment<3>(6)).norm());
  }
  // tolerances: rtol 1e-11, atol 1e-6 m / 1e-9 m/s per step over ~20 min of flight
  EXPECT_LE(max_d, 1e-5);   // relative position, m
  EXPECT_LE(max_w, 1e-8);   // relative velocity, m/s
  EXPECT_LE(max_rt, 5e-3);  // target's absolute position (7231 km), m: 7e-10 relative
  EXPECT_GT(fl.steps, N);
}

TEST(TwoSatelliteTruth, FailureNamesTheInterval) {
  const TwoSatelliteModel model(truth_params());
  TwoSatelliteTruth truth(model);
  MatrixXd U = MatrixXd::Zero(3, 6);
  U(1, 2) = std::numeric_limits<double>::quiet_NaN();
  const TruthFlight fl = truth.fly(release_state(), U, 60.0);
  EXPECT_NE(fl.status, PropagationStatus::success);
  EXPECT_EQ(fl.failed_interval, 2);
  EXPECT_NE(fl.message.find("interval 2"), std::string::npos) << fl.message;
  EXPECT_TRUE(fl.X.col(2).allFinite());
  // chaser at the Earth's centre (d = r_t): fly refuses it naming x0 (it was an rhs_failure status),
  // step() reports an impact at t = 0 without stepping.
  Vec12 x = release_state();
  x.head<3>() = x.segment<3>(3);
  try {
    truth.fly(x, MatrixXd::Zero(3, 3), 60.0);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("x0: the chaser starts at or below the Earth's surface"),
              std::string::npos)
        << e.what();
  }
  VectorXd xc = x;
  EXPECT_EQ(truth.step(xc, Vec3::Zero(), 60.0), PropagationStatus::impact);
  EXPECT_TRUE(xc.allFinite());
  // non-finite state
  VectorXd y = release_state();
  y(0) = std::nan("");
  EXPECT_NE(truth.step(y, Vec3::Zero(), 60.0), PropagationStatus::success);
  EXPECT_FALSE(truth.message().empty());
  // shapes
  EXPECT_THROW(truth.fly(VectorXd::Zero(11), MatrixXd::Zero(3, 2), 60.0), std::invalid_argument);
  EXPECT_THROW(truth.fly(release_state(), MatrixXd::Zero(2, 2), 60.0), std::invalid_argument);
  EXPECT_THROW(truth.fly(release_state(), MatrixXd::Zero(3, 2), 0.0), std::invalid_argument);
}

// Target and chaser slowed to 30 % of the circular speed fall into the Earth: the flight stops with
// impact at the crossing time of the first body, which point-mass Kepler gives independently.
TEST(TwoSatelliteTruth, FlyingIntoTheEarthStopsWithImpactAtTheKeplerTime) {
  TwoSatelliteParams p;
  p.mu = kMu;
  p.j2_on = false;
  p.drag_on = false;
  const TwoSatelliteModel model(p);
  TwoSatelliteTruth truth(model);
  Vec12 x = release_state();
  x.segment<3>(9) *= 0.3;
  x.segment<3>(6) *= 0.3;
  const double dt = 60.0;
  const TruthFlight fl = truth.fly(x, MatrixXd::Zero(3, 100), dt);
  ASSERT_EQ(fl.status, PropagationStatus::impact) << fl.message;
  // Kepler (km) for each body; the first to reach R ends the flight.
  double t_first = 1e300;
  for (int body = 0; body < 2; ++body) {
    satgnc::Vec6 s;
    s.head<3>() = (x.segment<3>(3) - (body == 1 ? x.head<3>() : Vec3::Zero().eval())) / 1e3;
    s.tail<3>() = (x.segment<3>(9) - (body == 1 ? x.segment<3>(6) : Vec3::Zero().eval())) / 1e3;
    const auto tr =
        satgnc::propagation::propagate_kepler(s, 0.0, {6000.0}, p.mu / 1e9, false, p.j2_radius / 1e3);
    ASSERT_EQ(tr.status, PropagationStatus::impact);
    t_first = std::min(t_first, tr.t_reached);
  }
  EXPECT_NEAR(fl.t_reached, t_first, 1e-5);
  EXPECT_EQ(fl.failed_interval, static_cast<int>(t_first / dt));
  EXPECT_NE(fl.message.find("impact at t = "), std::string::npos) << fl.message;
  EXPECT_TRUE(fl.X.leftCols(fl.failed_interval + 1).allFinite());
}
