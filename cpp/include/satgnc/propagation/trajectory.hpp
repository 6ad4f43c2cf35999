#pragma once
/// @file trajectory.hpp
/// What every propagator returns: states and STMs at the requested times, statistics and a status.
#include <string>
#include <vector>

#include "satgnc/core/status.hpp"
#include "satgnc/core/types.hpp"

namespace satgnc::propagation {

/// Outcome of a propagation (core/status.hpp). Anything but success means the arc ended early at
/// Trajectory::t_reached: too_much_work (Settings::max_steps exhausted), too_much_accuracy
/// (tolerances below double precision), error_test_failures (step size collapsed),
/// convergence_failures (corrector), rhs_failure (the force model failed, e.g. |r| reached 0),
/// solver_failure (any other), impact (surface radius or r = 0 reached; t_reached = impact time).
/// A fresh Trajectory is unsolved. status_message() gives the text (message table, as OSQP does).
using core::PropagationStatus;
using core::status_message;
using core::status_name;

/// Largest |component| of an initial state x0 = [r km, v km/s] a propagator accepts: the force
/// model's |r|^3 overflows double precision near 5e102 km (x0 = 1e300 was a "force model failed"
/// status at t0 instead of an error naming x0).
inline constexpr double kMaxStateComponent = 1e100;

/// Throw std::invalid_argument naming x0 unless every |x0_i| < kMaxStateComponent.
void validate_state_magnitude(const Vec6& x0);

/// Rules on the output times of an orbit arc (validate_orbit_arc_input). The default is the
/// two-arc rule of DOP853 and Kepler; kOneSidedArc is CVODES's.
struct ArcRules {
  bool strict = false;     ///< strictly monotone (no duplicates) instead of non-decreasing / non-increasing
  bool one_sided = false;  ///< every time on one side of t0 and ordered away from it (one integration)
  bool non_empty = false;  ///< at least one output time
};

/// Two arcs from t0: times monotone (non-strictly, increasing or decreasing), either side of t0,
/// possibly empty (DOP853 and Kepler).
inline constexpr ArcRules kTwoSidedArc{false, false, false};
/// One arc from t0: times non-empty, on one side of t0, strictly monotone away from it (CVODES).
inline constexpr ArcRules kOneSidedArc{true, true, true};

/// Hint of the |r0| = 0 error for a propagator that integrates gravity (CVODES, DOP853).
inline constexpr const char* kGravitySingular = "gravity is singular at the centre of the body";

/// The one check of an orbit arc's input, shared by every propagator. Throws
/// std::invalid_argument("name: rule (hint: ...)") unless x0 = [r km, v km/s] is finite with
/// |r0| > 0 and every |x0_i| < kMaxStateComponent, t0 (s) is finite, and the output times (s) are
/// finite and obey `rules`. `singular_hint` says why |r0| = 0 is refused by the caller.
/// One wording per rule:
/// - "x0: must be finite (no NaN or Inf)"
/// - "x0: position must be non-zero (|r0| = 0) (hint: <singular_hint>)"
/// - "t0: must be finite (no NaN or Inf)"
/// - "times: must not be empty (hint: ...)"
/// - "times: must be finite (no NaN or Inf), times[i] is not"
/// - "times: must all lie on one side of t0 (forward or backward), times[0] = .., t0 = .. (hint: ...)"
/// - "times: must be [strictly ]monotone (...)[ in the direction of propagation], times[i-1] = ..,
///   times[i] = .. (hint: ...)"
/// The success path does not allocate (the messages are built only on failure).
void validate_orbit_arc_input(const Vec6& x0, double t0, const std::vector<double>& times, ArcRules rules,
                              const char* singular_hint);

/// validate_orbit_arc_input with the two-arc rules (kTwoSidedArc), kept for existing callers.
inline void validate_orbit_arc_input(const Vec6& x0, double t0, const std::vector<double>& times,
                                     const char* singular_hint) {
  validate_orbit_arc_input(x0, t0, times, kTwoSidedArc, singular_hint);
}

/// Integrator statistics.
struct PropagationStats {
  long steps = 0;              ///< accepted steps
  long rhs_evals = 0;          ///< right-hand-side evaluations (state + variational equations)
  long error_test_fails = 0;   ///< rejected steps
  long nonlin_iters = 0;       ///< corrector iterations (implicit methods; 0 otherwise)
  long nonlin_conv_fails = 0;  ///< corrector convergence failures (CVODES)
  long lin_setups = 0;         ///< linear-solver setups (Jacobian evaluations; Newton corrector only)
  double last_step = 0.0;      ///< size of the last accepted step, s (signed)
};

/// States (km, km/s) and 6x6 STMs dPhi(t_i, t0) at the requested times t_i (s).
struct Trajectory {
  std::vector<double> times;  ///< s, as requested (only those reached when status != success)
  std::vector<Vec6> states;   ///< [r km, v km/s] at each time
  std::vector<Mat6> stms;     ///< d x(t_i) / d x(t0); empty when the STM was not requested
  PropagationStats stats;
  PropagationStatus status = PropagationStatus::unsolved;  ///< unsolved until a propagator fills it
  double t_reached = 0.0;                                  ///< last time the integrator reached, s
  std::string message;                                     ///< why it stopped, when status != success
};

}  // namespace satgnc::propagation
