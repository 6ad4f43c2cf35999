#pragma once
/// @file third_body.hpp
/// Sun and Moon as point masses acting on an Earth satellite, with the indirect term (the Earth's own
/// acceleration towards them), and their analytic Jacobians. Ephemerides from ERFA: eraEpv00 (Earth
/// heliocentric position, BCRS axes; the Sun's geocentric position is its negative) and eraMoon98
/// (geocentric Moon, GCRS axes). The GCRS axes are those of the BCRS, which satgnc takes as GCRF: no
/// rotation is applied. Positions are geometric (no light time, no aberration: what gravity needs).
/// The time argument is a two-part TT Julian date; ERFA wants TDB, and TDB - TT < 1.7 ms is neglected
/// (the Moon moves 1.7 m in that time). Units: km, km/s^2, km^3/s^2.
#include <memory>

#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/ephemeris_spk.hpp"

namespace satgnc::dynamics {

/// Sun and Moon gravitational parameters and which of them act.
struct ThirdBodies {
  bool sun = true;                     ///< include the Sun
  bool moon = true;                    ///< include the Moon
  double mu_sun = 132712440041.93938;  ///< km^3/s^2 (DE440, GM_Sun)
  double mu_moon = 4902.800118;        ///< km^3/s^2 (DE440, GM_Moon)
  /// Throw std::invalid_argument naming the field unless mu_sun and mu_moon are finite and > 0.
  void validate() const;
};

/// Astronomical unit, km (IAU 2012).
inline constexpr double kAstronomicalUnitKm = 149597870.7;

/// Geocentric position of the Sun (km, GCRF) at the TT Julian date jd1 + jd2 (eraEpv00).
Vec3 sun_position(double jd1, double jd2);
/// Geocentric position of the Moon (km, GCRF) at the TT Julian date jd1 + jd2 (eraMoon98).
Vec3 moon_position(double jd1, double jd2);

/// The Sun and Moon of ERFA by cubic Hermite interpolation (positions and velocities) between nodes
/// at whole multiples of step_days after J2000 TT: a propagation calls eraEpv00 (~20 us) and eraMoon98
/// (~2 us) once per node instead of at every evaluation. The result is a pure function of the date
/// (grid-aligned nodes), so repeated and perturbed propagations see the same ephemeris. Interpolation
/// error at the default step of 1/8 day: < 1 m for the Sun and < 5 m for the Moon (test_third_body),
/// i.e. < 1e-8 of the tidal acceleration. step_days = 0 calls ERFA at every evaluation. The nodes are
/// a mutable cache: one instance per thread (ForceModel holds one; copies are independent).
///
/// Built on a JPL DE file (an SpkEphemeris with the geocentric Sun and Moon), it evaluates the file's
/// Chebyshev segments at every call instead (no interpolation of its own): the TT date becomes TDB
/// seconds past J2000 through ERFA's eraDtdb at the geocentre, linearly interpolated between 1/8-day
/// nodes (error < 1e-9 s: TDB - TT has a second derivative below 1e-19 s/s^2 at the geocentre). The
/// SpkEphemeris is shared (immutable) between copies; an epoch outside its coverage throws
/// std::out_of_range naming the epoch and the coverage.
class EphemerisInterpolator {
 public:
  /// step_days: node spacing, days (>= 0; 0: no interpolation). Throws std::invalid_argument naming it.
  explicit EphemerisInterpolator(double step_days = 0.125);
  /// The Sun and Moon of a JPL DE file (must hold the pairs (10, 399) and (301, 399); throws
  /// std::invalid_argument naming the file otherwise, or when spk is null).
  explicit EphemerisInterpolator(std::shared_ptr<const SpkEphemeris> spk);
  double step_days() const { return step_; }  ///< days (the TDB node spacing with a DE file)
  /// The DE file in use, or null for ERFA.
  const std::shared_ptr<const SpkEphemeris>& spk() const { return spk_; }
  /// Geocentric Sun (km, GCRF) at the TT Julian date jd1 + jd2.
  Vec3 sun(double jd1, double jd2) const;
  /// Geocentric Moon (km, GCRF) at the TT Julian date jd1 + jd2.
  Vec3 moon(double jd1, double jd2) const;
  /// TDB seconds past J2000 of the TT Julian date jd1 + jd2 as used with a DE file (interpolated
  /// eraDtdb, see the class note).
  double tdb_seconds(double jd1, double jd2) const;

 private:
  struct Segment {
    double node = -1e300;  // index k of the segment [k step, (k + 1) step] after J2000
    Vec3 p0, v0, p1, v1;   // km and km/day at both nodes
  };
  struct TdbNodes {
    double node = -1e300;       // index k of [k step, (k + 1) step] after J2000 TT
    double d0 = 0.0, d1 = 0.0;  // TDB - TT at both nodes, s
  };
  double step_;
  mutable Segment sun_, moon_;
  std::shared_ptr<const SpkEphemeris> spk_;
  mutable TdbNodes tdb_;
};

/// Third-body acceleration on a satellite at r (km) from a body of parameter mu (km^3/s^2) at s (km),
/// both geocentric: mu [(s - r)/|s - r|^3 - s/|s|^3], km/s^2.
Vec3 third_body_acceleration(double mu, const Vec3& s, const Vec3& r);
/// The same and its Jacobian da/dr = mu (3 d d^T/|d|^5 - I/|d|^3), d = s - r (1/s^2).
void third_body_jacobian(double mu, const Vec3& s, const Vec3& r, Vec3& a, Mat3& da_dr);
/// Tidal potential energy per unit mass (km^2/s^2) with a = -grad V: -mu (1/|s - r| - s.r/|s|^3).
double third_body_potential(double mu, const Vec3& s, const Vec3& r);

}  // namespace satgnc::dynamics
