// SPK reader: synthetic DAF files written here with known polynomial motions (exact in Chebyshev
// form, so the reference is the polynomial itself), the chains, the errors at open and at evaluation,
// no allocation per evaluation, and the ForceModel hook. The DE421 cross-check against jplephem is in
// tests/python/test_ephemeris_spk.py.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "malloc_counter.hpp"
#include "satgnc/dynamics/ephemeris_spk.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/dynamics/force_model_config.hpp"
#include "satgnc/dynamics/third_body.hpp"

namespace dy = satgnc::dynamics;
using satgnc::Vec3;

namespace {

// A cubic motion x_i(t) = a_i + b_i t + c_i t^2 + d_i t^3 per axis, t in units of 1e8 s (the
// files span [-1e8, 1e8] s, so |t| <= 1).
struct Cubic {
  std::array<std::array<double, 4>, 3> k{};
  Vec3 pos(double et) const {
    const double t = et * 1e-8;
    Vec3 p;
    for (int i = 0; i < 3; ++i) p[i] = k[i][0] + t * (k[i][1] + t * (k[i][2] + t * k[i][3]));
    return p;
  }
  Vec3 vel(double et) const {  // km/s
    const double t = et * 1e-8;
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = (k[i][1] + t * (2 * k[i][2] + t * 3 * k[i][3])) * 1e-8;
    return v;
  }
};

// Chebyshev coefficients (degree 3, padded with zeros to ncoef) of one axis of a cubic on
// [mid - radius, mid + radius]: x(mid + radius s) = p0 + p1 s + p2 s^2 + p3 s^3, with s^2 = (T0 + T2)/2,
// s^3 = (3 T1 + T3)/4.
std::vector<double> cheb_axis(const std::array<double, 4>& k, double mid, double radius, int ncoef,
                              bool derivative) {
  const double m = mid * 1e-8, r = radius * 1e-8;
  std::array<double, 4> p{};  // power series in s
  if (!derivative) {
    p[0] = k[0] + m * (k[1] + m * (k[2] + m * k[3]));
    p[1] = r * (k[1] + 2 * k[2] * m + 3 * k[3] * m * m);
    p[2] = r * r * (k[2] + 3 * k[3] * m);
    p[3] = r * r * r * k[3];
  } else {  // velocity km/s: 1e-8 (k1 + 2 k2 t + 3 k3 t^2)
    p[0] = 1e-8 * (k[1] + 2 * k[2] * m + 3 * k[3] * m * m);
    p[1] = 1e-8 * r * (2 * k[2] + 6 * k[3] * m);
    p[2] = 1e-8 * r * r * 3 * k[3];
  }
  std::vector<double> c(static_cast<std::size_t>(ncoef), 0.0);
  c[0] = p[0] + p[2] / 2;
  c[1] = p[1] + 3 * p[3] / 4;
  c[2] = p[2] / 2;
  c[3] = p[3] / 4;
  return c;
}

struct SegSpec {
  int target, center, type;
  Cubic motion;
  double start, end;  // coverage, s
  int records;
  int ncoef = 6;
  int frame = 1;
};

void put_i32(std::vector<char>& b, std::size_t at, std::int32_t v) { std::memcpy(b.data() + at, &v, 4); }
void put_f64(std::vector<char>& b, std::size_t at, double v) { std::memcpy(b.data() + at, &v, 8); }
void put_str(std::vector<char>& b, std::size_t at, const std::string& s) {
  std::memcpy(b.data() + at, s.data(), s.size());
}

// One summary record (2), its name record (3), data from record 4 on.
std::string write_spk(const std::string& name, const std::vector<SegSpec>& segs,
                      const std::string& fmt = "LTL-IEEE", const std::string& idword = "DAF/SPK ") {
  std::vector<double> words;
  std::vector<std::pair<int, int>> addr;
  const int base = 3 * 128 + 1;
  for (const SegSpec& s : segs) {
    const int begin = base + static_cast<int>(words.size());
    const double intlen = (s.end - s.start) / s.records;
    const int comps = s.type == 3 ? 6 : 3;
    for (int r = 0; r < s.records; ++r) {
      const double mid = s.start + (r + 0.5) * intlen, radius = intlen / 2;
      words.push_back(mid);
      words.push_back(radius);
      for (int c = 0; c < comps; ++c) {
        const auto co = cheb_axis(s.motion.k[static_cast<std::size_t>(c % 3)], mid, radius, s.ncoef, c >= 3);
        words.insert(words.end(), co.begin(), co.end());
      }
    }
    words.push_back(s.start);
    words.push_back(intlen);
    words.push_back(2 + comps * s.ncoef);
    words.push_back(s.records);
    addr.emplace_back(begin, base + static_cast<int>(words.size()) - 1);
  }
  std::vector<char> b(3 * 1024 + words.size() * 8, '\0');
  put_str(b, 0, idword);
  put_i32(b, 8, 2);
  put_i32(b, 12, 6);
  put_str(b, 16, std::string(60, ' '));
  put_str(b, 16, "satgnc test");
  put_i32(b, 76, 2);
  put_i32(b, 80, 2);
  put_i32(b, 84, base + static_cast<int>(words.size()));
  put_str(b, 88, fmt);
  std::memcpy(b.data() + 699, "FTPSTR:\r:\n:\r\n:\r\x00:\x81:\x10\xce:ENDFTP", 28);
  put_f64(b, 1024, 0.0);
  put_f64(b, 1024 + 8, 0.0);
  put_f64(b, 1024 + 16, static_cast<double>(segs.size()));
  for (std::size_t k = 0; k < segs.size(); ++k) {
    const std::size_t at = 1024 + 24 + 40 * k;
    put_f64(b, at, segs[k].start);
    put_f64(b, at + 8, segs[k].end);
    put_i32(b, at + 16, segs[k].target);
    put_i32(b, at + 20, segs[k].center);
    put_i32(b, at + 24, segs[k].frame);
    put_i32(b, at + 28, segs[k].type);
    put_i32(b, at + 32, addr[k].first);
    put_i32(b, at + 36, addr[k].second);
    put_str(b, 2048 + 40 * k, std::string(40, ' '));
    put_str(b, 2048 + 40 * k, "SEG " + std::to_string(segs[k].target));
  }
  std::memcpy(b.data() + 3 * 1024, words.data(), words.size() * 8);
  const std::string path =
      (std::filesystem::temp_directory_path() / ("satgnc_spk_" + name + ".bsp")).string();
  std::ofstream(path, std::ios::binary).write(b.data(), static_cast<std::streamsize>(b.size()));
  return path;
}

Cubic random_cubic(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Cubic c;
  for (auto& axis : c.k) {
    axis = {scale * u(rng), scale * 0.3 * u(rng), scale * 0.1 * u(rng), scale * 0.05 * u(rng)};
  }
  return c;
}

// A DE-shaped file: SSB->Sun, SSB->EMB, EMB->Moon (type 3), EMB->Earth over [-1e8, 1e8] s.
struct DeLike {
  Cubic sun, emb, moon, earth;
  std::string path;
};

DeLike de_like(const std::string& name, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  DeLike d;
  d.sun = random_cubic(rng, 1e6);
  d.emb = random_cubic(rng, 1.5e8);
  d.moon = random_cubic(rng, 4e5);
  d.earth = random_cubic(rng, 5e3);
  d.path = write_spk(name, {{10, 0, 2, d.sun, -1e8, 1e8, 50, 11},
                            {3, 0, 2, d.emb, -1e8, 1e8, 40, 13},
                            {301, 3, 3, d.moon, -1e8, 1e8, 80, 7},
                            {399, 3, 2, d.earth, -1e8, 1e8, 80, 13}});
  return d;
}

std::string expect_open_error(const std::string& path, const std::vector<std::pair<int, int>>& pairs =
                                                           dy::SpkEphemeris::geocentric_sun_moon()) {
  try {
    dy::SpkEphemeris e(path, pairs);
  } catch (const std::invalid_argument& ex) {
    return ex.what();
  }
  ADD_FAILURE() << "no error for " << path;
  return "";
}

}  // namespace

