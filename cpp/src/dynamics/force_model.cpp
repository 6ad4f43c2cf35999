// Point-mass, J2 and exponential-drag accelerations with analytic Jacobians (km, km/s, s).
#include "satgnc/dynamics/force_model.hpp"

#include <cmath>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::dynamics {

namespace {
// Drag uses Cd*A/m in m^2/kg and rho in kg/m^3: their product is 1/m = 1e3/km.
constexpr double kPerMeterToPerKm = 1.0e3;

Mat3 cross_matrix(const Vec3& w) {
  Mat3 m;
  m << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return m;
}
}  // namespace

Vec3 point_mass_acceleration(double mu, const Vec3& r) {
  const double r2 = r.squaredNorm();
  const double rn = std::sqrt(r2);
  return (-mu / (r2 * rn)) * r;
}

void point_mass_jacobian(double mu, const Vec3& r, Vec3& a, Mat3& da_dr) {
  const double r2 = r.squaredNorm();
  const double rn = std::sqrt(r2);
  const double k = mu / (r2 * rn);
  a = -k * r;
  da_dr = (3.0 * k / r2) * (r * r.transpose());
  da_dr.diagonal().array() -= k;
}

Vec3 j2_acceleration(const J2Gravity& g, const Vec3& r) {
  const double r2 = r.squaredNorm();
  const double rn = std::sqrt(r2);
  const double k = -1.5 * g.j2 * g.mu * g.radius * g.radius / (r2 * r2 * rn);
  const double s = 5.0 * r.z() * r.z() / r2;
  return Vec3(k * r.x() * (1.0 - s), k * r.y() * (1.0 - s), k * r.z() * (3.0 - s));
}

void j2_jacobian(const J2Gravity& g, const Vec3& r, Vec3& a, Mat3& da_dr) {
  const double r2 = r.squaredNorm();
  const double rn = std::sqrt(r2);
  const double k = -1.5 * g.j2 * g.mu * g.radius * g.radius / (r2 * r2 * rn);  // k(r) ~ r^-5
  const double z = r.z();
  const double s = 5.0 * z * z / r2;
  const Vec3 c(1.0, 1.0, 3.0);
  // a_i = k x_i (c_i - s);  dk/dx_j = -5 k x_j / r^2;  ds/dx_j = 10 z dz_j / r^2 - 2 s x_j / r^2.
  Vec3 ds = (-2.0 * s / r2) * r;
  ds.z() += 10.0 * z / r2;
  for (int i = 0; i < 3; ++i) {
    const double f = c[i] - s;
    a[i] = k * r[i] * f;
    for (int j = 0; j < 3; ++j) {
      double d = -5.0 * k * r[j] / r2 * r[i] * f - k * r[i] * ds[j];
      if (i == j) d += k * f;
      da_dr(i, j) = d;
    }
  }
}

double j2_potential(const J2Gravity& g, const Vec3& r) {
  const double r2 = r.squaredNorm();
  const double rn = std::sqrt(r2);
  return g.mu * g.j2 * g.radius * g.radius * (3.0 * r.z() * r.z() / r2 - 1.0) / (2.0 * r2 * rn);
}

double exponential_density(const ExponentialDrag& d, double radius_km) {
  return d.rho0 * std::exp(-(radius_km - d.body_radius - d.h0) / d.scale_height);
}

void validate_density_radius(const ExponentialDrag& d, double radius_km, const char* name) {
  core::require_finite(radius_km, name);
  core::require(
      radius_km >= d.body_radius, name,
      "is below the surface: " + std::to_string(radius_km) +
          " km < body_radius = " + std::to_string(d.body_radius) + " km",
      "the exponential atmosphere is defined from the surface up; the argument is |r|, not the altitude");
}

Vec3 drag_acceleration(const ExponentialDrag& d, const Vec3& r, const Vec3& v) {
  const Vec3 w = v - d.omega.cross(r);
  const double beta = 0.5 * d.cd * d.area / d.mass * exponential_density(d, r.norm()) * kPerMeterToPerKm;
  return (-beta * w.norm()) * w;
}

void drag_jacobians(const ExponentialDrag& d, const Vec3& r, const Vec3& v, Vec3& a, Mat3& da_dr,
                    Mat3& da_dv) {
  const double rn = r.norm();
  const Vec3 w = v - d.omega.cross(r);
  const double wn = w.norm();
  const double beta = 0.5 * d.cd * d.area / d.mass * exponential_density(d, rn) * kPerMeterToPerKm;
  a = (-beta * wn) * w;
  // da/dw = -beta (|w| I + w w^T/|w|), which tends to 0 as w -> 0.
  Mat3 da_dw = Mat3::Zero();
  if (wn > 0.0) {
    da_dw = (-beta / wn) * (w * w.transpose());
    da_dw.diagonal().array() -= beta * wn;
  }
  da_dv = da_dw;
  // dbeta/dr = -beta/H r/|r|; dw/dr = -[omega]x.
  da_dr = ((beta * wn / (d.scale_height * rn)) * w) * r.transpose() - da_dw * cross_matrix(d.omega);
}

