#pragma once
/// @file atmosphere.hpp
/// Atmosphere density models and the drag term that uses them, with a co-rotating atmosphere.
/// Densities are in kg/m^3 at a position in the Earth-fixed frame (ITRF, km) and an epoch t (s after
/// the force model's epoch). The drag term lives in the inertial frame of the propagation (GCRF) and
/// sees the Earth's orientation through frames::EarthRotationModel. docs/atmosphere.md has the whole
/// story (models, units, ranges, the Sun direction, the Jacobians and how they are checked).
#include <memory>

#include "satgnc/core/types.hpp"
#include "satgnc/frames/earth_rotation.hpp"

namespace satgnc::dynamics {

/// Where and when a density is wanted. Built once per evaluation by atmosphere_point(); every model
/// reads the fields it needs (Harris-Priester: height, up, r_itrf, sun_itrf).
struct AtmospherePoint {
  double t = 0.0;                 ///< s after the force model's epoch
  Vec3 r_itrf = Vec3::Zero();     ///< position, ITRF, km
  Vec3 sun_itrf = Vec3::UnitX();  ///< unit vector from the Earth's centre towards the Sun, ITRF
  double height = 0.0;            ///< geodetic height above the WGS-84 ellipsoid, km
  double latitude = 0.0;          ///< geodetic latitude (WGS-84), rad
  double longitude = 0.0;         ///< east longitude, rad
  /// Unit normal of the WGS-84 ellipsoid through the point (ITRF): the gradient d height / d r_itrf.
  Vec3 up = Vec3::UnitZ();
};

/// The point for r_itrf (km, finite, not at the centre) and the Sun direction sun_itrf (any length
/// > 0, normalized here) at t (s). Geodetic coordinates from ERFA eraGc2gd (WGS-84). Does not throw.
AtmospherePoint atmosphere_point(double t, const Vec3& r_itrf, const Vec3& sun_itrf) noexcept;

/// Density of the neutral atmosphere. Implementations are immutable: const, thread-safe and free of
/// heap allocation (a propagation's right-hand side calls them at every stage).
class AtmosphereModel {
 public:
  virtual ~AtmosphereModel() = default;
  /// Total mass density at the point, kg/m^3 (>= 0).
  virtual double density(const AtmospherePoint& p) const noexcept = 0;
  /// Density (kg/m^3, returned) and its gradient with respect to r_itrf (kg/m^3 per km, ITRF) at the
  /// point. The default is a one-sided (forward) finite difference of density() alone with a step of
  /// gradient_step() km along each ITRF axis, for models that are not smooth or have no analytic
  /// gradient: truncation error |d2 rho/dh2| step / 2, i.e. a relative error of about
  /// step / (2 H) for a scale height H (5e-6 for the 1 m step and H = 100 km).
  virtual double density_gradient(const AtmospherePoint& p, Vec3& grad_itrf) const noexcept;
  /// Step of the default finite-difference gradient, km (1e-3 km = 1 m).
  virtual double gradient_step() const noexcept { return 1.0e-3; }
};

/// Harris-Priester density model as given by Montenbruck & Gill, "Satellite Orbits" (Springer, 2000),
/// section 3.5.2, Table 3.8 (mean solar activity; minimum and maximum density at 50 heights from 100 to
/// 1000 km): rho = rho_min(h) + (rho_max(h) - rho_min(h)) cos^n(psi/2), with exponential
/// interpolation in geodetic height h between the table heights and psi the angle between the
/// position and the apex of the diurnal bulge (the Sun direction turned by lag, default 30 deg, east
/// about the Earth's axis). Above 1000 km the density is 0 (as in M&G); below 100 km it continues the
/// 100-120 km layer's exponential (scale height 6.7 km: 1.5 kg/m^3 at sea level, M&G returns 0
/// there). Analytic gradient (the model is continuous with piecewise-smooth height dependence: the
/// gradient jumps at the table heights).
class HarrisPriester final : public AtmosphereModel {
 public:
  /// n: exponent of cos(psi/2), in [2, 6] (M&G: 2 for low-inclination orbits, 6 for polar ones);
  /// lag: right-ascension lag of the bulge apex behind the Sun, rad, in [0, pi] (M&G: 30 deg).
  /// Throws std::invalid_argument naming the argument.
  explicit HarrisPriester(double n = 2.0, double lag = 0.523599);
  double density(const AtmospherePoint& p) const noexcept override;
  double density_gradient(const AtmospherePoint& p, Vec3& grad_itrf) const noexcept override;
  double n() const { return n_; }      ///< exponent of cos(psi/2)
  double lag() const { return lag_; }  ///< rad

