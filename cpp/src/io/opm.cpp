// OPM (CCSDS 502.0-B-3 section 3), KVN: reader and writer.
#include "satgnc/io/opm.hpp"

#include <map>
#include <sstream>

#include "detail/kvn.hpp"
#include "detail/opm_lines.hpp"

namespace satgnc::io {

using detail::check_epoch;
using detail::fail;
using detail::format_number;
using detail::KvnLine;

namespace {

constexpr const char* kAxes[6] = {"X", "Y", "Z", "X_DOT", "Y_DOT", "Z_DOT"};
constexpr const char* kKepler[] = {"SEMI_MAJOR_AXIS",   "ECCENTRICITY", "INCLINATION",  "RA_OF_ASC_NODE",
                                   "ARG_OF_PERICENTER", "TRUE_ANOMALY", "MEAN_ANOMALY", "GM"};
constexpr const char* kSpacecraft[] = {"MASS", "SOLAR_RAD_AREA", "SOLAR_RAD_COEFF", "DRAG_AREA",
                                       "DRAG_COEFF"};
constexpr const char* kManeuver[] = {"MAN_EPOCH_IGNITION", "MAN_DURATION", "MAN_DELTA_MASS", "MAN_REF_FRAME",
                                     "MAN_DV_1",           "MAN_DV_2",     "MAN_DV_3"};

std::string cov_key(int i, int j) { return std::string("C") + kAxes[i] + "_" + kAxes[j]; }
std::string cov_unit(int i, int j) {
  return i < 3 && j < 3 ? "km**2" : (i >= 3 && j >= 3 ? "km**2/s**2" : "km**2/s");
}

bool in(const char* const* list, std::size_t n, const std::string& k) {
  for (std::size_t i = 0; i < n; ++i)
    if (k == list[i]) return true;
  return false;
}

}  // namespace

namespace detail {
// The OPM of KVN lines (tokenize_kvn's, or synthesized from XML by opm_xml.cpp with the XML's line
// numbers): one set of rules and messages for both encodings.
Opm parse_opm_lines(const std::vector<KvnLine>& lines, const std::string& source) {
  using K = KvnLine::Kind;
  Opm opm;
  const KvnLine& v = detail::check_version_line(lines, "CCSDS_OPM_VERS", {"1.0", "2.0", "3.0"}, source);
  opm.header.version = v.value;
  std::map<std::string, int> seen;  // keyword -> line (maneuver keywords: per maneuver)
  std::map<std::string, int> man_seen;
  std::vector<int> man_lines;  // line of each MAN_EPOCH_IGNITION
  std::map<std::string, double> kep, sc;
  Mat6 cov = Mat6::Zero();
  int cov_count = 0;
  std::vector<std::string> pending;
  bool header_keys = false;
  int last = v.line;
  auto close_maneuver = [&](int line) {
    if (opm.maneuvers.empty()) return;
    for (const char* k : kManeuver)
      if (!man_seen.count(k)) fail(source, line, k, "missing mandatory maneuver keyword");
  };
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const KvnLine& l = lines[i];
    last = l.line;
    if (l.kind == K::comment) {
      if (!header_keys)
        opm.header.comments.push_back(l.value);
      else if (!seen.count("OBJECT_NAME"))
        opm.metadata_comments.push_back(l.value);
      else
        pending.push_back(l.value);
      continue;
    }
    if (l.kind != K::key_value)
      fail(source, l.line, l.kind == K::raw ? l.value : l.key,
           "unexpected line (an OPM is KEYWORD = value lines)");
    const std::string& k = l.key;
    const bool man = k.rfind("MAN_", 0) == 0;
    if (!man && seen.count(k)) fail(source, l.line, k, "duplicate keyword");
    if (!man) seen[k] = l.line;
    auto num = [&](const std::string& unit) {
      detail::check_unit(l, unit, source);
      return detail::parse_number(l.value, source, l.line, k);
    };
    if (k == "CREATION_DATE" || k == "ORIGINATOR" || k == "MESSAGE_ID" || k == "CLASSIFICATION") {
      if (seen.count("OBJECT_NAME")) fail(source, l.line, k, "header keyword after the metadata");
      header_keys = true;
      if (k == "CREATION_DATE") opm.header.creation_date = check_epoch(l.value, source, l.line, k);
      if (k == "ORIGINATOR") opm.header.originator = l.value;
      if (k == "MESSAGE_ID") opm.header.message_id = l.value;
      if (k == "CLASSIFICATION") opm.header.classification = l.value;
      continue;
    }
    header_keys = true;
    if (k == "OBJECT_NAME") {
      opm.object_name = l.value;
    } else if (k == "OBJECT_ID") {
      opm.object_id = l.value;
    } else if (k == "CENTER_NAME") {
      opm.center_name = l.value;
    } else if (k == "REF_FRAME") {
      opm.ref_frame = l.value;
    } else if (k == "REF_FRAME_EPOCH") {
      opm.ref_frame_epoch = check_epoch(l.value, source, l.line, k);
    } else if (k == "TIME_SYSTEM") {
      opm.time_system = detail::parse_time_system(l.value, source, l.line);
    } else if (k == "EPOCH") {
      opm.epoch = check_epoch(l.value, source, l.line, k);
    } else if (in(kAxes, 6, k)) {
      for (int j = 0; j < 6; ++j)
        if (k == kAxes[j]) opm.state(j) = num(j < 3 ? "km" : "km/s");
    } else if (in(kKepler, 8, k)) {
      const bool angle = k != "SEMI_MAJOR_AXIS" && k != "ECCENTRICITY" && k != "GM";
      kep[k] = num(k == "SEMI_MAJOR_AXIS" ? "km" : k == "GM" ? "km**3/s**2" : angle ? "deg" : "");
    } else if (in(kSpacecraft, 5, k)) {
      sc[k] = num(k == "MASS" ? "kg" : (k == "SOLAR_RAD_AREA" || k == "DRAG_AREA") ? "m**2" : "");
    } else if (k == "COV_REF_FRAME") {
      opm.cov_ref_frame = l.value;
    } else if (k.size() > 2 && k[0] == 'C' && k[1] != 'O' && k != "CENTER_NAME" && k != "CREATION_DATE" &&
               k != "CLASSIFICATION") {
      bool found = false;
      for (int r = 0; r < 6 && !found; ++r)
        for (int c = 0; c <= r && !found; ++c)
          if (k == cov_key(r, c)) {
            cov(r, c) = cov(c, r) = num(cov_unit(r, c));
            ++cov_count;
            found = true;
          }
      if (!found) fail(source, l.line, k, "unknown keyword");
    } else if (man) {
      if (!in(kManeuver, 7, k)) fail(source, l.line, k, "unknown maneuver keyword");
      if (k == "MAN_EPOCH_IGNITION") {
        close_maneuver(l.line);
        opm.maneuvers.emplace_back();
        opm.maneuvers.back().comments = std::move(pending);
        pending.clear();
        man_seen.clear();
        man_lines.push_back(l.line);
        opm.maneuvers.back().epoch_ignition = check_epoch(l.value, source, l.line, k);
      } else if (opm.maneuvers.empty()) {
        fail(source, l.line, k, "maneuver keyword before MAN_EPOCH_IGNITION");
      } else if (man_seen.count(k)) {
        fail(source, l.line, k, "duplicate keyword in a maneuver (hint: MAN_EPOCH_IGNITION starts the next)");
      }
      man_seen[k] = l.line;
      OpmManeuver& m = opm.maneuvers.back();
      if (k == "MAN_DURATION") m.duration = num("s");
      if (k == "MAN_DELTA_MASS") m.delta_mass = num("kg");
      if (k == "MAN_REF_FRAME") m.ref_frame = l.value;
      if (k == "MAN_DV_1") m.dv(0) = num("km/s");
      if (k == "MAN_DV_2") m.dv(1) = num("km/s");
      if (k == "MAN_DV_3") m.dv(2) = num("km/s");
      continue;
    } else if (k.rfind("USER_DEFINED_", 0) == 0 && k.size() > 13) {
      opm.user_defined.emplace_back(k.substr(13), l.value);
    } else {
      fail(source, l.line, k, "unknown keyword");
    }
    if (!pending.empty()) {
      opm.data_comments.insert(opm.data_comments.end(), pending.begin(), pending.end());
      pending.clear();
    }
  }
  opm.data_comments.insert(opm.data_comments.end(), pending.begin(), pending.end());
  close_maneuver(last);
  for (const char* k : {"CREATION_DATE", "ORIGINATOR", "OBJECT_NAME", "OBJECT_ID", "CENTER_NAME", "REF_FRAME",
                        "TIME_SYSTEM", "EPOCH", "X", "Y", "Z", "X_DOT", "Y_DOT", "Z_DOT"})
    if (!seen.count(k)) fail(source, last, k, "missing mandatory keyword");
  opm.time = detail::to_epoch(opm.epoch, opm.time_system, source, seen["EPOCH"], "EPOCH");
  for (std::size_t i = 0; i < opm.maneuvers.size(); ++i)
    opm.maneuvers[i].ignition_time = detail::to_epoch(opm.maneuvers[i].epoch_ignition, opm.time_system,
                                                      source, man_lines[i], "MAN_EPOCH_IGNITION");
  if (!kep.empty()) {
    for (const char* k :
         {"SEMI_MAJOR_AXIS", "ECCENTRICITY", "INCLINATION", "RA_OF_ASC_NODE", "ARG_OF_PERICENTER", "GM"})
      if (!kep.count(k)) fail(source, last, k, "missing: Keplerian elements are all given or none");
    if (kep.count("TRUE_ANOMALY") == kep.count("MEAN_ANOMALY"))
      fail(source, last, "TRUE_ANOMALY", "exactly one of TRUE_ANOMALY and MEAN_ANOMALY is needed");
    OpmKeplerian e;
    e.semi_major_axis = kep["SEMI_MAJOR_AXIS"];
    e.eccentricity = kep["ECCENTRICITY"];
    e.inclination = kep["INCLINATION"];
    e.ra_of_asc_node = kep["RA_OF_ASC_NODE"];
    e.arg_of_pericenter = kep["ARG_OF_PERICENTER"];
    if (kep.count("TRUE_ANOMALY")) e.true_anomaly = kep["TRUE_ANOMALY"];
    if (kep.count("MEAN_ANOMALY")) e.mean_anomaly = kep["MEAN_ANOMALY"];
    e.gm = kep["GM"];
    opm.keplerian = e;
  }
  if (!sc.empty()) {
    OpmSpacecraft p;
    if (sc.count("MASS")) p.mass = sc["MASS"];
    if (sc.count("SOLAR_RAD_AREA")) p.solar_rad_area = sc["SOLAR_RAD_AREA"];
    if (sc.count("SOLAR_RAD_COEFF")) p.solar_rad_coeff = sc["SOLAR_RAD_COEFF"];
    if (sc.count("DRAG_AREA")) p.drag_area = sc["DRAG_AREA"];
    if (sc.count("DRAG_COEFF")) p.drag_coeff = sc["DRAG_COEFF"];
    opm.spacecraft = p;
  }
  if (cov_count > 0) {
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c <= r; ++c)
        if (!seen.count(cov_key(r, c)))
          fail(source, last, cov_key(r, c), "missing: the covariance needs all 21 lower-triangle terms");
    opm.covariance = cov;
  } else if (seen.count("COV_REF_FRAME")) {
    fail(source, seen["COV_REF_FRAME"], "CX_X", "missing: COV_REF_FRAME given without a covariance");
  }
  return opm;
}
}  // namespace detail

