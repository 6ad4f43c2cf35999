// frames::EopTable: IERS finals2000A / EOP 20 C04 readers and 4-point Lagrange interpolation.
#include "satgnc/frames/eop.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "satgnc/core/validate.hpp"

namespace satgnc::frames {

namespace {

constexpr double kMjd1960 = 36934.0;

std::string trim(const std::string& s) {
  std::size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

[[noreturn]] void file_error(const std::string& path, std::size_t line, const std::string& what) {
  throw std::invalid_argument(path + ":" + std::to_string(line) + ": " + what);
}

bool parse_number(const std::string& text, double& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(out);
}

// Fixed-column field [first, last] (1-based, inclusive), trimmed; empty when the line is shorter.
std::string column(const std::string& line, std::size_t first, std::size_t last) {
  if (line.size() < first) return "";
  return trim(line.substr(first - 1, last - first + 1));
}

struct Field {
  const std::string& path;
  std::size_t line_no;
  const std::string& line;
  // Value of a fixed-column field; false if blank; throws naming the column if not a number.
  bool get(std::size_t first, std::size_t last, const char* label, double& out) const {
    const std::string t = column(line, first, last);
    if (t.empty()) return false;
    if (!parse_number(t, out))
      file_error(path, line_no,
                 "columns " + std::to_string(first) + "-" + std::to_string(last) + " (" + label + "): '" + t +
                     "' is not a number");
    return true;
  }
  void require_field(std::size_t first, std::size_t last, const char* label, double& out) const {
    if (!get(first, last, label, out))
      file_error(
          path, line_no,
          "columns " + std::to_string(first) + "-" + std::to_string(last) + " (" + label + "): missing");
  }
};

std::ifstream open_or_throw(const std::string& path) {
  std::ifstream in(path);
  core::require(in.good(), "path", "cannot open EOP file '" + path + "'");
  return in;
}

void check_order(const std::string& path, std::size_t line_no, const std::vector<EopRow>& rows, double mjd) {
  if (!rows.empty() && !(mjd > rows.back().mjd))
    file_error(path, line_no,
               "MJD " + std::to_string(mjd) + " does not follow the previous row's MJD " +
                   std::to_string(rows.back().mjd) + " (rows must be in increasing date order)");
  if (mjd != std::floor(mjd)) file_error(path, line_no, "MJD " + std::to_string(mjd) + " is not at 0h UTC");
  if (mjd < kMjd1960) file_error(path, line_no, "MJD " + std::to_string(mjd) + " is before 1960 (no UTC)");
}

std::string span_text(const std::vector<EopRow>& rows) {
  auto day = [](double mjd) {
    return core::Epoch::from_mjd(mjd, core::TimeScale::utc).to_iso(core::TimeScale::utc, 0).substr(0, 10);
  };
  std::ostringstream s;
  s << "MJD " << rows.front().mjd << " .. " << rows.back().mjd << " = " << day(rows.front().mjd) << " .. "
    << day(rows.back().mjd) << " UTC";
  return s.str();
}

}  // namespace

const char* eop_source_name(EopSource source) noexcept {
  switch (source) {
    case EopSource::bulletin_b:
      return "bulletin_b";
    case EopSource::bulletin_a:
      return "bulletin_a";
    case EopSource::bulletin_a_prediction:
      return "bulletin_a_prediction";
    case EopSource::c04:
      return "c04";
    case EopSource::user:
      return "user";
  }
  return "?";
}

const char* out_of_range_policy_name(OutOfRangePolicy policy) noexcept {
  switch (policy) {
    case OutOfRangePolicy::error:
      return "error";
    case OutOfRangePolicy::hold_last:
      return "hold_last";
    case OutOfRangePolicy::zero:
      return "zero";
  }
  return "?";
}

OutOfRangePolicy out_of_range_policy_from_name(const std::string& name) {
  if (name == "error") return OutOfRangePolicy::error;
  if (name == "hold_last") return OutOfRangePolicy::hold_last;
  if (name == "zero") return OutOfRangePolicy::zero;
  core::require(false, "policy",
                "unknown out-of-range policy '" + name + "' (choices: error, hold_last, zero)");
  return OutOfRangePolicy::error;
}

EopTable::EopTable(std::vector<EopRow> rows, OutOfRangePolicy policy)
    : rows_(std::move(rows)), policy_(policy) {
  core::require(rows_.size() >= 2, "rows",
                "an EOP table needs at least 2 rows, got " + std::to_string(rows_.size()));
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    const EopRow& r = rows_[i];
    const std::string name = "rows[" + std::to_string(i) + "]";
    core::require(std::isfinite(r.xp) && std::isfinite(r.yp) && std::isfinite(r.ut1_utc) &&
                      std::isfinite(r.lod) && std::isfinite(r.dx) && std::isfinite(r.dy),
                  name, "values must be finite");
    core::require(std::isfinite(r.mjd) && r.mjd == std::floor(r.mjd) && r.mjd >= kMjd1960, name,
                  "mjd must be a whole day >= 36934 (1960-01-01), got " + std::to_string(r.mjd));
    if (i > 0)
      core::require(r.mjd > rows_[i - 1].mjd, name,
                    "mjd must increase from row to row, got " + std::to_string(r.mjd) + " after " +
                        std::to_string(rows_[i - 1].mjd));
  }
  t0_ = core::Epoch::from_mjd(rows_.front().mjd, core::TimeScale::utc);
  t_.resize(rows_.size());
  ut1_tai_.resize(rows_.size());
  dat_.resize(rows_.size());
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    const core::Epoch e = core::Epoch::from_mjd(rows_[i].mjd, core::TimeScale::utc);
    t_[i] = e - t0_;
    dat_[i] = e.tai_minus_utc();
    ut1_tai_[i] = rows_[i].ut1_utc - dat_[i];
  }
}