TEST(SpkEphemeris, ReadsDescriptorsAndNames) {
  const DeLike d = de_like("names", 1);
  const dy::SpkEphemeris e(d.path);
  ASSERT_EQ(e.segments().size(), 4u);
  EXPECT_EQ(e.internal_name(), "satgnc test");
  EXPECT_EQ(e.segments()[2].target, 301);
  EXPECT_EQ(e.segments()[2].center, 3);
  EXPECT_EQ(e.segments()[2].type, 3);
  EXPECT_EQ(e.segments()[2].name, "SEG 301");
  EXPECT_EQ(e.start_et(), -1e8);
  EXPECT_EQ(e.end_et(), 1e8);
}

// Seeded epochs: chained positions and velocities against the polynomials (exact in Chebyshev form,
// so only rounding separates them: 1e-12 relative to the largest term of the chain).
TEST(SpkEphemeris, ChainsMatchAnalyticMotionSeeded) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const DeLike d = de_like("chain" + std::to_string(seed), seed);
    const dy::SpkEphemeris e(d.path, {{10, 399}, {301, 399}, {399, 3}, {10, 0}, {0, 301}});
    std::mt19937_64 rng(seed + 100);
    std::uniform_real_distribution<double> u(-1e8, 1e8);
    for (int i = 0; i < 200; ++i) {
      const double et = i == 0 ? 1e8 : (i == 1 ? -1e8 : u(rng));  // both ends included
      const Vec3 sun = d.sun.pos(et) - d.emb.pos(et) - d.earth.pos(et);
      const Vec3 moon = d.moon.pos(et) - d.earth.pos(et);
      Vec3 r, v;
      e.state(10, 399, et, r, v);
      EXPECT_EQ(e.position(10, 399, et), r);  // same arithmetic with or without the velocity
      EXPECT_LT((r - sun).norm(), 1e-12 * 3e8) << "seed " << seed << " et " << et;  // |emb| reaches ~3e8 km
      EXPECT_LT((v - (d.sun.vel(et) - d.emb.vel(et) - d.earth.vel(et))).norm(), 1e-12 * 1e3);
      e.state(301, 399, et, r, v);
      EXPECT_LT((r - moon).norm(), 1e-12 * 1e6);
      EXPECT_LT((v - (d.moon.vel(et) - d.earth.vel(et))).norm(), 1e-12 * 10);  // type 3 velocity
      EXPECT_LT((e.position(399, 3, et) - d.earth.pos(et)).norm(), 1e-12 * 1e4);
      EXPECT_LT((e.position(0, 301, et) + d.emb.pos(et) + d.moon.pos(et)).norm(), 1e-12 * 3e8);
    }
  }
}

