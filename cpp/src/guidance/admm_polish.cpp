// Polish of the ADMM solver: the active-set polish (Y pattern or dual guess, with local repairs),
// the QP polish and the smoothed-dual Newton candidates; each accepted only with its certificate.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "detail/admm_workspace.hpp"

namespace satgnc::guidance::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

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
bool AdmmWorkspace::try_polish(bool rank_by_dual) noexcept {
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
int AdmmWorkspace::dual_candidate(std::uint64_t& signature) noexcept {
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
bool AdmmWorkspace::polish_swaps(int& F) noexcept {
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
bool AdmmWorkspace::polish_solve(int F) noexcept {
  const bool term = prob_.terminal_equality;
  viol_j_ = -1;
  bad_a_ = -1;
  const int M = polish_build_kkt(F);
  if (!solve_dense_in_place(KKT_, rhs_, sol_, M)) return false;
  bool fail = polish_unpack(F);
  if (polish_optimality_violated()) fail = true;
  if (fail) return false;
  accept_polished(term);
  return true;
}

// The compact KKT system of the candidate (free entries, then nx more unknowns) in KKT_, rhs_;
// returns its size F + nx.
int AdmmWorkspace::polish_build_kkt(int F) noexcept {
  const bool term = prob_.terminal_equality;
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
  return M;
}

// The solved free entries into Up_ (true if one lies outside its sign / box: the furthest is
// remembered in bad_a_, bad_val_ for a repair), then the terminal costate pN_ and the gradient.
bool AdmmWorkspace::polish_unpack(int F) noexcept {
  const bool term = prob_.terminal_equality;
  bool fail = false;
  double bad_out = 0.0;
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
  return fail;
}

// The L1 / box optimality conditions of the candidate in Up_ with the gradient grad_; true if one
// fails (the most violated fixed entry, the one a swap would free, in viol_j_, viol_sign_).
bool AdmmWorkspace::polish_optimality_violated() noexcept {
  const double tol = set_.polish_tolerance * (scaled_ ? w_.maxCoeff() : std::max(1.0, w_.maxCoeff()));
  bool fail = false;
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
        // a bound at 0 blocks one side of the kink: only the other side's condition applies
        const bool at_lo = lo_(i) == 0.0, at_hi = hi_(i) == 0.0;
        v = at_lo && at_hi ? -std::numeric_limits<double>::infinity()
                           : (at_lo ? -gk - w : (at_hi ? gk - w : std::abs(gk) - w));
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
  return fail;
}

// Store the certified polish candidate Up_ (with its gradient and terminal multiplier) as the result.
void AdmmWorkspace::accept_polished(bool term) noexcept {
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
bool AdmmWorkspace::qp_polish() noexcept {
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
bool AdmmWorkspace::dual_newton() noexcept {
  const bool term = prob_.terminal_equality;
  dn_e_ = xN0_ - prob_.xf;
  const double curv = dn_curvature();
  if (!(curv > 0.0) || !std::isfinite(curv)) return false;
  dn_nu_ = cg_;  // condensed step: Qf e (soft) or the terminal multiplier (hard)
  int steps = 0;
  constexpr int kMaxSteps = 120;
  double eps = curv;
  for (int level = 0; level < 14 && steps < kMaxSteps; ++level, eps *= 0.1) {
    for (int t = 0; t < 30 && steps < kMaxSteps; ++t, ++steps) {
      const int r = dn_newton_step(eps);
      if (r < 0) return false;
      if (r > 0) break;
    }
    const int F = dn_candidate(eps);
    if (F == 0 || (term && F < nx_)) continue;
    ++res_.info.polish_attempts;
    if (polish_solve(F)) return true;
  }
  return false;
}

// Mean curvature of the smooth part along the N nu axes (the first smoothing eps).
double AdmmWorkspace::dn_curvature() noexcept {
  const bool term = prob_.terminal_equality;
  const Eigen::Index n = static_cast<Eigen::Index>(N_) * nu_;
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
  return curv;
}

// The smoothed dual D(nu) at eps; s = M' nu and the minimizer u(nu) into dn_s_, dn_u_.
double AdmmWorkspace::dn_evaluate(const VectorXd& nu, double eps) noexcept {
  const bool term = prob_.terminal_equality;
  const Eigen::Index n = static_cast<Eigen::Index>(N_) * nu_;
  {
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
  }
}

// One damped Newton step on nu at eps: 0 moved, 1 converged or stalled (next level), -1 failed.
int AdmmWorkspace::dn_newton_step(double eps) noexcept {
  const bool term = prob_.terminal_equality;
  const Eigen::Index n = static_cast<Eigen::Index>(N_) * nu_;
  {
    {
      const double D0 = dn_evaluate(dn_nu_, eps);
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
      if (!dn_d_.allFinite()) return -1;
      const double slope = dn_g_.dot(dn_d_);
      double step = 1.0;
      bool moved = false;
      for (int ls = 0; ls < 40; ++ls, step *= 0.5) {
        dn_t_ = dn_nu_ + step * dn_d_;
        const VectorXd& trial = dn_t_;
        dn_g_ = trial;  // keep the trial point (evaluate overwrites dn_t_ in the soft case)
        if (dn_evaluate(dn_g_, eps) >= D0 + 1e-4 * step * slope) {
          dn_nu_ = dn_g_;
          moved = true;
          break;
        }
      }
      if (!moved || step * dn_d_.norm() <= 1e-13 * std::max(dn_nu_.norm(), 1e-300)) return 1;
    }
  }
  return 0;
}

// The polish candidate at eps: entries strictly inside (0, bound) free, the others fixed at 0 or
// the bound (Up_, free_idx_, fsign_); returns the free count, 0 if none or more than fit.
int AdmmWorkspace::dn_candidate(double eps) noexcept {
  const Eigen::Index n = static_cast<Eigen::Index>(N_) * nu_;
  {
    dn_evaluate(dn_nu_, eps);
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
    return fits ? F : 0;
  }
}

void AdmmWorkspace::polished_terminal() noexcept {
  // soft terminal: the polish solved the terminal error e = x_N - x_f as an unknown, to full relative
  // precision; the rolled-out x_N carries rounding of order eps |x_N(0)|, which swamps e when Qf is
  // large (and with it the dual bound built from Qf e). Same plan, exact-arithmetic terminal state.
  if (!prob_.terminal_equality) res_.X_flown.col(N_) = prob_.xf + pe_;
}

}  // namespace satgnc::guidance::detail
