// Setup of the ADMM solver (AdmmWorkspace constructor): validation, equilibration, the Riccati
// factorization, the buffers and the data of each part; and the between-solve updates.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "detail/admm_workspace.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::guidance::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

AdmmWorkspace::AdmmWorkspace(const LtvProblem& problem, const AdmmSettings& settings)
    : AdmmProblemData(problem, settings) {
  setup_sizes_and_workspace_check();
  setup_weights_and_bounds();
  setup_scaling_and_riccati();
  setup_buffers();
  setup_dual_split();
  setup_flat_pass();
  setup_psi_and_condensed();
  setup_qp_polish();
  setup_polish();
  ipm_setup();
  core::require(set_.method != AdmmMethod::kIpm || ipm_ok_, "method",
                "'ipm' covers L1 and box problems only (no group_l2_weight, no u_norm_max)",
                "use 'admm_ipm'");
}

// Settings and dynamics validated; sizes; the workspace size check before any allocation.
void AdmmWorkspace::setup_sizes_and_workspace_check() {
  using core::require;
  set_.validate();
  prob_.dynamics.validate();
  nx_ = prob_.dynamics.nx();
  nu_ = prob_.dynamics.nu();
  N_ = prob_.dynamics.horizon;
  {
    // size check before anything is allocated: a horizon whose workspace cannot be held is an error
    const double bytes = estimate_workspace_bytes(nx_, nu_, N_);
    res_.info.workspace_bytes = bytes;
    char buf[160];
    std::snprintf(buf, sizeof buf, "workspace of %.0f bytes (%.1f MB) exceeds max_workspace_bytes = %.0f",
                  bytes, bytes / 1e6, set_.max_workspace_bytes);
    require(bytes <= set_.max_workspace_bytes, "horizon",
            std::string("N = ") + std::to_string(N_) + " needs a " + buf,
            "shorten the horizon (receding horizon) or raise AdmmSettings::max_workspace_bytes");
  }
}

// x0, xf, L1 weights, group-L2, box and ball validated; w_, lo_, hi_ and the has_* flags.
void AdmmWorkspace::setup_weights_and_bounds() {
  using core::require;
  const std::string snx = std::to_string(nx_), snu = std::to_string(nu_);
  require(prob_.x0.size() == nx_, "x0", "must have nx = " + snx + " entries");
  core::require_finite(prob_.x0, "x0");
  if (prob_.xf.size() == 0) prob_.xf = VectorXd::Zero(nx_);
  require(prob_.xf.size() == nx_, "xf", "must have nx = " + snx + " entries");
  core::require_finite(prob_.xf, "xf");
  if (prob_.l1_weights.size() != 0) {
    require(prob_.l1_weights.size() == nu_, "l1_weights", "must have nu = " + snu + " entries");
    core::require_finite(prob_.l1_weights, "l1_weights");
    require(prob_.l1_weights.minCoeff() >= 0.0, "l1_weights", "must be >= 0",
            "a fuel weight cannot be negative");
    w_ = prob_.l1_weights;
  } else {
    w_ = VectorXd::Zero(nu_);
  }
  has_l1_ = w_.maxCoeff() > 0.0;
  core::require_nonnegative(prob_.group_l2_weight, "group_l2_weight");
  has_group_ = prob_.group_l2_weight > 0.0;
  lo_ = VectorXd::Constant(nu_, -std::numeric_limits<double>::infinity());
  hi_ = VectorXd::Constant(nu_, std::numeric_limits<double>::infinity());
  if (prob_.u_lower.size() != 0) {
    require(prob_.u_lower.size() == nu_, "u_lower", "must have nu = " + snu + " entries");
    require(!prob_.u_lower.array().isNaN().any() &&
                (prob_.u_lower.array() < std::numeric_limits<double>::infinity()).all(),
            "u_lower", "must not be NaN or +inf");
    lo_ = prob_.u_lower;
  }
  if (prob_.u_upper.size() != 0) {
    require(prob_.u_upper.size() == nu_, "u_upper", "must have nu = " + snu + " entries");
    require(!prob_.u_upper.array().isNaN().any() &&
                (prob_.u_upper.array() > -std::numeric_limits<double>::infinity()).all(),
            "u_upper", "must not be NaN or -inf");
    hi_ = prob_.u_upper;
  }
  for (int i = 0; i < nu_; ++i) {
    require(lo_(i) <= hi_(i), "u_lower", "must be <= u_upper (axis " + std::to_string(i) + ")",
            "lower bound " + std::to_string(lo_(i)) + " above upper bound " + std::to_string(hi_(i)));
  }
  has_box_ = (lo_.array() > -std::numeric_limits<double>::infinity()).any() ||
             (hi_.array() < std::numeric_limits<double>::infinity()).any();
  core::require_nonnegative(prob_.u_norm_max, "u_norm_max");
  has_ball_ = prob_.u_norm_max > 0.0;
  require(!(has_group_ && has_box_), "u_lower/u_upper",
          "per-axis bounds cannot be combined with group_l2_weight",
          "a gimballed engine is bounded by u_norm_max");
  require(!(has_ball_ && (has_l1_ || has_box_)), "u_norm_max",
          "needs zero l1_weights and no per-axis bounds (no closed-form prox otherwise)");
}

