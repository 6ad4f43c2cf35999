#pragma once
/// @file cvodes_ode.hpp
/// Generic N-dimensional ODE integration with SUNDIALS CVODES (Adams or BDF), for systems that are
/// not a 6-state orbit: y' = f(t, y), f given as a callback, optionally with its Jacobian df/dy
/// (then Newton with a dense Eigen LU of I - gamma J in a matrix-embedded linear solver; without it,
/// fixed-point iteration). Same conventions as CvodesPropagator (cvodes.hpp): satgnc's own
/// N_Vector, everything allocated once by the constructor, each integrate() call re-initialises
/// CVODES (CVodeReInit) at t0 with a stop time at t1, so a right-hand side that is discontinuous at
/// the interval boundaries (piecewise-constant control) is never stepped across. Units: the caller's.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "satgnc/propagation/cvodes.hpp"
#include "satgnc/propagation/trajectory.hpp"

namespace satgnc::propagation {

/// Settings of CvodesOde (plain struct).
struct CvodesOdeSettings {
  CvodesMethod method = CvodesMethod::adams;
  double rtol = 1e-10;  ///< relative tolerance (> 0)
  double atol = 1e-10;  ///< scalar absolute tolerance (> 0), units of y
  /// Optional per-component absolute tolerances (empty or n entries, all > 0).
  std::vector<double> atol_components;
  long max_steps = 100000;  ///< step budget of one integrate() call (> 0)
  int max_order = 0;        ///< 0: method default; else 1..12 (Adams), 1..5 (BDF)
  double max_step = 0.0;    ///< |h| upper bound; 0 = unbounded
  /// Throw std::invalid_argument naming the field (n: system dimension).
  void validate(int n) const;
};

/// Integrator of y' = f(t, y) (dimension n) with CVODES; reuse it for many arcs.
class CvodesOde {
 public:
  /// f(t, y, ydot): write ydot (n entries); return false on failure (e.g. a body inside the Earth):
  /// CVODES retries with a smaller step and then reports rhs_failure.
  using Rhs = std::function<bool(double t, const double* y, double* ydot)>;
  /// J(t, y, jac): write df/dy (n x n, column-major); return false on failure.
  using Jacobian = std::function<bool(double t, const double* y, double* jac)>;

  /// Validate and allocate every CVODES resource (std::invalid_argument on n < 1, empty rhs, bad
  /// settings; std::runtime_error when SUNDIALS cannot allocate). With a Jacobian: Newton corrector.
  CvodesOde(int n, Rhs rhs, const CvodesOdeSettings& settings = {}, Jacobian jacobian = nullptr);
  ~CvodesOde();
  CvodesOde(CvodesOde&&) noexcept;
  CvodesOde& operator=(CvodesOde&&) noexcept;
  CvodesOde(const CvodesOde&) = delete;
  CvodesOde& operator=(const CvodesOde&) = delete;

  /// g(t, y): positive while the system is outside a forbidden region (e.g. |r|^2 - R^2 for a body
  /// above the Earth's surface). Must not throw.
  using ImpactFunction = std::function<double(double t, const double* y)>;
  /// Stop every later integrate() where g reaches 0 from above: status impact, t_reached = the
  /// crossing time (CVODES root finding), y = the state there. A start with g(t0, y0) <= 0 returns
  /// impact at t0 without stepping. Setup-time call (allocates the root-finding memory); an empty
  /// function is an std::invalid_argument.
  void set_impact_function(ImpactFunction g);

  /// Integrate y from t0 to t1 (t1 != t0, either direction; y has n entries, overwritten with y(t1)
  /// on success and with the last reached state on failure). Never throws: a non-finite t0, t1 or y,
  /// or t1 == t0, returns PropagationStatus::solver_failure with message() "invalid input: ...";
  /// integration failures return their status (rhs_failure when the callback failed). message() and
  /// stats() describe the call. Runs under SATGNC_NO_MALLOC_SCOPE (core/no_malloc.hpp): after the
  /// constructor, Eigen allocates nothing here, so the callbacks must not either in a guarded build
  /// (the guard sees Eigen only; CVODES's own malloc calls and the failure messages are not seen).
  PropagationStatus integrate(double t0, Eigen::Ref<Eigen::VectorXd> y, double t1) noexcept;

  int dim() const;
  const CvodesOdeSettings& settings() const;
  /// Statistics of the last integrate() call.
  const PropagationStats& stats() const;
  /// Why the last integrate() call failed (empty on success).
  const std::string& message() const;
  /// Time reached by the last integrate() call.
  double t_reached() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace satgnc::propagation
