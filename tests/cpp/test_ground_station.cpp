// frames::GroundStation: ERFA's t_gd2gc WGS-84 case, look angles against independent constructions
// (zenith, cardinal directions, the angle to the geodetic normal), their rates against central
// differences, the GCRF state against a difference of positions, the depth limit.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "satgnc/frames/ground_station.hpp"

namespace {
using satgnc::Vec3;
using satgnc::Vec6;
using satgnc::core::Epoch;
using satgnc::core::TimeScale;
namespace fr = satgnc::frames;

constexpr double kDeg = M_PI / 180.0;
const std::string kFinals = std::string(SATGNC_TEST_EOP_DIR) + "/finals2000A_2016-12.txt";

// t_erfa_c.c t_gd2gc, WGS-84: longitude 3.1 rad, latitude -0.5 rad, height 2500 m ->
// (-5599000.5577049947, 233011.67223479203, -3040909.4706983363) m (ERFA tolerance 1e-7 m; here 1e-9 km
// after the deg <-> rad round trip of the inputs, ~1e-16 relative).
TEST(GroundStation, MatchesErfaGd2gcWgs84Case) {
  const fr::GroundStation s(-0.5 / kDeg, 3.1 / kDeg, 2.5);
  EXPECT_NEAR(s.position_itrf()(0), -5599.0005577049947, 1e-9);
  EXPECT_NEAR(s.position_itrf()(1), 233.01167223479203, 1e-9);
  EXPECT_NEAR(s.position_itrf()(2), -3040.9094706983363, 1e-9);
  // The ENU rows are orthonormal and "up" is the geodetic normal (not the radius direction).
  EXPECT_NEAR((s.itrf_to_enu() * s.itrf_to_enu().transpose() - satgnc::Mat3::Identity()).norm(), 0.0, 1e-15);
  EXPECT_NEAR(std::asin(s.itrf_to_enu()(2, 2)), -0.5, 1e-15);
}

TEST(GroundStation, LookAnglesOfKnownDirections) {
  // Station on the equator at longitude 0: east = +y, north = +z, up = +x.
  const fr::GroundStation s(0.0, 0.0, 0.0);
  const Vec3 r = s.position_itrf();
  auto look = [&](const Vec3& d) {
    Vec6 x;
    x << r + d, Vec3::Zero();
    return s.look_itrf(x);
  };
  EXPECT_NEAR(look(Vec3(500.0, 0.0, 0.0)).elevation, M_PI / 2.0, 1e-15);  // zenith
  EXPECT_NEAR(look(Vec3(0.0, 100.0, 0.0)).azimuth, M_PI / 2.0, 1e-15);    // east on the horizon
  EXPECT_NEAR(look(Vec3(0.0, 100.0, 0.0)).elevation, 0.0, 1e-15);
  EXPECT_NEAR(look(Vec3(0.0, 0.0, 100.0)).azimuth, 0.0, 1e-15);          // north
  EXPECT_NEAR(look(Vec3(0.0, -100.0, 0.0)).azimuth, 1.5 * M_PI, 1e-15);  // west: [0, 2 pi)
  const fr::LookAngles a = look(Vec3(100.0, 100.0, 0.0));
  EXPECT_NEAR(a.elevation, M_PI / 4.0, 1e-15);
  EXPECT_NEAR(a.range, 100.0 * std::sqrt(2.0), 1e-12);
  // An off-axis station: elevation = 90 deg - angle between the geodetic normal and the line of sight
  // (an independent construction from the normal n = (cos phi cos lam, cos phi sin lam, sin phi)).
  const fr::GroundStation t(37.5, -122.2, 0.3);
  const Vec3 sat(-2700.0, -4300.0, 5200.0);
  Vec6 xs;
  xs << sat, Vec3::Zero();
  const double phi = 37.5 * kDeg, lam = -122.2 * kDeg;
  const Vec3 n(std::cos(phi) * std::cos(lam), std::cos(phi) * std::sin(lam), std::sin(phi));
  const Vec3 los = (sat - t.position_itrf()).normalized();
  EXPECT_NEAR(t.look_itrf(xs).elevation, M_PI / 2.0 - std::acos(n.dot(los)), 1e-12);  // acos conditioning
}

// Rates against 5-point central differences of a satellite moving on a straight line in the ITRF
// (h = 0.05 s: truncation ~ f^(5) h^4 / 30 < 1e-12, rounding ~ 1e-13 * 1000 km / 0.6 s = 2e-10).
TEST(GroundStation, RatesMatchCentralDifferences) {
  const fr::GroundStation s(48.0, 11.3, 0.6, 5.0, "OBP");
  const Vec3 r0(4500.0, 1500.0, 5300.0), v(-3.0, 6.0, 2.5);
  auto at = [&](double t) {
    Vec6 x;
    x << r0 + v * t, v;
    return s.look_itrf(x);
  };
  const double h = 0.05;
  const fr::LookAngles a = at(0.0), p = at(h), m = at(-h), p2 = at(2 * h), m2 = at(-2 * h);
  auto d5 = [&](double fp2, double fp, double fm, double fm2) {
    return (-fp2 + 8 * fp - 8 * fm + fm2) / (12 * h);
  };
  EXPECT_NEAR(a.azimuth_rate, d5(p2.azimuth, p.azimuth, m.azimuth, m2.azimuth), 1e-9);
  EXPECT_NEAR(a.elevation_rate, d5(p2.elevation, p.elevation, m.elevation, m2.elevation), 1e-9);
  EXPECT_NEAR(a.range_rate, d5(p2.range, p.range, m.range, m2.range), 1e-9);
  EXPECT_EQ(s.visible(a.elevation), a.elevation >= 5.0 * kDeg);
  EXPECT_FALSE(s.visible(4.9 * kDeg));
  EXPECT_TRUE(s.visible(5.0 * kDeg));
}

// The GCRF state of a station: velocity against a central difference of GCRF positions (same
// left-out precession-nutation rate: 1e-7 km/s), speed = omega * distance from the CIP axis.
TEST(GroundStation, GcrfStateWithEop) {
  const fr::EopTable eop = fr::EopTable::read(kFinals);
  const fr::GroundStation s(-35.4, 149.0, 0.69, 10.0, "Canberra");
  const Epoch e = Epoch::parse("2016-12-20T10:00:00", TimeScale::utc);
  const Vec6 x = s.state_gcrf(e, eop);
  const double h = 1.0;
  const Vec3 v_fd = (s.state_gcrf(e + h, eop).head<3>() - s.state_gcrf(e - h, eop).head<3>()) / (2.0 * h);
  EXPECT_LT((x.tail<3>() - v_fd).norm(), 1e-7);
  const Vec3 p = s.position_itrf();
  EXPECT_NEAR(x.tail<3>().norm(), fr::kEarthRotationRate * std::hypot(p(0), p(1)), 2e-6);  // pole tilt ~1e-3
  EXPECT_NEAR(x.head<3>().norm(), p.norm(), 1e-9);  // a rotation keeps the length
  // look() from the GCRF equals look_itrf() of the transformed state.
  Vec6 sat;
  sat << 3000.0, 4000.0, -5000.0, -5.0, 1.0, 3.0;
  const fr::LookAngles a = s.look(sat, e, eop), b = s.look_itrf(fr::gcrs_to_itrs(sat, e, eop));
  EXPECT_DOUBLE_EQ(a.elevation, b.elevation);
  EXPECT_DOUBLE_EQ(a.range_rate, b.range_rate);
}

TEST(GroundStation, BadInputNamesTheArgument) {
  try {
    fr::GroundStation(31.5, 35.5, -0.7);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(
        std::string(e.what()),
        "height_km: -0.700000 km is below the WGS-84 ellipsoid by more than the deepest real station (limit "
        "-0.5 km; the Dead Sea shore is -0.43 km) (hint: height is in km, not m)");
  }
  EXPECT_NO_THROW(fr::GroundStation(31.5, 35.5, -0.43, 0.0, "Dead Sea shore"));
  EXPECT_THROW(fr::GroundStation(91.0, 0.0, 0.0), std::invalid_argument);
  EXPECT_THROW(fr::GroundStation(0.0, NAN, 0.0), std::invalid_argument);
  EXPECT_THROW(fr::GroundStation(0.0, 0.0, 350.0), std::invalid_argument);  // metres typed as km
  EXPECT_THROW(fr::GroundStation(0.0, 0.0, 0.0, 95.0), std::invalid_argument);
}

}  // namespace
