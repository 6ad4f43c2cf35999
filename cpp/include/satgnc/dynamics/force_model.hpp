#pragma once
/// @file force_model.hpp
/// Orbital force model: point-mass gravity plus optional J2, exponential drag, spherical-harmonic
/// gravity, Sun and Moon, and solar radiation pressure, each with analytic acceleration Jacobians. Units: km,
/// km/s, s (drag's area/mass and density are converted inside).
#include <Eigen/Geometry>
#include <optional>

#include "satgnc/core/constants.hpp"
#include "satgnc/core/epoch.hpp"
#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/atmosphere.hpp"
#include "satgnc/dynamics/gravity_field.hpp"
#include "satgnc/dynamics/srp.hpp"
#include "satgnc/dynamics/third_body.hpp"

namespace satgnc::dynamics {

/// Earth constants: core::earth (satgnc/core/constants.hpp), kept here under their old name.
namespace earth = core::earth;

/// Zonal J2 perturbation of a body with gravitational parameter mu (km^3/s^2) and radius (km).
struct J2Gravity {
  double mu = earth::mu;          ///< km^3/s^2
  double j2 = earth::j2;          ///< dimensionless
  double radius = earth::radius;  ///< km
};

/// Exponential atmosphere rho = rho0 exp(-(h - h0) / scale_height), h = |r| - body_radius, with a
/// co-rotating atmosphere: v_rel = v - omega x r. Acceleration -0.5 Cd (A/m) rho |v_rel| v_rel.
struct ExponentialDrag {
  double rho0 = 0.0;                          ///< density at h0, kg/m^3
  double h0 = 0.0;                            ///< reference altitude, km
  double scale_height = 1.0;                  ///< km
  double body_radius = earth::radius;         ///< km
  double cd = 2.2;                            ///< drag coefficient, dimensionless
  double area = 1.0;                          ///< cross-section, m^2
  double mass = 1.0;                          ///< kg
  Vec3 omega = Vec3(0.0, 0.0, earth::omega);  ///< atmosphere rotation, rad/s (inertial frame)
};

/// A model parameter whose acceleration partial ForceModel::acceleration_partial gives.
enum class ForceParameter {
  mu = 0,  ///< central-body gravitational parameter, km^3/s^2
  cr = 1,  ///< SRP reflectivity coefficient
  cd = 2,  ///< drag coefficient
};

/// Combined force model. Point-mass gravity is always on; J2 and drag are optional terms.
struct ForceModel {
  double mu = earth::mu;                ///< central-body gravitational parameter, km^3/s^2
  std::optional<J2Gravity> j2;          ///< J2 term (its mu should equal mu)
  std::optional<ExponentialDrag> drag;  ///< drag term
  // --- atmosphere drag (issue 14 item 4) ---
  /// Drag through a density model (Harris-Priester, ...) with a co-rotating atmosphere
  /// (dynamics/atmosphere.hpp); independent of `drag` (the paper's exponential model).
  std::optional<AtmosphereDrag> atmosphere_drag;
  // --- end atmosphere drag ---

  /// Throw std::invalid_argument (naming the field and the rule) on non-positive mu, radius, etc.
  void validate() const;
  /// Throw std::invalid_argument naming `name` unless r (km) is finite, non-zero (gravity is singular at
  /// the centre) and, with drag, at or above drag->body_radius (the atmosphere model's range). For
  /// single evaluations from an API; propagators check |r| > 0 in validate_orbit_arc_input instead.
  void validate_position(const Vec3& r, const char* name = "r") const;
  /// True when every term derives from a potential (no drag): det(STM) = 1 and symplecticity hold.
  /// SRP with an Earth shadow is not (the shadow switches it off), nor is drag of either kind.
  bool conservative() const {
    return !drag.has_value() && !atmosphere_drag.has_value() &&
           !(srp.has_value() && srp->shadow != ShadowModel::none);
  }
  /// Acceleration a(t, r, v), km/s^2.
  Vec3 acceleration(double t, const Vec3& r, const Vec3& v) const;
  /// Acceleration and its Jacobians da/dr (1/s^2) and da/dv (1/s).
  void acceleration_jacobians(double t, const Vec3& r, const Vec3& v, Vec3& a, Mat3& da_dr,
                              Mat3& da_dv) const;
  /// Potential energy per unit mass V(r) of the gravity terms (a_grav = -grad V), km^2/s^2.
  double potential(const Vec3& r) const;
  /// Specific orbital energy |v|^2/2 + V(r), km^2/s^2; conserved when conservative().
  double energy(const Vec3& r, const Vec3& v) const { return 0.5 * v.squaredNorm() + potential(r); }

