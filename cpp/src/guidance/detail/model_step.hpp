#pragma once
// Private to the guidance room (not installed): the one way the noexcept solvers (IlqrAdmmSolver,
// ScpSolver) call a user's dynamics.
#include "satgnc/dynamics/discrete_model.hpp"

namespace satgnc::guidance::detail {

/// model.step(k, x, u, x_next, A, B) (DiscreteModel's units and layout), with an exception thrown
/// by the model reported as a failed step (false), as a model's own `return false` is: the solvers
/// then end in their propagation_failed / ilqr_failed statuses instead of unwinding through a
/// noexcept solve(). The exception's message is not kept (no allocation inside solve()).
inline bool model_step(const dynamics::DiscreteModel& model, int k, const double* x, const double* u,
                       double* x_next, double* A, double* B) noexcept {
  try {
    return model.step(k, x, u, x_next, A, B);
  } catch (...) {
    return false;
  }
}

}  // namespace satgnc::guidance::detail
