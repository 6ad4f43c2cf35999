#pragma once
// Private helpers of the io room: the KVN tokenizer, value parsers that throw FormatError naming the
// file, the line and the keyword, epoch and time-system checks, and the number formatter of the writers.
#include <initializer_list>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "satgnc/io/ccsds.hpp"

namespace satgnc::io::detail {

/// One non-blank KVN line.
struct KvnLine {
  enum class Kind { comment, key_value, marker, raw };
  Kind kind = Kind::raw;
  int line = 0;       // 1-based
  std::string key;    // key_value: the keyword; marker: the marker (META_START, ...)
  std::string value;  // key_value: the value, unit removed; comment: its text; raw: the trimmed line
  std::string unit;   // key_value: the text inside a trailing [...], "" when none
};

/// The non-blank lines of a KVN text (LF, CRLF or CR line ends; a UTF-8 byte-order mark skipped).
std::vector<KvnLine> tokenize_kvn(const std::string& text, const std::string& source);

/// Throw FormatError(source, line, keyword, rule).
[[noreturn]] void fail(const std::string& source, int line, const std::string& keyword,
                       const std::string& rule);

/// A finite double spelled in full by `text` (leading '+' allowed), else FormatError "not a number".
double parse_number(const std::string& text, const std::string& source, int line, const std::string& keyword);
/// An integer spelled in full by `text`, else FormatError.
int parse_int(const std::string& text, const std::string& source, int line, const std::string& keyword);
/// Check a CCSDS ASCII time code A or B (see ccsds.hpp); returns `text` unchanged.
const std::string& check_epoch(const std::string& text, const std::string& source, int line,
                               const std::string& keyword);
/// The core::Epoch of a checked epoch text in a time system; FormatError (rule: the Epoch parser's
/// message) when the instant does not exist in that scale (e.g. 23:59:60 outside a leap second).
core::Epoch to_epoch(const std::string& text, TimeSystem ts, const std::string& source, int line,
                     const std::string& keyword);
/// The text a writer prints: `text` when not empty, else epoch_text(time, ts).
std::string epoch_or_time(const std::string& text, const core::Epoch& time, TimeSystem ts);
/// The TimeSystem of a TIME_SYSTEM value: unknown and unsupported values throw FormatError.
TimeSystem parse_time_system(const std::string& text, const std::string& source, int line);
/// Whitespace-separated fields of `text`.
std::vector<std::string> split_ws(const std::string& text);
/// Trimmed copy (spaces, tabs, CR).
std::string trim(const std::string& text);
/// Shortest decimal text that reads back to the same double (std::to_chars); throws
/// std::invalid_argument("<name>: must be finite") for NaN or Inf.
std::string format_number(double value, const std::string& name);
/// The text of a file; std::invalid_argument naming the path when it cannot be read.
std::string read_file(const std::string& path);
/// Write `text` to a file; std::invalid_argument naming the path when it cannot be written.
void write_file(const std::string& path, const std::string& text);
/// Check a unit given in brackets against the standard's unit (case-insensitive); "" passes.
void check_unit(const KvnLine& l, const std::string& expected, const std::string& source);
/// The first line of a KVN message, checked: `keyword = v` with v one of `versions`, else FormatError
/// (empty file, missing first line, or unsupported version naming the supported ones).
const KvnLine& check_version_line(const std::vector<KvnLine>& lines, const std::string& keyword,
                                  std::initializer_list<const char*> versions, const std::string& source);

/// The writers' check: what a writer wrote must read back under the reader's rules. Runs
/// `parse(text, "<written KIND>")`; a FormatError becomes std::invalid_argument("<name>: not a valid KIND:
/// <keyword>: <rule>"). Returns `text`.
template <class Parse>
std::string read_back_checked(std::string text, const std::string& name, const std::string& kind,
                              Parse parse) {
  try {
    (void)parse(text, "<written " + kind + ">");
  } catch (const FormatError& e) {
    throw std::invalid_argument(name + ": not a valid " + kind + ": " + e.keyword() + ": " + e.rule());
  }
  return text;
}

/// Writer: `key = value` and a line end.
void put(std::ostream& out, const std::string& key, const std::string& value);
/// Writer: put(out, key, value) when `value` is not empty, else nothing.
void put_opt(std::ostream& out, const std::string& key, const std::string& value);
/// Writer: one `COMMENT text` line per comment.
void put_comments(std::ostream& out, const std::vector<std::string>& comments);
/// Writer: the version line `version_keyword = h.version`, the header comments, then CLASSIFICATION
/// (when set), CREATION_DATE, ORIGINATOR and MESSAGE_ID (when set).
void put_header(std::ostream& out, const std::string& version_keyword, const Header& h);

/// The object metadata OEM and OPM share (references into the model being written).
struct ObjectMetadata {
  const std::string& object_name;
  const std::string& object_id;
  const std::string& center_name;
  const std::string& ref_frame;
  const std::string& ref_frame_epoch;
  TimeSystem time_system;
};
/// Writer: OBJECT_NAME, OBJECT_ID, CENTER_NAME, REF_FRAME, REF_FRAME_EPOCH (when set), TIME_SYSTEM.
void put_object(std::ostream& out, const ObjectMetadata& o);

/// Whether a message text is XML: its first character after blanks and a UTF-8 byte-order mark is '<'.
bool is_xml(const std::string& text);

}  // namespace satgnc::io::detail
