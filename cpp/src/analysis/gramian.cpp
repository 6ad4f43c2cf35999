#include "satgnc/analysis/gramian.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>

#include "satgnc/core/validate.hpp"

namespace satgnc::analysis {

using Eigen::MatrixXd;
using Eigen::VectorXd;

MatrixXd expm(const MatrixXd& M) {
  core::require(M.rows() == M.cols(), "M", "must be square");
  core::require_finite(M, "M");
  return M.exp();
}

GramianReport analyze_gramian(const MatrixXd& W_in) {
  core::require(W_in.rows() > 0 && W_in.rows() == W_in.cols(), "W", "must be square and non-empty");
  core::require_finite(W_in, "W");
  const double scale = std::max(W_in.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  core::require((W_in - W_in.transpose()).cwiseAbs().maxCoeff() <= 1e-8 * scale, "W", "must be symmetric");
  GramianReport g;
  g.W = 0.5 * (W_in + W_in.transpose());
  Eigen::SelfAdjointEigenSolver<MatrixXd> es(g.W);
  g.eigenvalues = es.eigenvalues();
  const Eigen::Index n = g.W.rows();
  g.weakest = es.eigenvectors().col(0);
  g.strongest = es.eigenvectors().col(n - 1);
  const double lmin = g.eigenvalues(0), lmax = g.eigenvalues(n - 1);
  g.condition = lmin > 0.0 ? lmax / lmin : std::numeric_limits<double>::infinity();
  return g;
}

namespace {
void check_lti(const MatrixXd& A, const MatrixXd& X, bool ctrb, double T) {
  core::require(A.rows() > 0 && A.rows() == A.cols(), "A", "must be square and non-empty");
  core::require_finite(A, "A");
  if (ctrb) {
    core::require(X.rows() == A.rows() && X.cols() > 0, "B", "must be n x m with m >= 1");
    core::require_finite(X, "B");
  } else {
    core::require(X.cols() == A.rows() && X.rows() > 0, "C", "must be p x n with p >= 1");
    core::require_finite(X, "C");
  }
  core::require_positive(T, "T");
}

// Van Loan (1978): for M = [[-F, Q], [0, F^T]] T, expm(M) = [[., E12], [0, E22]] and
// int_0^T e^{F^T s} Q e^{F s} ds = E22^T E12 — with F = A^T, Q = B B^T for W_c and F = A, Q = C^T C
// for W_o.
MatrixXd van_loan(const MatrixXd& F, const MatrixXd& Q, double T, double& floor) {
  const Eigen::Index n = F.rows();
  const double eps = std::numeric_limits<double>::epsilon();
  // Van Loan only over a short t = T / 2^k (|F| t <= 1/2): over T itself e^{-F T} is huge for a
  // stable F with fast modes and E22^T E12 cancelled to garbage (a Hurwitz 5x5 A, T = 6.5 s: lambda
  // = -1.6e17). Then doubling, W(2t) = W(t) + e^{F^T t} W(t) e^{F t}: sums of PSD terms, no cancellation.
  const double fn = F.lpNorm<Eigen::Infinity>() * T;
  int k = 0;
  while (k < 60 && std::ldexp(fn, -k) > 0.5) ++k;
  const double t = std::ldexp(T, -k);
  MatrixXd M = MatrixXd::Zero(2 * n, 2 * n);
  M.topLeftCorner(n, n) = -F.transpose();
  M.topRightCorner(n, n) = Q;
  M.bottomRightCorner(n, n) = F;
  const MatrixXd E = (M * t).exp();
  // Error of the product E22^T E12 ~ n eps |E22| |E12| (plus the exponential's own, of that order).
  floor =
      4.0 * static_cast<double>(n) * eps * E.bottomRightCorner(n, n).norm() * E.topRightCorner(n, n).norm();
  MatrixXd W = E.bottomRightCorner(n, n).transpose() * E.topRightCorner(n, n);
  MatrixXd Et = E.bottomRightCorner(n, n);  // e^{F t}
  for (int j = 0; j < k; ++j) {
    const double e2 = Et.squaredNorm();
    W += Et.transpose() * W * Et;
    // Propagated floor plus the rounding of this product and sum; for an unstable F it grows like W.
    floor = floor * (1.0 + e2) + 4.0 * static_cast<double>(n) * eps * (W.norm() + e2 * W.norm());
    Et = Et * Et;
  }
  return W;
}

// Van Loan over a long horizon of an unstable A: e^{AT} overflows, or the product E22^T E12 cancels
// and the small eigenvalues are rounding (the "PSD" Gramian with lambda = -5e53). Overflow and
// a negative eigenvalue beyond the rounding floor are errors naming T; otherwise the report carries
// the floor and says whether every eigenvalue is above it (resolved).
GramianReport checked_lti_gramian(const MatrixXd& W, double floor, double T) {
  core::require(W.allFinite() && std::isfinite(floor), "T",
                "too long for this A: e^{A T} overflows double precision (T = " + std::to_string(T) + " s)",
                "shorten T, or nondimensionalize the model");
  GramianReport g = analyze_gramian(0.5 * (W + W.transpose()));
  const Eigen::Index n = g.eigenvalues.size();
  g.rounding_floor = floor;
  if (g.eigenvalues(0) < -floor) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "lambda_min = %.3g < -%.3g (its rounding floor), lambda_max = %.3g",
                  g.eigenvalues(0), floor, g.eigenvalues(n - 1));
    core::require(false, "T",
                  "too long for this A: the Gramian lost positive semidefiniteness (" + std::string(buf) +
                      ", T = " + std::to_string(T) + " s)",
                  "shorten T, or nondimensionalize the model");
  }
  g.resolved = g.eigenvalues(0) > floor;
  return g;
}
}  // namespace

