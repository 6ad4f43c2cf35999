// SPK (DAF) reader for the JPL DE ephemerides: types 2 and 3 Chebyshev segments, chained by center.
// Layout from NAIF's DAF and SPK Required Reading: 1024-byte records, 8-byte words, 1-based addresses.
#include "satgnc/dynamics/ephemeris_spk.hpp"

#include <erfa.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace satgnc::dynamics {

namespace {

constexpr std::size_t kRecord = 1024;
constexpr int kJ2000Frame = 1;
constexpr double kSecondsPerDay = 86400.0;
constexpr double kJ2000 = 2451545.0;
// The FTP validation string of the file record (bytes 699..726): a text-mode transfer alters it.
constexpr char kFtpString[] = "FTPSTR:\r:\n:\r\n:\r\x00:\x81:\x10\xce:ENDFTP";
constexpr std::size_t kFtpLength = 28;

bool host_little_endian() {
  const std::uint16_t one = 1;
  unsigned char b = 0;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

std::string trim(const char* p, std::size_t n) {
  std::string s(p, n);
  const auto end = s.find_last_not_of(std::string(" \0", 2));
  return end == std::string::npos ? std::string() : s.substr(0, end + 1);
}

std::string printable(const std::string& s) {
  std::string out;
  for (const char c : s) out += (c >= 32 && c < 127) ? c : '?';
  return out;
}

std::int32_t read_i32(const char* p) {
  std::int32_t v = 0;
  std::memcpy(&v, p, 4);
  return v;
}

std::int32_t swap_i32(std::int32_t v) {
  std::uint32_t u = 0;
  std::memcpy(&u, &v, 4);
  u = (u >> 24) | ((u >> 8) & 0xff00u) | ((u << 8) & 0xff0000u) | (u << 24);
  std::memcpy(&v, &u, 4);
  return v;
}

double read_f64(const char* p) {
  double v = 0.0;
  std::memcpy(&v, p, 8);
  return v;
}

std::string fmt(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

std::string body(int code) {
  switch (code) {
    case naif::ssb:
      return "0 (solar-system barycentre)";
    case naif::emb:
      return "3 (Earth-Moon barycentre)";
    case naif::sun:
      return "10 (Sun)";
    case naif::moon:
      return "301 (Moon)";
    case naif::earth:
      return "399 (Earth)";
    default:
      return std::to_string(code);
  }
}

}  // namespace

std::string format_tdb_seconds(double et) {
  if (!std::isfinite(et)) return fmt(et) + " s TDB past J2000";
  int iy = 0, im = 0, id = 0;
  double fd = 0.0;
  const double days = et / kSecondsPerDay;
  const double whole = std::floor(days);
  if (eraJd2cal(kJ2000 + whole, days - whole, &iy, &im, &id, &fd) != 0) {
    return fmt(et) + " s TDB past J2000";
  }
  // eraJd2cal's day starts at midnight; fd is the fraction of that day.
  const double secs = fd * kSecondsPerDay;
  const int hh = static_cast<int>(secs / 3600.0);
  const int mm = static_cast<int>((secs - hh * 3600.0) / 60.0);
  const double ss = secs - hh * 3600.0 - mm * 60.0;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%06.3f TDB", iy, im, id, hh, mm, ss);
  return std::string(buf) + " (" + fmt(et) + " s past J2000)";
}

double SpkEphemeris::tdb_seconds_from_tt(double jd1, double jd2) {
  // At the geocentre (u = v = 0) eraDtdb does not depend on ut; the TT fraction stands in for it.
  const double frac = std::fmod(jd1, 1.0) + std::fmod(jd2, 1.0) + 0.5;
  const double dtdb = eraDtdb(jd1, jd2, frac - std::floor(frac), 0.0, 0.0, 0.0);
  return ((jd1 - kJ2000) + jd2) * kSecondsPerDay + dtdb;
}

SpkEphemeris::SpkEphemeris(const std::string& path, const std::vector<std::pair<int, int>>& pairs)
    : path_(path), pairs_(pairs) {
  auto fail = [&](const std::string& what) -> void { throw std::invalid_argument(path + ": " + what); };
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot open the file");
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::uint64_t>(in.tellg());
  in.seekg(0);
  if (size < kRecord)
    fail("not a DAF file: " + std::to_string(size) + " bytes, shorter than one 1024-byte record");
  char rec[kRecord];
  in.read(rec, kRecord);

  const std::string idword = std::string(rec, 8);
  if (idword.compare(0, 4, "DAF/") != 0 && idword != "NAIF/DAF") {
    fail("not a DAF file (ID word '" + printable(idword) + "', expected 'DAF/SPK ')");
  }
  if (idword.compare(0, 4, "DAF/") == 0 && trim(rec + 4, 4) != "SPK") {
    fail("a DAF of type '" + printable(trim(rec + 4, 4)) + "', not an SPK ephemeris ('DAF/SPK ')");
  }
  const std::string locfmt = trim(rec + 88, 8);
  const bool little = host_little_endian();
  const std::string host = little ? "LTL-IEEE" : "BIG-IEEE";
  std::int32_t nd = read_i32(rec + 8), ni = read_i32(rec + 12);
  if (locfmt == "LTL-IEEE" || locfmt == "BIG-IEEE") {
    if (locfmt != host) {
      fail("wrong endianness: the file is " + locfmt + " (" + (locfmt == "BIG-IEEE" ? "big" : "little") +
           "-endian), this machine reads " + host +
           " only (convert it with NAIF's toxfr and tobin, or spkmerge)");
    }
  } else if (locfmt.empty()) {  // pre-1999 files: infer the byte order from ND
    if (nd != 2 && swap_i32(nd) == 2)
      fail("wrong endianness: ND reads 2 only byte-swapped (a non-native binary file)");
  } else {
    fail("unknown binary format '" + printable(locfmt) + "' (expected LTL-IEEE or BIG-IEEE)");
  }
  if (std::string(rec + 699, 7) == "FTPSTR:" && std::memcmp(rec + 699, kFtpString, kFtpLength) != 0) {
    fail("damaged by a text-mode (ASCII) transfer: the FTP validation string differs");
  }
  if (nd != 2 || ni != 6) {
    fail("ND = " + std::to_string(nd) + ", NI = " + std::to_string(ni) + " (an SPK has ND = 2, NI = 6)");
  }
  internal_name_ = trim(rec + 16, 60);
  const std::int32_t fward = read_i32(rec + 76);
  const auto nrecords = static_cast<std::int64_t>((size + kRecord - 1) / kRecord);
  const std::uint64_t nwords = size / 8;

  // Summary records: a doubly linked list; each holds NEXT, PREV, NSUM and NSUM summaries of
  // ND + (NI + 1) / 2 = 5 words; its name record follows it.
  constexpr int kSummaryWords = 5;
  constexpr int kNameChars = 8 * kSummaryWords;
  std::int64_t next = fward;
  std::int64_t visited = 0;
  char names[kRecord];
  while (next != 0) {
    if (next < 2 || next + 1 > nrecords) {
      fail("summary record " + std::to_string(next) + " outside the file's " + std::to_string(nrecords) +
           " records");
    }
    if (++visited > nrecords) fail("the summary records form a cycle");
    in.seekg(static_cast<std::streamoff>((next - 1) * kRecord));
    in.read(rec, kRecord);
    in.read(names, kRecord);
    if (!in) fail("summary record " + std::to_string(next) + ": cannot read it and its name record");
    const double nxt = read_f64(rec), nsum = read_f64(rec + 16);
    if (!(nsum >= 0 && nsum <= 25 && nsum == std::floor(nsum)) || !(nxt >= 0 && nxt == std::floor(nxt))) {
      fail("summary record " + std::to_string(next) + ": invalid NEXT " + fmt(nxt) + " or NSUM " + fmt(nsum));
    }
    for (int k = 0; k < static_cast<int>(nsum); ++k) {
      const char* s = rec + 24 + 8 * kSummaryWords * k;
      SpkSegmentInfo info;
      info.start_et = read_f64(s);
      info.end_et = read_f64(s + 8);
      info.target = read_i32(s + 16);
      info.center = read_i32(s + 20);
      info.frame = read_i32(s + 24);
      info.type = read_i32(s + 28);
      info.begin_address = read_i32(s + 32);
      info.end_address = read_i32(s + 36);
      info.name = trim(names + kNameChars * k, kNameChars);
      const std::string which =
          "segment " + std::to_string(segments_.size() + 1) + " ('" + printable(info.name) + "')";
      if (!(std::isfinite(info.start_et) && std::isfinite(info.end_et) && info.start_et <= info.end_et)) {
        fail(which + ": invalid coverage [" + fmt(info.start_et) + ", " + fmt(info.end_et) + "] s");
      }
      if (info.begin_address < 1 || info.end_address < info.begin_address ||
          static_cast<std::uint64_t>(info.end_address) > nwords) {
        fail(which + ": data addresses [" + std::to_string(info.begin_address) + ", " +
             std::to_string(info.end_address) + "] outside the file's " + std::to_string(nwords) + " words");
      }
      segments_.push_back(std::move(info));
    }
    next = static_cast<std::int64_t>(nxt);
  }
  if (segments_.empty()) fail("no segment in the file");
  if (pairs_.empty()) fail("no (target, center) pair requested");

  // The parent of a body: the center of its segments (the file's last segment for it decides; a
  // body must have one center across its segments for the chain to be unique).
  auto parent_of = [&](int b, int& parent) {
    bool found = false;
    for (const SpkSegmentInfo& s : segments_) {
      if (s.target != b) continue;
      if (found && s.center != parent) {
        fail("body " + body(b) + " has segments with centers " + body(parent) + " and " + body(s.center) +
             " (chains need one center per body)");
      }
      parent = s.center;
      found = true;
    }
    return found;
  };
  auto path_to_root = [&](int b) {
    std::vector<int> p{b};
    int parent = 0;
    while (parent_of(p.back(), parent)) {
      if (std::find(p.begin(), p.end(), parent) != p.end())
        fail("segment centers form a cycle at body " + body(parent));
      p.push_back(parent);
    }
    return p;
  };
  auto edge_of = [&](int b) {  // index of the edge b -> parent, created on first use (data loaded)
    for (std::size_t i = 0; i < edges_.size(); ++i) {
      if (edges_[i].body == b) return static_cast<int>(i);
    }
    Edge e;
    e.body = b;
    for (std::size_t i = 0; i < segments_.size(); ++i) {
      const SpkSegmentInfo& s = segments_[i];
      if (s.target != b) continue;
      e.parent = s.center;
      const std::string which = "segment '" + printable(s.name) + "' (target " + body(s.target) +
                                ", center " + body(s.center) + ")";
      if (s.type != 2 && s.type != 3) {
        fail(which + ": unsupported SPK type " + std::to_string(s.type) +
             " (this reader reads types 2 and 3)");
      }
      if (s.frame != kJ2000Frame) {
        fail(which + ": frame code " + std::to_string(s.frame) + " (this reader takes J2000 = 1 only)");
      }
      Segment seg;
      seg.info = static_cast<int>(i);
      seg.type = s.type;
      seg.start_et = s.start_et;
      seg.end_et = s.end_et;
      const std::size_t count = static_cast<std::size_t>(s.end_address - s.begin_address + 1);
      seg.data.resize(count);
      in.seekg(static_cast<std::streamoff>(s.begin_address - 1) * 8);
      in.read(reinterpret_cast<char*>(seg.data.data()), static_cast<std::streamsize>(count * 8));
      if (!in) fail(which + ": cannot read its " + std::to_string(count) + " words");
      if (count < 4) fail(which + ": " + std::to_string(count) + " words, fewer than its 4-word directory");
      const double init = seg.data[count - 4], intlen = seg.data[count - 3];
      const double rsize = seg.data[count - 2], n = seg.data[count - 1];
      const int comps = s.type == 2 ? 3 : 6;
      const bool integral = rsize == std::floor(rsize) && n == std::floor(n) && rsize >= 2 + comps &&
                            n >= 1 && rsize < 1e6 && n < 1e9;
      if (!(std::isfinite(init) && std::isfinite(intlen) && intlen > 0 && integral) ||
          static_cast<double>(count - 4) != rsize * n || (static_cast<int>(rsize) - 2) % comps != 0) {
        fail(which + ": inconsistent type " + std::to_string(s.type) + " directory (INIT " + fmt(init) +
             ", INTLEN " + fmt(intlen) + ", RSIZE " + fmt(rsize) + ", N " + fmt(n) + " for " +
             std::to_string(count) + " words)");
      }
      seg.init = init;
      seg.intlen = intlen;
      seg.rsize = static_cast<int>(rsize);
      seg.n = static_cast<int>(n);
      seg.ncoef = (seg.rsize - 2) / comps;
      seg.data.resize(count - 4);
      for (int r = 0; r < seg.n; ++r) {
        if (!(seg.data[static_cast<std::size_t>(r) * seg.rsize + 1] > 0.0)) {
          fail(which + ": record " + std::to_string(r + 1) + " has a non-positive RADIUS");
        }
      }
      e.segments.push_back(static_cast<int>(loaded_.size()));
      loaded_.push_back(std::move(seg));
    }
    edges_.push_back(std::move(e));
    return static_cast<int>(edges_.size() - 1);
  };

  start_et_ = -1e300;
  end_et_ = 1e300;
  for (const auto& [target, center] : pairs_) {
    if (target == center) fail("target and center are both body " + body(target));
    const std::vector<int> pt = path_to_root(target), pc = path_to_root(center);
    // The nearest common body: target - center = (target -> common) - (center -> common).
    int common = -1;
    for (const int b : pt) {
      if (std::find(pc.begin(), pc.end(), b) != pc.end()) {
        common = b;
        break;
      }
    }
    if (common == -1) {
      fail("no chain of segments links target " + body(target) + " to center " + body(center));
    }
    Chain c;
    c.target = target;
    c.center = center;
    for (std::size_t i = 0; pt[i] != common; ++i) c.terms.emplace_back(edge_of(pt[i]), 1.0);
    for (std::size_t i = 0; pc[i] != common; ++i) c.terms.emplace_back(edge_of(pc[i]), -1.0);
    for (const auto& [ei, sign] : c.terms) {
      double lo = 1e300, hi = -1e300;  // the edge's span: union of its segments (assumed contiguous)
      for (const int si : edges_[static_cast<std::size_t>(ei)].segments) {
        lo = std::min(lo, loaded_[static_cast<std::size_t>(si)].start_et);
        hi = std::max(hi, loaded_[static_cast<std::size_t>(si)].end_et);
      }
      start_et_ = std::max(start_et_, lo);
      end_et_ = std::min(end_et_, hi);
      (void)sign;
    }
    chains_.push_back(std::move(c));
  }
  if (start_et_ > end_et_) fail("the segments of the requested chains do not overlap in time");
}

const SpkEphemeris::Chain& SpkEphemeris::chain(int target, int center) const {
  for (const Chain& c : chains_) {
    if (c.target == target && c.center == center) return c;
  }
  throw std::invalid_argument("SpkEphemeris: target " + body(target) + " from center " + body(center) +
                              " was not requested when " + path_ + " was opened");
}

void SpkEphemeris::throw_outside(const Edge& e, double et) const {
  std::string spans;
  for (const int si : e.segments) {
    const Segment& s = loaded_[static_cast<std::size_t>(si)];
    spans +=
        (spans.empty() ? "" : ", ") + format_tdb_seconds(s.start_et) + " to " + format_tdb_seconds(s.end_et);
  }
  throw std::out_of_range(path_ + ": epoch " + format_tdb_seconds(et) + " outside the coverage of body " +
                          body(e.body) + " relative to " + body(e.parent) + ": " + spans);
}

void SpkEphemeris::eval_edge(const Edge& e, double et, bool with_velocity, Vec3& r, Vec3& v) const {
  const Segment* seg = nullptr;
  for (auto it = e.segments.rbegin(); it != e.segments.rend(); ++it) {  // the last one listed wins
    const Segment& s = loaded_[static_cast<std::size_t>(*it)];
    if (et >= s.start_et && et <= s.end_et) {
      seg = &s;
      break;
    }
  }
  if (seg == nullptr) throw_outside(e, et);
  const double k = std::floor((et - seg->init) / seg->intlen);
  const int idx = static_cast<int>(std::clamp(k, 0.0, static_cast<double>(seg->n - 1)));
  const double* rec = seg->data.data() + static_cast<std::size_t>(idx) * static_cast<std::size_t>(seg->rsize);
  const double radius = rec[1];
  const double s = (et - rec[0]) / radius;
  const int nc = seg->ncoef;
  const double* c = rec + 2;
  // Chebyshev values T_k(s) and derivatives T'_k(s) by their three-term recurrences, three
  // components at once; the velocity of a type 3 segment has its own coefficients.
  double t0 = 1.0, t1 = s, d0 = 0.0, d1 = 1.0;
  double px = c[0], py = c[nc], pz = c[2 * nc];
  double vx = 0.0, vy = 0.0, vz = 0.0;
  if (nc > 1) {
    px += c[1] * s;
    py += c[nc + 1] * s;
    pz += c[2 * nc + 1] * s;
    vx = c[1];
    vy = c[nc + 1];
    vz = c[2 * nc + 1];
  }
  for (int j = 2; j < nc; ++j) {
    const double t2 = 2.0 * s * t1 - t0;
    const double d2 = 2.0 * t1 + 2.0 * s * d1 - d0;
    px += c[j] * t2;
    py += c[nc + j] * t2;
    pz += c[2 * nc + j] * t2;
    vx += c[j] * d2;
    vy += c[nc + j] * d2;
    vz += c[2 * nc + j] * d2;
    t0 = t1;
    t1 = t2;
    d0 = d1;
    d1 = d2;
  }
  r = Vec3(px, py, pz);
  if (!with_velocity) return;
  if (seg->type == 2) {
    v = Vec3(vx, vy, vz) / radius;
    return;
  }
  const double* cv = c + 3 * nc;
  double wx = cv[0], wy = cv[nc], wz = cv[2 * nc];
  t0 = 1.0;
  t1 = s;
  if (nc > 1) {
    wx += cv[1] * s;
    wy += cv[nc + 1] * s;
    wz += cv[2 * nc + 1] * s;
  }
  for (int j = 2; j < nc; ++j) {
    const double t2 = 2.0 * s * t1 - t0;
    wx += cv[j] * t2;
    wy += cv[nc + j] * t2;
    wz += cv[2 * nc + j] * t2;
    t0 = t1;
    t1 = t2;
  }
  v = Vec3(wx, wy, wz);
}

Vec3 SpkEphemeris::position(int target, int center, double et) const {
  const Chain& c = chain(target, center);
  Vec3 sum = Vec3::Zero(), r, v;
  for (const auto& [ei, sign] : c.terms) {
    eval_edge(edges_[static_cast<std::size_t>(ei)], et, false, r, v);
    sum += sign * r;
  }
  return sum;
}

void SpkEphemeris::state(int target, int center, double et, Vec3& r, Vec3& v) const {
  const Chain& c = chain(target, center);
  r.setZero();
  v.setZero();
  Vec3 ri, vi;
  for (const auto& [ei, sign] : c.terms) {
    eval_edge(edges_[static_cast<std::size_t>(ei)], et, true, ri, vi);
    r += sign * ri;
    v += sign * vi;
  }
}

}  // namespace satgnc::dynamics
