// OEM (CCSDS 502.0-B-3 section 5), KVN: reader and writer.
#include "satgnc/io/oem.hpp"

#include <map>
#include <sstream>

#include "detail/kvn.hpp"
#include "detail/oem_lines.hpp"

namespace satgnc::io {

using detail::check_epoch;
using detail::fail;
using detail::format_number;
using detail::KvnLine;

namespace {

void odm_header(Header& h, const KvnLine& l, std::map<std::string, int>& seen, const std::string& source) {
  if (seen.count(l.key)) fail(source, l.line, l.key, "duplicate keyword in the header");
  seen[l.key] = l.line;
  if (l.key == "CREATION_DATE")
    h.creation_date = check_epoch(l.value, source, l.line, l.key);
  else if (l.key == "ORIGINATOR")
    h.originator = l.value;
  else if (l.key == "MESSAGE_ID")
    h.message_id = l.value;
  else if (l.key == "CLASSIFICATION")
    h.classification = l.value;
  else
    fail(source, l.line, l.key,
         "unknown header keyword (hint: CREATION_DATE, ORIGINATOR, MESSAGE_ID, COMMENT)");
}

void oem_meta(OemMetadata& m, const KvnLine& l, const std::string& source) {
  const std::string& k = l.key;
  const std::string& v = l.value;
  if (k == "OBJECT_NAME")
    m.object_name = v;
  else if (k == "OBJECT_ID")
    m.object_id = v;
  else if (k == "CENTER_NAME")
    m.center_name = v;
  else if (k == "REF_FRAME")
    m.ref_frame = v;
  else if (k == "REF_FRAME_EPOCH")
    m.ref_frame_epoch = check_epoch(v, source, l.line, k);
  else if (k == "TIME_SYSTEM")
    m.time_system = detail::parse_time_system(v, source, l.line);
  else if (k == "START_TIME")
    m.start_time = check_epoch(v, source, l.line, k);
  else if (k == "USEABLE_START_TIME")
    m.useable_start_time = check_epoch(v, source, l.line, k);
  else if (k == "USEABLE_STOP_TIME")
    m.useable_stop_time = check_epoch(v, source, l.line, k);
  else if (k == "STOP_TIME")
    m.stop_time = check_epoch(v, source, l.line, k);
  else if (k == "INTERPOLATION")
    m.interpolation = v;
  else if (k == "INTERPOLATION_DEGREE") {
    const int d = detail::parse_int(v, source, l.line, k);
    if (d < 0) fail(source, l.line, k, "must be >= 0, got " + v);
    m.interpolation_degree = d;
  } else
    fail(source, l.line, k, "unknown metadata keyword");
}

}  // namespace

namespace detail {
// The OEM of KVN lines (from tokenize_kvn, or synthesized from XML by oem_xml.cpp with the XML's line
// numbers), so both encodings share one set of rules and messages.
Oem parse_oem_lines(const std::vector<KvnLine>& lines, const std::string& source) {
  using K = KvnLine::Kind;
  Oem oem;
  const KvnLine& v = detail::check_version_line(lines, "CCSDS_OEM_VERS", {"1.0", "2.0", "3.0"}, source);
  oem.header.version = v.value;
  enum class State { header, meta, data, cov } st = State::header;
  std::map<std::string, int> header_seen, meta_seen;
  int last = v.line;
  std::vector<std::string> pending_cov_comments;
  auto check_segment_end = [&](int line) {
    if (!oem.segments.empty() && oem.segments.back().states.empty())
      fail(source, line, "META_STOP", "segment without ephemeris data lines");
  };
  int cov_row = 6;  // rows read of the current covariance matrix (6: none pending)
  int cov_line = 0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const KvnLine& l = lines[i];
    last = l.line;
    switch (st) {
      case State::header:
        if (l.kind == K::comment) {
          oem.header.comments.push_back(l.value);
        } else if (l.kind == K::key_value) {
          odm_header(oem.header, l, header_seen, source);
        } else if (l.kind == K::marker && l.key == "META_START") {
          for (const char* k : {"CREATION_DATE", "ORIGINATOR"})
            if (!header_seen.count(k)) fail(source, l.line, k, "missing mandatory header keyword");
          oem.segments.emplace_back();
          meta_seen.clear();
          st = State::meta;
        } else {
          fail(source, l.line, l.kind == K::raw ? l.value : l.key, "unexpected line in the header");
        }
        break;
      case State::meta:
        if (l.kind == K::comment) {
          oem.segments.back().metadata.comments.push_back(l.value);
        } else if (l.kind == K::key_value) {
          if (meta_seen.count(l.key)) fail(source, l.line, l.key, "duplicate keyword in the metadata");
          meta_seen[l.key] = l.line;
          oem_meta(oem.segments.back().metadata, l, source);
        } else if (l.kind == K::marker && l.key == "META_STOP") {
          for (const char* k : {"OBJECT_NAME", "OBJECT_ID", "CENTER_NAME", "REF_FRAME", "TIME_SYSTEM",
                                "START_TIME", "STOP_TIME"})
            if (!meta_seen.count(k)) fail(source, l.line, k, "missing mandatory keyword");
          st = State::data;
        } else {
          fail(source, l.line, l.kind == K::raw ? l.value : l.key,
               "unexpected line in the metadata (META_STOP missing?)");
        }
        break;
      case State::data:
        if (l.kind == K::comment) {
          oem.segments.back().data_comments.push_back(l.value);
        } else if (l.kind == K::raw) {
          if (!oem.segments.back().covariances.empty())
            fail(source, l.line, "EPOCH", "ephemeris line after the covariance block");
          const std::vector<std::string> f = detail::split_ws(l.value);
          if (f.size() != 7 && f.size() != 10)
            fail(source, l.line, "EPHEMERIS",
                 "an ephemeris line is an epoch and 6 numbers (or 9 with accelerations), got " +
                     std::to_string(f.size()) + " fields");
          OemState s;
          s.epoch = check_epoch(f[0], source, l.line, "EPOCH");
          s.time =
              detail::to_epoch(s.epoch, oem.segments.back().metadata.time_system, source, l.line, "EPOCH");
          for (int j = 0; j < 6; ++j)
            s.state(j) = detail::parse_number(f[1 + j], source, l.line, "EPHEMERIS");
          if (f.size() == 10) {
            Vec3 a;
            for (int j = 0; j < 3; ++j) a(j) = detail::parse_number(f[7 + j], source, l.line, "EPHEMERIS");
            s.acceleration = a;
          }
          oem.segments.back().states.push_back(std::move(s));
        } else if (l.kind == K::marker && l.key == "COVARIANCE_START") {
          check_segment_end(l.line);
          st = State::cov;
        } else if (l.kind == K::marker && l.key == "META_START") {
          check_segment_end(l.line);
          oem.segments.emplace_back();
          meta_seen.clear();
          st = State::meta;
        } else {
          fail(source, l.line, l.kind == K::raw ? l.value : l.key, "unexpected line in the ephemeris data");
        }
        break;
      case State::cov: {
        auto& covs = oem.segments.back().covariances;
        if (l.kind == K::comment) {
          pending_cov_comments.push_back(l.value);
        } else if (l.kind == K::key_value && l.key == "EPOCH") {
          if (cov_row < 6)
            fail(source, l.line, "EPOCH", "covariance matrix incomplete: 6 rows of 1..6 numbers");
          covs.emplace_back();
          covs.back().comments = std::move(pending_cov_comments);
          pending_cov_comments.clear();
          covs.back().epoch = check_epoch(l.value, source, l.line, "EPOCH");
          covs.back().time = detail::to_epoch(covs.back().epoch, oem.segments.back().metadata.time_system,
                                              source, l.line, "EPOCH");
          cov_row = 0;
          cov_line = l.line;
        } else if (l.kind == K::key_value && l.key == "COV_REF_FRAME") {
          if (covs.empty() || cov_row != 0) fail(source, l.line, l.key, "must follow the covariance EPOCH");
          covs.back().cov_ref_frame = l.value;
        } else if (l.kind == K::raw) {
          if (covs.empty()) fail(source, l.line, "EPOCH", "missing before the covariance matrix");
          if (cov_row >= 6)
            fail(source, l.line, "COVARIANCE", "more than 6 rows (hint: EPOCH starts the next matrix)");
          const std::vector<std::string> f = detail::split_ws(l.value);
          if (static_cast<int>(f.size()) != cov_row + 1)
            fail(source, l.line, "COVARIANCE",
                 "row " + std::to_string(cov_row + 1) + " of the lower triangle needs " +
                     std::to_string(cov_row + 1) + " numbers, got " + std::to_string(f.size()));
          Mat6& m = covs.back().matrix;
          for (int j = 0; j <= cov_row; ++j) {
            m(cov_row, j) = detail::parse_number(f[j], source, l.line, "COVARIANCE");
            m(j, cov_row) = m(cov_row, j);
          }
          ++cov_row;
        } else if (l.kind == K::marker && l.key == "COVARIANCE_STOP") {
          if (covs.empty()) fail(source, l.line, "EPOCH", "covariance block without a matrix");
          if (cov_row < 6)
            fail(source, l.line, "COVARIANCE",
                 "matrix of EPOCH line " + std::to_string(cov_line) + " has " + std::to_string(cov_row) +
                     " of 6 rows");
          st = State::data;  // only META_START may follow; an ephemeris line is refused above
        } else {
          fail(source, l.line, l.kind == K::raw ? l.value : l.key, "unexpected line in the covariance block");
        }
        break;
      }
    }
  }
  if (st == State::header) fail(source, last, "META_START", "no segment (an OEM needs at least one)");
  if (st == State::meta) fail(source, last, "META_STOP", "missing at the end of the file");
  if (st == State::cov) fail(source, last, "COVARIANCE_STOP", "missing at the end of the file");
  check_segment_end(last);
  return oem;
}
}  // namespace detail

