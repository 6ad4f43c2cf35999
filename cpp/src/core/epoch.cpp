// core::Epoch: TAI whole seconds + fraction since J2000 TAI; scale conversions through ERFA.
#include "satgnc/core/epoch.hpp"

#include <erfa.h>
#include <erfam.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::core {

namespace {

constexpr double kJ2000 = 2451545.0;          // JD of J2000 (2000-01-01T12:00)
constexpr double kMjdZero = 2400000.5;        // JD of MJD 0
constexpr std::int64_t kMjdJ2000Day = 51544;  // MJD of 2000-01-01
constexpr std::int64_t kMjd1972 = 41317;      // MJD of 1972-01-01: integer TAI-UTC from here on
constexpr double kGpsMinusTai = -19.0;        // s, fixed since 1980-01-06
constexpr std::int64_t kMjd1960 = 36934;      // MJD of 1960-01-01: UTC (ERFA's table) starts here

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  std::int64_t q = a / b;
  if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
  return q;
}

// Seconds since J2000 (noon) of 0h of the day with this MJD, in any uniform scale.
std::int64_t day_start_seconds(std::int64_t mjd) { return (mjd - kMjdJ2000Day) * 86400 - 43200; }

// Calendar date of an MJD (whole day).
void mjd_to_date(std::int64_t mjd, int& y, int& m, int& d) {
  double fd = 0.0;
  eraJd2cal(kMjdZero, static_cast<double>(mjd), &y, &m, &d, &fd);
}

// TAI-UTC (s) at 0h UTC of the day with this MJD (>= 1972: an integer, constant over the day).
double dat_of_mjd(std::int64_t mjd) {
  int y = 0, m = 0, d = 0;
  mjd_to_date(mjd, y, m, d);
  double dat = 0.0;
  const int st = eraDat(y, m, d, 0.0, &dat);
  // Hot path (every UTC conversion): the message is built only on failure, so success allocates nothing.
  if (st < 0)
    require(false, "epoch", "UTC is defined from 1960 on (ERFA eraDat), got year " + std::to_string(y));
  return dat;
}

// TAI seconds since J2000 of 0h UTC of the day mjd (>= 1972).
std::int64_t utc_day_start_tai(std::int64_t mjd) {
  return day_start_seconds(mjd) + static_cast<std::int64_t>(dat_of_mjd(mjd));
}

// Raw two-part JD of a count of seconds since J2000 in some uniform scale.
JulianDate raw_jd(std::int64_t whole, double frac) {
  const std::int64_t days = floor_div(whole, 86400);
  const std::int64_t rem = whole - days * 86400;
  return {kJ2000 + static_cast<double>(days), (static_cast<double>(rem) + frac) / 86400.0};
}

// TDB - TT (s) at the geocentre for a date given as a two-part JD (TT or TDB: the difference of the
// two arguments, < 2 ms, changes the result by < 1e-13 s).
double tdb_minus_tt(const JulianDate& jd) { return eraDtdb(jd.jd1, jd.jd2, 0.0, 0.0, 0.0, 0.0); }

// A uniform-scale Epoch-like count from a two-part JD, keeping both parts' precision.
Epoch raw_from_jd(double jd1, double jd2) {
  const double a = jd1 - kJ2000;
  const double b = jd2;
  const double da = std::floor(a), db = std::floor(b);
  const double sa = (a - da) * 86400.0, sb = (b - db) * 86400.0;
  const double wa = std::floor(sa), wb = std::floor(sb);
  const auto whole = static_cast<std::int64_t>(da) * 86400 + static_cast<std::int64_t>(db) * 86400 +
                     static_cast<std::int64_t>(wa) + static_cast<std::int64_t>(wb);
  return Epoch::from_tai_seconds(whole, (sa - wa) + (sb - wb));
}

void require_utc_era(bool ok) {
  if (!ok) require(false, "epoch", "UTC is defined from 1960-01-01 on (ERFA eraDat's table starts there)");
}

bool is_post_1972_tai(std::int64_t tai_whole) {
  // 1972-01-01T00:00:00 UTC = 00:00:10 TAI.
  return tai_whole >= day_start_seconds(kMjd1972) + 10;
}

