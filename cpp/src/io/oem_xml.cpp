// OEM in XML (the NDM/XML layout of CCSDS 505.0-B, unqualified schema 2.0): reader and writer on
// pugixml. The reader turns the elements into the KVN lines the KVN reader takes (with the XML's line
// numbers), so both encodings obey the same rules and name the same keywords in their errors.
#include <algorithm>
#include <array>
#include <cstring>
#include <pugixml.hpp>
#include <sstream>

#include "detail/kvn.hpp"
#include "detail/oem_lines.hpp"
#include "detail/xml.hpp"
#include "satgnc/io/oem.hpp"

namespace satgnc::io {
namespace detail {

namespace {

constexpr std::array<const char*, 6> kState = {"X", "Y", "Z", "X_DOT", "Y_DOT", "Z_DOT"};
constexpr std::array<const char*, 3> kAccel = {"X_DDOT", "Y_DDOT", "Z_DDOT"};
constexpr std::array<const char*, 6> kCovAxis = {"X", "Y", "Z", "X_DOT", "Y_DOT", "Z_DOT"};

std::string cov_name(int r, int c) { return std::string("C") + kCovAxis[r] + "_" + kCovAxis[c]; }

using K = KvnLine::Kind;
KvnLine kv(const std::string& key, const std::string& value, int line) {
  return kvn_line(K::key_value, key, value, line);
}
KvnLine marker(const std::string& key, int line) { return kvn_line(K::marker, key, "", line); }
KvnLine raw(const std::string& value, int line) { return kvn_line(K::raw, "", value, line); }
KvnLine comment(const std::string& value, int line) { return kvn_line(K::comment, "", value, line); }

}  // namespace

Oem parse_oem_xml(const std::string& text, const std::string& source) {
  pugi::xml_document doc;
  const pugi::xml_node root = load_ndm(doc, text, source, "oem");
  const XmlLines lm{text};
  std::vector<KvnLine> lines;
  lines.push_back(kv("CCSDS_OEM_VERS", root.attribute("version").as_string(), lm.of(root)));
  const pugi::xml_node header = root.child("header");
  if (!header) fail(source, lm.of(root), "header", "missing <header>");
  for (const pugi::xml_node& n : elements(header))
    lines.push_back(is(n, "COMMENT") ? comment(value_of(n), lm.of(n)) : kv(n.name(), value_of(n), lm.of(n)));
  const pugi::xml_node body = root.child("body");
  if (!body) fail(source, lm.of(root), "body", "missing <body>");
  for (const pugi::xml_node& seg : elements(body)) {
    if (!is(seg, "segment"))
      fail(source, lm.of(seg), seg.name(), "unexpected element in <body> (hint: <segment>)");
    const pugi::xml_node meta = seg.child("metadata");
    if (!meta) fail(source, lm.of(seg), "metadata", "missing <metadata> in <segment>");
    lines.push_back(marker("META_START", lm.of(meta)));
    for (const pugi::xml_node& n : elements(meta))
      lines.push_back(is(n, "COMMENT") ? comment(value_of(n), lm.of(n))
                                       : kv(n.name(), value_of(n), lm.of(n)));
    lines.push_back(marker("META_STOP", lm.of(meta)));
    const pugi::xml_node data = seg.child("data");
    if (!data) fail(source, lm.of(seg), "data", "missing <data> in <segment>");
    bool in_cov = false;
    int last = lm.of(data);
    for (const pugi::xml_node& n : elements(data)) {
      const int line = lm.of(n);
      last = line;
      if (is(n, "COMMENT")) {
        lines.push_back(comment(value_of(n), line));
      } else if (is(n, "stateVector")) {
        // EPOCH, X, Y, Z, X_DOT, Y_DOT, Z_DOT[, X_DDOT, Y_DDOT, Z_DDOT], in this order.
        const std::vector<pugi::xml_node> e = elements(n);
        if (e.empty() || !is(e[0], "EPOCH")) fail(source, line, "EPOCH", "missing first in <stateVector>");
        if (e.size() != 7 && e.size() != 10)
          fail(source, line, "stateVector",
               "needs EPOCH and 6 components (or 9 with accelerations), got " + std::to_string(e.size()) +
                   " elements");
        std::string joined = value_of(e[0]);
        for (std::size_t j = 1; j < e.size(); ++j) {
          const char* want = j <= 6 ? kState[j - 1] : kAccel[j - 7];
          if (!is(e[j], want))
            fail(source, lm.of(e[j]), e[j].name(),
                 std::string("unexpected in <stateVector> (hint: ") + want + ")");
          const std::string v = value_of(e[j]);
          if (v.empty() || v.find_first_of(" \t\r\n") != std::string::npos)
            fail(source, lm.of(e[j]), want, "must hold one number");
          joined += " " + v;
        }
        lines.push_back(raw(joined, line));
      } else if (is(n, "covarianceMatrix")) {
        if (!in_cov) lines.push_back(marker("COVARIANCE_START", line));
        in_cov = true;
        const pugi::xml_node epoch = n.child("EPOCH");
        if (!epoch) fail(source, line, "EPOCH", "missing in <covarianceMatrix>");
        for (const pugi::xml_node& c : elements(n))
          if (is(c, "COMMENT")) lines.push_back(comment(value_of(c), lm.of(c)));
        lines.push_back(kv("EPOCH", value_of(epoch), lm.of(epoch)));
        if (const pugi::xml_node f = n.child("COV_REF_FRAME"))
          lines.push_back(kv("COV_REF_FRAME", value_of(f), lm.of(f)));
        for (const pugi::xml_node& c : elements(n)) {
          if (is(c, "COMMENT") || is(c, "EPOCH") || is(c, "COV_REF_FRAME")) continue;
          bool known = false;
          for (int a = 0; a < 6 && !known; ++a)
            for (int b = 0; b <= a && !known; ++b) known = cov_name(a, b) == c.name();
          if (!known)
            fail(source, lm.of(c), c.name(), "unexpected in <covarianceMatrix> (hint: CX_X .. CZ_DOT_Z_DOT)");
        }
        for (int a = 0; a < 6; ++a) {
          std::string row;
          int row_line = line;
          for (int b = 0; b <= a; ++b) {
            const std::string name = cov_name(a, b);
            const pugi::xml_node c = n.child(name.c_str());
            if (!c) fail(source, line, name, "missing in <covarianceMatrix>");
            row += (b ? " " : "") + value_of(c);
            row_line = lm.of(c);
          }
          lines.push_back(raw(row, row_line));
        }
      } else {
        fail(source, line, n.name(),
             "unexpected element in <data> (hint: <stateVector>, <covarianceMatrix>)");
      }
    }
    if (in_cov) lines.push_back(marker("COVARIANCE_STOP", last));
  }
  return parse_oem_lines(lines, source);
}

}  // namespace detail

using detail::leaf;
using detail::leaf_opt;

std::string format_oem_xml(const Oem& oem) {
  pugi::xml_document doc;
  pugi::xml_node root = detail::put_ndm_root(doc, "oem", "CCSDS_OEM_VERS", oem.header);
  pugi::xml_node body = root.append_child("body");
  for (std::size_t s = 0; s < oem.segments.size(); ++s) {
    const OemSegment& seg = oem.segments[s];
    const OemMetadata& m = seg.metadata;
    const std::string at = "segments[" + std::to_string(s) + "]";
    pugi::xml_node sx = body.append_child("segment");
    pugi::xml_node mx = sx.append_child("metadata");
    for (const auto& c : m.comments) leaf(mx, "COMMENT", c);
    detail::leaf_object(
        mx, {m.object_name, m.object_id, m.center_name, m.ref_frame, m.ref_frame_epoch, m.time_system});
    leaf(mx, "START_TIME", m.start_time);
    leaf_opt(mx, "USEABLE_START_TIME", m.useable_start_time);
    leaf_opt(mx, "USEABLE_STOP_TIME", m.useable_stop_time);
    leaf(mx, "STOP_TIME", m.stop_time);
    leaf_opt(mx, "INTERPOLATION", m.interpolation);
    if (m.interpolation_degree) leaf(mx, "INTERPOLATION_DEGREE", std::to_string(*m.interpolation_degree));
    pugi::xml_node dx = sx.append_child("data");
    for (const auto& c : seg.data_comments) leaf(dx, "COMMENT", c);
    for (std::size_t i = 0; i < seg.states.size(); ++i) {
      const OemState& st = seg.states[i];
      const std::string name = at + ".states[" + std::to_string(i) + "]";
      pugi::xml_node sv = dx.append_child("stateVector");
      leaf(sv, "EPOCH", detail::epoch_or_time(st.epoch, st.time, m.time_system));
      for (int j = 0; j < 6; ++j)
        leaf(sv, detail::kState[j], detail::format_number(st.state(j), name + ".state"));
      if (st.acceleration)
        for (int j = 0; j < 3; ++j)
          leaf(sv, detail::kAccel[j], detail::format_number((*st.acceleration)(j), name + ".acceleration"));
    }
    for (std::size_t c = 0; c < seg.covariances.size(); ++c) {
      const OemCovariance& cv = seg.covariances[c];
      const std::string name = at + ".covariances[" + std::to_string(c) + "].matrix";
      if (!(cv.matrix - cv.matrix.transpose()).isZero(0.0) &&
          !cv.matrix.isApprox(cv.matrix.transpose(), 1e-12))
        throw std::invalid_argument(name + ": must be symmetric");
      pugi::xml_node cx = dx.append_child("covarianceMatrix");
      for (const auto& cm : cv.comments) leaf(cx, "COMMENT", cm);
      leaf(cx, "EPOCH", detail::epoch_or_time(cv.epoch, cv.time, m.time_system));
      leaf_opt(cx, "COV_REF_FRAME", cv.cov_ref_frame);
      for (int a = 0; a < 6; ++a)
        for (int b = 0; b <= a; ++b)
          leaf(cx, detail::cov_name(a, b).c_str(), detail::format_number(cv.matrix(a, b), name));
    }
  }
  return detail::read_back_checked(
      detail::ndm_text(doc), "oem", "OEM",
      [](const std::string& t, const std::string& src) { return detail::parse_oem_xml(t, src); });
}

}  // namespace satgnc::io