Opm parse_opm(const std::string& text, const std::string& source) {
  if (detail::is_xml(text)) return detail::parse_opm_xml(text, source);
  return detail::parse_opm_lines(detail::tokenize_kvn(text, source), source);
}

Opm read_opm(const std::string& path) { return parse_opm(detail::read_file(path), path); }

using detail::put;
using detail::put_opt;

std::string format_opm(const Opm& opm) {
  std::ostringstream out;
  auto num = [](double v, const std::string& name) { return format_number(v, name); };
  detail::put_header(out, "CCSDS_OPM_VERS", opm.header);
  out << "\n";
  detail::put_comments(out, opm.metadata_comments);
  detail::put_object(out, {opm.object_name, opm.object_id, opm.center_name, opm.ref_frame,
                           opm.ref_frame_epoch, opm.time_system});
  out << "\n";
  detail::put_comments(out, opm.data_comments);
  put(out, "EPOCH", detail::epoch_or_time(opm.epoch, opm.time, opm.time_system));
  for (int j = 0; j < 6; ++j) put(out, kAxes[j], num(opm.state(j), "state") + (j < 3 ? " [km]" : " [km/s]"));
  if (opm.keplerian) {
    const OpmKeplerian& e = *opm.keplerian;
    if (e.true_anomaly.has_value() == e.mean_anomaly.has_value())
      throw std::invalid_argument("keplerian: exactly one of true_anomaly and mean_anomaly must be set");
    out << "\n";
    put(out, "SEMI_MAJOR_AXIS", num(e.semi_major_axis, "keplerian.semi_major_axis") + " [km]");
    put(out, "ECCENTRICITY", num(e.eccentricity, "keplerian.eccentricity"));
    put(out, "INCLINATION", num(e.inclination, "keplerian.inclination") + " [deg]");
    put(out, "RA_OF_ASC_NODE", num(e.ra_of_asc_node, "keplerian.ra_of_asc_node") + " [deg]");
    put(out, "ARG_OF_PERICENTER", num(e.arg_of_pericenter, "keplerian.arg_of_pericenter") + " [deg]");
    if (e.true_anomaly) put(out, "TRUE_ANOMALY", num(*e.true_anomaly, "keplerian.true_anomaly") + " [deg]");
    if (e.mean_anomaly) put(out, "MEAN_ANOMALY", num(*e.mean_anomaly, "keplerian.mean_anomaly") + " [deg]");
    put(out, "GM", num(e.gm, "keplerian.gm") + " [km**3/s**2]");
  }
  if (opm.spacecraft) {
    const OpmSpacecraft& p = *opm.spacecraft;
    out << "\n";
    if (p.mass) put(out, "MASS", num(*p.mass, "spacecraft.mass") + " [kg]");
    if (p.solar_rad_area)
      put(out, "SOLAR_RAD_AREA", num(*p.solar_rad_area, "spacecraft.solar_rad_area") + " [m**2]");
    if (p.solar_rad_coeff) put(out, "SOLAR_RAD_COEFF", num(*p.solar_rad_coeff, "spacecraft.solar_rad_coeff"));
    if (p.drag_area) put(out, "DRAG_AREA", num(*p.drag_area, "spacecraft.drag_area") + " [m**2]");
    if (p.drag_coeff) put(out, "DRAG_COEFF", num(*p.drag_coeff, "spacecraft.drag_coeff"));
  }
  if (opm.covariance) {
    const Mat6& c = *opm.covariance;
    if (!(c - c.transpose()).isZero(0.0)) throw std::invalid_argument("covariance: must be symmetric");
    out << "\n";
    put_opt(out, "COV_REF_FRAME", opm.cov_ref_frame);
    for (int r = 0; r < 6; ++r)
      for (int j = 0; j <= r; ++j)
        put(out, cov_key(r, j), num(c(r, j), "covariance") + " [" + cov_unit(r, j) + "]");
  } else if (!opm.cov_ref_frame.empty()) {
    throw std::invalid_argument("cov_ref_frame: set without a covariance");
  }
  for (std::size_t i = 0; i < opm.maneuvers.size(); ++i) {
    const OpmManeuver& m = opm.maneuvers[i];
    const std::string at = "maneuvers[" + std::to_string(i) + "]";
    out << "\n";
    detail::put_comments(out, m.comments);
    put(out, "MAN_EPOCH_IGNITION", detail::epoch_or_time(m.epoch_ignition, m.ignition_time, opm.time_system));
    put(out, "MAN_DURATION", num(m.duration, at + ".duration") + " [s]");
    put(out, "MAN_DELTA_MASS", num(m.delta_mass, at + ".delta_mass") + " [kg]");
    put(out, "MAN_REF_FRAME", m.ref_frame);
    for (int j = 0; j < 3; ++j)
      put(out, "MAN_DV_" + std::to_string(j + 1), num(m.dv(j), at + ".dv") + " [km/s]");
  }
  if (!opm.user_defined.empty()) out << "\n";
  for (const auto& [k, v] : opm.user_defined) put(out, "USER_DEFINED_" + k, v);
  return detail::read_back_checked(out.str(), "opm", "OPM", [](const std::string& t, const std::string& src) {
    return parse_opm(t, src);
  });
}

void write_opm(const std::string& path, const Opm& opm) { detail::write_file(path, format_opm(opm)); }

void write_opm(const std::string& path, const Opm& opm, bool xml) {
  detail::write_file(path, xml ? format_opm_xml(opm) : format_opm(opm));
}

}  // namespace satgnc::io
