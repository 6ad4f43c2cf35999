#pragma once
/// @file light_time.hpp
/// Light-time equations of a ground-station measurement tagged at reception, solved by fixed-point
/// iteration, and the short two-body shift that carries the spacecraft state from reception to the
/// bounce time. Everything in GCRF, km, km/s, s. The light-time equations are written in the
/// geocentric frame (no barycentric correction; the Shapiro delay is a separate modifier).
///
/// Down leg: c tau_d = |r(t_r - tau_d) - R(t_r)|; up leg: c tau_u = |r(t_b) - R(t_b - tau_u)| with
/// t_b = t_r - tau_d. The fixed-point map contracts by |v|/c (2.6e-5 in LEO), so each iteration
/// gains ~4.6 digits: from the instantaneous guess the 1e-14 s default is met in 3 iterations.
#include "satgnc/core/constants.hpp"
#include "satgnc/core/types.hpp"
#include "satgnc/observation/station_ephemeris.hpp"

namespace satgnc::observation {

/// Speed of light in vacuum, km/s (exact, SI).
inline constexpr double speed_of_light = 299792.458;

/// Light-time iteration settings.
struct LightTimeSettings {
  double tolerance =
      1e-14;  ///< s: stop when a fixed-point update changes tau by at most this (c * 1e-14 s = 3 um)
  int max_iterations = 10;  ///< per leg; beyond it the prediction's status is no_convergence

  /// Throws std::invalid_argument("light_time.tolerance: ...") unless tolerance is finite and in
  /// [1e-18, 1e-3] s and 1 <= max_iterations <= 100.
  void validate() const;
};

/// Shift a spacecraft state x = [r km, v km/s] by dt (s, either sign) with the third-order Taylor
/// series of two-body motion: r' = r + dt v + dt^2/2 a + dt^3/6 j, v' = v + dt a + dt^2/2 j, with
/// a = -mu r/|r|^3 and j = da/dt. Error (measured against Kepler, tests/cpp/test_light_time.cpp):
/// < 1e-13 km over the 10 ms light time of a LEO pass, < 1e-9 km over the 0.13 s of GEO. Optional
/// outputs: d x' / d x (6 x 6) and d x' / d dt (= [v', a + dt j]). Allocation-free; x must have
/// |r| > 0 (not checked: the caller validates).
void shift_state(const Vec6& x, double dt, double mu, Vec6& out, Mat6* dout_dx = nullptr,
                 Vec6* dout_ddt = nullptr) noexcept;

/// One solved leg.
struct LightTimeLeg {
  double tau = 0.0;        ///< light time, s
  int iterations = 0;      ///< fixed-point updates made
  bool converged = false;  ///< |last update| <= tolerance
};

/// Down leg: tau with c tau = |r(t_r - tau) - R_rx|, r(.) the shift_state of x (state at
/// reception). Starts from |r - R_rx| / c. Allocation-free.
LightTimeLeg solve_down_leg(const Vec6& x, const Vec3& station_at_reception, double mu,
                            const LightTimeSettings& settings) noexcept;

/// Up leg: tau with c tau = |r_bounce - R(t_bounce - tau)|, the station from `station` at
/// t_bounce - tau (its time axis). Starts from tau_guess (e.g. the down-leg tau). On return
/// `at_transmit` holds the station state at t_bounce - tau. Allocation-free.
LightTimeLeg solve_up_leg(const Vec3& r_bounce, const StationEphemeris& station, double t_bounce,
                          double tau_guess, const LightTimeSettings& settings,
                          StationState& at_transmit) noexcept;

}  // namespace satgnc::observation