// The UTC day (MJD) containing a TAI instant >= 1972, and its start in TAI seconds.
void find_utc_day(std::int64_t tai_whole, std::int64_t& mjd, std::int64_t& start) {
  // Guess with TAI-UTC of the guessed day itself, then walk (each step reuses the previous start).
  std::int64_t c = kMjdJ2000Day + floor_div(tai_whole + 43200, 86400);
  std::int64_t s0 = utc_day_start_tai(c);
  while (tai_whole < s0) s0 = utc_day_start_tai(--c);
  for (;;) {
    const std::int64_t s1 = utc_day_start_tai(c + 1);
    if (tai_whole < s1) {
      mjd = c;
      start = s0;
      return;
    }
    ++c;
    s0 = s1;
  }
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Rounded (whole, k) with k in [0, 10^decimals): the count rounded half up to decimals digits.
void round_fraction(std::int64_t& whole, double frac, int decimals, std::int64_t& k) {
  const double scale = std::pow(10.0, decimals);
  const auto top = static_cast<std::int64_t>(scale);
  k = static_cast<std::int64_t>(std::floor(frac * scale + 0.5));
  if (k >= top) {
    k -= top;
    whole += 1;
  }
}

Epoch from_fields(int y, int mo, int d, int h, int mi, int sec, double frac, TimeScale scale) {
  double djm0 = 0.0, djm = 0.0;
  require(y <= 1000000, "year", std::to_string(y) + " is after 1000000");
  const int st = eraCal2jd(y, mo, d, &djm0, &djm);
  require(st != -1, "year", std::to_string(y) + " is before -4799 (ERFA eraCal2jd)");
  require(st != -2, "month", std::to_string(mo) + " not in 1..12");
  require(st != -3, "day",
          std::to_string(d) + " not a day of " + std::to_string(y) + "-" + std::to_string(mo));
  require(h >= 0 && h <= 23, "hour", std::to_string(h) + " not in 0..23");
  require(mi >= 0 && mi <= 59, "minute", std::to_string(mi) + " not in 0..59");
  require(std::isfinite(frac) && frac >= 0.0 && frac < 1.0, "second", "fraction must be in [0, 1)");
  const auto mjd = static_cast<std::int64_t>(djm);
  const bool leap_ok = scale == TimeScale::utc && mjd >= kMjd1972 && h == 23 && mi == 59 &&
                       dat_of_mjd(mjd + 1) - dat_of_mjd(mjd) == 1.0;
  require(
      sec >= 0 && (sec <= 59 || (sec == 60 && leap_ok)), "second",
      std::to_string(sec) + (sec == 60 ? " is valid only at 23:59 of a UTC day that ends with a leap second"
                                       : " not in 0..59"));
  const std::int64_t naive = day_start_seconds(mjd) + h * 3600 + mi * 60 + sec;
  const Epoch as_is = Epoch::from_tai_seconds(naive, frac);
  switch (scale) {
    case TimeScale::tai:
      return as_is;
    case TimeScale::tt:
      return as_is + (-ERFA_TTMTAI);
    case TimeScale::gps:
      return as_is + (-kGpsMinusTai);
    case TimeScale::tdb: {
      const Epoch tt = as_is + (-tdb_minus_tt(raw_jd(naive, frac)));
      return tt + (-ERFA_TTMTAI);
    }
    case TimeScale::utc:
      require(mjd >= kMjd1960, "year", "UTC is defined from 1960 on (ERFA eraDat), got " + std::to_string(y));
      if (mjd >= kMjd1972)
        return Epoch::from_tai_seconds(naive + static_cast<std::int64_t>(dat_of_mjd(mjd)), frac);
      {
        double u1 = 0.0, u2 = 0.0, t1 = 0.0, t2 = 0.0;
        require(eraDtf2d("UTC", y, mo, d, h, mi, sec + frac, &u1, &u2) >= 0, "epoch",
                "UTC date not convertible (ERFA eraDtf2d)");
        require(eraUtctai(u1, u2, &t1, &t2) >= 0, "epoch", "UTC is defined from 1960 on (ERFA eraUtctai)");
        return raw_from_jd(t1, t2);
      }
  }
  return as_is;
}

[[noreturn]] void bad_iso(std::string_view text, const std::string& why) {
  throw std::invalid_argument("epoch: malformed ISO-8601 '" + std::string(text) + "' (" + why +
                              "; expected YYYY-MM-DDThh:mm:ss[.fff] or YYYY-DDDThh:mm:ss[.fff])");
}

}  // namespace

const char* time_scale_name(TimeScale scale) noexcept {
  switch (scale) {
    case TimeScale::tai:
      return "TAI";
    case TimeScale::tt:
      return "TT";
    case TimeScale::utc:
      return "UTC";
    case TimeScale::gps:
      return "GPS";
    case TimeScale::tdb:
      return "TDB";
  }
  return "?";
}