  // --- gravity field, Sun and Moon, SRP (issue 14 items 1-3, 5) ---
  /// Spherical-harmonic gravity (degrees >= 2, evaluated in ITRF through its EarthRotationModel);
  /// excludes j2 (the field holds C20). Its GM should equal mu (checked to 1e-6 relative).
  std::optional<GravityField> gravity;
  /// Sun and Moon point masses with the indirect term (ERFA ephemerides at the epoch below).
  std::optional<ThirdBodies> third_body;
  /// Cannonball solar radiation pressure (the Sun from ERFA at the epoch below).
  std::optional<SolarRadiationPressure> srp;
  /// Epoch of t = 0 as a two-part TT Julian date, days: t seconds is epoch_jd1 + (epoch_jd2 + t/86400).
  /// Used by third_body and srp (default J2000.0, 2000-01-01T12:00:00 TT).
  double epoch_jd1 = 2451545.0;
  double epoch_jd2 = 0.0;  ///< second part of the epoch's TT Julian date, days
  /// Set epoch_jd1/2 to the TT Julian date of e (the epoch of t = 0).
  void set_epoch(const core::Epoch& e) {
    const core::JulianDate j = e.jd(core::TimeScale::tt);
    epoch_jd1 = j.jd1;
    epoch_jd2 = j.jd2;
  }
  /// Sun and Moon positions for third_body and srp: ERFA interpolated on 1/8-day nodes (a cache:
  /// one ForceModel per thread). EphemerisInterpolator(0.0) calls ERFA at every evaluation.
  EphemerisInterpolator ephemeris;
  /// Potential energy per unit mass V(t, r) of every gravity term, third bodies included, km^2/s^2
  /// (a_grav = -grad V; time-dependent with a rotating field or third bodies).
  double potential(double t, const Vec3& r) const;
  /// |v|^2/2 + V(t, r), km^2/s^2.
  double energy(double t, const Vec3& r, const Vec3& v) const {
    return 0.5 * v.squaredNorm() + potential(t, r);
  }
  /// Partial derivative of the acceleration with respect to a model parameter (km/s^2 per unit of the
  /// parameter: per km^3/s^2 for mu, per unit Cr, per unit Cd) at t (s), r (km), v (km/s): the hook
  /// for estimated / consider parameters. mu scales the point mass, J2 and the gravity field; cr scales
  /// srp; cd scales drag and atmosphere_drag together (one Cd: their partials add). Throws
  /// std::invalid_argument when no term it scales is present.
  Vec3 acceleration_partial(ForceParameter p, double t, const Vec3& r, const Vec3& v) const;

 private:
  void validate_precise_terms() const;
  // The drag's Sun (GCRF, any length) at t: AtmosphereDrag::sun if a FixedSun (or another user model),
  // else ephemeris at the ForceModel's epoch.
  Vec3 drag_sun(double t) const;
  // Adds gravity, third bodies and SRP to a (and da_dr when not null).
  void add_precise_terms(double t, const Vec3& r, Vec3& a, Mat3* da_dr) const;
  // --- end gravity field, Sun and Moon, SRP ---
};

// Per-term functions, reusable by other models (e.g. one body of a two-satellite model).
// They do not validate their arguments (call ForceModel::validate() or check at setup).

/// Point-mass acceleration -mu r/|r|^3 (km/s^2) for mu in km^3/s^2, r in km.
Vec3 point_mass_acceleration(double mu, const Vec3& r);
/// Point-mass acceleration and da/dr = -mu/|r|^3 (I - 3 r r^T/|r|^2) (1/s^2).
void point_mass_jacobian(double mu, const Vec3& r, Vec3& a, Mat3& da_dr);

/// J2 acceleration -(3/2) J2 mu R^2/|r|^5 [x(1-5z^2/r^2), y(1-5z^2/r^2), z(3-5z^2/r^2)], km/s^2.
Vec3 j2_acceleration(const J2Gravity& g, const Vec3& r);
/// J2 acceleration and its Jacobian da/dr (1/s^2).
void j2_jacobian(const J2Gravity& g, const Vec3& r, Vec3& a, Mat3& da_dr);
/// J2 potential energy per unit mass mu J2 R^2 (3 z^2/r^2 - 1) / (2 r^3), km^2/s^2.
double j2_potential(const J2Gravity& g, const Vec3& r);

/// Exponential-atmosphere density at radius |r| (km), kg/m^3. Unchecked (hot path): below the surface
/// it grows without bound; see validate_density_radius.
double exponential_density(const ExponentialDrag& d, double radius_km);
/// Throw std::invalid_argument naming `name` unless radius_km is finite and >= d.body_radius (the
/// exponential model holds from the surface up; 1e37 kg/m^3 below it is not a density).
void validate_density_radius(const ExponentialDrag& d, double radius_km, const char* name = "radius");
/// Drag acceleration -0.5 Cd (A/m) rho |v_rel| v_rel with v_rel = v - omega x r, km/s^2.
Vec3 drag_acceleration(const ExponentialDrag& d, const Vec3& r, const Vec3& v);
/// Drag acceleration and its Jacobians da/dr (1/s^2, density gradient and co-rotation) and da/dv (1/s).
void drag_jacobians(const ExponentialDrag& d, const Vec3& r, const Vec3& v, Vec3& a, Mat3& da_dr,
                    Mat3& da_dv);

}  // namespace satgnc::dynamics
