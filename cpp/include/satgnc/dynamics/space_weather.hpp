#pragma once
/// @file space_weather.hpp
/// Solar and geomagnetic activity inputs of the atmosphere models that take them (NRLMSISE-00 and
/// its kin; Harris-Priester is tabulated for mean activity and ignores them). Given by the user;
/// the defaults are the moderate-activity constants of the NRLMSISE-00 reference test cases.

namespace satgnc::dynamics {

/// Space weather. Units: F10.7 in solar flux units (sfu, 1e-22 W m^-2 Hz^-1); Ap dimensionless (the
/// daily planetary index, 0-400).
struct SpaceWeather {
  double f107 = 150.0;   ///< F10.7 of the previous day, sfu, in [0, 400]
  double f107a = 150.0;  ///< 81-day centred average of F10.7, sfu, in [0, 400]
  double ap = 4.0;       ///< daily planetary geomagnetic index Ap, in [0, 400]

  /// Maximum accepted F10.7 and F10.7a, sfu (the largest observed daily values are ~370 sfu).
  static constexpr double max_f107 = 400.0;
  /// Maximum accepted Ap (the index saturates at 400).
  static constexpr double max_ap = 400.0;

  /// Throw std::invalid_argument naming prefix.field (e.g. "space_weather.f107: must be in [0, 400]
  /// sfu, got -1") unless every field is finite and in its range.
  void validate(const char* prefix = "space_weather") const;
};

}  // namespace satgnc::dynamics