EopTable EopTable::with_policy(OutOfRangePolicy policy) const {
  EopTable copy = *this;
  copy.policy_ = policy;
  return copy;
}

core::Epoch EopTable::first_epoch() const { return t0_; }
core::Epoch EopTable::last_epoch() const { return t0_ + t_.back(); }

bool EopTable::covers(const core::Epoch& epoch) const {
  const double t = epoch - t0_;
  return t >= 0.0 && t <= t_.back();
}

EopValues EopTable::at(const core::Epoch& epoch) const {
  const double t = epoch - t0_;
  const std::size_t n = rows_.size();
  EopValues v;
  if (!(t >= 0.0 && t <= t_.back())) {
    switch (policy_) {
      case OutOfRangePolicy::zero:
        v.ut1_tai = -epoch.tai_minus_utc();
        return v;
      case OutOfRangePolicy::hold_last: {
        const std::size_t k = t < 0.0 ? 0 : n - 1;
        const EopRow& r = rows_[k];
        v.xp = r.xp;
        v.yp = r.yp;
        v.ut1_utc = r.ut1_utc;
        v.lod = r.lod;
        v.dx = r.dx;
        v.dy = r.dy;
        v.ut1_tai = r.ut1_utc - epoch.tai_minus_utc();
        return v;
      }
      case OutOfRangePolicy::error: {
        std::string when;
        try {
          when = epoch.to_iso(core::TimeScale::utc, 3) + " UTC";
        } catch (const std::invalid_argument&) {
          when = epoch.to_iso(core::TimeScale::tai, 3) + " TAI";
        }
        core::require(
            false, "epoch", when + " is outside the EOP table (" + span_text(rows_) + ")",
            "load a newer table (satgnc.frames.default_eop() in Python) or choose the policy hold_last "
            "or zero");
      }
    }
  }
  // Interval [i, i+1] holding t.
  std::size_t i = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin());
  i = i == 0 ? 0 : i - 1;
  if (i >= n - 1) i = n - 2;
  auto blend = [&](auto&& f) {
    if (i >= 1 && i + 2 < n) {
      // 4-point Lagrange on rows i-1 .. i+2.
      const double x0 = t_[i - 1], x1 = t_[i], x2 = t_[i + 1], x3 = t_[i + 2];
      const double w0 = (t - x1) * (t - x2) * (t - x3) / ((x0 - x1) * (x0 - x2) * (x0 - x3));
      const double w1 = (t - x0) * (t - x2) * (t - x3) / ((x1 - x0) * (x1 - x2) * (x1 - x3));
      const double w2 = (t - x0) * (t - x1) * (t - x3) / ((x2 - x0) * (x2 - x1) * (x2 - x3));
      const double w3 = (t - x0) * (t - x1) * (t - x2) / ((x3 - x0) * (x3 - x1) * (x3 - x2));
      return w0 * f(i - 1) + w1 * f(i) + w2 * f(i + 1) + w3 * f(i + 2);
    }
    const double a = (t - t_[i]) / (t_[i + 1] - t_[i]);
    return (1.0 - a) * f(i) + a * f(i + 1);
  };
  v.xp = blend([&](std::size_t k) { return rows_[k].xp; });
  v.yp = blend([&](std::size_t k) { return rows_[k].yp; });
  v.lod = blend([&](std::size_t k) { return rows_[k].lod; });
  v.dx = blend([&](std::size_t k) { return rows_[k].dx; });
  v.dy = blend([&](std::size_t k) { return rows_[k].dy; });
  v.ut1_tai = blend([&](std::size_t k) { return ut1_tai_[k]; });
  // TAI-UTC at the epoch: constant over a UTC day, so that of row i's day when the next row is the next
  // day (t < t_[i+1]), of row i+1 at its own 0h; the general (slower) lookup across gaps of days.
  double dat = 0.0;
  if (t >= t_[i + 1])
    dat = dat_[i + 1];
  else if (rows_[i + 1].mjd == rows_[i].mjd + 1.0)
    dat = dat_[i];
  else
    dat = epoch.tai_minus_utc();
  v.ut1_utc = v.ut1_tai + dat;
  return v;
}

core::JulianDate EopTable::ut1_jd(const core::Epoch& epoch) const {
  return (epoch + at(epoch).ut1_tai).jd(core::TimeScale::tai);
}