void ForceModel::validate_position(const Vec3& r, const char* name) const {
  core::require_finite(r, name);
  core::require(r.norm() > 0.0, name, "must be non-zero (|r| = 0 is the centre of the body)",
                "point-mass gravity is singular there");
  if (drag) validate_density_radius(*drag, r.norm(), name);
  // --- atmosphere drag ---
  if (atmosphere_drag) {
    Mat3 rot;  // the height depends on the rotation only through polar motion: t = 0 is enough
    Vec3 omega;
    const double h = atmosphere_drag_point(*atmosphere_drag, 0.0, r, rot, omega).height;
    core::require(h >= 0.0, name,
                  "is below the WGS-84 ellipsoid (geodetic height " + std::to_string(h) + " km < 0)",
                  "the atmosphere models hold from the surface up");
  }
  // --- end atmosphere drag ---
}

void ForceModel::validate() const {
  using core::require;
  using core::require_positive;
  require_positive(mu, "mu");
  if (j2) {
    require_positive(j2->mu, "j2.mu");
    require_positive(j2->radius, "j2.radius");
    core::require_finite(j2->j2, "j2.j2");
    require(std::abs(j2->mu - mu) <= 1e-12 * mu, "j2.mu", "must equal the central-body mu",
            "the J2 term and the point mass describe the same body; set J2Gravity.mu = mu");
  }
  if (drag) {
    const ExponentialDrag& d = *drag;
    core::require_nonnegative(d.rho0, "drag.rho0");
    core::require_finite(d.h0, "drag.h0");
    require_positive(d.scale_height, "drag.scale_height");
    require_positive(d.body_radius, "drag.body_radius");
    core::require_nonnegative(d.cd, "drag.cd");
    core::require_nonnegative(d.area, "drag.area");
    require_positive(d.mass, "drag.mass");
    core::require_finite(d.omega, "drag.omega");
  }
  if (atmosphere_drag) {  // atmosphere drag: one epoch, the ForceModel's
    atmosphere_drag->validate("atmosphere_drag");
    if (const auto* erfa = dynamic_cast<const ErfaSun*>(atmosphere_drag->sun.get())) {
      core::require(erfa->epoch_jd1() + erfa->epoch_jd2() == epoch_jd1 + epoch_jd2, "atmosphere_drag.sun",
                    "ErfaSun epoch must equal the force model's epoch_jd1 + epoch_jd2 (or leave sun "
                    "unset: the force model's Sun)");
    }
  }
  validate_precise_terms();
}

Vec3 ForceModel::acceleration(double t, const Vec3& r, const Vec3& v) const {
  Vec3 a = point_mass_acceleration(mu, r);
  if (j2) a += j2_acceleration(*j2, r);
  if (drag) a += drag_acceleration(*drag, r, v);
  if (atmosphere_drag) a += atmosphere_drag_acceleration(*atmosphere_drag, t, r, v, drag_sun(t));
  add_precise_terms(t, r, a, nullptr);
  return a;
}

void ForceModel::acceleration_jacobians(double t, const Vec3& r, const Vec3& v, Vec3& a, Mat3& da_dr,
                                        Mat3& da_dv) const {
  point_mass_jacobian(mu, r, a, da_dr);
  da_dv.setZero();
  if (j2) {
    Vec3 aj;
    Mat3 gj;
    j2_jacobian(*j2, r, aj, gj);
    a += aj;
    da_dr += gj;
  }
  if (drag) {
    Vec3 ad;
    Mat3 gr, gv;
    drag_jacobians(*drag, r, v, ad, gr, gv);
    a += ad;
    da_dr += gr;
    da_dv += gv;
  }
  // --- atmosphere drag ---
  if (atmosphere_drag) {
    Vec3 ad;
    Mat3 gr, gv;
    atmosphere_drag_jacobians(*atmosphere_drag, t, r, v, drag_sun(t), ad, gr, gv);
    a += ad;
    da_dr += gr;
    da_dv += gv;
  }
  // --- end atmosphere drag ---
  add_precise_terms(t, r, a, &da_dr);
}

double ForceModel::potential(const Vec3& r) const { return potential(0.0, r); }

double ForceModel::potential(double t, const Vec3& r) const {
  double p = -mu / r.norm();
  if (j2) p += j2_potential(*j2, r);
  // --- gravity field, Sun and Moon ---
  if (gravity) p += gravity->potential(t, r);
  if (third_body) {
    const double d2 = epoch_jd2 + t / 86400.0;
    if (third_body->sun) p += third_body_potential(third_body->mu_sun, ephemeris.sun(epoch_jd1, d2), r);
    if (third_body->moon) p += third_body_potential(third_body->mu_moon, ephemeris.moon(epoch_jd1, d2), r);
  }
  return p;
}

