// OPM in XML (the NDM/XML layout of CCSDS 505.0-B, unqualified schema 2.0): reader and writer on
// pugixml. The reader flattens the groups into the KEYWORD = value lines the KVN reader takes (with
// the XML's line numbers), so both encodings obey the same rules and messages; it also checks that each
// element sits in its group.
#include <algorithm>
#include <cstring>
#include <pugixml.hpp>
#include <sstream>

#include "detail/kvn.hpp"
#include "detail/opm_lines.hpp"
#include "detail/xml.hpp"
#include "satgnc/io/opm.hpp"

namespace satgnc::io {
namespace detail {

namespace {

constexpr const char* kAxis[6] = {"X", "Y", "Z", "X_DOT", "Y_DOT", "Z_DOT"};

std::string cov_name(int r, int c) { return std::string("C") + kAxis[r] + "_" + kAxis[c]; }

struct Group {
  const char* element;
  std::vector<std::string> keys;
};

const std::vector<Group>& groups() {
  static const std::vector<Group> g = [] {
    std::vector<std::string> cov = {"COV_REF_FRAME"};
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c <= r; ++c) cov.push_back(cov_name(r, c));
    return std::vector<Group>{
        {"stateVector", {"EPOCH", "X", "Y", "Z", "X_DOT", "Y_DOT", "Z_DOT"}},
        {"keplerianElements",
         {"SEMI_MAJOR_AXIS", "ECCENTRICITY", "INCLINATION", "RA_OF_ASC_NODE", "ARG_OF_PERICENTER",
          "TRUE_ANOMALY", "MEAN_ANOMALY", "GM"}},
        {"spacecraftParameters", {"MASS", "SOLAR_RAD_AREA", "SOLAR_RAD_COEFF", "DRAG_AREA", "DRAG_COEFF"}},
        {"covarianceMatrix", cov},
        {"maneuverParameters",
         {"MAN_EPOCH_IGNITION", "MAN_DURATION", "MAN_DELTA_MASS", "MAN_REF_FRAME", "MAN_DV_1", "MAN_DV_2",
          "MAN_DV_3"}},
    };
  }();
  return g;
}

}  // namespace

Opm parse_opm_xml(const std::string& text, const std::string& source) {
  using K = KvnLine::Kind;
  pugi::xml_document doc;
  const pugi::xml_node root = load_ndm(doc, text, source, "opm");
  const XmlLines lm{text};
  std::vector<KvnLine> lines;
  lines.push_back(
      kvn_line(K::key_value, "CCSDS_OPM_VERS", root.attribute("version").as_string(), lm.of(root)));
  auto leaf = [&](const pugi::xml_node& n) {
    lines.push_back(is(n, "COMMENT") ? kvn_line(K::comment, "", value_of(n), lm.of(n))
                                     : kvn_line(K::key_value, n.name(), value_of(n), lm.of(n)));
  };
  const pugi::xml_node header = root.child("header");
  if (!header) fail(source, lm.of(root), "header", "missing <header>");
  for (const pugi::xml_node& n : elements(header)) leaf(n);
  const pugi::xml_node body = root.child("body");
  if (!body) fail(source, lm.of(root), "body", "missing <body>");
  const std::vector<pugi::xml_node> segs = elements(body);
  if (segs.size() != 1 || !is(segs[0], "segment"))
    fail(source, lm.of(body), "segment", "an OPM <body> holds exactly one <segment>");
  const pugi::xml_node meta = segs[0].child("metadata");
  if (!meta) fail(source, lm.of(segs[0]), "metadata", "missing <metadata> in <segment>");
  for (const pugi::xml_node& n : elements(meta)) leaf(n);
  const pugi::xml_node data = segs[0].child("data");
  if (!data) fail(source, lm.of(segs[0]), "data", "missing <data> in <segment>");
  for (const pugi::xml_node& g : elements(data)) {
    if (is(g, "COMMENT")) {
      leaf(g);
      continue;
    }
    if (is(g, "userDefinedParameters")) {
      for (const pugi::xml_node& u : elements(g)) {
        if (is(u, "COMMENT")) continue;
        const std::string p = u.attribute("parameter").as_string();
        if (!is(u, "USER_DEFINED") || p.empty())
          fail(source, lm.of(u), u.name(), "expected <USER_DEFINED parameter=\"NAME\">");
        lines.push_back(kvn_line(K::key_value, "USER_DEFINED_" + p, value_of(u), lm.of(u)));
      }
      continue;
    }
    const Group* grp = nullptr;
    for (const Group& c : groups())
      if (is(g, c.element)) grp = &c;
    if (grp == nullptr)
      fail(source, lm.of(g), g.name(),
           "unexpected element in <data> (hint: stateVector, keplerianElements, spacecraftParameters, "
           "covarianceMatrix, maneuverParameters, userDefinedParameters)");
    for (const pugi::xml_node& n : elements(g)) {
      if (!is(n, "COMMENT") && std::find(grp->keys.begin(), grp->keys.end(), n.name()) == grp->keys.end())
        fail(source, lm.of(n), n.name(), std::string("unexpected in <") + grp->element + ">");
      leaf(n);
    }
  }
  return parse_opm_lines(lines, source);
}

}  // namespace detail

namespace {
void leaf(pugi::xml_node parent, const char* name, const std::string& value, const char* units = nullptr) {
  pugi::xml_node n = parent.append_child(name);
  if (units != nullptr) n.append_attribute("units") = units;
  n.append_child(pugi::node_pcdata).set_value(value.c_str());
}
}  // namespace

