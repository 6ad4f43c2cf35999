// CVODES plumbing shared by CvodesPropagator and CvodesOde.
#include <cvodes/cvodes_ls.h>
#include <nvector/nvector_serial.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>
#include <sunnonlinsol/sunnonlinsol_newton.h>

#include <cstdio>
#include <stdexcept>
#include <string>

#include "detail/cvodes.hpp"
#include "detail/nvector.hpp"

namespace satgnc::propagation::detail {

std::string format_g17(double x) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

void RhsFailure::describe(std::string& message, const char* what, const char* unit) const {
  if (!failed) return;
  message += std::string("; ") + what + " failed at t = " + format_g17(t) + unit;
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

CvodesHandles::~CvodesHandles() {
  if (mem != nullptr) CVodeFree(&mem);
  if (nls != nullptr) SUNNonlinSolFree(nls);
  if (ls != nullptr) SUNLinSolFreeEmpty(ls);
  if (abstol != nullptr) N_VDestroy(abstol);
  if (y != nullptr) N_VDestroy(y);
  if (ctx != nullptr) SUNContext_Free(&ctx);
}

void cvodes_create(const CvodesSetup& s, CvodesHandles& h, std::string& cv_message) {
  const auto check = [&cv_message](int flag, const char* what) { cvodes_check(flag, what, cv_message); };
  const auto new_vector = [&s, &h]() {
    return s.serial_vector ? N_VNew_Serial(s.n, h.ctx) : nvector_new(s.n, h.ctx);
  };
  if (SUNContext_Create(nullptr, &h.ctx) != 0) throw std::runtime_error("SUNContext_Create failed");
  h.y = new_vector();
  if (h.y == nullptr) throw std::runtime_error("N_Vector allocation failed");
  double* yd = N_VGetArrayPointer(h.y);
  for (int i = 0; i < s.n; ++i) yd[i] = 0.0;
  yd[0] = s.y_first;
  h.mem = CVodeCreate(s.adams ? CV_ADAMS : CV_BDF, h.ctx);
  if (h.mem == nullptr) throw std::runtime_error("CVodeCreate failed");
  check(CVodeSetErrHandlerFn(h.mem, &cvodes_store_message, &cv_message), "CVodeSetErrHandlerFn");
  check(CVodeInit(h.mem, s.rhs, 0.0, h.y), "CVodeInit");
  check(CVodeSetUserData(h.mem, s.user_data), "CVodeSetUserData");
  if (s.atol_components == nullptr || s.atol_components->empty()) {
    check(CVodeSStolerances(h.mem, s.rtol, s.atol), "CVodeSStolerances");
  } else {
    h.abstol = new_vector();
    if (h.abstol == nullptr) throw std::runtime_error("N_Vector allocation failed");
    double* ad = N_VGetArrayPointer(h.abstol);
    const std::vector<double>& c = *s.atol_components;
    for (int i = 0; i < s.n; ++i)
      ad[i] = i < static_cast<int>(c.size()) ? c[static_cast<std::size_t>(i)] : s.atol;
    check(CVodeSVtolerances(h.mem, s.rtol, h.abstol), "CVodeSVtolerances");
  }
  if (s.max_order > 0) check(CVodeSetMaxOrd(h.mem, s.max_order), "CVodeSetMaxOrd");
  if (s.max_step > 0.0) check(CVodeSetMaxStep(h.mem, s.max_step), "CVodeSetMaxStep");
  cvodes_attach_corrector(h.mem, h.y, h.ctx, s.newton, s.user_data, s.ls_solve, cv_message, h.nls, h.ls);
}

void cvodes_root_downward(void* mem, CVRootFn g, const std::string& cv_message) {
  cvodes_check(CVodeRootInit(mem, 1, g), "CVodeRootInit", cv_message);
  int down = -1;  // only entering the region is an impact
  cvodes_check(CVodeSetRootDirection(mem, &down), "CVodeSetRootDirection", cv_message);
  cvodes_check(CVodeSetNoInactiveRootWarn(mem), "CVodeSetNoInactiveRootWarn", cv_message);
}

}  // namespace satgnc::propagation::detail
