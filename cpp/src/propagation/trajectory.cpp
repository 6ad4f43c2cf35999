// Message table of PropagationStatus.
#include "satgnc/propagation/trajectory.hpp"

namespace satgnc::propagation {

const char* status_message(PropagationStatus s) {
  switch (s) {
    case PropagationStatus::success:
      return "success";
    case PropagationStatus::too_much_work:
      return "too much work: the step budget (max_steps) was exhausted before the last requested time";
    case PropagationStatus::too_much_accuracy:
      return "too much accuracy requested: the tolerances are below what double precision delivers";
    case PropagationStatus::error_test_failures:
      return "repeated local error test failures (the step size collapsed)";
    case PropagationStatus::convergence_failures:
      return "the corrector failed to converge repeatedly";
    case PropagationStatus::rhs_failure:
      return "the force model failed (|r| reached 0 or the acceleration was not finite)";
    case PropagationStatus::solver_failure:
      return "integrator failure";
  }
  return "unknown status";
}

}  // namespace satgnc::propagation
