#pragma once
/// @file gravity_field.hpp
/// Spherical-harmonic gravity of the Earth from fully normalized coefficients C_nm, S_nm (ICGEM
/// `.gfc` files), evaluated in the Earth-fixed frame (ITRF) with a Cunningham (1970) recursion of the
/// fully normalized solid harmonics (Montenbruck & Gill, "Satellite Orbits", 2000, sec. 3.2.4-3.2.5),
/// which is stable to degree and order a few hundred (tested at 120). Acceleration, potential and the
/// analytic gradient da/dr (the Hessian of the potential, for the STM) come from the same harmonics: the
/// ladder operators (d/dx + i d/dy) and d/dz map the degree-n harmonics onto degree n+1 (n+2 for the
/// gradient). Units: km, km/s^2, 1/s^2; the coefficient file's GM (m^3/s^2) and radius (m) are
/// converted to km^3/s^2 and km on reading.
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "satgnc/core/types.hpp"
#include "satgnc/frames/earth_rotation.hpp"

namespace satgnc::dynamics {

/// Fully normalized spherical-harmonic coefficients of a gravity field (4-pi normalization, as in
/// ICGEM files and EGM96 / EGM2008). Degree-0 and degree-1 terms are stored but never evaluated: the
/// central term is ForceModel's point mass, and the origin is the centre of mass.
struct GravityCoefficients {
  std::string name;         ///< model name (the file's `modelname`)
  std::string tide_system;  ///< `tide_free`, `zero_tide`, `mean_tide` or empty (as given by the file)
  double mu = 0.0;          ///< GM of the model, km^3/s^2
  double radius = 0.0;      ///< reference radius, km
  int max_degree = 0;       ///< highest degree stored
  std::vector<double> c;    ///< C_nm at index n (n + 1) / 2 + m, 0 <= m <= n <= max_degree
  std::vector<double> s;    ///< S_nm, same layout (S_n0 = 0)

  /// Index of (n, m) in c and s.
  static int index(int n, int m) { return n * (n + 1) / 2 + m; }
  /// C_nm (0 <= m <= n <= max_degree; unchecked).
  double cnm(int n, int m) const { return c[static_cast<std::size_t>(index(n, m))]; }
  /// S_nm (0 <= m <= n <= max_degree; unchecked).
  double snm(int n, int m) const { return s[static_cast<std::size_t>(index(n, m))]; }
  /// Throw std::invalid_argument unless mu, radius > 0, max_degree >= 0, the arrays hold
  /// (max_degree + 1)(max_degree + 2)/2 finite values.
  void validate() const;
};

/// Read an ICGEM `.gfc` file (static field: `gfc` lines; header keywords `modelname`,
/// `earth_gravity_constant` (m^3/s^2), `radius` (m), `max_degree`, `norm` (must be fully_normalized
/// or absent), `tide_system`; Fortran `D` exponents accepted) up to max_degree (-1: the file's).
/// Throws std::invalid_argument naming the file, the line and the keyword on a malformed line, a
/// missing keyword, a degree above the header's max_degree, time-variable terms (`gfct`, `trnd`,
/// `acos`, `asin`: not supported), or max_degree above the file's.
GravityCoefficients load_gfc(const std::string& path, int max_degree = -1);
/// The same reader on a stream; `source` names it in error messages.
GravityCoefficients parse_gfc(std::istream& in, const std::string& source, int max_degree = -1);

/// Spherical-harmonic gravity (degrees 2..degree, orders 0..min(n, order)) of a body whose Earth-fixed
/// frame turns with respect to the inertial frame as `rotation` says. Built once (tables and the
/// workspace sized here); evaluation allocates nothing. Evaluation writes a private workspace: a
/// GravityField (and a ForceModel holding one) must not be evaluated from two threads at once; copy
/// it per thread (the copy shares the coefficients).
class GravityField {
 public:
  /// coefficients: shared, read-only; degree in [2, coefficients->max_degree]; order in [0, degree];
  /// rotation: GCRF -> ITRF at t seconds after the propagation epoch. Throws std::invalid_argument
  /// naming the argument ("degree: 80 is above the file's max_degree 70", a null pointer, ...).
  GravityField(std::shared_ptr<const GravityCoefficients> coefficients, int degree, int order,
               std::shared_ptr<const frames::EarthRotationModel> rotation);

  int degree() const { return degree_; }                              ///< highest degree
  int order() const { return order_; }                                ///< highest order
  double mu() const { return coef_->mu; }                             ///< km^3/s^2
  double radius() const { return coef_->radius; }                     ///< km
  const GravityCoefficients& coefficients() const { return *coef_; }  ///< the coefficients
  const std::shared_ptr<const GravityCoefficients>& coefficients_ptr() const { return coef_; }  ///< shared
  const frames::EarthRotationModel& rotation() const { return *rotation_; }  ///< Earth orientation
  const std::shared_ptr<const frames::EarthRotationModel>& rotation_ptr() const {
    return rotation_;
  }  ///< shared

  /// Acceleration of the non-central terms (n >= 2) at r_itrf (km, Earth-fixed), ITRF, km/s^2.
  Vec3 acceleration_fixed(const Vec3& r_itrf) const;
  /// Acceleration (km/s^2) and its gradient da/dr (1/s^2, symmetric, trace 0), both in ITRF.
  void gradient_fixed(const Vec3& r_itrf, Vec3& a, Mat3& da_dr) const;
  /// Potential energy per unit mass of the non-central terms, V = -U (a = -grad V), km^2/s^2.
  double potential_fixed(const Vec3& r_itrf) const;

  /// Acceleration at t (s after the epoch) and r (km, GCRF), in GCRF, km/s^2.
  Vec3 acceleration(double t, const Vec3& r) const;
  /// Acceleration (km/s^2) and da/dr (1/s^2), GCRF, at t (s after the epoch) and r (km, GCRF).
  void jacobian(double t, const Vec3& r, Vec3& a, Mat3& da_dr) const;
  /// Potential energy per unit mass (km^2/s^2) at t (s) and r (km, GCRF).
  double potential(double t, const Vec3& r) const;

 private:
  // Fills v_, w_ (fully normalized V_nm, W_nm) up to degree nmax and order mmax at r (ITRF, km).
  void harmonics(const Vec3& r, int nmax, int mmax) const;
  int stride() const { return degree_ + 3; }

  std::shared_ptr<const GravityCoefficients> coef_;
  std::shared_ptr<const frames::EarthRotationModel> rotation_;
  int degree_ = 0;
  int order_ = 0;
  // Recursion factors over (n, m), n, m <= degree + 2, index n * stride() + m.
  std::vector<double> rec_a_, rec_b_, sect_;
  // Ladder factors over (n, m), n <= degree, m <= order: 8 per entry.
  std::vector<double> ladder_;
  mutable std::vector<double> v_, w_;  // workspace
};

}  // namespace satgnc::dynamics
