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
///
/// A UD run (FilterResult::ud_factors stored) is smoothed on its factors, never forming or inverting
/// P_k+1|k: C_k' = U_p^-T D_p^-1 U_p^-1 Phi P_k|k by two unit-triangular substitutions, and
///   P_k|N = (I - C_k Phi) P_k|k (I - C_k Phi)' + C_k (Qd + P_k+1|N) C_k'
/// (equal to the form above for the optimal C_k, and a sum of PSD terms for any C_k) is factored
/// U D U' directly by the modified weighted Gram-Schmidt of the n x 3n array
/// [(I - C_k Phi) U_k|k, C_k U_Q, C_k U_k+1|N] with weights [D_k|k, D_Q, D_k+1|N]: D >= 0 by
/// construction. A zero D_p (singular prediction) is status covariance_not_pd at that step.
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
  bool factored = false;                         ///< true: smoothed on the run's UD factors
  /// Factored runs: smoothed U D U' packed per block like FilterResult::ud_factors (n x n N).
  Eigen::MatrixXd ud_factors;
  Eigen::MatrixXd initial_ud_factors;  ///< factored runs: smoothed factors at t0, packed (n x n)
};

/// RTS smoother sized at setup for n states and N steps; smooth() is noexcept and allocation-free.
class RtsSmoother {
 public:
  /// Size for n states and steps records (n >= 1, steps >= 0). Throws std::invalid_argument.
  RtsSmoother(int n, int steps);
  /// Smooth a run. The run must have the sizes given at setup and smoother data
  /// (status covariance_not_pd with failed_step = -2 otherwise). A run with UD factors is smoothed
  /// on them (see the file comment) unless `use_factors` is false. noexcept; no heap allocation.
  const SmootherResult& smooth(const FilterResult& run, bool use_factors = true) noexcept;
  /// The last result.
  const SmootherResult& result() const noexcept { return result_; }

 private:
  const SmootherResult& smooth_factored(const FilterResult& run) noexcept;

  SmootherResult result_;
  Eigen::MatrixXd gain_, tmp_, tmp2_, dp_;
  Eigen::MatrixXd us_, w_;  // factored: smoothed factors of step k+1 (packed), n x 3n MWGS array
  Eigen::VectorXd dw_;      // factored: 3n MWGS weights
  Eigen::VectorXd dx_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace satgnc::filter
