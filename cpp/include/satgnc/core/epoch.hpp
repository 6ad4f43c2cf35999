#pragma once
/// @file epoch.hpp
/// Time scales and the Epoch type: an instant stored in TAI as whole seconds plus a fraction, so
/// that no precision is lost over decades. Conversions among the scales go through ERFA (the open
/// SOFA-derived library of the IAU standards): eraDat for the leap-second table, eraUtctai /
/// eraTaiutc for UTC before 1972, eraDtf2d / eraCal2jd / eraJd2cal for calendars, eraDtdb for TDB.
///
/// UT1 is not a TimeScale here: it needs Earth orientation parameters (UT1-UTC), so it lives in the
/// frames room (satgnc/frames/eop.hpp, EopTable::ut1_minus_utc and EopTable::ut1_jd).
#include <cstdint>
#include <string>
#include <string_view>

namespace satgnc::core {

/// The time scales an Epoch converts to and from.
/// - tai: International Atomic Time (the storage scale).
/// - tt: Terrestrial Time, TT = TAI + 32.184 s exactly.
/// - utc: Coordinated Universal Time with leap seconds (ERFA's eraDat table; 23:59:60 is a valid
///   second on a leap-second day). From 1972-01-01 TAI-UTC is an integer and conversions are exact;
///   before 1972 (the "rubber second" era, back to 1960) ERFA's eraUtctai / eraTaiutc are used on a
///   two-part Julian date (resolution ~1e-11 s).
/// - gps: GPS time, GPS = TAI - 19 s exactly (no leap seconds).
/// - tdb: Barycentric Dynamical Time, TDB = TT + eraDtdb(TT) evaluated at the geocentre (observer
///   longitude and distances from the spin axis / equator set to zero). Approximation: the omitted
///   topocentric terms are below 2 microseconds for an Earth-bound observer; eraDtdb itself agrees
///   with the numerical time ephemeris to a few nanoseconds over 1950-2050 (ERFA documentation).
enum class TimeScale { tai, tt, utc, gps, tdb };

/// The upper-case name of a scale: "TAI", "TT", "UTC", "GPS", "TDB".
const char* time_scale_name(TimeScale scale) noexcept;

/// The scale named by name (case-insensitive: "UTC", "utc", "TAI", "TT", "GPS", "TDB"). Throws
/// std::invalid_argument("time_scale: unknown time system '<name>' (choices: TAI, TT, UTC, GPS, TDB)").
/// UT1 is refused with a hint that it needs EOP (frames::EopTable).
TimeScale time_scale_from_name(std::string_view name);

/// A two-part Julian date (days): jd1 + jd2 is the date, split to keep precision (ERFA's convention).
struct JulianDate {
  double jd1 = 0.0;  ///< days
  double jd2 = 0.0;  ///< days
};

/// A broken-down calendar date and time in some scale. second is in [0, 60), or [60, 61) in the
/// last minute of a UTC leap-second day.
struct CalendarTime {
  int year = 2000;      ///< Gregorian year
  int month = 1;        ///< 1..12
  int day = 1;          ///< 1..31
  int hour = 0;         ///< 0..23
  int minute = 0;       ///< 0..59
  double second = 0.0;  ///< s, [0, 61)
};

/// An instant, stored as TAI seconds since J2000 (2000-01-01T12:00:00 TAI): a 64-bit integer count
/// of whole seconds plus a double fraction in [0, 1). Differences of two epochs and shifts by a
/// double are exact to the double's resolution of the shift itself (1e-16 relative), independent of
/// the distance from J2000. Value type; all members are const and thread-safe.
class Epoch {
 public:
  /// J2000 TAI (2000-01-01T12:00:00 TAI).
  Epoch() = default;

