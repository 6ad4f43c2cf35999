#pragma once
/// @file time.hpp
/// Calendar to Julian date and the IAU-1982 Greenwich mean sidereal time used to place a station.
namespace satgnc::core {

/// Julian date of a Gregorian calendar date and time (any time scale; the result is in that scale).
/// Valid for 1900-03-01 .. 2100-02-28 (Vallado, "Fundamentals of Astrodynamics", 4th ed., Alg. 14).
/// Throws std::invalid_argument on out-of-range fields (a day past the month's end, a date before
/// 1900-03-01). second may be fractional.
double julian_date(int year, int month, int day, int hour, int minute, double second);

/// Greenwich mean sidereal time (IAU-1982, Vallado 4th ed. eq. 3-47) at UT1 Julian date, rad in [0, 2 pi).
double gmst_iau1982(double jd_ut1);

/// Bound on |UT1 - UTC| (s): the IERS inserts leap seconds to keep it below 0.9 s.
inline constexpr double kMaxUt1MinusUtc = 0.9;

/// GMST (rad) at a UTC Julian date with the UT1 - UTC offset (s). Throws std::invalid_argument
/// naming ut1_minus_utc_s unless |ut1_minus_utc_s| < kMaxUt1MinusUtc.
double gmst_from_utc(double jd_utc, double ut1_minus_utc_s = 0.0);

}  // namespace satgnc::core