Oem parse_oem(const std::string& text, const std::string& source) {
  if (detail::is_xml(text)) return detail::parse_oem_xml(text, source);
  return detail::parse_oem_lines(detail::tokenize_kvn(text, source), source);
}

Oem read_oem(const std::string& path) { return parse_oem(detail::read_file(path), path); }

using detail::put;
using detail::put_comments;
using detail::put_opt;

std::string format_oem(const Oem& oem) {
  std::ostringstream out;
  detail::put_header(out, "CCSDS_OEM_VERS", oem.header);
  for (std::size_t s = 0; s < oem.segments.size(); ++s) {
    const OemSegment& seg = oem.segments[s];
    const OemMetadata& m = seg.metadata;
    const std::string at = "segments[" + std::to_string(s) + "]";
    out << "\nMETA_START\n";
    put_comments(out, m.comments);
    detail::put_object(
        out, {m.object_name, m.object_id, m.center_name, m.ref_frame, m.ref_frame_epoch, m.time_system});
    put(out, "START_TIME", m.start_time);
    put_opt(out, "USEABLE_START_TIME", m.useable_start_time);
    put_opt(out, "USEABLE_STOP_TIME", m.useable_stop_time);
    put(out, "STOP_TIME", m.stop_time);
    put_opt(out, "INTERPOLATION", m.interpolation);
    if (m.interpolation_degree) put(out, "INTERPOLATION_DEGREE", std::to_string(*m.interpolation_degree));
    out << "META_STOP\n\n";
    put_comments(out, seg.data_comments);
    for (std::size_t i = 0; i < seg.states.size(); ++i) {
      const OemState& st = seg.states[i];
      const std::string name = at + ".states[" + std::to_string(i) + "]";
      out << detail::epoch_or_time(st.epoch, st.time, m.time_system);
      for (int j = 0; j < 6; ++j) out << " " << format_number(st.state(j), name + ".state");
      if (st.acceleration)
        for (int j = 0; j < 3; ++j)
          out << " " << format_number((*st.acceleration)(j), name + ".acceleration");
      out << "\n";
    }
    if (!seg.covariances.empty()) {
      out << "\nCOVARIANCE_START\n";
      for (std::size_t c = 0; c < seg.covariances.size(); ++c) {
        const OemCovariance& cv = seg.covariances[c];
        const std::string name = at + ".covariances[" + std::to_string(c) + "].matrix";
        if (!cv.matrix.isApprox(cv.matrix.transpose(), 1e-12) &&
            !(cv.matrix - cv.matrix.transpose()).isZero(0.0))
          throw std::invalid_argument(name + ": must be symmetric");
        put_comments(out, cv.comments);
        put(out, "EPOCH", detail::epoch_or_time(cv.epoch, cv.time, m.time_system));
        put_opt(out, "COV_REF_FRAME", cv.cov_ref_frame);
        for (int r = 0; r < 6; ++r) {
          for (int j = 0; j <= r; ++j) out << (j ? " " : "") << format_number(cv.matrix(r, j), name);
          out << "\n";
        }
      }
      out << "COVARIANCE_STOP\n";
    }
  }
  return detail::read_back_checked(out.str(), "oem", "OEM", [](const std::string& t, const std::string& src) {
    return parse_oem(t, src);
  });
}

void write_oem(const std::string& path, const Oem& oem) { detail::write_file(path, format_oem(oem)); }

void write_oem(const std::string& path, const Oem& oem, bool xml) {
  detail::write_file(path, xml ? format_oem_xml(oem) : format_oem(oem));
}

}  // namespace satgnc::io
