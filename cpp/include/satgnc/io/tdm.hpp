#pragma once
/// @file tdm.hpp
/// CCSDS Tracking Data Message (CCSDS 503.0-B-2), KVN and XML, reader and writer. Supported (see
/// docs/io.md for the section references):
/// - metadata: TIME_SYSTEM UTC / TAI / TT / GPS / TDB (mandatory), PARTICIPANT_1..5 (1 mandatory),
///   MODE = SEQUENTIAL with PATH (e.g. `1,2,1` two-way, `2,1` one-way down-leg; every index must name
///   a PARTICIPANT_n), START_TIME / STOP_TIME, INTEGRATION_INTERVAL (s) / INTEGRATION_REF,
///   RANGE_UNITS km (s and RU are refused as unsupported), ANGLE_TYPE AZEL / RADEC (XEYN, XSYE
///   refused); the other metadata keywords of the standard (corrections, delays, bands, ...) are
///   checked (numbers must be numbers) and kept as read in TdmMetadata::other;
/// - data: RANGE (km), DOPPLER_INSTANTANEOUS / DOPPLER_INTEGRATED (km/s), ANGLE_1 / ANGLE_2
///   (deg, in [-180, 360)), RECEIVE_FREQ[_n] / TRANSMIT_FREQ_n (Hz), TRANSMIT_FREQ_RATE_n (Hz/s),
///   CARRIER_POWER (dBW), PC_N0 / PR_N0 (dBHz), CLOCK_BIAS (s), CLOCK_DRIFT (s/s), TROPO_DRY /
///   TROPO_WET (m), STEC (TECU), PRESSURE (hPa), RHUMIDITY (%), TEMPERATURE (K), MAG, RCS (m**2).
///   Refused as unsupported: DOPPLER_COUNT, RECEIVE_PHASE_CT_n, TRANSMIT_PHASE_CT_n, DOR,
///   VLBI_DELAY (SINGLE_DIFF mode).
/// A malformed file throws FormatError naming the file, the line and the keyword.
#include <optional>
#include <string>
#include <vector>

#include "satgnc/io/ccsds.hpp"

namespace satgnc::io {

/// One TDM metadata section.
struct TdmMetadata {
  std::vector<std::string> comments;           ///< COMMENT lines of the section
  TimeSystem time_system = TimeSystem::utc;    ///< TIME_SYSTEM of every epoch of the segment
  std::vector<std::string> participants;       ///< PARTICIPANT_1..n (entry i is PARTICIPANT_{i+1})
  std::string mode;                            ///< MODE: "SEQUENTIAL", or "" when absent
  std::vector<int> path;                       ///< PATH as participant indices (1-based), empty when absent
  std::string start_time;                      ///< START_TIME as in the file, "" when absent
  std::string stop_time;                       ///< STOP_TIME as in the file, "" when absent
  std::optional<double> integration_interval;  ///< INTEGRATION_INTERVAL (s, > 0)
  std::string integration_ref;                 ///< INTEGRATION_REF: START, MIDDLE, END or ""
  std::string range_units;      ///< RANGE_UNITS: "km" or "" (absent: the standard's default km)
  std::string angle_type;       ///< ANGLE_TYPE: "AZEL", "RADEC" or ""
  std::vector<KeyValue> other;  ///< every other metadata keyword, as read, in file order
};

/// One tracking observation: `KEYWORD = epoch value` (KVN) or an <observation> element (XML).
struct TdmObservation {
  std::string keyword;  ///< data keyword, e.g. "RANGE", "ANGLE_1"
  std::string epoch;    ///< the time tag as in the file (in the segment's TIME_SYSTEM); writers print
                        ///< `time` when empty
  double value = 0.0;   ///< the value in `unit`
  std::string unit;     ///< the unit the standard gives the keyword: "km", "km/s", "deg", "Hz", ...
  core::Epoch time;     ///< the time tag as an instant (read: `epoch` in the segment's TIME_SYSTEM)
};

/// A metadata section and its data section.
struct TdmSegment {
  TdmMetadata metadata;                      ///< META_START..META_STOP
  std::vector<std::string> data_comments;    ///< COMMENT lines of the data section
  std::vector<TdmObservation> observations;  ///< DATA_START..DATA_STOP, in file order
};

/// A whole TDM: header and segments.
struct Tdm {
  Header header;                     ///< CCSDS_TDM_VERS, CREATION_DATE, ORIGINATOR, ...
  std::vector<TdmSegment> segments;  ///< one or more segments
};

/// The unit of a supported TDM data keyword ("" for MAG), or nullptr when the keyword is not one.
const char* tdm_unit(const std::string& keyword) noexcept;

/// Parse TDM text; KVN or XML is told by the first non-blank character ('<': XML).
/// @param source the name used in error messages (a file name)
/// @throws FormatError on a malformed message
Tdm parse_tdm(const std::string& text, const std::string& source = "<string>");
/// Read a TDM file (KVN or XML). @throws FormatError, std::invalid_argument if unreadable
Tdm read_tdm(const std::string& path);
/// The KVN text of a TDM. @throws std::invalid_argument when the model breaks a rule above
std::string format_tdm_kvn(const Tdm& tdm);
/// The XML text of a TDM (NDM/XML layout, CCSDS 505.0-B; schema ndmxml-2.0.0). @throws std::invalid_argument
/// as format_tdm_kvn
std::string format_tdm_xml(const Tdm& tdm);
/// Write a TDM file. @param xml false: KVN, true: XML. @throws std::invalid_argument
void write_tdm(const std::string& path, const Tdm& tdm, bool xml = false);

}  // namespace satgnc::io
