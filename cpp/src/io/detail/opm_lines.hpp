#pragma once
// Private to the io room: the OPM reader on KVN lines (opm.cpp) and the XML front end (opm_xml.cpp).
#include <string>
#include <vector>

#include "kvn.hpp"
#include "satgnc/io/opm.hpp"

namespace satgnc::io::detail {

/// The OPM of KVN lines (tokenize_kvn's, or synthesized from XML with the XML's line numbers).
Opm parse_opm_lines(const std::vector<KvnLine>& lines, const std::string& source);
/// Parse OPM XML: converts the elements into KVN lines, then parse_opm_lines.
Opm parse_opm_xml(const std::string& text, const std::string& source);

}  // namespace satgnc::io::detail
