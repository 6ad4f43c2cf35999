// Drag with any AtmosphereModel and a co-rotating atmosphere (GCRF; km, km/s, s), its Jacobians and
// its partial with respect to Cd.
#include <erfa.h>

#include <Eigen/Geometry>
#include <cmath>
#include <memory>
#include <string>

#include "satgnc/core/constants.hpp"
#include "satgnc/core/validate.hpp"
#include "satgnc/dynamics/atmosphere.hpp"

namespace satgnc::dynamics {

namespace {
// Cd*A/m in m^2/kg times rho in kg/m^3 is 1/m = 1e3/km.
constexpr double kPerMeterToPerKm = 1.0e3;
constexpr double kSecondsPerDay = 86400.0;

Mat3 cross_matrix(const Vec3& w) {
  Mat3 m;
  m << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return m;
}

void rotation(const AtmosphereDrag& d, double t, Mat3& gcrf_to_itrf, Vec3& omega_gcrf) noexcept {
  if (d.earth_rotation) {
    d.earth_rotation->rotation(t, gcrf_to_itrf, omega_gcrf);
    return;
  }
  const double th = core::earth::omega * t;  // UniformRotation(0, omega), inlined: no allocation
  const double c = std::cos(th), s = std::sin(th);
  gcrf_to_itrf << c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0;
  omega_gcrf = Vec3(0.0, 0.0, core::earth::omega);
}

double beta(const AtmosphereDrag& d) { return 0.5 * d.cd * d.area / d.mass * kPerMeterToPerKm; }
}  // namespace

FixedSun::FixedSun(const Vec3& direction) {
  core::require_finite(direction, "direction");
  core::require(direction.norm() > 0.0, "direction", "must be non-zero (a direction towards the Sun)");
  direction_ = direction.normalized();
}

ErfaSun::ErfaSun(double epoch_jd1, double epoch_jd2, double t_begin, double t_end, double node_spacing)
    : epoch_jd1_(epoch_jd1), epoch_jd2_(epoch_jd2), t_begin_(t_begin), spacing_(node_spacing), nodes_(0) {
  core::require_finite(epoch_jd1, "epoch_jd1");
  core::require_finite(epoch_jd2, "epoch_jd2");
  core::require_finite(t_begin, "t_begin");
  core::require_finite(t_end, "t_end");
  core::require(t_end > t_begin, "t_end", "must be > t_begin");
  core::require_positive(node_spacing, "node_spacing");
  const double n = std::ceil((t_end - t_begin) / node_spacing) + 1.0;
  core::require(n <= 1.0e6, "node_spacing", "gives more than 1e6 table nodes over [t_begin, t_end]");
  nodes_ = static_cast<int>(n);
  table_ = std::make_unique<double[]>(static_cast<std::size_t>(nodes_) * 6);
  for (int k = 0; k < nodes_; ++k) {
    Vec3 p, v;
    erfa_state(t_begin + k * node_spacing, p, v);
    for (int j = 0; j < 3; ++j) {
      table_[static_cast<std::size_t>(6 * k + j)] = p[j];
      table_[static_cast<std::size_t>(6 * k + 3 + j)] = v[j];
    }
  }
}

void ErfaSun::erfa_state(double t, Vec3& position_au, Vec3& velocity_au_per_day) const noexcept {
  double pvh[2][3];
  double pvb[2][3];
  eraEpv00(epoch_jd1_, epoch_jd2_ + t / kSecondsPerDay, pvh,
           pvb);  // status 1 outside 1900-2100: still smooth
  position_au = -Vec3(pvh[0][0], pvh[0][1], pvh[0][2]);
  velocity_au_per_day = -Vec3(pvh[1][0], pvh[1][1], pvh[1][2]);
}

Vec3 ErfaSun::direction(double t) const noexcept {
  const double u = (t - t_begin_) / spacing_;
  const double k = std::floor(u);
  if (!(k >= 0.0 && k + 1.0 < nodes_)) {  // outside the table (or NaN): ERFA directly
    Vec3 p, v;
    erfa_state(t, p, v);
    return p.normalized();
  }
  // Cubic Hermite on [node k, node k+1] with s in [0, 1]; velocities scaled to au per interval.
  const auto i = static_cast<std::size_t>(6 * static_cast<int>(k));
  const double s = u - k;
  const double h = spacing_ / kSecondsPerDay;
  const double h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s), h10 = s * (1.0 - s) * (1.0 - s);
  const double h01 = s * s * (3.0 - 2.0 * s), h11 = s * s * (s - 1.0);
  Vec3 p;
  for (int j = 0; j < 3; ++j) {
    const auto jj = static_cast<std::size_t>(j);
    p[j] = h00 * table_[i + jj] + h10 * h * table_[i + 3 + jj] + h01 * table_[i + 6 + jj] +
           h11 * h * table_[i + 9 + jj];
  }
  return p.normalized();
}