// The problem as given kept; equilibration; the Riccati setup and factorization at rho.
void AdmmWorkspace::setup_scaling_and_riccati() {
  using core::require;
  orig_ = prob_;
  du_.setOnes(nu_);
  cscale_ = 1.0;
  scaled_ = set_.equilibrate && set_.stopping == StoppingRule::kResiduals;
  if (scaled_) equilibrate_problem();
  ric_.emplace(RiccatiProblem{prob_.dynamics, prob_.Q, prob_.R, prob_.Qf, prob_.terminal_equality});
  require(ric_->factor(set_.rho), "rho", "Riccati factorization failed",
          "rho must make R + rho I positive definite");
  if (prob_.terminal_equality) {
    require(ric_->terminal_rank() >= 0, "terminal_equality", "internal");
  }
}

// Linear terms, warm start, best iterate, scratch and result arrays.
void AdmmWorkspace::setup_buffers() {
  q_.setZero(nx_, N_ + 1);
  r_.setZero(nu_, N_);
  update_linear_terms();
  Yws_.setZero(nu_, N_);
  Lws_.setZero(nu_, N_);
  bU_.setZero(nu_, N_);
  bY_.setZero(nu_, N_);
  bL_.setZero(nu_, N_);
  v_.setZero(nu_);
  ynew_.setZero(nu_);
  uhat_.setZero(nu_);
  utmp_.setZero(nu_);
  xtmp_.setZero(nx_);
  xtmp2_.setZero(nx_);
  res_.X.setZero(nx_, N_ + 1);
  res_.U.setZero(nu_, N_);
  res_.Y.setZero(nu_, N_);
  res_.Lambda.setZero(nu_, N_);
  res_.X_flown.setZero(nx_, N_ + 1);
  res_.terminal_multiplier.setZero(nx_);
  Gd_.setZero(nu_, N_);
  Hg_.setZero(nu_, N_);
  brk_.assign(static_cast<std::size_t>(N_) * static_cast<std::size_t>(nu_), PwlBreak{});
  lam_.setZero(nx_);
  lam2_.setZero(nx_);
  xN0all_.setZero(nx_);
  ycand_.setZero(nx_);
  pz_.setZero(nx_);
  res_.infeasibility_certificate.setZero(nx_);
}

void AdmmWorkspace::setup_dual_split() {
  // the diagonal of R goes into g for the dual bound (its conjugate is then finite everywhere);
  // a non-diagonal R keeps its off-diagonal part in f (R - diag(rg) may be indefinite: then all of R)
  rg_.setZero(nu_);
  if (prob_.R.size() != 0 && !has_group_ && !has_ball_) {
    const bool diag = (prob_.R - MatrixXd(prob_.R.diagonal().asDiagonal())).cwiseAbs().maxCoeff() == 0.0;
    if (diag) {
      rg_ = prob_.R.diagonal().cwiseMax(0.0);
    } else {
      Eigen::SelfAdjointEigenSolver<MatrixXd> es(0.5 * (prob_.R + prob_.R.transpose()),
                                                 Eigen::EigenvaluesOnly);
      rg_.setConstant(std::max(0.0, es.eigenvalues().minCoeff()));
    }
  }
  if (prob_.R.size() != 0) {
    Rf_ = prob_.R;
    Rf_.diagonal() -= rg_;
    rf_on_ = Rf_.cwiseAbs().maxCoeff() > 0.0;
  }
}

void AdmmWorkspace::setup_flat_pass() {
  // polish needs Q = 0, plain L1 (+ box containing zero, a bound at 0 included: one-sided thrusters);
  // see AdmmSettings::polish
  polish_ok_ = prob_.Q.size() == 0 && !has_group_ && !has_ball_ && has_l1_ && (lo_.array() <= 0.0).all() &&
               (hi_.array() >= 0.0).all();
  flat_ok_ = !has_group_ && !has_ball_;
  if (flat_ok_) {
    const Eigen::Index n = static_cast<Eigen::Index>(N_) * nu_;
    wrep_.resize(n);
    lorep_.resize(n);
    hirep_.resize(n);
    sigw_.resize(n);
    fa_.setZero(n);
    fb_.setZero(n);
    winvrep_.resize(n);
    hifin_.resize(n);
    lofin_.resize(n);
    for (Eigen::Index j = 0; j < n; ++j) {
      const Eigen::Index i = j % nu_;
      wrep_(j) = w_(i);
      lorep_(j) = lo_(i);
      hirep_(j) = hi_(i);
      winvrep_(j) = w_(i) > 0.0 ? 1.0 / w_(i) : 0.0;
      hifin_(j) = std::isfinite(hi_(i)) ? hi_(i) : 0.0;
      lofin_(j) = std::isfinite(lo_(i)) ? lo_(i) : 0.0;
      // signature weights in [1, 2): golden-ratio sequence, distinct per position
      const double f = static_cast<double>(j + 1) * 0.6180339887498949;
      sigw_(j) = 1.0 + (f - std::floor(f));
    }
  }
}

