// io::OPM in XML (NDM/XML, CCSDS 505.0-B): the standard's three examples (state + spacecraft,
// Keplerian + maneuvers, covariance) go KVN -> XML -> model and print the same KVN text (every number
// is printed in its shortest round-trip form, so equal text is equal doubles); files round-trip;
// malformed XML names the file, the XML line and the element.
#include <gtest/gtest.h>

#include <cstdio>

#include "ccsds_test_support.hpp"
#include "satgnc/io/opm.hpp"

namespace {
using satgnc::io::Opm;
using satgnc::io::parse_opm;
using satgnc::testing::ccsds_data;
using satgnc::testing::expect_format_error;
using satgnc::testing::replace_first;

TEST(OpmXml, StandardExamplesRoundTripThroughXml) {
  for (const char* f : {"opm_godzilla.kvn", "opm_eutelsat.kvn", "opm_osprey_cov.kvn"}) {
    SCOPED_TRACE(f);
    const Opm a = satgnc::io::read_opm(ccsds_data(f));
    const std::string xml = satgnc::io::format_opm_xml(a);
    EXPECT_EQ(xml.rfind("<?xml", 0), 0u);
    const Opm b = parse_opm(xml, "x.xml");
    EXPECT_EQ(satgnc::io::format_opm(b), satgnc::io::format_opm(a));
    EXPECT_EQ(b.state, a.state);  // exact
    EXPECT_EQ(b.time, a.time);
    EXPECT_EQ(b.maneuvers.size(), a.maneuvers.size());
    EXPECT_EQ(b.covariance.has_value(), a.covariance.has_value());
  }
  const Opm e = satgnc::io::read_opm(ccsds_data("opm_eutelsat.kvn"));
  ASSERT_GE(e.maneuvers.size(), 2u);
  const std::string path = ::testing::TempDir() + "satgnc_opm_roundtrip.xml";
  satgnc::io::write_opm(path, e, true);
  const Opm r = satgnc::io::read_opm(path);
  EXPECT_EQ(satgnc::io::format_opm(r), satgnc::io::format_opm(e));
  EXPECT_EQ(r.maneuvers[1].dv, e.maneuvers[1].dv);
  std::remove(path.c_str());
}

const std::string kXml =
    "<?xml version=\"1.0\"?>\n"                                                                     // 1
    "<opm id=\"CCSDS_OPM_VERS\" version=\"2.0\">\n"                                                 // 2
    "  <header><CREATION_DATE>2026-01-01T00:00:00</CREATION_DATE>\n"                                // 3
    "    <ORIGINATOR>SATGNC</ORIGINATOR></header>\n"                                                // 4
    "  <body><segment><metadata>\n"                                                                 // 5
    "    <OBJECT_NAME>SAT</OBJECT_NAME><OBJECT_ID>2026-001A</OBJECT_ID>\n"                          // 6
    "    <CENTER_NAME>EARTH</CENTER_NAME><REF_FRAME>GCRF</REF_FRAME>\n"                             // 7
    "    <TIME_SYSTEM>UTC</TIME_SYSTEM></metadata>\n"                                               // 8
    "    <data><stateVector><EPOCH>2026-01-01T00:00:00</EPOCH>\n"                                   // 9
    "      <X>7000</X><Y>0</Y><Z>0</Z>\n"                                                           // 10
    "      <X_DOT>0</X_DOT><Y_DOT>7.5</Y_DOT><Z_DOT>0</Z_DOT></stateVector>\n"                      // 11
    "      <userDefinedParameters><USER_DEFINED parameter=\"EARTH_MODEL\">WGS-84</USER_DEFINED>\n"  // 12
    "      </userDefinedParameters></data></segment></body></opm>\n";                               // 13

TEST(OpmXml, BadInputNamesFileXmlLineAndKeyword) {
  const Opm ok = parse_opm(kXml, "a.xml");
  ASSERT_EQ(ok.user_defined.size(), 1u);
  EXPECT_EQ(ok.user_defined[0].first, "EARTH_MODEL");
  EXPECT_EQ(ok.state[4], 7.5);
  auto bad = [](const std::string& text, int line, const std::string& key, const std::string& fragment) {
    expect_format_error([&] { parse_opm(text, "a.xml"); }, "a.xml", line, key, fragment);
  };
  bad(replace_first(kXml, "<Y_DOT>7.5</Y_DOT>", "<MASS>7.5</MASS>"), 11, "MASS",
      "unexpected in <stateVector>");
  bad(replace_first(kXml, "<Y>0</Y>", "<Y>zero</Y>"), 10, "Y", "");
  bad(replace_first(kXml, "    <TIME_SYSTEM>UTC</TIME_SYSTEM></metadata>\n", "    </metadata>\n"), 12,
      "TIME_SYSTEM", "missing mandatory keyword");
  bad(replace_first(kXml, "<ORIGINATOR>SATGNC</ORIGINATOR>", "<AUTHOR>X</AUTHOR>"), 4, "AUTHOR", "");
  bad(replace_first(kXml, "<stateVector>", "<orbit/><stateVector>"), 9, "orbit",
      "unexpected element in <data>");
  bad(replace_first(kXml, "<USER_DEFINED parameter=\"EARTH_MODEL\">", "<USER_DEFINED>"), 12, "USER_DEFINED",
      "expected <USER_DEFINED parameter=\"NAME\">");
  bad(replace_first(kXml, "</metadata>", "</metadat>"), 8, "XML", "not well-formed XML");
}

}  // namespace
