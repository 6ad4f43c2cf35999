// ADMM with a Riccati step for L1 / group-L2 / box-constrained LTV guidance (see admm.hpp).
#include "satgnc/guidance/admm.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include "satgnc/core/validate.hpp"

namespace satgnc::guidance {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

void AdmmSettings::validate() const {
  using core::require;
  core::require_positive(rho, "rho");
  require(max_iterations >= 1, "max_iterations", "must be >= 1");
  core::require_nonnegative(eps_abs, "eps_abs");
  core::require_nonnegative(eps_rel, "eps_rel");
  require(stopping == StoppingRule::kPaper || eps_abs > 0.0 || eps_rel > 0.0, "eps_abs/eps_rel",
          "at least one must be > 0 with the residual stopping rule");
  core::require_positive(paper_eps, "paper_eps");
  require(std::isfinite(relaxation) && relaxation > 0.0 && relaxation < 2.0, "relaxation",
          "must be in (0, 2)", "1.6 is a good default, 1 disables over-relaxation");
  require(adaptive_rho_interval >= 1, "adaptive_rho_interval", "must be >= 1");
  require(std::isfinite(adaptive_rho_tolerance) && adaptive_rho_tolerance >= 1.0, "adaptive_rho_tolerance",
          "must be >= 1");
  core::require_positive(rho_min, "rho_min");
  core::require_positive(rho_max, "rho_max");
  require(rho_min <= rho_max, "rho_min", "must be <= rho_max");
  require(polish_interval >= 1, "polish_interval", "must be >= 1");
  require(polish_max_free >= 0, "polish_max_free", "must be >= 0");
  require(polish_swaps >= 0, "polish_swaps", "must be >= 0");
  core::require_positive(polish_tolerance, "polish_tolerance");
  require(paper_global_rescale_iterations >= 0, "paper_global_rescale_iterations", "must be >= 0");
  core::require_nonnegative(eps_gap, "eps_gap");
  core::require_nonnegative(gap_floor, "gap_floor");
  core::require_nonnegative(terminal_tolerance, "terminal_tolerance");
  require(gap_check_interval >= 1, "gap_check_interval", "must be >= 1");
  require(std::isfinite(inaccurate_factor) && inaccurate_factor >= 1.0, "inaccurate_factor", "must be >= 1");
  core::require_nonnegative(time_limit, "time_limit");
  core::require_positive(max_workspace_bytes, "max_workspace_bytes");
  require(infeasibility_check_interval >= 1, "infeasibility_check_interval", "must be >= 1");
  require(method == AdmmMethod::kAdmm || method == AdmmMethod::kAdmmIpm || method == AdmmMethod::kIpm,
          "method", "must be admm, admm_ipm or ipm");
  require(ipm_after >= 0, "ipm_after", "must be >= 0");
  require(ipm_max_iterations >= 1, "ipm_max_iterations", "must be >= 1");
  core::require_positive(ipm_tolerance, "ipm_tolerance");
}

AdmmSolver::AdmmSolver(const LtvProblem& problem, const AdmmSettings& settings)
    : prob_(problem), set_(settings) {
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
  orig_ = prob_;
  du_.setOnes(nu_);
  cscale_ = 1.0;
  scaled_ = set_.equilibrate && set_.stopping == StoppingRule::kResiduals;
  if (scaled_) equilibrate_problem();
  ric_.setup(prob_.dynamics, prob_.Q, prob_.R, prob_.Qf, prob_.terminal_equality);
  require(ric_.factor(set_.rho), "rho", "Riccati factorization failed",
          "rho must make R + rho I positive definite");
  if (prob_.terminal_equality) {
    require(ric_.terminal_rank() >= 0, "terminal_equality", "internal");
  }
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
  lam_.setZero(nx_);
  lam2_.setZero(nx_);
  xN0all_.setZero(nx_);
  ycand_.setZero(nx_);
  pz_.setZero(nx_);
  res_.infeasibility_certificate.setZero(nx_);
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
  // polish needs Q = 0, plain L1 (+ box straddling zero); see AdmmSettings::polish
  polish_ok_ = prob_.Q.size() == 0 && !has_group_ && !has_ball_ && has_l1_ && (lo_.array() < 0.0).all() &&
               (hi_.array() > 0.0).all();
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
  ipm_setup();
  require(set_.method != AdmmMethod::kIpm || ipm_ok_, "method",
          "'ipm' covers L1 and box problems only (no group_l2_weight, no u_norm_max)", "use 'admm_ipm'");
}

void AdmmSolver::update_psib() noexcept {
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
bool AdmmSolver::cond_factor(double rho) noexcept {
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

void AdmmSolver::cond_step() noexcept {
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

namespace {
// Gaussian elimination with partial pivoting, in place (K and r are destroyed); false if singular.
bool solve_dense_in_place(MatrixXd& K, VectorXd& r, VectorXd& x, int M) noexcept {
  if (M == 0) return true;
  // row equilibration: the blocks of the polish systems carry different units (Qf G against G and
  // the identity), and the pivot test below is relative to the largest entry
  for (int i = 0; i < M; ++i) {
    const double m = K.row(i).head(M).cwiseAbs().maxCoeff();
    if (!(m > 0.0) || !std::isfinite(m)) return false;
    K.row(i).head(M) /= m;
    r(i) /= m;
  }
  const double scale = K.topLeftCorner(M, M).cwiseAbs().maxCoeff();
  if (!(scale > 0.0) || !std::isfinite(scale)) return false;
  for (int c = 0; c < M; ++c) {
    int p = c;
    for (int i = c + 1; i < M; ++i)
      if (std::abs(K(i, c)) > std::abs(K(p, c))) p = i;
    if (std::abs(K(p, c)) <= 1e-13 * scale) return false;
    if (p != c) {
      K.row(p).swap(K.row(c));
      std::swap(r(p), r(c));
    }
    for (int i = c + 1; i < M; ++i) {
      const double f = K(i, c) / K(c, c);
      if (f == 0.0) continue;
      for (int j = c; j < M; ++j) K(i, j) -= f * K(c, j);
      r(i) -= f * r(c);
    }
  }
  for (int i = M - 1; i >= 0; --i) {
    double v = r(i);
    for (int j = i + 1; j < M; ++j) v -= K(i, j) * x(j);
    x(i) = v / K(i, i);
  }
  return x.head(M).allFinite();
}
}  // namespace

// Active-set polish: classify the entries of Y (exact zeros of the soft threshold, exact bounds of
// the clip, the rest free with their sign), solve the reduced problem on the free entries exactly
// (x_N = x_fix + G_F u_F with G_F = Phi(N, k+1) B_k e_i), and accept only if the optimality
// conditions hold for every entry. Allocation-free (fixed-size padded KKT).
bool AdmmSolver::try_polish(bool rank_by_dual) noexcept {
  ++res_.info.polish_attempts;
  const MatrixXd& Y = res_.Y;
  const bool term = prob_.terminal_equality;
  int F = 0;
  for (int k = 0; k < N_; ++k) {
    for (int i = 0; i < nu_; ++i) {
      const double y = Y(i, k);
      if (y == 0.0 || y == lo_(i) || y == hi_(i)) {
        Up_(i, k) = y;
      } else {
        if (F >= fmax_) return false;
        fsign_[static_cast<std::size_t>(F)] = y > 0.0 ? 1.0 : -1.0;
        free_idx_[static_cast<std::size_t>(F++)] = k * nu_ + i;
        Up_(i, k) = 0.0;
      }
    }
  }
  if (term && F < nx_) return false;  // generic vertex needs nx free entries to meet x_N = x_f
  // rank by closeness of the dual estimate to the free condition |G_i| = w_i, or by |Y| without it
  const auto rank_score = [&](int j) {
    const int i = j % nu_, k = j / nu_;
    if (rank_by_dual) return -std::abs(std::abs(Gd_(i, k) * winv_(i)) - 1.0);
    return std::abs(Y(i, k));
  };
  if (F > nx_ && prob_.R.size() == 0) {
    // Without R the reduced problem has at most nx independent free entries (a vertex): keep the
    // nx largest; the rest are taken as zeros. The optimality check below guards the guess.
    for (int t = 0; t < nx_; ++t) {
      int best = t;
      for (int a = t + 1; a < F; ++a) {
        const int ja = free_idx_[static_cast<std::size_t>(a)], jb = free_idx_[static_cast<std::size_t>(best)];
        if (rank_score(ja) > rank_score(jb)) best = a;
      }
      std::swap(free_idx_[static_cast<std::size_t>(t)], free_idx_[static_cast<std::size_t>(best)]);
      std::swap(fsign_[static_cast<std::size_t>(t)], fsign_[static_cast<std::size_t>(best)]);
    }
    F = nx_;
  }
  return polish_solve(F);
}

// Active-set guess from the dual estimate G = -grad f(U) (stored by the ADMM pass; with R = 0 it is
// B_k' Phi(N, k+1)' p_N, a smooth function of the nx-dimensional terminal costate that converges
// long before Y's sparsity pattern settles). Optimality of L1 + box: u = 0 iff |G_i| <= w_i, u at a
// bound iff G_i beyond +-w_i on its side, u free iff |G_i| = w_i. The free set is taken as the
// entries with |G_i| / w_i closest to 1: nx of them with the terminal constraint (a vertex), else
// as many (1..nx) as the largest relative jump in that distance says. Builds the candidate in Up_,
// free_idx_, fsign_ and returns its free count (0: no candidate) and its signature.
int AdmmSolver::dual_candidate(std::uint64_t& signature) noexcept {
  // flat passes (the polish implies plain L1 + box, so the replicated arrays exist); fa_, fb_ are
  // free scratch once the ADMM pass of this iteration is done
  const int keep = nx_ + 1;
  const Eigen::Index n = static_cast<Eigen::Index>(N_) * nu_;
  Eigen::ArrayXd& t = fa_;
  Eigen::ArrayXd& dist = fb_;
  t = Eigen::Map<const Eigen::ArrayXd>(Gd_.data(), n) * winvrep_;
  dist = (t.abs() - 1.0).abs();
  // one pass: the fixed value of each entry, its share of the signature (position-keyed sum:
  // independent multiplies, a one-cycle add chain; a collision only skips one polish attempt) and
  // the keep smallest distances |(|t| - 1)| by insertion into a short sorted list
  constexpr std::uint64_t kKey = 0x9E3779B97F4A7C15ULL;
  double* up = Up_.data();
  int nk = 0;
  double thr = std::numeric_limits<double>::infinity();
  std::uint64_t h = 1469598103934665603ULL;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double tj = t(j);
    const double uj = tj > 1.0 ? hifin_(j) : (tj < -1.0 ? lofin_(j) : 0.0);
    up[j] = uj;
    h += (uj == 0.0 ? 1u : (uj > 0.0 ? 2u : 3u)) * ((static_cast<std::uint64_t>(j) + 1u) * kKey);
    const double d = dist(j);
    if (d < thr) {
      int pos = nk < keep ? nk++ : keep - 1;
      while (pos > 0 && seld_[static_cast<std::size_t>(pos - 1)] > d) {
        seld_[static_cast<std::size_t>(pos)] = seld_[static_cast<std::size_t>(pos - 1)];
        seli_[static_cast<std::size_t>(pos)] = seli_[static_cast<std::size_t>(pos - 1)];
        --pos;
      }
      seld_[static_cast<std::size_t>(pos)] = d;
      seli_[static_cast<std::size_t>(pos)] = static_cast<int>(j);
      if (nk == keep) thr = seld_[static_cast<std::size_t>(keep - 1)];
    }
  }
  const int F = std::min(nx_, nk);
  // second guess (smaller free set): where the sorted distances jump most
  gap_F_ = F;
  if (!prob_.terminal_equality && nk == keep) {
    double jump = 0.0;
    for (int f = 1; f <= nx_; ++f) {
      const double ratio =
          seld_[static_cast<std::size_t>(f)] / std::max(seld_[static_cast<std::size_t>(f - 1)], 1e-300);
      if (ratio > jump) {
        jump = ratio;
        gap_F_ = f;
      }
    }
  }
  for (int a = 0; a < F; ++a) {
    const int j = seli_[static_cast<std::size_t>(a)];
    free_idx_[static_cast<std::size_t>(a)] = j;
    fsign_[static_cast<std::size_t>(a)] = Gd_(j % nu_, j / nu_) > 0.0 ? 1.0 : -1.0;
    // the entry becomes free (value 0 in Up_): move its share of the signature to code 1
    const double old = up[j];
    const std::uint64_t c_old = old == 0.0 ? 1u : (old > 0.0 ? 2u : 3u);
    h += (1u - c_old) * ((static_cast<std::uint64_t>(j) + 1u) * kKey);  // modulo 2^64, exact
    up[j] = 0.0;
  }
  // signature: fixed values (above) and free entries with signs (order of free_idx_ does not matter)
  std::uint64_t hf = 0;
  for (int a = 0; a < F; ++a) {
    hf += (static_cast<std::uint64_t>(free_idx_[static_cast<std::size_t>(a)]) * 2654435761ULL) ^
          (fsign_[static_cast<std::size_t>(a)] > 0.0 ? 0x9e3779b97f4a7c15ULL : 0x7f4a7c159e3779b9ULL);
  }
  signature = h ^ (hf * 0xff51afd7ed558ccdULL) ^ static_cast<std::uint64_t>(F);
  return F;
}

// Local repair of a rejected guess: the dual estimate's free set is usually off by a neighbour in
// time (the switching function |G_i| / w_i is smooth in k), so free the most violated fixed entry in
// place of the free entry of the same axis nearest in time (within 2 steps), or in addition if there
// is room, and solve again; at most polish_swaps times.
bool AdmmSolver::polish_swaps(int& F) noexcept {
  for (int sweep = 0; sweep < set_.polish_swaps && (viol_j_ >= 0 || bad_a_ >= 0); ++sweep) {
    if (bad_a_ >= 0 && !prob_.terminal_equality) {
      if (F <= 1) return false;
      // a free entry left its sign or box: fix it there (zero or the bound) and drop it
      for (int a = 0; a < F; ++a) {
        const int fa = free_idx_[static_cast<std::size_t>(a)];
        Up_(fa % nu_, fa / nu_) = 0.0;
      }
      const int fb = free_idx_[static_cast<std::size_t>(bad_a_)];
      Up_(fb % nu_, fb / nu_) = bad_val_;
      free_idx_[static_cast<std::size_t>(bad_a_)] = free_idx_[static_cast<std::size_t>(F - 1)];
      fsign_[static_cast<std::size_t>(bad_a_)] = fsign_[static_cast<std::size_t>(F - 1)];
      --F;
      ++res_.info.polish_attempts;
      if (F > 0 && polish_solve(F)) return true;
      continue;
    }
    if (viol_j_ < 0) return false;
    const int j = viol_j_, kj = j / nu_, ij = j % nu_;
    int partner = -1, best = 3;
    for (int a = 0; a < F; ++a) {
      const int fa = free_idx_[static_cast<std::size_t>(a)];
      Up_(fa % nu_, fa / nu_) = 0.0;
      const int dk = std::abs(fa / nu_ - kj);
      if (fa % nu_ == ij && dk < best) {
        best = dk;
        partner = a;
      }
    }
    if (partner < 0) {
      if (prob_.terminal_equality || F >= std::min(nx_, fmax_)) return false;
      partner = F++;
    }
    free_idx_[static_cast<std::size_t>(partner)] = j;
    fsign_[static_cast<std::size_t>(partner)] = viol_sign_;
    Up_(ij, kj) = 0.0;
    ++res_.info.polish_attempts;
    if (polish_solve(F)) return true;
  }
  return false;
}

// Reduced KKT solve and optimality certificate for the candidate in Up_ (fixed entries; free ones
// zero), free_idx_[0..F) and their signs fsign_[0..F).
bool AdmmSolver::polish_solve(int F) noexcept {
  const bool term = prob_.terminal_equality;
  bool fail = false;
  viol_j_ = -1;
  bad_a_ = -1;
  double bad_out = 0.0;
  const Eigen::Map<const VectorXd> up(Up_.data(), static_cast<Index>(N_) * nu_);
  xtmp_ = xN0_;
  xtmp_.noalias() += PsiB_.transpose() * up;  // fixed part x_N^fix
  // Compact system: free entries, then nx more unknowns. Hard terminal: the terminal multiplier
  // (G_F' p = -w s, G_F u_F = -x_fix). Soft terminal: the terminal error e = x_N - x_f itself
  // (G_F u_F - e = -x_fix, G_F' Qf e = -w s): the normal equations G_F' Qf G_F would square the
  // conditioning, and p = Qf (x_N - x_f) recomputed from the rolled-out x_N loses all its digits
  // when the terminal error is small against x_N(0) (a large Qf), so no candidate could certify.
  const int M = F + nx_;
  for (int a = 0; a < F; ++a) {
    const int k = free_idx_[static_cast<std::size_t>(a)] / nu_,
              i = free_idx_[static_cast<std::size_t>(a)] % nu_;
    GF_.col(a) = PsiB_.row(k * nu_ + i).transpose();
  }
  KKT_.topLeftCorner(M, M).setZero();
  xtmp_ -= prob_.xf;
  for (int a = 0; a < F; ++a) {
    const int ka = free_idx_[static_cast<std::size_t>(a)] / nu_,
              ia = free_idx_[static_cast<std::size_t>(a)] % nu_;
    const double sa = fsign_[static_cast<std::size_t>(a)];
    rhs_(a) = -w_(ia) * sa;
    if (!term) {
      xtmp2_.noalias() = prob_.Qf * GF_.col(a);  // Qf symmetric: row a of G_F' Qf
      for (int j = 0; j < nx_; ++j) {
        KKT_(a, F + j) = xtmp2_(j);
        KKT_(F + j, a) = GF_(j, a);
      }
    } else {
      for (int j = 0; j < nx_; ++j) {
        KKT_(F + j, a) = GF_(j, a);
        KKT_(a, F + j) = GF_(j, a);
      }
    }
    if (prob_.R.size() != 0) {
      for (int b = 0; b < F; ++b) {
        const int kb = free_idx_[static_cast<std::size_t>(b)] / nu_,
                  ib = free_idx_[static_cast<std::size_t>(b)] % nu_;
        if (kb == ka) KKT_(a, b) += prob_.R(ia, ib);
      }
    }
  }
  for (int j = 0; j < nx_; ++j) {
    rhs_(F + j) = -xtmp_(j);
    if (!term) KKT_(F + j, F + j) = -1.0;
  }
  if (!solve_dense_in_place(KKT_, rhs_, sol_, M)) return false;
  const double tol = set_.polish_tolerance * (scaled_ ? w_.maxCoeff() : std::max(1.0, w_.maxCoeff()));
  for (int a = 0; a < F; ++a) {
    const int k = free_idx_[static_cast<std::size_t>(a)] / nu_,
              i = free_idx_[static_cast<std::size_t>(a)] % nu_;
    const double u = sol_(a);
    const double s = fsign_[static_cast<std::size_t>(a)];
    // still evaluated: the violations guide a repair (polish_swaps)
    const double out = std::max({-u * s, lo_(i) - u, u - hi_(i)});
    if (out > 0.0) {
      fail = true;
      if (out > bad_out) {
        bad_out = out;
        bad_a_ = a;
        bad_val_ = u > hi_(i) ? hi_(i) : (u < lo_(i) ? lo_(i) : 0.0);
      }
    }
    Up_(i, k) = u;
  }
  if (term) {
    pN_ = sol_.segment(F, nx_);
  } else {
    pe_ = sol_.segment(F, nx_);
    pN_.noalias() = prob_.Qf * pe_;  // Qf e from the solved terminal error
  }
  {
    Eigen::Map<VectorXd> g(grad_.data(), static_cast<Index>(N_) * nu_);
    g.noalias() = PsiB_ * pN_;
  }
  // gradient of the smooth part: B_k' Phi(N, k+1)' pN + R u_k; check the L1/box optimality conditions
  // and remember the most violated fixed entry (the one a swap would free)
  viol_j_ = -1;
  double vmax = 0.0;
  for (int k = 0; k < N_; ++k) {
    if (prob_.R.size() != 0) grad_.col(k).noalias() += prob_.R * Up_.col(k);
    for (int i = 0; i < nu_; ++i) {
      const double u = Up_(i, k), gk = grad_(i, k), w = w_(i);
      double v;
      if (u == 0.0) {
        v = std::abs(gk) - w;
      } else if (u == hi_(i)) {
        v = gk + w;
      } else if (u == lo_(i)) {
        v = w - gk;
      } else {
        if (std::abs(gk + (u > 0.0 ? w : -w)) > tol) fail = true;
        continue;
      }
      if (v > tol) {
        fail = true;
        if (v > vmax) {
          vmax = v;
          viol_j_ = k * nu_ + i;
          viol_sign_ = gk < 0.0 ? 1.0 : -1.0;
        }
      }
    }
  }
  if (fail) return false;
  accept_polished(term);
  return true;
}

// Store the certified polish candidate Up_ (with its gradient and terminal multiplier) as the result.
void AdmmSolver::accept_polished(bool term) noexcept {
  res_.U = Up_;
  res_.Y = Up_;
  rollout(Up_, Xp_);
  res_.X = Xp_;
  res_.Lambda = -grad_;
  if (term) res_.terminal_multiplier = pN_;
}

// QP polish (no L1, R diagonal > 0, Q = 0): entries of Y at a bound stay there, the others are free
// with u_i = -m_i' p / r_i. With H_F = sum_free m_i m_i' / r_i and x_fix the terminal state of the
// fixed entries alone: (I + H_F Qf) e = x_fix - x_f for the terminal error e (soft, p = Qf e), or
// H_F p = x_fix - x_f (hard terminal state). Accepted only if the free entries lie in the box and
// the fixed ones satisfy their sign condition (the KKT conditions of the QP).
bool AdmmSolver::qp_polish() noexcept {
  ++res_.info.polish_attempts;
  const bool term = prob_.terminal_equality;
  const MatrixXd& Y = res_.Y;
  Hq_.setZero();
  for (int k = 0; k < N_; ++k) {
    for (int i = 0; i < nu_; ++i) {
      const double y = Y(i, k);
      if (y == lo_(i) || y == hi_(i)) {
        Up_(i, k) = y;
      } else {
        Up_(i, k) = 0.0;
        const double c = 1.0 / prob_.R(i, i);
        const Index row = static_cast<Index>(k) * nu_ + i;
        for (int b = 0; b < nx_; ++b) {
          const double mb = c * PsiB_(row, b);
          for (int a = 0; a < nx_; ++a) Hq_(a, b) += mb * PsiB_(row, a);
        }
      }
    }
  }
  const Eigen::Map<const VectorXd> up(Up_.data(), static_cast<Index>(N_) * nu_);
  qb_ = xN0_ - prob_.xf;
  qb_.noalias() += PsiB_.transpose() * up;
  if (term) {
    Sq_ = Hq_;
  } else {
    Sq_.noalias() = Hq_ * prob_.Qf;
    Sq_.diagonal().array() += 1.0;
  }
  q_lu_.compute(Sq_);
  const auto piv = q_lu_.matrixLU().diagonal().cwiseAbs();
  if (!(piv.minCoeff() > 1e-13 * piv.maxCoeff()) || !std::isfinite(piv.maxCoeff())) return false;
  if (term) {
    pN_ = q_lu_.solve(qb_);
  } else {
    pe_ = q_lu_.solve(qb_);
    pN_.noalias() = prob_.Qf * pe_;
  }
  if (!pN_.allFinite()) return false;
  Eigen::Map<VectorXd> g(grad_.data(), static_cast<Index>(N_) * nu_);
  g.noalias() = PsiB_ * pN_;  // m_i' p
  double scale = 0.0;
  for (int k = 0; k < N_; ++k) {
    for (int i = 0; i < nu_; ++i) {
      const double y = Y(i, k);
      if (y != lo_(i) && y != hi_(i)) Up_(i, k) = -grad_(i, k) / prob_.R(i, i);
      grad_(i, k) += prob_.R(i, i) * Up_(i, k);  // gradient of the smooth part (zero on free entries)
      scale = std::max(scale, std::abs(prob_.R(i, i) * Up_(i, k)));
    }
  }
  const double tol = set_.polish_tolerance * std::max(scale, 1e-300);
  for (int k = 0; k < N_; ++k) {
    for (int i = 0; i < nu_; ++i) {
      const double u = Up_(i, k), y = Y(i, k), gk = grad_(i, k);
      if (y == hi_(i) && y != lo_(i)) {
        if (gk > tol) return false;  // at the upper bound the cost must decrease upward
      } else if (y == lo_(i) && y != hi_(i)) {
        if (gk < -tol) return false;
      } else if (u < lo_(i) || u > hi_(i)) {
        return false;
      }
    }
  }
  accept_polished(term);
  return true;
}

// Smoothed dual of the L1 (+ box) problem without R: with eps/2 ||U||^2 added, the dual in the
// terminal multiplier nu (nx) is smooth and concave, D(nu) = nu' e0 - 1/2 nu' Qf^-1 nu (soft only)
// + sum_i min_u [s_i u + w_i |u| + eps/2 u^2] over the box, s = M' nu, with the minimizer
// u_i = clip(-soft(s_i, w_i) / eps, lo_i, hi_i). Newton on nu (Hessian Qf^-1 + sum_free m_i m_i' / eps)
// with backtracking, eps lowered by 10 per level from the mean curvature; at each level the entries
// strictly inside (0, bound) are the free set of a candidate for the exact polish (polish_solve).
// Starts from ADMM's terminal multiplier; nx-dimensional, so it finds the active set that ADMM's
// iterates approach slowly. Returns true with the certified plan in res_ (as polish_solve).
bool AdmmSolver::dual_newton() noexcept {
  const bool term = prob_.terminal_equality;
  const Eigen::Index n = static_cast<Eigen::Index>(N_) * nu_;
  dn_e_ = xN0_ - prob_.xf;
  double curv = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    if (term) {
      curv += PsiB_.row(j).squaredNorm();
    } else {
      dn_t_.noalias() = prob_.Qf * PsiB_.row(j).transpose();
      curv += PsiB_.row(j).dot(dn_t_);
    }
  }
  curv /= static_cast<double>(n);
  if (!(curv > 0.0) || !std::isfinite(curv)) return false;
  dn_nu_ = cg_;  // condensed step: Qf e (soft) or the terminal multiplier (hard)
  const auto evaluate = [&](const VectorXd& nu, double eps) {
    // s, u(nu) into dn_s_, dn_u_; returns D(nu)
    Eigen::Map<VectorXd> sv(dn_s_.data(), n);
    sv.noalias() = PsiB_ * nu;
    double D = nu.dot(dn_e_);
    if (!term) {
      dn_t_.noalias() = dn_qi_ * nu;
      D -= 0.5 * nu.dot(dn_t_);
    }
    for (Eigen::Index j = 0; j < n; ++j) {
      const double sj = dn_s_(j), w = wrep_(j);
      const double v = sj > w ? sj - w : (sj < -w ? sj + w : 0.0);
      const double u = std::clamp(-v / eps, lorep_(j), hirep_(j));
      dn_u_(j) = u;
      D += sj * u + w * std::abs(u) + 0.5 * eps * u * u;
    }
    return D;
  };
  int steps = 0;
  constexpr int kMaxSteps = 120;
  double eps = curv;
  for (int level = 0; level < 14 && steps < kMaxSteps; ++level, eps *= 0.1) {
    for (int t = 0; t < 30 && steps < kMaxSteps; ++t, ++steps) {
      const double D0 = evaluate(dn_nu_, eps);
      // gradient e0 + M u - Qf^-1 nu and Hessian (negated)
      dn_g_ = dn_e_;
      dn_g_.noalias() += PsiB_.transpose() * dn_u_;
      if (!term) {
        dn_g_.noalias() -= dn_qi_ * dn_nu_;
        dn_H_ = dn_qi_;
      } else {
        dn_H_.setZero();
      }
      for (Eigen::Index j = 0; j < n; ++j) {
        const double u = dn_u_(j);
        if (u == 0.0 || u == lorep_(j) || u == hirep_(j)) continue;
        for (int b = 0; b < nx_; ++b) {
          const double mb = PsiB_(j, b) / eps;
          for (int a = 0; a < nx_; ++a) dn_H_(a, b) += mb * PsiB_(j, a);
        }
      }
      const double tr = dn_H_.trace();
      dn_H_.diagonal().array() += 1e-12 * std::max(tr, 1e-300) / nx_ + (term ? 1e-300 : 0.0);
      dn_lu_.compute(dn_H_);
      dn_d_ = dn_lu_.solve(dn_g_);
      if (!dn_d_.allFinite()) return false;
      const double slope = dn_g_.dot(dn_d_);
      double step = 1.0;
      bool moved = false;
      for (int ls = 0; ls < 40; ++ls, step *= 0.5) {
        dn_t_ = dn_nu_ + step * dn_d_;
        const VectorXd& trial = dn_t_;
        dn_g_ = trial;  // keep the trial point (evaluate overwrites dn_t_ in the soft case)
        if (evaluate(dn_g_, eps) >= D0 + 1e-4 * step * slope) {
          dn_nu_ = dn_g_;
          moved = true;
          break;
        }
      }
      if (!moved || step * dn_d_.norm() <= 1e-13 * std::max(dn_nu_.norm(), 1e-300)) break;
    }
    // candidate: entries strictly inside (0, bound) free, the others fixed at 0 or the bound
    evaluate(dn_nu_, eps);
    int F = 0;
    bool fits = true;
    for (Eigen::Index j = 0; j < n; ++j) {
      const double u = dn_u_(j);
      const bool fixed = u == 0.0 || u == lorep_(j) || u == hirep_(j);
      Up_.data()[j] = fixed ? u : 0.0;
      if (fixed) continue;
      if (F >= nx_ || F >= fmax_) {
        fits = false;
        break;
      }
      free_idx_[static_cast<std::size_t>(F)] = static_cast<int>(j);
      fsign_[static_cast<std::size_t>(F)] = u > 0.0 ? 1.0 : -1.0;
      ++F;
    }
    if (!fits || F == 0 || (term && F < nx_)) continue;
    ++res_.info.polish_attempts;
    if (polish_solve(F)) return true;
  }
  return false;
}

void AdmmSolver::polished_terminal() noexcept {
  // soft terminal: the polish solved the terminal error e = x_N - x_f as an unknown, to full relative
  // precision; the rolled-out x_N carries rounding of order eps |x_N(0)|, which swamps e when Qf is
  // large (and with it the dual bound built from Qf e). Same plan, exact-arithmetic terminal state.
  if (!prob_.terminal_equality) res_.X_flown.col(N_) = prob_.xf + pe_;
}

void AdmmSolver::update_linear_terms() noexcept {
  // q_k = -Q x_f (k = 1..N-1), q_N = -Qf x_f
  q_.setZero();
  if (prob_.Q.size() != 0) {
    xtmp_.noalias() = prob_.Q * prob_.xf;
    for (int k = 1; k < N_; ++k) q_.col(k) = -xtmp_;
  }
  q_.col(N_).noalias() = prob_.Qf * prob_.xf;
  q_.col(N_) *= -1.0;
}

void AdmmSolver::warm_start(const Eigen::Ref<const MatrixXd>& Y, const Eigen::Ref<const MatrixXd>& Lambda) {
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

void AdmmSolver::set_x0(const Eigen::Ref<const VectorXd>& x0) {
  core::require(x0.size() == nx_, "x0", "must have nx entries");
  core::require_finite(x0, "x0");
  prob_.x0 = x0;
  orig_.x0 = x0;
}

void AdmmSolver::set_xf(const Eigen::Ref<const VectorXd>& xf) {
  core::require(xf.size() == nx_, "xf", "must have nx entries");
  core::require_finite(xf, "xf");
  prob_.xf = xf;
  orig_.xf = xf;
  update_linear_terms();
}

void AdmmSolver::update_settings(const AdmmSettings& settings) {
  settings.validate();
  set_ = settings;
}

double AdmmSolver::terminal_miss_ratio() noexcept {
  // flown miss over the miss of the zero plan, in units of terminal_tolerance (res_.X_flown current)
  if (!prob_.terminal_equality) return 0.0;
  xtmp_ = res_.X_flown.col(N_) - prob_.xf;
  xtmp2_ = xN0all_ - prob_.xf;
  const double ref = set_.terminal_tolerance * xtmp2_.norm();
  const double miss = xtmp_.norm();
  return miss == 0.0 ? 0.0 : (ref > 0.0 ? miss / ref : std::numeric_limits<double>::infinity());
}

double AdmmSolver::control_cost(const Eigen::Ref<const VectorXd>& u) const noexcept {
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

double AdmmSolver::trajectory_objective(const Eigen::Ref<const MatrixXd>& X,
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

void AdmmSolver::rollout(const Eigen::Ref<const MatrixXd>& U, Eigen::Ref<MatrixXd> X) const noexcept {
  const LtvDynamics& d = prob_.dynamics;
  X.col(0) = prob_.x0;
  for (int k = 0; k < N_; ++k) {
    X.col(k + 1).noalias() = d.A_at(k) * X.col(k);
    X.col(k + 1).noalias() += d.B_at(k) * U.col(k);
    if (!d.c.empty()) X.col(k + 1) += d.c.size() == 1 ? d.c[0] : d.c[k];
  }
}

double AdmmSolver::objective_of(const Eigen::Ref<const MatrixXd>& U) const {
  core::require(U.rows() == nu_ && U.cols() == N_, "U", "must be nu x N");
  MatrixXd Us = U;
  Us.array().colwise() /= du_.array();
  MatrixXd X(nx_, N_ + 1);
  rollout(Us, X);
  return trajectory_objective(X, Us) / cscale_;
}

namespace {
// Closed-form prox of w|.|_1 / rho (+ group-L2 w_g ||.||_2 / rho) (+ box or ball) for one stage.
template <typename V, typename Y>
inline void prox_stage(const V& v, Y& y, const double* w, const double* lo, const double* hi, double inv_rho,
                       double wg, double umax, bool l1, bool group, bool box, bool ball) noexcept {
  const Eigen::Index m = v.size();
  if (ball) {
    const double nv = v.norm();
    double scale = nv > 0.0 ? std::max(0.0, 1.0 - wg * inv_rho / nv) : 0.0;
    if (scale * nv > umax) scale = umax / nv;
    y = scale * v;
    return;
  }
  if (l1) {
    for (Eigen::Index i = 0; i < m; ++i) {
      const double t = w[i] * inv_rho, vi = v(i);
      y(i) = vi > t ? vi - t : (vi < -t ? vi + t : 0.0);
    }
  } else {
    y = v;
  }
  if (group) {
    const double ny = y.norm();
    y *= ny > 0.0 ? std::max(0.0, 1.0 - wg * inv_rho / ny) : 0.0;
  }
  if (box) {
    for (Eigen::Index i = 0; i < m; ++i) y(i) = std::min(std::max(y(i), lo[i]), hi[i]);
  }
}
}  // namespace

namespace {
template <typename S>
S make_scratch(double* data, Eigen::Index m) noexcept {
  if constexpr (S::SizeAtCompileTime == Eigen::Dynamic) {
    return S(data, m);
  } else {
    (void)data;
    (void)m;
    return S();
  }
}
}  // namespace

template <int NU>
AdmmSolver::PassStats AdmmSolver::admm_pass(double rho, double a) noexcept {
  // Relaxation, prox, multiplier update, residuals, next linear term r = Lambda - rho Y and the
  // active-set signature, in one pass over the stages (fixed-size nu in the (6, 3) instantiation).
  using VU = Eigen::Matrix<double, NU, 1>;
  const Eigen::Index m = nu_;
  PassStats st;
  const double inv_rho = 1.0 / rho;
  const double* U = res_.U.data();
  double* Y = res_.Y.data();
  double* L = res_.Lambda.data();
  double* R = r_.data();
  double* G = Gd_.data();
  const double* w = w_.data();
  const double* lo = lo_.data();
  const double* hi = hi_.data();
  const double wg = prob_.group_l2_weight, umax = prob_.u_norm_max;
  // fixed size: register-resident locals; dynamic: the preallocated scratch
  using Scratch = std::conditional_t<NU == Eigen::Dynamic, Eigen::Map<VU>, VU>;
  Scratch uhat = make_scratch<Scratch>(uhat_.data(), m), v = make_scratch<Scratch>(v_.data(), m),
          yn = make_scratch<Scratch>(ynew_.data(), m);
  std::uint64_t h = 1469598103934665603ULL;
  int nfree = 0;
  for (int k = 0; k < N_; ++k) {
    Eigen::Map<const VU> u(U + k * m, m);
    Eigen::Map<VU> y(Y + k * m, m), l(L + k * m, m), rk(R + k * m, m), g(G + k * m, m);
    g = l + rho * (u - y);  // -grad f(U): the dual estimate of the active-set guess
    uhat = a * u + (1.0 - a) * y;
    v = uhat + inv_rho * l;
    prox_stage(v, yn, w, lo, hi, inv_rho, wg, umax, has_l1_, has_group_, has_box_, has_ball_);
    for (Eigen::Index i = 0; i < m; ++i) {
      const double yi = yn(i), diff = u(i) - yi;
      st.dual = std::max(st.dual, std::abs(yi - y(i)));
      st.prim = std::max(st.prim, std::abs(diff));
      st.fro2 += diff * diff;
      st.nU = std::max(st.nU, std::abs(u(i)));
      st.nY = std::max(st.nY, std::abs(yi));
      const double li = l(i) + rho * (uhat(i) - yi);
      l(i) = li;
      st.nL = std::max(st.nL, std::abs(li));
      y(i) = yi;
      rk(i) = li - rho * yi;
      // active-set code: 0 zero, 1 lower bound, 2 upper bound, 3 free positive, 4 free negative
      const unsigned code = yi == 0.0 ? 0u : (yi == lo[i] ? 1u : (yi == hi[i] ? 2u : (yi > 0.0 ? 3u : 4u)));
      nfree += code >= 3u;
      // position-keyed sum: independent multiplies, a one-cycle add chain (a serial FNV multiply
      // chain over N nu entries cost ~0.3 us per iteration); collisions only skip a polish attempt
      h += (code + 1u) * ((static_cast<std::uint64_t>(k * m + i) + 1u) * 0x9E3779B97F4A7C15ULL);
    }
  }
  st.dual *= rho;
  st.signature = h;
  st.nfree = nfree;
  return st;
}

AdmmSolver::PassStats AdmmSolver::admm_pass_flat(double rho, double a, bool fro2) noexcept {
  const Eigen::Index n = static_cast<Eigen::Index>(N_) * nu_;
  const double inv_rho = 1.0 / rho;
  Eigen::Map<const Eigen::ArrayXd> u(res_.U.data(), n);
  Eigen::Map<Eigen::ArrayXd> y(res_.Y.data(), n), l(res_.Lambda.data(), n), r(r_.data(), n), g(Gd_.data(), n);
  Eigen::ArrayXd& uh = fa_;
  Eigen::ArrayXd& yn = fb_;
  PassStats st;
  g = l + rho * (u - y);  // -grad f(U): the dual estimate of the active-set guess
  uh = a * u + (1.0 - a) * y;
  yn = uh + inv_rho * l;
  // soft threshold (v - clamp(v, -t, t), bitwise equal to the branchy form) then clip to the box
  yn = (yn - yn.max(-inv_rho * wrep_).min(inv_rho * wrep_)).max(lorep_).min(hirep_);
  st.dual = rho * (yn - y).abs().maxCoeff();
  st.prim = (u - yn).abs().maxCoeff();
  if (fro2) st.fro2 = (u - yn).square().sum();  // only the paper's rule needs it every iteration
  st.nU = u.abs().maxCoeff();
  st.nY = yn.abs().maxCoeff();
  l += rho * (uh - yn);
  st.nL = l.abs().maxCoeff();
  y = yn;
  r = l - rho * yn;
  // active-set code: 0 zero, 1 lower bound, 2 upper bound, 3 free positive, 4 free negative; the
  // signature only has to repeat when the active set repeats (a collision skips one polish attempt)
  double sig = 0.0;
  int nfree = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double yi = yn(j);
    const double code =
        yi == 0.0 ? 0.0 : (yi == lorep_(j) ? 1.0 : (yi == hirep_(j) ? 2.0 : (yi > 0.0 ? 3.0 : 4.0)));
    nfree += code >= 3.0;
    sig += (code + 1.0) * sigw_(j);
  }
  std::uint64_t bits = 0;
  std::memcpy(&bits, &sig, sizeof bits);
  st.signature = bits;
  st.nfree = nfree;
  return st;
}

const AdmmResult& AdmmSolver::solve() noexcept {
  const auto t0 = std::chrono::steady_clock::now();
  solve_start_ = t0;
  AdmmInfo& info = res_.info;
  info = AdmmInfo();
  info.workspace_bytes = estimate_workspace_bytes(nx_, nu_, N_);
  const int fact0 = ric_.factorizations();
  double rho = set_.rho;
  MatrixXd& X = res_.X;
  MatrixXd& U = res_.U;
  MatrixXd& Y = res_.Y;
  MatrixXd& L = res_.Lambda;
  if (warm_) {
    Y = Yws_;
    L = Lws_;
  } else {
    Y.setZero();
    L.setZero();
  }
  {  // x_N of the zero control (x0 and x_f may change between solves)
    const LtvDynamics& d = prob_.dynamics;
    xN0all_ = prob_.x0;
    for (int k = 0; k < N_; ++k) {
      xtmp_.noalias() = d.A_at(k) * xN0all_;
      if (!d.c.empty()) xtmp_ += d.c.size() == 1 ? d.c[0] : d.c[k];
      xN0all_ = xtmp_;
    }
    if (psi_ok_) xN0_ = xN0all_;
  }
  res_.infeasibility_certificate.setZero();
  const bool timed = set_.time_limit > 0.0;
  const bool gap_on = set_.eps_gap > 0.0;
  const bool infeas_on = prob_.terminal_equality && has_box_;
  int last_gap_it = -set_.gap_check_interval;
  // a polish certificate is accepted only if the duality gap agrees (tolerances of the scaled
  // problem can be loose against tiny weights)
  const auto polish_gap_ok = [&]() {
    if (!gap_on) return true;
    dual_at_u_ = false;  // the polish replaced U by the polished plan
    rollout(Y, res_.X_flown);
    polished_terminal();
    const double P = trajectory_objective(res_.X_flown, Y);
    const VectorXd& pm = prob_.terminal_equality ? res_.terminal_multiplier : pz_;
    return evaluate_gap(res_.X_flown, Y, pm, P) <= set_.eps_gap && terminal_miss_ratio() <= 1.0;
  };
  bool ok = true;
  // condensed x/u step where it applies (a hard terminal state outside the reachable subspace goes
  // to the Riccati step, which reports it)
  bool cond = cond_ok_ && set_.condensed && set_.cache_gains &&
              !(prob_.terminal_equality && ric_.terminal_rank() < nx_);
  int cond_facts = 0;
  if (cond && (!cond_rho_valid_ || cond_rho_ != rho)) {
    ++cond_facts;
    cond = cond_factor(rho);  // ill-conditioned: the Riccati step instead
  }
  if (!cond && (ric_.rho() != rho || ric_.factorizations() == 0)) ok = ric_.factor(rho);
  if (first_solve_) {
    info.factorizations = 1;  // the setup factorization serves this solve
    first_solve_ = false;
  }
  const double a = set_.relaxation;
  const double dimU = static_cast<double>(N_) * nu_;
  double best = std::numeric_limits<double>::infinity();
  double best_prim = 0.0, best_dual = 0.0, best_paper = 0.0;
  AdmmStatus status = AdmmStatus::kMaxIterations;
  int it = 0;
  if (!ok) status = AdmmStatus::kNumericalError;
  bool r_valid = false;  // r_ = Lambda - rho Y is produced by the previous pass
  const bool paper_rule = set_.stopping == StoppingRule::kPaper;
  const bool polish_on = polish_ok_ && set_.polish && set_.stopping == StoppingRule::kResiduals;
  int next_dn_it = 50;
  const bool qp_polish_on = qp_polish_ok_ && set_.polish && set_.stopping == StoppingRule::kResiduals;
  std::uint64_t prev_sig = 0, tried_sig = 0, prev_dsig = 0, tried_dsig = 0;
  std::array<std::uint64_t, 16> failed{};  // rejected dual guesses of this solve (ring)
  int n_failed = 0, next_failed = 0;
  std::array<std::uint64_t, 16> yfailed{};  // rejected Y-pattern candidates (ring)
  int n_yfailed = 0, next_yfailed = 0;
  bool have_prev = false, have_tried = false, have_dprev = false, have_dtried = false;
  // interior-point method: alone (kIpm) before any ADMM iteration, or as the endgame at ipm_after
  const bool ipm_on = ipm_ok_ && !paper_rule && set_.method != AdmmMethod::kAdmm;
  const int ipm_at = set_.method == AdmmMethod::kIpm ? 0 : set_.ipm_after;
  bool ipm_only = false;
  if (ok && ipm_on && ipm_at == 0) {
    if (ipm_solve(false)) {
      info.ipm_solved = true;
      status = AdmmStatus::kSolved;
    } else if (set_.method == AdmmMethod::kIpm) {
      // no certificate: the IPM's plan is returned as it is, with its true objective and gap;
      // states or an objective that overflow are a numerical error (no ADMM iteration follows either way)
      rollout(iU_, X);
      ipm_only = iU_.allFinite() && X.allFinite() && std::isfinite(trajectory_objective(X, iU_));
      if (!ipm_only) {
        ok = false;
        status = AdmmStatus::kNumericalError;
      } else if (out_of_time()) {
        status = AdmmStatus::kTimeLimit;
      }
    }
    if (ipm_only) {
      U = iU_;
      Y = iU_;
      L.setZero();
      if (prob_.terminal_equality) res_.terminal_multiplier = inu_;
    }
  }
  while (ok && !info.ipm_solved && !ipm_only && it < set_.max_iterations) {
    ++it;
    if (!r_valid) r_ = L - rho * Y;
    RiccatiStatus rs = RiccatiStatus::kOk;
    if (cond)
      cond_step();
    else
      rs = set_.cache_gains ? ric_.solve(prob_.x0, q_, r_, prob_.xf, X, U)
                            : ric_.solve_full(rho, prob_.x0, q_, r_, prob_.xf, X, U);
    if (rs == RiccatiStatus::kTerminalUnreachable) {
      status = AdmmStatus::kTerminalUnreachable;
      break;
    }
    if (rs != RiccatiStatus::kOk) {
      status = AdmmStatus::kNumericalError;
      break;
    }
    const PassStats st = flat_ok_ ? admm_pass_flat(rho, a, paper_rule)
                                  : (nu_ == 3 ? admm_pass<3>(rho, a) : admm_pass<Eigen::Dynamic>(rho, a));
    r_valid = true;
    const double prim = st.prim, dual = st.dual;
    double nL = st.nL;
    if (set_.paper_multiplier_rescale && it == 1) {
      for (int i = 0; i < nu_; ++i) {
        const double mx = L.row(i).cwiseAbs().maxCoeff();
        if (mx > 0.0) L.row(i) *= w_(i) / mx;
      }
      r_valid = false;
      nL = L.cwiseAbs().maxCoeff();
    } else if (set_.paper_multiplier_rescale && it <= set_.paper_global_rescale_iterations) {
      const double mx = L.cwiseAbs().maxCoeff();
      if (mx > 0.0) L *= w_.maxCoeff() / mx;
      r_valid = false;
      nL = L.cwiseAbs().maxCoeff();
    }
    info.primal_residual = prim;
    info.dual_residual = dual;
    info.eps_primal = set_.eps_abs + set_.eps_rel * std::max(st.nU, st.nY);
    info.eps_dual = set_.eps_abs + set_.eps_rel * nL;
    info.paper_criterion = std::sqrt(st.fro2) / dimU;
    if (!std::isfinite(prim) || !std::isfinite(dual) || !std::isfinite(nL)) {
      status = AdmmStatus::kNumericalError;
      break;
    }
    if (set_.track_best) {
      const double eps_p = info.eps_primal > 0.0 ? info.eps_primal : 1e-300;
      const double eps_d = info.eps_dual > 0.0 ? info.eps_dual : 1e-300;
      const double measure = std::max(prim / eps_p, dual / eps_d);
      if (measure < best) {  // X is recomputed from U at the end
        best = measure;
        best_prim = prim;
        best_dual = dual;
        best_paper = info.paper_criterion;
        bU_ = U;
        bY_ = Y;
        bL_ = L;
      }
    }
    if (polish_on && dual_ok_ && set_.polish_dual) {
      std::uint64_t dsig = 0;
      int F = dual_candidate(dsig);
      const bool stable = have_dprev && dsig == prev_dsig;
      // a dual guess (fixed values, free set and signs) determines its polish and repairs, so one
      // that failed fails again: remember the last few (guesses oscillate between a handful)
      bool fresh = !have_dtried || dsig != tried_dsig;
      for (int q = 0; q < n_failed && fresh; ++q) fresh = failed[static_cast<std::size_t>(q)] != dsig;
      prev_dsig = dsig;
      have_dprev = true;
      if (F > 0 && fresh && (stable || it % set_.polish_interval == 0)) {
        tried_dsig = dsig;
        have_dtried = true;
        ++res_.info.polish_attempts;
        if (polish_solve(F) || polish_swaps(F)) {
          if (polish_gap_ok()) {
            info.polished = true;
            status = AdmmStatus::kSolved;
            break;
          }
          r_valid = false;  // rejected by the gap: ADMM continues from the polished Y, Lambda
        }
        failed[static_cast<std::size_t>(next_failed)] = dsig;
        next_failed = (next_failed + 1) % static_cast<int>(failed.size());
        n_failed = std::min(n_failed + 1, static_cast<int>(failed.size()));
      }
    }
    if (polish_on) {
      // The polish candidate depends only on the active-set signature of Y (and, when more than nx
      // entries are free without R, on their magnitudes): try once per new signature as soon as it
      // repeats, and every polish_interval iterations in the magnitude-dependent case.
      const bool stable = have_prev && st.signature == prev_sig;
      const bool by_magnitude = st.nfree > nx_ && prob_.R.size() == 0;
      bool fresh = !have_tried || st.signature != tried_sig;
      // without the magnitude ranking the pattern determines the candidate: skip recent failures
      for (int q = 0; q < n_yfailed && fresh && !by_magnitude; ++q)
        fresh = yfailed[static_cast<std::size_t>(q)] != st.signature;
      const bool attempt =
          st.nfree <= fmax_ && ((stable && fresh) || (by_magnitude && it % set_.polish_interval == 0));
      prev_sig = st.signature;
      have_prev = true;
      if (attempt) {
        tried_sig = st.signature;
        have_tried = true;
        // with more than nx free entries the kept ones are ranked by |Y|, then by the dual estimate
        if (try_polish(false) || (dual_ok_ && set_.polish_dual && st.nfree > nx_ && try_polish(true))) {
          if (polish_gap_ok()) {
            info.polished = true;
            status = AdmmStatus::kSolved;
            break;
          }
          r_valid = false;
        }
        if (!by_magnitude) {
          yfailed[static_cast<std::size_t>(next_yfailed)] = st.signature;
          next_yfailed = (next_yfailed + 1) % static_cast<int>(yfailed.size());
          n_yfailed = std::min(n_yfailed + 1, static_cast<int>(yfailed.size()));
        }
      }
    }
    if (polish_on && dn_ok_ && set_.polish_dual && cond && it == next_dn_it) {
      next_dn_it *= 2;  // at 50, 100, 200, ... iterations: ADMM alone is slow on this problem
      // not at the endgame's iteration: the IPM is cheaper there (measured on the random suite:
      // 146 -> 356 problems certified by the IPM, p95 solve time 2.9 -> 2.0 ms)
      if (!(ipm_on && it == ipm_at) && dual_newton()) {
        if (polish_gap_ok()) {
          info.polished = true;
          status = AdmmStatus::kSolved;
          break;
        }
        r_valid = false;
      }
    }
    if (qp_polish_on) {
      // the candidate depends only on which entries of Y sit at a bound: once per new pattern
      const bool stable = have_prev && st.signature == prev_sig;
      const bool fresh = !have_tried || st.signature != tried_sig;
      prev_sig = st.signature;
      have_prev = true;
      if (stable && fresh) {
        tried_sig = st.signature;
        have_tried = true;
        if (qp_polish()) {
          if (polish_gap_ok()) {
            info.polished = true;
            status = AdmmStatus::kSolved;
            break;
          }
          r_valid = false;
        }
      }
    }
    if (set_.stopping == StoppingRule::kPaper) {
      if (info.paper_criterion <= set_.paper_eps) {
        status = AdmmStatus::kSolvedPaperRule;
        break;
      }
    } else if (prim <= info.eps_primal && dual <= info.eps_dual) {
      // the residuals are not an optimality test: also require the relative duality gap of Y
      if (!gap_on) {
        status = AdmmStatus::kSolved;
        break;
      }
      if (it - last_gap_it >= set_.gap_check_interval) {
        last_gap_it = it;
        if (cond) rollout(U, X);
        dual_at_u_ = true;
        rollout(Y, res_.X_flown);
        const double P = trajectory_objective(res_.X_flown, Y);
        const VectorXd& pm = prob_.terminal_equality ? (cond ? cg_ : ric_.terminal_multiplier()) : pz_;
        if (evaluate_gap(res_.X_flown, Y, pm, P) <= set_.eps_gap && terminal_miss_ratio() <= 1.0) {
          status = AdmmStatus::kSolved;
          break;
        }
      }
    }
    if (ipm_on && it == ipm_at) {
      // endgame: accepted only through the same gap / terminal tests; otherwise ADMM goes on
      // warm from ADMM's iterate (measured: 386 -> 390 / 391 suite problems solved), cold if that
      // fails or there is no plan yet (Y = 0)
      const bool warm = res_.Y.cwiseAbs().maxCoeff() > 0.0;
      if ((warm && ipm_solve(true)) || ipm_solve(false)) {
        info.ipm_solved = true;
        status = AdmmStatus::kSolved;
        break;
      }
    }
    if (timed &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > set_.time_limit) {
      status = AdmmStatus::kTimeLimit;
      break;
    }
    if (infeas_on && it % set_.infeasibility_check_interval == 0 && prim > info.eps_primal) {
      // Farkas candidates: the terminal multiplier (it diverges along the certificate) and the miss
      // of the flown plan, both signs
      const VectorXd& pm = cond ? cg_ : ric_.terminal_multiplier();
      lam2_ = pm;
      bool found = check_infeasible(lam2_);
      if (!found) {
        lam2_ = -pm;
        found = check_infeasible(lam2_);
      }
      if (!found) {
        rollout(Y, res_.X_flown);
        lam2_ = prob_.xf - res_.X_flown.col(N_);
        found = check_infeasible(lam2_);
      }
      if (found) {
        status = AdmmStatus::kPrimalInfeasible;
        break;
      }
    }
    if (set_.adaptive_rho && it % set_.adaptive_rho_interval == 0) {
      // OSQP's rule on normalized residuals; a zero residual (e.g. Y stuck at 0: no dual residual)
      // still moves rho, by at most 100x per update
      const double pn = prim / std::max(std::max(st.nU, st.nY), 1e-300);
      const double dn = dual / std::max(nL, 1e-300);
      if (pn > 0.0 || dn > 0.0) {
        const double ratio = std::clamp(std::sqrt(pn / std::max(dn, 1e-300)), 1e-2, 1e2);
        const double rho_new = std::clamp(rho * ratio, set_.rho_min, set_.rho_max);
        if (rho_new > set_.adaptive_rho_tolerance * rho || rho_new < rho / set_.adaptive_rho_tolerance) {
          rho = rho_new;
          r_valid = false;
          ++info.rho_updates;
          if (cond) {
            ++cond_facts;
            cond = cond_factor(rho);  // ill-conditioned at this rho: the Riccati step from here on
          }
          if (!cond && !ric_.factor(rho)) {
            status = AdmmStatus::kNumericalError;
            break;
          }
        }
      }
    }
  }
  const bool at_limit = status == AdmmStatus::kMaxIterations || status == AdmmStatus::kTimeLimit;
  if (at_limit && set_.track_best && std::isfinite(best)) {
    U = bU_;
    Y = bY_;
    L = bL_;
    info.primal_residual = best_prim;  // residuals of the returned (best) iterate
    info.dual_residual = best_dual;
    info.paper_criterion = best_paper;
    rollout(U, X);
  } else if (status == AdmmStatus::kNumericalError) {
    // never a non-finite plan: the best finite iterate with its residuals, else (the failure came
    // before any finite iterate, e.g. dynamics that overflow) the zero plan, residuals infinite
    if (set_.track_best && std::isfinite(best)) {
      U = bU_;
      Y = bY_;
      L = bL_;
      info.primal_residual = best_prim;
      info.dual_residual = best_dual;
      info.paper_criterion = best_paper;
    } else {
      U.setZero();
      Y.setZero();
      L.setZero();
      info.primal_residual = std::numeric_limits<double>::infinity();
      info.dual_residual = std::numeric_limits<double>::infinity();
    }
    rollout(U, X);
  } else if ((cond && !info.polished) || ipm_only) {
    rollout(U, X);  // the condensed step produces U only
  }
  if (!paper_rule && flat_ok_) info.paper_criterion = (U - Y).norm() / dimU;  // of the returned iterate
  info.iterations = it;
  info.rho = rho;
  info.condensed = cond;
  info.factorizations += ric_.factorizations() - fact0 + cond_facts;
  if (prob_.terminal_equality && !info.polished && !info.ipm_solved && !ipm_only)
    res_.terminal_multiplier = cond ? cg_ : ric_.terminal_multiplier();
  rollout(Y, res_.X_flown);
  if (info.polished) polished_terminal();
  if (info.ipm_solved && !prob_.terminal_equality) res_.X_flown.col(N_) = prob_.xf + ie_;  // as certified
  info.objective = trajectory_objective(res_.X_flown, Y);
  info.objective_u = trajectory_objective(X, U);
  // overflowing states (possible only with numerical_error): +inf says so, never NaN
  if (std::isnan(info.objective)) info.objective = std::numeric_limits<double>::infinity();
  if (std::isnan(info.objective_u)) info.objective_u = std::numeric_limits<double>::infinity();
  info.certified = info.polished;
  if (!((info.polished || info.ipm_solved) && gap_on)) {
    // (a certified plan's gap was just evaluated on this same plan, flown states and multiplier)
    dual_at_u_ =
        !info.polished && !info.ipm_solved;  // X, U: the (best) x/u iterate (the plan itself for the IPM)
    const VectorXd& pm = prob_.terminal_equality ? res_.terminal_multiplier : pz_;
    evaluate_gap(res_.X_flown, Y, pm, info.objective);
  }
  if (at_limit && set_.stopping == StoppingRule::kResiduals) {
    // loose pass on the returned iterate: residuals within inaccurate_factor x their tolerances
    // (best is that ratio when tracked) and the gap within inaccurate_factor x eps_gap
    const double meas = set_.track_best && std::isfinite(best)
                            ? best
                            : std::max(info.primal_residual / std::max(info.eps_primal, 1e-300),
                                       info.dual_residual / std::max(info.eps_dual, 1e-300));
    if (meas <= set_.inaccurate_factor &&
        (!gap_on || info.duality_gap <= set_.inaccurate_factor * set_.eps_gap) &&
        terminal_miss_ratio() <= set_.inaccurate_factor)
      status = AdmmStatus::kSolvedInaccurate;
  }
  info.status = status;
  xtmp_ = res_.X_flown.col(N_) - prob_.xf;
  info.terminal_miss = xtmp_.norm();
  if (std::isnan(info.terminal_miss)) info.terminal_miss = std::numeric_limits<double>::infinity();
  if (scaled_) unscale_result();
  info.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res_;
}

bool AdmmSolver::update_dynamics(const std::vector<MatrixXd>& A, const std::vector<MatrixXd>& B,
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
    if (!ric_.set_stage_dynamics(static_cast<int>(k), A[k], d.B[k], c.empty() ? empty : c[k])) return false;
  }
  if (psi_ok_) {
    for (int k = N_ - 1; k >= 1; --k)
      Psi_.middleCols((k - 1) * nx_, nx_).noalias() = Psi_.middleCols(k * nx_, nx_) * d.A_at(k);
    update_psib();
  }
  return ric_.factor(set_.rho);
}

}  // namespace satgnc::guidance
