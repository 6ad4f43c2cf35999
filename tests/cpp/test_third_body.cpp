// Sun and Moon: ephemerides against Meeus' worked examples (ERFA frames -> true equator of date),
// the third-body Jacobian against 4th-order finite differences, the tidal potential, and the
// ForceModel wiring (epoch, partials, validation).
#include <erfa.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/dynamics/third_body.hpp"
#include "testing.hpp"

namespace {
using satgnc::Mat3;
using satgnc::Vec3;
namespace dy = satgnc::dynamics;
constexpr double kDeg = M_PI / 180.0;

// Right ascension and declination (deg) on the true equator and equinox of date of a GCRF vector.
void ra_dec_of_date(const Vec3& g, double jd1, double jd2, double& ra, double& dec) {
  double rnpb[3][3];
  eraPnm06a(jd1, jd2, rnpb);
  Vec3 t;
  for (int i = 0; i < 3; ++i) t[i] = rnpb[i][0] * g[0] + rnpb[i][1] * g[1] + rnpb[i][2] * g[2];
  ra = std::atan2(t.y(), t.x()) / kDeg;
  if (ra < 0) ra += 360.0;
  dec = std::asin(t.z() / t.norm()) / kDeg;
}

TEST(ThirdBody, SunMatchesMeeusExample25a) {
  // Meeus, Astronomical Algorithms (2nd ed. 1998), Example 25.a: 1992 October 13.0 TD (JD 2448908.5):
  // R = 0.99766 AU, apparent alpha = 198.38083 deg, delta = -7.78507 deg (low-accuracy method, 0.01 deg).
  const Vec3 s = dy::sun_position(2448908.5, 0.0);
  // The example's low-accuracy series (mean elements + equation of centre) is good to ~1e-4 AU in R;
  // eraEpv00 gives 0.9976085 AU: tolerance 1e-4 AU.
  EXPECT_NEAR(s.norm() / dy::kAstronomicalUnitKm, 0.99766, 1e-4);
  double ra = 0, dec = 0;
  ra_dec_of_date(s, 2448908.5, 0.0, ra, dec);
  // Geometric vs apparent: aberration 20.5" (0.0057 deg) + the example's 0.01 deg: tolerance 0.02 deg.
  std::printf("Sun 1992-10-13.0 TT: ra %.5f dec %.5f deg (Meeus 25.a apparent 198.38083, -7.78507)\n", ra,
              dec);
  EXPECT_NEAR(ra, 198.38083, 0.02);
  EXPECT_NEAR(dec, -7.78507, 0.02);
}

TEST(ThirdBody, MoonMatchesMeeusExample47a) {
  // Meeus Example 47.a: 1992 April 12, 0h TD (JD 2448724.5): Delta = 368409.7 km, apparent
  // alpha = 134.688470 deg, delta = 13.768368 deg. eraMoon98 is Meeus' ch. 47 series (ERFA doc):
  // distance to 1 km; direction to 10" (IAU 2006 frame chain vs Meeus' ecliptic of date).
  const Vec3 m = dy::moon_position(2448724.5, 0.0);
  EXPECT_NEAR(m.norm(), 368409.7, 1.0);
  double ra = 0, dec = 0;
  ra_dec_of_date(m, 2448724.5, 0.0, ra, dec);
  std::printf(
      "Moon 1992-04-12.0 TT: %.3f km ra %.6f dec %.6f deg (Meeus 47.a 368409.7, 134.688470, 13.768368)\n",
      m.norm(), ra, dec);
  EXPECT_NEAR(ra, 134.688470, 10.0 / 3600.0);
  EXPECT_NEAR(dec, 13.768368, 10.0 / 3600.0);
}

TEST(ThirdBody, InterpolatedEphemerisStaysWithinMetresOfErfa) {
  const dy::EphemerisInterpolator eph;  // 1/8-day nodes
  double sun_err = 0.0, moon_err = 0.0;
  for (int i = 0; i <= 2000; ++i) {
    const double d = -0.7 + 2.0 * i / 2000.0;  // two days around J2000 + 0.3, both signs of jd2
    sun_err = std::max(sun_err, (eph.sun(2451545.3, d) - dy::sun_position(2451545.3, d)).norm());
    moon_err = std::max(moon_err, (eph.moon(2451545.3, d) - dy::moon_position(2451545.3, d)).norm());
  }
  std::printf("Hermite 1/8 day: max Sun error %.3g km, Moon %.3g km\n", sun_err, moon_err);
  // Cubic Hermite error h^4/384 |x''''|: ~1e-5 km for the Sun, ~1e-3 km for the Moon at h = 1/8 day.
  EXPECT_LT(sun_err, 1e-3);
  EXPECT_LT(moon_err, 5e-3);
  // A node value is exact, and step 0 is ERFA itself.
  EXPECT_LE((eph.moon(2451545.0, 0.25) - dy::moon_position(2451545.0, 0.25)).norm(), 1e-6);
  EXPECT_EQ(dy::EphemerisInterpolator(0.0).sun(2451545.0, 0.1), dy::sun_position(2451545.0, 0.1));
  EXPECT_THROW(dy::EphemerisInterpolator(-1.0), std::invalid_argument);
}

TEST(ThirdBody, JacobianMatchesFourthOrderDifferencesAndPotentialGradient) {
  const double mu = dy::ThirdBodies{}.mu_moon;
  const Vec3 s = dy::moon_position(2451545.0, 0.25);
  for (const Vec3& r : {Vec3(6778.0, 0.0, 0.0), Vec3(-20000.0, 30000.0, 5000.0), Vec3(42164.0, 10.0, -3.0)}) {
    Vec3 a;
    Mat3 G;
    dy::third_body_jacobian(mu, s, r, a, G);
    // Direct and indirect terms cancel to ~1/100 of each: rounding ~100 eps, tolerance 1e-13.
    SATGNC_EXPECT_REL(dy::third_body_acceleration(mu, s, r), a, 1e-13);
    Mat3 Gfd;
    Vec3 gv;
    const double h = 10.0;  // km: |s - r| ~ 4e5 km, truncation (h/d)^4 ~ 4e-19; rounding 1e-16 |a_ind| / h
    for (int j = 0; j < 3; ++j) {
      Vec3 e = Vec3::Zero();
      e[j] = h;
      auto f = [&](const Vec3& x) { return dy::third_body_acceleration(mu, s, x); };
      auto V = [&](const Vec3& x) { return dy::third_body_potential(mu, s, x); };
      Gfd.col(j) = (-f(r + 2 * e) + 8 * f(r + e) - 8 * f(r - e) + f(r - 2 * e)) / (12 * h);
      gv[j] = -(-V(r + 2 * e) + 8 * V(r + e) - 8 * V(r - e) + V(r - 2 * e)) / (12 * h);
    }
    // The tidal gradient is ~mu/d^3 = 7e-14 1/s^2 while a's indirect part is ~3e-8 km/s^2, so the FD
    // rounding floor is ~1e-16 * 3e-8 / 10 = 3e-25: tolerance 1e-7 relative.
    SATGNC_EXPECT_REL(G, Gfd, 1e-7);
    // Potential: |V| ~ mu/d ~ 1e-2 km^2/s^2 whose differences lose 1e-18/10: tolerance 1e-5 of |a|.
    SATGNC_EXPECT_REL(a, gv, 1e-5);
  }
  // At the geocentre the direct and indirect terms cancel.
  EXPECT_LE(dy::third_body_acceleration(mu, s, Vec3::Zero()).norm(), 1e-25);
}

TEST(ThirdBody, ForceModelUsesTheEpochAndRefusesBadParameters) {
  dy::ForceModel fm;
  fm.third_body = dy::ThirdBodies{};
  fm.epoch_jd1 = 2451545.0;
  fm.epoch_jd2 = 0.5;
  fm.validate();
  const Vec3 r(7000.0, 100.0, -50.0), v(0.0, 7.5, 0.0);
  const double t = 3600.0;
  const double d2 = 0.5 + t / 86400.0;
  fm.ephemeris = dy::EphemerisInterpolator(0.0);  // ERFA at every call, as in the sum below
  const Vec3 expect =
      dy::point_mass_acceleration(fm.mu, r) +
      dy::third_body_acceleration(fm.third_body->mu_sun, dy::sun_position(2451545.0, d2), r) +
      dy::third_body_acceleration(fm.third_body->mu_moon, dy::moon_position(2451545.0, d2), r);
  // Same terms summed in another order: a few ulps of the point mass.
  SATGNC_EXPECT_REL(fm.acceleration(t, r, v), expect, 4e-15);
  Vec3 a;
  Mat3 G, Gv;
  fm.acceleration_jacobians(t, r, v, a, G, Gv);
  SATGNC_EXPECT_REL(a, expect, 4e-15);
  EXPECT_EQ(Gv.norm(), 0.0);
  // Lunar + solar tidal acceleration in LEO: 1e-9 .. 2e-9 km/s^2 (Montenbruck & Gill Fig. 3.1: ~1e-6 m/s^2).
  const double tidal = (a - dy::point_mass_acceleration(fm.mu, r)).norm();
  EXPECT_GT(tidal, 3e-10);
  EXPECT_LT(tidal, 3e-9);
  // The epoch from a core::Epoch: 2000-01-01T12:00:00 TT is JD 2451545.0 TT exactly.
  fm.set_epoch(satgnc::core::Epoch::parse("2000-01-01T12:00:00", satgnc::core::TimeScale::tt));
  EXPECT_EQ(fm.epoch_jd1 + fm.epoch_jd2, 2451545.0);
  fm.third_body->mu_moon = -1.0;
  try {
    fm.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("third_body.mu_moon: must be finite and > 0", 0), 0u) << e.what();
  }
}

}  // namespace
