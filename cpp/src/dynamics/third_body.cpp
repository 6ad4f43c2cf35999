// Sun and Moon point masses with the indirect term; ephemerides from ERFA (km, km/s^2).
#include "satgnc/dynamics/third_body.hpp"

#include <erfa.h>

#include <cmath>

#include "satgnc/core/validate.hpp"

namespace satgnc::dynamics {

void ThirdBodies::validate() const {
  core::require_positive(mu_sun, "third_body.mu_sun");
  core::require_positive(mu_moon, "third_body.mu_moon");
}

Vec3 sun_position(double jd1, double jd2) {
  double pvh[2][3], pvb[2][3];
  eraEpv00(jd1, jd2, pvh, pvb);  // status 1 (outside 1900-2100) still gives the series' value
  return Vec3(-pvh[0][0], -pvh[0][1], -pvh[0][2]) * kAstronomicalUnitKm;
}

Vec3 moon_position(double jd1, double jd2) {
  double pv[2][3];
  eraMoon98(jd1, jd2, pv);
  return Vec3(pv[0][0], pv[0][1], pv[0][2]) * kAstronomicalUnitKm;
}

Vec3 third_body_acceleration(double mu, const Vec3& s, const Vec3& r) {
  const Vec3 d = s - r;
  const double dn = d.norm();
  const double sn = s.norm();
  return mu * (d / (dn * dn * dn) - s / (sn * sn * sn));
}

void third_body_jacobian(double mu, const Vec3& s, const Vec3& r, Vec3& a, Mat3& da_dr) {
  const Vec3 d = s - r;
  const double d2 = d.squaredNorm();
  const double dn = std::sqrt(d2);
  const double sn = s.norm();
  const double k = mu / (d2 * dn);
  a = k * d - (mu / (sn * sn * sn)) * s;
  da_dr = (3.0 * k / d2) * (d * d.transpose());
  da_dr.diagonal().array() -= k;
}

double third_body_potential(double mu, const Vec3& s, const Vec3& r) {
  const double sn = s.norm();
  return -mu * (1.0 / (s - r).norm() - s.dot(r) / (sn * sn * sn));
}

}  // namespace satgnc::dynamics