TimeScale time_scale_from_name(std::string_view name) {
  const std::string n = lower(name);
  if (n == "tai") return TimeScale::tai;
  if (n == "tt") return TimeScale::tt;
  if (n == "utc") return TimeScale::utc;
  if (n == "gps") return TimeScale::gps;
  if (n == "tdb") return TimeScale::tdb;
  require(false, "time_scale",
          "unknown time system '" + std::string(name) + "' (choices: TAI, TT, UTC, GPS, TDB)",
          n == "ut1" ? "UT1 needs Earth orientation parameters: satgnc::frames::EopTable" : "");
  return TimeScale::tai;
}

Epoch Epoch::from_tai_seconds(std::int64_t whole, double fraction) {
  if (!(std::isfinite(fraction) && std::fabs(fraction) < 9e15))
    require(false, "fraction", "must be finite and |fraction| < 9e15 s");
  const double f = std::floor(fraction);
  Epoch e;
  e.whole_ = whole + static_cast<std::int64_t>(f);
  e.frac_ = fraction - f;
  if (e.frac_ >= 1.0) {  // fraction just below an integer rounded up
    e.frac_ -= 1.0;
    e.whole_ += 1;
  }
  return e;
}

Epoch Epoch::operator+(double dt) const {
  if (!(std::isfinite(dt) && std::fabs(dt) < 9e15)) require(false, "dt", "must be finite and |dt| < 9e15 s");
  const double w = std::floor(dt);
  return from_tai_seconds(whole_ + static_cast<std::int64_t>(w), frac_ + (dt - w));
}

Epoch Epoch::from_jd(double jd1, double jd2, TimeScale scale) {
  require_finite(jd1, "jd1");
  require_finite(jd2, "jd2");
  // 1e8 days (~270000 years) around J2000: keeps every day count well inside int64.
  require(std::fabs(jd1 - kJ2000) + std::fabs(jd2) < 1e8, "jd1",
          "jd1 + jd2 must be within 1e8 days of J2000 (JD 2451545)");
  switch (scale) {
    case TimeScale::tai:
      return raw_from_jd(jd1, jd2);
    case TimeScale::tt:
      return raw_from_jd(jd1, jd2) + (-ERFA_TTMTAI);
    case TimeScale::gps:
      return raw_from_jd(jd1, jd2) + (-kGpsMinusTai);
    case TimeScale::tdb:
      return raw_from_jd(jd1, jd2) + (-tdb_minus_tt({jd1, jd2}) - ERFA_TTMTAI);
    case TimeScale::utc: {
      require(jd1 + jd2 >= kMjdZero + static_cast<double>(kMjd1960), "jd1",
              "UTC is defined from 1960-01-01 (JD 2436934.5) on (ERFA eraDat)");
      // Quasi-JD -> (day, fraction of that UTC day), each part split exactly.
      const double a = jd1 - kMjdZero;
      const double da = std::floor(a), db = std::floor(jd2);
      double f = (a - da) + (jd2 - db);
      const double df = std::floor(f);
      f -= df;
      const auto mjd = static_cast<std::int64_t>(da + db + df);
      if (mjd >= kMjd1972) {
        const std::int64_t start = utc_day_start_tai(mjd);
        const double secs = f * static_cast<double>(utc_day_start_tai(mjd + 1) - start);
        const double w = std::floor(secs);
        return Epoch::from_tai_seconds(start + static_cast<std::int64_t>(w), secs - w);
      }
      double t1 = 0.0, t2 = 0.0;
      require(eraUtctai(jd1, jd2, &t1, &t2) >= 0, "jd1", "UTC is defined from 1960 on (ERFA eraUtctai)");
      return raw_from_jd(t1, t2);
    }
  }
  return {};
}

Epoch Epoch::from_mjd(double mjd, TimeScale scale) {
  require_finite(mjd, "mjd");
  return from_jd(kMjdZero, mjd, scale);
}

Epoch Epoch::from_calendar(int year, int month, int day, int hour, int minute, double second,
                           TimeScale scale) {
  require(std::isfinite(second) && second >= 0.0 && second < 61.0, "second", "must be finite and in [0, 61)");
  const double w = std::floor(second);
  return from_fields(year, month, day, hour, minute, static_cast<int>(w), second - w, scale);
}