  /// From TAI seconds since J2000 TAI given as whole + fraction (any finite fraction; normalised).
  static Epoch from_tai_seconds(std::int64_t whole, double fraction = 0.0);
  /// From a two-part Julian date (days) in scale. jd1 + jd2 is the date; either split works, but
  /// precision is best with jd1 a whole or half day. UTC uses ERFA's quasi-JD convention (a leap
  /// day is 86401 s long). Throws std::invalid_argument naming jd1/jd2 if not finite or the date is
  /// outside ERFA's UTC table (before 1960) for scale utc, or more than 1e8 days from J2000.
  static Epoch from_jd(double jd1, double jd2, TimeScale scale);
  /// From a Modified Julian Date (days, MJD = JD - 2400000.5) in scale.
  static Epoch from_mjd(double mjd, TimeScale scale);
  /// From a calendar date and time in scale (Gregorian). second in [0, 60), or [60, 61) only in
  /// the last minute of a UTC leap-second day. Throws std::invalid_argument naming the field.
  static Epoch from_calendar(int year, int month, int day, int hour, int minute, double second,
                             TimeScale scale);
  /// Parse ISO-8601 text in scale: "YYYY-MM-DDThh:mm:ss[.f...]" or the day-of-year form
  /// "YYYY-DDDThh:mm:ss[.f...]" (CCSDS), a space in place of 'T', "YYYY-MM-DD" (midnight), an
  /// optional trailing 'Z' (accepted only for scale utc). Up to 18 fraction digits are read exactly
  /// (no decimal-to-binary rounding of the whole seconds). Throws std::invalid_argument naming the
  /// text, e.g. "epoch: malformed ISO-8601 '2016-13-01T00:00:00' (month 13 not in 1..12)".
  static Epoch parse(std::string_view text, TimeScale scale);

  /// Two-part Julian date in scale (days): jd1 holds whole or half days, jd2 the fraction. For utc,
  /// ERFA's quasi-JD (jd1 = the day's 0h, jd2 = seconds of day / length of that UTC day, 86401 s on
  /// a leap-second day), the form eraUtctai and eraD2dtf take.
  JulianDate jd(TimeScale scale) const;
  /// Modified Julian Date in scale (days), as one double (resolution ~1e-6 s today).
  double mjd(TimeScale scale) const;
  /// Calendar date and time in scale with second rounded to decimals (0..12) digits; a UTC epoch
  /// inside a leap second reads 23:59:60.x.
  CalendarTime calendar(TimeScale scale, int decimals = 9) const;
  /// ISO-8601 "YYYY-MM-DDThh:mm:ss[.f]" in scale with decimals (0..12) fraction digits (rounded
  /// half up); 23:59:60.x inside a UTC leap second. No scale suffix is written.
  std::string to_iso(TimeScale scale, int decimals = 3) const;

  /// scale - TAI at this instant (s): TT 32.184, GPS -19, UTC -(TAI-UTC), TDB 32.184 + eraDtdb.
  double offset_from_tai(TimeScale scale) const;
  /// TAI - UTC at this instant (s), from ERFA's table (37 s since 2017-01-01).
  double tai_minus_utc() const;

  /// Whole TAI seconds since J2000 TAI.
  std::int64_t tai_whole() const { return whole_; }
  /// Fraction of the TAI second, in [0, 1).
  double tai_fraction() const { return frac_; }
  /// TAI seconds since J2000 TAI as one double (resolution ~1e-7 s at 30 years; use differences of
  /// epochs for precise intervals).
  double tai_seconds() const { return static_cast<double>(whole_) + frac_; }

  /// The epoch dt seconds later. Throws std::invalid_argument("dt: ...") unless dt is finite and
  /// |dt| < 9e15 s (the check allocates nothing when it passes).
  Epoch operator+(double dt) const;
  /// The epoch dt seconds earlier.
  Epoch operator-(double dt) const { return *this + (-dt); }
  /// Shift this epoch by dt seconds.
  Epoch& operator+=(double dt) { return *this = *this + dt; }
  /// Shift this epoch by -dt seconds.
  Epoch& operator-=(double dt) { return *this = *this + (-dt); }
  /// Seconds from other to this (this - other), exact to the double rounding of the result.
  double operator-(const Epoch& other) const {
    return static_cast<double>(whole_ - other.whole_) + (frac_ - other.frac_);
  }
  /// Same instant.
  bool operator==(const Epoch& o) const { return whole_ == o.whole_ && frac_ == o.frac_; }
  /// Different instants.
  bool operator!=(const Epoch& o) const { return !(*this == o); }
  /// Earlier than.
  bool operator<(const Epoch& o) const {
    return whole_ < o.whole_ || (whole_ == o.whole_ && frac_ < o.frac_);
  }
  /// Later than.
  bool operator>(const Epoch& o) const { return o < *this; }
  /// Not later than.
  bool operator<=(const Epoch& o) const { return !(o < *this); }
  /// Not earlier than.
  bool operator>=(const Epoch& o) const { return !(*this < o); }

 private:
  std::int64_t whole_ = 0;  // TAI s since J2000 TAI
  double frac_ = 0.0;       // [0, 1)
};

}  // namespace satgnc::core
