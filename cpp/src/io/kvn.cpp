// KVN tokenizer and value checks shared by the TDM, OEM and OPM readers and writers.
#include "detail/kvn.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace satgnc::io {

FormatError::FormatError(std::string file, int line, std::string keyword, std::string rule)
    : std::invalid_argument((line > 0 ? file + ":" + std::to_string(line) : file) + ": " +
                            (keyword.empty() ? std::string() : keyword + ": ") + rule),
      file_(std::move(file)),
      line_(line),
      keyword_(std::move(keyword)),
      rule_(std::move(rule)) {}

std::string epoch_text(const core::Epoch& time, TimeSystem ts) {
  std::string s = time.to_iso(ts, 12);
  const auto dot = s.find('.');
  if (dot != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

namespace detail {

std::string trim(const std::string& text) {
  const char* ws = " \t\r\n\f\v";
  const auto b = text.find_first_not_of(ws);
  if (b == std::string::npos) return {};
  const auto e = text.find_last_not_of(ws);
  return text.substr(b, e - b + 1);
}

std::vector<std::string> split_ws(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string f;
  while (in >> f) out.push_back(f);
  return out;
}

void fail(const std::string& source, int line, const std::string& keyword, const std::string& rule) {
  throw FormatError(source, line, keyword, rule);
}

namespace {
bool is_key(const std::string& s) {
  return !s.empty() && std::isupper(static_cast<unsigned char>(s[0])) &&
         std::all_of(s.begin(), s.end(),
                     [](unsigned char c) { return std::isupper(c) || std::isdigit(c) || c == '_'; });
}
}  // namespace

std::vector<KvnLine> tokenize_kvn(const std::string& text, const std::string& source) {
  std::vector<KvnLine> out;
  std::size_t pos = 0;
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) pos = 3;
  int line = 0;
  while (pos <= text.size()) {
    std::size_t end = text.find_first_of("\r\n", pos);
    if (end == std::string::npos) end = text.size();
    ++line;
    const std::string raw = trim(text.substr(pos, end - pos));
    if (end < text.size() && text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n') ++end;
    pos = end + 1;
    if (raw.empty()) continue;
    KvnLine l;
    l.line = line;
    if (raw.compare(0, 7, "COMMENT") == 0 && (raw.size() == 7 || raw[7] == ' ' || raw[7] == '\t')) {
      l.kind = KvnLine::Kind::comment;
      l.value = trim(raw.substr(7));
    } else if (const auto eq = raw.find('='); eq != std::string::npos) {
      l.kind = KvnLine::Kind::key_value;
      l.key = trim(raw.substr(0, eq));
      if (!is_key(l.key))
        fail(source, line, l.key.empty() ? "=" : l.key,
             "malformed line (hint: KEYWORD = value, keywords in upper case)");
      l.value = trim(raw.substr(eq + 1));
      if (l.value.empty()) fail(source, line, l.key, "empty value (hint: KEYWORD = value)");
      if (!l.value.empty() && l.value.back() == ']') {
        const auto open = l.value.rfind('[');
        if (open != std::string::npos) {
          l.unit = trim(l.value.substr(open + 1, l.value.size() - open - 2));
          l.value = trim(l.value.substr(0, open));
        }
      }
    } else if (is_key(raw)) {
      l.kind = KvnLine::Kind::marker;
      l.key = raw;
    } else {
      l.kind = KvnLine::Kind::raw;
      l.value = raw;
    }
    out.push_back(std::move(l));
    if (end >= text.size()) break;
  }
  return out;
}

double parse_number(const std::string& text, const std::string& source, int line,
                    const std::string& keyword) {
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+' && b + 1 != e && b[1] != '-') ++b;  // "+1" reads, "+-1" does not
  double v = 0.0;
  const auto r = std::from_chars(b, e, v);
  if (text.empty() || r.ec != std::errc() || r.ptr != e || !std::isfinite(v))
    fail(source, line, keyword, "not a number: '" + text + "'");
  return v;
}

int parse_int(const std::string& text, const std::string& source, int line, const std::string& keyword) {
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;
  int v = 0;
  const auto r = std::from_chars(b, e, v);
  if (text.empty() || r.ec != std::errc() || r.ptr != e)
    fail(source, line, keyword, "not an integer: '" + text + "'");
  return v;
}

namespace {
bool digits(const std::string& s, std::size_t at, std::size_t n, int& out) {
  if (at + n > s.size()) return false;
  out = 0;
  for (std::size_t i = at; i < at + n; ++i) {
    if (!std::isdigit(static_cast<unsigned char>(s[i]))) return false;
    out = out * 10 + (s[i] - '0');
  }
  return true;
}
bool leap_year(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }
}  // namespace

const std::string& check_epoch(const std::string& text, const std::string& source, int line,
                               const std::string& keyword) {
  const std::string hint =
      "not an epoch: '" + text + "' (hint: YYYY-MM-DDThh:mm:ss[.f] or YYYY-DDDThh:mm:ss[.f])";
  int year = 0, month = 0, day = 0, doy = 0, hh = 0, mm = 0, ss = 0;
  std::string s = text;
  if (!s.empty() && s.back() == 'Z') s.pop_back();
  if (!digits(s, 0, 4, year) || s.size() < 5 || s[4] != '-') fail(source, line, keyword, hint);
  std::size_t t = 0;
  if (s.size() > 10 && s[7] == '-' && s[10] == 'T') {  // code A
    if (!digits(s, 5, 2, month) || !digits(s, 8, 2, day)) fail(source, line, keyword, hint);
    static const int mdays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    if (month < 1 || month > 12) fail(source, line, keyword, hint + ": month out of range");
    const int dmax = mdays[month - 1] + (month == 2 && leap_year(year) ? 1 : 0);
    if (day < 1 || day > dmax) fail(source, line, keyword, hint + ": day out of range");
    t = 10;
  } else if (s.size() > 8 && s[8] == 'T') {  // code B
    if (!digits(s, 5, 3, doy)) fail(source, line, keyword, hint);
    if (doy < 1 || doy > (leap_year(year) ? 366 : 365))
      fail(source, line, keyword, hint + ": day of year out of range");
    t = 8;
  } else {
    fail(source, line, keyword, hint);
  }
  if (s.size() < t + 9 || s[t + 3] != ':' || s[t + 6] != ':' || !digits(s, t + 1, 2, hh) ||
      !digits(s, t + 4, 2, mm) || !digits(s, t + 7, 2, ss))
    fail(source, line, keyword, hint);
  const std::size_t rest = t + 9;  // optional ".f..." (any number of digits)
  if (rest < s.size()) {
    bool ok = s[rest] == '.' && rest + 1 < s.size();
    for (std::size_t i = rest + 1; ok && i < s.size(); ++i)
      ok = std::isdigit(static_cast<unsigned char>(s[i]));
    if (!ok) fail(source, line, keyword, hint);
  }
  if (hh > 23 || mm > 59) fail(source, line, keyword, hint + ": time out of range");
  if (ss > 60 || (ss == 60 && !(hh == 23 && mm == 59)))
    fail(source, line, keyword, hint + ": seconds out of range (60 only at 23:59, a leap second)");
  return text;
}

TimeSystem parse_time_system(const std::string& text, const std::string& source, int line) {
  if (text == "UTC") return TimeSystem::utc;
  if (text == "TAI") return TimeSystem::tai;
  if (text == "TT") return TimeSystem::tt;
  if (text == "GPS") return TimeSystem::gps;
  if (text == "TDB") return TimeSystem::tdb;
  static const char* known[] = {"UT1", "TCB", "TCG", "GMST", "MET", "MRT", "SCLK", "GMT", "TDR", "TT2"};
  for (const char* k : known)
    if (text == k)
      fail(source, line, "TIME_SYSTEM",
           "unsupported time system '" + text + "' (supported: UTC, TAI, TT, GPS, TDB)");
  fail(source, line, "TIME_SYSTEM", "unknown time system '" + text + "' (supported: UTC, TAI, TT, GPS, TDB)");
}

core::Epoch to_epoch(const std::string& text, TimeSystem ts, const std::string& source, int line,
                     const std::string& keyword) {
  try {
    return core::Epoch::parse(text, ts);
  } catch (const std::invalid_argument& e) {
    fail(source, line, keyword, std::string("not a valid ") + time_system_name(ts) + " epoch: " + e.what());
  }
}

std::string epoch_or_time(const std::string& text, const core::Epoch& time, TimeSystem ts) {
  return text.empty() ? epoch_text(time, ts) : text;
}

std::string format_number(double value, const std::string& name) {
  if (!std::isfinite(value)) throw std::invalid_argument(name + ": must be finite (no NaN or Inf)");
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  return std::string(buf, r.ptr);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("path: cannot open '" + path + "' for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::invalid_argument("path: cannot open '" + path + "' for writing");
  out << text;
  if (!out) throw std::invalid_argument("path: writing '" + path + "' failed");
}

void check_unit(const KvnLine& l, const std::string& expected, const std::string& source) {
  if (l.unit.empty()) return;
  auto lower = [](std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
  };
  if (lower(l.unit) != lower(expected))
    fail(source, l.line, l.key,
         "unsupported unit '[" + l.unit + "]' (this keyword is in " +
             (expected.empty() ? "no unit" : expected) + ")");
}

const KvnLine& check_version_line(const std::vector<KvnLine>& lines, const std::string& keyword,
                                  std::initializer_list<const char*> versions, const std::string& source) {
  using K = KvnLine::Kind;
  if (lines.empty()) fail(source, 0, keyword, "missing mandatory keyword (empty file)");
  const KvnLine& v = lines.front();
  if (v.kind != K::key_value || v.key != keyword)
    fail(source, v.line, keyword, "missing mandatory keyword (must be the first line)");
  std::string supported;
  for (const char* s : versions) {
    if (v.value == s) return v;
    supported += (supported.empty() ? "" : ", ") + std::string(s);
  }
  fail(source, v.line, v.key, "unsupported version '" + v.value + "' (supported: " + supported + ")");
}

void put(std::ostream& out, const std::string& key, const std::string& value) {
  out << key << " = " << value << "\n";
}

void put_opt(std::ostream& out, const std::string& key, const std::string& value) {
  if (!value.empty()) put(out, key, value);
}

void put_comments(std::ostream& out, const std::vector<std::string>& comments) {
  for (const auto& c : comments) out << "COMMENT " << c << "\n";
}

void put_header(std::ostream& out, const std::string& version_keyword, const Header& h) {
  put(out, version_keyword, h.version);
  put_comments(out, h.comments);
  put_opt(out, "CLASSIFICATION", h.classification);
  put(out, "CREATION_DATE", h.creation_date);
  put(out, "ORIGINATOR", h.originator);
  put_opt(out, "MESSAGE_ID", h.message_id);
}

void put_object(std::ostream& out, const ObjectMetadata& o) {
  put(out, "OBJECT_NAME", o.object_name);
  put(out, "OBJECT_ID", o.object_id);
  put(out, "CENTER_NAME", o.center_name);
  put(out, "REF_FRAME", o.ref_frame);
  put_opt(out, "REF_FRAME_EPOCH", o.ref_frame_epoch);
  put(out, "TIME_SYSTEM", time_system_name(o.time_system));
}

bool is_xml(const std::string& text) {
  const std::size_t first = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
  return first != std::string::npos && text[first] == '<';
}

}  // namespace detail
}  // namespace satgnc::io
