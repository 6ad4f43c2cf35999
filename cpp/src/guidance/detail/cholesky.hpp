#pragma once
// Private to the guidance room (not installed): the small in-place Cholesky factorization and solve
// used by the iLQR backward passes, one code for the dynamic-size and the fixed-size (NU) paths.
// Plain loops: Eigen's LLT solve with a multi-column right-hand side takes its blocked path, and the
// loops keep one operation order on both paths. No allocation.
#include <Eigen/Core>
#include <cmath>

namespace satgnc::guidance::detail {

/// Cholesky M = L L^T in place (the lower triangle of M is overwritten with L; the strict upper
/// triangle is not read). N is the compile-time size or Eigen::Dynamic (then M.rows()). Returns false
/// if M is not (numerically) positive definite.
template <int N, typename Mat>
inline bool cholesky_factor_inplace(Mat& M) {
  const int n = N == Eigen::Dynamic ? static_cast<int>(M.rows()) : N;
  for (int j = 0; j < n; ++j) {
    double diag = M(j, j);
    for (int p = 0; p < j; ++p) diag -= M(j, p) * M(j, p);
    if (!(diag > 0.0) || !std::isfinite(diag)) return false;
    const double ljj = std::sqrt(diag);
    M(j, j) = ljj;
    for (int i = j + 1; i < n; ++i) {
      double v = M(i, j);
      for (int p = 0; p < j; ++p) v -= M(i, p) * M(j, p);
      M(i, j) = v / ljj;
    }
  }
  return true;
}

/// Solve L L^T X = B in place, column by column (B is n x m; L from cholesky_factor_inplace).
template <int N, typename Mat, typename Rhs>
inline void cholesky_solve_inplace(const Mat& L, Rhs& B) {
  const int n = N == Eigen::Dynamic ? static_cast<int>(L.rows()) : N;
  for (int c = 0; c < B.cols(); ++c) {
    for (int i = 0; i < n; ++i) {
      double v = B(i, c);
      for (int p = 0; p < i; ++p) v -= L(i, p) * B(p, c);
      B(i, c) = v / L(i, i);
    }
    for (int i = n - 1; i >= 0; --i) {
      double v = B(i, c);
      for (int p = i + 1; p < n; ++p) v -= L(p, i) * B(p, c);
      B(i, c) = v / L(i, i);
    }
  }
}

}  // namespace satgnc::guidance::detail
