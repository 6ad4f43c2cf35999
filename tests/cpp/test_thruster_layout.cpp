// Thruster layout: allocation, input matrix, survivors and the setup checks (messages asserted).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "satgnc/dynamics/cw.hpp"
#include "satgnc/guidance/thruster_layout.hpp"

namespace {
using satgnc::Vec3;
using satgnc::guidance::Thruster;
using satgnc::guidance::ThrusterLayout;

Thruster make(const Vec3& d, double fmax, const std::string& name = "", double mib = 0.0) {
  Thruster t;
  t.direction = d;
  t.max_thrust = fmax;
  t.min_impulse_bit = mib;
  t.position = Vec3(0.5, 0.0, 0.0);
  t.name = name;
  return t;
}

std::vector<Thruster> six() {
  return {make(Vec3::UnitX(), 1.0),  make(-Vec3::UnitX(), 1.0), make(Vec3::UnitY(), 2.0),
          make(-Vec3::UnitY(), 2.0), make(Vec3::UnitZ(), 0.5),  make(-Vec3::UnitZ(), 0.5, "", 0.01)};
}

std::string message_of(const std::vector<Thruster>& t) {
  try {
    ThrusterLayout l(t);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ThrusterLayout, AllocationIsTheDirectionsAndNamesDefault) {
  ThrusterLayout l(six());
  ASSERT_EQ(l.size(), 6);
  const Eigen::MatrixXd D = l.allocation();
  // exact: the unit axes are stored as given
  EXPECT_EQ(D(0, 0), 1.0);
  EXPECT_EQ(D(0, 1), -1.0);
  EXPECT_EQ(D(2, 5), -1.0);
  EXPECT_EQ(l.names()[3], "T3");
  EXPECT_EQ(l.max_thrust()(2), 2.0);
  EXPECT_EQ(l.min_impulse_bit()(5), 0.01);
  // torque r x d with r = (0.5, 0, 0): +y thrust gives +0.5 N m about z (exact)
  EXPECT_EQ(l.torque_allocation()(2, 2), 0.5);
  EXPECT_EQ(l.torque_allocation()(1, 4), -0.5);
}

TEST(ThrusterLayout, InputMatrixIsBTimesD) {
  // CW force input B (6 x 3): B D must equal the column-by-column product (round-off: 1 ulp)
  auto cw = satgnc::dynamics::cw_linear_model(satgnc::dynamics::CwModel(1.1e-3, 100.0));
  ThrusterLayout l(six());
  const Eigen::MatrixXd Bt = l.input_matrix(cw.B);
  ASSERT_EQ(Bt.rows(), 6);
  ASSERT_EQ(Bt.cols(), 6);
  EXPECT_NEAR((Bt.col(0) - cw.B.col(0)).norm(), 0.0, 1e-18);
  EXPECT_NEAR((Bt.col(5) + cw.B.col(2)).norm(), 0.0, 1e-18);
  try {
    l.input_matrix(Eigen::MatrixXd::Ones(6, 2));
    FAIL() << "2 columns accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "B_force: must have 3 columns (force components, N), got 2");
  }
}

TEST(ThrusterLayout, SurvivorsAndWithout) {
  ThrusterLayout l(six());
  const std::vector<int> keep = l.survivors({4, 1});
  EXPECT_EQ(keep, (std::vector<int>{0, 2, 3, 5}));
  ThrusterLayout s = l.without({4, 1});
  ASSERT_EQ(s.size(), 4);
  EXPECT_EQ(s.names()[3], "T5");  // names survive the removal
  EXPECT_EQ(s.allocation()(2, 3), -1.0);
  try {
    l.survivors({6});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "failed[0]: must be a thruster index in [0, 6), got 6");
  }
  try {
    l.survivors({1, 1});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "failed[1]: repeats thruster 1");
  }
  try {
    l.survivors({0, 1, 2, 3, 4, 5});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "failed: loses every thruster (no layout survives)");
  }
}

TEST(ThrusterLayout, BadInputNamesTheThrusterAndField) {
  auto t = six();
  t[2].direction = Vec3(1.0, 1.0, 0.0);
  EXPECT_EQ(message_of(t),
            "thrusters[2].direction: must be a unit vector, got norm 1.4142135623730951 (hint: divide the "
            "direction by its norm; tolerance 1e-9)");
  t = six();
  t[3].max_thrust = -1.0;
  EXPECT_EQ(message_of(t), "thrusters[3].max_thrust: must be finite and > 0 N, got -1");
  t = six();
  t[0].min_impulse_bit = -0.5;
  EXPECT_EQ(message_of(t), "thrusters[0].min_impulse_bit: must be finite and >= 0 N s, got -0.5");
  t = six();
  t[1].name = "T0";
  EXPECT_EQ(message_of(t), "thrusters[1].name: must be unique, 'T0' repeats");
  EXPECT_EQ(message_of({}), "thrusters: must hold at least one thruster");
  t = six();
  t[4].position(1) = std::nan("");
  EXPECT_EQ(message_of(t), "thrusters[4].position: must be finite (no NaN or Inf)");
  // a direction within the 1e-9 tolerance is accepted and normalized to 1 to round-off
  t = six();
  t[0].direction = Vec3(1.0 + 5e-10, 0.0, 0.0);
  ThrusterLayout ok(t);
  EXPECT_NEAR(ok.allocation().col(0).norm(), 1.0, 1e-15);
}

}  // namespace
