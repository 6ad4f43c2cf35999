// io::TDM (CCSDS 503.0-B-2), KVN and XML: the standard's examples parse to the printed numbers, write ->
// read round trips keep every value bit for bit, and every malformed input names file, line and keyword.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "ccsds_test_support.hpp"
#include "satgnc/io/tdm.hpp"

namespace {
using satgnc::io::FormatError;
using satgnc::io::parse_tdm;
using satgnc::io::read_tdm;
using satgnc::io::Tdm;
using satgnc::io::TdmObservation;
using satgnc::io::TimeSystem;
using satgnc::testing::ccsds_data;
using satgnc::testing::expect_format_error;
using satgnc::testing::replace_line;

// Values are compared with ==: the reader converts with std::from_chars (correctly rounded), as the
// compiler converts the literal below, so the same decimal text gives the same double (tolerance 0).
void expect_same(const Tdm& a, const Tdm& b, bool same_version = true) {
  satgnc::testing::expect_same_header(a.header, b.header, same_version);
  ASSERT_EQ(a.segments.size(), b.segments.size());
  for (std::size_t s = 0; s < a.segments.size(); ++s) {
    const auto& ma = a.segments[s].metadata;
    const auto& mb = b.segments[s].metadata;
    EXPECT_EQ(ma.comments, mb.comments);
    EXPECT_EQ(ma.time_system, mb.time_system);
    EXPECT_EQ(ma.participants, mb.participants);
    EXPECT_EQ(ma.mode, mb.mode);
    EXPECT_EQ(ma.path, mb.path);
    EXPECT_EQ(ma.start_time, mb.start_time);
    EXPECT_EQ(ma.stop_time, mb.stop_time);
    EXPECT_EQ(ma.integration_interval, mb.integration_interval);
    EXPECT_EQ(ma.integration_ref, mb.integration_ref);
    EXPECT_EQ(ma.range_units, mb.range_units);
    EXPECT_EQ(ma.angle_type, mb.angle_type);
    EXPECT_EQ(ma.other, mb.other);
    EXPECT_EQ(a.segments[s].data_comments, b.segments[s].data_comments);
    ASSERT_EQ(a.segments[s].observations.size(), b.segments[s].observations.size());
    for (std::size_t i = 0; i < a.segments[s].observations.size(); ++i) {
      const TdmObservation& oa = a.segments[s].observations[i];
      const TdmObservation& ob = b.segments[s].observations[i];
      EXPECT_EQ(oa.keyword, ob.keyword);
      EXPECT_EQ(oa.epoch, ob.epoch);
      EXPECT_EQ(oa.value, ob.value) << oa.keyword << " at " << oa.epoch;  // bit-identical
      EXPECT_EQ(oa.unit, ob.unit);
      EXPECT_EQ(oa.time, ob.time) << oa.epoch;
    }
  }
}

TEST(Tdm, JaxaExampleKvnParsesToThePrintedNumbers) {
  const Tdm t = read_tdm(ccsds_data("tdm_jaxa.kvn"));
  EXPECT_EQ(t.header.version, "1.0");
  EXPECT_EQ(t.header.originator, "JAXA");
  EXPECT_EQ(t.header.creation_date, "1998-06-10T01:00:00");
  ASSERT_EQ(t.segments.size(), 1u);
  const auto& m = t.segments[0].metadata;
  EXPECT_EQ(m.time_system, TimeSystem::utc);
  EXPECT_EQ(m.participants, (std::vector<std::string>{"NORTH", "F07R07", "E7"}));
  EXPECT_EQ(m.mode, "SEQUENTIAL");
  EXPECT_EQ(m.path, (std::vector<int>{1, 2, 3, 2, 1}));
  EXPECT_EQ(m.range_units, "km");
  EXPECT_EQ(m.angle_type, "AZEL");
  ASSERT_TRUE(m.integration_interval.has_value());
  EXPECT_EQ(*m.integration_interval, 1.0);
  EXPECT_EQ(m.integration_ref, "MIDDLE");
  EXPECT_EQ(m.start_time, "1998-06-10T00:57:37");
  EXPECT_EQ(m.stop_time, "1998-06-10T00:57:44");
  // Corrections are kept as read, in file order.
  ASSERT_EQ(m.other.size(), 4u);
  EXPECT_EQ(m.other[2], (satgnc::io::KeyValue{"CORRECTION_RANGE", "2.0"}));
  EXPECT_EQ(m.other[3], (satgnc::io::KeyValue{"CORRECTIONS_APPLIED", "YES"}));
  EXPECT_EQ(m.comments, (std::vector<std::string>{"This is a meta-data comment"}));
  const auto& obs = t.segments[0].observations;
  ASSERT_EQ(obs.size(), 20u);  // 4 epochs x (RANGE, ANGLE_1, ANGLE_2, TRANSMIT_FREQ_1, RECEIVE_FREQ)
  EXPECT_EQ(obs[0].keyword, "RANGE");
  EXPECT_EQ(obs[0].epoch, "1998-06-10T00:57:37");
  EXPECT_EQ(obs[0].value, 80452.7542);
  EXPECT_EQ(obs[0].unit, "km");
  EXPECT_EQ(obs[1].keyword, "ANGLE_1");
  EXPECT_EQ(obs[1].value, 256.64002393);
  EXPECT_EQ(obs[1].unit, "deg");
  EXPECT_EQ(obs[2].value, 13.38100016);
  EXPECT_EQ(obs[3].keyword, "TRANSMIT_FREQ_1");
  EXPECT_EQ(obs[3].value, 2106395199.07917);
  EXPECT_EQ(obs[3].unit, "Hz");
  EXPECT_EQ(obs[4].keyword, "RECEIVE_FREQ");
  EXPECT_EQ(obs[4].value, 2287487999.0);
  EXPECT_EQ(obs[5].value, 80452.7368);
  EXPECT_EQ(obs[10].value, 80452.7197);
  EXPECT_EQ(obs[15].epoch, "1998-06-10T00:57:44");
  EXPECT_EQ(obs[15].value, 80452.6331);
}

TEST(Tdm, JaxaExampleXmlEqualsTheKvnForm) {
  const Tdm x = read_tdm(ccsds_data("tdm_jaxa.xml"));
  Tdm k = read_tdm(ccsds_data("tdm_jaxa.kvn"));
  EXPECT_EQ(x.header.version, "2.0");
  k.header.comments.erase(k.header.comments.begin());  // the KVN file's provenance comment
  expect_same(x, k, /*same_version=*/false);
}

TEST(Tdm, OneWayExampleWithDayOfYearEpochs) {
  const Tdm t = read_tdm(ccsds_data("tdm_dsn_oneway.kvn"));
  const auto& m = t.segments[0].metadata;
  EXPECT_EQ(m.path, (std::vector<int>{2, 1}));  // one-way: spacecraft (2) to station (1)
  EXPECT_EQ(m.participants[0], "DSS-25");
  EXPECT_EQ(m.other[0], (satgnc::io::KeyValue{"FREQ_OFFSET", "32021035200.0"}));
  const auto& obs = t.segments[0].observations;
  ASSERT_EQ(obs.size(), 7u);
  EXPECT_EQ(obs[0].keyword, "TRANSMIT_FREQ_2");
  EXPECT_EQ(obs[0].value, 32023442781.733);
  EXPECT_EQ(obs[1].epoch, "2005-159T17:41:00");
  EXPECT_EQ(obs[1].value, -409.2735);
  EXPECT_EQ(obs[6].value, -218.7951);
}

Tdm synthetic() {
  // Every supported metadata field and the measurement types; values chosen to need all 17
  // significant digits, a subnormal-free tiny value and a leap-second epoch.
  Tdm t;
  t.header.version = "2.0";
  t.header.comments = {"synthetic round-trip case"};
  t.header.creation_date = "2026-12-02T00:00:00";
  t.header.originator = "SATGNC";
  t.header.message_id = "RT-1";
  satgnc::io::TdmSegment s;
  s.metadata.time_system = TimeSystem::utc;  // 23:59:60.5 exists only in UTC, on 2016-12-31
  s.metadata.participants = {"DSS-65", "SAT", "DSS-63"};
  s.metadata.mode = "SEQUENTIAL";
  s.metadata.path = {1, 2, 3};
  s.metadata.start_time = "2016-12-31T23:59:59";
  s.metadata.stop_time = "2017-001T00:00:10.125";
  s.metadata.integration_interval = 0.1;
  s.metadata.integration_ref = "END";
  s.metadata.range_units = "km";
  s.metadata.angle_type = "RADEC";
  s.metadata.other = {{"CORRECTION_RANGE", "0.0123"}, {"TRANSMIT_DELAY_1", "7.7e-5"}};
  s.data_comments = {"data comment"};
  const std::pair<const char*, double> vals[] = {{"RANGE", 12345.678901234567},
                                                 {"DOPPLER_INSTANTANEOUS", -7.1234567890123456},
                                                 {"DOPPLER_INTEGRATED", 1.0000000000000002},
                                                 {"ANGLE_1", 359.99999999999994},
                                                 {"ANGLE_2", -89.123456789012345},
                                                 {"RECEIVE_FREQ_3", 8.4e9 + 0.123},
                                                 {"CLOCK_BIAS", 1.5e-300}};
  const auto leap = satgnc::core::Epoch::parse("2016-12-31T23:59:60.5", TimeSystem::utc);
  for (const auto& [k, v] : vals)
    s.observations.push_back({k, "2016-12-31T23:59:60.5", v, satgnc::io::tdm_unit(k), leap});
  t.segments.push_back(s);
  s.metadata.time_system = TimeSystem::gps;
  for (auto& o : s.observations) {
    o.epoch = "2017-001T00:00:10.125";
    o.time = satgnc::core::Epoch::parse(o.epoch, TimeSystem::gps);
  }
  s.metadata.path = {2, 1};
  s.metadata.participants = {"GS", "SAT"};
  t.segments.push_back(s);
  return t;
}

TEST(Tdm, KvnRoundTripKeepsEveryValue) {
  const Tdm a = read_tdm(ccsds_data("tdm_jaxa.kvn"));
  expect_same(parse_tdm(satgnc::io::format_tdm_kvn(a)), a);
  const Tdm s = synthetic();
  const std::string text = satgnc::io::format_tdm_kvn(s);
  expect_same(parse_tdm(text), s);
  EXPECT_NE(text.find("RANGE = 2016-12-31T23:59:60.5 12345.678901234567\n"), std::string::npos) << text;
  EXPECT_NE(text.find("PATH = 1,2,3\n"), std::string::npos);
}

TEST(Tdm, XmlRoundTripKeepsEveryValue) {
  const Tdm a = read_tdm(ccsds_data("tdm_jaxa.xml"));
  expect_same(parse_tdm(satgnc::io::format_tdm_xml(a)), a);
  const Tdm s = synthetic();
  const std::string xml = satgnc::io::format_tdm_xml(s);
  EXPECT_EQ(xml.rfind("<?xml", 0), 0u);
  expect_same(parse_tdm(xml), s);
  // Files: both forms through write_tdm / read_tdm.
  const std::string path = ::testing::TempDir() + "satgnc_tdm_roundtrip.xml";
  satgnc::io::write_tdm(path, s, /*xml=*/true);
  expect_same(read_tdm(path), s);
  satgnc::io::write_tdm(path, s, /*xml=*/false);
  expect_same(read_tdm(path), s);
  std::remove(path.c_str());
}

// A valid base file; each bad-input case below changes one line.
const std::string kBase =
    "CCSDS_TDM_VERS = 2.0\n"                 // 1
    "CREATION_DATE = 2026-01-01T00:00:00\n"  // 2
    "ORIGINATOR = SATGNC\n"                  // 3
    "META_START\n"                           // 4
    "TIME_SYSTEM = UTC\n"                    // 5
    "PARTICIPANT_1 = STATION\n"              // 6
    "PARTICIPANT_2 = SAT\n"                  // 7
    "MODE = SEQUENTIAL\n"                    // 8
    "PATH = 1,2,1\n"                         // 9
    "RANGE_UNITS = km\n"                     // 10
    "ANGLE_TYPE = AZEL\n"                    // 11
    "META_STOP\n"                            // 12
    "DATA_START\n"                           // 13
    "RANGE = 2026-01-01T00:00:00 1000.5\n"   // 14
    "ANGLE_1 = 2026-01-01T00:00:00 10.25\n"  // 15
    "DATA_STOP\n";                           // 16

TEST(Tdm, BaseCaseIsValid) {
  const Tdm t = parse_tdm(kBase, "base.kvn");
  ASSERT_EQ(t.segments[0].observations.size(), 2u);
  EXPECT_EQ(t.segments[0].observations[1].value, 10.25);
}

TEST(Tdm, BadInputNamesFileLineAndKeyword) {
  satgnc::testing::expect_bad_lines(
      kBase,
      {
          {5, "TIME_SYSTEM = XYZ", 5, "TIME_SYSTEM", "unknown time system 'XYZ'"},
          {5, "TIME_SYSTEM = UT1", 5, "TIME_SYSTEM", "unsupported time system 'UT1'"},
          {5, "", 11, "TIME_SYSTEM",
           "missing mandatory keyword"},  // reported at META_STOP (line 11 once removed)
          {6, "", 11, "PARTICIPANT_1", "missing mandatory keyword"},
          {9, "PATH = 1,3,1", 9, "PATH", "names participant 3, but only PARTICIPANT_1..PARTICIPANT_2"},
          {9, "PATH = 1,x", 9, "PATH", "malformed path"},
          {9, "", 8, "PATH", "MODE = SEQUENTIAL requires PATH"},
          {8, "", 8, "MODE", "PATH requires MODE = SEQUENTIAL"},  // PATH moved up to line 8
          {10, "RANGE_UNITS = s", 10, "RANGE_UNITS", "unsupported range unit 's' (supported: km)"},
          {10, "RANGE_UNITS = RU", 10, "RANGE_UNITS", "unsupported range unit 'RU'"},
          {10, "RANGE_UNITS = furlong", 10, "RANGE_UNITS", "unknown range unit"},
          {11, "ANGLE_TYPE = XEYN", 11, "ANGLE_TYPE", "unsupported angle type"},
          {11, "", 14, "ANGLE_1", "need ANGLE_TYPE"},
          {10, "CORRECTION_RANGE = two", 10, "CORRECTION_RANGE", "not a number: 'two'"},
          {10, "RANGE_FOO = 1", 10, "RANGE_FOO", "unknown metadata keyword"},
          {14, "RANGE = 2026-01-01T00:00:00 12a", 14, "RANGE", "not a number: '12a'"},
          {14, "RANGE = 2026-01-01T00:00:00", 14, "RANGE", "malformed data line"},
          {14, "RANGE = 2026-01-01T00:00:00 +-1", 14, "RANGE", "not a number: '+-1'"},
          {14, "RANGE = 2026-01-01T00:00:00 nan", 14, "RANGE", "not a number: 'nan'"},
          {14, "RANGE = 2026-13-01T00:00:00 1.0", 14, "RANGE", "month out of range"},
          {14, "RANGE = 2026-01-01T00:00:00.12a 1.0", 14, "RANGE", "not an epoch"},
          {14, "RANGE = 2026-01-01T23:58:60 1.0", 14, "RANGE", "seconds out of range"},
          {14, "RANGEX = 2026-01-01T00:00:00 1.0", 14, "RANGEX", "unknown data keyword"},
          {14, "DOPPLER_COUNT = 2026-01-01T00:00:00 1.0", 14, "DOPPLER_COUNT", "unsupported data keyword"},
          {1, "CCSDS_TDM_VERS = 9.9", 1, "CCSDS_TDM_VERS", "unsupported version"},
          {1, "", 1, "CCSDS_TDM_VERS", "missing mandatory keyword"},
          {3, "", 3, "ORIGINATOR", "missing mandatory header keyword"},  // at META_START
          {16, "", 15, "DATA_STOP", "missing at the end of the file"},
          {7, "PARTICIPANT_3 = SAT", 7, "PARTICIPANT_3", "without a gap"},
          {3, "ORIGINATOR =", 3, "ORIGINATOR", "empty value"},
          {15, "ANGLE_1 = 2026-01-01T00:00:00 360.0", 15, "ANGLE_1", "angle 360.0 deg outside [-180, 360)"},
      },
      "bad.kvn", [](const std::string& text, const std::string& source) { parse_tdm(text, source); });
}

TEST(Tdm, StandardExamplesWithUnsupportedUnitsAreRefusedByName) {
  const std::string ru = ccsds_data("tdm_dsn_range_ru.kvn");
  expect_format_error([&] { read_tdm(ru); }, ru, 14, "RANGE_UNITS",
                      "unsupported range unit 'RU' (supported: km)");
  const std::string xsye = ccsds_data("tdm_gsoc_xsye.kvn");
  expect_format_error([&] { read_tdm(xsye); }, xsye, 15, "ANGLE_TYPE", "unsupported angle type 'XSYE'");
}

TEST(Tdm, XmlBadInputNamesLineAndKeyword) {
  std::string xml = satgnc::io::format_tdm_xml(parse_tdm(kBase));
  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = xml;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  auto line_of = [&](const std::string& s, const std::string& what) {
    const auto p = s.find(what);
    return 1 + static_cast<int>(std::count(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(p), '\n'));
  };
  const std::string ts = with("<TIME_SYSTEM>UTC</TIME_SYSTEM>", "<TIME_SYSTEM>XYZ</TIME_SYSTEM>");
  expect_format_error([&] { parse_tdm(ts, "bad.xml"); }, "bad.xml", line_of(ts, "<TIME_SYSTEM>"),
                      "TIME_SYSTEM", "unknown time system 'XYZ'");
  const std::string path = with("<PATH>1,2,1</PATH>", "<PATH>1,4,1</PATH>");
  expect_format_error([&] { parse_tdm(path, "bad.xml"); }, "bad.xml", line_of(path, "<PATH>"), "PATH",
                      "names participant 4");
  const std::string num = with("<RANGE>1000.5</RANGE>", "<RANGE>1e</RANGE>");
  expect_format_error([&] { parse_tdm(num, "bad.xml"); }, "bad.xml", line_of(num, "<RANGE>"), "RANGE",
                      "not a number: '1e'");
  const std::string unk = with("<RANGE>1000.5</RANGE>", "<RANGE_X>1000.5</RANGE_X>");
  expect_format_error([&] { parse_tdm(unk, "bad.xml"); }, "bad.xml", line_of(unk, "<RANGE_X>"), "RANGE_X",
                      "unknown data keyword");
  const std::string broken = with("</metadata>", "</metadatum>");
  expect_format_error([&] { parse_tdm(broken, "bad.xml"); }, "bad.xml", line_of(broken, "</metadatum>"),
                      "XML", "not well-formed XML");
}

TEST(Tdm, WriterRefusesAnInvalidModel) {
  Tdm t = parse_tdm(kBase);
  t.segments[0].metadata.path = {1, 3, 1};  // participant 3 is not defined
  try {
    satgnc::io::format_tdm_kvn(t);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tdm: not a valid TDM: PATH: path '1,3,1' names participant 3"),
              std::string::npos)
        << e.what();
  }
  t = parse_tdm(kBase);
  t.segments[0].observations[0].value = std::nan("");
  try {
    satgnc::io::format_tdm_xml(t);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "segments[0].observations[0].value: must be finite (no NaN or Inf)");
  }
  EXPECT_THROW(read_tdm("/nonexistent/satgnc.tdm"), std::invalid_argument);
}