GramianReport controllability_gramian(const MatrixXd& A, const MatrixXd& B, double T) {
  check_lti(A, B, true, T);
  double floor = 0.0;
  const MatrixXd W = van_loan(A.transpose(), B * B.transpose(), T, floor);
  return checked_lti_gramian(W, floor, T);
}

GramianReport observability_gramian(const MatrixXd& A, const MatrixXd& C, double T) {
  check_lti(A, C, false, T);
  double floor = 0.0;
  const MatrixXd W = van_loan(A, C.transpose() * C, T, floor);
  return checked_lti_gramian(W, floor, T);
}

GramianReport ltv_observability_gramian(const std::vector<MatrixXd>& stms, const std::vector<MatrixXd>& H,
                                        const std::vector<double>& weights) {
  core::require(!stms.empty(), "stms", "needs at least one transition matrix");
  core::require(
      H.size() == stms.size(), "H",
      "needs one partial per STM (" + std::to_string(stms.size()) + "), got " + std::to_string(H.size()));
  core::require(weights.empty() || weights.size() == stms.size(), "weights", "must be empty or one per STM");
  const Eigen::Index n = stms.front().rows();
  core::require(n > 0, "stms", "must be non-empty square matrices");
  MatrixXd W = MatrixXd::Zero(n, n);
  for (size_t j = 0; j < stms.size(); ++j) {
    core::require(stms[j].rows() == n && stms[j].cols() == n, "stms",
                  "entry " + std::to_string(j) + " must be " + std::to_string(n) + "x" + std::to_string(n));
    core::require(H[j].cols() == n, "H", "entry " + std::to_string(j) + " must have n columns");
    core::require_finite(stms[j], "stms");
    core::require_finite(H[j], "H");
    const double w = weights.empty() ? 1.0 : weights[j];
    core::require_nonnegative(w, "weights");
    const MatrixXd HP = H[j] * stms[j];
    W.noalias() += w * HP.transpose() * HP;
  }
  return analyze_gramian(W);
}

double minimum_energy(const GramianReport& g, const VectorXd& x_f) {
  core::require(x_f.size() == g.W.rows(), "x_f", "must have n entries");
  core::require_finite(x_f, "x_f");
  Eigen::SelfAdjointEigenSolver<MatrixXd> es(g.W);
  const VectorXd c = es.eigenvectors().transpose() * x_f;
  const double lmax = es.eigenvalues().maxCoeff();
  double e = 0.0;
  for (Eigen::Index i = 0; i < c.size(); ++i) {
    const double l = es.eigenvalues()(i);
    if (l <= 1e-14 * lmax) {
      if (std::abs(c(i)) > 1e-12 * x_f.norm()) return std::numeric_limits<double>::infinity();
      continue;
    }
    e += c(i) * c(i) / l;
  }
  return e;
}

}  // namespace satgnc::analysis
