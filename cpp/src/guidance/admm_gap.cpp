// Optimality and infeasibility certificates of the ADMM solver (see admm.hpp, AdmmInfo): the
// Lagrangian gradient by one backward costate sweep, the Fenchel dual bound and its relative gap,
// the Farkas test of an unreachable terminal state under box bounds, and the workspace estimate.
#include <algorithm>
#include <cmath>
#include <limits>

#include "detail/admm_workspace.hpp"

namespace satgnc::guidance::detail {

using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

double AdmmWorkspace::estimate_workspace_bytes(int nx, int nu, int N) noexcept {
  // per stage: Riccati (P, K, closed-loop A and A', Quu^-1, Quu^-1 B', Z, affine terms), the ADMM
  // iterates, best / warm copies, the condensed / polish matrices and the flat per-entry arrays
  const double n = nx, m = nu;
  const double per_stage =
      6.0 * n * n + 5.0 * n * m + m * m + 8.0 * n + 30.0 * m +
      (3.0 * n * m + m * m + 2.0 * n + 41.0 * m);  // + the interior-point arrays (and checkpoint)
  return 8.0 * (per_stage * (static_cast<double>(N) + 1.0) + 64.0 * (n + m) * (n + m) + 512.0 * n * n);
}

double AdmmWorkspace::lagrangian_gradient(const Eigen::Ref<const MatrixXd>& X,
                                          const Eigen::Ref<const MatrixXd>& U,
                                          const Eigen::Ref<const VectorXd>& p, bool with_cost) noexcept {
  const LtvDynamics& d = prob_.dynamics;
  double f = 0.0;
  lam_ = p;
  if (with_cost) {
    xtmp_ = X.col(N_) - prob_.xf;
    xtmp2_.noalias() = prob_.Qf * xtmp_;
    f += 0.5 * xtmp_.dot(xtmp2_);
    lam_ += xtmp2_;
  }
  const bool stage_q = with_cost && prob_.Q.size() != 0;
  const bool stage_r = with_cost && rf_on_;
  const bool cw63 = nx_ == 6 && nu_ == 3;
  for (int k = N_ - 1; k >= 0; --k) {
    if (ipm_cw_) {
      // on the CW blocks (ipm_setup_cw): the fixed-size products below without their exact zeros,
      // the kept terms in Eigen's order for a 6-long SSE2 dot (lanes {0,2,4}, {1,3,5}, each
      // first + (second + third), then lane 0 + lane 1), so the sums are bitwise the same
      const double* l = lam_.data();
      double* h = Hg_.col(k).data();
      for (int c = 0; c < 2; ++c) {
        const double* b = cwB4_ + 4 * c;
        h[c] = (b[0] * l[0] + b[3] * l[4]) + (b[1] * l[1] + b[2] * l[3]);
      }
      h[2] = cwB2_[0] * l[2] + cwB2_[1] * l[5];
    } else if (cw63) {
      // fixed-size products (the dynamic ones were a library call each, 2 N per sweep)
      Hg_.col(k).noalias() = Eigen::Map<const Eigen::Matrix<double, 6, 3>>(d.B_at(k).data()).transpose() *
                             Eigen::Map<const Eigen::Matrix<double, 6, 1>>(lam_.data());
    } else {
      Hg_.col(k).noalias() = d.B_at(k).transpose() * lam_;
    }
    if (stage_r) {
      utmp_.noalias() = Rf_ * U.col(k);
      f += 0.5 * U.col(k).dot(utmp_);
      Hg_.col(k) += utmp_;
    }
    if (k == 0) break;
    if (ipm_cw_) {
      const double* l = lam_.data();
      double* o = lam2_.data();
      for (int a = 0; a < 4; ++a) {
        const double* c = cwA4_ + 4 * a;
        o[kCwIn[a]] = (c[0] * l[0] + c[3] * l[4]) + (c[1] * l[1] + c[2] * l[3]);
      }
      for (int a = 0; a < 2; ++a) o[kCwOut[a]] = cwA2_[2 * a] * l[2] + cwA2_[1 + 2 * a] * l[5];
    } else if (cw63) {
      Eigen::Map<Eigen::Matrix<double, 6, 1>>(lam2_.data()).noalias() =
          Eigen::Map<const Eigen::Matrix<double, 6, 6>>(d.A_at(k).data()).transpose() *
          Eigen::Map<const Eigen::Matrix<double, 6, 1>>(lam_.data());
    } else {
      lam2_.noalias() = d.A_at(k).transpose() * lam_;
    }
    lam_ = lam2_;
    if (stage_q) {
      xtmp_ = X.col(k) - prob_.xf;
      xtmp2_.noalias() = prob_.Q * xtmp_;
      f += 0.5 * xtmp_.dot(xtmp2_);
      lam_ += xtmp2_;
    }
  }
  return f;
}

// g*(z) at z = -s Hg_: per entry sup over [lo, hi] of z u - r/2 u^2 - w |u| (r the part of R moved
// into g, diagonal), per stage for group-L2 (+ ball).
double AdmmWorkspace::conj_g(double s) const noexcept {
  double total = 0.0;
  if (has_group_ || has_ball_) {
    const double wg = prob_.group_l2_weight, umax = prob_.u_norm_max;
    for (int k = 0; k < N_; ++k) {
      double n2 = 0.0;
      for (int i = 0; i < nu_; ++i) {
        const double z = -s * Hg_(i, k);
        const double e = z - std::clamp(z, -w_(i), w_(i));  // part outside the L1 dual box
        n2 += e * e;
      }
      const double nz = std::sqrt(n2);
      if (has_ball_) {
        total += umax * std::max(0.0, nz - wg);
      } else if (nz > wg) {
        return kInf;
      }
    }
    return total;
  }
  for (int k = 0; k < N_; ++k) {
    for (int i = 0; i < nu_; ++i) {
      const double z = -s * Hg_(i, k), w = w_(i), lo = lo_(i), hi = hi_(i), r = rg_(i);
      if (r > 0.0) {
        const double v = z > w ? z - w : (z < -w ? z + w : 0.0);
        const double u = std::clamp(v / r, lo, hi);
        total += z * u - 0.5 * r * u * u - w * std::abs(u);
        continue;
      }
      // concave piecewise linear: the sup is at lo, hi or 0 (if inside); infinite toward an open side
      if ((z > w && hi == kInf) || (z < -w && lo == -kInf)) return kInf;
      double best = -kInf;
      if (hi < kInf) best = std::max(best, z * hi - w * std::abs(hi));
      if (lo > -kInf) best = std::max(best, z * lo - w * std::abs(lo));
      if (lo <= 0.0 && hi >= 0.0) best = std::max(best, 0.0);
      total += best;
    }
  }
  return total;
}

double AdmmWorkspace::conj_g_flat(double s) noexcept {
  const Eigen::Map<const Eigen::ArrayXd> h(Hg_.data(), gbuf_.size());
  const double ns = -s;
  gbuf_ = (im4_ > 0.5).select(ns * h * hifin_ - gch_, -kInf);
  gbuf_ = gbuf_.max((im3_ > 0.5).select(ns * h * lofin_ - gcl_, -kInf));
  gbuf_ = gbuf_.max((gzok_ > 0.5).select(Eigen::ArrayXd::Zero(gbuf_.size()), -kInf));
  double total = 0.0;
  for (Eigen::Index j = 0; j < gbuf_.size(); ++j) total += gbuf_(j);  // conj_g's summation order
  return total;
}

double AdmmWorkspace::evaluate_gap(const Eigen::Ref<const MatrixXd>& X, const Eigen::Ref<const MatrixXd>& U,
                                   const Eigen::Ref<const VectorXd>& p, double P) noexcept {
  // two dual candidates: residuals at the plan Y, and at the x/u iterate U, whose Lagrangian gradient
  // is -(Lambda + rho (U - Y_prev)), nearly inside the dual box of g by construction
  double best = dual_bound(X, U, p);
  if (dual_at_u_) best = std::max(best, dual_bound(res_.X, res_.U, p));
  AdmmInfo& info = res_.info;
  if (std::isnan(best)) best = -kInf;  // overflowing states: no bound (a valid one, never NaN)
  info.primal_objective = std::isnan(P) ? kInf : P;
  info.dual_objective = best;
  const double denom = std::max({std::abs(P), std::abs(best), set_.gap_floor});
  const double gap = denom > 0.0 ? (P - best) / denom : 0.0;
  info.duality_gap = std::isfinite(gap) && std::isfinite(P) && std::isfinite(best) ? gap : kInf;
  return info.duality_gap;
}

double AdmmWorkspace::dual_bound(const Eigen::Ref<const MatrixXd>& X, const Eigen::Ref<const MatrixXd>& U,
                                 const Eigen::Ref<const VectorXd>& p, bool golden) noexcept {
  const double f = lagrangian_gradient(X, U, p, true);
  double c1 = 2.0 * f;
  for (int k = 0; k < N_; ++k) c1 -= Hg_.col(k).dot(U.col(k));
  if (prob_.terminal_equality) {
    xtmp_ = X.col(N_) - prob_.xf;
    c1 += p.dot(xtmp_);
  }
  // L1 + box without R in g: the vectorized conjugate (finite on [0, smax], where D is evaluated)
  const bool flat = flat_ok_ && !has_group_ && !has_ball_ && (rg_.array() == 0.0).all() && Hg_.allFinite();
  const auto D = [&](double s) { return -s * s * f + s * c1 - (flat ? conj_g_flat(s) : conj_g(s)); };
  // largest s with g* finite (bisection: finiteness is monotone in s), capped at 2
  double smax = 2.0;
  if (!has_group_ && !has_ball_) {
    // per entry without R the sup in g* is infinite once s |h| > w toward an open side: the bound
    // in closed form (one pass instead of 60 bisection passes); rounding at the bound falls back
    for (int k = 0; k < N_; ++k)
      for (int i = 0; i < nu_; ++i) {
        const double h = Hg_(i, k);
        if (rg_(i) > 0.0 || h == 0.0) continue;
        if ((h < 0.0 && hi_(i) == kInf) || (h > 0.0 && lo_(i) == -kInf))
          smax = std::min(smax, w_(i) / std::abs(h));
      }
  }
  if (!std::isfinite(conj_g(smax))) {
    double a = 0.0, b = smax;
    for (int t = 0; t < 60; ++t) {
      const double m = 0.5 * (a + b);
      (std::isfinite(conj_g(m)) ? a : b) = m;
    }
    smax = a;
  }
  double best = D(0.0);
  if (smax > 0.0 && flat && !golden) {
    // piecewise quadratic: its maximizer exactly (was a golden-section search: 52 evaluations of D)
    best = std::max(best, D(dual_argmax_pwq(f, c1, smax)));
  } else if (smax > 0.0) {
    best = std::max(best, dual_max_golden(f, c1, smax));
  }
  if (!std::isfinite(best)) best = D(0.0);  // D(0) = -g*(0) = 0 for g >= 0 with g(0) = 0
  return best;
}

double AdmmWorkspace::dual_max_golden(double f, double c1, double smax) const noexcept {
  const auto D = [&](double s) { return -s * s * f + s * c1 - conj_g(s); };
  constexpr double g = 0.6180339887498949;
  double a = 0.0, b = smax;
  double x1 = b - g * (b - a), x2 = a + g * (b - a);
  double f1 = D(x1), f2 = D(x2);
  double best = std::max({D(smax), f1, f2});
  for (int t = 0; t < 50 && b - a > 1e-12 * smax; ++t) {
    if (f1 < f2) {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + g * (b - a);
      f2 = D(x2);
      best = std::max(best, f2);
    } else {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - g * (b - a);
      f1 = D(x1);
      best = std::max(best, f1);
    }
  }
  return best;
}

// D'(s) = -2 f s + c1 - G'(s), G(s) = sum_j g_j*(-s h_j) for L1 + box without R in g. Per entry, z =
// -s h moves away from 0 in the direction sigma = -sign h; the maximizer of z u - w |u| over the box
// is u = clamp(0, lo, hi) while |z| < w and the bound on the side of sigma beyond, so G_j'(s) = -h u
// is a step: |h| psi0 from s = 0 (psi0 = clamp(0, L, H), [L, H] the box seen along sigma: [lo, hi]
// or [-hi, -lo]), up by |h| (H - psi0) >= 0 at s = w / |h| (an open side there ends [0, smax]).
// The jumps are nonnegative, so their running sums lose no digits. With R in g the derivative has
// ramps, whose ends subtract what their starts added: in the running sums that cancellation lost
// the bound's digits when the ramps' slopes h^2 / r spanned many decades (measured on the QPs of
// test_admm_dual), so that case keeps the golden-section search.
double AdmmWorkspace::dual_argmax_pwq(double f, double c1, double smax) noexcept {
  double a = 0.0;  // G'(0+)
  int nb = 0;
  for (int k = 0; k < N_; ++k) {
    for (int i = 0; i < nu_; ++i) {
      const double h = Hg_(i, k);
      if (h == 0.0) continue;
      const double ah = std::abs(h), w = w_(i);
      const double L = h < 0.0 ? lo_(i) : -hi_(i), H = h < 0.0 ? hi_(i) : -lo_(i);
      const double psi0 = std::clamp(0.0, L, H);
      a += ah * psi0;
      if (!(H < kInf && H > psi0)) continue;
      const double t = w / ah, jump = ah * (H - psi0);
      if (t <= 0.0) {
        a += jump;
      } else if (t < smax) {
        brk_[static_cast<std::size_t>(nb++)] = PwlBreak{t, jump, 0.0};
      }
    }
  }
  return concave_pwq_argmax(c1, 2.0 * f, a, 0.0, brk_.data(), nb, smax);
}

bool AdmmWorkspace::check_infeasible(const Eigen::Ref<const VectorXd>& y) noexcept {
  const double ny = y.norm();
  if (!(ny > 0.0) || !std::isfinite(ny)) return false;
  ycand_ = y / ny;
  lagrangian_gradient(res_.X, res_.U, ycand_, false);  // Hg_ = M' y
  // support of the box along m = M' y: sum_j max(lo_j m_j, hi_j m_j), infinite toward an open side
  double sigma = 0.0;
  for (int k = 0; k < N_; ++k) {
    for (int i = 0; i < nu_; ++i) {
      const double m = Hg_(i, k);
      if (m > 0.0) {
        if (hi_(i) == kInf) return false;
        sigma += m * hi_(i);
      } else if (m < 0.0) {
        if (lo_(i) == -kInf) return false;
        sigma += m * lo_(i);
      }
    }
  }
  xtmp_ = prob_.xf - xN0all_;
  const double b = ycand_.dot(xtmp_);
  if (!(b - sigma > 1e-9 * (std::abs(b) + std::abs(sigma))) || !(b - sigma > 0.0)) return false;
  res_.infeasibility_certificate = ycand_;
  return true;
}

}  // namespace satgnc::guidance::detail
