// TDM (CCSDS 503.0-B-2): the model builder shared by the KVN and XML readers, the KVN reader and writer.
#include "satgnc/io/tdm.hpp"

#include <cstring>
#include <sstream>

#include "detail/kvn.hpp"
#include "detail/tdm_builder.hpp"

namespace satgnc::io {

namespace {

struct DataUnit {
  const char* key;
  const char* unit;
};
// CCSDS 503.0-B-2 section 3.5 (tracking data keywords) with the units of its table 3-5.
constexpr DataUnit kDataUnits[] = {
    {"RANGE", "km"},
    {"DOPPLER_INSTANTANEOUS", "km/s"},
    {"DOPPLER_INTEGRATED", "km/s"},
    {"ANGLE_1", "deg"},
    {"ANGLE_2", "deg"},
    {"RECEIVE_FREQ", "Hz"},
    {"RECEIVE_FREQ_1", "Hz"},
    {"RECEIVE_FREQ_2", "Hz"},
    {"RECEIVE_FREQ_3", "Hz"},
    {"RECEIVE_FREQ_4", "Hz"},
    {"RECEIVE_FREQ_5", "Hz"},
    {"TRANSMIT_FREQ_1", "Hz"},
    {"TRANSMIT_FREQ_2", "Hz"},
    {"TRANSMIT_FREQ_3", "Hz"},
    {"TRANSMIT_FREQ_4", "Hz"},
    {"TRANSMIT_FREQ_5", "Hz"},
    {"TRANSMIT_FREQ_RATE_1", "Hz/s"},
    {"TRANSMIT_FREQ_RATE_2", "Hz/s"},
    {"TRANSMIT_FREQ_RATE_3", "Hz/s"},
    {"TRANSMIT_FREQ_RATE_4", "Hz/s"},
    {"TRANSMIT_FREQ_RATE_5", "Hz/s"},
    {"CARRIER_POWER", "dBW"},
    {"PC_N0", "dBHz"},
    {"PR_N0", "dBHz"},
    {"CLOCK_BIAS", "s"},
    {"CLOCK_DRIFT", "s/s"},
    {"TROPO_DRY", "m"},
    {"TROPO_WET", "m"},
    {"STEC", "TECU"},
    {"PRESSURE", "hPa"},
    {"RHUMIDITY", "%"},
    {"TEMPERATURE", "K"},
    {"MAG", ""},
    {"RCS", "m**2"},
};

bool unsupported_data(const std::string& k) {
  return k == "DOPPLER_COUNT" || k == "DOR" || k == "VLBI_DELAY" || k.rfind("RECEIVE_PHASE_CT_", 0) == 0 ||
         k.rfind("TRANSMIT_PHASE_CT_", 0) == 0;
}

enum class MetaKind { text, number, integer, yes_no };
struct MetaKey {
  const char* key;
  MetaKind kind;
};
// Metadata keywords of CCSDS 503.0-B-2 section 3.3 that the model keeps as read (TdmMetadata::other).
constexpr MetaKey kOtherMeta[] = {
    {"TRACK_ID", MetaKind::text},
    {"DATA_TYPES", MetaKind::text},
    {"TRANSMIT_BAND", MetaKind::text},
    {"RECEIVE_BAND", MetaKind::text},
    {"TURNAROUND_NUMERATOR", MetaKind::integer},
    {"TURNAROUND_DENOMINATOR", MetaKind::integer},
    {"TIMETAG_REF", MetaKind::text},
    {"FREQ_OFFSET", MetaKind::number},
    {"RANGE_MODE", MetaKind::text},
    {"RANGE_MODULUS", MetaKind::number},
    {"REFERENCE_FRAME", MetaKind::text},
    {"INTERPOLATION", MetaKind::text},
    {"INTERPOLATION_DEGREE", MetaKind::integer},
    {"DOPPLER_COUNT_BIAS", MetaKind::number},
    {"DOPPLER_COUNT_SCALE", MetaKind::integer},
    {"DOPPLER_COUNT_ROLLOVER", MetaKind::text},
    {"DATA_QUALITY", MetaKind::text},
    {"CORRECTION_ANGLE_1", MetaKind::number},
    {"CORRECTION_ANGLE_2", MetaKind::number},
    {"CORRECTION_DOPPLER", MetaKind::number},
    {"CORRECTION_MAG", MetaKind::number},
    {"CORRECTION_RANGE", MetaKind::number},
    {"CORRECTION_RCS", MetaKind::number},
    {"CORRECTION_RECEIVE", MetaKind::number},
    {"CORRECTION_TRANSMIT", MetaKind::number},
    {"CORRECTION_ABERRATION_YEARLY", MetaKind::number},
    {"CORRECTION_ABERRATION_DIURNAL", MetaKind::number},
    {"CORRECTIONS_APPLIED", MetaKind::yes_no},
};

// TRANSMIT_DELAY_n, RECEIVE_DELAY_n (s), EPHEMERIS_NAME_n, n = 1..5.
bool indexed_meta(const std::string& k, MetaKind& kind) {
  for (const char* base : {"TRANSMIT_DELAY_", "RECEIVE_DELAY_", "EPHEMERIS_NAME_"}) {
    const std::size_t n = std::strlen(base);
    if (k.size() == n + 1 && k.compare(0, n, base) == 0 && k[n] >= '1' && k[n] <= '5') {
      kind = base[0] == 'E' ? MetaKind::text : MetaKind::number;
      return true;
    }
  }
  return false;
}

int participant_index(const std::string& k) {
  if (k.size() == 13 && k.compare(0, 12, "PARTICIPANT_") == 0 && k[12] >= '1' && k[12] <= '5')
    return k[12] - '0';
  return 0;
}

}  // namespace

const char* tdm_unit(const std::string& keyword) noexcept {
  for (const DataUnit& d : kDataUnits)
    if (keyword == d.key) return d.unit;
  return nullptr;
}

namespace detail {

void TdmBuilder::version(const std::string& value, int line) {
  if (value != "1.0" && value != "2.0")
    fail(source_, line, "CCSDS_TDM_VERS", "unsupported version '" + value + "' (supported: 1.0, 2.0)");
  tdm_.header.version = value;
  have_version_ = true;
}

void TdmBuilder::header(const std::string& key, const std::string& value, int line) {
  if (header_seen_.count(key)) fail(source_, line, key, "duplicate keyword in the header");
  if (value.empty()) fail(source_, line, key, "empty value");
  header_seen_[key] = line;
  if (key == "CREATION_DATE") {
    tdm_.header.creation_date = check_epoch(value, source_, line, key);
  } else if (key == "ORIGINATOR") {
    tdm_.header.originator = value;
  } else if (key == "MESSAGE_ID") {
    tdm_.header.message_id = value;
  } else if (key == "CLASSIFICATION") {
    tdm_.header.classification = value;
  } else {
    fail(source_, line, key, "unknown header keyword (hint: CREATION_DATE, ORIGINATOR, MESSAGE_ID, COMMENT)");
  }
}

void TdmBuilder::begin_segment(int line) {
  if (!have_version_) fail(source_, line, "CCSDS_TDM_VERS", "missing mandatory keyword (the first line)");
  for (const char* k : {"CREATION_DATE", "ORIGINATOR"})
    if (!header_seen_.count(k)) fail(source_, line, k, "missing mandatory header keyword");
  tdm_.segments.emplace_back();
  meta_seen_.clear();
  participants_.clear();
  path_text_.clear();
}

void TdmBuilder::meta(const std::string& key, const std::string& value, int line) {
  if (meta_seen_.count(key)) fail(source_, line, key, "duplicate keyword in the metadata");
  if (value.empty()) fail(source_, line, key, "empty value");
  meta_seen_[key] = line;
  TdmMetadata& m = tdm_.segments.back().metadata;
  if (key == "TIME_SYSTEM") {
    m.time_system = parse_time_system(value, source_, line);
  } else if (const int p = participant_index(key); p > 0) {
    if (value.empty()) fail(source_, line, key, "must not be empty");
    participants_[p] = value;
  } else if (key == "MODE") {
    if (value == "SINGLE_DIFF")
      fail(source_, line, key, "unsupported mode 'SINGLE_DIFF' (supported: SEQUENTIAL)");
    if (value != "SEQUENTIAL")
      fail(source_, line, key, "unknown mode '" + value + "' (supported: SEQUENTIAL)");
    m.mode = value;
  } else if (key == "PATH") {
    path_text_ = value;
    m.path.clear();
    std::stringstream ss(value);
    std::string item;
    while (std::getline(ss, item, ',')) {
      const std::string t = trim(item);
      if (t.size() != 1 || t[0] < '1' || t[0] > '5')
        fail(source_, line, key,
             "malformed path '" + value + "' (hint: participant indices 1..5, e.g. 1,2,1)");
      m.path.push_back(t[0] - '0');
    }
    if (m.path.size() < 2)
      fail(source_, line, key, "malformed path '" + value + "': needs at least two participants");
    for (std::size_t i = 1; i < m.path.size(); ++i)
      if (m.path[i] == m.path[i - 1])
        fail(source_, line, key, "malformed path '" + value + "': a leg from a participant to itself");
  } else if (key == "PATH_1" || key == "PATH_2") {
    fail(source_, line, key, "unsupported (SINGLE_DIFF paths; supported: MODE = SEQUENTIAL with PATH)");
  } else if (key == "START_TIME") {
    m.start_time = check_epoch(value, source_, line, key);
  } else if (key == "STOP_TIME") {
    m.stop_time = check_epoch(value, source_, line, key);
  } else if (key == "INTEGRATION_INTERVAL") {
    const double v = parse_number(value, source_, line, key);
    if (!(v > 0.0)) fail(source_, line, key, "must be > 0 s, got " + value);
    m.integration_interval = v;
  } else if (key == "INTEGRATION_REF") {
    if (value != "START" && value != "MIDDLE" && value != "END")
      fail(source_, line, key, "unknown value '" + value + "' (hint: START, MIDDLE, END)");
    m.integration_ref = value;
  } else if (key == "RANGE_UNITS") {
    if (value == "s" || value == "RU")
      fail(source_, line, key, "unsupported range unit '" + value + "' (supported: km)");
    if (value != "km") fail(source_, line, key, "unknown range unit '" + value + "' (supported: km)");
    m.range_units = value;
  } else if (key == "ANGLE_TYPE") {
    if (value == "XEYN" || value == "XSYE")
      fail(source_, line, key, "unsupported angle type '" + value + "' (supported: AZEL, RADEC)");
    if (value != "AZEL" && value != "RADEC")
      fail(source_, line, key, "unknown angle type '" + value + "' (supported: AZEL, RADEC)");
    m.angle_type = value;
  } else {
    MetaKind kind = MetaKind::text;
    bool known = indexed_meta(key, kind);
    for (const MetaKey& k : kOtherMeta)
      if (key == k.key) {
        kind = k.kind;
        known = true;
      }
    if (!known) fail(source_, line, key, "unknown metadata keyword");
    if (kind == MetaKind::number) parse_number(value, source_, line, key);
    if (kind == MetaKind::integer) parse_int(value, source_, line, key);
    if (kind == MetaKind::yes_no && value != "YES" && value != "NO")
      fail(source_, line, key, "must be YES or NO, got '" + value + "'");
    m.other.emplace_back(key, value);
  }
}

void TdmBuilder::end_meta(int line) {
  TdmMetadata& m = tdm_.segments.back().metadata;
  if (!meta_seen_.count("TIME_SYSTEM")) fail(source_, line, "TIME_SYSTEM", "missing mandatory keyword");
  if (!participants_.count(1)) fail(source_, line, "PARTICIPANT_1", "missing mandatory keyword");
  const int n = static_cast<int>(participants_.size());
  for (const auto& [i, name] : participants_)
    if (i > n)
      fail(source_, meta_seen_["PARTICIPANT_" + std::to_string(i)], "PARTICIPANT_" + std::to_string(i),
           "participants must be numbered 1.." + std::to_string(n) + " without a gap");
  m.participants.clear();
  for (const auto& [i, name] : participants_) m.participants.push_back(name);
  if (!m.path.empty()) {
    const int pl = meta_seen_["PATH"];
    if (m.mode.empty()) fail(source_, pl, "MODE", "missing: PATH requires MODE = SEQUENTIAL");
    for (int p : m.path)
      if (p > n)
        fail(source_, pl, "PATH",
             "path '" + path_text_ + "' names participant " + std::to_string(p) +
                 ", but only PARTICIPANT_1.." + "PARTICIPANT_" + std::to_string(n) + " are defined");
  } else if (!m.mode.empty()) {
    fail(source_, meta_seen_["MODE"], "PATH", "missing: MODE = SEQUENTIAL requires PATH");
  }
}

void TdmBuilder::observation(const std::string& key, const std::string& epoch, const std::string& value,
                             int line) {
  const char* unit = tdm_unit(key);
  if (unit == nullptr) {
    if (unsupported_data(key))
      fail(source_, line, key, "unsupported data keyword (see docs/io.md for the supported ones)");
    fail(source_, line, key, "unknown data keyword");
  }
  const TdmMetadata& m = tdm_.segments.back().metadata;
  if ((key == "ANGLE_1" || key == "ANGLE_2") && m.angle_type.empty())
    fail(source_, line, key, "angle data need ANGLE_TYPE in the metadata (missing mandatory keyword)");
  TdmObservation o;
  o.keyword = key;
  o.epoch = check_epoch(epoch, source_, line, key);
  o.time = to_epoch(o.epoch, m.time_system, source_, line, key);
  o.value = parse_number(value, source_, line, key);
  if ((key == "ANGLE_1" || key == "ANGLE_2") && !(o.value >= -180.0 && o.value < 360.0))
    fail(source_, line, key, "angle " + value + " deg outside [-180, 360)");
  o.unit = unit;
  tdm_.segments.back().observations.push_back(std::move(o));
}

Tdm TdmBuilder::finish(int line) {
  if (!have_version_) fail(source_, line, "CCSDS_TDM_VERS", "missing mandatory keyword (the first line)");
  if (tdm_.segments.empty()) fail(source_, line, "META_START", "no segment (a TDM needs at least one)");
  return std::move(tdm_);
}

Tdm parse_tdm_xml(const std::string& text, const std::string& source);  // tdm_xml.cpp

namespace {

Tdm parse_tdm_kvn(const std::string& text, const std::string& source) {
  const std::vector<KvnLine> lines = tokenize_kvn(text, source);
  TdmBuilder b(source);
  enum class State { header, meta, between, data, after } st = State::header;
  using K = KvnLine::Kind;
  int last = 0;
  bool first = true;
  for (const KvnLine& l : lines) {
    last = l.line;
    if (first) {
      first = false;
      if (l.kind != K::key_value || l.key != "CCSDS_TDM_VERS")
        fail(source, l.line, "CCSDS_TDM_VERS", "missing mandatory keyword (must be the first line)");
      b.version(l.value, l.line);
      continue;
    }
    switch (st) {
      case State::header:
      case State::after:
        if (l.kind == K::comment && st == State::header) {
          b.header_comment(l.value);
        } else if (l.kind == K::key_value && st == State::header) {
          b.header(l.key, l.value, l.line);
        } else if (l.kind == K::marker && l.key == "META_START") {
          b.begin_segment(l.line);
          st = State::meta;
        } else {
          fail(source, l.line, l.kind == K::raw ? l.value : l.key,
               st == State::header ? "unexpected line in the header (hint: META_START starts a segment)"
                                   : "unexpected line after DATA_STOP (hint: META_START starts a segment)");
        }
        break;
      case State::meta:
        if (l.kind == K::comment) {
          b.meta_comment(l.value);
        } else if (l.kind == K::key_value) {
          b.meta(l.key, l.value, l.line);
        } else if (l.kind == K::marker && l.key == "META_STOP") {
          b.end_meta(l.line);
          st = State::between;
        } else {
          fail(source, l.line, l.kind == K::raw ? l.value : l.key,
               "unexpected line in the metadata (META_STOP missing?)");
        }
        break;
      case State::between:
        if (l.kind == K::marker && l.key == "DATA_START") {
          st = State::data;
        } else {
          fail(source, l.line, "DATA_START", "missing after META_STOP");
        }
        break;
      case State::data:
        if (l.kind == K::comment) {
          b.data_comment(l.value);
        } else if (l.kind == K::key_value) {
          const std::vector<std::string> f = split_ws(l.value);
          if (f.size() != 2) fail(source, l.line, l.key, "malformed data line (hint: KEYWORD = epoch value)");
          b.observation(l.key, f[0], f[1], l.line);
        } else if (l.kind == K::marker && l.key == "DATA_STOP") {
          st = State::after;
        } else {
          fail(source, l.line, l.kind == K::raw ? l.value : l.key,
               "unexpected line in the data (DATA_STOP missing?)");
        }
        break;
    }
  }
  if (first) fail(source, 0, "CCSDS_TDM_VERS", "missing mandatory keyword (empty file)");
  if (st == State::meta) fail(source, last, "META_STOP", "missing at the end of the file");
  if (st == State::between) fail(source, last, "DATA_START", "missing at the end of the file");
  if (st == State::data) fail(source, last, "DATA_STOP", "missing at the end of the file");
  return b.finish(last);
}

}  // namespace
}  // namespace detail

Tdm parse_tdm(const std::string& text, const std::string& source) {
  if (detail::is_xml(text)) return detail::parse_tdm_xml(text, source);
  return detail::parse_tdm_kvn(text, source);
}

Tdm read_tdm(const std::string& path) { return parse_tdm(detail::read_file(path), path); }

using detail::put;
using detail::put_comments;
using detail::put_opt;

std::string format_tdm_kvn(const Tdm& tdm) {
  std::ostringstream out;
  detail::put_header(out, "CCSDS_TDM_VERS", tdm.header);
  for (std::size_t s = 0; s < tdm.segments.size(); ++s) {
    const TdmSegment& seg = tdm.segments[s];
    const TdmMetadata& m = seg.metadata;
    out << "META_START\n";
    put_comments(out, m.comments);
    put(out, "TIME_SYSTEM", time_system_name(m.time_system));
    put_opt(out, "START_TIME", m.start_time);
    put_opt(out, "STOP_TIME", m.stop_time);
    for (std::size_t i = 0; i < m.participants.size(); ++i)
      put(out, "PARTICIPANT_" + std::to_string(i + 1), m.participants[i]);
    put_opt(out, "MODE", m.mode);
    if (!m.path.empty()) {
      std::string p;
      for (std::size_t i = 0; i < m.path.size(); ++i) p += (i ? "," : "") + std::to_string(m.path[i]);
      put(out, "PATH", p);
    }
    if (m.integration_interval)
      put(out, "INTEGRATION_INTERVAL",
          detail::format_number(*m.integration_interval,
                                "segments[" + std::to_string(s) + "].integration_interval"));
    put_opt(out, "INTEGRATION_REF", m.integration_ref);
    put_opt(out, "RANGE_UNITS", m.range_units);
    put_opt(out, "ANGLE_TYPE", m.angle_type);
    for (const auto& [k, v] : m.other) put(out, k, v);
    out << "META_STOP\nDATA_START\n";
    put_comments(out, seg.data_comments);
    for (std::size_t i = 0; i < seg.observations.size(); ++i) {
      const TdmObservation& o = seg.observations[i];
      out << o.keyword << " = " << detail::epoch_or_time(o.epoch, o.time, m.time_system) << " "
          << detail::format_number(
                 o.value, "segments[" + std::to_string(s) + "].observations[" + std::to_string(i) + "].value")
          << "\n";
    }
    out << "DATA_STOP\n";
  }
  return detail::read_back_checked(out.str(), "tdm", "TDM", [](const std::string& t, const std::string& src) {
    return detail::parse_tdm_kvn(t, src);
  });
}

void write_tdm(const std::string& path, const Tdm& tdm, bool xml) {
  detail::write_file(path, xml ? format_tdm_xml(tdm) : format_tdm_kvn(tdm));
}

}  // namespace satgnc::io
