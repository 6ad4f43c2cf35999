// Cannonball solar radiation pressure with cylindrical / conical Earth shadow (Montenbruck & Gill 3.4).
#include "satgnc/dynamics/srp.hpp"

#include <algorithm>
#include <cmath>

#include "satgnc/core/validate.hpp"
#include "satgnc/dynamics/third_body.hpp"

namespace satgnc::dynamics {

namespace {
constexpr double kPi = 3.14159265358979323846;

// Lit fraction and, when grad != nullptr, its gradient with respect to r (1/km).
double shadow_and_gradient(const SolarRadiationPressure& p, const Vec3& s, const Vec3& r, Vec3* grad) {
  if (grad) grad->setZero();
  if (p.shadow == ShadowModel::none) return 1.0;
  if (p.shadow == ShadowModel::cylindrical) {
    const Vec3 sh = s.normalized();
    const double along = r.dot(sh);
    if (along >= 0.0) return 1.0;
    return (r - along * sh).norm() < p.occulting_radius ? 0.0 : 1.0;
  }
  // Conical: apparent radii a (Sun), b (Earth) and separation c seen from the satellite.
  const Vec3 ds = s - r;
  const double D = ds.norm();
  const double rho = r.norm();
  const double a = std::asin(std::min(1.0, p.sun_radius / D));
  const double b = std::asin(std::min(1.0, p.occulting_radius / rho));
  const Vec3 ue = -r / rho;
  const Vec3 us = ds / D;
  const double q = std::clamp(ue.dot(us), -1.0, 1.0);
  const double c = std::acos(q);
  if (c >= a + b) return 1.0;
  if (c <= b - a) return 0.0;
  double nu = 0.0, dnu_da = 0.0, dnu_db = 0.0, dnu_dc = 0.0;
  if (c <= a - b) {  // annular: the Earth's disc inside the Sun's
    nu = 1.0 - b * b / (a * a);
    dnu_da = 2.0 * b * b / (a * a * a);
    dnu_db = -2.0 * b / (a * a);
  } else {
    const double x = (c * c + a * a - b * b) / (2.0 * c);
    const double y = std::sqrt(std::max(0.0, a * a - x * x));
    const double ta = std::acos(std::clamp(x / a, -1.0, 1.0));
    const double tb = std::acos(std::clamp((c - x) / b, -1.0, 1.0));
    const double A = a * a * ta + b * b * tb - c * y;  // overlap area of the two discs
    nu = 1.0 - A / (kPi * a * a);
    // dA/da = 2 a ta, dA/db = 2 b tb, dA/dc = -2 y (arc lengths and chord of the lens).
    dnu_da = -2.0 * a * ta / (kPi * a * a) + 2.0 * A / (kPi * a * a * a);
    dnu_db = -2.0 * b * tb / (kPi * a * a);
    dnu_dc = 2.0 * y / (kPi * a * a);
  }
  if (grad) {
    const double sa = p.sun_radius / D, sb = p.occulting_radius / rho;
    const Vec3 da = (-sa / (D * std::sqrt(std::max(1e-300, 1.0 - sa * sa)))) * (-us);  // dD/dr = -us
    const Vec3 db = (-sb / (rho * std::sqrt(std::max(1e-300, 1.0 - sb * sb)))) * (r / rho);
    const Vec3 rh = r / rho;
    const Vec3 dq = -(us - rh * rh.dot(us)) / rho - (ue - us * us.dot(ue)) / D;
    const Vec3 dc = (-1.0 / std::sqrt(std::max(1e-300, 1.0 - q * q))) * dq;
    *grad = dnu_da * da + dnu_db * db + dnu_dc * dc;
  }
  return nu;
}

double srp_scale(const SolarRadiationPressure& p) {
  // P Cr A/m in m/s^2 at 1 AU -> km/s^2, times AU^2 (km^2): a = nu K (r - s)/|r - s|^3.
  return p.pressure * p.cr * p.area / p.mass * 1e-3 * kAstronomicalUnitKm * kAstronomicalUnitKm;
}
}  // namespace

void SolarRadiationPressure::validate() const {
  core::require_nonnegative(area, "srp.area");
  core::require_positive(mass, "srp.mass");
  core::require_nonnegative(cr, "srp.cr");
  core::require_nonnegative(pressure, "srp.pressure");
  core::require_positive(occulting_radius, "srp.occulting_radius");
  core::require_positive(sun_radius, "srp.sun_radius");
  core::require(
      shadow == ShadowModel::none || shadow == ShadowModel::cylindrical || shadow == ShadowModel::conical,
      "srp.shadow", "must be none, cylindrical or conical");
}

double srp_shadow(const SolarRadiationPressure& p, const Vec3& s, const Vec3& r) {
  return shadow_and_gradient(p, s, r, nullptr);
}

Vec3 srp_acceleration(const SolarRadiationPressure& p, const Vec3& s, const Vec3& r) {
  const double nu = shadow_and_gradient(p, s, r, nullptr);
  if (nu == 0.0) return Vec3::Zero();
  const Vec3 d = r - s;
  const double dn = d.norm();
  return (nu * srp_scale(p) / (dn * dn * dn)) * d;
}

void srp_jacobian(const SolarRadiationPressure& p, const Vec3& s, const Vec3& r, Vec3& a, Mat3& da_dr) {
  Vec3 gnu;
  const double nu = shadow_and_gradient(p, s, r, &gnu);
  const Vec3 d = r - s;
  const double d2 = d.squaredNorm();
  const double dn = std::sqrt(d2);
  const double K = srp_scale(p);
  const Vec3 e = (K / (d2 * dn)) * d;  // the lit acceleration
  a = nu * e;
  da_dr = (-3.0 * nu * K / (d2 * d2 * dn)) * (d * d.transpose());
  da_dr.diagonal().array() += nu * K / (d2 * dn);
  da_dr += e * gnu.transpose();
}

}  // namespace satgnc::dynamics