  static constexpr double min_table_height = 100.0;   ///< km, first row of M&G Table 3.8
  static constexpr double max_table_height = 1000.0;  ///< km, last row; density 0 above

 private:
  double n_;
  double lag_;
};

/// Direction of the Sun seen from the Earth's centre, in the inertial frame of the propagation (GCRF),
/// at t (s after the force model's epoch). Implementations are immutable, thread-safe, allocation-free.
class SunDirectionModel {
 public:
  virtual ~SunDirectionModel() = default;
  /// Unit vector towards the Sun, GCRF, at t (s).
  virtual Vec3 direction(double t) const noexcept = 0;
};

/// A fixed Sun direction (any non-zero length; normalized at construction): for tests and short arcs.
class FixedSun final : public SunDirectionModel {
 public:
  /// Throws std::invalid_argument naming `direction` unless it is finite and non-zero.
  explicit FixedSun(const Vec3& direction);
  Vec3 direction(double) const noexcept override { return direction_; }

 private:
  Vec3 direction_;
};

/// The geocentric Sun from ERFA eraEpv00 (the Sun is minus the heliocentric Earth; BCRS axes taken as
/// GCRF's, light time and aberration, 20 arcsec, neglected; TDB taken = TT, 2 ms). eraEpv00 costs
/// ~50 us, too much for every right-hand side: it is evaluated at construction every `node_spacing`
/// seconds over [t_begin, t_end] and interpolated by cubic Hermite polynomials on its positions and
/// velocities (interpolation error (omega h)^4 / 384 ~ 4e-12 rad for the 6 h default, omega = 2e-7
/// rad/s). Outside the table, eraEpv00 is called directly (exact, slow).
class ErfaSun final : public SunDirectionModel {
 public:
  /// Epoch of t = 0: the two-part TT Julian date epoch_jd1 + epoch_jd2 (days; the convention of
  /// ForceModel's epoch). The table covers t in [t_begin, t_end] s (default one day before to 31 days
  /// after the epoch) with nodes every node_spacing s (default 6 h). Throws std::invalid_argument
  /// naming the argument (non-finite, t_end <= t_begin, spacing <= 0, or more than 1e6 nodes).
  explicit ErfaSun(double epoch_jd1, double epoch_jd2 = 0.0, double t_begin = -86400.0,
                   double t_end = 31.0 * 86400.0, double node_spacing = 21600.0);
  Vec3 direction(double t) const noexcept override;
  double epoch_jd1() const { return epoch_jd1_; }  ///< first part of the TT Julian date of t = 0, days
  double epoch_jd2() const { return epoch_jd2_; }  ///< second part, days
  /// Geocentric Sun position (au) and velocity (au/day) straight from eraEpv00 at t (s), GCRF axes.
  void erfa_state(double t, Vec3& position_au, Vec3& velocity_au_per_day) const noexcept;

