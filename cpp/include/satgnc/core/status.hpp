#pragma once
/// @file status.hpp
/// One status scheme for every solver, integrator and test of the library.
///
/// Each enum is one X-macro list `X(name, value, "message")`. From it come the enum (snake_case
/// enumerators, `unsolved` declared first, explicit numeric values that never change: Python keys
/// results by them and new statuses are appended), `status_name(E)` (the enumerator's name, which
/// is the string Python users read: "solved", "converged", "success", ...), `status_message(E)`
/// (one sentence) and `status_table<E>()` (a std::array of {value, name, message}, the table the
/// bindings and Python read; nothing re-types it). Old enumerator spellings stay as
/// `[[deprecated]]` aliases of the same value and are not part of the tables.
///
/// Room headers re-export their enum (`namespace satgnc::guidance { using core::AdmmStatus; }`).
/// `Verdict` is the one intended exception to "unsolved first": it is the verdict of a rank test,
/// not the outcome of a run (every call returns one or throws), so it has no `unsolved`.
/// Header-only and constexpr: nothing here allocates or throws.
#include <array>
#include <cstddef>
#include <type_traits>

namespace satgnc::core {

/// One row of a status table.
struct StatusEntry {
  int value;            ///< numeric value of the enumerator (stable)
  const char* name;     ///< enumerator name, snake_case
  const char* message;  ///< one-sentence description
};

/// Specialized for every status enum below; `table` is its std::array of StatusEntry.
template <class E>
struct StatusTraits {
  static constexpr bool is_status = false;
};

/// True for the enums declared in this header.
template <class E>
inline constexpr bool is_status_v = StatusTraits<E>::is_status;

/// The {value, name, message} rows of a status enum, in declaration order (`unsolved` first).
template <class E>
constexpr auto status_table() noexcept {
  static_assert(is_status_v<E>, "status_table<E>: E must be a status enum of satgnc/core/status.hpp");
  return StatusTraits<E>::table;
}

/// The enumerator with this name, or `fallback` when no row has it (lookup of a user string).
template <class E>
constexpr E status_from_name(const char* name, E fallback) noexcept {
  for (const StatusEntry& e : StatusTraits<E>::table) {
    const char* a = e.name;
    const char* b = name;
    while (*a != '\0' && *a == *b) {
      ++a;
      ++b;
    }
    if (*a == *b) return static_cast<E>(e.value);
  }
  return fallback;
}

}  // namespace satgnc::core

// ------------------------------------------------------------------------------------------------
// Generator macros (undefined at the end of this header).
#define SATGNC_STATUS_ENUMERATOR_(name, value, message) name = value,
#define SATGNC_STATUS_ALIAS_(old_name, new_name) old_name [[deprecated("use " #new_name)]] = new_name,
#define SATGNC_STATUS_ROW_(name, value, message) StatusEntry{value, #name, message},
#define SATGNC_STATUS_NAME_CASE_(name, value, message) \
  case E_::name:                                       \
    return #name;
#define SATGNC_STATUS_MESSAGE_CASE_(name, value, message) \
  case E_::name:                                          \
    return message;
#define SATGNC_NO_ALIASES_(A)

/// Declares `enum class Enum` from LIST and ALIASES, and its status_name, status_message and table.
#define SATGNC_DEFINE_STATUS_(Enum, LIST, ALIASES)                                          \
  enum class Enum : int { LIST(SATGNC_STATUS_ENUMERATOR_) ALIASES(SATGNC_STATUS_ALIAS_) };  \
  /** Enumerator name of a status ("unknown" for a value outside the table). */             \
  constexpr const char* status_name(Enum s) noexcept {                                      \
    using E_ = Enum;                                                                        \
    switch (s) { LIST(SATGNC_STATUS_NAME_CASE_) }                                           \
    return "unknown";                                                                       \
  }                                                                                         \
  /** One-sentence message of a status ("unknown status" for a value outside the table). */ \
  constexpr const char* status_message(Enum s) noexcept {                                   \
    using E_ = Enum;                                                                        \
    switch (s) { LIST(SATGNC_STATUS_MESSAGE_CASE_) }                                        \
    return "unknown status";                                                                \
  }                                                                                         \
  template <>                                                                               \
  struct StatusTraits<Enum> {                                                               \
    static constexpr bool is_status = true;                                                 \
    static constexpr std::array table{LIST(SATGNC_STATUS_ROW_)};                            \
  };

