// Objective of the ADMM solver's problem: control cost, trajectory objective, rollout, terminal miss.
#include <cmath>
#include <limits>

#include "detail/admm_workspace.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::guidance::detail {

using Eigen::MatrixXd;
using Eigen::VectorXd;

double AdmmWorkspace::terminal_miss_ratio() noexcept {
  // flown miss over the miss of the zero plan, in units of terminal_tolerance (res_.X_flown current)
  if (!prob_.terminal_equality) return 0.0;
  xtmp_ = res_.X_flown.col(N_) - prob_.xf;
  xtmp2_ = xN0all_ - prob_.xf;
  const double ref = set_.terminal_tolerance * xtmp2_.norm();
  const double miss = xtmp_.norm();
  return miss == 0.0 ? 0.0 : (ref > 0.0 ? miss / ref : std::numeric_limits<double>::infinity());
}

double AdmmWorkspace::control_cost(const Eigen::Ref<const VectorXd>& u) const noexcept {
  double c = w_.dot(u.cwiseAbs());
  if (has_group_) c += prob_.group_l2_weight * u.norm();
  if (prob_.R.size() != 0) {
    double quad = 0.0;
    for (int i = 0; i < nu_; ++i)
      for (int j = 0; j < nu_; ++j) quad += u(i) * prob_.R(i, j) * u(j);
    c += 0.5 * quad;
  }
  return c;
}

double AdmmWorkspace::trajectory_objective(const Eigen::Ref<const MatrixXd>& X,
                                           const Eigen::Ref<const MatrixXd>& U) const noexcept {
  double J = 0.0;
  xtmp_ = X.col(N_) - prob_.xf;
  xtmp2_.noalias() = prob_.Qf * xtmp_;
  J += 0.5 * xtmp_.dot(xtmp2_);
  if (prob_.Q.size() != 0) {
    for (int k = 1; k < N_; ++k) {
      xtmp_ = X.col(k) - prob_.xf;
      xtmp2_.noalias() = prob_.Q * xtmp_;
      J += 0.5 * xtmp_.dot(xtmp2_);
    }
  }
  for (int k = 0; k < N_; ++k) J += control_cost(U.col(k));
  return J;
}

void AdmmWorkspace::rollout(const Eigen::Ref<const MatrixXd>& U, Eigen::Ref<MatrixXd> X) const noexcept {
  const LtvDynamics& d = prob_.dynamics;
  X.col(0) = prob_.x0;
  const bool cw63 = nx_ == 6 && nu_ == 3;
  for (int k = 0; k < N_; ++k) {
    if (cw63) {
      // fixed-size products (the dynamic ones were a library call each, 2 N per rollout)
      using V6 = Eigen::Matrix<double, 6, 1>;
      Eigen::Map<V6> xn(X.col(k + 1).data());
      xn.noalias() = Eigen::Map<const Eigen::Matrix<double, 6, 6>>(d.A_at(k).data()) *
                     Eigen::Map<const V6>(X.col(k).data());
      xn.noalias() += Eigen::Map<const Eigen::Matrix<double, 6, 3>>(d.B_at(k).data()) *
                      Eigen::Map<const Eigen::Matrix<double, 3, 1>>(U.col(k).data());
    } else {
      X.col(k + 1).noalias() = d.A_at(k) * X.col(k);
      X.col(k + 1).noalias() += d.B_at(k) * U.col(k);
    }
    if (!d.c.empty()) X.col(k + 1) += d.c.size() == 1 ? d.c[0] : d.c[k];
  }
}

double AdmmWorkspace::objective_of(const Eigen::Ref<const MatrixXd>& U) const {
  core::require(U.rows() == nu_ && U.cols() == N_, "U", "must be nu x N");
  MatrixXd Us = U;
  Us.array().colwise() /= du_.array();
  MatrixXd X(nx_, N_ + 1);
  rollout(Us, X);
  return trajectory_objective(X, Us) / cscale_;
}

}  // namespace satgnc::guidance::detail
