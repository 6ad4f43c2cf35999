// PropagatedTwoSatelliteMap (guidance/nonlinear_model.hpp): the discrete map and its Jacobians from
// DOP853 integration of the state, STM and control sensitivity. Jacobians against central finite
// differences of the map, the map against a fine-step RK4 map, no allocation in step(), failures
// (a body inside the Earth, non-finite input) reported as false and, in the solvers, as the interval.
#include <Eigen/Dense>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "malloc_counter.hpp"
#include "satgnc/guidance/ilqr_admm.hpp"
#include "satgnc/guidance/nonlinear_model.hpp"
#include "satgnc/guidance/scp.hpp"
#include "testing.hpp"
#include "two_satellite_fixture.hpp"

using Eigen::MatrixXd;
using Eigen::VectorXd;
using satgnc::Vec3;
using satgnc::dynamics::Mat12;
using satgnc::dynamics::Mat12x3;
using satgnc::dynamics::TwoSatelliteModel;
using satgnc::dynamics::TwoSatelliteParams;
using satgnc::dynamics::Vec12;
using namespace satgnc::guidance;

namespace {
using satgnc::testing::kMu;
using satgnc::testing::kR;
using satgnc::testing::release_state;

TwoSatelliteParams params_j2_drag() {
  TwoSatelliteParams p;
  p.mu = kMu;
  p.j2_on = true;
  p.drag_on = true;
  p.rho0 = 1e-3;  // heavier drag than the scenario's so that its Jacobian terms are visible
  return p;
}

PropagatedMapSettings scaled_settings(const Vec12& x0, double rtol) {
  const ReferenceScaling sc = published_scaling(x0, kMu, 4.6);
  PropagatedMapSettings s;
  s.rtol = rtol;
  s.atol = rtol;
  s.state_scale = sc.state_scale;
  s.control_scale = sc.control_scale;
  return s;
}
}  // namespace

TEST(PropagatedMap, JacobiansMatchCentralFiniteDifferences) {
  const TwoSatelliteModel model(params_j2_drag());
  const Vec12 xsi = release_state();
  const PropagatedTwoSatelliteMap map(model, scaled_settings(xsi, 1e-13));
  const Vec12 z = xsi.cwiseQuotient(map.state_scale());
  const Vec3 v(0.3, -0.2, 0.1);  // scaled force (~0.1 N)
  Vec12 zn;
  Mat12 A;
  Mat12x3 B;
  ASSERT_TRUE(map.step(0, z.data(), v.data(), zn.data(), A.data(), B.data()));
  // Fourth-order central differences of the map itself (5-point stencil), h = 1e-3 in scaled units:
  // truncation ~h^4 and the adaptive integrator's tolerance noise (~1e-13 / h) both below 1e-9.
  const double h = 1e-3;
  Mat12 Afd;
  Mat12x3 Bfd;
  auto fd = [&](auto perturb) {
    Vec12 out = Vec12::Zero(), zz;
    const double c[4] = {1.0, -8.0, 8.0, -1.0}, o[4] = {-2.0, -1.0, 1.0, 2.0};
    for (int i = 0; i < 4; ++i) {
      Vec12 a = z;
      Vec3 b = v;
      perturb(a, b, o[i] * h);
      EXPECT_TRUE(map.step(0, a.data(), b.data(), zz.data(), nullptr, nullptr));
      out += c[i] * zz;
    }
    return Vec12(out / (12.0 * h));
  };
  for (int j = 0; j < 12; ++j) Afd.col(j) = fd([j](Vec12& a, Vec3&, double d) { a(j) += d; });
  for (int j = 0; j < 3; ++j) Bfd.col(j) = fd([j](Vec12&, Vec3& b, double d) { b(j) += d; });
  // issue 6 evidence: Jacobians of the discrete map against finite differences, 1e-7 relative
  EXPECT_LE(satgnc::testing::rel_err(A, Afd), 1e-7);
  EXPECT_LE(satgnc::testing::rel_err(B, Bfd), 1e-7);
  // column by column as well (small columns are not hidden by the large ones)
  for (int j = 0; j < 12; ++j)
    EXPECT_LE(satgnc::testing::rel_err(A.col(j), Afd.col(j)), 1e-6) << "column " << j;
  for (int j = 0; j < 3; ++j)
    EXPECT_LE(satgnc::testing::rel_err(B.col(j), Bfd.col(j)), 1e-6) << "column " << j;
}