// Two segments for one body: the later one in the file wins where both cover the epoch, and the
// span is their union.
TEST(SpkEphemeris, LaterSegmentTakesPrecedence) {
  std::mt19937_64 rng(7);
  const Cubic a = random_cubic(rng, 1e5), b = random_cubic(rng, 1e5);
  const std::string path =
      write_spk("two", {{301, 399, 2, a, -1e7, 2e7, 10}, {301, 399, 2, b, 0.0, 3e7, 10}});
  const dy::SpkEphemeris e(path, {{301, 399}});
  EXPECT_EQ(e.start_et(), -1e7);
  EXPECT_EQ(e.end_et(), 3e7);
  EXPECT_LT((e.position(301, 399, -5e6) - a.pos(-5e6)).norm(), 1e-7);
  EXPECT_LT((e.position(301, 399, 1e7) - b.pos(1e7)).norm(), 1e-7);
  EXPECT_LT((e.position(301, 399, 2.5e7) - b.pos(2.5e7)).norm(), 1e-7);
}

TEST(SpkEphemeris, EpochOutsideCoverageNamesEpochAndCoverage) {
  const DeLike d = de_like("outside", 2);
  const dy::SpkEphemeris e(d.path);
  try {
    (void)e.position(301, 399, 1e8 + 1.0);
    FAIL() << "no error";
  } catch (const std::out_of_range& ex) {
    const std::string m = ex.what();
    EXPECT_NE(m.find(d.path), std::string::npos) << m;
    EXPECT_NE(m.find("epoch 2003-03-03T21:46:41.000 TDB"), std::string::npos) << m;  // J2000 + 1e8 + 1 s
    EXPECT_NE(m.find("to 2003-03-03T21:46:40.000 TDB"), std::string::npos) << m;
    EXPECT_NE(m.find("1996-10-31T02:13:20.000 TDB"), std::string::npos) << m;  // J2000 - 1e8 s
  }
  EXPECT_THROW((void)e.position(301, 399, std::nan("")), std::out_of_range);
  EXPECT_THROW((void)e.position(10, 301, 0.0), std::invalid_argument);  // pair not prepared
}