Epoch Epoch::parse(std::string_view text, TimeScale scale) {
  std::size_t b = 0, e = text.size();
  while (b < e && std::isspace(static_cast<unsigned char>(text[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(text[e - 1]))) --e;
  const std::string_view t = text.substr(b, e - b);
  std::size_t i = 0;
  auto digits = [&](std::size_t max) {
    std::size_t n = 0;
    while (i + n < t.size() && n < max && std::isdigit(static_cast<unsigned char>(t[i + n]))) ++n;
    return n;
  };
  auto number = [&](std::size_t n) {
    int v = 0;
    for (std::size_t k = 0; k < n; ++k) v = 10 * v + (t[i + k] - '0');
    i += n;
    return v;
  };
  auto expect = [&](char c, const char* what) {
    if (i >= t.size() || t[i] != c) bad_iso(text, std::string("expected '") + c + "' " + what);
    ++i;
  };
  if (digits(4) != 4) bad_iso(text, "year must have 4 digits");
  const int year = number(4);
  expect('-', "after the year");
  const std::size_t nd = digits(4);
  int month = 0, day = 0;
  if (nd == 2) {
    month = number(2);
    expect('-', "after the month");
    if (digits(3) != 2) bad_iso(text, "day must have 2 digits");
    day = number(2);
  } else if (nd == 3) {
    const int doy = number(3);
    const int ndays = (year % 4 == 0 && (year % 100 != 0 || year % 400 == 0)) ? 366 : 365;
    if (doy < 1 || doy > ndays)
      bad_iso(text, "day of year " + std::to_string(doy) + " not in 1.." + std::to_string(ndays));
    double djm0 = 0.0, djm = 0.0;
    eraCal2jd(year, 1, 1, &djm0, &djm);
    double fd = 0.0;
    int yy = 0;
    eraJd2cal(djm0, djm + doy - 1, &yy, &month, &day, &fd);
  } else {
    bad_iso(text, "month must have 2 digits or day of year 3 digits");
  }
  int hour = 0, minute = 0, sec = 0;
  double frac = 0.0;
  if (i < t.size() && (t[i] == 'T' || t[i] == ' ')) {
    ++i;
    if (digits(3) != 2) bad_iso(text, "hour must have 2 digits");
    hour = number(2);
    expect(':', "after the hour");
    if (digits(3) != 2) bad_iso(text, "minute must have 2 digits");
    minute = number(2);
    expect(':', "after the minute");
    if (digits(3) != 2) bad_iso(text, "second must have 2 digits");
    sec = number(2);
    if (i < t.size() && t[i] == '.') {
      ++i;
      const std::size_t nf = digits(1000);
      if (nf == 0) bad_iso(text, "no digit after the decimal point");
      std::int64_t num = 0;
      double den = 1.0;
      for (std::size_t k = 0; k < nf && k < 18; ++k) {
        num = 10 * num + (t[i + k] - '0');
        den *= 10.0;
      }
      i += nf;
      frac = static_cast<double>(num) / den;
    }
  }
  if (i < t.size() && t[i] == 'Z') {
    if (scale != TimeScale::utc)
      bad_iso(text, std::string("'Z' means UTC but the scale is ") + time_scale_name(scale));
    ++i;
  }
  if (i != t.size()) bad_iso(text, "unexpected '" + std::string(t.substr(i)) + "'");
  try {
    return from_fields(year, month, day, hour, minute, sec, frac, scale);
  } catch (const std::invalid_argument& err) {
    bad_iso(text, err.what());
  }
}

double Epoch::offset_from_tai(TimeScale scale) const {
  switch (scale) {
    case TimeScale::tai:
      return 0.0;
    case TimeScale::tt:
      return ERFA_TTMTAI;
    case TimeScale::gps:
      return kGpsMinusTai;
    case TimeScale::tdb: {
      const Epoch tt = *this + ERFA_TTMTAI;
      return ERFA_TTMTAI + tdb_minus_tt(raw_jd(tt.whole_, tt.frac_));
    }
    case TimeScale::utc:
      return -tai_minus_utc();
  }
  return 0.0;
}

double Epoch::tai_minus_utc() const {
  if (is_post_1972_tai(whole_)) {
    std::int64_t mjd = 0, start = 0;
    find_utc_day(whole_, mjd, start);
    return dat_of_mjd(mjd);
  }
  require_utc_era(whole_ >= day_start_seconds(kMjd1960));
  const JulianDate t = raw_jd(whole_, frac_);
  double u1 = 0.0, u2 = 0.0;
  if (eraTaiutc(t.jd1, t.jd2, &u1, &u2) < 0)
    require(false, "epoch", "UTC is defined from 1960 on (ERFA eraTaiutc)");
  int y = 0, m = 0, d = 0;
  double fd = 0.0;
  eraJd2cal(u1, u2, &y, &m, &d, &fd);
  double dat = 0.0;
  eraDat(y, m, d, fd, &dat);
  return dat;
}

JulianDate Epoch::jd(TimeScale scale) const {
  if (scale == TimeScale::utc) {
    if (is_post_1972_tai(whole_)) {
      std::int64_t mjd = 0, start = 0;
      find_utc_day(whole_, mjd, start);
      const double len = static_cast<double>(utc_day_start_tai(mjd + 1) - start);
      return {kMjdZero + static_cast<double>(mjd), (static_cast<double>(whole_ - start) + frac_) / len};
    }
    require_utc_era(whole_ >= day_start_seconds(kMjd1960));
    const JulianDate t = raw_jd(whole_, frac_);
    JulianDate u;
    if (eraTaiutc(t.jd1, t.jd2, &u.jd1, &u.jd2) < 0)
      require(false, "epoch", "UTC is defined from 1960 on (ERFA eraTaiutc)");
    return u;
  }
  const Epoch s = *this + offset_from_tai(scale);
  return raw_jd(s.whole_, s.frac_);
}

double Epoch::mjd(TimeScale scale) const {
  const JulianDate j = jd(scale);
  return (j.jd1 - kMjdZero) + j.jd2;
}

namespace {
// Calendar fields with the second's fraction as the integer k (units of 10^-ndp s).
void calendar_impl(const Epoch& e, TimeScale scale, int decimals, CalendarTime& c, std::int64_t& k,
                   int& ndp) {
  require(decimals >= 0 && decimals <= 12, "decimals", "must be in 0..12, got " + std::to_string(decimals));
  ndp = decimals;
  k = 0;
  if (scale == TimeScale::utc && !is_post_1972_tai(e.tai_whole())) {
    const JulianDate u = e.jd(TimeScale::utc);
    std::array<int, 4> hmsf{};
    ndp = decimals > 9 ? 9 : decimals;
    require(eraD2dtf("UTC", ndp, u.jd1, u.jd2, &c.year, &c.month, &c.day, hmsf.data()) >= 0, "epoch",
            "UTC date not convertible (ERFA eraD2dtf)");
    c.hour = hmsf[0];
    c.minute = hmsf[1];
    k = hmsf[3];
    c.second = hmsf[2];
    return;
  }
  std::int64_t sod = 0, mjd = 0;
  if (scale == TimeScale::utc) {
    std::int64_t w = e.tai_whole();
    round_fraction(w, e.tai_fraction(), decimals, k);
    std::int64_t start = 0;
    find_utc_day(w, mjd, start);
    sod = w - start;
  } else {
    const Epoch s = e + e.offset_from_tai(scale);
    std::int64_t w = s.tai_whole();
    round_fraction(w, s.tai_fraction(), decimals, k);
    const std::int64_t since_midnight = w + 43200;
    const std::int64_t days = floor_div(since_midnight, 86400);
    mjd = kMjdJ2000Day + days;
    sod = since_midnight - days * 86400;
  }
  mjd_to_date(mjd, c.year, c.month, c.day);
  c.hour = static_cast<int>(sod >= 86400 ? 23 : sod / 3600);
  c.minute = static_cast<int>(sod >= 86400 ? 59 : (sod % 3600) / 60);
  c.second = static_cast<double>(sod - c.hour * 3600 - c.minute * 60);
}
}  // namespace

CalendarTime Epoch::calendar(TimeScale scale, int decimals) const {
  CalendarTime c;
  std::int64_t k = 0;
  int ndp = 0;
  calendar_impl(*this, scale, decimals, c, k, ndp);
  c.second += static_cast<double>(k) * std::pow(10.0, -ndp);
  return c;
}

std::string Epoch::to_iso(TimeScale scale, int decimals) const {
  CalendarTime c;
  std::int64_t k = 0;
  int ndp = 0;
  calendar_impl(*this, scale, decimals, c, k, ndp);
  const auto whole_sec = static_cast<int>(c.second);
  std::array<char, 64> buf{};
  int n = std::snprintf(buf.data(), buf.size(), "%04d-%02d-%02dT%02d:%02d:%02d", c.year, c.month, c.day,
                        c.hour, c.minute, whole_sec);
  std::string out(buf.data(), static_cast<std::size_t>(n));
  if (decimals > 0) {
    // The fraction digits from the rounded integer, not from printf's rounding of a double.
    long long digits = static_cast<long long>(k);
    for (int j = ndp; j < decimals; ++j) digits *= 10;  // pre-1972 UTC: ERFA gives <= 9 digits
    n = std::snprintf(buf.data(), buf.size(), ".%0*lld", decimals, digits);
    out.append(buf.data(), static_cast<std::size_t>(n));
  }
  return out;
}

}  // namespace satgnc::core
