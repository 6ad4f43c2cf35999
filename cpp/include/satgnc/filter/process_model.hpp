#pragma once
/// @file process_model.hpp
/// The process model a filter of this room propagates with: the state, its transition matrix and
/// the discrete process noise over [t0, t1]. Generic over the state size n (set at setup); the
/// filter knows nothing of orbits (the orbit layer, filter/orbit_*, implements this interface with
/// satgnc's STM propagators and state-noise / dynamic-model compensation).
///
/// Units: times in s (any fixed origin the caller chooses, e.g. s past a reference Epoch); the
/// state's units are the model's (the orbit layer uses km, km/s).
#include <Eigen/Core>

#include "satgnc/filter/status.hpp"

namespace satgnc::filter {

/// Abstract process model x(t1) = f(x(t0), t0, t1), Phi = dx(t1)/dx(t0), Qd = discrete process noise.
///
/// Contract for implementers: `propagate` is noexcept and allocation-free after the model's own
/// setup (the filter calls it inside its no-allocation scope); every output is written in place
/// into storage the filter sized at setup (x1: n, Phi and Qd: n x n). Qd must be symmetric
/// positive semidefinite (the filter reports `process_failed` when a diagonal entry is negative or
/// any output is non-finite). The filter never calls it with t1 == t0 (it uses Phi = I, Qd = 0).
class ProcessModel {
 public:
  virtual ~ProcessModel() = default;
  /// State dimension n (> 0); constant for the model's lifetime.
  virtual int state_dimension() const noexcept = 0;
  /// Propagate x0 from t0 to t1 (s; t1 > t0 in a filter run).
  /// @param x0 state at t0 (n)
  /// @param t0 start time, s
  /// @param t1 end time, s
  /// @param x1 out: state at t1 (n)
  /// @param phi out: state transition matrix dx1/dx0 (n x n); may be left unset when with_jacobian is false
  /// @param qd out: discrete process noise over [t0, t1] (n x n, symmetric PSD; always set)
  /// @param with_jacobian false when only x1 and qd are needed (UKF sigma points)
  /// @return ModelStatus::success, or failed (outputs then undefined)
  virtual ModelStatus propagate(const Eigen::Ref<const Eigen::VectorXd>& x0, double t0, double t1,
                                Eigen::Ref<Eigen::VectorXd> x1, Eigen::Ref<Eigen::MatrixXd> phi,
                                Eigen::Ref<Eigen::MatrixXd> qd, bool with_jacobian) noexcept = 0;
};

}  // namespace satgnc::filter
