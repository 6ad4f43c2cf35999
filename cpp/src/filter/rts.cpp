// Fixed-interval RTS smoother (filter/rts.hpp).
#include "satgnc/filter/rts.hpp"

#include <cmath>
#include <string>

#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::filter {

RtsSmoother::RtsSmoother(int n, int steps) {
  core::require(n >= 1, "n", "must be >= 1, got " + std::to_string(n));
  core::require(steps >= 0, "steps", "must be >= 0, got " + std::to_string(steps));
  result_.n = n;
  result_.steps = steps;
  result_.initial_state.setZero(n);
  result_.initial_covariance.setZero(n, n);
  result_.states.setZero(n, steps);
  result_.covariances.setZero(n, static_cast<Eigen::Index>(n) * steps);
  gain_.setZero(n, n);
  tmp_.setZero(n, n);
  tmp2_.setZero(n, n);
  dp_.setZero(n, n);
  dx_.setZero(n);
  result_.ud_factors.setZero(n, static_cast<Eigen::Index>(n) * steps);
  result_.initial_ud_factors.setZero(n, n);
  us_.setZero(n, n);
  w_.setZero(n, 3 * n);
  dw_.setZero(3 * n);
  llt_ = Eigen::LLT<Eigen::MatrixXd>(Eigen::MatrixXd::Identity(n, n));  // computed: info() set (UBSan)
  llt_.compute(Eigen::MatrixXd::Identity(n, n));
}

namespace {

// Modified weighted Gram-Schmidt (Thornton): w diag(dw) w' = U D U', written packed into out
// (strict upper = U, diagonal = D >= 0). w (n x m) is overwritten.
template <class Out>
void mwgs(Eigen::MatrixXd& w, const Eigen::VectorXd& dw, Out&& out) noexcept {
  const Eigen::Index n = w.rows();
  const Eigen::Index m = w.cols();
  out.setZero();
  for (Eigen::Index j = n - 1; j >= 0; --j) {
    double sigma = 0.0;
    for (Eigen::Index k = 0; k < m; ++k) sigma += w(j, k) * w(j, k) * dw(k);
    if (!(sigma > 0.0)) continue;  // rank lost in this direction: D_j = 0, column of U zero
    out(j, j) = sigma;
    for (Eigen::Index i = 0; i < j; ++i) {
      double s = 0.0;
      for (Eigen::Index k = 0; k < m; ++k) s += w(i, k) * dw(k) * w(j, k);
      const double uij = s / sigma;
      out(i, j) = uij;
      for (Eigen::Index k = 0; k < m; ++k) w(i, k) -= uij * w(j, k);
    }
  }
}

// P = U D U' of a packed block f into p: P_ij = sum_{k >= max(i, j)} U_ik D_k U_jk.
template <class Packed, class Out>
void form_packed(const Packed& f, Out&& p) noexcept {
  const Eigen::Index n = f.rows();
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i <= j; ++i) {
      double a = 0.0;
      for (Eigen::Index k = j; k < n; ++k) {
        const double uik = k == i ? 1.0 : f(i, k);
        const double ujk = k == j ? 1.0 : f(j, k);
        a += uik * f(k, k) * ujk;
      }
      p(i, j) = a;
      p(j, i) = a;
    }
  }
}

}  // namespace

const SmootherResult& RtsSmoother::smooth(const FilterResult& run, bool use_factors) noexcept {
  SATGNC_NO_MALLOC_SCOPE;
  SmootherResult& s = result_;
  const int n = s.n;
  const int N = s.steps;
  s.status = FilterStatus::success;
  s.failed_step = -1;
  s.factored = false;
  if (run.n != n || run.steps != N || run.predicted_states.cols() != N ||
      run.transitions.cols() != static_cast<Eigen::Index>(n) * N) {
    s.status = FilterStatus::covariance_not_pd;
    s.failed_step = -2;
    return s;
  }
  const auto nN = static_cast<Eigen::Index>(n) * N;
  if (use_factors && N > 0 && run.ud_factors.cols() == nN && run.predicted_ud_factors.cols() == nN &&
      run.process_noise_ud_factors.cols() == nN && run.initial_ud_factors.cols() == n) {
    return smooth_factored(run);
  }
  auto block = [n](const Eigen::MatrixXd& m, int k) {
    return m.middleCols(static_cast<Eigen::Index>(k) * n, n);
  };
  if (N == 0) {
    s.initial_state = run.initial_state;
    s.initial_covariance = run.initial_covariance;
    return s;
  }
  s.states.col(N - 1) = run.states.col(N - 1);
  s.covariances.middleCols(static_cast<Eigen::Index>(N - 1) * n, n) = block(run.covariances, N - 1);
  // k = N-2 .. 0 are steps; k = -1 is the initial epoch t0.
  for (int k = N - 2; k >= -1; --k) {
    const auto pk = k >= 0 ? block(run.covariances, k) : run.initial_covariance.middleCols(0, n);
    llt_.compute(block(run.predicted_covariances, k + 1));
    if (llt_.info() != Eigen::Success) {
      s.status = FilterStatus::covariance_not_pd;
      s.failed_step = k + 1;
      return s;
    }
    // C = P_k Phi' Ppred^-1  <=>  C' = Ppred^-1 Phi P_k
    tmp_.noalias() = block(run.transitions, k + 1) * pk;
    llt_.solveInPlace(tmp_);
    gain_ = tmp_.transpose();
    for (int c : run.consider) {
      if (c >= 0 && c < n) gain_.row(c).setZero();
    }  // consider parameters keep their values
    dx_ = s.states.col(k + 1) - run.predicted_states.col(k + 1);
    dp_ = block(s.covariances, k + 1) - block(run.predicted_covariances, k + 1);
    tmp2_.noalias() = gain_ * dp_;
    if (k >= 0) {
      s.states.col(k) = run.states.col(k);
      s.states.col(k).noalias() += gain_ * dx_;
      auto out = s.covariances.middleCols(static_cast<Eigen::Index>(k) * n, n);
      out = pk;
      out.noalias() += tmp2_ * gain_.transpose();
    } else {
      s.initial_state = run.initial_state;
      s.initial_state.noalias() += gain_ * dx_;
      s.initial_covariance = pk;
      s.initial_covariance.noalias() += tmp2_ * gain_.transpose();
    }
  }
  return s;
}

