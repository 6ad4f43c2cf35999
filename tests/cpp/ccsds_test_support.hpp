#pragma once
// Shared by test_tdm / test_oem / test_opm: the data folder and an assertion on FormatError's parts.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "satgnc/io/ccsds.hpp"

namespace satgnc::testing {

/// tests/data/ccsds (set by tests/cpp/CMakeLists.txt).
inline std::string ccsds_data(const std::string& name) {
  return std::string(SATGNC_CCSDS_DATA_DIR) + "/" + name;
}

/// The whole text of a file.
inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Apply n deterministic one-character mutations (replace, delete, duplicate) to `text` and run
/// `parse` on each; every run must return or throw io::FormatError naming `source`. Returns the
/// number that parsed (the rest were refused).
inline int mutation_runs(const std::string& text, int n, const std::string& source,
                         const std::function<void(const std::string&)>& parse) {
  unsigned state = 2024u;
  auto next = [&state] { return state = state * 1103515245u + 12345u, (state >> 8) & 0xffffffu; };
  int parsed = 0;
  for (int k = 0; k < n; ++k) {
    std::string t = text;
    const std::size_t at = next() % t.size();
    const char c = static_cast<char>(32 + next() % 95);
    const unsigned op = next() % 3;
    if (op == 0)
      t[at] = c;
    else if (op == 1)
      t.erase(at, 1);
    else
      t.insert(at, 1, t[at]);
    try {
      parse(t);
      ++parsed;
    } catch (const io::FormatError& e) {
      EXPECT_EQ(e.file(), source);
    }
  }
  return parsed;
}

/// Run f, which must throw io::FormatError with exactly this file, line and keyword and a message
/// containing `fragment`; the full message must read "<file>:<line>: <keyword>: ...".
inline void expect_format_error(const std::function<void()>& f, const std::string& file, int line,
                                const std::string& keyword, const std::string& fragment) {
  try {
    f();
    ADD_FAILURE() << "no FormatError; expected " << file << ":" << line << ": " << keyword;
  } catch (const io::FormatError& e) {
    EXPECT_EQ(e.file(), file);
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.keyword(), keyword) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    const std::string head =
        line > 0 ? file + ":" + std::to_string(line) + ": " + keyword + ": " : file + ": " + keyword + ": ";
    EXPECT_EQ(std::string(e.what()).rfind(head, 0), 0u) << e.what();
  }
}

/// The lines of `text` with line `n` (1-based) replaced by `with` ("" removes the line).
inline std::string replace_line(const std::string& text, int n, const std::string& with) {
  std::string out;
  int i = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++i;
    const std::string line = text.substr(pos, end - pos);
    if (i != n)
      out += line + "\n";
    else if (!with.empty())
      out += with + "\n";
    pos = end + 1;
  }
  return out;
}

/// Exact comparison (tolerance 0: strings) of two headers; the version only when `same_version`.
inline void expect_same_header(const io::Header& a, const io::Header& b, bool same_version = true) {
  if (same_version) EXPECT_EQ(a.version, b.version);
  EXPECT_EQ(a.comments, b.comments);
  EXPECT_EQ(a.creation_date, b.creation_date);
  EXPECT_EQ(a.originator, b.originator);
  EXPECT_EQ(a.message_id, b.message_id);
}

/// One bad-input case: line `line` of a valid base text replaced by `with` ("" removes it).
struct BadLine {
  int line;              // line replaced
  const char* with;      // replacement ("" removes it)
  int error_line;        // line the error names
  const char* keyword;   // keyword it names
  const char* fragment;  // part of the rule
};

/// For each case, `parse(text, source)` of the changed base must throw FormatError naming `source`, the
/// case's error line and keyword, with the fragment in its message (expect_format_error).
inline void expect_bad_lines(const std::string& base, const std::vector<BadLine>& cases,
                             const std::string& source,
                             const std::function<void(const std::string&, const std::string&)>& parse) {
  for (const BadLine& c : cases) {
    SCOPED_TRACE(std::string("line ") + std::to_string(c.line) + " -> '" + c.with + "'");
    const std::string text = replace_line(base, c.line, c.with);
    expect_format_error([&] { parse(text, source); }, source, c.error_line, c.keyword, c.fragment);
  }
}

}  // namespace satgnc::testing
