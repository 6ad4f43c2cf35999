// frames::UniformRotation: the rotation, its rate, and the kinematic identity v_itrf = R (v - w x r).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "satgnc/frames/earth_rotation.hpp"

namespace {
using satgnc::Mat3;
using satgnc::Vec3;
using satgnc::frames::UniformRotation;

TEST(UniformRotation, QuarterTurnMapsInertialYToFixedX) {
  const double w = 7.2921159e-5;
  const UniformRotation rot(0.0, w);
  Mat3 R;
  Vec3 om;
  rot.rotation(0.25 * 2.0 * M_PI / w, R, om);
  // After a quarter turn the fixed x axis points along inertial +y.
  const Vec3 x = R * Vec3(0.0, 1.0, 0.0);
  EXPECT_NEAR(x(0), 1.0, 1e-12);
  EXPECT_NEAR(x.tail<2>().norm(), 0.0, 1e-12);
  EXPECT_NEAR((R * R.transpose() - Mat3::Identity()).norm(), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(om(2), w);
}

TEST(UniformRotation, VelocityTransformMatchesFiniteDifference) {
  const UniformRotation rot(0.3, 7.2921159e-5);
  const Vec3 r(7000.0, -1200.0, 300.0);  // a point at rest in the inertial frame, km
  Mat3 R0, Rp, Rm;
  Vec3 om;
  const double t = 1234.5, h = 1.0;
  rot.rotation(t, R0, om);
  rot.rotation(t + h, Rp, om);
  rot.rotation(t - h, Rm, om);
  const Vec3 v_fd = (Rp * r - Rm * r) / (2.0 * h);
  const Vec3 v = R0 * (Vec3::Zero() - om.cross(r));
  // Central difference of a rotation at 1 s over 7000 km: error ~ w^3 h^2 r / 6 ~ 4e-10 km/s.
  EXPECT_NEAR((v - v_fd).norm(), 0.0, 1e-9);
}

TEST(UniformRotation, RejectsNonFiniteArguments) {
  EXPECT_THROW(UniformRotation(std::nan(""), 7e-5), std::invalid_argument);
  try {
    UniformRotation(0.0, INFINITY);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("omega"), std::string::npos);
  }
}
}  // namespace