 private:
  double epoch_jd1_;
  double epoch_jd2_;
  double t_begin_;
  double spacing_;
  int nodes_;
  std::unique_ptr<double[]> table_;  // per node: position (au), velocity (au/day)
};

/// Drag with any AtmosphereModel and a co-rotating atmosphere, in the inertial frame (GCRF) of the
/// propagation: a = -0.5 Cd (A/m) rho |v_rel| v_rel with v_rel = v - omega x r (km/s^2 for r km,
/// v km/s; A m^2, m kg, rho kg/m^3 converted inside). rho is evaluated at r_itrf = R(t) r with R and
/// omega from earth_rotation and the Sun from sun_direction or ERFA.
struct AtmosphereDrag {
  std::shared_ptr<const AtmosphereModel> atmosphere;  ///< required (validate() refuses null)
  /// Earth orientation; null means frames::UniformRotation(0, core::earth::omega) (the paper's model:
  /// ITRF x axis on GCRF x at t = 0). Harris-Priester depends on the rotation only through the
  /// position's latitude, so the start angle does not matter to it.
  std::shared_ptr<const frames::EarthRotationModel> earth_rotation;
  /// Direction of the Sun (GCRF) for the models with a diurnal bulge. Null (the default) means the
  /// force model's Sun: inside a ForceModel, ForceModel::ephemeris at the ForceModel's epoch (the same
  /// cached ERFA Sun as the third body and SRP, one epoch); alone, ERFA (eraEpv00) at t s after J2000.0
  /// TT, the ForceModel's default epoch. An ErfaSun inside a ForceModel must have the ForceModel's
  /// epoch (validate refuses another) and is then replaced by the ForceModel's ephemeris; a FixedSun
  /// (tests, short arcs) is used as given.
  std::shared_ptr<const SunDirectionModel> sun;
  double cd = 2.2;    ///< drag coefficient, dimensionless (>= 0)
  double area = 1.0;  ///< cross-section, m^2 (>= 0)
  double mass = 1.0;  ///< kg (> 0)

  /// Throw std::invalid_argument naming prefix + the field on a null atmosphere, negative cd or area,
  /// or non-positive mass.
  void validate(const char* prefix = "atmosphere_drag") const;
};

/// The atmosphere point of GCRF position r (km) at t (s), with omega_gcrf (rad/s) and R (GCRF->ITRF).
AtmospherePoint atmosphere_drag_point(const AtmosphereDrag& d, double t, const Vec3& r, Mat3& gcrf_to_itrf,
                                      Vec3& omega_gcrf) noexcept;
/// Density (kg/m^3) seen by the drag term at GCRF position r (km) and t (s).
double atmosphere_drag_density(const AtmosphereDrag& d, double t, const Vec3& r) noexcept;
/// Drag acceleration, km/s^2, at t (s), GCRF r (km) and v (km/s).
Vec3 atmosphere_drag_acceleration(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v) noexcept;
/// Drag acceleration (km/s^2) and its Jacobians da/dr (1/s^2: the density gradient, analytic or by the
/// model's finite difference, and the co-rotation) and da/dv (1/s).
void atmosphere_drag_jacobians(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v, Vec3& a,
                               Mat3& da_dr, Mat3& da_dv) noexcept;
/// Partial of the acceleration with respect to Cd, km/s^2 per unit Cd (a / Cd; exact also at Cd = 0).
Vec3 atmosphere_drag_cd_partial(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v) noexcept;

/// The Sun direction (GCRF, unit) the drag term uses at t (s) when alone: d.sun, or with a null sun
/// ERFA at t s after J2000.0 TT.
Vec3 atmosphere_drag_sun(const AtmosphereDrag& d, double t) noexcept;
/// atmosphere_drag_acceleration with the Sun given: sun_gcrf (any length > 0) towards the Sun, GCRF.
Vec3 atmosphere_drag_acceleration(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v,
                                  const Vec3& sun_gcrf) noexcept;
/// atmosphere_drag_jacobians with the Sun given (sun_gcrf towards the Sun, GCRF, any length > 0).
void atmosphere_drag_jacobians(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v,
                               const Vec3& sun_gcrf, Vec3& a, Mat3& da_dr, Mat3& da_dv) noexcept;
/// atmosphere_drag_cd_partial with the Sun given (sun_gcrf towards the Sun, GCRF, any length > 0).
Vec3 atmosphere_drag_cd_partial(const AtmosphereDrag& d, double t, const Vec3& r, const Vec3& v,
                                const Vec3& sun_gcrf) noexcept;

}  // namespace satgnc::dynamics
