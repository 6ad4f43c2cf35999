#include "satgnc/observation/station_ephemeris.hpp"

#include <erfa.h>

#include <cmath>
#include <string>
#include <utility>

#include "satgnc/core/validate.hpp"

namespace satgnc::observation {

RotatingStationEphemeris::RotatingStationEphemeris(const dynamics::Station& station,
                                                   const dynamics::Ellipsoid& ellipsoid)
    : station_(station) {
  station_.validate();
  core::require(std::isfinite(ellipsoid.a) && ellipsoid.a > 0.0, "ellipsoid.a", "must be finite and > 0 km");
  core::require(std::isfinite(ellipsoid.f) && ellipsoid.f >= 0.0 && ellipsoid.f < 1.0, "ellipsoid.f",
                "must be in [0, 1)");
  double xyz[3] = {station_.r0(0), station_.r0(1), station_.r0(2)};
  double elong = 0.0, phi = 0.0, height = 0.0;
  const int status = eraGc2gde(ellipsoid.a, ellipsoid.f, xyz, &elong, &phi, &height);
  core::require(status == 0, "station.r0", "ERFA eraGc2gde could not convert it to geodetic coordinates");
  latitude_ = phi;
  height_ = height;
}

void RotatingStationEphemeris::state(double t, StationState& out) const noexcept {
  const Vec6 s = station_.state(t);
  out.r = s.head<3>();
  out.v = s.tail<3>();
  const double w2 = station_.omega * station_.omega;
  out.a = Vec3(-w2 * out.r(0), -w2 * out.r(1), 0.0);  // omega z x (omega z x R)
  const double rho_xy = std::hypot(out.r(0), out.r(1));
  const double cl = rho_xy > 0.0 ? out.r(0) / rho_xy : 1.0;
  const double sl = rho_xy > 0.0 ? out.r(1) / rho_xy : 0.0;
  const double cp = std::cos(latitude_), sp = std::sin(latitude_);
  out.enu.row(0) = Vec3(-sl, cl, 0.0).transpose();
  out.enu.row(1) = Vec3(-sp * cl, -sp * sl, cp).transpose();
  out.enu.row(2) = Vec3(cp * cl, cp * sl, sp).transpose();
}

EarthFixedStationEphemeris::EarthFixedStationEphemeris(
    double latitude_rad, double longitude_rad, double height_km,
    std::shared_ptr<const frames::EarthRotationModel> rotation)
    : latitude_(latitude_rad), longitude_(longitude_rad), height_(height_km), rotation_(std::move(rotation)) {
  constexpr double kHalfPi = 1.5707963267948966;
  core::require(std::isfinite(latitude_rad) && std::abs(latitude_rad) <= kHalfPi, "latitude",
                "must be finite and within [-pi/2, pi/2] rad");
  core::require_finite(longitude_rad, "longitude");
  core::require(std::isfinite(height_km) && height_km >= kMinStationHeight && height_km <= 100.0, "height",
                "must be in [-0.5, 100] km above the ellipsoid (the Dead Sea shore is -0.43 km), got " +
                    std::to_string(height_km));
  core::require(rotation_ != nullptr, "rotation", "must be an Earth rotation model, got null");
  double xyz[3];
  const int status = eraGd2gc(1 /* WGS84 */, longitude_rad, latitude_rad, 1000.0 * height_km, xyz);
  core::require(status == 0, "latitude", "ERFA eraGd2gc refused the geodetic coordinates");
  r_itrf_ = Vec3(xyz[0], xyz[1], xyz[2]) / 1000.0;
  const double cl = std::cos(longitude_rad), sl = std::sin(longitude_rad);
  const double cp = std::cos(latitude_rad), sp = std::sin(latitude_rad);
  enu_itrf_.row(0) = Vec3(-sl, cl, 0.0).transpose();
  enu_itrf_.row(1) = Vec3(-sp * cl, -sp * sl, cp).transpose();
  enu_itrf_.row(2) = Vec3(cp * cl, cp * sl, sp).transpose();
}

EarthFixedStationEphemeris EarthFixedStationEphemeris::from_ground_station(
    const frames::GroundStation& station, std::shared_ptr<const frames::EarthRotationModel> rotation) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  return EarthFixedStationEphemeris(station.latitude_deg() * kDeg, station.longitude_deg() * kDeg,
                                    station.height_km(), std::move(rotation));
}

void EarthFixedStationEphemeris::state(double t, StationState& out) const noexcept {
  Mat3 M;
  Vec3 w;
  rotation_->rotation(t, M, w);
  out.r = M.transpose() * r_itrf_;
  out.v = w.cross(out.r);
  out.a = w.cross(out.v);
  out.enu = enu_itrf_ * M;
}

}  // namespace satgnc::observation
