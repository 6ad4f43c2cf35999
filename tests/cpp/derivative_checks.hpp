#pragma once
// Shared checks of analytic derivatives in satgnc gtests: the 4th-order central-difference Jacobian of a
// 3-vector field and the block-wise relative error of 6x6 state transition matrices.
#include <algorithm>

#include "satgnc/core/types.hpp"
#include "testing.hpp"

namespace satgnc::testing {

/// Jacobian of f: R^3 -> R^3 at r by 4th-order central differences with step h.
template <typename F>
Mat3 fd4(const F& f, const Vec3& r, double h) {
  Mat3 J;
  for (int j = 0; j < 3; ++j) {
    Vec3 e = Vec3::Zero();
    e[j] = h;
    J.col(j) = (-f(r + 2 * e) + 8 * f(r + e) - 8 * f(r - e) + f(r - 2 * e)) / (12 * h);
  }
  return J;
}

/// Largest relative error over the four 3x3 blocks of two 6x6 STMs (the blocks differ by orders of
/// magnitude in their units, so each is compared on its own scale).
inline double block_rel_err(const Mat6& a, const Mat6& b) {
  double e = 0.0;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      e = std::max(e, rel_err(a.block<3, 3>(3 * i, 3 * j), b.block<3, 3>(3 * i, 3 * j)));
  return e;
}

}  // namespace satgnc::testing
