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
