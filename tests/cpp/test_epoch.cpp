// core::Epoch and TimeScale: ERFA's own test values (t_erfa_c.c), Vallado's Example 3-14 time line,
// the 2016-12-31 leap second, ISO round trips, precision of differences, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "error_checks.hpp"
#include "satgnc/core/epoch.hpp"

namespace {
using satgnc::core::CalendarTime;
using satgnc::core::Epoch;
using satgnc::core::JulianDate;
using satgnc::core::time_scale_from_name;
using satgnc::core::TimeScale;
using satgnc::testing::message_of;

// t_erfa_c.c t_dat: eraDat(2003,6,1) = 32, (2008,1,17) = 33, (2017,9,1) = 37 (exact).
TEST(Epoch, TaiMinusUtcMatchesErfaDatCases) {
  EXPECT_EQ(Epoch::from_calendar(2003, 6, 1, 0, 0, 0.0, TimeScale::utc).tai_minus_utc(), 32.0);
  EXPECT_EQ(Epoch::from_calendar(2008, 1, 17, 0, 0, 0.0, TimeScale::utc).tai_minus_utc(), 33.0);
  EXPECT_EQ(Epoch::from_calendar(2017, 9, 1, 0, 0, 0.0, TimeScale::utc).tai_minus_utc(), 37.0);
}

// t_erfa_c.c t_utctai: UTC 2453750.5 + 0.892100694 -> TAI 2453750.5 + 0.8924826384444444444 (1e-12 d).
TEST(Epoch, UtcToTaiMatchesErfaUtctaiCase) {
  const Epoch e = Epoch::from_jd(2453750.5, 0.892100694, TimeScale::utc);
  const JulianDate t = e.jd(TimeScale::tai);
  // Our jd1 is noon-based: compare the sums relative to the day. 1e-12 d is ERFA's own tolerance.
  EXPECT_NEAR((t.jd1 - 2453750.5) + t.jd2, 0.8924826384444444444, 1e-12);
  // And back (t_taiutc: TAI 0.892482639 -> UTC 0.8921006945555555556, 1e-12 d).
  const Epoch f = Epoch::from_jd(2453750.5, 0.892482639, TimeScale::tai);
  const JulianDate u = f.jd(TimeScale::utc);
  EXPECT_EQ(u.jd1, 2453750.5);
  EXPECT_NEAR(u.jd2, 0.8921006945555555556, 1e-12);
  // t_taitt: TAI 0.892482639 -> TT 0.892855139 (1e-12 d).
  const JulianDate tt = f.jd(TimeScale::tt);
  EXPECT_NEAR((tt.jd1 - 2453750.5) + tt.jd2, 0.892855139, 1e-12);
}

// t_erfa_c.c t_d2dtf: eraD2dtf("UTC", 5, 2400000.5, 49533.99999) = 1994-06-30 23:59:60.13599, and
// t_dtf2d: 1994-06-30 23:59:60.13599 UTC = quasi-JD 2449534.49999 (1e-6 d).
TEST(Epoch, LeapSecondOf1994MatchesErfaD2dtfCase) {
  const Epoch e = Epoch::from_jd(2400000.5, 49533.99999, TimeScale::utc);
  EXPECT_EQ(e.to_iso(TimeScale::utc, 5), "1994-06-30T23:59:60.13599");
  const Epoch g = Epoch::from_calendar(1994, 6, 30, 23, 59, 60.13599, TimeScale::utc);
  const JulianDate q = g.jd(TimeScale::utc);
  EXPECT_NEAR(q.jd1 + q.jd2, 2449534.49999, 1e-6);
  EXPECT_NEAR(g - e, 0.0,
              1e-6);  // 1e-5 of the JD's 5th decimal of a day ~ 0.9 s; both are the same leap second
}

// The 2016-12-31 leap second: TAI-UTC 36 -> 37 s; 23:59:60.5 UTC = 2017-01-01T00:00:36.5 TAI.
TEST(Epoch, LeapSecond2016ParsesFormatsAndCounts) {
  const Epoch leap = Epoch::parse("2016-12-31T23:59:60.5", TimeScale::utc);
  EXPECT_EQ(leap.to_iso(TimeScale::tai, 3), "2017-01-01T00:00:36.500");
  EXPECT_EQ(leap.to_iso(TimeScale::utc, 1), "2016-12-31T23:59:60.5");
  EXPECT_EQ(leap.tai_minus_utc(), 36.0);
  const Epoch before = Epoch::parse("2016-12-31T23:59:59", TimeScale::utc);
  const Epoch after = Epoch::parse("2017-01-01T00:00:00", TimeScale::utc);
  EXPECT_EQ(after - before, 2.0);  // exact: two SI seconds span the leap
  EXPECT_EQ(before.tai_minus_utc(), 36.0);
  EXPECT_EQ(after.tai_minus_utc(), 37.0);
  // Quasi-JD of a leap day: 86401 s long, so 23:59:60.5 is 86400.5 / 86401 of the day.
  const JulianDate q = leap.jd(TimeScale::utc);
  EXPECT_EQ(q.jd1, 2457753.5);
  EXPECT_NEAR(q.jd2, 86400.5 / 86401.0, 1e-16);  // one ulp of a number < 1
  // And back from the quasi-JD: the leap second again (JD fraction resolution ~1e-11 s).
  EXPECT_NEAR(Epoch::from_jd(q.jd1, q.jd2, TimeScale::utc) - leap, 0.0, 1e-10);
  // Rounding carries into the leap second, not into the next day.
  EXPECT_EQ((before + 0.9999999).to_iso(TimeScale::utc, 3), "2016-12-31T23:59:60.000");
  // 23:59:60 on an ordinary day, or in TAI, is refused.
  EXPECT_THROW(Epoch::parse("2016-12-30T23:59:60", TimeScale::utc), std::invalid_argument);
  EXPECT_THROW(Epoch::parse("2016-12-31T23:59:60", TimeScale::tai), std::invalid_argument);
}

// Vallado 4th ed. Example 3-7 / 3-14 time line: 2004-04-06 07:51:28.386009 UTC, TAI-UTC = 32 s;
// TT = 07:52:32.570009, JD_TT = 2453101.828154745 (printed to 1e-9 d).
TEST(Epoch, ValladoExampleTimeLine) {
  const Epoch e = Epoch::parse("2004-04-06T07:51:28.386009", TimeScale::utc);
  EXPECT_EQ(e.to_iso(TimeScale::tt, 6), "2004-04-06T07:52:32.570009");
  EXPECT_EQ(e.to_iso(TimeScale::gps, 6), "2004-04-06T07:51:41.386009");  // GPS = TAI - 19 s
  const JulianDate tt = e.jd(TimeScale::tt);
  EXPECT_NEAR(tt.jd1 + tt.jd2, 2453101.828154745, 1e-9);
  // TDB - TT at the geocentre is periodic, |.| < 1.7 ms (eraDtdb's amplitude).
  EXPECT_LT(std::fabs(e.offset_from_tai(TimeScale::tdb) - 32.184), 1.7e-3);
}

// GPS time began at 1980-01-06T00:00:00 UTC, when TAI-UTC was 19 s.
TEST(Epoch, GpsEpochIsUtcOf1980_01_06) {
  const Epoch e = Epoch::parse("1980-01-06T00:00:00Z", TimeScale::utc);
  EXPECT_EQ(e.to_iso(TimeScale::gps, 0), "1980-01-06T00:00:00");
  EXPECT_EQ(e.to_iso(TimeScale::tai, 0), "1980-01-06T00:00:19");
}

TEST(Epoch, IsoRoundTripsInEveryScale) {
  const char* texts[] = {"2024-02-29T13:45:07.123456789", "1999-12-31T23:59:59.999999999",
                         "2035-07-01T00:00:00.000000001", "1975-06-15T06:07:08.900000000"};
  for (TimeScale s : {TimeScale::tai, TimeScale::tt, TimeScale::utc, TimeScale::gps, TimeScale::tdb}) {
    for (const char* t : texts) {
      // 9 digits round trip exactly: the epoch holds the fraction to ~1e-16 s.
      EXPECT_EQ(Epoch::parse(t, s).to_iso(s, 9), std::string(t)) << satgnc::core::time_scale_name(s);
    }
  }
  // Day-of-year form (CCSDS): 2024-060 is 2024-02-29.
  EXPECT_EQ(Epoch::parse("2024-060T13:45:07.5", TimeScale::utc),
            Epoch::parse("2024-02-29T13:45:07.5", TimeScale::utc));
  EXPECT_EQ(Epoch::parse("2024-02-29", TimeScale::tt).to_iso(TimeScale::tt, 0), "2024-02-29T00:00:00");
}

TEST(Epoch, JulianDateRoundTripAndMjd) {
  const Epoch e = Epoch::parse("2021-03-04T05:06:07.25", TimeScale::tt);
  for (TimeScale s : {TimeScale::tai, TimeScale::tt, TimeScale::utc, TimeScale::gps, TimeScale::tdb}) {
    const JulianDate j = e.jd(s);
    // A two-part JD resolves ~1e-16 d = 1e-11 s: round trip to 2e-11 s.
    EXPECT_NEAR(Epoch::from_jd(j.jd1, j.jd2, s) - e, 0.0, 2e-11) << satgnc::core::time_scale_name(s);
  }
  // MJD 59277 is 2021-03-04; 05:06:07.25 is 18367.25 s of that day.
  EXPECT_NEAR(e.mjd(TimeScale::tt), 59277.0 + 18367.25 / 86400.0, 1e-10);  // one double MJD: ~1e-11 d
}

// Differences stay exact far from J2000, where one double JD would lose ~1e-5 s.
TEST(Epoch, DifferencesExactOverDecades) {
  const Epoch e = Epoch::parse("2049-11-30T17:00:00.3", TimeScale::tai);
  for (double dt : {1e-9, 0.1, 12345.678, 99999.999, -54321.123}) {
    const double back = (e + dt) - e;
    // Error <= one ulp of the fraction in [0, 1) plus one of dt: 2.3e-16 s + ulp(dt).
    EXPECT_NEAR(back, dt, 2.3e-16 + std::fabs(dt) * 2.3e-16) << dt;
  }
  EXPECT_LT(e, e + 1e-12);
  EXPECT_GT(e, e - 1e-12);
  EXPECT_NEAR((e + 0.7 - 0.7) - e, 0.0, 2.3e-16);  // two roundings of the fraction, each <= 1.1e-16 s
}

TEST(Epoch, BadInputNamesTheArgument) {
  EXPECT_EQ(message_of([] { time_scale_from_name("GMT"); }),
            "time_scale: unknown time system 'GMT' (choices: TAI, TT, UTC, GPS, TDB)");
  EXPECT_NE(message_of([] { time_scale_from_name("UT1"); }).find("EopTable"), std::string::npos);
  EXPECT_EQ(time_scale_from_name("utc"), TimeScale::utc);
  const std::string m = message_of([] { Epoch::parse("2016-13-01T00:00:00", TimeScale::utc); });
  EXPECT_NE(m.find("'2016-13-01T00:00:00'"), std::string::npos) << m;
  EXPECT_NE(m.find("month: 13 not in 1..12"), std::string::npos) << m;
  const std::string m2 = message_of([] { Epoch::parse("2016-01-01T1:00:00", TimeScale::utc); });
  EXPECT_NE(m2.find("hour must have 2 digits"), std::string::npos) << m2;
  const std::string m3 = message_of([] { Epoch::parse("2016-01-01T10:00:00Z", TimeScale::tai); });
  EXPECT_NE(m3.find("'Z' means UTC"), std::string::npos) << m3;
  EXPECT_THROW(Epoch::parse("2016-02-30T00:00:00", TimeScale::utc), std::invalid_argument);
  EXPECT_THROW(Epoch::parse("2016-01-01T00:00:00 junk", TimeScale::utc), std::invalid_argument);
  EXPECT_THROW(Epoch::from_calendar(2016, 1, 1, 24, 0, 0.0, TimeScale::tai), std::invalid_argument);
  EXPECT_THROW(Epoch::from_jd(NAN, 0.0, TimeScale::tt), std::invalid_argument);
  EXPECT_THROW(Epoch::from_calendar(1950, 1, 1, 0, 0, 0.0, TimeScale::utc), std::invalid_argument);
  EXPECT_THROW(Epoch::from_jd(2430000.5, 0.0, TimeScale::utc), std::invalid_argument);
  EXPECT_THROW(Epoch::from_calendar(1950, 1, 1, 0, 0, 0.0, TimeScale::tai).to_iso(TimeScale::utc),
               std::invalid_argument);
  // 1965 (rubber-second UTC) goes through ERFA: from 1965-03-01, TAI-UTC = 3.6401300 + (MJD - 38761)
  // * 0.001296 s (USNO tai-utc.dat); 1965-06-01 is MJD 38912.
  const Epoch r = Epoch::from_calendar(1965, 6, 1, 0, 0, 0.0, TimeScale::utc);
  EXPECT_NEAR(r.tai_minus_utc(), 3.6401300 + (38912.0 - 38761.0) * 0.001296, 1e-9);  // ERFA resolves ~1e-11 s
  EXPECT_EQ(r.to_iso(TimeScale::utc, 6), "1965-06-01T00:00:00.000000");
  EXPECT_THROW(Epoch() + INFINITY, std::invalid_argument);
  EXPECT_THROW(Epoch::from_jd(1e300, 0.0, TimeScale::tt), std::invalid_argument);
  EXPECT_THROW(Epoch::from_calendar(2147483000, 1, 1, 0, 0, 0.0, TimeScale::tai), std::invalid_argument);
  EXPECT_THROW(Epoch().to_iso(TimeScale::tai, 13), std::invalid_argument);
}

}  // namespace