// --- gravity field, Sun and Moon, SRP (issue 14 items 1-3, 5) ---
void ForceModel::validate_precise_terms() const {
  using core::require;
  if (gravity) {
    require(!j2.has_value(), "gravity", "cannot be combined with j2: the field holds C20",
            "drop j2, or use j2 without a gravity field");
    require(std::abs(gravity->mu() - mu) <= 1e-6 * mu, "gravity.mu",
            "must equal the central-body mu to 1e-6 relative, got " + std::to_string(gravity->mu()) +
                " vs mu = " + std::to_string(mu),
            "set ForceModel.mu = gravity.mu");
  }
  if (third_body) third_body->validate();
  if (srp) srp->validate();
  if (third_body || srp) {
    core::require_finite(epoch_jd1, "epoch_jd1");
    core::require_finite(epoch_jd2, "epoch_jd2");
  }
  if (const auto& spk = ephemeris.spk()) {  // a DE file must cover t = 0 at least
    const double et = ephemeris.tdb_seconds(epoch_jd1, epoch_jd2);
    require(spk->covers(et), "epoch_jd1 + epoch_jd2",
            "the epoch " + format_tdb_seconds(et) + " is outside " + spk->path() + "'s coverage " +
                format_tdb_seconds(spk->start_et()) + " to " + format_tdb_seconds(spk->end_et()));
  }
}

void ForceModel::add_precise_terms(double t, const Vec3& r, Vec3& a, Mat3* da_dr) const {
  if (gravity) {
    if (da_dr) {
      Vec3 ag;
      Mat3 gg;
      gravity->jacobian(t, r, ag, gg);
      a += ag;
      *da_dr += gg;
    } else {
      a += gravity->acceleration(t, r);
    }
  }
  if (!third_body && !srp) return;
  const double d2 = epoch_jd2 + t / 86400.0;
  const bool need_sun = (third_body && third_body->sun) || srp;
  const Vec3 sun = need_sun ? ephemeris.sun(epoch_jd1, d2) : Vec3::Zero();
  Vec3 at;
  Mat3 gt;
  if (third_body && third_body->sun) {
    if (da_dr) {
      third_body_jacobian(third_body->mu_sun, sun, r, at, gt);
      a += at;
      *da_dr += gt;
    } else {
      a += third_body_acceleration(third_body->mu_sun, sun, r);
    }
  }
  if (third_body && third_body->moon) {
    const Vec3 moon = ephemeris.moon(epoch_jd1, d2);
    if (da_dr) {
      third_body_jacobian(third_body->mu_moon, moon, r, at, gt);
      a += at;
      *da_dr += gt;
    } else {
      a += third_body_acceleration(third_body->mu_moon, moon, r);
    }
  }
  if (srp) {
    if (da_dr) {
      srp_jacobian(*srp, sun, r, at, gt);
      a += at;
      *da_dr += gt;
    } else {
      a += srp_acceleration(*srp, sun, r);
    }
  }
}

Vec3 ForceModel::drag_sun(double t) const {
  const SunDirectionModel* sun = atmosphere_drag ? atmosphere_drag->sun.get() : nullptr;
  if (sun != nullptr && dynamic_cast<const ErfaSun*>(sun) == nullptr) return sun->direction(t);  // FixedSun
  return ephemeris.sun(epoch_jd1, epoch_jd2 + t / 86400.0);  // the cached Sun of third_body and srp
}

Vec3 ForceModel::acceleration_partial(ForceParameter p, double t, const Vec3& r, const Vec3& v) const {
  switch (p) {
    case ForceParameter::mu: {
      // Every central-body term is linear in mu (J2 and the field scale with their own GM = mu).
      Vec3 a = point_mass_acceleration(mu, r);
      if (j2) a += j2_acceleration(*j2, r);
      if (gravity) a += gravity->acceleration(t, r);
      return a / mu;
    }
    case ForceParameter::cr: {
      if (!srp) core::require(false, "parameter", "cr needs an srp term");  // message built on failure only
      SolarRadiationPressure unit = *srp;
      unit.cr = 1.0;
      return srp_acceleration(unit, ephemeris.sun(epoch_jd1, epoch_jd2 + t / 86400.0), r);
    }
    case ForceParameter::cd: {
      // One Cd scales every drag term: the exponential drag and the atmosphere drag add up. The
      // message is built on failure only (no allocation on the hot path).
      if (!drag && !atmosphere_drag)
        core::require(false, "parameter", "cd needs a drag or atmosphere_drag term");
      Vec3 a = Vec3::Zero();
      if (drag) {
        ExponentialDrag unit = *drag;
        unit.cd = 1.0;
        a += drag_acceleration(unit, r, v);
      }
      if (atmosphere_drag) a += atmosphere_drag_cd_partial(*atmosphere_drag, t, r, v, drag_sun(t));
      return a;
    }
  }
  throw std::invalid_argument("parameter: unknown ForceParameter");
}
// --- end gravity field, Sun and Moon, SRP ---

}  // namespace satgnc::dynamics
