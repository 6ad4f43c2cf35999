// TDM in XML (the NDM/XML layout of CCSDS 505.0-B, unqualified schema 2.0): reader and writer on
// pugixml (Debian libpugixml-dev). The reader feeds the same TdmBuilder as the KVN reader.
#include <algorithm>
#include <cstring>
#include <pugixml.hpp>
#include <sstream>

#include "detail/kvn.hpp"
#include "detail/tdm_builder.hpp"
#include "satgnc/io/tdm.hpp"

namespace satgnc::io {
namespace detail {

namespace {

struct LineMap {
  const std::string& text;
  int line_of(const pugi::xml_node& n) const {
    const std::ptrdiff_t off = n.offset_debug();
    if (off < 0) return 0;
    const auto end = text.begin() + std::min<std::ptrdiff_t>(off, static_cast<std::ptrdiff_t>(text.size()));
    return 1 + static_cast<int>(std::count(text.begin(), end, '\n'));
  }
};

std::string value_of(const pugi::xml_node& n) { return trim(n.child_value()); }

}  // namespace

Tdm parse_tdm_xml(const std::string& text, const std::string& source) {
  pugi::xml_document doc;
  const pugi::xml_parse_result r = doc.load_buffer(text.data(), text.size(), pugi::parse_default);
  const LineMap lm{text};
  if (!r) {
    const auto end =
        text.begin() + std::min<std::ptrdiff_t>(r.offset, static_cast<std::ptrdiff_t>(text.size()));
    fail(source, 1 + static_cast<int>(std::count(text.begin(), end, '\n')), "XML",
         std::string("not well-formed XML: ") + r.description());
  }
  const pugi::xml_node root = doc.document_element();
  if (std::strcmp(root.name(), "tdm") != 0)
    fail(source, lm.line_of(root), root.name(), "the root element must be <tdm>");
  TdmBuilder b(source);
  b.version(root.attribute("version").as_string(), lm.line_of(root));
  const pugi::xml_node header = root.child("header");
  if (!header) fail(source, lm.line_of(root), "header", "missing <header>");
  for (pugi::xml_node n = header.first_child(); n; n = n.next_sibling()) {
    if (n.type() != pugi::node_element) continue;
    if (std::strcmp(n.name(), "COMMENT") == 0)
      b.header_comment(value_of(n));
    else
      b.header(n.name(), value_of(n), lm.line_of(n));
  }
  const pugi::xml_node body = root.child("body");
  if (!body) fail(source, lm.line_of(root), "body", "missing <body>");
  int last = lm.line_of(body);
  for (pugi::xml_node seg = body.first_child(); seg; seg = seg.next_sibling()) {
    if (seg.type() != pugi::node_element) continue;
    if (std::strcmp(seg.name(), "segment") != 0)
      fail(source, lm.line_of(seg), seg.name(), "unexpected element in <body> (hint: <segment>)");
    b.begin_segment(lm.line_of(seg));
    const pugi::xml_node meta = seg.child("metadata");
    if (!meta) fail(source, lm.line_of(seg), "metadata", "missing <metadata> in <segment>");
    for (pugi::xml_node n = meta.first_child(); n; n = n.next_sibling()) {
      if (n.type() != pugi::node_element) continue;
      if (std::strcmp(n.name(), "COMMENT") == 0)
        b.meta_comment(value_of(n));
      else
        b.meta(n.name(), value_of(n), lm.line_of(n));
    }
    b.end_meta(lm.line_of(meta));
    const pugi::xml_node data = seg.child("data");
    if (!data) fail(source, lm.line_of(seg), "data", "missing <data> in <segment>");
    for (pugi::xml_node n = data.first_child(); n; n = n.next_sibling()) {
      if (n.type() != pugi::node_element) continue;
      if (std::strcmp(n.name(), "COMMENT") == 0) {
        b.data_comment(value_of(n));
        continue;
      }
      const int line = lm.line_of(n);
      last = line;
      if (std::strcmp(n.name(), "observation") != 0)
        fail(source, line, n.name(), "unexpected element in <data> (hint: <observation>)");
      const pugi::xml_node epoch = n.child("EPOCH");
      if (!epoch) fail(source, line, "EPOCH", "missing in <observation>");
      pugi::xml_node value;
      for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling())
        if (c.type() == pugi::node_element && std::strcmp(c.name(), "EPOCH") != 0) {
          if (value) fail(source, lm.line_of(c), c.name(), "an <observation> holds one value");
          value = c;
        }
      if (!value) fail(source, line, "observation", "no value after EPOCH");
      b.observation(value.name(), value_of(epoch), value_of(value), lm.line_of(value));
    }
  }
  return b.finish(last);
}

}  // namespace detail

