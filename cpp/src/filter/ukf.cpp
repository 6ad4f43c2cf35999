// UKF of filter::KalmanFilter: Wan & van der Merwe scaled sigma points (2n + 1 points, weights
// from alpha, beta, kappa), additive process and measurement noise. The process noise Qd is the
// one of the propagated mean sigma point (point 0, the prior mean), which also gives the
// transition matrix stored for the smoother.
#include <cmath>

#include "detail/filter_workspace.hpp"

namespace satgnc::filter::detail {

namespace {
// Mean and covariance of the columns of pts (deviations from column 0 first, which keeps the
// large weights of a small alpha from cancelling digits). Writes mean, cov = sum wc (p - mean)(p - mean)'.
template <class Pts, class Mean, class Cov, class Dev>
void weighted_moments(const Pts& pts, const Eigen::VectorXd& wm, const Eigen::VectorXd& wc, Mean& mean,
                      Cov& cov, Dev& dev) noexcept {
  const Eigen::Index np = pts.cols();
  mean = pts.col(0);
  for (Eigen::Index i = 1; i < np; ++i) mean += wm(i) * (pts.col(i) - pts.col(0));
  cov.setZero();
  for (Eigen::Index i = 0; i < np; ++i) {
    dev = pts.col(i) - mean;
    for (Eigen::Index c = 0; c < dev.size(); ++c) cov.col(c) += (wc(i) * dev(c)) * dev;
  }
}
}  // namespace

FilterStatus FilterWorkspace::ukf_predict(double t1) noexcept {
  if (!P.allFinite()) return FilterStatus::covariance_not_pd;
  llt.compute(P);
  if (llt.info() != Eigen::Success) return FilterStatus::covariance_not_pd;
  const int np = 2 * n + 1;
  X.col(0) = x;
  // sigma points x +- c L_i from the stored factor (lower triangle of matrixLLT(); no copy)
  for (int i = 0; i < n; ++i) {
    for (int row = 0; row < n; ++row) {
      const double l = row >= i ? llt.matrixLLT()(row, i) : 0.0;
      X(row, 1 + i) = x(row) + ukf_c * l;
      X(row, 1 + n + i) = x(row) - ukf_c * l;
    }
  }
  ModelStatus ms = process->propagate(X.col(0), t, t1, x1, phi, qd, true);
  if (ms != ModelStatus::success || !x1.allFinite() || !phi.allFinite() || !qd.allFinite()) {
    return FilterStatus::process_failed;
  }
  for (int i = 0; i < n; ++i) {
    if (qd(i, i) < 0.0) return FilterStatus::process_failed;
  }
  Xp.col(0) = x1;
  for (int i = 1; i < np; ++i) {
    ms = process->propagate(X.col(i), t, t1, x1, T, T2, false);
    if (ms != ModelStatus::success || !x1.allFinite()) return FilterStatus::process_failed;
    Xp.col(i) = x1;
  }
  weighted_moments(Xp, wm, wc, x, P, xn);
  P += qd;
  symmetrize();
  t = t1;
  last_phi = phi;
  return covariance_pd() ? FilterStatus::success : FilterStatus::covariance_not_pd;
}

FilterStatus FilterWorkspace::ukf_update(const MeasurementRecord& rec, int m, StepRecord& out) noexcept {
  out.iterations = 1;
  llt.compute(P);
  if (llt.info() != Eigen::Success) return FilterStatus::covariance_not_pd;
  const int np = 2 * n + 1;
  for (int i = 0; i < n; ++i) {
    for (int row = 0; row < n; ++row) {
      const double l = row >= i ? llt.matrixLLT()(row, i) : 0.0;
      X(row, 1 + i) = x(row) + ukf_c * l;
      X(row, 1 + n + i) = x(row) - ukf_c * l;
    }
  }
  X.col(0) = x;
  for (int i = 0; i < np; ++i) {
    const ModelStatus ms = measurement->measure(X.col(i), rec, z.head(m), H.topRows(m), false);
    if (ms != ModelStatus::success || !z.head(m).allFinite()) return FilterStatus::measurement_failed;
    Z.col(i).head(m) = z.head(m);
  }
  auto Zm = Z.topRows(m);
  // predicted measurement mean (in y), S, Pxz
  SmallVec zbar = Zm.col(0);
  for (int i = 1; i < np; ++i) zbar += wm(i) * (Zm.col(i) - Zm.col(0));
  S.setZero(m, m);
  PHt.leftCols(m).setZero();
  SmallVec dz(m);
  for (int i = 0; i < np; ++i) {
    dz = Zm.col(i) - zbar;
    xn = X.col(i) - x;
    S.noalias() += (wc(i) * dz) * dz.transpose();
    for (int c = 0; c < m; ++c) PHt.col(c) += (wc(i) * dz(c)) * xn;
  }
  for (int i = 0; i < m; ++i) {
    const auto iu = static_cast<std::size_t>(i);
    r(i) = rec.sigma[iu] * rec.sigma[iu];
    S(i, i) += r(i);
    y(i) = rec.value[iu] - zbar(i);
  }
  const FilterStatus is = innovation_statistics(m, out);
  if (is != FilterStatus::success) return is;
  out.flag = gate_decision(rec, m, out);
  if (out.flag == EditFlag::rejected) return FilterStatus::rejected;
  // K = Pxz S^-1; x += K y; P -= K S K'
  Sinv.setIdentity(m, m);
  sllt.solveInPlace(Sinv);
  K.leftCols(m).noalias() = PHt.leftCols(m) * Sinv;
  if (has_consider) {
    // Consider rows of K zeroed: the general form P - K Pxz' - Pxz K' + K S K', valid for any gain.
    K.leftCols(m).array().colwise() *= cmask.array();
    x.noalias() += K.leftCols(m) * y;
    T.noalias() = K.leftCols(m) * PHt.leftCols(m).transpose();
    P -= T;
    P -= T.transpose();
    TH.leftCols(m).noalias() = K.leftCols(m) * S;
    P.noalias() += TH.leftCols(m) * K.leftCols(m).transpose();
  } else {
    x.noalias() += K.leftCols(m) * y;
    P.noalias() -= K.leftCols(m) * PHt.leftCols(m).transpose();
  }
  symmetrize();
  postfit(rec, m, out);
  return covariance_pd() ? FilterStatus::success : FilterStatus::covariance_not_pd;
}

}  // namespace satgnc::filter::detail
