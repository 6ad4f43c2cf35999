#pragma once
// Private helpers of the guidance room (not installed).
#include <Eigen/Core>
#include <algorithm>
#include <utility>

namespace satgnc::guidance::detail {

/// 1/2 (x - t)' W (x - t) by loops: W * (x - t) inside an expression would allocate a temporary,
/// and the solvers call this inside their allocation-free solve().
inline double half_weighted_error(const Eigen::MatrixXd& W, const Eigen::Ref<const Eigen::VectorXd>& x,
                                  const Eigen::VectorXd& t) noexcept {
  const Eigen::Index n = x.size();
  double c = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double ej = x(j) - t(j);
    if (ej == 0.0) continue;
    double row = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) row += W(i, j) * (x(i) - t(i));
    c += ej * row;
  }
  return 0.5 * c;
}

/// One breakpoint of a piecewise-linear derivative: for s > t the derivative grows by da + db s.
struct PwlBreak {
  double t = 0.0, da = 0.0, db = 0.0;
};

/// Maximizer over [0, smax] of a concave piecewise quadratic D whose derivative is
/// D'(s) = c - e s - (a + b s) - sum over the breaks with t_j < s of (da_j + db_j s),
/// nonincreasing in s (the caller's breaks lie in (0, smax); a + b s is the derivative's part that
/// applies from s = 0). A selection over the breakpoints (expected O(n), no sort; `br` is reordered
/// in place): each round takes a pivot breakpoint, sums the breaks at or below it and keeps the side
/// where D' changes sign. Exact up to the rounding of the running sums of (da, db): breaks that
/// undo earlier ones (the end of a ramp) cancel digits there, jumps (db = 0, da >= 0) do not. The
/// caller evaluates D itself at the result, so the maximizer's accuracy is never the bound's validity.
inline double concave_pwq_argmax(double c, double e, double a, double b, PwlBreak* br, int n,
                                 double smax) noexcept {
  double lo = 0.0, hi = smax;
  int first = 0, last = n;
  while (first < last) {
    // median of three as the pivot: the breaks come in stage order, often nearly monotone
    const double t0 = br[first].t, t1 = br[first + (last - first) / 2].t, t2 = br[last - 1].t;
    const double piv = std::max(std::min(t0, t1), std::min(std::max(t0, t1), t2));
    // [first, m1): t < piv; [m1, m2): t == piv; [m2, last): t > piv
    double sa = 0.0, sb = 0.0;
    int m1 = first;
    for (int q = first; q < last; ++q)
      if (br[q].t < piv) {
        std::swap(br[q], br[m1]);
        sa += br[m1].da;
        sb += br[m1].db;
        ++m1;
      }
    int m2 = m1;
    for (int q = m1; q < last; ++q)
      if (br[q].t == piv) {
        std::swap(br[q], br[m2]);
        sa += br[m2].da;
        sb += br[m2].db;
        ++m2;
      }
    if (c - e * piv - ((a + sa) + (b + sb) * piv) > 0.0) {  // D' > 0 just above the pivot
      lo = piv;
      a += sa;
      b += sb;
      first = m2;
    } else {
      hi = piv;
      last = m1;
    }
  }
  // no breakpoint in (lo, hi): D' = c - a - (e + b) s there
  const double slope = e + b;
  if (slope > 0.0) return std::clamp((c - a) / slope, lo, hi);
  return c - a > 0.0 ? hi : lo;
}

}  // namespace satgnc::guidance::detail
