#include "satgnc/core/time.hpp"

#include <cmath>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::core {

double julian_date(int year, int month, int day, int hour, int minute, double second) {
  using core::require;
  require(year >= 1900 && year <= 2100, "year", "must be in 1900..2100");
  require(month >= 1 && month <= 12, "month", "must be in 1..12");
  static constexpr int kDays[12] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  const int days = month == 2 && !leap ? 28 : kDays[month - 1];
  // 2021-02-31 was accepted and read as 2021-03-03.
  require(day >= 1 && day <= days, "day",
          "must be in 1.." + std::to_string(days) + " for month " + std::to_string(month) + " of " +
              std::to_string(year) + ", got " + std::to_string(day));
  // Alg. 14's validity starts on 1900-03-01 (1900 is not a leap year; the formula assumes it is).
  require(year > 1900 || month >= 3, "year", "must be on or after 1900-03-01 (the formula's validity)");
  require(hour >= 0 && hour <= 23, "hour", "must be in 0..23");
  require(minute >= 0 && minute <= 59, "minute", "must be in 0..59");
  require(std::isfinite(second) && second >= 0.0 && second < 61.0, "second", "must be in [0, 61)");
  // Vallado Alg. 14 (integer parts taken with truncation as printed there).
  const double y = year, m = month;
  const double jd = 367.0 * y - std::trunc(7.0 * (y + std::trunc((m + 9.0) / 12.0)) * 0.25) +
                    std::trunc(275.0 * m / 9.0) + day + 1721013.5;
  return jd + ((second / 60.0 + minute) / 60.0 + hour) / 24.0;
}

double gmst_iau1982(double jd_ut1) {
  core::require_finite(jd_ut1, "jd_ut1");
  constexpr double kTwoPi = 6.283185307179586476925;
  const double t = (jd_ut1 - 2451545.0) / 36525.0;
  // Seconds of sidereal time; 876600 h = 3155760000 s per century, plus the IAU-1982 polynomial.
  double sec = 67310.54841 + (876600.0 * 3600.0 + 8640184.812866) * t + 0.093104 * t * t - 6.2e-6 * t * t * t;
  double rad = std::fmod(sec * kTwoPi / 86400.0, kTwoPi);
  if (rad < 0.0) rad += kTwoPi;
  return rad;
}

double gmst_from_utc(double jd_utc, double ut1_minus_utc_s) {
  // IERS keeps |UT1 - UTC| < 0.9 s with leap seconds: 5 s is a unit or sign error, not an offset.
  core::require(std::isfinite(ut1_minus_utc_s) && std::abs(ut1_minus_utc_s) < kMaxUt1MinusUtc,
                "ut1_minus_utc_s",
                "|UT1 - UTC| must be < 0.9 s (IERS), got " + std::to_string(ut1_minus_utc_s),
                "the offset is in seconds; leap seconds keep it below 0.9 s");
  return gmst_iau1982(jd_utc + ut1_minus_utc_s / 86400.0);
}

}  // namespace satgnc::core
