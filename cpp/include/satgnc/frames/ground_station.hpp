#pragma once
/// @file ground_station.hpp
/// A tracking station fixed in the ITRF at WGS-84 geodetic coordinates (eraGd2gc), carried to the
/// GCRF with the IAU 2006/2000A chain and EOP (earth_orientation.hpp), and the topocentric azimuth /
/// elevation of a satellite with their rates and an elevation mask. Station motion from plate
/// tectonics, solid-Earth tides and ocean loading (cm level) is not modelled.
///
/// The Gao-Luo paper's station rotating about inertial z (dynamics::Station) is unchanged and stays
/// the model of the paper's reproduction.
#include <string>

#include "satgnc/core/epoch.hpp"
#include "satgnc/core/types.hpp"
#include "satgnc/frames/earth_orientation.hpp"
#include "satgnc/frames/eop.hpp"

namespace satgnc::frames {

/// Lowest accepted height above the WGS-84 ellipsoid (km). The lowest land is the Dead Sea shore,
/// about -0.43 km below sea level (the geoid there is within 0.03 km of the ellipsoid); -0.5 km leaves
/// a margin for that and refuses a height typed in metres or with the wrong sign of a deep value.
inline constexpr double kMinStationHeightKm = -0.5;

/// Topocentric look angles of a satellite from a station and their rates. Azimuth from north
/// towards east, in [0, 2 pi); elevation above the plane normal to the geodetic vertical.
struct LookAngles {
  double azimuth = 0.0;         ///< rad, [0, 2 pi)
  double elevation = 0.0;       ///< rad, [-pi/2, pi/2]
  double range = 0.0;           ///< km
  double azimuth_rate = 0.0;    ///< rad/s (undefined at the zenith: returned as 0 there)
  double elevation_rate = 0.0;  ///< rad/s
  double range_rate = 0.0;      ///< km/s
};

/// A ground station at WGS-84 geodetic coordinates, fixed in the ITRF.
class GroundStation {
 public:
  /// latitude_deg in [-90, 90], longitude_deg finite (east positive), height_km above the WGS-84
  /// ellipsoid >= kMinStationHeightKm (-0.5 km) and <= 100 km, elevation_mask_deg in [-90, 90].
  /// Throws std::invalid_argument naming the argument.
  GroundStation(double latitude_deg, double longitude_deg, double height_km, double elevation_mask_deg = 0.0,
                std::string name = "");

  const std::string& name() const { return name_; }        ///< label
  double latitude_deg() const { return lat_deg_; }         ///< geodetic, deg
  double longitude_deg() const { return lon_deg_; }        ///< east, deg
  double height_km() const { return height_km_; }          ///< above WGS-84, km
  double elevation_mask_deg() const { return mask_deg_; }  ///< deg
  const Vec3& position_itrf() const { return r_itrf_; }    ///< km, ITRF
  /// Rows east, north, up (geodetic vertical) in ITRF axes: v_enu = itrf_to_enu() v_itrf.
  const Mat3& itrf_to_enu() const { return enu_; }

  /// Station state [r (km), v (km/s)] in the GCRF at epoch, EOP from table.
  Vec6 state_gcrf(const core::Epoch& epoch, const EopTable& table) const;
  /// Station state in the GCRF with a precomputed orientation.
  Vec6 state_gcrf(const EarthOrientation& orientation) const;

  /// Look angles of a satellite whose ITRF state [r (km), v (km/s)] is given (v relative to the
  /// ITRF, as gcrs_to_itrs returns it).
  LookAngles look_itrf(const Vec6& satellite_itrf) const;
  /// Look angles of a satellite whose GCRF state is given, at epoch with EOP from table.
  LookAngles look(const Vec6& satellite_gcrf, const core::Epoch& epoch, const EopTable& table) const;
  /// True when elevation (rad) is at or above the mask.
  bool visible(double elevation_rad) const;

 private:
  std::string name_;
  double lat_deg_, lon_deg_, height_km_, mask_deg_;
  Vec3 r_itrf_;
  Mat3 enu_;
};

}  // namespace satgnc::frames
