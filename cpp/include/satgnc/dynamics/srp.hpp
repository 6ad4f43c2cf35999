#pragma once
/// @file srp.hpp
/// Solar radiation pressure on a cannonball (area, mass, Cr) with the Earth's shadow, cylindrical or
/// conical with the exact penumbra of two overlapping discs (Montenbruck & Gill, "Satellite Orbits",
/// 2000, sec. 3.4.1-3.4.2, eq. 3.75 and 3.85-3.89), and the analytic Jacobian, the shadow function's
/// derivative in the penumbra included (the cylindrical shadow is a step: its derivative is zero
/// except on the shadow boundary, where it does not exist). Units: positions km, acceleration km/s^2;
/// area m^2, mass kg, pressure N/m^2.
#include "satgnc/core/constants.hpp"
#include "satgnc/core/types.hpp"

namespace satgnc::dynamics {

/// Earth shadow model of SolarRadiationPressure.
enum class ShadowModel {
  none = 0,         ///< always lit
  cylindrical = 1,  ///< a cylinder of the Earth's radius behind the Earth: lit (1) or not (0)
  conical = 2,      ///< umbra and penumbra of the Sun's disc seen past the Earth's: fraction in [0, 1]
};

/// Cannonball solar radiation pressure: a = nu P (AU/d)^2 Cr (A/m) u, u the unit vector from the Sun
/// to the satellite, d their distance, nu the lit fraction of the Sun's disc.
struct SolarRadiationPressure {
  double area = 1.0;          ///< cross-section, m^2
  double mass = 1.0;          ///< kg
  double cr = 1.3;            ///< reflectivity coefficient, dimensionless (1: absorbing, 2: mirror)
  double pressure = 4.56e-6;  ///< radiation pressure at 1 AU, N/m^2
  ShadowModel shadow = ShadowModel::conical;      ///< Earth shadow
  double occulting_radius = core::earth::radius;  ///< Earth radius for the shadow, km
  double sun_radius = 696000.0;                   ///< km
  /// Throw std::invalid_argument naming the field ("srp.area: must be finite and >= 0") on a negative
  /// area or cr, a non-positive mass, pressure or radius.
  void validate() const;
};

/// Lit fraction of the Sun's disc nu in [0, 1] at r (km, geocentric) with the Sun at s (km).
double srp_shadow(const SolarRadiationPressure& p, const Vec3& s, const Vec3& r);
/// SRP acceleration (km/s^2) at r (km) with the Sun at s (km), both geocentric.
Vec3 srp_acceleration(const SolarRadiationPressure& p, const Vec3& s, const Vec3& r);
/// SRP acceleration (km/s^2) and its Jacobian da/dr (1/s^2), the penumbra's d nu/dr included.
void srp_jacobian(const SolarRadiationPressure& p, const Vec3& s, const Vec3& r, Vec3& a, Mat3& da_dr);

}  // namespace satgnc::dynamics
