// frames::EopTable: the finals2000A and EOP 20 C04 readers on the samples cut from astropy-iers-data
// (tests/data/eop), 4-point Lagrange interpolation against the closed-form midpoint rule, UT1 across
// the 2016-12-31 leap second, the out-of-range policies, malformed files, and no allocation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "error_checks.hpp"
#include "malloc_counter.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/frames/eop.hpp"

namespace {
using satgnc::core::Epoch;
using satgnc::core::TimeScale;
using satgnc::frames::EopRow;
using satgnc::frames::EopSource;
using satgnc::frames::EopTable;
using satgnc::frames::EopValues;
using satgnc::frames::OutOfRangePolicy;
using satgnc::testing::message_of;

const std::string kDir = SATGNC_TEST_EOP_DIR;
const std::string kFinals = kDir + "/finals2000A_2016-12.txt";
const std::string kC04 = kDir + "/eopc04_2016-12.txt";

Epoch utc(const char* iso) { return Epoch::parse(iso, TimeScale::utc); }

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(EopTable, ReadsFinals2000aSampleWithBulletinBValues) {
  const EopTable eop = EopTable::read_finals2000a(kFinals);
  ASSERT_EQ(eop.rows().size(), 62u);  // 2016-12-01 .. 2017-01-31
  // Row 2016-12-31 (MJD 57753), Bulletin B columns: x 0.081318", y 0.262990", UT1-UTC -0.4077600 s,
  // dX -0.021 mas, dY -0.048 mas; LOD from Bulletin A 0.8842 ms. Exact: the file's digits.
  const EopRow& r = eop.rows()[30];
  EXPECT_EQ(r.mjd, 57753.0);
  EXPECT_EQ(r.source, EopSource::bulletin_b);
  EXPECT_DOUBLE_EQ(r.xp, 0.081318);
  EXPECT_DOUBLE_EQ(r.yp, 0.262990);
  EXPECT_DOUBLE_EQ(r.ut1_utc, -0.4077600);
  EXPECT_DOUBLE_EQ(r.dx, -0.021e-3);
  EXPECT_DOUBLE_EQ(r.dy, -0.048e-3);
  EXPECT_DOUBLE_EQ(r.lod, 0.8842e-3);
  // At a row's own epoch the interpolant returns the row (Lagrange weights 0/1; 1e-15 rounding).
  const EopValues v = eop.at(utc("2016-12-31T00:00:00"));
  EXPECT_NEAR(v.xp, 0.081318, 1e-15);
  EXPECT_NEAR(v.ut1_utc, -0.4077600, 1e-14);
  EXPECT_NEAR(v.ut1_tai, -0.4077600 - 36.0, 1e-14);
  // read() picks the format from the first data line.
  EXPECT_EQ(EopTable::read(kFinals).rows().size(), 62u);
}

TEST(EopTable, ReadsC04SampleAndAgreesWithFinals) {
  const EopTable c04 = EopTable::read_c04(kC04);
  const EopTable fin = EopTable::read(kFinals);
  ASSERT_EQ(c04.rows().size(), 62u);
  EXPECT_EQ(c04.rows()[0].source, EopSource::c04);
  EXPECT_EQ(EopTable::read(kC04).rows()[0].source, EopSource::c04);
  // 2016-12-01: x 0.129928", UT1-UTC -0.3697110 s, LOD 0.0012228 s, dX 0.000026" (file digits).
  EXPECT_DOUBLE_EQ(c04.rows()[0].xp, 0.129928);
  EXPECT_DOUBLE_EQ(c04.rows()[0].ut1_utc, -0.3697110);
  EXPECT_DOUBLE_EQ(c04.rows()[0].lod, 0.0012228);
  EXPECT_DOUBLE_EQ(c04.rows()[0].dx, 0.000026);
  // Two IERS series of the same days: C04 (ITRF2020) and Bulletin B agree to a fraction of a mas in
  // polar motion and 0.1 ms in UT1 (their published mutual consistency; measured 0.15 mas, 0.02 ms).
  for (const char* t : {"2016-12-05T06:00:00", "2017-01-20T18:30:00"}) {
    const EopValues a = c04.at(utc(t)), b = fin.at(utc(t));
    EXPECT_LT(std::fabs(a.xp - b.xp), 0.5e-3) << t;
    EXPECT_LT(std::fabs(a.yp - b.yp), 0.5e-3) << t;
    EXPECT_LT(std::fabs(a.ut1_utc - b.ut1_utc), 1e-4) << t;
  }
}

// Equally spaced nodes: the 4-point Lagrange value at the middle of the central interval is
// (-f0 + 9 f1 + 9 f2 - f3) / 16, an independent closed form.
TEST(EopTable, FourPointLagrangeMatchesMidpointRule) {
  const EopTable eop = EopTable::read(kFinals);
  const auto& R = eop.rows();
  const std::size_t i = 9;  // 2016-12-10 .. 12-11, far from the leap second
  const EopValues v = eop.at(utc("2016-12-10T12:00:00"));
  auto mid = [&](double EopRow::* f) {
    return (-(R[i - 1].*f) + 9.0 * (R[i].*f) + 9.0 * (R[i + 1].*f) - (R[i + 2].*f)) / 16.0;
  };
  EXPECT_NEAR(v.xp, mid(&EopRow::xp), 1e-15);  // a few ulps of 0.1"
  EXPECT_NEAR(v.yp, mid(&EopRow::yp), 1e-15);
  EXPECT_NEAR(v.ut1_utc, mid(&EopRow::ut1_utc), 1e-14);  // via UT1-TAI (~36 s): ulps of 36
  EXPECT_NEAR(v.lod, mid(&EopRow::lod), 1e-17);
  // First interval: linear.
  const EopValues w = eop.at(utc("2016-12-01T06:00:00"));
  EXPECT_NEAR(w.xp, 0.75 * R[0].xp + 0.25 * R[1].xp, 1e-15);
}

// UT1-UTC jumps by +1 s at the leap second; UT1-TAI is continuous across it.
TEST(EopTable, Ut1AcrossTheLeapSecond) {
  const EopTable eop = EopTable::read(kFinals);
  const Epoch before = utc("2016-12-31T23:59:59.5");
  const Epoch after = utc("2017-01-01T00:00:00.5");
  const EopValues a = eop.at(before), b = eop.at(after);
  EXPECT_NEAR(b.ut1_utc - a.ut1_utc, 1.0, 1e-5);  // 2 s of UT1 drift at ~1 ms/day: 2.3e-8 s, plus the leap
  EXPECT_NEAR(b.ut1_tai - a.ut1_tai, 0.0, 1e-6);  // continuous (drift over 2 s: < 1e-7 s)
  // Mid-day before the leap: UT1-UTC near the mean of the neighbours' UT1-TAI (-36.40776, -36.40870)
  // + 36 s, not the mean of -0.40776 and +0.59130 that interpolating UT1-UTC would give.
  EXPECT_NEAR(eop.at(utc("2016-12-31T12:00:00")).ut1_utc, -0.40823, 2e-5);
  // UT1 as a Julian date: UT1 = UTC + (UT1-UTC).
  const auto j = eop.ut1_jd(utc("2016-12-15T00:00:00"));
  EXPECT_NEAR((j.jd1 - 2457737.5 + j.jd2) * 86400.0, eop.ut1_minus_utc(utc("2016-12-15T00:00:00")), 2e-6);
}

// at() takes TAI-UTC from the row's day (consecutive rows) or looks it up (a gap of days): both must
// equal Epoch::tai_minus_utc() exactly, across the leap second.
TEST(EopTable, Ut1MinusUtcUsesTheEpochsTaiMinusUtc) {
  const EopTable eop = EopTable::read(kFinals);
  std::vector<EopRow> sparse;
  for (std::size_t k = 0; k < eop.rows().size(); k += 3) sparse.push_back(eop.rows()[k]);  // every 3rd day
  const EopTable gaps(sparse);
  const Epoch e0 = utc("2016-12-05T00:00:00");
  for (int k = 0; k < 400; ++k) {
    const Epoch e = e0 + 10007.3 * k;  // 46 days in steps that visit every time of day
    if (!gaps.covers(e)) continue;
    const EopValues a = eop.at(e), b = gaps.at(e);
    EXPECT_EQ(a.ut1_utc - a.ut1_tai, e.tai_minus_utc()) << k;  // integer seconds: exact
    EXPECT_EQ(b.ut1_utc - b.ut1_tai, e.tai_minus_utc()) << k;
    EXPECT_NEAR(a.ut1_tai, b.ut1_tai, 2e-4) << k;  // cubic through every 3rd day: < 0.2 ms of UT1
  }
}

TEST(EopTable, OutOfRangePolicies) {
  const EopTable eop = EopTable::read(kFinals);
  const Epoch late = utc("2017-02-15T00:00:00");
  const std::string m = message_of([&] { eop.at(late); });
  EXPECT_NE(m.find("epoch: 2017-02-15T00:00:00.000 UTC is outside the EOP table"), std::string::npos) << m;
  EXPECT_NE(m.find("MJD 57723 .. 57784 = 2016-12-01 .. 2017-01-31 UTC"), std::string::npos) << m;
  EXPECT_FALSE(eop.covers(late));
  EXPECT_TRUE(eop.covers(utc("2017-01-31T00:00:00")));
  const EopValues h = eop.with_policy(OutOfRangePolicy::hold_last).at(late);
  EXPECT_EQ(h.xp, eop.rows().back().xp);
  EXPECT_EQ(h.ut1_utc, eop.rows().back().ut1_utc);
  const EopValues z = eop.with_policy(OutOfRangePolicy::zero).at(late);
  EXPECT_EQ(z.xp, 0.0);
  EXPECT_EQ(z.ut1_utc, 0.0);
  EXPECT_EQ(z.ut1_tai, -37.0);
  EXPECT_EQ(satgnc::frames::out_of_range_policy_from_name("hold_last"), OutOfRangePolicy::hold_last);
  EXPECT_EQ(message_of([] { satgnc::frames::out_of_range_policy_from_name("clamp"); }),
            "policy: unknown out-of-range policy 'clamp' (choices: error, hold_last, zero)");
}

TEST(EopTable, MalformedFilesNameTheFileAndLine) {
  std::ifstream in(kFinals);
  std::string header, l1, l2;
  std::getline(in, header);
  std::getline(in, l1);
  std::getline(in, l2);
  std::string bad = l2;
  bad.replace(7, 8, "57724.x0");
  const std::string p1 = write_temp("bad_finals.txt", header + "\n" + l1 + "\n" + bad + "\n");
  EXPECT_EQ(message_of([&] { EopTable::read_finals2000a(p1); }),
            p1 + ":3: columns 8-15 (MJD): '57724.x0' is not a number");
  const std::string p2 = write_temp("unordered_finals.txt", l2 + "\n" + l1 + "\n");
  EXPECT_NE(message_of([&] { EopTable::read_finals2000a(p2); }).find(p2 + ":2: MJD 57723"),
            std::string::npos);
  const std::string p3 = write_temp("short_c04.txt", "# c\n2016  12   1   0  57723.00    0.129928\n");
  EXPECT_EQ(message_of([&] { EopTable::read_c04(p3); }),
            p3 + ":2: expected at least 13 columns (YR MM DD HH MJD x y UT1-UTC dX dY xrt yrt LOD), got 6");
  const std::string p4 =
      write_temp("c04_14.txt",
                 "1962   1   1  37665  -0.012700   0.213000   0.0326338   0.0017230   0.000000   "
                 "0.000000   0.030000   0.030000  0.0020000  0.0014000    0.004774    0.002000\n");
  EXPECT_NE(
      message_of([&] { EopTable::read_c04(p4); }).find(p4 + ":1: column HH: 37665.000000 is not an hour"),
      std::string::npos);
  EXPECT_NE(message_of([] { EopTable::read("/nonexistent/finals.all"); }).find("path: cannot open EOP file"),
            std::string::npos);
  EXPECT_THROW(EopTable(std::vector<EopRow>(1)), std::invalid_argument);
}

// Bench item of issue 13: EOP interpolation allocates nothing.
TEST(EopTable, InterpolationAllocatesNothing) {
  const EopTable eop = EopTable::read(kFinals);
  const Epoch e0 = utc("2016-12-03T00:00:00");
  double sum = 0.0;
  g_mallocs = 0;
  g_count = true;
  {
    SATGNC_NO_MALLOC_SCOPE;
    for (int k = 0; k < 1000; ++k) {
      const Epoch e = e0 + 4000.0 * k;  // 46 days, across the leap second
      const EopValues v = eop.at(e);
      sum += v.xp + v.ut1_utc + eop.ut1_jd(e).jd2;
    }
  }
  g_count = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_TRUE(std::isfinite(sum));
}

}  // namespace
