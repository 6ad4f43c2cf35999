#pragma once
// Private: the exact maximizer of the L1 engines' one-parameter Fenchel dual bound
//   D(s) = c1 s - f s^2 - sum_v g_v*(-s h_v),  s in [0, smax],
// g_v(u) = w_i |u| + r_i / 2 u^2 + indicator of [lo_i, hi_i] (i = v mod nu, 0 in the box, w, r >= 0).
// D is concave and piecewise quadratic: each entry's conjugate changes form at |s h| = w (u leaves 0)
// and, with r > 0, at |s h| = w + r |bound| (u saturates). A selection over those kinks gives the
// maximizer in about one pass, where a golden-section search needs ~60 evaluations of D. Only the
// point is returned: the caller evaluates D there itself, so its bound stays valid (weak duality
// holds at every s with g* finite) whatever the rounding of the breaks' running sums.
#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "quadratic.hpp"

namespace satgnc::guidance::detail {

/// argmax of D on [0, smax] (see the file comment); h is nu x N (entries v = k nu + i), `brk` a
/// buffer of at least 2 N nu entries (sized at setup: nothing is allocated here). smax must keep
/// g* finite (the caller's cap for entries without r toward an unbounded side). The kinks become
/// breaks of D' for quadratic.hpp's concave_pwq_argmax (the L1 engine's maximizer too).
inline double concave_dual_argmax(const Eigen::MatrixXd& h, const Eigen::VectorXd& w,
                                  const Eigen::VectorXd& r, const Eigen::VectorXd& lo,
                                  const Eigen::VectorXd& hi, double c1, double f, double smax,
                                  std::vector<PwlBreak>& brk) noexcept {
  if (!(smax > 0.0)) return 0.0;
  const int nu = static_cast<int>(h.rows()), nv = static_cast<int>(h.size());
  const double* hv = h.data();
  int nb = 0;
  for (int v = 0; v < nv; ++v) {
    const int i = v % nu;
    // the bound that -s h pushes u to: hi for h < 0, lo for h > 0 (its magnitude)
    const double ah = std::abs(hv[v]), bd = hv[v] < 0.0 ? hi(i) : -lo(i);
    if (ah == 0.0 || bd == 0.0) continue;  // g* = 0 along s: no kink
    const double s1 = w(i) / ah;
    if (!(s1 < smax)) continue;
    if (r(i) > 0.0) {
      // g* = (s|h| - w)^2 / (2r) from s1 (a ramp of G'), linear (s|h| - w) bd - r bd^2 / 2 from s2
      const double da = ah * w(i) / r(i), db = ah * ah / r(i);
      brk[static_cast<std::size_t>(nb++)] = PwlBreak{s1, -da, db};
      const double s2 = (w(i) + r(i) * bd) / ah;
      if (s2 < smax) brk[static_cast<std::size_t>(nb++)] = PwlBreak{s2, da + ah * bd, -db};
    } else {
      brk[static_cast<std::size_t>(nb++)] = PwlBreak{s1, ah * bd, 0.0};  // g* = (s|h| - w) bd past s1
    }
  }
  // D'(s) = c1 - 2 f s - G'(s), G'(0+) = 0 (0 lies in the box)
  return concave_pwq_argmax(c1, 2.0 * f, 0.0, 0.0, brk.data(), nb, smax);
}

}  // namespace satgnc::guidance::detail
