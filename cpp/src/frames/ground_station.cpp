// frames::GroundStation: WGS-84 geodetic station (eraGd2gc), GCRF state with EOP, look angles.
#include "satgnc/frames/ground_station.hpp"

#include <erfa.h>
#include <erfam.h>

#include <cmath>
#include <string>
#include <utility>

#include "satgnc/core/validate.hpp"

namespace satgnc::frames {

GroundStation::GroundStation(double latitude_deg, double longitude_deg, double height_km,
                             double elevation_mask_deg, std::string name)
    : name_(std::move(name)),
      lat_deg_(latitude_deg),
      lon_deg_(longitude_deg),
      height_km_(height_km),
      mask_deg_(elevation_mask_deg) {
  core::require(std::isfinite(latitude_deg) && std::fabs(latitude_deg) <= 90.0, "latitude_deg",
                "must be in [-90, 90], got " + std::to_string(latitude_deg));
  core::require_finite(longitude_deg, "longitude_deg");
  core::require_finite(height_km, "height_km");
  core::require(height_km >= kMinStationHeightKm, "height_km",
                std::to_string(height_km) +
                    " km is below the WGS-84 ellipsoid by more than the deepest real station (limit -0.5 km; "
                    "the Dead Sea shore is -0.43 km)",
                "height is in km, not m");
  core::require(height_km <= 100.0, "height_km",
                "must be <= 100 km for a ground station, got " + std::to_string(height_km) +
                    " (hint: height is in km)");
  core::require(std::isfinite(elevation_mask_deg) && std::fabs(elevation_mask_deg) <= 90.0,
                "elevation_mask_deg", "must be in [-90, 90], got " + std::to_string(elevation_mask_deg));
  const double phi = latitude_deg * ERFA_DD2R;
  const double lam = longitude_deg * ERFA_DD2R;
  double xyz[3];
  const int st = eraGd2gc(ERFA_WGS84, lam, phi, height_km * 1e3, xyz);
  core::require(st == 0, "height_km",
                "ERFA eraGd2gc refused the coordinates (status " + std::to_string(st) + ")");
  r_itrf_ = Vec3(xyz[0], xyz[1], xyz[2]) * 1e-3;
  const double sp = std::sin(phi), cp = std::cos(phi), sl = std::sin(lam), cl = std::cos(lam);
  enu_ << -sl, cl, 0.0,        //
      -sp * cl, -sp * sl, cp,  //
      cp * cl, cp * sl, sp;
}

Vec6 GroundStation::state_gcrf(const EarthOrientation& orientation) const {
  Vec6 x;
  x << r_itrf_, Vec3::Zero();
  return itrs_to_gcrs(x, orientation);
}

Vec6 GroundStation::state_gcrf(const core::Epoch& epoch, const EopTable& table) const {
  return state_gcrf(earth_orientation(epoch, table));
}

LookAngles GroundStation::look_itrf(const Vec6& satellite_itrf) const {
  const Vec3 rho = enu_ * (satellite_itrf.head<3>() - r_itrf_);
  const Vec3 rho_dot = enu_ * satellite_itrf.tail<3>();  // the station is at rest in the ITRF
  const double e = rho(0), n = rho(1), u = rho(2);
  const double h2 = e * e + n * n;
  const double h = std::sqrt(h2);
  const double range = rho.norm();
  LookAngles a;
  a.range = range;
  a.range_rate = rho.dot(rho_dot) / range;
  a.elevation = std::atan2(u, h);
  double az = std::atan2(e, n);
  if (az < 0.0) az += 2.0 * M_PI;
  a.azimuth = az;
  if (h > 0.0) {
    const double h_dot = (e * rho_dot(0) + n * rho_dot(1)) / h;
    a.azimuth_rate = (rho_dot(0) * n - e * rho_dot(1)) / h2;
    a.elevation_rate = (h * rho_dot(2) - u * h_dot) / (range * range);
  }
  return a;
}

LookAngles GroundStation::look(const Vec6& satellite_gcrf, const core::Epoch& epoch,
                               const EopTable& table) const {
  return look_itrf(gcrs_to_itrs(satellite_gcrf, epoch, table));
}

bool GroundStation::visible(double elevation_rad) const { return elevation_rad >= mask_deg_ * ERFA_DD2R; }

}  // namespace satgnc::frames