const SmootherResult& RtsSmoother::smooth_factored(const FilterResult& run) noexcept {
  SATGNC_NO_MALLOC_SCOPE;
  SmootherResult& s = result_;
  const int n = s.n;
  const int N = s.steps;
  s.factored = true;
  auto block = [n](const Eigen::MatrixXd& m, int k) {
    return m.middleCols(static_cast<Eigen::Index>(k) * n, n);
  };
  auto out_block = [n](Eigen::MatrixXd& m, int k) {
    return m.middleCols(static_cast<Eigen::Index>(k) * n, n);
  };
  s.states.col(N - 1) = run.states.col(N - 1);
  out_block(s.ud_factors, N - 1) = block(run.ud_factors, N - 1);
  form_packed(block(run.ud_factors, N - 1), out_block(s.covariances, N - 1));
  for (int k = N - 2; k >= -1; --k) {
    const auto fk = k >= 0 ? block(run.ud_factors, k) : run.initial_ud_factors.middleCols(0, n);
    const auto fp = block(run.predicted_ud_factors, k + 1);
    const auto fq = block(run.process_noise_ud_factors, k + 1);
    const auto phi = block(run.transitions, k + 1);
    const auto fs = block(s.ud_factors, k + 1);
    for (int i = 0; i < n; ++i) {
      if (!(fp(i, i) > 0.0) || !std::isfinite(fp(i, i))) {
        s.status = FilterStatus::covariance_not_pd;
        s.failed_step = k + 1;
        return s;
      }
    }
    // tmp = Phi U_k D_k U_k' (= Phi P_k|k, a product: nothing inverted)
    gain_ = fk.triangularView<Eigen::StrictlyUpper>();
    gain_.diagonal().setOnes();
    tmp2_.noalias() = phi * gain_;  // Phi U_k
    dp_ = tmp2_;
    for (int c = 0; c < n; ++c) dp_.col(c) *= fk(c, c);  // Phi U_k D_k
    tmp_.noalias() = dp_ * gain_.transpose();
    // C' = U_p^-T D_p^-1 U_p^-1 tmp: back substitution (unit upper), scaling, forward (unit lower).
    for (int i = n - 1; i >= 0; --i) {
      for (int j = i + 1; j < n; ++j) tmp_.row(i) -= fp(i, j) * tmp_.row(j);
    }
    for (int i = 0; i < n; ++i) tmp_.row(i) /= fp(i, i);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < i; ++j) tmp_.row(i) -= fp(j, i) * tmp_.row(j);
    }
    gain_ = tmp_.transpose();  // C_k
    dx_ = s.states.col(k + 1) - run.predicted_states.col(k + 1);
    // W = [(I - C Phi) U_k, C U_Q, C U_s], weights [D_k, D_Q, D_s]
    dp_.noalias() = gain_ * tmp2_;  // C Phi U_k
    tmp_ = fk.triangularView<Eigen::StrictlyUpper>();
    tmp_.diagonal().setOnes();  // U_k
    w_.leftCols(n) = tmp_ - dp_;
    tmp_ = fq.triangularView<Eigen::StrictlyUpper>();
    tmp_.diagonal().setOnes();
    w_.middleCols(n, n).noalias() = gain_ * tmp_;
    tmp_ = fs.triangularView<Eigen::StrictlyUpper>();
    tmp_.diagonal().setOnes();
    w_.rightCols(n).noalias() = gain_ * tmp_;
    dw_.head(n) = fk.diagonal();
    dw_.segment(n, n) = fq.diagonal();
    dw_.tail(n) = fs.diagonal();
    if (k >= 0) {
      s.states.col(k) = run.states.col(k);
      s.states.col(k).noalias() += gain_ * dx_;
      mwgs(w_, dw_, out_block(s.ud_factors, k));
      form_packed(block(s.ud_factors, k), out_block(s.covariances, k));
    } else {
      s.initial_state = run.initial_state;
      s.initial_state.noalias() += gain_ * dx_;
      mwgs(w_, dw_, s.initial_ud_factors.middleCols(0, n));
      form_packed(s.initial_ud_factors.middleCols(0, n), s.initial_covariance.middleCols(0, n));
    }
  }
  return s;
}

}  // namespace satgnc::filter
