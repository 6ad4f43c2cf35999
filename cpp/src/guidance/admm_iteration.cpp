// ADMM iteration: solve() as begin, a loop of iterate_once (x/u step, fused pass, best iterate,
// polishes, stopping test, interior-point endgame, limits, adaptive rho) and finish.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include "detail/admm_workspace.hpp"

namespace satgnc::guidance::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

void AdmmWorkspace::update_linear_terms() noexcept {
  // q_k = -Q x_f (k = 1..N-1), q_N = -Qf x_f
  q_.setZero();
  if (prob_.Q.size() != 0) {
    xtmp_.noalias() = prob_.Q * prob_.xf;
    for (int k = 1; k < N_; ++k) q_.col(k) = -xtmp_;
  }
  q_.col(N_).noalias() = prob_.Qf * prob_.xf;
  q_.col(N_) *= -1.0;
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
AdmmWorkspace::PassStats AdmmWorkspace::admm_pass(double rho, double a) noexcept {
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

AdmmWorkspace::PassStats AdmmWorkspace::admm_pass_flat(double rho, double a, bool fro2) noexcept {
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

const AdmmResult& AdmmWorkspace::solve() noexcept {
  begin_solve();
  while (ok_ && !res_.info.ipm_solved && !ipm_only_ && it_ < set_.max_iterations) {
    if (!iterate_once()) break;
  }
  finish_solve();
  return res_;
}

// Start of solve(): the clock, a fresh info, the warm start, x_N of the zero control, the
// factorization at the settings' rho, the loop state; the interior-point method alone (kIpm).
void AdmmWorkspace::begin_solve() noexcept {
  const auto t0 = std::chrono::steady_clock::now();
  solve_start_ = t0;
  AdmmInfo& info = res_.info;
  info = AdmmInfo();
  info.workspace_bytes = estimate_workspace_bytes(nx_, nu_, N_);
  fact0_ = ric_->factorizations();
  rho_ = set_.rho;
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
  timed_ = set_.time_limit > 0.0;
  gap_on_ = set_.eps_gap > 0.0;
  infeas_on_ = prob_.terminal_equality && has_box_;
  last_gap_it_ = -set_.gap_check_interval;
  ok_ = true;
  // condensed x/u step where it applies (a hard terminal state outside the reachable subspace goes
  // to the Riccati step, which reports it)
  cond_ = cond_ok_ && set_.condensed && set_.cache_gains &&
          !(prob_.terminal_equality && ric_->terminal_rank() < nx_);
  cond_facts_ = 0;
  if (cond_ && (!cond_rho_valid_ || cond_rho_ != rho_)) {
    ++cond_facts_;
    cond_ = cond_factor(rho_);  // ill-conditioned: the Riccati step instead
  }
  if (!cond_ && (ric_->rho() != rho_ || ric_->factorizations() == 0)) ok_ = ric_->factor(rho_);
  if (first_solve_) {
    info.factorizations = 1;  // the setup factorization serves this solve
    first_solve_ = false;
  }
  reset_loop_state();
  if (ok_ && ipm_on_ && ipm_at_ == 0) start_ipm_alone();
}

// The loop's state at the start of a solve (best iterate, status, polish rings, IPM flags).
void AdmmWorkspace::reset_loop_state() noexcept {
  a_ = set_.relaxation;
  dimU_ = static_cast<double>(N_) * nu_;
  best_ = std::numeric_limits<double>::infinity();
  best_prim_ = 0.0;
  best_dual_ = 0.0;
  best_paper_ = 0.0;
  status_ = AdmmStatus::max_iterations;
  it_ = 0;
  if (!ok_) status_ = AdmmStatus::numerical_error;
  r_valid_ = false;  // r_ = Lambda - rho Y is produced by the previous pass
  paper_rule_ = set_.stopping == StoppingRule::kPaper;
  polish_on_ = polish_ok_ && set_.polish && set_.stopping == StoppingRule::kResiduals;
  next_dn_it_ = 50;
  qp_polish_on_ = qp_polish_ok_ && set_.polish && set_.stopping == StoppingRule::kResiduals;
  prev_sig_ = 0;
  tried_sig_ = 0;
  prev_dsig_ = 0;
  tried_dsig_ = 0;
  failed_.fill(0);  // rejected dual guesses of this solve (ring)
  n_failed_ = 0;
  next_failed_ = 0;
  yfailed_.fill(0);  // rejected Y-pattern candidates (ring)
  n_yfailed_ = 0;
  next_yfailed_ = 0;
  have_prev_ = false;
  have_tried_ = false;
  have_dprev_ = false;
  have_dtried_ = false;
  // interior-point method: alone (kIpm) before any ADMM iteration, or as the endgame at ipm_after
  ipm_on_ = ipm_ok_ && !paper_rule_ && set_.method != AdmmMethod::kAdmm;
  ipm_at_ = set_.method == AdmmMethod::kIpm ? 0 : set_.ipm_after;
  ipm_only_ = false;
}

// The interior-point method before any ADMM iteration (ipm_at == 0).
void AdmmWorkspace::start_ipm_alone() noexcept {
  AdmmInfo& info = res_.info;
  MatrixXd& X = res_.X;
  MatrixXd& U = res_.U;
  MatrixXd& Y = res_.Y;
  MatrixXd& L = res_.Lambda;
  if (ipm_solve(false)) {
    info.ipm_solved = true;
    status_ = AdmmStatus::solved;
  } else if (set_.method == AdmmMethod::kIpm) {
    // no certificate: the IPM's plan is returned as it is, with its true objective and gap;
    // states or an objective that overflow are a numerical error (no ADMM iteration follows either way)
    rollout(iU_, X);
    ipm_only_ = iU_.allFinite() && X.allFinite() && std::isfinite(trajectory_objective(X, iU_));
    if (!ipm_only_) {
      ok_ = false;
      status_ = AdmmStatus::numerical_error;
    } else if (out_of_time()) {
      status_ = AdmmStatus::time_limit;
    }
  }
  if (ipm_only_) {
    U = iU_;
    Y = iU_;
    L.setZero();
    if (prob_.terminal_equality) res_.terminal_multiplier = inu_;
  }
}

// One ADMM iteration; false ends the loop (status set).
bool AdmmWorkspace::iterate_once() noexcept {
  ++it_;
  if (!xu_step()) return false;
  if (!pass_and_residuals()) return false;
  if (set_.track_best) track_best();
  if (polish_round()) return false;
  if (check_stop()) return false;
  if (ipm_endgame()) return false;
  if (check_limits()) return false;
  return !adapt_rho();
}

// The x/u step (condensed or Riccati); false on an unreachable terminal state or a numerical error.
bool AdmmWorkspace::xu_step() noexcept {
  MatrixXd& X = res_.X;
  MatrixXd& U = res_.U;
  MatrixXd& Y = res_.Y;
  MatrixXd& L = res_.Lambda;
  if (!r_valid_) r_ = L - rho_ * Y;
  RiccatiStatus rs = RiccatiStatus::solved;
  if (cond_)
    cond_step();
  else
    rs = set_.cache_gains ? ric_->solve(prob_.x0, q_, r_, prob_.xf, X, U)
                          : ric_->solve_full(rho_, prob_.x0, q_, r_, prob_.xf, X, U);
  if (rs == RiccatiStatus::terminal_unreachable) {
    status_ = AdmmStatus::terminal_unreachable;
    return false;
  }
  if (rs != RiccatiStatus::solved) {
    status_ = AdmmStatus::numerical_error;
    return false;
  }
  return true;
}

// Relaxation / prox / multiplier pass, the paper's multiplier rescale and the residuals in info;
// false on a non-finite residual.
bool AdmmWorkspace::pass_and_residuals() noexcept {
  AdmmInfo& info = res_.info;
  MatrixXd& L = res_.Lambda;
  st_ = flat_ok_ ? admm_pass_flat(rho_, a_, paper_rule_)
                 : (nu_ == 3 ? admm_pass<3>(rho_, a_) : admm_pass<Eigen::Dynamic>(rho_, a_));
  r_valid_ = true;
  prim_ = st_.prim;
  dual_ = st_.dual;
  nL_ = st_.nL;
  if (set_.paper_multiplier_rescale && it_ == 1) {
    for (int i = 0; i < nu_; ++i) {
      const double mx = L.row(i).cwiseAbs().maxCoeff();
      if (mx > 0.0) L.row(i) *= w_(i) / mx;
    }
    r_valid_ = false;
    nL_ = L.cwiseAbs().maxCoeff();
  } else if (set_.paper_multiplier_rescale && it_ <= set_.paper_global_rescale_iterations) {
    const double mx = L.cwiseAbs().maxCoeff();
    if (mx > 0.0) L *= w_.maxCoeff() / mx;
    r_valid_ = false;
    nL_ = L.cwiseAbs().maxCoeff();
  }
  info.primal_residual = prim_;
  info.dual_residual = dual_;
  info.eps_primal = set_.eps_abs + set_.eps_rel * std::max(st_.nU, st_.nY);
  info.eps_dual = set_.eps_abs + set_.eps_rel * nL_;
  info.paper_criterion = std::sqrt(st_.fro2) / dimU_;
  if (!std::isfinite(prim_) || !std::isfinite(dual_) || !std::isfinite(nL_)) {
    status_ = AdmmStatus::numerical_error;
    return false;
  }
  return true;
}

// Keep the iterate with the smallest residual-to-tolerance ratio (returned at a limit).
void AdmmWorkspace::track_best() noexcept {
  const AdmmInfo& info = res_.info;
  const double eps_p = info.eps_primal > 0.0 ? info.eps_primal : 1e-300;
  const double eps_d = info.eps_dual > 0.0 ? info.eps_dual : 1e-300;
  const double measure = std::max(prim_ / eps_p, dual_ / eps_d);
  if (measure < best_) {  // X is recomputed from U at the end
    best_ = measure;
    best_prim_ = prim_;
    best_dual_ = dual_;
    best_paper_ = info.paper_criterion;
    bU_ = res_.U;
    bY_ = res_.Y;
    bL_ = res_.Lambda;
  }
}

// The polishes of this iteration; true if one is certified (status solved).
bool AdmmWorkspace::polish_round() noexcept {
  if (polish_on_ && dual_ok_ && set_.polish_dual && polish_by_dual()) return true;
  if (polish_on_ && polish_by_pattern()) return true;
  if (polish_on_ && dn_ok_ && set_.polish_dual && cond_ && it_ == next_dn_it_ && polish_by_dual_newton())
    return true;
  return qp_polish_on_ && polish_qp_round();
}

// A polish certificate is accepted only if the duality gap agrees (tolerances of the scaled
// problem can be loose against tiny weights).
bool AdmmWorkspace::accept_polish() noexcept {
  if (polish_gap_ok()) {
    res_.info.polished = true;
    status_ = AdmmStatus::solved;
    return true;
  }
  r_valid_ = false;  // rejected by the gap: ADMM continues from the polished Y, Lambda
  return false;
}

bool AdmmWorkspace::polish_gap_ok() noexcept {
  const MatrixXd& Y = res_.Y;
  if (!gap_on_) return true;
  dual_at_u_ = false;  // the polish replaced U by the polished plan
  rollout(Y, res_.X_flown);
  polished_terminal();
  const double P = trajectory_objective(res_.X_flown, Y);
  const VectorXd& pm = prob_.terminal_equality ? res_.terminal_multiplier : pz_;
  return gap_within(evaluate_gap(res_.X_flown, Y, pm, P), set_.eps_gap) && terminal_miss_ratio() <= 1.0;
}

// The active-set guess from the dual estimate.
bool AdmmWorkspace::polish_by_dual() noexcept {
  std::uint64_t dsig = 0;
  int F = dual_candidate(dsig);
  const bool stable = have_dprev_ && dsig == prev_dsig_;
  // a dual guess (fixed values, free set and signs) determines its polish and repairs, so one
  // that failed fails again: remember the last few (guesses oscillate between a handful)
  bool fresh = !have_dtried_ || dsig != tried_dsig_;
  for (int q = 0; q < n_failed_ && fresh; ++q) fresh = failed_[static_cast<std::size_t>(q)] != dsig;
  prev_dsig_ = dsig;
  have_dprev_ = true;
  if (F > 0 && fresh && (stable || it_ % set_.polish_interval == 0)) {
    tried_dsig_ = dsig;
    have_dtried_ = true;
    ++res_.info.polish_attempts;
    if (polish_solve(F) || polish_swaps(F)) {
      if (accept_polish()) return true;
    }
    failed_[static_cast<std::size_t>(next_failed_)] = dsig;
    next_failed_ = (next_failed_ + 1) % static_cast<int>(failed_.size());
    n_failed_ = std::min(n_failed_ + 1, static_cast<int>(failed_.size()));
  }
  return false;
}

// The polish candidate depends only on the active-set signature of Y (and, when more than nx
// entries are free without R, on their magnitudes): try once per new signature as soon as it
// repeats, and every polish_interval iterations in the magnitude-dependent case.
bool AdmmWorkspace::polish_by_pattern() noexcept {
  const bool stable = have_prev_ && st_.signature == prev_sig_;
  const bool by_magnitude = st_.nfree > nx_ && prob_.R.size() == 0;
  bool fresh = !have_tried_ || st_.signature != tried_sig_;
  // without the magnitude ranking the pattern determines the candidate: skip recent failures
  for (int q = 0; q < n_yfailed_ && fresh && !by_magnitude; ++q)
    fresh = yfailed_[static_cast<std::size_t>(q)] != st_.signature;
  const bool attempt =
      st_.nfree <= fmax_ && ((stable && fresh) || (by_magnitude && it_ % set_.polish_interval == 0));
  prev_sig_ = st_.signature;
  have_prev_ = true;
  if (attempt) {
    tried_sig_ = st_.signature;
    have_tried_ = true;
    // with more than nx free entries the kept ones are ranked by |Y|, then by the dual estimate
    if (try_polish(false) || (dual_ok_ && set_.polish_dual && st_.nfree > nx_ && try_polish(true))) {
      if (accept_polish()) return true;
    }
    if (!by_magnitude) {
      yfailed_[static_cast<std::size_t>(next_yfailed_)] = st_.signature;
      next_yfailed_ = (next_yfailed_ + 1) % static_cast<int>(yfailed_.size());
      n_yfailed_ = std::min(n_yfailed_ + 1, static_cast<int>(yfailed_.size()));
    }
  }
  return false;
}

// The smoothed-dual Newton candidate (called at it == next_dn_it).
bool AdmmWorkspace::polish_by_dual_newton() noexcept {
  next_dn_it_ *= 2;  // at 50, 100, 200, ... iterations: ADMM alone is slow on this problem
  // not at the endgame's iteration: the IPM is cheaper there (measured on the random suite:
  // 146 -> 356 problems certified by the IPM, p95 solve time 2.9 -> 2.0 ms)
  if (!(ipm_on_ && it_ == ipm_at_) && dual_newton()) {
    if (accept_polish()) return true;
  }
  return false;
}

// The QP polish: the candidate depends only on which entries of Y sit at a bound, once per pattern.
bool AdmmWorkspace::polish_qp_round() noexcept {
  const bool stable = have_prev_ && st_.signature == prev_sig_;
  const bool fresh = !have_tried_ || st_.signature != tried_sig_;
  prev_sig_ = st_.signature;
  have_prev_ = true;
  if (stable && fresh) {
    tried_sig_ = st_.signature;
    have_tried_ = true;
    if (qp_polish()) {
      if (accept_polish()) return true;
    }
  }
  return false;
}

// The stopping rule (paper, or residuals and the relative duality gap of Y); true stops.
bool AdmmWorkspace::check_stop() noexcept {
  AdmmInfo& info = res_.info;
  MatrixXd& X = res_.X;
  MatrixXd& U = res_.U;
  MatrixXd& Y = res_.Y;
  if (set_.stopping == StoppingRule::kPaper) {
    if (info.paper_criterion <= set_.paper_eps) {
      status_ = AdmmStatus::solved_paper_rule;
      return true;
    }
  } else if (prim_ <= info.eps_primal && dual_ <= info.eps_dual) {
    // the residuals are not an optimality test: also require the relative duality gap of Y
    if (!gap_on_) {
      status_ = AdmmStatus::solved;
      return true;
    }
    if (it_ - last_gap_it_ >= set_.gap_check_interval) {
      last_gap_it_ = it_;
      if (cond_) rollout(U, X);
      dual_at_u_ = true;
      rollout(Y, res_.X_flown);
      const double P = trajectory_objective(res_.X_flown, Y);
      const VectorXd& pm = prob_.terminal_equality ? (cond_ ? cg_ : ric_->terminal_multiplier()) : pz_;
      if (gap_within(evaluate_gap(res_.X_flown, Y, pm, P), set_.eps_gap) && terminal_miss_ratio() <= 1.0) {
        status_ = AdmmStatus::solved;
        return true;
      }
    }
  }
  return false;
}

// The interior-point endgame at ipm_at; true if its plan is certified.
bool AdmmWorkspace::ipm_endgame() noexcept {
  AdmmInfo& info = res_.info;
  if (ipm_on_ && it_ == ipm_at_) {
    // endgame: accepted only through the same gap / terminal tests; otherwise ADMM goes on
    // warm from ADMM's iterate (measured: 386 -> 390 / 391 suite problems solved), cold if that
    // fails or there is no plan yet (Y = 0)
    const bool warm = res_.Y.cwiseAbs().maxCoeff() > 0.0;
    if ((warm && ipm_solve(true)) || ipm_solve(false)) {
      info.ipm_solved = true;
      status_ = AdmmStatus::solved;
      return true;
    }
  }
  return false;
}

// Time limit and the Farkas infeasibility test; true stops.
bool AdmmWorkspace::check_limits() noexcept {
  const AdmmInfo& info = res_.info;
  const MatrixXd& Y = res_.Y;
  if (timed_ && std::chrono::duration<double>(std::chrono::steady_clock::now() - solve_start_).count() >
                    set_.time_limit) {
    status_ = AdmmStatus::time_limit;
    return true;
  }
  if (infeas_on_ && it_ % set_.infeasibility_check_interval == 0 && prim_ > info.eps_primal) {
    // Farkas candidates: the terminal multiplier (it diverges along the certificate) and the miss
    // of the flown plan, both signs
    const VectorXd& pm = cond_ ? cg_ : ric_->terminal_multiplier();
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
      status_ = AdmmStatus::primal_infeasible;
      return true;
    }
  }
  return false;
}

// Adaptive rho (OSQP's rule); true stops (a failed refactorization).
bool AdmmWorkspace::adapt_rho() noexcept {
  AdmmInfo& info = res_.info;
  if (set_.adaptive_rho && it_ % set_.adaptive_rho_interval == 0) {
    // OSQP's rule on normalized residuals; a zero residual (e.g. Y stuck at 0: no dual residual)
    // still moves rho, by at most 100x per update
    const double pn = prim_ / std::max(std::max(st_.nU, st_.nY), 1e-300);
    const double dn = dual_ / std::max(nL_, 1e-300);
    if (pn > 0.0 || dn > 0.0) {
      const double ratio = std::clamp(std::sqrt(pn / std::max(dn, 1e-300)), 1e-2, 1e2);
      const double rho_new = std::clamp(rho_ * ratio, set_.rho_min, set_.rho_max);
      if (rho_new > set_.adaptive_rho_tolerance * rho_ || rho_new < rho_ / set_.adaptive_rho_tolerance) {
        rho_ = rho_new;
        r_valid_ = false;
        ++info.rho_updates;
        if (cond_) {
          ++cond_facts_;
          cond_ = cond_factor(rho_);  // ill-conditioned at this rho: the Riccati step from here on
        }
        if (!cond_ && !ric_->factor(rho_)) {
          status_ = AdmmStatus::numerical_error;
          return true;
        }
      }
    }
  }
  return false;
}

// End of solve(): the returned iterate, objectives, gap, the inaccurate test, unscaling, the time.
void AdmmWorkspace::finish_solve() noexcept {
  AdmmInfo& info = res_.info;
  MatrixXd& X = res_.X;
  MatrixXd& U = res_.U;
  MatrixXd& Y = res_.Y;
  restore_best_or_zero();
  if (!paper_rule_ && flat_ok_) info.paper_criterion = (U - Y).norm() / dimU_;  // of the returned iterate
  info.iterations = it_;
  info.rho = rho_;
  info.condensed = cond_;
  info.factorizations += ric_->factorizations() - fact0_ + cond_facts_;
  if (prob_.terminal_equality && !info.polished && !info.ipm_solved && !ipm_only_)
    res_.terminal_multiplier = cond_ ? cg_ : ric_->terminal_multiplier();
  rollout(Y, res_.X_flown);
  if (info.polished) polished_terminal();
  if (info.ipm_solved && !prob_.terminal_equality) res_.X_flown.col(N_) = prob_.xf + ie_;  // as certified
  info.objective = trajectory_objective(res_.X_flown, Y);
  info.objective_u = trajectory_objective(X, U);
  // overflowing states (possible only with numerical_error): +inf says so, never NaN
  if (std::isnan(info.objective)) info.objective = std::numeric_limits<double>::infinity();
  if (std::isnan(info.objective_u)) info.objective_u = std::numeric_limits<double>::infinity();
  info.certified = info.polished;
  if (!((info.polished || info.ipm_solved) && gap_on_)) {
    // (a certified plan's gap was just evaluated on this same plan, flown states and multiplier)
    dual_at_u_ =
        !info.polished && !info.ipm_solved;  // X, U: the (best) x/u iterate (the plan itself for the IPM)
    const VectorXd& pm = prob_.terminal_equality ? res_.terminal_multiplier : pz_;
    evaluate_gap(res_.X_flown, Y, pm, info.objective);
  }
  check_inaccurate();
  info.status = status_;
  xtmp_ = res_.X_flown.col(N_) - prob_.xf;
  info.terminal_miss = xtmp_.norm();
  if (std::isnan(info.terminal_miss)) info.terminal_miss = std::numeric_limits<double>::infinity();
  if (scaled_) unscale_result();
  info.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - solve_start_).count();
}

// At a limit the best iterate is returned; after a numerical error the best finite one, else zero.
void AdmmWorkspace::restore_best_or_zero() noexcept {
  AdmmInfo& info = res_.info;
  MatrixXd& X = res_.X;
  MatrixXd& U = res_.U;
  MatrixXd& Y = res_.Y;
  MatrixXd& L = res_.Lambda;
  const bool at_limit = status_ == AdmmStatus::max_iterations || status_ == AdmmStatus::time_limit;
  if (at_limit && set_.track_best && std::isfinite(best_)) {
    U = bU_;
    Y = bY_;
    L = bL_;
    info.primal_residual = best_prim_;  // residuals of the returned (best) iterate
    info.dual_residual = best_dual_;
    info.paper_criterion = best_paper_;
    rollout(U, X);
  } else if (status_ == AdmmStatus::numerical_error) {
    // never a non-finite plan: the best finite iterate with its residuals, else (the failure came
    // before any finite iterate, e.g. dynamics that overflow) the zero plan, residuals infinite
    if (set_.track_best && std::isfinite(best_)) {
      U = bU_;
      Y = bY_;
      L = bL_;
      info.primal_residual = best_prim_;
      info.dual_residual = best_dual_;
      info.paper_criterion = best_paper_;
    } else {
      U.setZero();
      Y.setZero();
      L.setZero();
      info.primal_residual = std::numeric_limits<double>::infinity();
      info.dual_residual = std::numeric_limits<double>::infinity();
    }
    rollout(U, X);
  } else if ((cond_ && !info.polished) || ipm_only_) {
    rollout(U, X);  // the condensed step produces U only
  }
}

// Loose pass on the returned iterate at a limit (residual rule): residuals within
// inaccurate_factor x their tolerances (best is that ratio when tracked) and the gap within
// inaccurate_factor x eps_gap (in absolute value) -> solved_inaccurate.
void AdmmWorkspace::check_inaccurate() noexcept {
  const AdmmInfo& info = res_.info;
  const bool at_limit = status_ == AdmmStatus::max_iterations || status_ == AdmmStatus::time_limit;
  if (at_limit && set_.stopping == StoppingRule::kResiduals) {
    const double meas = set_.track_best && std::isfinite(best_)
                            ? best_
                            : std::max(info.primal_residual / std::max(info.eps_primal, 1e-300),
                                       info.dual_residual / std::max(info.eps_dual, 1e-300));
    if (meas <= set_.inaccurate_factor &&
        (!gap_on_ || gap_within(info.duality_gap, set_.inaccurate_factor * set_.eps_gap)) &&
        terminal_miss_ratio() <= set_.inaccurate_factor)
      status_ = AdmmStatus::solved_inaccurate;
  }
}

}  // namespace satgnc::guidance::detail
