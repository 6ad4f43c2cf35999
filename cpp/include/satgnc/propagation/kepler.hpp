#pragma once
/// @file kepler.hpp
/// Analytic two-body propagation in universal variables (Battin, "An Introduction to the Mathematics
/// and Methods of Astrodynamics", rev. ed. 1999, ch. 4.5-4.6 and 9.7; Goodyear 1965) with the analytic
/// 6x6 state transition matrix. One formulation covers ellipses (also many revolutions), parabolas,
/// near-parabolic orbits and hyperbolas: the Stumpff functions are evaluated by series near psi = 0.
/// Units: km, km/s, s, km^3/s^2.
#include <string>
#include <vector>

#include "satgnc/core/status.hpp"
#include "satgnc/core/types.hpp"
#include "satgnc/propagation/trajectory.hpp"

namespace satgnc::propagation {

/// Outcome of kepler_step (core/status.hpp; no exceptions on this path: embedded use): success,
/// invalid_input (non-finite x0/dt/mu, mu <= 0 or |r0| = 0), no_convergence (the universal Kepler
/// equation did not converge in KeplerLimits::max_iterations), overflow (hyperbolic functions
/// overflowed, |dt| far beyond the asymptote's reach); unsolved before a step ran.
using core::KeplerStatus;

/// Human-readable message for a KeplerStatus.
[[deprecated("use status_message")]] inline const char* kepler_status_message(KeplerStatus s) {
  return core::status_message(s);
}

/// Fixed iteration limits of the Kepler solver (constexpr: the solver has no settings to tune).
struct KeplerLimits {
  static constexpr int max_iterations = 60;  ///< Laguerre iterations, each bracketed (bisection fallback)
};

/// Diagnostics of one kepler_step.
struct KeplerInfo {
  int iterations = 0;     ///< iterations spent on the universal Kepler equation
  double chi = 0.0;       ///< universal anomaly at dt, sqrt(km)
  double alpha = 0.0;     ///< 1/a = 2/r0 - v0^2/mu, 1/km (> 0 ellipse, 0 parabola, < 0 hyperbola)
  double residual = 0.0;  ///< |F(chi)| of the universal Kepler equation at exit, sqrt(km^3/s^2) * s
  KeplerStatus status = KeplerStatus::unsolved;  ///< what kepler_step returned (unsolved until it runs)
};

/// Propagate a two-body state by dt.
/// @param x0  initial state [r (km), v (km/s)]
/// @param dt  time of flight, s (any sign; 0 returns x0 and the identity)
/// @param mu  gravitational parameter, km^3/s^2 (> 0)
/// @param x   output state at t0 + dt, [km, km/s]
/// @param stm optional output d x(t0 + dt) / d x0 (6x6, mixed units); nullptr skips it
/// @param info optional diagnostics
/// @param max_iterations iteration budget of the Kepler solver (tests lower it to force a failure)
/// @return KeplerStatus::success, or why x is not valid. Allocates nothing; throws nothing.
KeplerStatus kepler_step(const Vec6& x0, double dt, double mu, Vec6& x, Mat6* stm, KeplerInfo* info = nullptr,
                         int max_iterations = KeplerLimits::max_iterations);

/// Stumpff functions c_k(psi), k = 0..5, with c_k(psi) = sum_j (-psi)^j / (k + 2j)!.
/// Series for |psi| < 1, closed forms (trigonometric or hyperbolic) elsewhere.
void stumpff(double psi, double c[6]);

/// Message for a failed kepler_step that names the conic actually propagated (alpha = 1/a, 1/km):
/// "overflow" is a hyperbola's asymptote only when alpha < 0.
std::string kepler_failure_message(KeplerStatus s, double alpha, double dt);

/// First time s in (0, |dt|] after which the two-body arc from x0 (forward in time for dt > 0,
/// backward for dt < 0) reaches |r| = surface_radius (km), or the centre (|r| = 0) when
/// surface_radius is 0: a collision orbit (periapsis below 1e-9 |r0|) counts as reaching it.
/// @return s >= 0 (the arc time to impact, s), or -1 when the arc stays above the radius.
/// Uses the periapsis time (ellipses) or a unimodal search (open conics) and bisection; ~100
/// kepler_step calls when an impact is found, a few otherwise. Allocates nothing; throws nothing.
double kepler_time_to_radius(const Vec6& x0, double dt, double mu, double surface_radius);

/// Propagate x0 (epoch t0) to each requested time with kepler_step (each time directly from t0, so
/// errors do not accumulate).
/// @param x0 initial state [km, km/s]; @param t0 epoch, s; @param times output times, s,
///   monotone (increasing or decreasing), any side of t0; @param mu km^3/s^2;
/// @param with_stm also return the STMs.
/// @param surface_radius km (>= 0). An arc that reaches |r| = surface_radius before a requested time
///   (or r = 0, always checked: a collision orbit) stops with PropagationStatus::impact, t_reached =
///   the impact time (s) and the outputs before it; 0 checks only the centre.
/// @throws std::invalid_argument naming the argument on non-finite x0/t0/times, |r0| = 0, mu <= 0,
///   non-monotone times, a negative surface_radius or |r0| below it. A solver failure or an impact is
///   reported in Trajectory::status / message (states up to it).
Trajectory propagate_kepler(const Vec6& x0, double t0, const std::vector<double>& times, double mu,
                            bool with_stm, double surface_radius = 0.0);

}  // namespace satgnc::propagation
