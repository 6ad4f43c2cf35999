// io::OPM (CCSDS 502.0-B-3 section 3), KVN: the standard's three examples parse to the printed numbers
// (state, Keplerian elements, spacecraft, covariance, maneuvers), write -> read round trips are bit for
// bit, malformed files name file, line and keyword.
#include <gtest/gtest.h>

#include <cstdio>

#include "ccsds_test_support.hpp"
#include "satgnc/io/opm.hpp"

namespace {
using satgnc::Mat6;
using satgnc::Vec3;
using satgnc::Vec6;
using satgnc::io::Opm;
using satgnc::io::parse_opm;
using satgnc::io::read_opm;
using satgnc::testing::ccsds_data;
using satgnc::testing::expect_format_error;
using satgnc::testing::replace_line;

// Exact comparisons (tolerance 0): from_chars and the compiler round the same decimal text the same way.
void expect_same(const Opm& a, const Opm& b) {
  satgnc::testing::expect_same_header(a.header, b.header);
  EXPECT_EQ(a.metadata_comments, b.metadata_comments);
  EXPECT_EQ(a.object_name, b.object_name);
  EXPECT_EQ(a.object_id, b.object_id);
  EXPECT_EQ(a.center_name, b.center_name);
  EXPECT_EQ(a.ref_frame, b.ref_frame);
  EXPECT_EQ(a.ref_frame_epoch, b.ref_frame_epoch);
  EXPECT_EQ(a.time_system, b.time_system);
  EXPECT_EQ(a.data_comments, b.data_comments);
  EXPECT_EQ(a.epoch, b.epoch);
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.state, b.state);
  ASSERT_EQ(a.keplerian.has_value(), b.keplerian.has_value());
  if (a.keplerian) {
    EXPECT_EQ(a.keplerian->semi_major_axis, b.keplerian->semi_major_axis);
    EXPECT_EQ(a.keplerian->eccentricity, b.keplerian->eccentricity);
    EXPECT_EQ(a.keplerian->inclination, b.keplerian->inclination);
    EXPECT_EQ(a.keplerian->ra_of_asc_node, b.keplerian->ra_of_asc_node);
    EXPECT_EQ(a.keplerian->arg_of_pericenter, b.keplerian->arg_of_pericenter);
    EXPECT_EQ(a.keplerian->true_anomaly, b.keplerian->true_anomaly);
    EXPECT_EQ(a.keplerian->mean_anomaly, b.keplerian->mean_anomaly);
    EXPECT_EQ(a.keplerian->gm, b.keplerian->gm);
  }
  ASSERT_EQ(a.spacecraft.has_value(), b.spacecraft.has_value());
  if (a.spacecraft) {
    EXPECT_EQ(a.spacecraft->mass, b.spacecraft->mass);
    EXPECT_EQ(a.spacecraft->solar_rad_area, b.spacecraft->solar_rad_area);
    EXPECT_EQ(a.spacecraft->solar_rad_coeff, b.spacecraft->solar_rad_coeff);
    EXPECT_EQ(a.spacecraft->drag_area, b.spacecraft->drag_area);
    EXPECT_EQ(a.spacecraft->drag_coeff, b.spacecraft->drag_coeff);
  }
  EXPECT_EQ(a.cov_ref_frame, b.cov_ref_frame);
  ASSERT_EQ(a.covariance.has_value(), b.covariance.has_value());
  if (a.covariance) EXPECT_EQ(*a.covariance, *b.covariance);
  ASSERT_EQ(a.maneuvers.size(), b.maneuvers.size());
  for (std::size_t i = 0; i < a.maneuvers.size(); ++i) {
    EXPECT_EQ(a.maneuvers[i].comments, b.maneuvers[i].comments);
    EXPECT_EQ(a.maneuvers[i].epoch_ignition, b.maneuvers[i].epoch_ignition);
    EXPECT_EQ(a.maneuvers[i].ignition_time, b.maneuvers[i].ignition_time);
    EXPECT_EQ(a.maneuvers[i].duration, b.maneuvers[i].duration);
    EXPECT_EQ(a.maneuvers[i].delta_mass, b.maneuvers[i].delta_mass);
    EXPECT_EQ(a.maneuvers[i].ref_frame, b.maneuvers[i].ref_frame);
    EXPECT_EQ(a.maneuvers[i].dv, b.maneuvers[i].dv);
  }
  EXPECT_EQ(a.user_defined, b.user_defined);
}