TEST(Tdm, EpochsAreInstantsInTheSegmentsTimeSystem) {
  using satgnc::core::Epoch;
  const Tdm t = read_tdm(ccsds_data("tdm_jaxa.kvn"));
  EXPECT_EQ(t.segments[0].observations[0].time,
            Epoch::from_calendar(1998, 6, 10, 0, 57, 37.0, TimeSystem::utc));
  EXPECT_EQ(t.segments[0].observations[19].time - t.segments[0].observations[0].time, 7.0);  // s, exact
  // Day-of-year form: 2005-159 is June 8.
  const Tdm d = read_tdm(ccsds_data("tdm_dsn_oneway.kvn"));
  EXPECT_EQ(d.segments[0].observations[1].time,
            Epoch::from_calendar(2005, 6, 8, 17, 41, 0.0, TimeSystem::utc));
  // A leap second is a second: 23:59:60.5 is 0.5 s before 2017-01-01T00:00:00 UTC (exact).
  const Tdm leap = parse_tdm(replace_line(kBase, 14, "RANGE = 2016-12-31T23:59:60.5 1.0"));
  EXPECT_EQ(Epoch::parse("2017-01-01T00:00:00", TimeSystem::utc) - leap.segments[0].observations[0].time,
            0.5);
  // 18 fraction digits (more than an int holds) read to the double resolution of the fraction.
  const Tdm longf = parse_tdm(replace_line(kBase, 14, "RANGE = 2026-01-01T00:00:00.123456789012345678 1.0"));
  EXPECT_NEAR(longf.segments[0].observations[0].time - Epoch::parse("2026-01-01T00:00:00", TimeSystem::utc),
              0.123456789012345678, 1e-16);  // s; 1e-16: double spacing near 0.12
  // The same text in TAI does not exist, nor 23:59:60 on a day without a leap second.
  const std::string tai =
      replace_line(replace_line(kBase, 5, "TIME_SYSTEM = TAI"), 14, "RANGE = 2016-12-31T23:59:60.5 1.0");
  expect_format_error([&] { parse_tdm(tai, "bad.kvn"); }, "bad.kvn", 14, "RANGE", "not a valid TAI epoch");
  const std::string no_leap = replace_line(kBase, 14, "RANGE = 2026-06-30T23:59:60 1.0");
  expect_format_error([&] { parse_tdm(no_leap, "bad.kvn"); }, "bad.kvn", 14, "RANGE",
                      "not a valid UTC epoch");
  // A writer given only the instant prints it (up to 12 fraction digits, trailing zeros dropped).
  Tdm w = parse_tdm(kBase);
  w.segments[0].observations[0].epoch.clear();
  w.segments[0].observations[0].time = Epoch::parse("2016-12-31T23:59:60.25", TimeSystem::utc) + 1e-9;
  const std::string text = satgnc::io::format_tdm_kvn(w);
  EXPECT_NE(text.find("RANGE = 2016-12-31T23:59:60.250000001 1000.5"), std::string::npos) << text;
  // Read back, the printed digits give the instant again to the double rounding of its fraction (1e-15 s).
  EXPECT_LE(std::abs(parse_tdm(text).segments[0].observations[0].time - w.segments[0].observations[0].time),
            1e-15);
}

