#pragma once
// Private to the propagation room: what CvodesPropagator (orbits with STM) and CvodesOde (generic
// N-dimensional systems) share in driving SUNDIALS CVODES 6.4.
#include <cvodes/cvodes.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_nonlinearsolver.h>

#include <string>
#include <vector>

#include "satgnc/propagation/trajectory.hpp"

namespace satgnc::propagation::detail {

/// Right-hand-side failure bookkeeping shared by CvodesPropagator and CvodesOde: written only when
/// an evaluation fails, read to explain a failed integration.
struct RhsFailure {
  bool failed = false;
  double t = 0.0;  ///< time of the last failed evaluation, s

  /// Record a failed evaluation at time `at` (s) and return 1, CVODES' "recoverable" right-hand-side
  /// flag: CVODES retries with a smaller step, then reports a failure. No allocation.
  int record(double at) noexcept {
    failed = true;
    t = at;
    return 1;
  }
  /// Append "; <what> failed at t = <t, %.17g><unit>" to message when a failure was recorded.
  void describe(std::string& message, const char* what, const char* unit) const;
};

/// x with 17 significant digits (printf %.17g: round-trips a double), for messages.
std::string format_g17(double x);

/// CVode() return flag -> PropagationStatus.
PropagationStatus cvodes_flag_status(int flag);

/// Integrator statistics of the current CVODES memory (lin_setups untouched).
void cvodes_read_stats(void* mem, PropagationStats& s);

/// Throw std::runtime_error("CVODES set-up failed in <what>: <cv_message>") when flag < 0.
void cvodes_check(int flag, const char* what, const std::string& cv_message);

/// CVODES error handler that stores the message in the std::string passed as user data (the core
/// never prints): CVodeSetErrHandlerFn(mem, &cvodes_store_message, &message).
void cvodes_store_message(int code, const char* module, const char* function, char* msg, void* message);

/// Time, gamma and predicted state of the current Newton system (for a matrix-embedded linear
/// solver that refreshes I - gamma J itself); false if CVODES cannot provide them.
bool cvodes_newton_point(void* mem, realtype& t, realtype& gamma, N_Vector& ypred);

/// Solve callback of a matrix-embedded linear solver (x = (I - gamma J)^-1 b computed by the owner).
using CvodesLsSolve = int (*)(SUNLinearSolver, SUNMatrix, N_Vector, N_Vector, realtype);

/// Attach the corrector to `mem`: fixed-point iteration, or Newton with a matrix-embedded linear
/// solver whose content is `content` and whose solve is `solve`. The created solvers are returned in
/// nls / ls (the caller frees them). Throws std::runtime_error on failure.
void cvodes_attach_corrector(void* mem, N_Vector y, SUNContext ctx, bool newton, void* content,
                             CvodesLsSolve solve, const std::string& cv_message, SUNNonlinearSolver& nls,
                             SUNLinearSolver& ls);

/// The SUNDIALS objects one integrator owns (context, CVODES memory, state and tolerance vectors,
/// nonlinear and linear solver), freed in reverse order of creation by the destructor. Not copyable.
struct CvodesHandles {
  SUNContext ctx = nullptr;
  void* mem = nullptr;
  N_Vector y = nullptr;
  N_Vector abstol = nullptr;
  SUNNonlinearSolver nls = nullptr;
  SUNLinearSolver ls = nullptr;

  CvodesHandles() = default;
  CvodesHandles(const CvodesHandles&) = delete;
  CvodesHandles& operator=(const CvodesHandles&) = delete;
  ~CvodesHandles();
};

/// What CvodesPropagator and CvodesOde tell cvodes_create (their settings, validated by the caller).
struct CvodesSetup {
  int n = 0;                   ///< state dimension
  bool adams = true;           ///< CV_ADAMS, else CV_BDF
  bool serial_vector = false;  ///< SUNDIALS' serial N_Vector instead of satgnc's (nvector.hpp)
  double y_first = 0.0;        ///< CVodeInit's state is [y_first, 0, ..., 0] (CVodeReInit sets the real one)
  CVRhsFn rhs = nullptr;       ///< right-hand side, called with user_data
  void* user_data = nullptr;   ///< CVODES user data, and the content of the matrix-embedded linear solver
  double rtol = 0.0;           ///< relative tolerance
  double atol = 0.0;           ///< scalar absolute tolerance (and the components beyond atol_components)
  const std::vector<double>* atol_components = nullptr;  ///< null or empty: scalar atol only
  int max_order = 0;                                     ///< 0: CVODES' default
  double max_step = 0.0;                                 ///< 0: unbounded
  bool newton = false;  ///< Newton corrector with ls_solve, else fixed-point iteration
  CvodesLsSolve ls_solve = nullptr;
};

/// The set-up sequence both integrators share: context, state vector, CVodeCreate, error handler
/// (messages into cv_message, which must outlive h.mem), CVodeInit, user data, tolerances, maximum
/// order and step, corrector (cvodes_attach_corrector). Fills h; throws std::runtime_error naming the
/// failing call (h frees whatever was created).
void cvodes_create(const CvodesSetup& s, CvodesHandles& h, std::string& cv_message);

/// Root function g (one component) of which only downward crossings count (an impact: the state
/// enters the region g <= 0), without inactive-root warnings. Throws like cvodes_check.
void cvodes_root_downward(void* mem, CVRootFn g, const std::string& cv_message);

}  // namespace satgnc::propagation::detail
