// The io room's shared NDM/XML pieces (detail/xml.hpp).
#include "detail/xml.hpp"

#include <algorithm>
#include <cstring>
#include <sstream>

namespace satgnc::io::detail {

int XmlLines::of(const pugi::xml_node& n) const {
  const std::ptrdiff_t off = n.offset_debug();
  if (off < 0) return 0;
  const auto end = text.begin() + std::min<std::ptrdiff_t>(off, static_cast<std::ptrdiff_t>(text.size()));
  return 1 + static_cast<int>(std::count(text.begin(), end, '\n'));
}

std::string value_of(const pugi::xml_node& n) { return trim(n.child_value()); }

bool is(const pugi::xml_node& n, const char* name) { return std::strcmp(n.name(), name) == 0; }

std::vector<pugi::xml_node> elements(const pugi::xml_node& n) {
  std::vector<pugi::xml_node> out;
  for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling())
    if (c.type() == pugi::node_element) out.push_back(c);
  return out;
}

KvnLine kvn_line(KvnLine::Kind kind, const std::string& key, const std::string& value, int line) {
  KvnLine l;
  l.kind = kind;
  l.key = key;
  l.value = value;
  l.line = line;
  return l;
}

pugi::xml_node load_ndm(pugi::xml_document& doc, const std::string& text, const std::string& source,
                        const char* root_name) {
  const pugi::xml_parse_result r = doc.load_buffer(text.data(), text.size(), pugi::parse_default);
  if (!r) {
    const auto end =
        text.begin() + std::min<std::ptrdiff_t>(r.offset, static_cast<std::ptrdiff_t>(text.size()));
    fail(source, 1 + static_cast<int>(std::count(text.begin(), end, '\n')), "XML",
         std::string("not well-formed XML: ") + r.description());
  }
  const pugi::xml_node root = doc.document_element();
  if (!is(root, root_name))
    fail(source, XmlLines{text}.of(root), root.name(),
         std::string("the root element must be <") + root_name + ">");
  return root;
}

void leaf(pugi::xml_node parent, const char* name, const std::string& value) {
  parent.append_child(name).append_child(pugi::node_pcdata).set_value(value.c_str());
}

void leaf_opt(pugi::xml_node parent, const char* name, const std::string& value) {
  if (!value.empty()) leaf(parent, name, value);
}

pugi::xml_node put_ndm_root(pugi::xml_document& doc, const char* root_name, const char* id, const Header& h) {
  pugi::xml_node decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version") = "1.0";
  decl.append_attribute("encoding") = "UTF-8";
  pugi::xml_node root = doc.append_child(root_name);
  root.append_attribute("xmlns:xsi") = "http://www.w3.org/2001/XMLSchema-instance";
  root.append_attribute("xsi:noNamespaceSchemaLocation") =
      "https://sanaregistry.org/r/ndmxml_unqualified/ndmxml-2.0.0-master-2.0.xsd";
  root.append_attribute("id") = id;
  root.append_attribute("version") = h.version.c_str();
  pugi::xml_node x = root.append_child("header");
  for (const auto& c : h.comments) leaf(x, "COMMENT", c);
  leaf_opt(x, "CLASSIFICATION", h.classification);
  leaf(x, "CREATION_DATE", h.creation_date);
  leaf(x, "ORIGINATOR", h.originator);
  leaf_opt(x, "MESSAGE_ID", h.message_id);
  return root;
}

void leaf_object(pugi::xml_node m, const ObjectMetadata& o) {
  leaf(m, "OBJECT_NAME", o.object_name);
  leaf(m, "OBJECT_ID", o.object_id);
  leaf(m, "CENTER_NAME", o.center_name);
  leaf(m, "REF_FRAME", o.ref_frame);
  leaf_opt(m, "REF_FRAME_EPOCH", o.ref_frame_epoch);
  leaf(m, "TIME_SYSTEM", time_system_name(o.time_system));
}

std::string ndm_text(const pugi::xml_document& doc) {
  std::ostringstream out;
  doc.save(out, "  ", pugi::format_default, pugi::encoding_utf8);
  return out.str();
}

}  // namespace satgnc::io::detail
