#pragma once
/// @file earth_orientation.hpp
/// IAU 2006/2000A CIO-based transformation between the GCRS (GCRF) and the ITRS (ITRF), with EOP,
/// through ERFA (SOFA Tools for Earth Attitude, section 5.5):
///   r_ITRS = W(xp, yp, s') R3(ERA) Q(X + dX, Y + dY, s) r_GCRS
/// - Q: CIP X, Y and the CIO locator s from eraXys06a (IAU 2006 precession, IAU 2000A nutation) at
///   TT, plus the IERS pole offsets dX, dY (eraC2ixys);
/// - ERA: Earth rotation angle eraEra00 at UT1 (UT1 from the EOP table);
/// - W: polar motion eraPom00(xp, yp, s'), s' = eraSp00 (TIO locator) at TT.
/// EME2000 (the J2000 mean equator and equinox, "J2000" of older tools) differs from the GCRS by the
/// frame bias: r_EME2000 = B r_GCRS, B = eraBp06's rb (IAU 2006, 23 mas at most).
///
/// Velocities: v_ITRS = W (R3 Q v_GCRS - omega x r_TIRS), omega = (0, 0, 7.292115146706979e-5 (1 -
/// LOD / 86400)) rad/s about the CIP (IERS Conventions 2010 eq. 5.24 rate with LOD). Left out: the
/// rates of precession-nutation (dQ/dt, ~1e-11 rad/s: ~7e-8 km/s at GEO) and of polar motion (dW/dt,
/// ~1e-13 rad/s), both negligible against the Earth-rotation term at the 1e-7 km/s level.
#include <vector>

#include "satgnc/core/epoch.hpp"
#include "satgnc/core/types.hpp"
#include "satgnc/frames/earth_rotation.hpp"
#include "satgnc/frames/eop.hpp"

namespace satgnc::frames {

/// Nominal mean angular velocity of the Earth (rad/s), IERS Conventions 2010 (eq. 5.25 context):
/// omega = 7.292115146706979e-5 (1 - LOD / 86400).
inline constexpr double kEarthRotationRate = 7.292115146706979e-5;

/// The factors of the GCRS -> ITRS rotation at one epoch.
struct EarthOrientation {
  Mat3 q = Mat3::Identity();             ///< GCRS -> CIRS (celestial-to-intermediate), eraC2ixys
  double era = 0.0;                      ///< Earth rotation angle, rad
  Mat3 w = Mat3::Identity();             ///< TIRS -> ITRS (polar motion), eraPom00
  Mat3 gcrs_to_itrs = Mat3::Identity();  ///< W R3(ERA) Q
  double omega = kEarthRotationRate;     ///< Earth rotation rate with LOD, rad/s
};

/// The full IAU 2006/2000A chain at epoch with EOP values eop (arcsec, s). Calls the full
/// precession-nutation series (eraXys06a, ~1400 terms): for per-step use, see IauEarthRotation.
EarthOrientation earth_orientation(const core::Epoch& epoch, const EopValues& eop);
/// The same with EOP interpolated from table (its out-of-range policy applies).
EarthOrientation earth_orientation(const core::Epoch& epoch, const EopTable& table);

/// GCRS -> ITRS rotation matrix at epoch (r_itrs = M r_gcrs).
Mat3 gcrs_to_itrs_matrix(const core::Epoch& epoch, const EopTable& table);

/// Position (km) GCRS -> ITRS at epoch.
Vec3 gcrs_to_itrs(const Vec3& r_gcrs, const core::Epoch& epoch, const EopTable& table);
/// Position (km) ITRS -> GCRS at epoch.
Vec3 itrs_to_gcrs(const Vec3& r_itrs, const core::Epoch& epoch, const EopTable& table);
/// State [r (km), v (km/s)] GCRS -> ITRS at epoch, with the Earth-rotation velocity term.
Vec6 gcrs_to_itrs(const Vec6& x_gcrs, const core::Epoch& epoch, const EopTable& table);
/// State [r (km), v (km/s)] ITRS -> GCRS at epoch, with the Earth-rotation velocity term.
Vec6 itrs_to_gcrs(const Vec6& x_itrs, const core::Epoch& epoch, const EopTable& table);
/// State GCRS -> ITRS with a precomputed orientation.
Vec6 gcrs_to_itrs(const Vec6& x_gcrs, const EarthOrientation& o);
/// State ITRS -> GCRS with a precomputed orientation.
Vec6 itrs_to_gcrs(const Vec6& x_itrs, const EarthOrientation& o);

/// Frame bias B (IAU 2006, eraBp06): r_EME2000 = B r_GCRS. Constant.
Mat3 gcrs_to_eme2000_matrix();
/// Position or velocity vector GCRS -> EME2000 (a constant rotation: same for both).
Vec3 gcrs_to_eme2000(const Vec3& v_gcrs);
/// Position or velocity vector EME2000 -> GCRS.
Vec3 eme2000_to_gcrs(const Vec3& v_eme2000);

/// The IAU 2006/2000A orientation for a propagation: EarthRotationModel built from the epoch of
/// t = 0, an EOP table and the span [t_begin, t_end] (s after the epoch) it will be asked about.
/// Setup samples the slowly varying parts (CIP X + dX, Y + dY, s; xp, yp; UT1-TAI; LOD) on a grid of
/// step seconds (default 3600 s) from t_begin - step to t_end + 2 step with the full chain, and
/// rotation(t) interpolates them (4-point Lagrange) and evaluates ERA exactly (eraEra00 at
/// UT1 = TAI + interpolated UT1-TAI), so the right-hand side never calls the nutation series.
/// Measured interpolation error against earth_orientation() at the default step: 2.9e-12 rad
/// (test_earth_orientation: max angle of R_interp^T R_full - I over 2000 random epochs in 3 days).
/// Outside the span the end polynomials are extrapolated (the error grows; build with a span that
/// covers the propagation). rotation() allocates nothing and does not throw.
class IauEarthRotation final : public EarthRotationModel {
 public:
  /// Throws std::invalid_argument if t_begin > t_end, step <= 0 or > 86400 s, the grid would exceed
  /// 10^6 nodes, or (policy error) the span leaves the EOP table.
  IauEarthRotation(const core::Epoch& epoch, const EopTable& eop, double t_begin, double t_end,
                   double step = 3600.0);
  void rotation(double t, Mat3& gcrf_to_itrf, Vec3& omega_gcrf) const noexcept override;
  /// The interpolated orientation at t (s after the epoch); rotation() returns its parts.
  EarthOrientation orientation(double t) const noexcept;
  const core::Epoch& epoch() const { return epoch_; }  ///< epoch of t = 0
  double t_begin() const { return t_begin_; }          ///< s
  double t_end() const { return t_end_; }              ///< s
  double step() const { return step_; }                ///< grid step, s

 private:
  core::Epoch epoch_;
  core::JulianDate tt0_;  // TT of t = 0
  double t_begin_, t_end_, step_, t_first_;
  std::vector<double> x_, y_, s_, xp_, yp_, ut1_tai_, lod_;  // on the grid; radians / s
};

}  // namespace satgnc::frames