TEST(Opm, StateAndSpacecraftExample) {
  const Opm o = read_opm(ccsds_data("opm_godzilla.kvn"));
  EXPECT_EQ(o.object_name, "GODZILLA 5");
  EXPECT_EQ(o.ref_frame, "ITRF2000");
  EXPECT_EQ(o.metadata_comments, (std::vector<std::string>{"GEOCENTRIC, CARTESIAN, EARTH FIXED"}));
  EXPECT_EQ(o.epoch, "1998-12-18T14:28:15.1172");
  EXPECT_EQ(o.state, (Vec6() << 6503.514, 1239.647, -717.49, -0.87316, 8.74042, -4.191076).finished());
  ASSERT_TRUE(o.spacecraft.has_value());
  EXPECT_EQ(o.spacecraft->mass, 3000.0);
  EXPECT_EQ(o.spacecraft->solar_rad_area, 18.77);
  EXPECT_EQ(o.spacecraft->drag_coeff, 2.5);
  EXPECT_FALSE(o.keplerian.has_value());
  EXPECT_FALSE(o.covariance.has_value());
}

TEST(Opm, KeplerianAndManeuverExample) {
  const Opm o = read_opm(ccsds_data("opm_eutelsat.kvn"));
  EXPECT_EQ(o.ref_frame, "TOD");
  EXPECT_EQ(o.state(1), -40218.5751);
  EXPECT_EQ(o.state(5), -0.00101495);
  ASSERT_TRUE(o.keplerian.has_value());
  EXPECT_EQ(o.keplerian->semi_major_axis, 41399.5123);
  EXPECT_EQ(o.keplerian->eccentricity, 0.020842611);
  EXPECT_EQ(o.keplerian->arg_of_pericenter, 218.242943);
  EXPECT_EQ(o.keplerian->true_anomaly, 41.922339);
  EXPECT_FALSE(o.keplerian->mean_anomaly.has_value());
  EXPECT_EQ(o.keplerian->gm, 398600.4415);
  EXPECT_EQ(o.spacecraft->mass, 1913.0);
  EXPECT_EQ(o.spacecraft->solar_rad_coeff, 1.3);
  ASSERT_EQ(o.maneuvers.size(), 2u);
  EXPECT_EQ(o.maneuvers[0].epoch_ignition, "2000-06-03T09:00:34.1");
  // 2000-06-03T09:00:34.1 UTC is 2000-06-03T00:00:00 UTC (the state epoch's date) + 32434.1 s.
  EXPECT_NEAR(o.maneuvers[0].ignition_time -
                  satgnc::core::Epoch::from_calendar(2000, 6, 3, 0, 0, 0.0, satgnc::io::TimeSystem::utc),
              32434.1, 1e-9);  // s; 1e-9: the fraction 0.1 is not exact in binary
  EXPECT_EQ(o.maneuvers[0].duration, 132.6);
  EXPECT_EQ(o.maneuvers[0].delta_mass, -18.418);
  EXPECT_EQ(o.maneuvers[0].ref_frame, "J2000");
  EXPECT_EQ(o.maneuvers[0].dv, Vec3(-0.023257, 0.0168316, -0.00893444));
  EXPECT_EQ(o.maneuvers[0].comments.size(),
            3u);  // "2 planned maneuvers", "First maneuver...", "Non-impulsive..."
  EXPECT_EQ(o.maneuvers[1].ref_frame, "RTN");
  EXPECT_EQ(o.maneuvers[1].dv, Vec3(0.001015, -0.001873, 0.0));
  EXPECT_EQ(o.data_comments,
            (std::vector<std::string>{"State Vector", "Keplerian elements", "Spacecraft parameters"}));
}

TEST(Opm, CovarianceExample) {
  const Opm o = read_opm(ccsds_data("opm_osprey_cov.kvn"));
  ASSERT_TRUE(o.covariance.has_value());
  const Mat6& c = *o.covariance;
  EXPECT_EQ(c(0, 0), 3.331349476038534e-04);
  EXPECT_EQ(c(1, 0), 4.618927349220216e-04);
  EXPECT_EQ(c(0, 1), c(1, 0));
  EXPECT_EQ(c(3, 2), 2.484949578400095e-07);
  EXPECT_EQ(c(5, 4), 1.008862586240695e-10);
  EXPECT_EQ(c(5, 5), 6.224444338635500e-10);
  EXPECT_EQ((c - c.transpose()).norm(), 0.0);
}

TEST(Opm, RoundTripKeepsEveryValue) {
  for (const char* f : {"opm_godzilla.kvn", "opm_eutelsat.kvn", "opm_osprey_cov.kvn"}) {
    SCOPED_TRACE(f);
    const Opm a = read_opm(ccsds_data(f));
    expect_same(parse_opm(satgnc::io::format_opm(a)), a);
  }
  Opm o = read_opm(ccsds_data("opm_eutelsat.kvn"));
  o.keplerian->true_anomaly.reset();
  o.keplerian->mean_anomaly = 1.0 / 3.0;
  o.state(0) = 6778.137 / 7.0;
  o.covariance = Mat6::Identity() * (1.0 / 3.0);
  o.cov_ref_frame = "RTN";
  o.time_system = satgnc::io::TimeSystem::tdb;
  o.time = satgnc::core::Epoch::parse(o.epoch, o.time_system);
  for (auto& m : o.maneuvers) m.ignition_time = satgnc::core::Epoch::parse(m.epoch_ignition, o.time_system);
  o.user_defined = {{"EARTH_MODEL", "WGS-84"}};
  const std::string path = ::testing::TempDir() + "satgnc_opm_roundtrip.opm";
  satgnc::io::write_opm(path, o);
  expect_same(read_opm(path), o);
  std::remove(path.c_str());
}

