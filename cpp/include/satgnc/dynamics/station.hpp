#pragma once
/// @file station.hpp
/// Ground stations in the inertial frame. A station is an inertial position at the epoch (t = 0) that
/// rotates about the inertial +z axis at a constant rate (the Earth rotation angle grows linearly).
/// Two ways to build one: from geodetic coordinates on a named ellipsoid plus the UTC epoch (through
/// GMST IAU-1982), or directly from an inertial position at t0 and a rate (the paper's mode, Table 3).
/// Polar motion, precession and nutation are not modelled (GMST-only rotation).
#include <string>

#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/force_model.hpp"

namespace satgnc::dynamics {

/// Reference ellipsoid: equatorial radius a (km) and flattening f.
struct Ellipsoid {
  const char* name;
  double a;  ///< km
  double f;  ///< dimensionless
};

namespace ellipsoids {
inline constexpr Ellipsoid wgs84{"WGS-84", 6378.137, 1.0 / 298.257223563};
inline constexpr Ellipsoid grs80{"GRS-80", 6378.137, 1.0 / 298.257222101};
inline constexpr Ellipsoid iau1976{"IAU-1976", 6378.140, 1.0 / 298.257};
inline constexpr Ellipsoid krassovsky{"Krassovsky", 6378.245, 1.0 / 298.3};
/// Spherical Earth of radius 6378.137 km (f = 0).
inline constexpr Ellipsoid sphere{"sphere", 6378.137, 0.0};
}  // namespace ellipsoids

/// Ellipsoid by name (case-insensitive: "WGS-84", "WGS84", "GRS-80", "IAU-1976", "Krassovsky",
/// "sphere"); throws std::invalid_argument listing the choices.
Ellipsoid ellipsoid_by_name(const std::string& name);

/// Earth-fixed position (km) of geodetic latitude/longitude (rad) and height above the ellipsoid (km).
Vec3 geodetic_to_ecef(double lat_rad, double lon_rad, double height_km,
                      const Ellipsoid& ell = ellipsoids::wgs84);

/// Rotation about +z by angle (rad): x_inertial = rot_z(theta) * x_fixed.
Mat3 rot_z(double theta);

/// A tracking station: inertial position r0 (km) at t = 0 rotating about +z at omega (rad/s).
struct Station {
  Vec3 r0 = Vec3::Zero();                 ///< inertial position at the epoch t = 0, km
  double omega = dynamics::earth::omega;  ///< rotation rate about inertial +z, rad/s

  /// Station from geodetic coordinates (deg, deg, km) at the UTC epoch jd_utc (Julian date):
  /// r0 = rot_z(GMST(jd_utc + dut1)) * ecef. Throws std::invalid_argument on bad input.
  static Station from_geodetic(double lat_deg, double lon_deg, double height_km, double jd_utc,
                               double ut1_minus_utc_s = 0.0, const Ellipsoid& ell = ellipsoids::wgs84,
                               double omega = dynamics::earth::omega);
  /// Station from its Earth-fixed position (km) and the Earth rotation angle at t = 0 (rad).
  static Station from_ecef(const Vec3& ecef, double theta0_rad, double omega = dynamics::earth::omega);
  /// The paper's mode: inertial position at t0 (km), rotated about +z at omega (rad/s).
  static Station from_inertial(const Vec3& r0, double omega = dynamics::earth::omega);

  /// Throw std::invalid_argument unless r0 and omega are finite and |r0| > 0.
  void validate() const;
  /// Inertial state [R (km), V = omega z x R (km/s)] at t seconds after the epoch. No allocation.
  Vec6 state(double t) const;
};

/// Rotation rate (rad/s) implied by a printed inertial station state [R, V] if V = omega z x R:
/// least-squares omega = (z x R) . V / |z x R|^2. Used to check the paper's Table 3.
double implied_rotation_rate(const Vec6& station_state);

}  // namespace satgnc::dynamics
