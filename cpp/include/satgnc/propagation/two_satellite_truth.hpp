#pragma once
/// @file two_satellite_truth.hpp
/// "Truth" flight of the two-satellite model (dynamics/two_satellite.hpp) under a piecewise-constant
/// control plan, integrated by satgnc's CVODES path (propagation/cvodes_ode.hpp: Adams with Newton on
/// the analytic 12x12 Jacobian). CVODES is re-initialised at every control-interval boundary (the
/// right-hand side jumps there) with a stop time at the boundary, so no step straddles a jump.
/// SI units: m, m/s, N, s; state as in two_satellite.hpp. The Earth's surface is the sphere of
/// radius params.j2_radius (the equatorial radius, 6378.1363 km): a body that reaches it ends the
/// flight with PropagationStatus::impact at the crossing time (CVODES root finding).
#include <Eigen/Core>
#include <memory>
#include <string>

#include "satgnc/dynamics/two_satellite.hpp"
#include "satgnc/propagation/cvodes_ode.hpp"

namespace satgnc::propagation {

/// CVODES settings suited to the 12-state in SI: rtol 1e-11, per-component atol 1e-6 m (positions)
/// and 1e-9 m/s (velocities).
propagation::CvodesOdeSettings default_truth_settings();

/// Result of TwoSatelliteTruth::fly.
struct TruthFlight {
  Eigen::MatrixXd X;  ///< 12 x (N+1) states at the interval boundaries, SI (only the reached ones valid)
  propagation::PropagationStatus status = propagation::PropagationStatus::success;
  int failed_interval = -1;  ///< interval k on which the integration failed (-1: none)
  std::string message;       ///< why it failed, naming the interval
  double t_reached = 0.0;    ///< s from the start: the end on success, the impact or failure time otherwise
  long steps = 0;            ///< CVODES steps over all intervals
  long rhs_evals = 0;        ///< right-hand-side evaluations over all intervals
};

/// CVODES truth propagator of the two-satellite model; allocate once, fly many plans.
class TwoSatelliteTruth {
 public:
  /// Validates the settings (std::invalid_argument naming the field).
  explicit TwoSatelliteTruth(const dynamics::TwoSatelliteModel& model,
                             const propagation::CvodesOdeSettings& settings = default_truth_settings());
  ~TwoSatelliteTruth();
  TwoSatelliteTruth(TwoSatelliteTruth&&) noexcept;
  TwoSatelliteTruth& operator=(TwoSatelliteTruth&&) noexcept;
  TwoSatelliteTruth(const TwoSatelliteTruth&) = delete;
  TwoSatelliteTruth& operator=(const TwoSatelliteTruth&) = delete;

  /// Propagate x (12, SI) over [0, dt] s with the constant force u (3, N): x is overwritten.
  /// Never throws; non-finite input or a model failure returns a status (message() says why); a body
  /// reaching the surface returns impact (x = the state there, integrator().t_reached() its time).
  propagation::PropagationStatus step(Eigen::Ref<Eigen::VectorXd> x,
                                      const Eigen::Ref<const Eigen::VectorXd>& u, double dt) noexcept;
  /// Fly the plan U (3 x N, N, piecewise constant over intervals of dt s) from x0 (12, SI).
  /// Throws std::invalid_argument on wrong shapes, dt <= 0, or a non-finite x0 or one with a body at
  /// or below the surface; failures (and an impact) are in the result.
  TruthFlight fly(const Eigen::Ref<const Eigen::VectorXd>& x0, const Eigen::Ref<const Eigen::MatrixXd>& U,
                  double dt);
  /// Message of the last step() failure (empty on success).
  const std::string& message() const;
  const propagation::CvodesOde& integrator() const;
  const dynamics::TwoSatelliteModel& model() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace satgnc::propagation