EopTable EopTable::read_finals2000a(const std::string& path, OutOfRangePolicy policy) {
  std::ifstream in = open_or_throw(path);
  std::vector<EopRow> rows;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;  // '#' lines: comments (e.g. a provenance line)
    const Field f{path, line_no, line};
    EopRow r;
    f.require_field(8, 15, "MJD", r.mjd);
    double xa = 0.0, ya = 0.0, ua = 0.0;
    const bool has_x = f.get(19, 27, "PM_x_A", xa);
    const bool has_u = f.get(59, 68, "UT1_UTC_A", ua);
    if (!has_x && !has_u) continue;  // a date past the prediction horizon: no values
    if (!has_x) file_error(path, line_no, "columns 19-27 (PM_x_A): missing");
    if (!has_u) file_error(path, line_no, "columns 59-68 (UT1_UTC_A): missing");
    f.require_field(38, 46, "PM_y_A", ya);
    check_order(path, line_no, rows, r.mjd);
    double lod_ms = 0.0, dxa = 0.0, dya = 0.0;
    f.get(80, 86, "LOD_A", lod_ms);
    f.get(98, 106, "dX_2000A_A", dxa);
    f.get(117, 125, "dY_2000A_A", dya);
    double xb = 0.0, yb = 0.0, ub = 0.0, dxb = 0.0, dyb = 0.0;
    const bool has_b =
        f.get(135, 144, "PM_X_B", xb) && f.get(145, 154, "PM_Y_B", yb) && f.get(155, 165, "UT1_UTC_B", ub);
    const bool has_b_nut = f.get(166, 175, "dX_2000A_B", dxb) && f.get(176, 185, "dY_2000A_B", dyb);
    r.lod = lod_ms * 1e-3;
    if (has_b) {
      r.xp = xb;
      r.yp = yb;
      r.ut1_utc = ub;
      r.source = EopSource::bulletin_b;
    } else {
      r.xp = xa;
      r.yp = ya;
      r.ut1_utc = ua;
      r.source = column(line, 58, 58) == "P" ? EopSource::bulletin_a_prediction : EopSource::bulletin_a;
    }
    r.dx = (has_b && has_b_nut ? dxb : dxa) * 1e-3;  // mas -> arcsec
    r.dy = (has_b && has_b_nut ? dyb : dya) * 1e-3;
    rows.push_back(r);
  }
  core::require(rows.size() >= 2, "path",
                "'" + path + "' holds fewer than 2 EOP rows (not a finals2000A file?)");
  return EopTable(std::move(rows), policy);
}

EopTable EopTable::read_c04(const std::string& path, OutOfRangePolicy policy) {
  std::ifstream in = open_or_throw(path);
  std::vector<EopRow> rows;
  std::string line;
  std::size_t line_no = 0;
  static const char* const kNames[] = {"YR",      "MM", "DD", "HH",  "MJD", "x",  "y",
                                       "UT1-UTC", "dX", "dY", "xrt", "yrt", "LOD"};
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    std::istringstream ss(t);
    std::string tok;
    double v[13] = {};
    int k = 0;
    while (k < 13 && ss >> tok) {
      if (!parse_number(tok, v[k]))
        file_error(path, line_no, std::string("column ") + kNames[k] + ": '" + tok + "' is not a number");
      ++k;
    }
    if (k < 13)
      file_error(path, line_no,
                 "expected at least 13 columns (YR MM DD HH MJD x y UT1-UTC dX dY xrt yrt LOD), got " +
                     std::to_string(k));
    if (v[3] < 0.0 || v[3] > 23.0)
      file_error(
          path, line_no,
          "column HH: " + std::to_string(v[3]) +
              " is not an hour (0..23); the older EOP 14 C04 layout (YR MM DD MJD x y UT1-UTC LOD ...) is "
              "not read: use the EOP 20 C04 file (YR MM DD HH MJD ...)");
    EopRow r;
    r.mjd = v[4];
    check_order(path, line_no, rows, r.mjd);
    r.xp = v[5];
    r.yp = v[6];
    r.ut1_utc = v[7];
    r.dx = v[8];
    r.dy = v[9];
    r.lod = v[12];
    r.source = EopSource::c04;
    rows.push_back(r);
  }
  core::require(rows.size() >= 2, "path",
                "'" + path + "' holds fewer than 2 EOP rows (not an EOP 20 C04 file?)");
  return EopTable(std::move(rows), policy);
}

EopTable EopTable::read(const std::string& path, OutOfRangePolicy policy) {
  std::ifstream in = open_or_throw(path);
  std::string line;
  while (std::getline(in, line)) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    // finals2000A: "73 1 2 41684.00 ..." (the MJD's point in column 13); C04: "1962   1   1   0  37665.00".
    const bool finals = line.size() > 12 && line[12] == '.';
    return finals ? read_finals2000a(path, policy) : read_c04(path, policy);
  }
  core::require(false, "path", "'" + path + "' holds no EOP rows");
  return read_c04(path, policy);
}

}  // namespace satgnc::frames
