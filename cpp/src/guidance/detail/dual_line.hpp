#pragma once
// Private: the exact maximizer of the L1 engines' one-parameter Fenchel dual bound
//   D(s) = c1 s - f s^2 - sum_v g_v*(-s h_v),  s in [0, smax],
// g_v(u) = w_i |u| + r_i / 2 u^2 + indicator of [lo_i, hi_i] (i = v mod nu, 0 in the box, w, r >= 0).
// D is concave and piecewise quadratic: each entry's conjugate changes form at |s h| = w (u leaves 0)
// and, with r > 0, at |s h| = w + r |bound| (u saturates). Sorting those kinks and sweeping D'(s) =
// a - b s piece by piece gives the maximizer in one pass plus a sort, where a golden-section search
// needs ~60 evaluations of D. Only the point is returned: the caller evaluates D there itself, so its
// bound stays valid (weak duality holds at every s with g* finite) whatever the sweep's rounding.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

namespace satgnc::guidance::detail {

/// A kink of D' at s: entry v, kind 1 (u leaves 0) or 2 (u reaches its bound, r > 0 only).
struct DualKink {
  double s;
  int v;
  int kind;
};

/// argmax of D on [0, smax] (see the file comment); h is nu x N (entries v = k nu + i), `kinks` a
/// buffer of at least 2 N nu entries (sized at setup: nothing is allocated here). smax must keep
/// g* finite (the caller's cap for entries without r toward an unbounded side).
inline double concave_dual_argmax(const Eigen::MatrixXd& h, const Eigen::VectorXd& w,
                                  const Eigen::VectorXd& r, const Eigen::VectorXd& lo,
                                  const Eigen::VectorXd& hi, double c1, double f, double smax,
                                  std::vector<DualKink>& kinks) noexcept {
  if (!(smax > 0.0)) return 0.0;
  const int nu = static_cast<int>(h.rows()), nv = static_cast<int>(h.size());
  const double* hv = h.data();
  // the bound that v = -s h pushes u to: hi for h < 0, lo for h > 0 (its magnitude)
  const auto bound = [&](int v) { return hv[v] < 0.0 ? hi(v % nu) : -lo(v % nu); };
  int nk = 0;
  for (int v = 0; v < nv; ++v) {
    const double ah = std::abs(hv[v]), bd = bound(v);
    if (ah == 0.0 || bd == 0.0) continue;  // g* = 0 along s: no kink
    const int i = v % nu;
    const double s1 = w(i) / ah;
    if (!(s1 < smax)) continue;
    kinks[nk++] = {s1, v, 1};
    if (r(i) > 0.0) {
      const double s2 = (w(i) + r(i) * bd) / ah;
      if (s2 < smax) kinks[nk++] = {s2, v, 2};
    }
  }
  std::sort(kinks.begin(), kinks.begin() + nk,
            [](const DualKink& x, const DualKink& y) { return x.s < y.s; });
  // D'(s) = a - b s on each piece
  double a = c1, b = 2.0 * f, s_lo = 0.0;
  for (int q = 0;; ++q) {
    const double s_hi = q < nk ? kinks[q].s : smax;
    if (a - b * s_lo <= 0.0) return s_lo;  // D' turned nonpositive at this kink
    if (b > 0.0 && a - b * s_hi <= 0.0) return std::min(std::max(a / b, s_lo), s_hi);
    if (q >= nk) return smax;
    const int v = kinks[q].v, i = v % nu;
    const double ah = std::abs(hv[v]), bd = bound(v);
    if (r(i) > 0.0) {
      // quadratic piece g* = (s|h| - w)^2 / (2r) between the kinks, linear (s|h| - w) bd - r bd^2 / 2 after
      const double sgn = kinks[q].kind == 1 ? 1.0 : -1.0;
      a += sgn * ah * w(i) / r(i);
      b += sgn * ah * ah / r(i);
      if (kinks[q].kind == 2) a -= ah * bd;
    } else {
      a -= ah * bd;  // g* = (s|h| - w) bd past the kink
    }
    s_lo = s_hi;
  }
}

}  // namespace satgnc::guidance::detail
