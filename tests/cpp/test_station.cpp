// Station model: Julian date, GMST, geodetic -> inertial, rotation, textbook examples.
#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "satgnc/od/measurement.hpp"
#include "satgnc/od/station.hpp"
#include "satgnc/od/time.hpp"
#include "testing.hpp"

using namespace satgnc;
using namespace satgnc::od;

namespace {
constexpr double kDeg = M_PI / 180.0;
}

TEST(Time, JulianDateVallado) {
  // Vallado, Fundamentals of Astrodynamics and Applications, 4th ed., Example 3-4:
  // 1996 Oct 26 14:20:00 UT1 -> JD 2450383.09722222 (printed to 8 decimals).
  EXPECT_NEAR(julian_date(1996, 10, 26, 14, 20, 0.0), 2450383.09722222, 1e-8);
  EXPECT_DOUBLE_EQ(julian_date(2000, 1, 1, 12, 0, 0.0), 2451545.0);
}

TEST(Time, GmstVallado35) {
  // Vallado 4th ed., Example 3-5: 1992 Aug 20 12:14 UT1 -> GMST = 152.578787886 deg (printed to 9
  // decimals; other printings show ...810, so allow 1e-6 deg).
  const double g = gmst_iau1982(julian_date(1992, 8, 20, 12, 14, 0.0)) / kDeg;
  EXPECT_NEAR(g, 152.578787886, 1e-6);
  // IAU-1982 at J2000.0 (2000-01-01 12:00 UT1): 18h41m50.54841s = 280.46061837 deg.
  EXPECT_NEAR(gmst_iau1982(2451545.0) / kDeg, 280.46061837, 1e-8);
  // UT1 - UTC shifts GMST by 1.0027379 * dut1 * 15 arcsec/s.
  const double jd = julian_date(1992, 8, 20, 12, 14, 0.0);
  const double d = gmst_from_utc(jd, 0.5) - gmst_from_utc(jd, 0.0);
  // A JD near 2.4e6 resolves ~4e-5 s, i.e. ~1e-3 arcsec of GMST.
  EXPECT_NEAR(d / kDeg * 3600.0, 0.5 * 15.0 * 1.0027379, 2e-3);
}

TEST(Time, BadInput) {
  EXPECT_THROW(julian_date(1981, 13, 1, 0, 0, 0.0), std::invalid_argument);
  EXPECT_THROW(julian_date(1981, 3, 21, 6, 0, NAN), std::invalid_argument);
  // A day past the month's end was accepted (2021-02-31 read as 2021-03-03); 2020 is a leap year,
  // 1900 is not (the formula's validity starts on 1900-03-01).
  EXPECT_THROW(julian_date(2021, 2, 29, 0, 0, 0.0), std::invalid_argument);
  EXPECT_THROW(julian_date(2021, 4, 31, 0, 0, 0.0), std::invalid_argument);
  EXPECT_THROW(julian_date(1900, 2, 28, 0, 0, 0.0), std::invalid_argument);
  EXPECT_DOUBLE_EQ(julian_date(2020, 2, 29, 0, 0, 0.0) + 1.0, julian_date(2020, 3, 1, 0, 0, 0.0));
  EXPECT_DOUBLE_EQ(julian_date(2000, 2, 29, 0, 0, 0.0) + 1.0, julian_date(2000, 3, 1, 0, 0, 0.0));
  // |UT1 - UTC| < 0.9 s (IERS): 5 s is a unit or sign error.
  const double jd = julian_date(2020, 1, 1, 0, 0, 0.0);
  EXPECT_NO_THROW(gmst_from_utc(jd, 0.89));
  EXPECT_NO_THROW(gmst_from_utc(jd, -0.89));
  for (double bad : {5.0, -0.9, 0.9, static_cast<double>(NAN)}) {
    try {
      gmst_from_utc(jd, bad);
      ADD_FAILURE() << "no throw for " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind("ut1_minus_utc_s: |UT1 - UTC| must be < 0.9 s", 0), 0u)
          << e.what();
    }
  }
  EXPECT_THROW(gmst_iau1982(INFINITY), std::invalid_argument);
}

