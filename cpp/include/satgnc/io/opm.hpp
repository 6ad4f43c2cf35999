#pragma once
/// @file opm.hpp
/// CCSDS Orbit Parameter Message (CCSDS 502.0-B-3 section 3), KVN: reader and writer of a state
/// vector (km, km/s) with optional osculating Keplerian elements (km, deg, km**3/s**2), spacecraft
/// parameters (kg, m**2), a 6 x 6 covariance and maneuvers. Units in square brackets after a value
/// are checked against the standard's unit. Malformed files throw FormatError.
#include <optional>
#include <string>
#include <vector>

#include "satgnc/core/types.hpp"
#include "satgnc/io/ccsds.hpp"

namespace satgnc::io {

/// Osculating Keplerian elements (all mandatory when any is given; one of the two anomalies).
struct OpmKeplerian {
  double semi_major_axis = 0.0;        ///< SEMI_MAJOR_AXIS (km)
  double eccentricity = 0.0;           ///< ECCENTRICITY
  double inclination = 0.0;            ///< INCLINATION (deg)
  double ra_of_asc_node = 0.0;         ///< RA_OF_ASC_NODE (deg)
  double arg_of_pericenter = 0.0;      ///< ARG_OF_PERICENTER (deg)
  std::optional<double> true_anomaly;  ///< TRUE_ANOMALY (deg)
  std::optional<double> mean_anomaly;  ///< MEAN_ANOMALY (deg)
  double gm = 0.0;                     ///< GM (km**3/s**2)
};

/// Spacecraft parameters (each optional).
struct OpmSpacecraft {
  std::optional<double> mass;             ///< MASS (kg)
  std::optional<double> solar_rad_area;   ///< SOLAR_RAD_AREA (m**2)
  std::optional<double> solar_rad_coeff;  ///< SOLAR_RAD_COEFF
  std::optional<double> drag_area;        ///< DRAG_AREA (m**2)
  std::optional<double> drag_coeff;       ///< DRAG_COEFF
};

/// One maneuver (MAN_EPOCH_IGNITION starts it; all six keywords mandatory).
struct OpmManeuver {
  std::vector<std::string> comments;  ///< COMMENT lines just before it
  std::string epoch_ignition;         ///< MAN_EPOCH_IGNITION ("": write `ignition_time`)
  core::Epoch ignition_time;          ///< the instant (read: epoch_ignition in the OPM's TIME_SYSTEM)
  double duration = 0.0;              ///< MAN_DURATION (s)
  double delta_mass = 0.0;            ///< MAN_DELTA_MASS (kg, <= 0)
  std::string ref_frame;              ///< MAN_REF_FRAME, e.g. "RTN", "EME2000"
  Vec3 dv = Vec3::Zero();             ///< MAN_DV_1..3 (km/s)
};

/// A whole OPM.
struct Opm {
  Header header;                               ///< CCSDS_OPM_VERS, CREATION_DATE, ORIGINATOR, ...
  std::vector<std::string> metadata_comments;  ///< COMMENT lines before OBJECT_NAME
  std::string object_name;                     ///< OBJECT_NAME (mandatory)
  std::string object_id;                       ///< OBJECT_ID (mandatory)
  std::string center_name;                     ///< CENTER_NAME (mandatory)
  std::string ref_frame;                       ///< REF_FRAME (mandatory)
  std::string ref_frame_epoch;                 ///< REF_FRAME_EPOCH, "" when absent
  TimeSystem time_system = TimeSystem::utc;    ///< TIME_SYSTEM (mandatory)
  std::vector<std::string> data_comments;      ///< COMMENT lines of the data sections
  std::string epoch;                           ///< EPOCH of the state vector (mandatory; "": write `time`)
  core::Epoch time;                            ///< the instant (read: `epoch` in the TIME_SYSTEM)
  Vec6 state = Vec6::Zero();                   ///< X..Z (km), X_DOT..Z_DOT (km/s), mandatory
  std::optional<OpmKeplerian> keplerian;       ///< osculating elements, when given
  std::optional<OpmSpacecraft> spacecraft;     ///< spacecraft parameters, when any is given
  std::string cov_ref_frame;                   ///< COV_REF_FRAME, "" when absent
  std::optional<Mat6> covariance;              ///< CX_X..CZ_DOT_Z_DOT (all 21 when any), symmetric
  std::vector<OpmManeuver> maneuvers;          ///< in file order
  std::vector<KeyValue> user_defined;          ///< USER_DEFINED_xxx (keyword without the prefix)
};

/// Parse OPM text, KVN or XML (told by the first non-blank character, '<': XML; the NDM/XML layout of
/// CCSDS 505.0-B: <opm><header/><body><segment><metadata/><data> with stateVector, keplerianElements,
/// spacecraftParameters, covarianceMatrix, maneuverParameters, userDefinedParameters). Both encodings go
/// through the same rules; XML errors name the XML line. @param source the name used in error messages.
/// @throws FormatError
Opm parse_opm(const std::string& text, const std::string& source = "<string>");
/// Read an OPM file (KVN or XML). @throws FormatError, std::invalid_argument if unreadable
Opm read_opm(const std::string& path);
/// The KVN text of an OPM. @throws std::invalid_argument when the model breaks a rule above
std::string format_opm(const Opm& opm);
/// Write an OPM KVN file. @throws std::invalid_argument
void write_opm(const std::string& path, const Opm& opm);
/// The XML text of an OPM (NDM/XML, schema ndmxml-2.0.0), read back and checked as the KVN writer does.
/// @throws std::invalid_argument as format_opm
std::string format_opm_xml(const Opm& opm);
/// Write an OPM file. @param xml false: KVN, true: XML. @throws std::invalid_argument
void write_opm(const std::string& path, const Opm& opm, bool xml);

}  // namespace satgnc::io