void AdmmWorkspace::setup_psi_and_condensed() {
  // condensed step: no stage state cost, and R empty or diagonal (D = R + rho I stays diagonal)
  cond_ok_ = prob_.Q.size() == 0 &&
             (prob_.R.size() == 0 ||
              (prob_.R - MatrixXd(prob_.R.diagonal().asDiagonal())).cwiseAbs().maxCoeff() == 0.0);
  psi_ok_ = polish_ok_ || cond_ok_;
  if (psi_ok_) {
    Psi_.setZero(nx_, nx_ * N_);
    Psi_.middleCols((N_ - 1) * nx_, nx_).setIdentity();
    for (int k = N_ - 1; k >= 1; --k) {
      Psi_.middleCols((k - 1) * nx_, nx_).noalias() = Psi_.middleCols(k * nx_, nx_) * prob_.dynamics.A_at(k);
    }
    // row k nu + i: (Phi(N, k+1) B_k e_i)', so x_N = x_N(U = 0) + PsiB' vec(U) and grad = PsiB p_N
    PsiB_.setZero(N_ * nu_, nx_);
    xN0_.setZero(nx_);
    if (cond_ok_) {
      Gax_.setZero(nx_, nx_ * nu_);
      dinv_.setZero(nu_);
      Sc_.setZero(nx_, nx_);
      Hc_.setZero(nx_, nx_);
      cond_lu_ = Eigen::PartialPivLU<MatrixXd>(nx_);
      cb_.setZero(nx_);
      ce_.setZero(nx_);
      cg_.setZero(nx_);
      Tc_.setZero(nu_, N_);
    }
    update_psib();
  }
}

void AdmmWorkspace::setup_qp_polish() {
  // QP polish: no L1 weights, no stage Q, R diagonal and positive definite (+ box): any number of
  // free entries, eliminated through an nx x nx system (qp_polish)
  qp_polish_ok_ = !polish_ok_ && cond_ok_ && flat_ok_ && !has_l1_ && prob_.R.size() != 0 &&
                  prob_.R.diagonal().minCoeff() > 0.0;
  if (qp_polish_ok_) {
    Up_.setZero(nu_, N_);
    Xp_.setZero(nx_, N_ + 1);
    grad_.setZero(nu_, N_);
    pN_.setZero(nx_);
    pe_.setZero(nx_);
    Hq_.setZero(nx_, nx_);
    Sq_.setZero(nx_, nx_);
    qb_.setZero(nx_);
    q_lu_ = Eigen::PartialPivLU<MatrixXd>(nx_);
  }
}

void AdmmWorkspace::setup_polish() {
  if (polish_ok_) {
    fmax_ = set_.polish_max_free > 0 ? set_.polish_max_free : 8 * nx_;
    fmax_ = std::min(fmax_, N_ * nu_);
    GF_.setZero(nx_, fmax_);
    KKT_.setZero(fmax_ + nx_, fmax_ + nx_);
    rhs_.setZero(fmax_ + nx_);
    sol_.setZero(fmax_ + nx_);
    Up_.setZero(nu_, N_);
    Xp_.setZero(nx_, N_ + 1);
    grad_.setZero(nu_, N_);
    pN_.setZero(nx_);
    pe_.setZero(nx_);
    free_idx_.assign(static_cast<std::size_t>(fmax_), 0);
    fsign_.assign(static_cast<std::size_t>(fmax_), 0.0);
    dual_ok_ = prob_.R.size() == 0 && w_.minCoeff() > 0.0 && fmax_ >= nx_;
    // smoothed-dual Newton (dual_newton): needs the condensed map and, with a soft terminal, Qf^-1
    dn_ok_ = dual_ok_ && cond_ok_;
    if (dn_ok_ && !prob_.terminal_equality) {
      Eigen::LDLT<MatrixXd> ldlt(prob_.Qf);
      dn_ok_ = ldlt.info() == Eigen::Success && ldlt.isPositive() &&
               ldlt.vectorD().minCoeff() > 1e-12 * ldlt.vectorD().maxCoeff();
      if (dn_ok_) dn_qi_ = ldlt.solve(MatrixXd::Identity(nx_, nx_));
    }
    if (dn_ok_) {
      const Eigen::Index n = static_cast<Eigen::Index>(N_) * nu_;
      dn_s_.setZero(n);
      dn_u_.setZero(n);
      dn_nu_.setZero(nx_);
      dn_g_.setZero(nx_);
      dn_d_.setZero(nx_);
      dn_t_.setZero(nx_);
      dn_e_.setZero(nx_);
      dn_H_.setZero(nx_, nx_);
      dn_lu_ = Eigen::PartialPivLU<MatrixXd>(nx_);
      if (dn_qi_.size() == 0) dn_qi_.setZero(nx_, nx_);
    }
    winv_ = w_.cwiseInverse();
    seld_.assign(static_cast<std::size_t>(nx_ + 1), 0.0);
    seli_.assign(static_cast<std::size_t>(nx_ + 1), 0);
  }
}

