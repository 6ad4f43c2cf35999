// io::OEM (CCSDS 502.0-B-3 section 5), KVN: the standard's example parses to the printed numbers, a
// trajectory with covariance round-trips bit for bit, malformed files name file, line and keyword.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "ccsds_test_support.hpp"
#include "satgnc/io/oem.hpp"

namespace {
using satgnc::Mat6;
using satgnc::Vec3;
using satgnc::Vec6;
using satgnc::io::Oem;
using satgnc::io::parse_oem;
using satgnc::io::read_oem;
using satgnc::testing::ccsds_data;
using satgnc::testing::expect_format_error;
using satgnc::testing::expect_same_oem;
using satgnc::testing::replace_line;

TEST(Oem, StandardExampleParsesToThePrintedNumbers) {
  const Oem o = read_oem(ccsds_data("oem_mgs.kvn"));
  EXPECT_EQ(o.header.version, "2.0");
  EXPECT_EQ(o.header.originator, "NASA/JPL");
  ASSERT_EQ(o.segments.size(), 2u);
  const auto& s0 = o.segments[0];
  EXPECT_EQ(s0.metadata.object_name, "MARS GLOBAL SURVEYOR");
  EXPECT_EQ(s0.metadata.center_name, "MARS BARYCENTER");
  EXPECT_EQ(s0.metadata.ref_frame, "EME2000");
  EXPECT_EQ(s0.metadata.interpolation, "HERMITE");
  EXPECT_EQ(s0.metadata.interpolation_degree, 7);
  EXPECT_EQ(s0.data_comments.size(), 2u);
  ASSERT_EQ(s0.states.size(), 4u);
  EXPECT_EQ(s0.states[0].epoch, "1996-12-18T12:00:00.331");
  EXPECT_EQ(s0.states[0].state,
            (Vec6() << 2789.619, -280.045, -1746.755, 4.73372, -2.49586, -1.04195).finished());
  EXPECT_FALSE(s0.states[0].acceleration.has_value());
  const auto& s1 = o.segments[1];
  EXPECT_EQ(s1.states[0].state(1), -63.042);  // printed "-063.042"
  EXPECT_EQ(s1.states[3].state(5), 0.88535);
  ASSERT_EQ(s1.covariances.size(), 2u);
  EXPECT_EQ(s1.covariances[0].epoch, "1996-12-28T21:29:07.267");
  EXPECT_EQ(s1.covariances[0].cov_ref_frame, "EME2000");
  const Mat6& c = s1.covariances[0].matrix;
  EXPECT_EQ(c(0, 0), 3.3313494e-04);
  EXPECT_EQ(c(1, 0), 4.6189273e-04);
  EXPECT_EQ(c(0, 1), 4.6189273e-04);  // the lower triangle is mirrored
  EXPECT_EQ(c(5, 5), 6.2244443e-10);
  EXPECT_EQ(c(5, 3), 1.8692631e-10);
  EXPECT_EQ(s1.covariances[1].matrix(2, 2), 3.3420420e-04);
}

TEST(Oem, RoundTripKeepsEveryValue) {
  const Oem a = read_oem(ccsds_data("oem_mgs.kvn"));
  expect_same_oem(parse_oem(satgnc::io::format_oem(a)), a);
  // An estimated trajectory with accelerations, a covariance per point and full-precision numbers.
  Oem t;
  t.header.creation_date = "2026-12-02T12:00:00";
  t.header.originator = "SATGNC";
  satgnc::io::OemSegment s;
  s.metadata.object_name = "LEO-1";
  s.metadata.object_id = "2026-001A";
  s.metadata.center_name = "EARTH";
  s.metadata.ref_frame = "GCRF";
  s.metadata.time_system = satgnc::io::TimeSystem::tt;
  s.metadata.start_time = "2026-12-02T00:00:00";
  s.metadata.stop_time = "2026-12-02T00:02:00";
  for (int i = 0; i < 3; ++i) {
    satgnc::io::OemState st;
    st.epoch = "2026-12-02T00:0" + std::to_string(i) + ":00";
    st.time = satgnc::core::Epoch::parse(st.epoch, satgnc::io::TimeSystem::tt);
    st.state << 6778.137 + i / 3.0, -1.0 / 7.0, 1e-17, 7.6686 * std::sqrt(2.0), -0.0, 1.0 / 3.0;
    st.acceleration = Vec3(-8.0e-3 / 3.0, 1e-9, 3.0e-300);
    s.states.push_back(st);
    satgnc::io::OemCovariance cv;
    cv.epoch = st.epoch;
    cv.time = st.time;
    cv.cov_ref_frame = i == 0 ? "" : "RTN";
    Mat6 L = Mat6::Random();
    cv.matrix = L * L.transpose() * 1e-6;
    cv.matrix = (0.5 * (cv.matrix + cv.matrix.transpose())).eval();
    s.covariances.push_back(cv);
  }
  t.segments.push_back(s);
  const std::string path = ::testing::TempDir() + "satgnc_oem_roundtrip.oem";
  satgnc::io::write_oem(path, t);
  expect_same_oem(read_oem(path), t);
  std::remove(path.c_str());
}

const std::string kBase =
    "CCSDS_OEM_VERS = 2.0\n"                       // 1
    "CREATION_DATE = 2026-01-01T00:00:00\n"        // 2
    "ORIGINATOR = SATGNC\n"                        // 3
    "META_START\n"                                 // 4
    "OBJECT_NAME = SAT\n"                          // 5
    "OBJECT_ID = 2026-001A\n"                      // 6
    "CENTER_NAME = EARTH\n"                        // 7
    "REF_FRAME = GCRF\n"                           // 8
    "TIME_SYSTEM = UTC\n"                          // 9
    "START_TIME = 2026-01-01T00:00:00\n"           // 10
    "STOP_TIME = 2026-01-01T00:01:00\n"            // 11
    "META_STOP\n"                                  // 12
    "2026-01-01T00:00:00 7000 0 0 0 7.5 0\n"       // 13
    "2026-01-01T00:01:00 6999 450 0 -0.5 7.5 0\n"  // 14
    "COVARIANCE_START\n"                           // 15
    "EPOCH = 2026-01-01T00:00:00\n"                // 16
    "1\n"                                          // 17
    "0 1\n"                                        // 18
    "0 0 1\n"                                      // 19
    "0 0 0 1e-6\n"                                 // 20
    "0 0 0 0 1e-6\n"                               // 21
    "0 0 0 0 0 1e-6\n"                             // 22
    "COVARIANCE_STOP\n";                           // 23

TEST(Oem, BadInputNamesFileLineAndKeyword) {
  ASSERT_EQ(parse_oem(kBase).segments[0].covariances.size(), 1u);
  satgnc::testing::expect_bad_lines(
      kBase,
      {
          {9, "TIME_SYSTEM = MET", 9, "TIME_SYSTEM", "unsupported time system 'MET'"},
          {9, "TIME_SYSTEM = UTX", 9, "TIME_SYSTEM", "unknown time system 'UTX'"},
          {8, "", 11, "REF_FRAME", "missing mandatory keyword"},
          {8, "REF_FRAMES = GCRF", 8, "REF_FRAMES", "unknown metadata keyword"},
          {13, "2026-01-01T00:00:00 7000 0 0 0 7.5", 13, "EPHEMERIS", "got 6 fields"},
          {13, "2026-01-01T00:00:00 7000 0 zero 0 7.5 0", 13, "EPHEMERIS", "not a number: 'zero'"},
          {13, "2026-01-01 7000 0 0 0 7.5 0", 13, "EPOCH", "not an epoch"},
          {18, "0 1 2", 18, "COVARIANCE", "row 2 of the lower triangle needs 2 numbers, got 3"},
          {22, "", 22, "COVARIANCE", "has 5 of 6 rows"},
          {23, "", 22, "COVARIANCE_STOP", "missing at the end of the file"},
          {10, "START_TIME = 2026-02-30T00:00:00", 10, "START_TIME", "day out of range"},
      },
      "bad.oem", [](const std::string& text, const std::string& source) { parse_oem(text, source); });
}

TEST(Oem, WriterRefusesAnInvalidModel) {
  Oem o = parse_oem(kBase);
  o.segments[0].states[1].state(2) = std::numeric_limits<double>::infinity();
  try {
    satgnc::io::format_oem(o);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "segments[0].states[1].state: must be finite (no NaN or Inf)");
  }
  o = parse_oem(kBase);
  o.segments[0].covariances[0].matrix(0, 1) = 0.5;  // not symmetric
  EXPECT_THROW(satgnc::io::format_oem(o), std::invalid_argument);
  o = parse_oem(kBase);
  o.segments[0].metadata.object_name.clear();  // mandatory: the written "OBJECT_NAME = " would not read back
  try {
    satgnc::io::format_oem(o);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "oem: not a valid OEM: OBJECT_NAME: empty value (hint: KEYWORD = value)");
  }
}

