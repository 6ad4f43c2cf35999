#pragma once
// Private to the io room: the OEM reader on KVN lines (oem.cpp) and the XML front end (oem_xml.cpp).
#include <string>
#include <vector>

#include "kvn.hpp"
#include "satgnc/io/oem.hpp"

namespace satgnc::io::detail {

/// The OEM of KVN lines (tokenize_kvn's, or synthesized from XML with the XML's line numbers).
Oem parse_oem_lines(const std::vector<KvnLine>& lines, const std::string& source);
/// Parse OEM XML: converts the elements into KVN lines, then parse_oem_lines.
Oem parse_oem_xml(const std::string& text, const std::string& source);

}  // namespace satgnc::io::detail
