// TDM in XML (the NDM/XML layout of CCSDS 505.0-B, unqualified schema 2.0): reader and writer on
// pugixml (Debian libpugixml-dev). The reader feeds the same TdmBuilder as the KVN reader.
#include <algorithm>
#include <pugixml.hpp>
#include <sstream>

#include "detail/kvn.hpp"
#include "detail/tdm_builder.hpp"
#include "detail/xml.hpp"
#include "satgnc/io/tdm.hpp"

namespace satgnc::io {
namespace detail {

Tdm parse_tdm_xml(const std::string& text, const std::string& source) {
  pugi::xml_document doc;
  const pugi::xml_node root = load_ndm(doc, text, source, "tdm");
  const XmlLines lm{text};
  TdmBuilder b(source);
  b.version(root.attribute("version").as_string(), lm.of(root));
  const pugi::xml_node header = root.child("header");
  if (!header) fail(source, lm.of(root), "header", "missing <header>");
  for (const pugi::xml_node& n : elements(header)) {
    if (is(n, "COMMENT"))
      b.header_comment(value_of(n));
    else
      b.header(n.name(), value_of(n), lm.of(n));
  }
  const pugi::xml_node body = root.child("body");
  if (!body) fail(source, lm.of(root), "body", "missing <body>");
  int last = lm.of(body);
  for (const pugi::xml_node& seg : elements(body)) {
    if (!is(seg, "segment"))
      fail(source, lm.of(seg), seg.name(), "unexpected element in <body> (hint: <segment>)");
    b.begin_segment(lm.of(seg));
    const pugi::xml_node meta = seg.child("metadata");
    if (!meta) fail(source, lm.of(seg), "metadata", "missing <metadata> in <segment>");
    for (const pugi::xml_node& n : elements(meta)) {
      if (is(n, "COMMENT"))
        b.meta_comment(value_of(n));
      else
        b.meta(n.name(), value_of(n), lm.of(n));
    }
    b.end_meta(lm.of(meta));
    const pugi::xml_node data = seg.child("data");
    if (!data) fail(source, lm.of(seg), "data", "missing <data> in <segment>");
    for (const pugi::xml_node& n : elements(data)) {
      if (is(n, "COMMENT")) {
        b.data_comment(value_of(n));
        continue;
      }
      const int line = lm.of(n);
      last = line;
      if (!is(n, "observation"))
        fail(source, line, n.name(), "unexpected element in <data> (hint: <observation>)");
      const pugi::xml_node epoch = n.child("EPOCH");
      if (!epoch) fail(source, line, "EPOCH", "missing in <observation>");
      pugi::xml_node value;
      for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling())
        if (c.type() == pugi::node_element && !is(c, "EPOCH")) {
          if (value) fail(source, lm.of(c), c.name(), "an <observation> holds one value");
          value = c;
        }
      if (!value) fail(source, line, "observation", "no value after EPOCH");
      b.observation(value.name(), value_of(epoch), value_of(value), lm.of(value));
    }
  }
  return b.finish(last);
}

}  // namespace detail

using detail::leaf;
using detail::leaf_opt;

std::string format_tdm_xml(const Tdm& tdm) {
  pugi::xml_document doc;
  pugi::xml_node root = detail::put_ndm_root(doc, "tdm", "CCSDS_TDM_VERS", tdm.header);
  pugi::xml_node body = root.append_child("body");
  for (std::size_t s = 0; s < tdm.segments.size(); ++s) {
    const TdmSegment& seg = tdm.segments[s];
    const TdmMetadata& m = seg.metadata;
    pugi::xml_node sx = body.append_child("segment");
    pugi::xml_node mx = sx.append_child("metadata");
    for (const auto& c : m.comments) leaf(mx, "COMMENT", c);
    leaf(mx, "TIME_SYSTEM", time_system_name(m.time_system));
    leaf_opt(mx, "START_TIME", m.start_time);
    leaf_opt(mx, "STOP_TIME", m.stop_time);
    for (std::size_t i = 0; i < m.participants.size(); ++i)
      leaf(mx, ("PARTICIPANT_" + std::to_string(i + 1)).c_str(), m.participants[i]);
    leaf_opt(mx, "MODE", m.mode);
    if (!m.path.empty()) {
      std::string p;
      for (std::size_t i = 0; i < m.path.size(); ++i) p += (i ? "," : "") + std::to_string(m.path[i]);
      leaf(mx, "PATH", p);
    }
    if (m.integration_interval)
      leaf(mx, "INTEGRATION_INTERVAL",
           detail::format_number(*m.integration_interval,
                                 "segments[" + std::to_string(s) + "].integration_interval"));
    leaf_opt(mx, "INTEGRATION_REF", m.integration_ref);
    leaf_opt(mx, "RANGE_UNITS", m.range_units);
    leaf_opt(mx, "ANGLE_TYPE", m.angle_type);
    for (const auto& [k, v] : m.other) leaf(mx, k.c_str(), v);
    pugi::xml_node dx = sx.append_child("data");
    for (const auto& c : seg.data_comments) leaf(dx, "COMMENT", c);
    for (std::size_t i = 0; i < seg.observations.size(); ++i) {
      const TdmObservation& o = seg.observations[i];
      pugi::xml_node ox = dx.append_child("observation");
      leaf(ox, "EPOCH", detail::epoch_or_time(o.epoch, o.time, m.time_system));
      leaf(ox, o.keyword.c_str(),
           detail::format_number(
               o.value, "segments[" + std::to_string(s) + "].observations[" + std::to_string(i) + "].value"));
    }
  }
  return detail::read_back_checked(
      detail::ndm_text(doc), "tdm", "TDM",
      [](const std::string& t, const std::string& src) { return detail::parse_tdm_xml(t, src); });
}

}  // namespace satgnc::io