namespace {
void leaf(pugi::xml_node parent, const char* name, const std::string& value) {
  parent.append_child(name).append_child(pugi::node_pcdata).set_value(value.c_str());
}
}  // namespace

std::string format_tdm_xml(const Tdm& tdm) {
  pugi::xml_document doc;
  pugi::xml_node decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version") = "1.0";
  decl.append_attribute("encoding") = "UTF-8";
  pugi::xml_node root = doc.append_child("tdm");
  root.append_attribute("xmlns:xsi") = "http://www.w3.org/2001/XMLSchema-instance";
  root.append_attribute("xsi:noNamespaceSchemaLocation") =
      "https://sanaregistry.org/r/ndmxml_unqualified/ndmxml-2.0.0-master-2.0.xsd";
  root.append_attribute("id") = "CCSDS_TDM_VERS";
  root.append_attribute("version") = tdm.header.version.c_str();
  pugi::xml_node h = root.append_child("header");
  for (const auto& c : tdm.header.comments) leaf(h, "COMMENT", c);
  if (!tdm.header.classification.empty()) leaf(h, "CLASSIFICATION", tdm.header.classification);
  leaf(h, "CREATION_DATE", tdm.header.creation_date);
  leaf(h, "ORIGINATOR", tdm.header.originator);
  if (!tdm.header.message_id.empty()) leaf(h, "MESSAGE_ID", tdm.header.message_id);
  pugi::xml_node body = root.append_child("body");
  for (std::size_t s = 0; s < tdm.segments.size(); ++s) {
    const TdmSegment& seg = tdm.segments[s];
    const TdmMetadata& m = seg.metadata;
    pugi::xml_node sx = body.append_child("segment");
    pugi::xml_node mx = sx.append_child("metadata");
    for (const auto& c : m.comments) leaf(mx, "COMMENT", c);
    leaf(mx, "TIME_SYSTEM", time_system_name(m.time_system));
    if (!m.start_time.empty()) leaf(mx, "START_TIME", m.start_time);
    if (!m.stop_time.empty()) leaf(mx, "STOP_TIME", m.stop_time);
    for (std::size_t i = 0; i < m.participants.size(); ++i)
      leaf(mx, ("PARTICIPANT_" + std::to_string(i + 1)).c_str(), m.participants[i]);
    if (!m.mode.empty()) leaf(mx, "MODE", m.mode);
    if (!m.path.empty()) {
      std::string p;
      for (std::size_t i = 0; i < m.path.size(); ++i) p += (i ? "," : "") + std::to_string(m.path[i]);
      leaf(mx, "PATH", p);
    }
    if (m.integration_interval)
      leaf(mx, "INTEGRATION_INTERVAL",
           detail::format_number(*m.integration_interval,
                                 "segments[" + std::to_string(s) + "].integration_interval"));
    if (!m.integration_ref.empty()) leaf(mx, "INTEGRATION_REF", m.integration_ref);
    if (!m.range_units.empty()) leaf(mx, "RANGE_UNITS", m.range_units);
    if (!m.angle_type.empty()) leaf(mx, "ANGLE_TYPE", m.angle_type);
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
  std::ostringstream out;
  doc.save(out, "  ", pugi::format_default, pugi::encoding_utf8);
  return detail::read_back_checked(out.str(), "tdm", "TDM", [](const std::string& t, const std::string& src) {
    return detail::parse_tdm_xml(t, src);
  });
}

}  // namespace satgnc::io
