#pragma once
// Shared helpers for satgnc gtests: relative-tolerance comparisons in the style of heyoka's approximately().
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace satgnc::testing {

/// Relative error |a - b| / max(|b|, floor), the floor guarding comparisons with zero.
inline double rel_err(double a, double b, double floor = 1e-300) {
  return std::abs(a - b) / std::max(std::abs(b), floor);
}

/// Max-norm relative error of two arrays: ||a - b||_inf / max(||b||_inf, floor).
template <typename A, typename B>
double rel_err(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b, double floor = 1e-300) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), floor);
}

}  // namespace satgnc::testing

/// EXPECT that a and b agree to relative tolerance tol (scalars or Eigen arrays).
#define SATGNC_EXPECT_REL(a, b, tol) \
  EXPECT_LE(::satgnc::testing::rel_err((a), (b)), (tol)) << "a = " << (a) << "\nb = " << (b)
