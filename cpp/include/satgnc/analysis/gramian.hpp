#pragma once
/// @file gramian.hpp
/// Finite-horizon Gramians for models that are not asymptotically stable (every orbital model):
/// LTI by the Van Loan block exponential, LTV from state transition matrices, with condition number,
/// weakest direction and minimum-energy cost.
#include <Eigen/Core>
#include <vector>

namespace satgnc::analysis {

/// Matrix exponential by scaling and squaring with a Pade approximant (Eigen's MatrixFunctions).
Eigen::MatrixXd expm(const Eigen::MatrixXd& M);

/// A symmetric positive semidefinite Gramian and what it says.
struct GramianReport {
  Eigen::MatrixXd W;            ///< n x n Gramian (units: state^2 per input^2 s, or per output^2)
  Eigen::VectorXd eigenvalues;  ///< ascending
  double condition = 0.0;       ///< lambda_max / lambda_min (inf when lambda_min <= 0)
  Eigen::VectorXd weakest;      ///< unit eigenvector of lambda_min: hardest to reach / observe
  Eigen::VectorXd strongest;    ///< unit eigenvector of lambda_max
  /// Upper bound of the rounding error of the computed W (same units; LTI Gramians only, else 0):
  /// eigenvalues below it are not resolved. Unstable models over long horizons have a floor far
  /// above eps lambda_max (cancellation in Van Loan's product E22^T E12).
  double rounding_floor = 0.0;
  /// Every eigenvalue lies above rounding_floor (false: the small ones, and the condition, are noise).
  bool resolved = true;
};

/// Controllability Gramian W_c(T) = int_0^T e^{A t} B B^T e^{A^T t} dt, horizon T > 0 (s), via
/// Van Loan: expm(T [[-A, B B^T], [0, A^T]]) = [[F11, F12], [0, F22]], W_c = F22^T F12.
/// @throws std::invalid_argument naming T when e^{AT} overflows or the result has a negative
///   eigenvalue beyond its rounding floor (the horizon is too long for double precision).
GramianReport controllability_gramian(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double T);
/// Observability Gramian W_o(T) = int_0^T e^{A^T t} C^T C e^{A t} dt (same construction, dual).
GramianReport observability_gramian(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C, double T);

/// LTV observability Gramian from transition matrices Phi_j = Phi(t_j, t0) (n x n) and measurement
/// partials H_j (p_j x n): W = sum_j w_j Phi_j^T H_j^T H_j Phi_j (weights w_j >= 0, empty: all 1;
/// use w_j = 1/sigma_j^2 for the information matrix, or quadrature weights for the integral).
GramianReport ltv_observability_gramian(const std::vector<Eigen::MatrixXd>& stms,
                                        const std::vector<Eigen::MatrixXd>& H,
                                        const std::vector<double>& weights = {});

/// Eigen-analysis of a symmetric W (validated square, finite, symmetric to 1e-8 relative).
GramianReport analyze_gramian(const Eigen::MatrixXd& W);

/// Minimum control energy x_f^T W_c^+ x_f to reach x_f from 0 (or, for W_o, the inverse of the
/// output energy of x_f scaled by |x_f|^2). Uses the eigen-decomposition; inf when x_f has a component
/// along a zero eigenvalue (relative 1e-14 of lambda_max).
double minimum_energy(const GramianReport& g, const Eigen::VectorXd& x_f);

}  // namespace satgnc::analysis