TEST(SpkEphemeris, BadFilesNameFileAndProblem) {
  const std::string dir = std::filesystem::temp_directory_path().string();
  const std::string text = dir + "/satgnc_spk_text.bsp";
  std::ofstream(text) << std::string(2000, 'x');
  EXPECT_NE(expect_open_error(text).find(text + ": not a DAF file (ID word 'xxxxxxxx'"), std::string::npos);
  const std::string tiny = dir + "/satgnc_spk_tiny.bsp";
  std::ofstream(tiny) << "DAF/SPK ";
  EXPECT_NE(expect_open_error(tiny).find("shorter than one 1024-byte record"), std::string::npos);
  EXPECT_NE(expect_open_error(dir + "/satgnc_no_such.bsp").find("cannot open the file"), std::string::npos);

  std::mt19937_64 rng(3);
  const Cubic c = random_cubic(rng, 1e5);
  const std::vector<SegSpec> ok{{10, 399, 2, c, 0, 1e6, 4}, {301, 399, 2, c, 0, 1e6, 4}};
  EXPECT_NE(
      expect_open_error(write_spk("big", ok, "BIG-IEEE")).find("wrong endianness: the file is BIG-IEEE"),
      std::string::npos);
  EXPECT_NE(
      expect_open_error(write_spk("ck", ok, "LTL-IEEE", "DAF/CK  ")).find("a DAF of type 'CK', not an SPK"),
      std::string::npos);
  EXPECT_NE(expect_open_error(write_spk("vax", ok, "VAX-GFLT")).find("unknown binary format 'VAX-GFLT'"),
            std::string::npos);
  const std::string t13 = write_spk("t13", {{10, 399, 13, c, 0, 1e6, 4}, {301, 399, 2, c, 0, 1e6, 4}});
  EXPECT_NE(expect_open_error(t13).find(
                "segment 'SEG 10' (target 10 (Sun), center 399 (Earth)): unsupported SPK type 13"),
            std::string::npos);
  // A type-13 segment off the requested chains is listed but not read.
  EXPECT_NO_THROW(dy::SpkEphemeris(t13, {{301, 399}}));
  SegSpec eclip{10, 399, 2, c, 0, 1e6, 4};
  eclip.frame = 17;
  EXPECT_NE(expect_open_error(write_spk("frame", {eclip, ok[1]})).find("frame code 17"), std::string::npos);
  EXPECT_NE(expect_open_error(write_spk("nomoon", {ok[0]}))
                .find("no chain of segments links target 301 (Moon) to center 399 (Earth)"),
            std::string::npos);
  const std::string disjoint =
      write_spk("disjoint", {{10, 399, 2, c, 0, 1e6, 4}, {301, 399, 2, c, 2e6, 3e6, 4}});
  EXPECT_NE(expect_open_error(disjoint).find("do not overlap in time"), std::string::npos);

  // Truncated data: an end address beyond the file.
  const std::string good = write_spk("trunc", ok);
  std::filesystem::resize_file(good, std::filesystem::file_size(good) - 64);
  EXPECT_NE(expect_open_error(good).find("outside the file's"), std::string::npos);
  // A text-mode transfer: CR LF rewritten in the FTP string.
  const std::string ftp = write_spk("ftp", ok);
  {
    std::fstream f(ftp, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(699 + 8);
    f.put('\n');
  }
  EXPECT_NE(expect_open_error(ftp).find("text-mode (ASCII) transfer"), std::string::npos);
  // A directory whose RSIZE does not divide the data.
  const std::string dir_bad = write_spk("rsize", ok);
  {
    std::fstream f(dir_bad, std::ios::in | std::ios::out | std::ios::binary);
    const double rsize = 99.0;
    const auto size = static_cast<std::streamoff>(std::filesystem::file_size(dir_bad));
    f.seekp(size - 16);  // RSIZE of the last segment
    f.write(reinterpret_cast<const char*>(&rsize), 8);
  }
  EXPECT_NE(expect_open_error(dir_bad, {{301, 399}}).find("inconsistent type 2 directory"),
            std::string::npos);
}

TEST(SpkEphemeris, EvaluationAllocatesNothing) {
  const DeLike d = de_like("malloc", 4);
  const dy::SpkEphemeris e(d.path);
  dy::EphemerisInterpolator eph(std::make_shared<const dy::SpkEphemeris>(d.path));
  Vec3 r, v, acc = Vec3::Zero();
  g_mallocs = 0;
  g_count = true;
  for (int i = 0; i < 100; ++i) {
    e.state(10, 399, i * 1e5, r, v);
    acc += r + v + e.position(301, 399, -i * 1e5);
    acc += eph.sun(2451545.0, i * 0.3) + eph.moon(2451545.0, i * 0.3);
  }
  g_count = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_TRUE(acc.allFinite());
}

// TT -> TDB: ERFA's eraDtdb at the geocentre, and its interpolation on 1/8-day nodes within 1e-9 s.
TEST(SpkEphemeris, TtToTdb) {
  // 2006-01-15T21:24:37.5 TT: eraDtdb's own documentation example is topocentric; at the geocentre
  // TDB - TT is the annual term ~ +1.66e-3 sin(g), g ~ 10.8 deg in mid-January: ~ -0.3 ms ... checked
  // against eraDtdb directly here (the independent check is the DE421 / jplephem test in Python).
  const double et = dy::SpkEphemeris::tdb_seconds_from_tt(2453736.0, 0.3921);
  EXPECT_NEAR(et - ((2453736.0 - 2451545.0) + 0.3921) * 86400.0, 0.0, 1.7e-3);  // |TDB - TT| < 1.7 ms
  const DeLike d = de_like("tdb", 5);
  const dy::EphemerisInterpolator eph(std::make_shared<const dy::SpkEphemeris>(d.path));
  std::mt19937_64 rng(11);
  // +-10 days (80 node intervals): et < 8.7e5 s, whose rounding (1.2e-10 s) stays below the bound.
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  double worst = 0.0;
  for (int i = 0; i < 500; ++i) {
    const double days = u(rng);
    worst = std::max(worst, std::abs(eph.tdb_seconds(2451545.0, days) -
                                     dy::SpkEphemeris::tdb_seconds_from_tt(2451545.0, days)));
  }
  EXPECT_LT(worst, 1e-9);  // linear interpolation of TDB - TT on 3-hour nodes
}

TEST(SpkEphemeris, ForceModelUsesTheFileSunAndMoon) {
  const DeLike d = de_like("fm", 6);
  auto spk = std::make_shared<const dy::SpkEphemeris>(d.path);
  dy::ForceModel fm;
  fm.third_body = dy::ThirdBodies{};
  fm.epoch_jd1 = 2451545.0;
  fm.epoch_jd2 = 100.0;
  fm.ephemeris = dy::EphemerisInterpolator(spk);
  fm.validate();
  const Vec3 r(7000.0, 100.0, -300.0), v(0.0, 7.5, 0.1);
  const double t = 1234.5;
  const double et = fm.ephemeris.tdb_seconds(fm.epoch_jd1, fm.epoch_jd2 + t / 86400.0);
  const Vec3 expect = dy::third_body_acceleration(fm.third_body->mu_sun, spk->position(10, 399, et), r) +
                      dy::third_body_acceleration(fm.third_body->mu_moon, spk->position(301, 399, et), r);
  const Vec3 got = fm.acceleration(t, r, v) - dy::point_mass_acceleration(fm.mu, r);
  // got is the total minus the point mass (|a| ~ 8e-3 km/s^2): its rounding, 1e-15 of that, bounds it.
  EXPECT_LT((got - expect).norm(), 1e-15 * dy::point_mass_acceleration(fm.mu, r).norm());
  // The epoch outside the file: validate() names it and the coverage.
  fm.epoch_jd2 = 5000.0;
  try {
    fm.validate();
    FAIL() << "no error";
  } catch (const std::invalid_argument& ex) {
    EXPECT_NE(std::string(ex.what()).find("outside " + d.path + "'s coverage"), std::string::npos)
        << ex.what();
  }
  EXPECT_THROW(dy::EphemerisInterpolator(std::shared_ptr<const dy::SpkEphemeris>()), std::invalid_argument);
  EXPECT_THROW(dy::EphemerisInterpolator(std::make_shared<const dy::SpkEphemeris>(
                   d.path, std::vector<std::pair<int, int>>{{301, 399}})),
               std::invalid_argument);
}

// The force-model TOML names the file (relative to the TOML's folder); errors carry file and line.
TEST(SpkEphemeris, TomlEphemerisKey) {
  const DeLike d = de_like("toml", 8);  // covers J2000 -+ 1157 days
  const std::filesystem::path p(d.path);
  const std::string dir = p.parent_path().string(), name = p.filename().string();
  const dy::ForceModelConfig cfg = dy::parse_force_model_config(
      "[epoch]\ntime = \"2001-01-01T00:00:00\"\nscale = \"tt\"\n[third_body]\nephemeris = \"" + name + "\"\n",
      "fm.toml", dir);
  EXPECT_EQ(cfg.ephemeris_file, dir + "/" + name);
  ASSERT_NE(cfg.model.ephemeris.spk(), nullptr);
  EXPECT_EQ(cfg.model.ephemeris.spk()->path(), dir + "/" + name);
  auto error = [&](const std::string& text) {
    try {
      (void)dy::parse_force_model_config(text, "fm.toml", dir);
    } catch (const dy::ForceModelConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("[third_body]\nephemeris = \"nope.bsp\"\n")
                .find("fm.toml:2: [third_body] ephemeris: " + dir + "/nope.bsp: cannot open the file"),
            std::string::npos);
  const std::string late =
      error("[epoch]\ntime = \"2010-01-01T00:00:00\"\n[third_body]\nephemeris = \"" + name + "\"\n");
  EXPECT_NE(late.find("fm.toml:4: [third_body] ephemeris: the epoch 2010-01-01T00:01:06.18"),
            std::string::npos)
      << late;
  EXPECT_NE(late.find("coverage 1996-10-31T02:13:20.000 TDB"), std::string::npos) << late;
  EXPECT_NE(error("[third_body]\nephemeris = \"\"\n").find("must be \"erfa\" or the path"),
            std::string::npos);
  EXPECT_NE(error("[third_body]\nephemerides = \"x\"\n").find("unknown key"), std::string::npos);
}
