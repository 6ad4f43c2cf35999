#pragma once
/// @file solver.hpp
/// The one solver contract of the library (as OSQP and proxsuite have it) and the base of every
/// solver's Info.
///
/// Shape every solver follows (guidance::AdmmSolver, IlqrAdmmSolver, ScpSolver, od::OdSolver;
/// integrators and kernels document where they differ):
///  - `XSettings`: plain fields with documented defaults and units, and `validate()` that throws
///    std::invalid_argument("name: rule (hint: ...)") through core::require.
///  - `XProblem`: constant problem data, validated the same way.
///  - `XSolver(problem, settings)`: validates both, copies what it needs and allocates its workspace
///    once. Invalid settings throw here, at setup, never later.
///  - `const XResult& solve() noexcept`: no throw and no heap allocation (in test builds the
///    no-allocation guard of core/no_malloc.hpp checks it); the result's arrays are sized at setup.
///  - `XResult` holds the solution and `info`, an `XInfo` derived from InfoBase below: status,
///    iterations, residuals and the wall time of solve().
///  - Status enums live in core/status.hpp (snake_case, `unsolved` first, one name/message table).
#include "satgnc/core/status.hpp"

namespace satgnc::core {

/// Fields every solver's Info has. `Status` is a status enum of core/status.hpp with an `unsolved`
/// enumerator, which is the value before the first solve().
template <class Status>
struct InfoBase {
  static_assert(is_status_v<Status>, "InfoBase<Status>: Status must be a status enum of core/status.hpp");
  Status status = Status::unsolved;  ///< outcome of the last solve(); unsolved before the first
  int iterations = 0;                ///< iterations of the last solve() (each solver documents which)
  double primal_residual = 0.0;      ///< primal residual at the returned iterate, in the solver's units
  double dual_residual = 0.0;        ///< dual residual (or step size) at the returned iterate, solver's units
  double solve_time = 0.0;           ///< wall time of the last solve(), s
};

}  // namespace satgnc::core