void AdmmWorkspace::warm_start(const Eigen::Ref<const MatrixXd>& Y,
                               const Eigen::Ref<const MatrixXd>& Lambda) {
  core::require(Y.rows() == nu_ && Y.cols() == N_, "Y", "must be nu x N");
  core::require(Lambda.rows() == nu_ && Lambda.cols() == N_, "Lambda", "must be nu x N");
  core::require_finite(Y, "Y");
  core::require_finite(Lambda, "Lambda");
  Yws_ = Y;
  Lws_ = Lambda;
  if (scaled_) {  // into the scaled problem: Y~ = D_u^-1 Y, Lambda~ = c D_u Lambda
    // explicit loops: the broadcast of c D_u was evaluated into a heap temporary at every call
    // (SCP warm-starts its subproblems inside its allocation-free solve)
    for (int k = 0; k < N_; ++k)
      for (int i = 0; i < nu_; ++i) {
        Yws_(i, k) /= du_(i);
        Lws_(i, k) *= cscale_ * du_(i);
      }
  }
  warm_ = true;
}

void AdmmWorkspace::set_x0(const Eigen::Ref<const VectorXd>& x0) {
  core::require(x0.size() == nx_, "x0", "must have nx entries");
  core::require_finite(x0, "x0");
  prob_.x0 = x0;
  orig_.x0 = x0;
}

void AdmmWorkspace::set_xf(const Eigen::Ref<const VectorXd>& xf) {
  core::require(xf.size() == nx_, "xf", "must have nx entries");
  core::require_finite(xf, "xf");
  prob_.xf = xf;
  orig_.xf = xf;
  update_linear_terms();
}

void AdmmWorkspace::update_settings(const AdmmSettings& settings) {
  settings.validate();
  set_ = settings;
}

bool AdmmWorkspace::update_dynamics(const std::vector<MatrixXd>& A, const std::vector<MatrixXd>& B,
                                    const std::vector<VectorXd>& c) noexcept {
  LtvDynamics& d = prob_.dynamics;
  if (A.size() != d.A.size() || B.size() != d.B.size() || c.size() != d.c.size()) return false;
  const std::size_t n = A.size();
  if ((n == 1 && N_ > 1) || B.size() != n || (!c.empty() && c.size() != n)) return false;
  for (std::size_t k = 0; k < n; ++k) {
    if (A[k].rows() != nx_ || A[k].cols() != nx_ || B[k].rows() != nx_ || B[k].cols() != nu_) return false;
    if (!c.empty() && c[k].size() != nx_) return false;
    if (!A[k].allFinite() || !B[k].allFinite() || (!c.empty() && !c[k].allFinite())) return false;
  }
  const VectorXd empty;
  for (std::size_t k = 0; k < n; ++k) {
    d.A[k] = A[k];
    for (int i = 0; i < nu_; ++i) d.B[k].col(i) = B[k].col(i) * du_(i);  // the equilibrated B, in place
    if (!c.empty()) d.c[k] = c[k];
    orig_.dynamics.A[k] = A[k];
    orig_.dynamics.B[k] = B[k];
    if (!c.empty()) orig_.dynamics.c[k] = c[k];
    if (!ric_->set_stage_dynamics(static_cast<int>(k), A[k], d.B[k], c.empty() ? empty : c[k])) return false;
  }
  if (psi_ok_) {
    for (int k = N_ - 1; k >= 1; --k)
      Psi_.middleCols((k - 1) * nx_, nx_).noalias() = Psi_.middleCols(k * nx_, nx_) * d.A_at(k);
    update_psib();
  }
  // the IPM's CW blocks are copies of A and B (an LTI problem with N = 1 can be updated)
  if (ipm_ok_) ipm_setup_cw();
  return ric_->factor(set_.rho);
}

}  // namespace satgnc::guidance::detail
