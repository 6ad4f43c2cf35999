#pragma once
/// @file force_model_config.hpp
/// The force-model TOML (issue 14 item 8): one file names the models and their parameters, read by
/// C++ (a flight-style program without Python) and by Python (satgnc.load_force_model), so that
/// propagation, OD and the guidance truth use the same file. Parsed with toml++ (Debian
/// libtomlplusplus-dev). Schema, units and defaults: docs/force_models.md "The force-model TOML";
/// example: examples/force_model.toml.
///
/// Sections (every one optional; an absent section keeps the default):
/// - [central_body] mu (km^3/s^2, > 0; default the gravity file's GM, else core::earth::mu),
///   radius (km, > 0; default 6378.1363)
/// - [epoch] time (ISO 8601 calendar date of t = 0, e.g. "2024-03-20T12:00:00"), scale ("utc"
///   default, "tai", "tt", "gps", "tdb", "ut1" refused)
/// - [earth_orientation] model ("uniform" default: rotation about z at core::earth::omega from
///   theta0 = 0; "iau2006": IAU 2006/2000A with EOP, needs [epoch] and eop), eop (path of an IERS
///   finals2000A or C04 file, relative to the TOML's folder), days (span covered after the epoch,
///   default 7, (0, 3660]), theta0_deg (uniform only, default 0)
/// - [gravity] model ("point_mass" default, "j2", "egm2008" (the shipped degree-70 file), "file"),
///   file (ICGEM .gfc path for model = "file"), degree (2..file's max, default 20), order
///   (0..degree, default = degree), j2 (model "j2", default core::earth::j2); the field turns with
///   [earth_orientation]
/// - [third_body] sun, moon (booleans, default true once the section is present), ephemeris ("erfa"
///   default, or the path of a JPL DE SPK .bsp file, relative to the TOML's folder: its Sun and Moon
///   then serve the third bodies, SRP and the drag's Sun; the [epoch] must lie in its coverage)
/// - [srp] area (m^2, >= 0, required), mass (kg, > 0, required), cr ([0, 3], default 1.3), shadow ("conical"
/// default,
///   "cylindrical", "none")
/// - [drag] area (m^2, >= 0, required), mass (kg, > 0, required), cd ([0, 10], default 2.2), atmosphere
///   ("harris_priester" default, "exponential", "nrlmsise00": NRLMSISE-00 with
///   [space_weather] and the [epoch] (J2000 TT without one)), rho0
///   (kg/m^3, > 0), h0 (km), scale_height (km, > 0) for "exponential"; hp_n ([2, 6], default 2),
///   hp_lag_deg ([0, 180], default 30) for "harris_priester"
/// - [space_weather] f107, f107a (sfu, [0, 400], default 150), ap ([0, 400], default 4)
/// Errors are ForceModelConfigError: the file, the line, "[section] key" and the rule.
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "satgnc/core/epoch.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/dynamics/space_weather.hpp"
#include "satgnc/dynamics/two_satellite.hpp"

namespace satgnc::dynamics {

/// A force-model TOML that breaks its schema. what() reads "<file>:<line>: [<section>] <key>: <rule>"
/// (no line when none is at fault, e.g. a missing file).
class ForceModelConfigError : public std::invalid_argument {
 public:
  /// @param file the file (or source name); @param line 1-based, 0 when no single line is at fault;
  /// @param key "[section] key" or "[section]"; @param rule what is wrong.
  ForceModelConfigError(std::string file, int line, std::string key, std::string rule);
  const std::string& file() const noexcept { return file_; }  ///< the file or source name
  int line() const noexcept { return line_; }                 ///< 1-based line, 0 if none
  const std::string& key() const noexcept { return key_; }    ///< "[section] key"
  const std::string& rule() const noexcept { return rule_; }  ///< the rule broken

 private:
  std::string file_;
  int line_;
  std::string key_;
  std::string rule_;
};

/// What a force-model TOML describes: the ForceModel ready to propagate plus what it was built from.
struct ForceModelConfig {
  ForceModel model;                     ///< validated, epoch set from [epoch] when given
  std::optional<core::Epoch> epoch;     ///< epoch of t = 0 ([epoch]); empty: J2000.0 TT (the default)
  SpaceWeather space_weather;           ///< [space_weather] (for density models that use it)
  std::string gravity_model;            ///< "point_mass", "j2", "egm2008" or "file"
  std::string gravity_file;             ///< the .gfc path read (empty without a field)
  std::string atmosphere;               ///< "", "harris_priester", "exponential" or "nrlmsise00"
  std::string earth_orientation;        ///< "uniform" or "iau2006"
  std::string eop_file;                 ///< the EOP path read (iau2006), else empty
  std::string ephemeris_file;           ///< the JPL DE file of [third_body] ephemeris, else empty (ERFA)
  std::string source;                   ///< the TOML file (or source name)
  double radius = core::earth::radius;  ///< [central_body] radius, km
};

/// Read a force-model TOML file. `egm2008_path` locates the shipped EGM2008 .gfc for
/// [gravity] model = "egm2008" (Python passes satgnc.dynamics.EGM2008_PATH; C++ programs pass their
/// copy; empty: that model is an error saying so). Relative paths in the file are taken from the
/// TOML's folder. Throws ForceModelConfigError.
ForceModelConfig load_force_model_config(const std::string& path, const std::string& egm2008_path = "");

/// The same on TOML text; `source` names it in errors, `base_dir` resolves relative paths.
ForceModelConfig parse_force_model_config(std::string_view text, const std::string& source,
                                          const std::string& base_dir = ".",
                                          const std::string& egm2008_path = "");

/// The two-satellite model's parameters (dynamics/two_satellite.hpp, SI) for the guidance truth from
/// the same file: mu (km^3/s^2 -> m^3/s^2), J2 ([gravity] model "j2"), the surface / J2 radius, and
/// the exponential drag rewritten as rho0 exp(-decay (|r| - radius)) (rho0 = file rho0 exp(h0 /
/// scale_height), decay = 1 / scale_height) with the file's cd, area and mass for both bodies. The
/// rest of `base` (control frame, atmosphere rotation) is kept. The two-satellite model has no
/// gravity field, Sun, Moon, SRP or density table: a file with one of those throws
/// ForceModelConfigError naming the section.
TwoSatelliteParams two_satellite_params(const ForceModelConfig& config,
                                        const TwoSatelliteParams& base = TwoSatelliteParams());

/// load_force_model_config(path, egm2008_path).model.
ForceModel load_force_model(const std::string& path, const std::string& egm2008_path = "");

}  // namespace satgnc::dynamics
