#include "satgnc/dynamics/station.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "satgnc/core/time.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::dynamics {

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
std::string normalize(const std::string& s) {
  std::string out;
  for (char c : s)
    if (std::isalnum(static_cast<unsigned char>(c))) out += static_cast<char>(std::tolower(c));
  return out;
}
}  // namespace

Ellipsoid ellipsoid_by_name(const std::string& name) {
  const std::string n = normalize(name);
  if (n == "wgs84") return ellipsoids::wgs84;
  if (n == "grs80") return ellipsoids::grs80;
  if (n == "iau1976" || n == "iau76") return ellipsoids::iau1976;
  if (n == "krassovsky" || n == "krasovsky" || n == "krassowsky") return ellipsoids::krassovsky;
  if (n == "sphere") return ellipsoids::sphere;
  throw std::invalid_argument("ellipsoid: unknown name '" + name +
                              "' (hint: one of WGS-84, GRS-80, IAU-1976, Krassovsky, sphere)");
}

Vec3 geodetic_to_ecef(double lat_rad, double lon_rad, double height_km, const Ellipsoid& ell) {
  core::require(std::isfinite(lat_rad) && std::abs(lat_rad) <= 0.5 * 3.14159265358979323846 + 1e-12,
                "latitude", "must be finite and within [-90, 90] deg");
  core::require_finite(lon_rad, "longitude");
  core::require(std::isfinite(height_km) && height_km > -12.0 && height_km < 100.0, "height_km",
                "must be finite, in km, within (-12, 100)", "heights are km, not m");
  core::require_positive(ell.a, "ellipsoid.a");
  core::require(std::isfinite(ell.f) && ell.f >= 0.0 && ell.f < 0.1, "ellipsoid.f", "must be in [0, 0.1)");
  const double e2 = ell.f * (2.0 - ell.f);
  const double s = std::sin(lat_rad), c = std::cos(lat_rad);
  const double n = ell.a / std::sqrt(1.0 - e2 * s * s);  // prime-vertical radius of curvature
  return Vec3((n + height_km) * c * std::cos(lon_rad), (n + height_km) * c * std::sin(lon_rad),
              (n * (1.0 - e2) + height_km) * s);
}

Mat3 rot_z(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Mat3 m;
  m << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return m;
}

Station Station::from_geodetic(double lat_deg, double lon_deg, double height_km, double jd_utc,
                               double ut1_minus_utc_s, const Ellipsoid& ell, double omega) {
  const Vec3 ecef = geodetic_to_ecef(lat_deg * kDeg, lon_deg * kDeg, height_km, ell);
  return from_ecef(ecef, core::gmst_from_utc(jd_utc, ut1_minus_utc_s), omega);
}

Station Station::from_ecef(const Vec3& ecef, double theta0_rad, double omega) {
  core::require_finite(ecef, "ecef");
  core::require_finite(theta0_rad, "theta0");
  Station s;
  s.r0 = rot_z(theta0_rad) * ecef;
  s.omega = omega;
  s.validate();
  return s;
}

Station Station::from_inertial(const Vec3& r0, double omega) {
  Station s;
  s.r0 = r0;
  s.omega = omega;
  s.validate();
  return s;
}

void Station::validate() const {
  core::require_finite(r0, "station.r0");
  core::require(r0.norm() > 0.0, "station.r0", "must not be the zero vector");
  core::require_finite(omega, "station.omega");
}

Vec6 Station::state(double t) const {
  const double th = omega * t, c = std::cos(th), s = std::sin(th);
  Vec6 out;
  out(0) = c * r0(0) - s * r0(1);
  out(1) = s * r0(0) + c * r0(1);
  out(2) = r0(2);
  out(3) = -omega * out(1);
  out(4) = omega * out(0);
  out(5) = 0.0;
  return out;
}

double implied_rotation_rate(const Vec6& x) {
  core::require_finite(x, "station_state");
  const double zx = -x(1), zy = x(0);  // z x R
  const double den = zx * zx + zy * zy;
  core::require(den > 0.0, "station_state", "position must not lie on the z axis");
  return (zx * x(3) + zy * x(4)) / den;
}

}  // namespace satgnc::dynamics
