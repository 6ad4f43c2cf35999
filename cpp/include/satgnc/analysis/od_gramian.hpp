#pragma once
/// @file od_gramian.hpp
/// Observability of single-station orbit determination (Gao & Luo's set-up): the LTV observability
/// Gramian W = sum_j Phi(t_j, t0)^T H_j^T H_j Phi(t_j, t0) of range-only or range-rate-only tracking,
/// with the STMs from the analytic Kepler propagator. Units: km, km/s, s; range partials in 1 (km/km)
/// and range-rate partials in 1/s and 1 (see range_partial / range_rate_partial in linearize.hpp,
/// computed here for the analysis; satgnc/od owns the estimators' measurement models).
#include <utility>
#include <vector>

#include "satgnc/analysis/gramian.hpp"
#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/station.hpp"

namespace satgnc::analysis {

/// Which measurement the station provides.
enum class OdMeasurement { range = 0, range_rate, both };

/// Deprecated: use dynamics::Station (satgnc/dynamics/station.hpp), the one station model.
/// Station on a sphere rotating about +z: R(t) = Rz(rate t) R0 (km), V(t) = rate z x R(t) (km/s),
/// inertial frame. Converts to dynamics::Station{r0, rate} (same position; velocity equal up to the
/// sign of a zero). Its default rate stays the paper's, not the Earth's.
struct [[deprecated("use satgnc::dynamics::Station")]] RotatingStation {
  Vec3 r0;                ///< position at t = 0, km (inertial)
  double rate = 7.27e-5;  ///< rotation rate, rad/s (the paper's Table 3 station velocity implies 7.27e-5)
  Vec3 position(double t) const;  ///< km, inertial
  Vec3 velocity(double t) const;  ///< km/s, inertial
  /// The same station as a dynamics::Station (r0 km, omega = rate rad/s).
  operator dynamics::Station() const { return dynamics::Station{r0, rate}; }
};

/// Gramian of one OD arc and its conditioning.
struct OdGramianReport {
  GramianReport gramian;        ///< in km and km/s (mixed units)
  double jacobi_condition = 0;  ///< condition of D W D, D = diag(W_ii)^-1/2 (unit-free)
  /// Singular values of the stacked sensitivity M = [H_1 Phi_1; ...; H_N Phi_N] (W = M^T M),
  /// descending: computed without squaring, so they stay accurate where W's eigenvalues do not.
  Eigen::VectorXd singular_values;
  double sensitivity_condition = 0;         ///< sigma_max / sigma_min of M (= sqrt(cond W))
  double jacobi_sensitivity_condition = 0;  ///< the same after scaling M's columns to unit norm
  std::vector<double> times;                ///< observation times, s
};

/// Observability Gramian of x0 = [r km, v km/s] (inertial) at t = 0 from `kind` measurements at
/// `times` (s) from `station` (dynamics::Station: r0 km, omega rad/s; the partials are
/// dynamics::predict_measurement's), two-body dynamics with mu (km^3/s^2). Throws
/// std::invalid_argument on bad input (naming station.r0 / station.omega) or if the Kepler
/// propagation fails.
OdGramianReport od_observability_gramian(const Vec6& x0, const dynamics::Station& station,
                                         const std::vector<double>& times, OdMeasurement kind, double mu);

/// Elevation (rad) of the satellite above the station's geocentric horizon at time t (s).
double elevation(const Vec6& x0, const dynamics::Station& station, double t, double mu);

/// The visibility pass containing t = 0 (elevation > 0), searched in [-t_max, t_max] (s) with step dt
/// (s) and refined by bisection to 1e-6 s: {rise, set} (s). Throws if the satellite is not visible at 0.
std::pair<double, double> visibility_pass(const Vec6& x0, const dynamics::Station& station, double mu,
                                          double t_max = 3600.0, double dt = 10.0);

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif
/// Deprecated overloads: the same with a RotatingStation (invalid input names station.rate as before).
[[deprecated("use the dynamics::Station overload")]] OdGramianReport od_observability_gramian(
    const Vec6& x0, const RotatingStation& station, const std::vector<double>& times, OdMeasurement kind,
    double mu);
/// Deprecated: elevation with a RotatingStation.
[[deprecated("use the dynamics::Station overload")]] inline double elevation(const Vec6& x0,
                                                                             const RotatingStation& station,
                                                                             double t, double mu) {
  return elevation(x0, dynamics::Station(station), t, mu);
}
/// Deprecated: visibility_pass with a RotatingStation.
[[deprecated("use the dynamics::Station overload")]] inline std::pair<double, double> visibility_pass(
    const Vec6& x0, const RotatingStation& station, double mu, double t_max = 3600.0, double dt = 10.0) {
  return visibility_pass(x0, dynamics::Station(station), mu, t_max, dt);
}
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

}  // namespace satgnc::analysis