TEST(Station, GeodeticWgs84) {
  const Vec3 eq = geodetic_to_ecef(0.0, 0.0, 0.0);
  EXPECT_NEAR(eq(0), 6378.137, 1e-9);
  const Vec3 pole = geodetic_to_ecef(M_PI / 2, 0.0, 0.0);
  EXPECT_NEAR(pole(2), 6356.752314245, 1e-6);  // WGS-84 semi-minor axis b = a (1 - f)
  const Vec3 k = geodetic_to_ecef(0.3, 1.0, 0.0, ellipsoids::krassovsky);
  EXPECT_GT(k.norm(), 6350.0);
  EXPECT_STREQ(ellipsoid_by_name("wgs 84").name, "WGS-84");
  EXPECT_STREQ(ellipsoid_by_name("IAU-1976").name, "IAU-1976");
  EXPECT_THROW(ellipsoid_by_name("clarke"), std::invalid_argument);
  EXPECT_THROW(geodetic_to_ecef(2.0, 0.0, 0.0), std::invalid_argument);
  EXPECT_THROW(geodetic_to_ecef(0.2, 0.0, 150.0), std::invalid_argument);  // metres given as km
}

TEST(Station, RotationAndVelocity) {
  const Station s =
      Station::from_geodetic(23.0 + 10.0 / 60.0, 113.25, 0.15, julian_date(1981, 3, 21, 6, 0, 0.0));
  const Vec6 x0 = s.state(0.0);
  EXPECT_NEAR((x0.tail<3>() - s.omega * Vec3::UnitZ().cross(x0.head<3>())).norm(), 0.0, 1e-15);
  const double h = 1e-3;
  const Vec3 fd = (s.state(100.0 + h).head<3>() - s.state(100.0 - h).head<3>()) / (2 * h);
  EXPECT_NEAR((fd - s.state(100.0).tail<3>()).norm(), 0.0, 1e-9);
  EXPECT_NEAR(s.state(3600.0).head<3>().norm(), x0.head<3>().norm(), 1e-9);
  EXPECT_THROW(Station::from_inertial(Vec3::Zero()), std::invalid_argument);
  EXPECT_THROW(Station::from_inertial(Vec3(1, NAN, 0)), std::invalid_argument);
}

TEST(Station, PaperTable3ImpliedRate) {
  // The paper's Table 3 station velocity equals omega z x R only with omega ~ 7.27e-5 rad/s,
  // not the Earth's 7.2921e-5 rad/s (0.3 % low); its velocities are printed to 1e-5 km/s, so the
  // implied rate is good to ~5e-9 rad/s.
  Vec6 t3;
  t3 << 5463.14996, 2139.12637, 2493.77850, -0.15551, 0.39717, 0.0;
  const double w = implied_rotation_rate(t3);
  EXPECT_NEAR(w, 7.270e-5, 5e-8);
  EXPECT_GT(std::abs(w - dynamics::earth::omega), 1.5e-7);
}

TEST(Station, CurtisExample510RangeRate) {
  // Curtis, Orbital Mechanics for Engineering Students, 3rd ed. (2013), Example 5.10: a sea-level
  // station at latitude 60 deg and local sidereal time 300 deg (Re = 6378 km, f = 0.003353,
  // omega_E = 7.292115e-5 rad/s) observes rho = 2551 km, rhodot = 0; the book's answer is
  // r = 3831 I - 2216 J + 6605 K km, v = 1.504 I - 4.562 J - 0.2920 K km/s (4 significant digits).
  // The rounding (+-0.5 km per component, +-0.5 m/s) allows |d rho| < 0.9 km, |d rhodot| < 2e-3 km/s.
  const Ellipsoid curtis{"Curtis", 6378.0, 0.003353};
  const Station s =
      Station::from_ecef(geodetic_to_ecef(60.0 * kDeg, 0.0, 0.0, curtis), 300.0 * kDeg, 7.292115e-5);
  Vec6 x;
  x << 3831.0, -2216.0, 6605.0, 1.504, -4.562, -0.2920;
  double rho = 0, rhodot = 0;
  ASSERT_TRUE(predict_measurement(MeasurementType::range, x, s.state(0.0), rho));
  ASSERT_TRUE(predict_measurement(MeasurementType::range_rate, x, s.state(0.0), rhodot));
  EXPECT_NEAR(rho, 2551.0, 0.9);
  EXPECT_NEAR(rhodot, 0.0, 2e-3);
  // The same state seen from a station at the wrong sidereal time (+1 deg) misses the range by > 10 km.
  const Station wrong = Station::from_ecef(geodetic_to_ecef(60.0 * kDeg, 0.0, 0.0, curtis), 301.0 * kDeg);
  predict_measurement(MeasurementType::range, x, wrong.state(0.0), rho);
  EXPECT_GT(std::abs(rho - 2551.0), 10.0);
}