const std::string kBase =
    "CCSDS_OPM_VERS = 2.0\n"                 // 1
    "CREATION_DATE = 2026-01-01T00:00:00\n"  // 2
    "ORIGINATOR = SATGNC\n"                  // 3
    "OBJECT_NAME = SAT\n"                    // 4
    "OBJECT_ID = 2026-001A\n"                // 5
    "CENTER_NAME = EARTH\n"                  // 6
    "REF_FRAME = GCRF\n"                     // 7
    "TIME_SYSTEM = UTC\n"                    // 8
    "EPOCH = 2026-01-01T00:00:00\n"          // 9
    "X = 7000 [km]\n"                        // 10
    "Y = 0\n"                                // 11
    "Z = 0\n"                                // 12
    "X_DOT = 0\n"                            // 13
    "Y_DOT = 7.5 [km/s]\n"                   // 14
    "Z_DOT = 0\n"                            // 15
    "SEMI_MAJOR_AXIS = 7000 [km]\n"          // 16
    "ECCENTRICITY = 0\n"                     // 17
    "INCLINATION = 0\n"                      // 18
    "RA_OF_ASC_NODE = 0\n"                   // 19
    "ARG_OF_PERICENTER = 0\n"                // 20
    "TRUE_ANOMALY = 0\n"                     // 21
    "GM = 398600.4415\n";                    // 22

TEST(Opm, BadInputNamesFileLineAndKeyword) {
  ASSERT_TRUE(parse_opm(kBase).keplerian.has_value());
  satgnc::testing::expect_bad_lines(
      kBase,
      {
          {8, "TIME_SYSTEM = GMST", 8, "TIME_SYSTEM", "unsupported time system 'GMST'"},
          {8, "TIME_SYSTEM = local", 8, "TIME_SYSTEM", "unknown time system 'local'"},
          {9, "", 21, "EPOCH", "missing mandatory keyword"},
          {11, "", 21, "Y", "missing mandatory keyword"},
          {10, "X = 7000 [m]", 10, "X", "unsupported unit '[m]' (this keyword is in km)"},
          {14, "Y_DOT = fast", 14, "Y_DOT", "not a number: 'fast'"},
          {17, "", 21, "ECCENTRICITY", "Keplerian elements are all given or none"},
          {22, "GM = 398600.4415\nMEAN_ANOMALY = 0", 23, "TRUE_ANOMALY",
           "exactly one of TRUE_ANOMALY and MEAN_ANOMALY"},
          {18, "INCLINATION = 0 [rad]", 18, "INCLINATION", "unsupported unit '[rad]'"},
          {12, "Q = 0", 12, "Q", "unknown keyword"},
          {12, "CX_Q = 0", 12, "CX_Q", "unknown keyword"},
          {22, "CX_X = 1", 22, "GM", "Keplerian elements are all given or none"},
          {22, "MAN_DURATION = 1", 22, "MAN_DURATION", "before MAN_EPOCH_IGNITION"},
          {1, "CCSDS_OEM_VERS = 2.0", 1, "CCSDS_OPM_VERS", "missing mandatory keyword"},
      },
      "bad.opm", [](const std::string& text, const std::string& source) { parse_opm(text, source); });
  // Partial covariance: the first missing term is named.
  expect_format_error([&] { parse_opm(kBase + "CX_X = 1\nCY_X = 0\n", "bad.opm"); }, "bad.opm", 24, "CY_Y",
                      "all 21 lower-triangle terms");
  // Incomplete maneuver.
  expect_format_error(
      [&] { parse_opm(kBase + "MAN_EPOCH_IGNITION = 2026-01-01T01:00:00\nMAN_DURATION = 1\n", "bad.opm"); },
      "bad.opm", 24, "MAN_DELTA_MASS", "missing mandatory maneuver keyword");
}

TEST(Opm, MutatedFilesEitherParseOrRaiseFormatError) {
  // Robustness: 1500 one-character mutations of the standard's example; each parses or throws
  // FormatError (no other exception, no crash). Both outcomes must occur (the loop ran).
  const std::string text = satgnc::testing::read_text(ccsds_data("opm_eutelsat.kvn"));
  const int parsed = satgnc::testing::mutation_runs(
      text, 1500, "mutated", [](const std::string& t) { (void)parse_opm(t, "mutated"); });
  EXPECT_GT(parsed, 150);
  EXPECT_LT(parsed, 1350);
}

}  // namespace
