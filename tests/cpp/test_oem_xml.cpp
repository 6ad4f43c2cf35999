// io::OEM in XML (NDM/XML, CCSDS 505.0-B): KVN -> XML -> model keeps every value bit for bit (the
// standard's example and an estimated trajectory with covariance), files round-trip, malformed XML names
// the file, the XML line and the element.
#include <gtest/gtest.h>

#include <cstdio>

#include "ccsds_test_support.hpp"
#include "satgnc/io/oem.hpp"

namespace {
using satgnc::Mat6;
using satgnc::io::Oem;
using satgnc::io::parse_oem;
using satgnc::testing::ccsds_data;
using satgnc::testing::expect_format_error;
using satgnc::testing::expect_same_oem;
using satgnc::testing::replace_first;

TEST(OemXml, StandardExampleRoundTripsThroughXml) {
  const Oem a = satgnc::io::read_oem(ccsds_data("oem_mgs.kvn"));
  const std::string xml = satgnc::io::format_oem_xml(a);
  EXPECT_EQ(xml.rfind("<?xml", 0), 0u);
  EXPECT_NE(xml.find("<stateVector>"), std::string::npos);
  expect_same_oem(parse_oem(xml), a);
  // XML -> KVN gives the text KVN -> KVN gives.
  EXPECT_EQ(satgnc::io::format_oem(parse_oem(xml)), satgnc::io::format_oem(a));
}

TEST(OemXml, EstimatedTrajectoryWithCovarianceFileRoundTrip) {
  Oem t;
  t.header.creation_date = "2026-12-02T12:00:00";
  t.header.originator = "SATGNC";
  t.header.comments = {"batch OD result"};
  satgnc::io::OemSegment s;
  s.metadata.object_name = "LEO-1";
  s.metadata.object_id = "2026-001A";
  s.metadata.center_name = "EARTH";
  s.metadata.ref_frame = "GCRF";
  s.metadata.time_system = satgnc::io::TimeSystem::utc;
  s.metadata.start_time = "2026-12-02T00:00:00";
  s.metadata.stop_time = "2026-12-02T00:02:00";
  for (int i = 0; i < 3; ++i) {
    satgnc::io::OemState st;
    st.epoch = "2026-12-02T00:0" + std::to_string(i) + ":00";
    st.time = satgnc::core::Epoch::parse(st.epoch, satgnc::core::TimeScale::utc);
    st.state << 6778.137 + i / 3.0, -1.0 / 7.0, 1e-17, 7.6686, -0.0, 1.0 / 3.0;
    if (i == 1) st.acceleration = satgnc::Vec3(-8.0e-3 / 3.0, 1e-9, 3.0e-300);
    s.states.push_back(st);
    satgnc::io::OemCovariance cv;
    cv.epoch = st.epoch;
    cv.time = st.time;
    cv.cov_ref_frame = i == 0 ? "" : "RTN";
    if (i == 2) cv.comments = {"after the last pass"};
    const Mat6 L = Mat6::Random();
    cv.matrix = L * L.transpose() * 1e-6;
    cv.matrix = (0.5 * (cv.matrix + cv.matrix.transpose())).eval();
    s.covariances.push_back(cv);
  }
  t.segments.push_back(s);
  t.segments.push_back(s);
  t.segments[1].covariances.clear();
  const std::string path = ::testing::TempDir() + "satgnc_oem_roundtrip.xml";
  satgnc::io::write_oem(path, t, true);
  expect_same_oem(satgnc::io::read_oem(path), t);
  std::remove(path.c_str());
}

const std::string kXml =
    "<?xml version=\"1.0\"?>\n"                                             // 1
    "<oem id=\"CCSDS_OEM_VERS\" version=\"2.0\">\n"                         // 2
    "  <header><CREATION_DATE>2026-01-01T00:00:00</CREATION_DATE>\n"        // 3
    "    <ORIGINATOR>SATGNC</ORIGINATOR></header>\n"                        // 4
    "  <body><segment><metadata>\n"                                         // 5
    "    <OBJECT_NAME>SAT</OBJECT_NAME><OBJECT_ID>2026-001A</OBJECT_ID>\n"  // 6
    "    <CENTER_NAME>EARTH</CENTER_NAME><REF_FRAME>GCRF</REF_FRAME>\n"     // 7
    "    <TIME_SYSTEM>UTC</TIME_SYSTEM>\n"                                  // 8
    "    <START_TIME>2026-01-01T00:00:00</START_TIME>\n"                    // 9
    "    <STOP_TIME>2026-01-01T00:01:00</STOP_TIME></metadata>\n"           // 10
    "    <data><stateVector><EPOCH>2026-01-01T00:00:00</EPOCH>\n"           // 11
    "      <X>7000</X><Y>0</Y><Z>0</Z>\n"                                   // 12
    "      <X_DOT>0</X_DOT><Y_DOT>7.5</Y_DOT><Z_DOT>0</Z_DOT>\n"            // 13
    "    </stateVector></data></segment></body></oem>\n";                   // 14

TEST(OemXml, BadInputNamesFileXmlLineAndKeyword) {
  ASSERT_EQ(parse_oem(kXml, "a.xml").segments[0].states.size(), 1u);
  auto bad = [](const std::string& text, int line, const std::string& key, const std::string& fragment) {
    expect_format_error([&] { parse_oem(text, "a.xml"); }, "a.xml", line, key, fragment);
  };
  bad(replace_first(kXml, "<Y_DOT>7.5</Y_DOT>", "<V_Y>7.5</V_Y>"), 13, "V_Y", "unexpected in <stateVector>");
  bad(replace_first(kXml, "<Y>0</Y>", "<Y>zero</Y>"), 11, "EPHEMERIS",
      "");  // the number rule of the KVN reader
  bad(replace_first(kXml, "<TIME_SYSTEM>UTC</TIME_SYSTEM>", "<TIME_SYSTEM>UT2</TIME_SYSTEM>"), 8,
      "TIME_SYSTEM", "");
  bad(replace_first(kXml, "    <TIME_SYSTEM>UTC</TIME_SYSTEM>\n", "\n"), 5, "TIME_SYSTEM",
      "missing mandatory keyword");
  bad(replace_first(kXml, "<ORIGINATOR>SATGNC</ORIGINATOR>", "<AUTHOR>X</AUTHOR>"), 4, "AUTHOR",
      "unknown header keyword");
  bad(replace_first(kXml, "</stateVector>", "</stateVector><ephemeris/>"), 14, "ephemeris",
      "unexpected element in <data>");
  bad(replace_first(kXml, "</stateVector>",
                    "</stateVector><covarianceMatrix><EPOCH>2026-01-01T00:00:00</EPOCH></covarianceMatrix>"),
      14, "CX_X", "missing in <covarianceMatrix>");
  bad(replace_first(kXml, "</metadata>", "</metadat>"), 10, "XML", "not well-formed XML");
  bad(replace_first(kXml, "version=\"2.0\"", "version=\"9.0\""), 2, "CCSDS_OEM_VERS", "");
}

}  // namespace