void AtmosphereDrag::validate(const char* prefix) const {
  const std::string p = std::string(prefix) + ".";
  core::require(atmosphere != nullptr, p + "atmosphere",
                "must be set (an AtmosphereModel, e.g. HarrisPriester)");
  core::require_nonnegative(cd, p + "cd");
  core::require_nonnegative(area, p + "area");
  core::require_positive(mass, p + "mass");
}

namespace {
AtmospherePoint drag_point(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& sun,
                           Mat3& gcrf_to_itrf, Vec3& omega_gcrf) noexcept {
  rotation(d, t, gcrf_to_itrf, omega_gcrf);
  return atmosphere_point(t, gcrf_to_itrf * r, gcrf_to_itrf * sun);
}

/// Density at the drag point and the velocity relative to the co-rotating atmosphere: what the
/// acceleration and its Cd partial share.
struct DragFlow {
  double rho;
  Vec3 w;
};

DragFlow drag_flow(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v,
                   const Vec3& sun) noexcept {
  Mat3 rot;
  Vec3 omega;
  const double rho = d.atmosphere->density(drag_point(d, t, r, sun, rot, omega));
  return {rho, v - omega.cross(r)};
}
}  // namespace

Vec3 atmosphere_drag_sun(const AtmosphereDrag& d, double t) noexcept {
  if (d.sun) return d.sun->direction(t);
  double pvh[2][3];
  double pvb[2][3];
  eraEpv00(2451545.0, t / kSecondsPerDay, pvh, pvb);  // J2000.0 TT, ForceModel's default epoch
  return -Vec3(pvh[0][0], pvh[0][1], pvh[0][2]).normalized();
}

AtmospherePoint atmosphere_drag_point(const AtmosphereDrag& d, double t, const Vec3& r, Mat3& gcrf_to_itrf,
                                      Vec3& omega_gcrf) noexcept {
  return drag_point(d, t, r, atmosphere_drag_sun(d, t), gcrf_to_itrf, omega_gcrf);
}

double atmosphere_drag_density(const AtmosphereDrag& d, double t, const Vec3& r) noexcept {
  Mat3 rot;
  Vec3 omega;
  return d.atmosphere->density(atmosphere_drag_point(d, t, r, rot, omega));
}

Vec3 atmosphere_drag_acceleration(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v) noexcept {
  return atmosphere_drag_acceleration(d, t, r, v, atmosphere_drag_sun(d, t));
}

Vec3 atmosphere_drag_acceleration(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v,
                                  const Vec3& sun_gcrf) noexcept {
  const DragFlow f = drag_flow(d, t, r, v, sun_gcrf);
  return (-beta(d) * f.rho * f.w.norm()) * f.w;
}

void atmosphere_drag_jacobians(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v, Vec3& a,
                               Mat3& da_dr, Mat3& da_dv) noexcept {
  atmosphere_drag_jacobians(d, t, r, v, atmosphere_drag_sun(d, t), a, da_dr, da_dv);
}

void atmosphere_drag_jacobians(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v,
                               const Vec3& sun_gcrf, Vec3& a, Mat3& da_dr, Mat3& da_dv) noexcept {
  Mat3 rot;
  Vec3 omega;
  Vec3 grad_itrf;
  const double rho = d.atmosphere->density_gradient(drag_point(d, t, r, sun_gcrf, rot, omega), grad_itrf);
  const Vec3 grad = rot.transpose() * grad_itrf;  // d rho / d r_gcrf, kg/m^3 per km
  const Vec3 w = v - omega.cross(r);
  const double wn = w.norm();
  const double b = beta(d);
  a = (-b * rho * wn) * w;
  // da/dw = -b rho (|w| I + w w^T/|w|), which tends to 0 as w -> 0.
  Mat3 da_dw = Mat3::Zero();
  if (wn > 0.0) {
    da_dw = (-b * rho / wn) * (w * w.transpose());
    da_dw.diagonal().array() -= b * rho * wn;
  }
  da_dv = da_dw;
  // da/dr = -b |w| w grad^T + da/dw dw/dr, dw/dr = -[omega]x.
  da_dr = ((-b * wn) * w) * grad.transpose() - da_dw * cross_matrix(omega);
}

Vec3 atmosphere_drag_cd_partial(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v) noexcept {
  return atmosphere_drag_cd_partial(d, t, r, v, atmosphere_drag_sun(d, t));
}

Vec3 atmosphere_drag_cd_partial(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v,
                                const Vec3& sun_gcrf) noexcept {
  const DragFlow f = drag_flow(d, t, r, v, sun_gcrf);
  return (-0.5 * d.area / d.mass * kPerMeterToPerKm * f.rho * f.w.norm()) * f.w;  // a / Cd
}

}  // namespace satgnc::dynamics