std::string format_opm_xml(const Opm& opm) {
  // The KVN writer checks the model's rules (anomalies, covariance symmetry, ...): run it first.
  (void)format_opm(opm);
  auto num = [](double v, const std::string& name) { return detail::format_number(v, name); };
  pugi::xml_document doc;
  pugi::xml_node root = detail::put_ndm_root(doc, "opm", "CCSDS_OPM_VERS", opm.header);
  pugi::xml_node seg = root.append_child("body").append_child("segment");
  pugi::xml_node m = seg.append_child("metadata");
  for (const auto& c : opm.metadata_comments) leaf(m, "COMMENT", c);
  detail::leaf_object(m, {opm.object_name, opm.object_id, opm.center_name, opm.ref_frame, opm.ref_frame_epoch,
                          opm.time_system});
  pugi::xml_node d = seg.append_child("data");
  for (const auto& c : opm.data_comments) leaf(d, "COMMENT", c);
  pugi::xml_node sv = d.append_child("stateVector");
  leaf(sv, "EPOCH", detail::epoch_or_time(opm.epoch, opm.time, opm.time_system));
  for (int j = 0; j < 6; ++j) leaf(sv, detail::kAxis[j], num(opm.state(j), "state"), j < 3 ? "km" : "km/s");
  if (opm.keplerian) {
    const OpmKeplerian& e = *opm.keplerian;
    pugi::xml_node k = d.append_child("keplerianElements");
    leaf(k, "SEMI_MAJOR_AXIS", num(e.semi_major_axis, "keplerian.semi_major_axis"), "km");
    leaf(k, "ECCENTRICITY", num(e.eccentricity, "keplerian.eccentricity"));
    leaf(k, "INCLINATION", num(e.inclination, "keplerian.inclination"), "deg");
    leaf(k, "RA_OF_ASC_NODE", num(e.ra_of_asc_node, "keplerian.ra_of_asc_node"), "deg");
    leaf(k, "ARG_OF_PERICENTER", num(e.arg_of_pericenter, "keplerian.arg_of_pericenter"), "deg");
    if (e.true_anomaly) leaf(k, "TRUE_ANOMALY", num(*e.true_anomaly, "keplerian.true_anomaly"), "deg");
    if (e.mean_anomaly) leaf(k, "MEAN_ANOMALY", num(*e.mean_anomaly, "keplerian.mean_anomaly"), "deg");
    leaf(k, "GM", num(e.gm, "keplerian.gm"), "km**3/s**2");
  }
  if (opm.spacecraft) {
    const OpmSpacecraft& p = *opm.spacecraft;
    pugi::xml_node s = d.append_child("spacecraftParameters");
    if (p.mass) leaf(s, "MASS", num(*p.mass, "spacecraft.mass"), "kg");
    if (p.solar_rad_area)
      leaf(s, "SOLAR_RAD_AREA", num(*p.solar_rad_area, "spacecraft.solar_rad_area"), "m**2");
    if (p.solar_rad_coeff) leaf(s, "SOLAR_RAD_COEFF", num(*p.solar_rad_coeff, "spacecraft.solar_rad_coeff"));
    if (p.drag_area) leaf(s, "DRAG_AREA", num(*p.drag_area, "spacecraft.drag_area"), "m**2");
    if (p.drag_coeff) leaf(s, "DRAG_COEFF", num(*p.drag_coeff, "spacecraft.drag_coeff"));
  }
  if (opm.covariance) {
    pugi::xml_node c = d.append_child("covarianceMatrix");
    if (!opm.cov_ref_frame.empty()) leaf(c, "COV_REF_FRAME", opm.cov_ref_frame);
    for (int r = 0; r < 6; ++r)
      for (int j = 0; j <= r; ++j)
        leaf(c, detail::cov_name(r, j).c_str(), num((*opm.covariance)(r, j), "covariance"));
  }
  for (std::size_t i = 0; i < opm.maneuvers.size(); ++i) {
    const OpmManeuver& mv = opm.maneuvers[i];
    const std::string at = "maneuvers[" + std::to_string(i) + "]";
    pugi::xml_node x = d.append_child("maneuverParameters");
    for (const auto& c : mv.comments) leaf(x, "COMMENT", c);
    leaf(x, "MAN_EPOCH_IGNITION",
         detail::epoch_or_time(mv.epoch_ignition, mv.ignition_time, opm.time_system));
    leaf(x, "MAN_DURATION", num(mv.duration, at + ".duration"), "s");
    leaf(x, "MAN_DELTA_MASS", num(mv.delta_mass, at + ".delta_mass"), "kg");
    leaf(x, "MAN_REF_FRAME", mv.ref_frame);
    for (int j = 0; j < 3; ++j)
      leaf(x, ("MAN_DV_" + std::to_string(j + 1)).c_str(), num(mv.dv(j), at + ".dv"), "km/s");
  }
  if (!opm.user_defined.empty()) {
    pugi::xml_node u = d.append_child("userDefinedParameters");
    for (const auto& [k, v] : opm.user_defined) {
      pugi::xml_node n = u.append_child("USER_DEFINED");
      n.append_attribute("parameter") = k.c_str();
      n.append_child(pugi::node_pcdata).set_value(v.c_str());
    }
  }
  return detail::read_back_checked(
      detail::ndm_text(doc), "opm", "OPM",
      [](const std::string& t, const std::string& src) { return detail::parse_opm_xml(t, src); });
}

}  // namespace satgnc::io
