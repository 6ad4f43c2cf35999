#pragma once
// Private: the pieces shared by the two interior-point methods of the guidance room, the L1 / box
// endgame of AdmmSolver (admm_ipm.cpp) and the state-constrained StateIpm (state_ipm.cpp). Their
// Newton systems differ (StateIpm carries per-node state Hessians, NT-scaled cones and an equality
// Schur complement), so the Riccati recursions stay apart; what is the same is shared here.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <utility>

namespace satgnc::guidance::detail::ipm {

/// Mehrotra's centering parameter sigma = (aff / cur)^3 clipped to [0, 1], where aff and cur are the
/// complementarity after the full affine (predictor) step and at the current point, in the same
/// normalization (sums, or means over the same count).
inline double mehrotra_sigma(double aff, double cur) noexcept {
  return std::pow(std::clamp(aff / std::max(cur, 1e-300), 0.0, 1.0), 3.0);
}

/// Fraction of the step to the boundary taken, from Mehrotra's sigma: 1 - clamp(sigma / 10, 1e-6, 1e-2).
/// 0.99 while the corrector centres; up to 1 - 1e-6 once the affine step predicts the end (sigma -> 0),
/// where a fixed 0.99 cuts every residual by exactly 100 per step and the stopping test waits a step or
/// two more (docs/guidance.md, session 10 (q11b); docs/guidance_safety.md, session 11 (a16)).
inline double fraction_to_boundary(double sigma) noexcept {
  return 1.0 - std::clamp(0.1 * sigma, 1e-6, 1e-2);
}

/// Cholesky factorization of a stage Hessian H (in place in `llt`). Near the end of an interior-point
/// run the barrier terms span many decades and H may lose definiteness to rounding: on failure the
/// diagonal is shifted by shift x (max |H_ii| + floor), shift = shift0, 100 shift0, ... while shift <=
/// shift_max (H keeps the shift). False when no shift in that range gives a factorization.
template <class Llt, class Matrix>
bool llt_with_shift(Llt& llt, Matrix& H, double shift0, double shift_max, double floor) noexcept {
  llt.compute(H);
  for (double shift = shift0; llt.info() != Eigen::Success; shift *= 100.0) {
    if (shift > shift_max) return false;
    H.diagonal().array() += shift * (H.diagonal().cwiseAbs().maxCoeff() + floor);
    llt.compute(H);
  }
  return true;
}

/// Inverse of a symmetric 3 x 3 matrix by its LDL' factorization (lower triangle read; false where a
/// pivot is <= 0 or NaN, where Eigen's LLT fails). No square roots and one division per pivot: the
/// Riccati recursion is latency-bound, and this chain is on its critical path (Cholesky with three
/// square roots and six divisions was ~130 cycles of dependent latency per stage).
template <typename M, typename Out>
bool ldl_inverse3(const M& a, Out& inv) noexcept {
  const double d0 = a(0, 0);
  if (!(d0 > 0.0)) return false;
  if (a(2, 0) == 0.0 && a(2, 1) == 0.0) {
    // third axis decoupled (the Clohessy-Wiltshire out-of-plane control): the same numbers without
    // the terms that are exact zeros (up to the sign of a zero), and its pivot's division no longer
    // waits for the other two (two dependent divisions instead of three)
    const double d2 = a(2, 2);
    if (!(d2 > 0.0)) return false;
    const double i2 = 1.0 / d2, i0 = 1.0 / d0;
    const double l10 = a(1, 0) * i0, d1 = a(1, 1) - l10 * a(1, 0);
    if (!(d1 > 0.0)) return false;
    const double i1 = 1.0 / d1, m10 = -l10;
    inv(2, 2) = i2;
    inv(1, 2) = inv(2, 1) = inv(0, 2) = inv(2, 0) = 0.0;
    inv(1, 1) = i1;
    inv(0, 1) = inv(1, 0) = m10 * i1;
    inv(0, 0) = i0 + m10 * m10 * i1;
    return true;
  }
  const double i0 = 1.0 / d0;
  const double l10 = a(1, 0) * i0, l20 = a(2, 0) * i0;
  const double d1 = a(1, 1) - l10 * a(1, 0);
  if (!(d1 > 0.0)) return false;
  const double i1 = 1.0 / d1;
  const double c21 = a(2, 1) - l20 * a(1, 0);
  const double l21 = c21 * i1;
  const double d2 = a(2, 2) - l20 * a(2, 0) - l21 * c21;
  if (!(d2 > 0.0)) return false;
  const double i2 = 1.0 / d2;
  // M = L^-1 (unit lower), inverse = M' D^-1 M
  const double m10 = -l10, m21 = -l21, m20 = -l20 - l21 * m10;
  inv(2, 2) = i2;
  inv(1, 2) = inv(2, 1) = m21 * i2;
  inv(0, 2) = inv(2, 0) = m20 * i2;
  inv(1, 1) = i1 + m21 * m21 * i2;
  inv(0, 1) = inv(1, 0) = m10 * i1 + m20 * m21 * i2;
  inv(0, 0) = i0 + m10 * m10 * i1 + m20 * m20 * i2;
  return true;
}

/// ldl_inverse3 of the stage Hessian a, shifted on failure as llt_with_shift does (the diagonal by
/// shift x (max |a_ii| + floor), shift = shift0, 100 shift0, ... while shift <= shift_max; a keeps the
/// shift): near the end of an interior-point run the barrier terms span many decades and the stage
/// Hessian may lose definiteness to rounding. False past shift_max.
template <typename M, typename Out>
bool ldl_inverse3_shifted(M& a, Out& inv, double shift0, double shift_max, double floor) noexcept {
  for (double shift = shift0; !ldl_inverse3(a, inv); shift *= 100.0) {
    if (shift > shift_max) return false;
    a.diagonal().array() += shift * (a.diagonal().cwiseAbs().maxCoeff() + floor);
  }
  return true;
}

/// out (R x C) = X (R x K) Y (K x C) on column-major arrays (mode 0), out += (mode 1), out -= (mode -1):
/// each column of out as axpys over the columns of X, compile-time sizes (the loops unroll and vectorize
/// without reordering a sum; Eigen's fixed-size products of Maps were not inlined at these sizes).
template <int R, int K, int C, int Mode = 0>
inline void mm(const double* X, const double* Y, double* out) noexcept {
  for (int j = 0; j < C; ++j) {
    double acc[R] = {};
    for (int l = 0; l < K; ++l) {
      const double y = Y[l + K * j];
      for (int i = 0; i < R; ++i) acc[i] += X[i + R * l] * y;
    }
    for (int i = 0; i < R; ++i) {
      if constexpr (Mode == 0) out[i + R * j] = acc[i];
      if constexpr (Mode == 1) out[i + R * j] += acc[i];
      if constexpr (Mode == -1) out[i + R * j] -= acc[i];
    }
  }
}

/// out (C x R) = X' for X (R x C), column-major arrays.
template <int R, int C>
inline void transpose(const double* X, double* out) noexcept {
  for (int j = 0; j < C; ++j)
    for (int i = 0; i < R; ++i) out[j + C * i] = X[i + R * j];
}

/// The step x += a dx for each (x, dx) pair of the primal-dual iterate.
template <class X, class DX, class... Rest>
void take_step(double a, X&& x, const DX& dx, Rest&&... rest) noexcept {
  x += a * dx;
  if constexpr (sizeof...(Rest) > 0) take_step(a, std::forward<Rest>(rest)...);
}

}  // namespace satgnc::guidance::detail::ipm