TEST(Tdm, MutatedFilesEitherParseOrRaiseFormatError) {
  // Robustness: 3000 single-character mutations (replace, delete, duplicate) of the KVN and XML forms
  // of the JAXA example; each must parse or throw FormatError (no other exception, no crash; valgrind
  // memcheck clean when run under it). Counts are asserted so that the loop cannot silently skip.
  const std::string texts[2] = {satgnc::testing::read_text(ccsds_data("tdm_jaxa.kvn")),
                                satgnc::testing::read_text(ccsds_data("tdm_jaxa.xml"))};
  unsigned state = 12345u;
  auto next = [&state] { return state = state * 1103515245u + 12345u, (state >> 8) & 0xffffffu; };
  int parsed = 0, refused = 0;
  for (int k = 0; k < 3000; ++k) {
    std::string t = texts[k % 2];
    const std::size_t at = next() % t.size();
    const char c = static_cast<char>(32 + next() % 95);
    switch (next() % 3) {
      case 0:
        t[at] = c;
        break;
      case 1:
        t.erase(at, 1);
        break;
      default:
        t.insert(at, 1, t[at]);
        break;
    }
    try {
      (void)parse_tdm(t, "mutated");
      ++parsed;
    } catch (const FormatError& e) {
      EXPECT_EQ(e.file(), "mutated");
      ++refused;
    }
  }
  EXPECT_EQ(parsed + refused, 3000);
  EXPECT_GT(refused, 300);  // many mutations break a keyword, a number or the XML
  EXPECT_GT(parsed, 300);   // many only touch a comment or a digit
}

}  // namespace
