#pragma once
/// @file cvodes.hpp
/// Orbit propagation with SUNDIALS CVODES (Adams or BDF), state plus the 6x6 state transition
/// matrix (STM) through the variational equations dPhi/dt = A(x) Phi, A = [[0, I], [da/dr, da/dv]].
/// Units: km, km/s, s.
///
/// Settings / workspace / result: the CVODES memory, vectors and solvers are created once by the
/// CvodesPropagator constructor for one ForceModel and reused by every propagate() call, which only
/// re-initialises them (CVodeReInit). The core never prints; failures come back as a status.
#include <memory>
#include <vector>

#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/propagation/trajectory.hpp"

namespace satgnc::propagation {

/// Linear multistep family.
enum class CvodesMethod {
  /// Adams-Moulton, orders 1..12: CVODES's choice for non-stiff orbits (5-15x cheaper than BDF there).
  /// Not satgnc's default: on a LEO day DOP853 (dop853.hpp) is 5-8x faster at every accuracy and
  /// meets 1 mm per day where Adams meets it at no tolerance (docs/propagation.md "Defaults").
  adams,
  bdf,  ///< backward differentiation formulas, orders 1..5 (stiff problems, e.g. re-entry drag)
};

/// Corrector (nonlinear solver) of the implicit multistep formula.
enum class CvodesCorrector {
  /// Newton for both methods. Measured on a 2 h J2 LEO arc with STM at rtol 1e-10: Adams + Newton
  /// takes 156 steps / 201 f-evaluations against 336 / 469 with fixed point, and is more accurate
  /// per unit of work (docs/propagation.md).
  automatic,
  fixed_point,  ///< functional iteration, no Jacobian
  newton,       ///< Newton with satgnc's block-diagonal linear solver (analytic 6x6 Jacobian)
};

/// Which N_Vector implementation carries the state inside CVODES.
enum class CvodesVector {
  satgnc,           ///< satgnc's own serial N_Vector (compiled with our flags; default)
  sundials_serial,  ///< SUNDIALS' NVECTOR_SERIAL from the linked libsundials (reference)
};

/// Tolerances and options. The defaults (rtol 1e-10, atol 1e-12, kept for the OD and paper numbers
/// that use them) are off by ~0.3 m per LEO day with the STM, ~0.15 m without (measured,
/// docs/propagation.md "Defaults"); satgnc's default propagator is DOP853 at kDefaultOrbitRtol.
struct CvodesSettings {
  CvodesMethod method = CvodesMethod::adams;
  CvodesCorrector corrector = CvodesCorrector::automatic;
  CvodesVector vector = CvodesVector::satgnc;
  double rtol = 1e-10;  ///< relative tolerance, in (0, 1)
  double atol = 1e-12;  ///< scalar absolute tolerance, km and km/s (STM entries: dimensionless mix)
  /// Optional per-component absolute tolerances: empty (use atol), 6 values (state; the STM entries
  /// keep atol) or 42 values (state then the STM column by column). All > 0.
  std::vector<double> atol_components;
  long max_steps = 500000;    ///< total step budget of one propagate() call (> 0)
  int max_order = 0;          ///< 0: method default (Adams 12, BDF 5); else 1..12 (Adams), 1..5 (BDF)
  bool with_stm = true;       ///< integrate the 36 variational equations as well
  double initial_step = 0.0;  ///< |h0| in s; 0 lets CVODES estimate it
  double max_step = 0.0;      ///< |h| upper bound in s; 0 means unbounded
  /// Radius of the body's surface, km (>= 0; e.g. 6378.1363 for the Earth). With R > 0, x0 must lie
  /// above it (|r0| > R) and an arc that reaches |r| = R stops with PropagationStatus::impact,
  /// t_reached = the impact time (CVODES root finding on |r|^2 - R^2, downward crossings, located
  /// to the solver's roundoff), holding the outputs before it. 0: no surface (only r = 0 is singular).
  double surface_radius = 0.0;

  /// Throw std::invalid_argument naming the field on any invalid value.
  void validate() const;
};

/// CVODES propagator bound to one force model; reuse it for many arcs.
class CvodesPropagator {
 public:
  /// Validate model and settings and allocate every CVODES resource (throws std::invalid_argument,
  /// or std::runtime_error when SUNDIALS cannot allocate).
  explicit CvodesPropagator(const dynamics::ForceModel& model, const CvodesSettings& settings = {});
  ~CvodesPropagator();
  CvodesPropagator(CvodesPropagator&&) noexcept;
  CvodesPropagator& operator=(CvodesPropagator&&) noexcept;
  CvodesPropagator(const CvodesPropagator&) = delete;
  CvodesPropagator& operator=(const CvodesPropagator&) = delete;

  /// Propagate x0 = [r km, v km/s] given at t0 (s) to every time in `times` (s). Times must be
  /// finite, strictly monotone in one direction and on one side of t0 (forward or backward); a
  /// time equal to t0 returns x0 and the identity. Throws std::invalid_argument on bad input (x0
  /// non-finite, |r| = 0 or |r| <= settings.surface_radius, bad times); integration failures and an
  /// impact return a Trajectory whose status is not success, holding the outputs reached, t_reached
  /// and a message saying why.
  Trajectory propagate(const Vec6& x0, double t0, const std::vector<double>& times);

  /// Same, writing into `out` (whose vectors keep their capacity across calls): allocation-free
  /// once `out` has the capacity (test_cvodes.cpp counts operator new), and run under
  /// SATGNC_NO_MALLOC_SCOPE (core/no_malloc.hpp; it sees Eigen only, not CVODES's malloc calls).
  void propagate(const Vec6& x0, double t0, const std::vector<double>& times, Trajectory& out);

  const dynamics::ForceModel& model() const;
  const CvodesSettings& settings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot convenience: build a CvodesPropagator and propagate once.
Trajectory propagate_cvodes(const dynamics::ForceModel& model, const Vec6& x0, double t0,
                            const std::vector<double>& times, const CvodesSettings& settings = {});

/// Throw std::invalid_argument unless x0 is finite with |r| > 0 and times are finite, non-empty,
/// strictly monotone and on one side of t0: validate_orbit_arc_input with kOneSidedArc (CVODES's
/// rules), kept for existing callers.
inline void validate_propagation_input(const Vec6& x0, double t0, const std::vector<double>& times) {
  validate_orbit_arc_input(x0, t0, times, kOneSidedArc, kGravitySingular);
}

}  // namespace satgnc::propagation
