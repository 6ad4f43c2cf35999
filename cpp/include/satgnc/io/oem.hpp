#pragma once
/// @file oem.hpp
/// CCSDS Orbit Ephemeris Message (CCSDS 502.0-B-3 section 5), KVN: reader and writer of trajectories
/// (position km, velocity km/s, optional acceleration km/s**2) with optional covariance blocks
/// (6 x 6, km**2, km**2/s, km**2/s**2, lower triangle on 6 lines). Malformed files throw FormatError.
#include <optional>
#include <string>
#include <vector>

#include "satgnc/core/types.hpp"
#include "satgnc/io/ccsds.hpp"

namespace satgnc::io {

/// OEM metadata (META_START..META_STOP).
struct OemMetadata {
  std::vector<std::string> comments;         ///< COMMENT lines of the section
  std::string object_name;                   ///< OBJECT_NAME (mandatory)
  std::string object_id;                     ///< OBJECT_ID (mandatory)
  std::string center_name;                   ///< CENTER_NAME (mandatory), e.g. "EARTH"
  std::string ref_frame;                     ///< REF_FRAME (mandatory), e.g. "EME2000", "GCRF", "ITRF2000"
  std::string ref_frame_epoch;               ///< REF_FRAME_EPOCH, "" when absent
  TimeSystem time_system = TimeSystem::utc;  ///< TIME_SYSTEM (mandatory)
  std::string start_time;                    ///< START_TIME (mandatory)
  std::string useable_start_time;            ///< USEABLE_START_TIME, "" when absent
  std::string useable_stop_time;             ///< USEABLE_STOP_TIME, "" when absent
  std::string stop_time;                     ///< STOP_TIME (mandatory)
  std::string interpolation;                 ///< INTERPOLATION, "" when absent
  std::optional<int> interpolation_degree;   ///< INTERPOLATION_DEGREE (>= 0)
};

/// One ephemeris line: epoch, [x y z] km, [vx vy vz] km/s, optional [ax ay az] km/s**2.
struct OemState {
  std::string epoch;                 ///< as in the file, in the segment's TIME_SYSTEM ("": write `time`)
  core::Epoch time;                  ///< the instant (read: `epoch` in the segment's TIME_SYSTEM)
  Vec6 state = Vec6::Zero();         ///< position (km) and velocity (km/s)
  std::optional<Vec3> acceleration;  ///< km/s**2, when the line has 9 numbers
};

/// One covariance matrix of a COVARIANCE_START..COVARIANCE_STOP block.
struct OemCovariance {
  std::vector<std::string> comments;  ///< COMMENT lines before its EPOCH
  std::string epoch;                  ///< EPOCH (mandatory; "": write `time`)
  core::Epoch time;                   ///< the instant (read: `epoch` in the segment's TIME_SYSTEM)
  std::string cov_ref_frame;          ///< COV_REF_FRAME, "" when absent (then REF_FRAME applies)
  Mat6 matrix = Mat6::Zero();         ///< symmetric, [km, km/s] blocks: km**2, km**2/s, km**2/s**2
};

/// A metadata section, its ephemeris lines and its covariance matrices.
struct OemSegment {
  OemMetadata metadata;                    ///< META_START..META_STOP
  std::vector<std::string> data_comments;  ///< COMMENT lines among the ephemeris lines
  std::vector<OemState> states;            ///< ephemeris data lines, in file order (at least one)
  std::vector<OemCovariance> covariances;  ///< covariance matrices, possibly none
};

/// A whole OEM.
struct Oem {
  Header header;                     ///< CCSDS_OEM_VERS, CREATION_DATE, ORIGINATOR, ...
  std::vector<OemSegment> segments;  ///< one or more segments
};

/// Parse OEM text, KVN or XML (told by the first non-blank character, '<': XML; the NDM/XML layout of
/// CCSDS 505.0-B, <oem><header/><body><segment><metadata/><data><stateVector/>...<covarianceMatrix/>).
/// Both encodings go through the same rules; XML errors name the XML line. @param source the name used
/// in error messages. @throws FormatError
Oem parse_oem(const std::string& text, const std::string& source = "<string>");
/// Read an OEM file (KVN or XML). @throws FormatError, std::invalid_argument if unreadable
Oem read_oem(const std::string& path);
/// The KVN text of an OEM (numbers in the shortest form that reads back to the same double).
/// @throws std::invalid_argument when the model misses a mandatory field or a value is not finite
std::string format_oem(const Oem& oem);
/// Write an OEM KVN file. @throws std::invalid_argument
void write_oem(const std::string& path, const Oem& oem);
/// The XML text of an OEM (NDM/XML, schema ndmxml-2.0.0: <stateVector> with EPOCH, X..Z_DOT[, X_DDOT..],
/// <covarianceMatrix> with EPOCH, COV_REF_FRAME, CX_X..CZ_DOT_Z_DOT), read back and checked as the KVN
/// writer does. @throws std::invalid_argument as format_oem
std::string format_oem_xml(const Oem& oem);
/// Write an OEM file. @param xml false: KVN, true: XML. @throws std::invalid_argument
void write_oem(const std::string& path, const Oem& oem, bool xml);

}  // namespace satgnc::io
