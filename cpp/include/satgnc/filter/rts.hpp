#pragma once
/// @file rts.hpp
/// Fixed-interval Rauch-Tung-Striebel smoother over a stored filter run (FilterResult with
/// store_smoother_data; any EKF form: the UD run stores its full covariances U D U').
///
///   C_k = P_k|k Phi_k+1' P_k+1|k^-1,  x_k|N = x_k|k + C_k (x_k+1|N - x_k+1|k),
///   P_k|N = P_k|k + C_k (P_k+1|N - P_k+1|k) C_k',
/// run from the last step back to the initial epoch t0 (the smoothed initial state is reported too).
/// The consider parameters of the run (FilterResult::consider) keep their filtered values: their
/// rows of C_k are zero (as in the Schmidt-Kalman update).
/// Rejected and failed steps carry their predicted values as "updated" ones, so they smooth through.
#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "satgnc/filter/kalman_filter.hpp"

namespace satgnc::filter {

/// Smoothed run, time-major like FilterResult.
struct SmootherResult {
  int n = 0;                                     ///< state dimension
  int steps = 0;                                 ///< N
  Eigen::VectorXd initial_state;                 ///< smoothed state at t0 (n)
  Eigen::MatrixXd initial_covariance;            ///< smoothed covariance at t0 (n x n)
  Eigen::MatrixXd states;                        ///< n x N smoothed states
  Eigen::MatrixXd covariances;                   ///< n x (n N) smoothed covariances (block k)
  FilterStatus status = FilterStatus::unsolved;  ///< success, or covariance_not_pd (a P_k+1|k not PD)
  int failed_step = -1;                          ///< step whose predicted covariance failed (-1: none)
};

/// RTS smoother sized at setup for n states and N steps; smooth() is noexcept and allocation-free.
class RtsSmoother {
 public:
  /// Size for n states and steps records (n >= 1, steps >= 0). Throws std::invalid_argument.
  RtsSmoother(int n, int steps);
  /// Smooth a run. The run must have the sizes given at setup and smoother data
  /// (status covariance_not_pd with failed_step = -2 otherwise). noexcept; no heap allocation.
  const SmootherResult& smooth(const FilterResult& run) noexcept;
  /// The last result.
  const SmootherResult& result() const noexcept { return result_; }

 private:
  SmootherResult result_;
  Eigen::MatrixXd gain_, tmp_, tmp2_, dp_;
  Eigen::VectorXd dx_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace satgnc::filter
