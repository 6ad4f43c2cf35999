// UD form of the EKF: Bierman's scalar measurement update and Thornton's modified weighted
// Gram-Schmidt (MWGS) time update (Bierman, "Factorization Methods for Discrete Sequential
// Estimation", 1977, chapters V and VI). P = U D U', U unit upper triangular, D diagonal >= 0.
#include <cmath>

#include "detail/filter_workspace.hpp"

namespace satgnc::filter::detail {

// a (symmetric PSD, upper triangle read) = u diag(dd) u'; work is n x n scratch. Zero pivots (PSD
// but singular a, e.g. process noise on some components only) give d_j = 0 and a zero column.
void FilterWorkspace::ud_factor(const Eigen::MatrixXd& a, Eigen::MatrixXd& u, Eigen::VectorXd& dd,
                                Eigen::MatrixXd& work) noexcept {
  work = a;
  u.setIdentity();
  const double tiny = 1e-300;
  for (int j = n - 1; j >= 0; --j) {
    const double dj = work(j, j);
    if (dj > tiny) {
      dd(j) = dj;
      const double alpha = 1.0 / dj;
      for (int k = 0; k < j; ++k) {
        const double beta = work(k, j);
        u(k, j) = alpha * beta;
        for (int i = 0; i <= k; ++i) work(i, k) -= beta * u(i, j);
      }
    } else {
      dd(j) = 0.0;
      for (int k = 0; k < j; ++k) u(k, j) = 0.0;
    }
  }
}

FilterStatus FilterWorkspace::thornton() noexcept {
  // W = [Phi U, G], weights [D, Dq]; P+ = W diag(dw) W' = U+ D+ U+'.
  ud_factor(qd, G, dq, qc);
  W.leftCols(n).noalias() = phi * U;
  W.rightCols(n) = G;
  dw.head(n) = d;
  dw.tail(n) = dq;
  U.setIdentity();
  for (int j = n - 1; j >= 0; --j) {
    double sigma = 0.0;
    for (int k = 0; k < 2 * n; ++k) sigma += W(j, k) * W(j, k) * dw(k);
    d(j) = sigma;
    if (!(sigma > 0.0)) {
      d(j) = 0.0;  // lost rank: reported by the PD check
      continue;
    }
    for (int i = 0; i < j; ++i) {
      double s = 0.0;
      for (int k = 0; k < 2 * n; ++k) s += W(i, k) * dw(k) * W(j, k);
      const double uij = s / sigma;
      U(i, j) = uij;
      for (int k = 0; k < 2 * n; ++k) W(i, k) -= uij * W(j, k);
    }
  }
  if (!U.allFinite() || !d.allFinite()) return FilterStatus::covariance_not_pd;
  if (settings.check_covariance && !(d.minCoeff() > 0.0)) return FilterStatus::covariance_not_pd;
  return FilterStatus::success;
}

// Bierman scalar update with row j of H, variance rv and residual res.
FilterStatus FilterWorkspace::bierman(int j, double rv, double res) noexcept {
  f.noalias() = U.transpose() * H.row(j).transpose();
  v = d.cwiseProduct(f);
  double alpha = rv + v(0) * f(0);
  if (!(alpha > 0.0)) return FilterStatus::innovation_not_pd;
  d(0) *= rv / alpha;
  b.setZero();
  b(0) = v(0);
  for (int c = 1; c < n; ++c) {
    const double alpha_prev = alpha;
    alpha += f(c) * v(c);
    if (!(alpha > 0.0)) return FilterStatus::innovation_not_pd;
    const double lambda = -f(c) / alpha_prev;
    d(c) *= alpha_prev / alpha;
    for (int i = 0; i < c; ++i) {
      const double u_old = U(i, c);
      U(i, c) = u_old + b(i) * lambda;
      b(i) += v(c) * u_old;
    }
    b(c) = v(c);
  }
  x.noalias() += (res / alpha) * b;
  return FilterStatus::success;
}

}  // namespace satgnc::filter::detail
