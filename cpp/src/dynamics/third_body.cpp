// Sun and Moon point masses with the indirect term; ephemerides from ERFA (km, km/s^2).
#include "satgnc/dynamics/third_body.hpp"

#include <erfa.h>

#include <algorithm>
#include <cmath>
#include <utility>

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

namespace {
constexpr double kJ2000 = 2451545.0;

void sun_pv(double jd1, double jd2, Vec3& p, Vec3& v) {
  double pvh[2][3], pvb[2][3];
  eraEpv00(jd1, jd2, pvh, pvb);
  p = -Vec3(pvh[0][0], pvh[0][1], pvh[0][2]) * kAstronomicalUnitKm;
  v = -Vec3(pvh[1][0], pvh[1][1], pvh[1][2]) * kAstronomicalUnitKm;  // km/day
}

void moon_pv(double jd1, double jd2, Vec3& p, Vec3& v) {
  double pv[2][3];
  eraMoon98(jd1, jd2, pv);
  p = Vec3(pv[0][0], pv[0][1], pv[0][2]) * kAstronomicalUnitKm;
  v = Vec3(pv[1][0], pv[1][1], pv[1][2]) * kAstronomicalUnitKm;  // km/day
}

template <typename Pv>
Vec3 hermite(double step, double jd1, double jd2, Pv pv, double& node, Vec3& p0, Vec3& v0, Vec3& p1,
             Vec3& v1) {
  const double u = ((jd1 - kJ2000) + jd2) / step;
  const double k = std::floor(u);
  if (k != node) {
    pv(kJ2000, k * step, p0, v0);
    pv(kJ2000, (k + 1.0) * step, p1, v1);
    node = k;
  }
  const double s = u - k, s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  return h00 * p0 + (h10 * step) * v0 + h01 * p1 + (h11 * step) * v1;
}
}  // namespace

EphemerisInterpolator::EphemerisInterpolator(double step_days) : step_(step_days) {
  core::require_nonnegative(step_days, "step_days");
}

EphemerisInterpolator::EphemerisInterpolator(std::shared_ptr<const SpkEphemeris> spk)
    : step_(0.125), spk_(std::move(spk)) {
  core::require(spk_ != nullptr, "spk", "must be an opened SpkEphemeris, got null");
  for (const auto& [target, center] : SpkEphemeris::geocentric_sun_moon()) {
    const auto& p = spk_->pairs();
    core::require(std::find(p.begin(), p.end(), std::make_pair(target, center)) != p.end(), "spk",
                  spk_->path() + " was opened without the geocentric Sun (10, 399) and Moon (301, 399)");
  }
}

double EphemerisInterpolator::tdb_seconds(double jd1, double jd2) const {
  const double days = (jd1 - kJ2000) + jd2;
  const double u = days / step_;
  const double k = std::floor(u);
  if (k != tdb_.node) {
    const double t0 = SpkEphemeris::tdb_seconds_from_tt(kJ2000, k * step_);
    const double t1 = SpkEphemeris::tdb_seconds_from_tt(kJ2000, (k + 1.0) * step_);
    tdb_.d0 = t0 - k * step_ * 86400.0;
    tdb_.d1 = t1 - (k + 1.0) * step_ * 86400.0;
    tdb_.node = k;
  }
  const double s = u - k;
  return days * 86400.0 + ((1.0 - s) * tdb_.d0 + s * tdb_.d1);
}

Vec3 EphemerisInterpolator::sun(double jd1, double jd2) const {
  if (spk_) return spk_->position(naif::sun, naif::earth, tdb_seconds(jd1, jd2));
  if (step_ == 0.0) return sun_position(jd1, jd2);
  return hermite(step_, jd1, jd2, sun_pv, sun_.node, sun_.p0, sun_.v0, sun_.p1, sun_.v1);
}

Vec3 EphemerisInterpolator::moon(double jd1, double jd2) const {
  if (spk_) return spk_->position(naif::moon, naif::earth, tdb_seconds(jd1, jd2));
  if (step_ == 0.0) return moon_position(jd1, jd2);
  return hermite(step_, jd1, jd2, moon_pv, moon_.node, moon_.p0, moon_.v0, moon_.p1, moon_.v1);
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
