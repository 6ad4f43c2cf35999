// Fixed-interval RTS smoother (filter/rts.hpp).
#include "satgnc/filter/rts.hpp"

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
  llt_ = Eigen::LLT<Eigen::MatrixXd>(Eigen::MatrixXd::Identity(n, n));  // computed: info() set (UBSan)
  llt_.compute(Eigen::MatrixXd::Identity(n, n));
}

const SmootherResult& RtsSmoother::smooth(const FilterResult& run) noexcept {
  SATGNC_NO_MALLOC_SCOPE;
  SmootherResult& s = result_;
  const int n = s.n;
  const int N = s.steps;
  s.status = FilterStatus::success;
  s.failed_step = -1;
  if (run.n != n || run.steps != N || run.predicted_states.cols() != N ||
      run.transitions.cols() != static_cast<Eigen::Index>(n) * N) {
    s.status = FilterStatus::covariance_not_pd;
    s.failed_step = -2;
    return s;
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

}  // namespace satgnc::filter
