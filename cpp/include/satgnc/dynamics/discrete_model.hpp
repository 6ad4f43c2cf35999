#pragma once
/// @file discrete_model.hpp
/// Discrete dynamics x_{k+1} = f_k(x_k, u_k) with Jacobians: the interface the nonlinear guidance
/// solvers (iLQR inside ADMM, sequential convex programming) are written against, and its linear
/// time-varying implementation. The two-satellite maps are in satgnc/propagation/two_satellite_map.hpp
/// and satgnc/propagation/propagated_map.hpp. Units are the implementation's (SI for the maps).
#include <Eigen/Core>
#include <vector>

namespace satgnc::dynamics {

/// Discrete dynamics with Jacobians. Implementations must not allocate in step() and must return
/// false (not NaN) when the step fails (model failure, non-finite result).
class DiscreteModel {
 public:
  virtual ~DiscreteModel() = default;
  /// State dimension nx.
  virtual int state_dim() const = 0;
  /// Control dimension nu.
  virtual int control_dim() const = 0;
  /// x_next = f_k(x, u) for interval k (0-based). When A and B are non-null they receive the
  /// Jacobians df/dx (nx x nx) and df/du (nx x nu), column-major. Pointers are to contiguous
  /// arrays of length nx, nu, nx, nx*nx, nx*nu.
  virtual bool step(int k, const double* x, const double* u, double* x_next, double* A, double* B) const = 0;
  /// Indices (0-based, ascending) of exogenous states t: their next value depends neither on the
  /// other states nor on the control (df_t/dx_c = 0 and df_t/du = 0 for every k; e.g. the target's
  /// orbit in the two-satellite model). Solvers may then skip the t-t block of the value function,
  /// which does not enter the gains. Default: none. Called at solver setup only (may allocate).
  virtual std::vector<int> exogenous_states() const { return {}; }
};

/// x_{k+1} = A_k x_k + B_k u_k + c_k. A single (A, B, c) is used for every k when one is given.
class LinearDiscreteModel final : public DiscreteModel {
 public:
  /// Throws std::invalid_argument on inconsistent or non-finite data.
  LinearDiscreteModel(std::vector<Eigen::MatrixXd> A, std::vector<Eigen::MatrixXd> B,
                      std::vector<Eigen::VectorXd> c);
  int state_dim() const override { return nx_; }
  int control_dim() const override { return nu_; }
  bool step(int k, const double* x, const double* u, double* x_next, double* A, double* B) const override;
  /// Number of intervals the model was given data for (1 = time-invariant).
  int intervals() const { return static_cast<int>(A_.size()); }
  /// Overwrite interval k's data in place (no allocation; sizes must match, c only if the model
  /// was built with c). Returns false on a size mismatch or a bad k.
  bool set(int k, const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& B,
           const Eigen::Ref<const Eigen::VectorXd>& c);

 private:
  std::vector<Eigen::MatrixXd> A_, B_;
  std::vector<Eigen::VectorXd> c_;
  int nx_ = 0, nu_ = 0;
};

}  // namespace satgnc::dynamics