namespace satgnc::core {

// ------------------------------------------------------------------------------------------------
/// AdmmStatus: outcome of guidance::AdmmSolver::solve() (docs/guidance.md has what each guarantees).
#define SATGNC_ADMM_STATUS(X)                                                                                \
  X(unsolved, 5, "not solved yet")                                                                           \
  X(solved, 0,                                                                                               \
    "solved: residuals and relative duality gap within tolerance, or certified active-set polish")           \
  X(solved_paper_rule, 1,                                                                                    \
    "stopped by the paper's rule ||U-Y||/dim(U) <= eps (not a convergence certificate)")                     \
  X(max_iterations, 2, "maximum iterations reached: best iterate returned, check the residuals")             \
  X(terminal_unreachable, 3, "terminal state unreachable: x_f is outside the reachable set of the dynamics") \
  X(numerical_error, 4, "numerical error: non-finite iterate or failed Riccati factorization")               \
  X(solved_inaccurate, 6, "solved inaccurate: stopped at a limit with only the loose tolerances met")        \
  X(primal_infeasible, 7,                                                                                    \
    "primal infeasible: the bounds and the terminal state cannot all hold (certificate given)")              \
  X(time_limit, 8, "time limit reached: best iterate returned, check the residuals")
#define SATGNC_ADMM_STATUS_ALIASES(A)           \
  A(kSolved, solved)                            \
  A(kSolvedPaperRule, solved_paper_rule)        \
  A(kMaxIterations, max_iterations)             \
  A(kTerminalUnreachable, terminal_unreachable) \
  A(kNumericalError, numerical_error)           \
  A(kUnsolved, unsolved)                        \
  A(kSolvedInaccurate, solved_inaccurate) A(kPrimalInfeasible, primal_infeasible) A(kTimeLimit, time_limit)
SATGNC_DEFINE_STATUS_(AdmmStatus, SATGNC_ADMM_STATUS, SATGNC_ADMM_STATUS_ALIASES)

/// RiccatiStatus: outcome of one guidance::RiccatiSolver::solve() (a kernel inside ADMM).
#define SATGNC_RICCATI_STATUS(X)                                            \
  X(unsolved, 2, "factor() was not called or failed")                       \
  X(solved, 0, "solved (and x_N = x_f when the terminal constraint is on)") \
  X(terminal_unreachable, 1, "x_f is outside the reachable set; the least-squares multiplier was used")
#define SATGNC_RICCATI_STATUS_ALIASES(A) \
  A(kOk, solved) A(kTerminalUnreachable, terminal_unreachable) A(kNotFactored, unsolved)
SATGNC_DEFINE_STATUS_(RiccatiStatus, SATGNC_RICCATI_STATUS, SATGNC_RICCATI_STATUS_ALIASES)

/// IlqrAdmmStatus: outcome of guidance::IlqrAdmmSolver::solve() (docs/guidance_nonlinear.md).
#define SATGNC_ILQR_ADMM_STATUS(X)                                                            \
  X(unsolved, 4, "solve() not called")                                                        \
  X(solved, 0, "solved: stopping rule met and the plan rolls out on the model")               \
  X(max_iterations, 1, "max_iter reached; best iterate (smallest ||U - Y||) returned")        \
  X(propagation_failed, 2,                                                                    \
    "the dynamics failed (initial rollout or the returned plan; see failed_interval)")        \
  X(ilqr_failed, 3, "iLQR made no progress up to reg_max; best iterate returned")             \
  X(solved_inaccurate, 5,                                                                     \
    "stopped at a limit with the residual rule met at inaccurate_factor x eps; best iterate") \
  X(time_limit, 6, "time_limit reached; best iterate returned")
#define SATGNC_ILQR_ADMM_STATUS_ALIASES(A) A(not_run, unsolved)
SATGNC_DEFINE_STATUS_(IlqrAdmmStatus, SATGNC_ILQR_ADMM_STATUS, SATGNC_ILQR_ADMM_STATUS_ALIASES)

/// ScpStatus: outcome of guidance::ScpSolver::solve(). Whatever the status, the returned U is the
/// iterate of lowest true cost seen.
#define SATGNC_SCP_STATUS(X)                                                                          \
  X(unsolved, 5, "solve() not called")                                                                \
  X(solved, 0,                                                                                        \
    "solved: predicted decrease <= tol * max(1, J) on a solved subproblem, trust region inactive")    \
  X(max_outer, 1, "max_outer reached; best iterate returned")                                         \
  X(propagation_failed, 2, "the dynamics failed (see failed_interval); best iterate returned")        \
  X(inner_failed, 3, "the convex subproblem solver failed (see inner_status); best iterate returned") \
  X(line_search_failed, 4,                                                                            \
    "no acceptable step (line search exhausted or trust radius below tr_min); best iterate returned") \
  X(solved_inaccurate, 6,                                                                             \
    "stopped at a limit with predicted decrease <= tol_inaccurate * max(1, J); best iterate")         \
  X(inner_infeasible, 7,                                                                              \
    "the linearized subproblem is infeasible (x_f outside what the box reaches; see "                 \
    "infeasibility_certificate / infeasibility_margin) and no restoration step lowers the "           \
    "terminal miss; best iterate returned")                                                           \
  X(time_limit, 8, "time_limit reached; best iterate returned")
#define SATGNC_SCP_STATUS_ALIASES(A) A(not_run, unsolved)
SATGNC_DEFINE_STATUS_(ScpStatus, SATGNC_SCP_STATUS, SATGNC_SCP_STATUS_ALIASES)

/// OdStatus: outcome of od::OdSolver::solve() (guarantees: docs/od.md, "Statuses").
#define SATGNC_OD_STATUS(X)                                                                            \
  X(unsolved, 6, "not solved yet")                                                                     \
  X(converged, 0, "converged")                                                                         \
  X(max_iterations, 1, "maximum number of iterations reached")                                         \
  X(singular, 2, "Jacobian is rank deficient (see rank): the data do not determine the state")         \
  X(diverged, 3, "diverged: an iterate went below the minimum radius or became unbound (energy >= 0)") \
  X(propagation_failed, 4, "propagation failed")                                                       \
  X(degenerate_geometry, 5, "zero range: the satellite is at the station, range-rate is undefined")    \
  X(stalled, 7, "stalled: no trial step lowered the cost and the convergence test does not hold")
SATGNC_DEFINE_STATUS_(OdStatus, SATGNC_OD_STATUS, SATGNC_NO_ALIASES_)

/// PropagationStatus: outcome of a propagation (Trajectory::status). Anything but success means the
/// arc ended early at Trajectory::t_reached; a fresh Trajectory is unsolved.
#define SATGNC_PROPAGATION_STATUS(X)                                                             \
  X(unsolved, 8, "not propagated yet")                                                           \
  X(success, 0, "success")                                                                       \
  X(too_much_work, 1,                                                                            \
    "too much work: the step budget (max_steps) was exhausted before the last requested time")   \
  X(too_much_accuracy, 2,                                                                        \
    "too much accuracy requested: the tolerances are below what double precision delivers")      \
  X(error_test_failures, 3, "repeated local error test failures (the step size collapsed)")      \
  X(convergence_failures, 4, "the corrector failed to converge repeatedly")                      \
  X(rhs_failure, 5, "the force model failed (|r| reached 0 or the acceleration was not finite)") \
  X(solver_failure, 6, "integrator failure")                                                     \
  X(impact, 7, "impact: the trajectory reached the surface radius (or the centre, r = 0) at t_reached")
SATGNC_DEFINE_STATUS_(PropagationStatus, SATGNC_PROPAGATION_STATUS, SATGNC_NO_ALIASES_)

/// Dop853Status: outcome of propagation::Dop853::solve(). invalid_settings is kept for its number:
/// since settings are validated by the constructor (it throws), solve() no longer returns it.
#define SATGNC_DOP853_STATUS(X)                                                             \
  X(unsolved, 7, "not solved yet")                                                          \
  X(success, 0, "success")                                                                  \
  X(invalid_settings, 1,                                                                    \
    "invalid settings: need rtol > 10 eps, atol >= 0, max_steps > 0, h0 >= 0, h_max >= 0, " \
    "0 < safety < 1, 0 < fac_min <= 1 <= fac_max, 0 <= beta <= 0.2")                        \
  X(invalid_input, 2,                                                                       \
    "invalid input: non-finite t0, y0 or output time, or output times not monotone away "   \
    "from t0")                                                                              \
  X(max_steps, 3, "step budget (max_steps) exhausted before the last output time")          \
  X(step_size_too_small, 4, "step size became smaller than the resolution of t")            \
  X(rhs_failure, 5, "right-hand side returned a non-finite derivative")                     \
  X(event, 6, "the event function reached zero (e.g. the surface was reached)")
SATGNC_DEFINE_STATUS_(Dop853Status, SATGNC_DOP853_STATUS, SATGNC_NO_ALIASES_)

/// KeplerStatus: outcome of propagation::kepler_step (no exceptions on that path: embedded use).
#define SATGNC_KEPLER_STATUS(X)                                                                 \
  X(unsolved, 4, "not propagated yet")                                                          \
  X(success, 0, "success")                                                                      \
  X(invalid_input, 1, "invalid input: non-finite state, time or mu, mu <= 0, or |r0| = 0")      \
  X(no_convergence, 2, "universal Kepler equation did not converge within the iteration limit") \
  X(overflow, 3, "hyperbolic functions overflowed (time of flight too long for this hyperbola)")
SATGNC_DEFINE_STATUS_(KeplerStatus, SATGNC_KEPLER_STATUS, SATGNC_NO_ALIASES_)

/// ObservationStatus: outcome of one observation::MeasurementModel::predict() (docs/observation.md).
#define SATGNC_OBSERVATION_STATUS(X)                                                                   \
  X(unsolved, 4, "not predicted yet")                                                                  \
  X(success, 0, "success: light time converged and the value and partials are set")                    \
  X(no_convergence, 1,                                                                                 \
    "the light-time iteration did not converge within max_iterations; value and partials of the last " \
    "iterate")                                                                                         \
  X(degenerate_geometry, 2,                                                                            \
    "degenerate geometry: range below min_range, or the angle is undefined (zenith, celestial pole)")  \
  X(invalid_input, 3, "invalid input: non-finite state, time, bias or station state")
SATGNC_DEFINE_STATUS_(ObservationStatus, SATGNC_OBSERVATION_STATUS, SATGNC_NO_ALIASES_)

/// Verdict of an analysis rank test (intended exception: a verdict, not a run outcome, so no
/// `unsolved`). The message is the verdict in words ("full rank", ...).
#define SATGNC_VERDICT(X)                                                                                \
  X(full_rank, 0, "full rank")           /* controllable / observable, with margin >= fuzz */            \
  X(rank_deficient, 1, "rank deficient") /* uncontrollable / unobservable, with margin >= fuzz */        \
  X(not_robustly_decidable, 2, "not robustly decidable") /* a singular value in the fuzz band, or the */ \
                                                         /* verdict hinges on entries below the tolerance */
SATGNC_DEFINE_STATUS_(Verdict, SATGNC_VERDICT, SATGNC_NO_ALIASES_)

}  // namespace satgnc::core

// SATGNC_DEFINE_STATUS_(Enum, LIST, ALIASES) and its helper macros stay defined: a room that keeps
// its status lists in its own header (filter/status.hpp) declares them with the same generator, inside
// namespace satgnc::core, and re-exports them into its namespace like the enums above.
