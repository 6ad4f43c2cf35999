// CVODES plumbing shared by CvodesPropagator and CvodesOde.
#include <cvodes/cvodes_ls.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>
#include <sunnonlinsol/sunnonlinsol_newton.h>

#include <cstdio>
#include <stdexcept>
#include <string>

#include "detail/cvodes.hpp"

namespace satgnc::propagation::detail {

void RhsFailure::describe(std::string& message, const char* what, const char* unit) const {
  if (!failed) return;
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.17g", t);
  message += std::string("; ") + what + " failed at t = " + buf + unit;
}

PropagationStatus cvodes_flag_status(int flag) {
  switch (flag) {
    case CV_TOO_MUCH_WORK:
      return PropagationStatus::too_much_work;
    case CV_TOO_MUCH_ACC:
      return PropagationStatus::too_much_accuracy;
    case CV_ERR_FAILURE:
      return PropagationStatus::error_test_failures;
    case CV_CONV_FAILURE:
      return PropagationStatus::convergence_failures;
    case CV_RHSFUNC_FAIL:
    case CV_FIRST_RHSFUNC_ERR:
    case CV_REPTD_RHSFUNC_ERR:
    case CV_UNREC_RHSFUNC_ERR:
      return PropagationStatus::rhs_failure;
    default:
      return PropagationStatus::solver_failure;
  }
}

void cvodes_read_stats(void* mem, PropagationStats& s) {
  CVodeGetNumSteps(mem, &s.steps);
  CVodeGetNumRhsEvals(mem, &s.rhs_evals);
  CVodeGetNumErrTestFails(mem, &s.error_test_fails);
  CVodeGetNumNonlinSolvIters(mem, &s.nonlin_iters);
  CVodeGetNumNonlinSolvConvFails(mem, &s.nonlin_conv_fails);
  CVodeGetLastStep(mem, &s.last_step);
}

void cvodes_check(int flag, const char* what, const std::string& cv_message) {
  if (flag < 0) throw std::runtime_error(std::string("CVODES set-up failed in ") + what + ": " + cv_message);
}

void cvodes_store_message(int, const char*, const char*, char* msg, void* message) {
  *static_cast<std::string*>(message) = msg;
}

bool cvodes_newton_point(void* mem, realtype& t, realtype& gamma, N_Vector& ypred) {
  realtype rl1;
  N_Vector yn, fn, zn1;
  void* ud;
  return CVodeGetNonlinearSystemData(mem, &t, &ypred, &yn, &fn, &gamma, &rl1, &zn1, &ud) == CV_SUCCESS;
}

namespace {
SUNLinearSolver_Type matrix_embedded(SUNLinearSolver) { return SUNLINEARSOLVER_MATRIX_EMBEDDED; }
}  // namespace

void cvodes_attach_corrector(void* mem, N_Vector y, SUNContext ctx, bool newton, void* content,
                             CvodesLsSolve solve, const std::string& cv_message, SUNNonlinearSolver& nls,
                             SUNLinearSolver& ls) {
  if (!newton) {
    nls = SUNNonlinSol_FixedPoint(y, 0, ctx);
    if (nls == nullptr) throw std::runtime_error("SUNNonlinSol_FixedPoint failed");
    cvodes_check(CVodeSetNonlinearSolver(mem, nls), "CVodeSetNonlinearSolver", cv_message);
    return;
  }
  nls = SUNNonlinSol_Newton(y, ctx);
  if (nls == nullptr) throw std::runtime_error("SUNNonlinSol_Newton failed");
  cvodes_check(CVodeSetNonlinearSolver(mem, nls), "CVodeSetNonlinearSolver", cv_message);
  ls = SUNLinSolNewEmpty(ctx);
  if (ls == nullptr) throw std::runtime_error("SUNLinSolNewEmpty failed");
  ls->content = content;
  ls->ops->gettype = &matrix_embedded;
  ls->ops->solve = solve;
  cvodes_check(CVodeSetLinearSolver(mem, ls, nullptr), "CVodeSetLinearSolver", cv_message);
}

}  // namespace satgnc::propagation::detail
