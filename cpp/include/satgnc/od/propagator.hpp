#pragma once
/// @file propagator.hpp
/// The small propagation interface the OD solvers run on: fill states and STMs at given times.
#include <memory>
#include <vector>

#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/propagation/cvodes.hpp"
#include "satgnc/propagation/trajectory.hpp"

namespace satgnc::od {

/// States and state transition matrices of one arc from x0 at t = 0.
class StmPropagator {
 public:
  virtual ~StmPropagator() = default;
  /// Propagate x0 = [r km, v km/s] given at t = 0 to the n ascending times (s; times[0] may be 0 or
  /// negative), writing states[i] and stms[i] = d x(times[i]) / d x0. Return false on failure.
  /// Implementations used inside OdSolver::solve() must not allocate with Eigen (its
  /// SATGNC_NO_MALLOC_SCOPE covers this call in guarded builds); an exception thrown here ends the
  /// evaluation as OdStatus::propagation_failed.
  virtual bool propagate(const Vec6& x0, const double* times, int n, Vec6* states, Mat6* stms) = 0;
  /// Setup hook: size any internal buffer for calls with up to max_times output times, so that
  /// propagate() allocates nothing afterwards. Solvers call it once at setup (BatchEstimator's
  /// constructor); the default does nothing.
  virtual void reserve(int max_times) { static_cast<void>(max_times); }
};

/// Two-body propagation with the exact STM (universal-variable Kepler step of satgnc::propagation).
class KeplerStmPropagator final : public StmPropagator {
 public:
  /// mu in km^3/s^2 (> 0).
  explicit KeplerStmPropagator(double mu);
  bool propagate(const Vec6& x0, const double* times, int n, Vec6* states, Mat6* stms) override;
  double mu() const { return mu_; }

 private:
  double mu_;
};

/// Numerical propagation with the CVODES propagator of satgnc::propagation (J2, drag, ...). The
/// ascending times may lie on both sides of the epoch: times < 0 run as a backward arc from t = 0,
/// the others as a forward arc (each arc re-initialises the same CVODES memory). After
/// reserve(max_times), propagate() allocates nothing for calls with up to max_times times (CVODES
/// itself allocates only in the constructor; test_od_batch.cpp counts 0 mallocs in a BatchEstimator's
/// first solve()); a call with more times grows the buffers once.
class CvodesStmPropagator final : public StmPropagator {
 public:
  /// The model and settings are validated and copied (std::invalid_argument naming the field);
  /// settings.with_stm is forced to true.
  explicit CvodesStmPropagator(const dynamics::ForceModel& model,
                               const propagation::CvodesSettings& settings = {});
  bool propagate(const Vec6& x0, const double* times, int n, Vec6* states, Mat6* stms) override;
  /// Size the time lists and both arcs' output trajectories for up to max_times (>= 0) times.
  void reserve(int max_times) override;

 private:
  propagation::CvodesPropagator prop_;
  std::vector<double> t_;        // forward arc: times >= 0, ascending
  std::vector<double> t_back_;   // backward arc: times < 0, descending
  propagation::Trajectory out_;  // forward arc
  propagation::Trajectory out_back_;
};

/// The paper's short-arc approximation, eq. (19): states from the wrapped propagator, but the STM
/// replaced by [[I, t I], [0, I]]. Kept to show that Newton with this STM does not converge.
class ShortArcStmPropagator final : public StmPropagator {
 public:
  explicit ShortArcStmPropagator(std::shared_ptr<StmPropagator> inner);
  bool propagate(const Vec6& x0, const double* times, int n, Vec6* states, Mat6* stms) override;

 private:
  std::shared_ptr<StmPropagator> inner_;
};

}  // namespace satgnc::od
