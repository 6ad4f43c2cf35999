#pragma once
// Shared by the CCSDS file tests (TDM, OEM, OPM; KVN and XML): the data folder and an assertion on
// FormatError's parts.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "satgnc/io/ccsds.hpp"
#include "satgnc/io/oem.hpp"

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

/// Exact comparison (tolerance 0) of two OEMs, field by field: from_chars and the compiler round the same
/// decimal text the same way, and the writers print the shortest decimal that reads back to the double.
inline void expect_same_oem(const io::Oem& a, const io::Oem& b) {
  expect_same_header(a.header, b.header);
  ASSERT_EQ(a.segments.size(), b.segments.size());
  for (std::size_t s = 0; s < a.segments.size(); ++s) {
    const auto& sa = a.segments[s];
    const auto& sb = b.segments[s];
    EXPECT_EQ(sa.metadata.comments, sb.metadata.comments);
    EXPECT_EQ(sa.metadata.object_name, sb.metadata.object_name);
    EXPECT_EQ(sa.metadata.object_id, sb.metadata.object_id);
    EXPECT_EQ(sa.metadata.center_name, sb.metadata.center_name);
    EXPECT_EQ(sa.metadata.ref_frame, sb.metadata.ref_frame);
    EXPECT_EQ(sa.metadata.ref_frame_epoch, sb.metadata.ref_frame_epoch);
    EXPECT_EQ(sa.metadata.time_system, sb.metadata.time_system);
    EXPECT_EQ(sa.metadata.start_time, sb.metadata.start_time);
    EXPECT_EQ(sa.metadata.useable_start_time, sb.metadata.useable_start_time);
    EXPECT_EQ(sa.metadata.useable_stop_time, sb.metadata.useable_stop_time);
    EXPECT_EQ(sa.metadata.stop_time, sb.metadata.stop_time);
    EXPECT_EQ(sa.metadata.interpolation, sb.metadata.interpolation);
    EXPECT_EQ(sa.metadata.interpolation_degree, sb.metadata.interpolation_degree);
    EXPECT_EQ(sa.data_comments, sb.data_comments);
    ASSERT_EQ(sa.states.size(), sb.states.size());
    for (std::size_t i = 0; i < sa.states.size(); ++i) {
      EXPECT_EQ(sa.states[i].epoch, sb.states[i].epoch);
      EXPECT_EQ(sa.states[i].time, sb.states[i].time);
      EXPECT_EQ(sa.states[i].state, sb.states[i].state);
      ASSERT_EQ(sa.states[i].acceleration.has_value(), sb.states[i].acceleration.has_value());
      if (sa.states[i].acceleration) EXPECT_EQ(*sa.states[i].acceleration, *sb.states[i].acceleration);
    }
    ASSERT_EQ(sa.covariances.size(), sb.covariances.size());
    for (std::size_t i = 0; i < sa.covariances.size(); ++i) {
      EXPECT_EQ(sa.covariances[i].comments, sb.covariances[i].comments);
      EXPECT_EQ(sa.covariances[i].epoch, sb.covariances[i].epoch);
      EXPECT_EQ(sa.covariances[i].time, sb.covariances[i].time);
      EXPECT_EQ(sa.covariances[i].cov_ref_frame, sb.covariances[i].cov_ref_frame);
      EXPECT_EQ(sa.covariances[i].matrix, sb.covariances[i].matrix);
    }
  }
}

/// `s` with the first `a` replaced by `b` (a test failure when `a` is absent).
inline std::string replace_first(std::string s, const std::string& a, const std::string& b) {
  const std::size_t i = s.find(a);
  EXPECT_NE(i, std::string::npos) << a;
  return i == std::string::npos ? s : s.replace(i, a.size(), b);
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
