#pragma once
/// @file constants.hpp
/// Physical constants defined once for the library and exported to Python (satgnc.EARTH_*).

namespace satgnc::core {

/// Earth constants (EGM-96 / WGS-84 values as used by Vallado, "Fundamentals of Astrodynamics and
/// Applications", 4th ed., Table D-1 / D-3). dynamics::earth is an alias of this namespace.
namespace earth {
inline constexpr double mu = 398600.4418;      ///< gravitational parameter, km^3/s^2 (EGM-96)
inline constexpr double radius = 6378.1363;    ///< equatorial radius, km (EGM-96)
inline constexpr double j2 = 1.0826266835e-3;  ///< unnormalized J2 (EGM-96, -C20 * sqrt(5)), dimensionless
inline constexpr double omega = 7.292115e-5;   ///< rotation rate, rad/s (IERS, mean)
}  // namespace earth

}  // namespace satgnc::core
