// Equilibration of the ADMM problem (AdmmSettings::equilibrate): per-axis control scaling D_u and
// a cost scaling c, applied at setup; results are unscaled after each solve.
#include <algorithm>
#include <cmath>

#include "detail/admm_workspace.hpp"

namespace satgnc::guidance::detail {

using Eigen::MatrixXd;
using Eigen::VectorXd;

void AdmmWorkspace::equilibrate_problem() {
  LtvDynamics& d = prob_.dynamics;
  // sizes are validated later by the Riccati setup: leave a malformed problem unscaled
  if (prob_.Qf.rows() != nx_ || prob_.Qf.cols() != nx_) return;
  if (prob_.R.size() != 0 && (prob_.R.rows() != nu_ || prob_.R.cols() != nu_)) return;
  // mean curvature of the smooth part along each control axis: mean_k m_ki' W m_ki (+ R_ii), with
  // m_ki = Phi(N, k+1) B_k e_i and W = Qf (the column norms of dx_N/du with a hard terminal state)
  const bool qf_zero = prob_.Qf.cwiseAbs().maxCoeff() == 0.0;
  const MatrixXd W = qf_zero ? MatrixXd::Identity(nx_, nx_) : MatrixXd(prob_.Qf);
  VectorXd h = VectorXd::Zero(nu_);
  MatrixXd Phi = MatrixXd::Identity(nx_, nx_);
  for (int k = N_ - 1; k >= 0; --k) {
    const MatrixXd MB = Phi * d.B_at(k);
    h += (MB.transpose() * W * MB).diagonal();
    Phi = (Phi * d.A_at(k)).eval();
  }
  h /= static_cast<double>(N_);
  if (prob_.R.size() != 0) h += prob_.R.diagonal().cwiseMax(0.0);
  if (!h.allFinite()) return;
  const double hmax = h.maxCoeff();
  if (!(hmax > 0.0)) return;  // no curvature information: leave the problem as given
  // per-axis shape D': L1 axes by their weight (uniform soft threshold), otherwise by curvature
  // (unit curvature per axis); one scale for all axes with a group norm
  VectorXd dp(nu_);
  const bool by_weight = has_l1_ && w_.minCoeff() > 0.0 && !has_group_ && !has_ball_;
  for (int i = 0; i < nu_; ++i) {
    const double hi = h(i) > 1e-12 * hmax ? h(i) : hmax;
    dp(i) = by_weight ? 1.0 / w_(i) : 1.0 / std::sqrt(hi);
  }
  if (has_group_ || has_ball_) dp.setConstant(1.0 / std::sqrt(h.mean() > 0.0 ? h.mean() : hmax));
  // overall control scale a and cost scale c: the largest scaled weight becomes 1 and the mean
  // scaled curvature kCurvature (u = a D' u~: weight c a w D', curvature c a^2 h D'^2)
  constexpr double kCurvature = 256.0;
  const double hbar = (h.array() * dp.array().square()).mean();
  double wmax = 0.0;
  for (int i = 0; i < nu_; ++i) wmax = std::max(wmax, dp(i) * w_(i));
  wmax = std::max(wmax, dp(0) * prob_.group_l2_weight);
  double a = 1.0, c = kCurvature / hbar;
  if (wmax > 0.0) {
    a = kCurvature * wmax / hbar;
    c = 1.0 / (a * wmax);
  }
  // powers of two: the scaling is exact in floating point, and a problem within sqrt(2) of the
  // reference frame is solved exactly as given
  const auto pow2 = [](double v) { return std::exp2(std::round(std::log2(std::clamp(v, 1e-150, 1e150)))); };
  du_ = a * dp;
  for (int i = 0; i < nu_; ++i) du_(i) = pow2(du_(i));
  cscale_ = pow2(c);
  if (!du_.allFinite() || !std::isfinite(cscale_)) {
    du_.setOnes(nu_);
    cscale_ = 1.0;
    return;
  }
  c = cscale_;
  for (auto& B : d.B) B = (B * du_.asDiagonal()).eval();
  prob_.Qf *= c;
  if (prob_.Q.size() != 0) prob_.Q *= c;
  if (prob_.R.size() != 0) prob_.R = (c * du_.asDiagonal() * prob_.R * du_.asDiagonal()).eval();
  w_ = c * w_.cwiseProduct(du_);
  if (prob_.l1_weights.size() != 0) prob_.l1_weights = w_;
  lo_ = lo_.cwiseQuotient(du_);
  hi_ = hi_.cwiseQuotient(du_);
  if (prob_.u_lower.size() != 0) prob_.u_lower = lo_;
  if (prob_.u_upper.size() != 0) prob_.u_upper = hi_;
  prob_.group_l2_weight *= c * du_(0);
  prob_.u_norm_max /= du_(0);
}

void AdmmWorkspace::unscale_result() noexcept {
  // u = D_u u~, Lambda = Lambda~ / (c D_u), p = p~ / c, J = J~ / c; states are not scaled
  AdmmResult& r = res_;
  // explicit loops: a broadcast of an expression would evaluate it into a heap temporary
  for (int k = 0; k < N_; ++k) {
    for (int i = 0; i < nu_; ++i) {
      r.U(i, k) *= du_(i);
      r.Y(i, k) *= du_(i);
      r.Lambda(i, k) /= cscale_ * du_(i);
    }
  }
  r.terminal_multiplier /= cscale_;
  AdmmInfo& i = r.info;
  i.objective /= cscale_;
  i.objective_u /= cscale_;
  i.primal_objective /= cscale_;
  i.dual_objective /= cscale_;
}

}  // namespace satgnc::guidance::detail
