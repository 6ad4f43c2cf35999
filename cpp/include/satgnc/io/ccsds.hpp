#pragma once
/// @file ccsds.hpp
/// What the CCSDS Navigation Data Messages of the io room share: the error a malformed file raises
/// (FormatError: file, line, keyword), the supported time systems and the header. Epochs are kept
/// twice: as the file's text (CCSDS ASCII time code A `YYYY-MM-DDThh:mm:ss[.f][Z]` or B
/// `YYYY-DDDThh:mm:ss[.f][Z]`) and as a core::Epoch read in the segment's TIME_SYSTEM (a UTC
/// 23:59:60.x is valid only on a leap-second day). Writers print the text, or the Epoch (ISO-8601,
/// up to 12 fraction digits, trailing zeros dropped) when the text is empty.
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "satgnc/core/epoch.hpp"

namespace satgnc::io {

/// A malformed CCSDS file. what() reads "<file>:<line>: <keyword>: <rule>" ("<file>: <keyword>:
/// <rule>" when no single line is at fault, line() == 0).
class FormatError : public std::invalid_argument {
 public:
  /// @param file the file name (or the source name given to a parse_* function)
  /// @param line 1-based line number, 0 when no single line is at fault
  /// @param keyword the keyword at fault (e.g. "PATH", "RANGE_UNITS")
  /// @param rule what is wrong, with a hint where one helps
  FormatError(std::string file, int line, std::string keyword, std::string rule);
  /// The file name or source name.
  const std::string& file() const noexcept { return file_; }
  /// 1-based line number, 0 when no single line is at fault.
  int line() const noexcept { return line_; }
  /// The keyword at fault.
  const std::string& keyword() const noexcept { return keyword_; }
  /// The rule broken (without file, line and keyword).
  const std::string& rule() const noexcept { return rule_; }

 private:
  std::string file_;
  int line_;
  std::string keyword_;
  std::string rule_;
};

/// TIME_SYSTEM values this room reads and writes: the scales of core::Epoch (UTC, TAI, TT, GPS,
/// TDB). Other values of the CCSDS time-system table (UT1, TCB, TCG, GMST, MET, MRT, SCLK) are
/// refused as unsupported.
using TimeSystem = core::TimeScale;

/// "UTC", "TAI", "TT", "GPS" or "TDB".
inline const char* time_system_name(TimeSystem ts) noexcept { return core::time_scale_name(ts); }

/// The ISO-8601 text the writers print for an epoch given only as a core::Epoch: up to 12 fraction
/// digits (1 ps), trailing zeros and a bare '.' dropped; 23:59:60.x inside a UTC leap second.
std::string epoch_text(const core::Epoch& time, TimeSystem ts);

/// A keyword = value pair kept as read (keywords the room validates but does not model).
using KeyValue = std::pair<std::string, std::string>;

/// The header of an ODM (OEM, OPM) or a TDM.
struct Header {
  std::string version = "2.0";        ///< CCSDS_xxx_VERS (written as given; read: "1.0", "2.0" or "3.0")
  std::vector<std::string> comments;  ///< header COMMENT lines
  std::string classification;         ///< CLASSIFICATION (optional, version 3 ODM), "" when absent
  std::string creation_date;          ///< CREATION_DATE (mandatory), as in the file
  std::string originator;             ///< ORIGINATOR (mandatory)
  std::string message_id;             ///< MESSAGE_ID (optional), "" when absent
};

}  // namespace satgnc::io
