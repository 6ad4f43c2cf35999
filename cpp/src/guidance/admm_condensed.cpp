// Condensed x/u step of the ADMM solver (AdmmSettings::condensed): the stored map M = [Phi(N, k+1)
// B_k]_k, its per-axis Gram matrices and the nx x nx factorization refactored with rho.
#include <cmath>

#include "detail/admm_workspace.hpp"

namespace satgnc::guidance::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

void AdmmWorkspace::update_psib() noexcept {
  // row k nu + i of PsiB_ = (Phi(N, k+1) B_k e_i)', through the nx scratch vector (no temporary)
  for (int k = 0; k < N_; ++k) {
    for (int i = 0; i < nu_; ++i) {
      xtmp_.noalias() = Psi_.middleCols(k * nx_, nx_) * prob_.dynamics.B_at(k).col(i);
      PsiB_.row(k * nu_ + i) = xtmp_.transpose();
    }
  }
  if (cond_ok_) {
    // per-axis Gram matrices: H = M D^-1 M' = sum_i dinv_i Gax_i for any rho, without a pass over N
    Gax_.setZero();
    for (int k = 0; k < N_; ++k) {
      for (int i = 0; i < nu_; ++i) {
        Gax_.middleCols(i * nx_, nx_).noalias() +=
            PsiB_.row(k * nu_ + i).transpose() * PsiB_.row(k * nu_ + i);
      }
    }
    cond_rho_valid_ = false;
  }
}

// Condensed LQR step: with D = R + rho I diagonal and no stage state cost, stationarity gives
// U = -D^-1 (r + M' g) with x_N = x_N0 + M U; g = Qf (x_N - x_f) (soft terminal) or the terminal
// multiplier (hard). Eliminating U: (I + H Qf) e = b (soft, e = x_N - x_f) or H g = b (hard), with
// H = M D^-1 M' and b = x_N0 - x_f - M D^-1 r.
bool AdmmWorkspace::cond_factor(double rho) noexcept {
  for (int i = 0; i < nu_; ++i) dinv_(i) = 1.0 / ((prob_.R.size() == 0 ? 0.0 : prob_.R(i, i)) + rho);
  Hc_.setZero();
  for (int i = 0; i < nu_; ++i) Hc_ += dinv_(i) * Gax_.middleCols(i * nx_, nx_);
  if (prob_.terminal_equality) {
    Sc_ = Hc_;
  } else {
    Sc_.noalias() = Hc_ * prob_.Qf;
    Sc_.diagonal().array() += 1.0;
  }
  cond_lu_.compute(Sc_);
  cond_rho_ = rho;
  cond_rho_valid_ = true;
  // pivot ratio as the conditioning test (Eigen's rcond() estimate allocates)
  const auto piv = cond_lu_.matrixLU().diagonal().cwiseAbs();
  const double pmax = piv.maxCoeff(), pmin = piv.minCoeff();
  return std::isfinite(pmax) && pmin > 1e-12 * pmax;
}

void AdmmWorkspace::cond_step() noexcept {
  const Eigen::Index n = static_cast<Eigen::Index>(N_) * nu_;
  for (int k = 0; k < N_; ++k)
    for (int i = 0; i < nu_; ++i) Tc_(i, k) = dinv_(i) * r_(i, k);
  Eigen::Map<const VectorXd> t(Tc_.data(), n);
  cb_ = xN0_ - prob_.xf;
  cb_.noalias() -= PsiB_.transpose() * t;
  ce_ = cond_lu_.solve(cb_);
  if (prob_.terminal_equality) {
    cg_ = ce_;
  } else {
    cg_.noalias() = prob_.Qf * ce_;
  }
  MatrixXd& U = res_.U;
  Eigen::Map<VectorXd> u(U.data(), n);
  u.noalias() = PsiB_ * cg_;
  for (int k = 0; k < N_; ++k)
    for (int i = 0; i < nu_; ++i) U(i, k) = -(Tc_(i, k) + dinv_(i) * U(i, k));
}

}  // namespace satgnc::guidance::detail
