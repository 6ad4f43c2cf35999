#pragma once
// Private helpers of the io room's NDM/XML readers and writers (CCSDS 505.0-B, pugixml): XML line
// numbers, the root every message checks, and the declaration, root and header every writer prints.
#include <pugixml.hpp>
#include <string>
#include <vector>

#include "kvn.hpp"

namespace satgnc::io::detail {

/// 1-based line numbers of the nodes of a parsed `text` (0 when pugixml kept no offset).
struct XmlLines {
  const std::string& text;
  int of(const pugi::xml_node& n) const;
};

/// The element's text, trimmed.
std::string value_of(const pugi::xml_node& n);
/// Whether the element is named `name`.
bool is(const pugi::xml_node& n, const char* name);
/// The child elements of `n` in order (COMMENTs included).
std::vector<pugi::xml_node> elements(const pugi::xml_node& n);
/// A KVN line made from an XML element, for the readers that feed the KVN rules.
KvnLine kvn_line(KvnLine::Kind kind, const std::string& key, const std::string& value, int line);

/// Parse `text` into `doc` and return its root element. FormatError naming the line: "XML" when the
/// text is not well-formed, the root's name when it is not <root_name>.
pugi::xml_node load_ndm(pugi::xml_document& doc, const std::string& text, const std::string& source,
                        const char* root_name);

/// Writer: <name>value</name> appended to `parent`; leaf_opt writes nothing for an empty value.
void leaf(pugi::xml_node parent, const char* name, const std::string& value);
void leaf_opt(pugi::xml_node parent, const char* name, const std::string& value);
/// Writer: the XML declaration, the <root_name> element (NDM/XML 2.0 unqualified schema, id, the
/// header's version) and its <header> (comments, CLASSIFICATION when set, CREATION_DATE, ORIGINATOR,
/// MESSAGE_ID when set). Returns the root.
pugi::xml_node put_ndm_root(pugi::xml_document& doc, const char* root_name, const char* id, const Header& h);
/// Writer: OBJECT_NAME, OBJECT_ID, CENTER_NAME, REF_FRAME, REF_FRAME_EPOCH (when set), TIME_SYSTEM: the
/// object metadata OEM and OPM share (put_object is the KVN twin).
void leaf_object(pugi::xml_node m, const ObjectMetadata& o);
/// Writer: the document's text, two-space indent, UTF-8.
std::string ndm_text(const pugi::xml_document& doc);

}  // namespace satgnc::io::detail
