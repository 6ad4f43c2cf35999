// frames: IAU 2006/2000A CIO-based GCRS <-> ITRS. Vallado's Example 3-14, ERFA's own t_erfa_c values
// (eraC2t06a, eraBp06), the velocity term against a central difference of the full chain, and
// IauEarthRotation's interpolation error against the unapproximated chain.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <stdexcept>

#include "malloc_counter.hpp"
#include "satgnc/frames/earth_orientation.hpp"

namespace {
using satgnc::Mat3;
using satgnc::Vec3;
using satgnc::Vec6;
using satgnc::core::Epoch;
using satgnc::core::TimeScale;
namespace fr = satgnc::frames;

constexpr double kAs2R = 4.848136811095359935899141e-6;  // arcsec -> rad

const std::string kFinals = std::string(SATGNC_TEST_EOP_DIR) + "/finals2000A_2016-12.txt";

// Angle (rad) of the rotation A^T B.
double angle_between(const Mat3& a, const Mat3& b) {
  return Eigen::AngleAxisd(Mat3(a.transpose() * b)).angle();
}

// Vallado, Fundamentals of Astrodynamics and Applications, 4th ed., Example 3-14: 2004-04-06
// 07:51:28.386009 UTC, xp -0.140682", yp 0.333309", UT1-UTC -0.4399619 s, LOD 1.5563 ms, dX -0.000205",
// dY -0.000136"; ITRF r = (-1033.4793830, 7901.2952754, 6380.3565958) km, v = (-3.225636520,
// -2.872451450, 5.531924446) km/s. GCRF of the IAU-2006/2000 CIO reduction (Table 3-6, 1e-7 km and
// 1e-9 km/s resolution): r = (5102.50895290, 6123.01139910, 6378.13693380) km, v = (-4.7432201610,
// 0.7905364950, 5.5337557240) km/s, as quoted identically by several public reproductions (satmad,
// ssapy, SatelliteToolbox.jl tests). Why we differ by 9.03 mm: tests/python/test_frames_vallado.py.
TEST(EarthOrientation, ValladoExample3_14ItrfToGcrf) {
  const Epoch e = Epoch::parse("2004-04-06T07:51:28.386009", TimeScale::utc);
  fr::EopValues eop;
  eop.xp = -0.140682;
  eop.yp = 0.333309;
  eop.ut1_utc = -0.4399619;
  eop.lod = 0.0015563;
  eop.dx = -0.000205;
  eop.dy = -0.000136;
  Vec6 x_itrf;
  x_itrf << -1033.4793830, 7901.2952754, 6380.3565958, -3.225636520, -2.872451450, 5.531924446;
  Vec6 book;
  book << 5102.50895290, 6123.01139910, 6378.13693380, -4.7432201610, 0.7905364950, 5.5337557240;
  const fr::EarthOrientation o = fr::earth_orientation(e, eop);
  const Vec6 g = fr::itrs_to_gcrs(x_itrf, o);
  // Measured |dr| = 9.028e-6 km, |dv| = 4.44e-9 km/s. 8.5 mm of it is the book's JD_UT1 =
  // 2453101.827406783 held in one double: 14.69 us after the exact UT1 (1.07e-9 rad about the pole);
  // 0.85 mm is its IAU 2000A series where we use IAU 2006/2000A (IERS 2010).
  EXPECT_NEAR((g.head<3>() - book.head<3>()).norm(), 9.028e-6, 2e-9);
  EXPECT_NEAR((g.tail<3>() - book.tail<3>()).norm(), 4.439e-9, 2e-12);
  // With the book's UT1 (UT1-UTC + 14.69 us) only the series difference is left: to the printed
  // 1e-6 km (measured 6.95e-7 km in y) and 1e-9 km/s (measured 6.8e-10).
  fr::EopValues late = eop;
  late.ut1_utc += 1.468998682696565e-5;
  const Vec6 gb = fr::itrs_to_gcrs(x_itrf, fr::earth_orientation(e, late));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(gb(i), book(i), 1e-6) << i;
  for (int i = 3; i < 6; ++i) EXPECT_NEAR(gb(i), book(i), 1e-9) << i;
  // And back (orthogonal matrices): 1e-11 km is ~1e3 ulps of 8000 km.
  EXPECT_LT((fr::gcrs_to_itrs(g, o) - x_itrf).norm(), 1e-11);
}

// t_erfa_c.c t_c2t06a: TT = UT1 = MJD 53736.0, xp = 2.55060238e-7 rad, yp = 1.860359247e-6 rad
// (no dX, dY) -> the GCRS -> ITRS matrix to 1e-12 (ERFA's own tolerance).
TEST(EarthOrientation, MatchesErfaC2t06aTestValues) {
  const Epoch e = Epoch::from_mjd(53736.0, TimeScale::tt);
  fr::EopValues eop;
  eop.xp = 2.55060238e-7 / kAs2R;
  eop.yp = 1.860359247e-6 / kAs2R;
  // UT1 = TT numerically: 2006-01-01T00:00 TT is 2005-12-31T23:58:55.816 UTC, when TAI-UTC = 32 s.
  eop.ut1_utc = 32.184 + 32.0;
  const Mat3 m = fr::earth_orientation(e, eop).gcrs_to_itrs;
  const double expected[3][3] = {{-0.1810332128305897282, 0.9834769806938592296, 0.6555550962998436505e-4},
                                 {-0.9834768134136214897, -0.1810332203649130832, 0.5749800844905594110e-3},
                                 {0.5773474024748545878e-3, 0.3961816829632690581e-4, 0.9999998325501747785}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(m(i, j), expected[i][j], 1e-12) << i << j;
}

// t_erfa_c.c t_bp06: the frame bias rb (constant) to 1e-12 / 1e-14 (ERFA's tolerances).
TEST(EarthOrientation, FrameBiasMatchesErfaBp06) {
  const Mat3 b = fr::gcrs_to_eme2000_matrix();
  EXPECT_NEAR(b(0, 0), 0.9999999999999942497, 1e-12);
  EXPECT_NEAR(b(0, 1), -0.7078368960971557145e-7, 1e-14);
  EXPECT_NEAR(b(0, 2), 0.8056213977613185606e-7, 1e-14);
  EXPECT_NEAR(b(1, 0), 0.7078368694637674333e-7, 1e-14);
  EXPECT_NEAR(b(1, 2), 0.3305943742989134124e-7, 1e-14);
  EXPECT_NEAR(b(2, 0), -0.8056214211620056792e-7, 1e-14);
  EXPECT_NEAR(b(2, 1), -0.3305943172740586950e-7, 1e-14);
  const Vec3 r(7000.0, -100.0, 300.0);
  EXPECT_LT((fr::eme2000_to_gcrs(fr::gcrs_to_eme2000(r)) - r).norm(), 1e-11);  // ulps of 7000 km
  // The bias is at most 23 mas: 7000 km * 1.1e-7 rad = 0.8 m.
  EXPECT_LT((fr::gcrs_to_eme2000(r) - r).norm(), 1e-3);
}

// The Earth-rotation velocity term against a central difference of the full chain for a point at
// rest in the ITRF. Left out by design: the precession-nutation and polar-motion rates (~1e-11 rad/s:
// < 7e-8 km/s at 6400 km); the central difference at h = 1 s adds ~w^3 h^2 r / 6 ~ 4e-10 km/s.
TEST(EarthOrientation, VelocityTermMatchesCentralDifference) {
  const fr::EopTable eop = fr::EopTable::read(kFinals);
  const Epoch e = Epoch::parse("2016-12-20T03:00:00", TimeScale::utc);
  Vec6 x;
  x << 4000.0, -3000.0, 3500.0, 0.0, 0.0, 0.0;
  const Vec6 g = fr::itrs_to_gcrs(x, e, eop);
  const double h = 1.0;
  const Vec3 rp = fr::itrs_to_gcrs(Vec3(x.head<3>()), e + h, eop);
  const Vec3 rm = fr::itrs_to_gcrs(Vec3(x.head<3>()), e - h, eop);
  const Vec3 v_fd = (rp - rm) / (2.0 * h);
  EXPECT_LT((g.tail<3>() - v_fd).norm(), 1e-7) << (g.tail<3>() - v_fd).transpose();
  EXPECT_GT(g.tail<3>().norm(), 0.3);  // ~ w r cos(lat) = 7.29e-5 * 5000 km
}

// IauEarthRotation: grid + exact ERA against the full chain at 2000 random epochs over 3 days, across
// the 2016-12-31 leap second. Target < 1e-10 rad; measured max 2.9e-12 rad (printed).
TEST(IauEarthRotation, InterpolationErrorBelow1e10RadAgainstFullChain) {
  const fr::EopTable eop = fr::EopTable::read(kFinals);
  const Epoch e0 = Epoch::parse("2016-12-30T00:00:00", TimeScale::utc);
  const fr::IauEarthRotation rot(e0, eop, 0.0, 3.0 * 86400.0);
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(0.0, 3.0 * 86400.0);
  double worst = 0.0, worst_omega = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const double t = u(gen);
    Mat3 r;
    Vec3 w;
    rot.rotation(t, r, w);
    const fr::EarthOrientation full = fr::earth_orientation(e0 + t, eop);
    worst = std::max(worst, angle_between(r, full.gcrs_to_itrs));
    worst_omega = std::max(worst_omega, std::fabs(w.norm() - full.omega));
  }
  std::printf("IauEarthRotation: max rotation error %.3g rad, max |omega| error %.3g rad/s\n", worst,
              worst_omega);
  EXPECT_LT(worst, 1e-10);
  EXPECT_LT(worst_omega, 1e-16);  // LOD interpolation only: ~1e-12 relative of 7.3e-5
}

// The interface's kinematic identity v_itrf = R (v_gcrf - w x r_gcrf) against a central difference of
// rotation() for a point at rest in the GCRF (same left-out rates as above: 1e-7 km/s).
TEST(IauEarthRotation, OmegaMatchesCentralDifferenceAndAllocatesNothing) {
  const fr::EopTable eop = fr::EopTable::read(kFinals);
  const fr::IauEarthRotation rot(Epoch::parse("2016-12-10T00:00:00", TimeScale::utc), eop, -3600.0, 86400.0);
  const Vec3 r(7000.0, -1200.0, 300.0);
  Mat3 r0, rp, rm;
  Vec3 w, wd;
  const double t = 5000.0, h = 1.0;
  rot.rotation(t, r0, w);
  rot.rotation(t + h, rp, wd);
  rot.rotation(t - h, rm, wd);
  const Vec3 v_fd = (rp * r - rm * r) / (2.0 * h);
  EXPECT_LT((r0 * (Vec3::Zero() - w.cross(r)) - v_fd).norm(), 1e-7);
  // The rotation axis is the CIP: its GCRS direction is (X, Y, ~1), X, Y ~ 1e-3 rad in 2016.
  EXPECT_NEAR(w.normalized()(2), 1.0, 1e-5);
  g_mallocs = 0;
  g_count = true;
  double sum = 0.0;
  for (int k = 0; k < 1000; ++k) {
    rot.rotation(80.0 * k, r0, w);
    sum += r0(0, 0) + w(2);
  }
  g_count = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_TRUE(std::isfinite(sum));
}

TEST(IauEarthRotation, BadInput) {
  const fr::EopTable eop = fr::EopTable::read(kFinals);
  const Epoch e0 = Epoch::parse("2017-01-30T00:00:00", TimeScale::utc);
  // The span leaves the table (ends 2017-01-31): the error policy throws at setup, naming the epoch.
  try {
    fr::IauEarthRotation(e0, eop, 0.0, 5.0 * 86400.0);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& err) {
    EXPECT_NE(std::string(err.what()).find("is outside the EOP table"), std::string::npos) << err.what();
  }
  // hold_last accepts it.
  EXPECT_NO_THROW(
      fr::IauEarthRotation(e0, eop.with_policy(fr::OutOfRangePolicy::hold_last), 0.0, 5.0 * 86400.0));
  EXPECT_THROW(fr::IauEarthRotation(e0, eop, 10.0, 0.0), std::invalid_argument);
  EXPECT_THROW(fr::IauEarthRotation(e0, eop, 0.0, 10.0, 0.0), std::invalid_argument);
}

}  // namespace