TEST(Oem, TrajectoryGivenAsEpochsIsWrittenAndReadBack) {
  // A propagated trajectory: instants t0 + 60 k s (no text epochs), across the 2016 leap second.
  using satgnc::core::Epoch;
  using satgnc::io::TimeSystem;
  Oem o = parse_oem(kBase);
  auto& seg = o.segments[0];
  const Epoch t0 = Epoch::parse("2016-12-31T23:58:30", TimeSystem::utc);
  seg.metadata.start_time = "2016-12-31T23:58:30";
  seg.metadata.stop_time = "2017-01-01T00:01:29";
  seg.states.resize(3);
  seg.covariances[0].epoch.clear();
  seg.covariances[0].time = t0;
  for (int k = 0; k < 3; ++k) {
    seg.states[k].epoch.clear();
    seg.states[k].time = t0 + 60.0 * k;
    seg.states[k].state = Vec6::Constant(k + 0.5);
  }
  const std::string text = satgnc::io::format_oem(o);
  // 60 s after 23:58:30 on a leap-second day is 23:59:30; 120 s after is 00:00:29 (23:59:60 in between).
  EXPECT_NE(text.find("2016-12-31T23:59:30 1.5 1.5"), std::string::npos) << text;
  EXPECT_NE(text.find("2017-01-01T00:00:29 2.5 2.5"), std::string::npos) << text;
  const Oem back = parse_oem(text);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(back.segments[0].states[k].time - t0, 60.0 * k);  // s, exact
  EXPECT_EQ(back.segments[0].covariances[0].time, t0);
}

TEST(Oem, MutatedFilesEitherParseOrRaiseFormatError) {
  // Robustness: 1500 one-character mutations of the standard's example; each parses or throws
  // FormatError (no other exception, no crash). Both outcomes must occur (the loop ran).
  const std::string text = satgnc::testing::read_text(ccsds_data("oem_mgs.kvn"));
  const int parsed = satgnc::testing::mutation_runs(
      text, 1500, "mutated", [](const std::string& t) { (void)parse_oem(t, "mutated"); });
  EXPECT_GT(parsed, 150);
  EXPECT_LT(parsed, 1350);
}

}  // namespace