TEST(PropagatedMap, AgreesWithFineStepRk4MapToTheTolerance) {
  const TwoSatelliteModel model(params_j2_drag());
  const Vec12 xsi = release_state();
  const PropagatedMapSettings ps = scaled_settings(xsi, 1e-10);
  const PropagatedTwoSatelliteMap map(model, ps);
  TwoSatelliteMapSettings rs;
  rs.dt = ps.dt;
  rs.scheme = 4;
  rs.substeps = 600;  // h = 0.1 s: RK4 error ~1e-15 relative, far below the DOP853 tolerance
  rs.state_scale = ps.state_scale;
  rs.control_scale = ps.control_scale;
  const TwoSatelliteMap rk4(model, rs);
  const Vec12 z = xsi.cwiseQuotient(map.state_scale());
  const Vec3 v(0.3, -0.2, 0.1);
  Vec12 z1, z2, z3;
  Mat12 A1, A2;
  Mat12x3 B1, B2;
  ASSERT_TRUE(map.step(0, z.data(), v.data(), z1.data(), A1.data(), B1.data()));
  ASSERT_TRUE(map.step(0, z.data(), v.data(), z3.data(), nullptr, nullptr));
  ASSERT_TRUE(rk4.step(0, z.data(), v.data(), z2.data(), A2.data(), B2.data()));
  // scaled state, every component O(1): agreement to a few times rtol = 1e-10
  EXPECT_LE((z1 - z2).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LE((z3 - z2).cwiseAbs().maxCoeff(), 1e-9);  // the state-only integration as well
  EXPECT_LE(satgnc::testing::rel_err(A1, A2), 1e-9);
  EXPECT_LE(satgnc::testing::rel_err(B1, B2), 1e-9);
  EXPECT_GT(map.last_info().steps, 0);
  EXPECT_EQ(map.last_info().status, 0);
}

TEST(PropagatedMap, StepDoesNotAllocate) {
  const TwoSatelliteModel model(params_j2_drag());
  const Vec12 xsi = release_state();
  const PropagatedTwoSatelliteMap map(model, scaled_settings(xsi, 1e-10));
  const Vec12 z = xsi.cwiseQuotient(map.state_scale());
  const Vec3 v(0.3, -0.2, 0.1);
  Vec12 zn;
  Mat12 A;
  Mat12x3 B;
  g_mallocs = 0;
  g_count = true;
  const bool ok1 = map.step(0, z.data(), v.data(), zn.data(), A.data(), B.data());
  const bool ok2 = map.step(1, z.data(), v.data(), zn.data(), nullptr, nullptr);
  g_count = false;
  EXPECT_TRUE(ok1 && ok2);
  EXPECT_EQ(g_mallocs.load(), 0);
}

TEST(PropagatedMap, InsideTheEarthOrNonFiniteReturnsFalse) {
  const TwoSatelliteModel model(params_j2_drag());
  PropagatedMapSettings s;  // SI, no scaling
  const PropagatedTwoSatelliteMap map(model, s);
  Vec12 x = release_state();
  x(3) = 6000.0e3;  // target 378 km below the surface
  const Vec3 u = Vec3::Zero();
  Vec12 xn;
  Mat12 A;
  Mat12x3 B;
  EXPECT_FALSE(map.step(4, x.data(), u.data(), xn.data(), A.data(), B.data()));
  EXPECT_FALSE(map.last_info().ok);
  EXPECT_EQ(map.last_info().interval, 4);
  EXPECT_NE(map.last_info().status, 0);
  EXPECT_FALSE(map.step(0, x.data(), u.data(), xn.data(), nullptr, nullptr));
  Vec12 y = release_state();
  y(7) = std::nan("");
  EXPECT_FALSE(map.step(0, y.data(), u.data(), xn.data(), A.data(), B.data()));
  Vec3 un(std::numeric_limits<double>::infinity(), 0.0, 0.0);
  EXPECT_FALSE(map.step(0, release_state().data(), un.data(), xn.data(), nullptr, nullptr));
  // and a good state still works afterwards
  EXPECT_TRUE(map.step(0, release_state().data(), u.data(), xn.data(), A.data(), B.data()));
}

TEST(PropagatedMap, SolversNameTheIntervalWhereThePropagationFails) {
  // Target falling radially at 1 km/s from 7000 km; min_radius 6800 km is crossed after ~200 s,
  // i.e. in interval 3 of 60 s.
  TwoSatelliteParams p = params_j2_drag();
  const TwoSatelliteModel model(p);
  PropagatedMapSettings s;
  s.dt = 60.0;
  s.min_radius = 6800.0e3;
  const PropagatedTwoSatelliteMap map(model, s);
  Vec12 x0 = Vec12::Zero();
  x0(3) = 7000.0e3;
  x0(9) = -1000.0;
  x0(10) = 7000.0;
  NonlinearL1Problem prob;
  prob.horizon = 8;
  prob.x0 = x0;
  prob.Qf = MatrixXd::Identity(12, 12);
  prob.alpha = VectorXd::Ones(3);
  prob.stage_weight = 1.0;
  IlqrAdmmSolver ilqr(map, prob);
  ilqr.set_initial_controls(MatrixXd::Zero(3, 8));
  EXPECT_EQ(ilqr.solve(), IlqrAdmmStatus::propagation_failed);
  EXPECT_EQ(ilqr.result().info.failed_interval, 3);
  ScpSolver scp(map, prob);
  EXPECT_EQ(scp.solve(), ScpStatus::propagation_failed);
  EXPECT_EQ(scp.result().info.failed_interval, 3);
}

TEST(PropagatedMap, BadSettingsThrowNamingTheField) {
  const TwoSatelliteModel model;
  auto throws_with = [&](PropagatedMapSettings s, const std::string& name) {
    try {
      PropagatedTwoSatelliteMap m(model, s);
      ADD_FAILURE() << "no throw for " << name;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  PropagatedMapSettings s;
  s.dt = 0.0;
  throws_with(s, "dt");
  s = PropagatedMapSettings();
  s.rtol = -1.0;
  throws_with(s, "rtol");
  s = PropagatedMapSettings();
  s.max_steps = 0;
  throws_with(s, "max_steps");
  s = PropagatedMapSettings();
  s.state_scale = VectorXd::Ones(11);
  throws_with(s, "state_scale");
  s = PropagatedMapSettings();
  s.control_scale = -VectorXd::Ones(3);
  throws_with(s, "control_scale");
  s = PropagatedMapSettings();
  s.min_radius = std::nan("");
  throws_with(s, "min_radius");
}
