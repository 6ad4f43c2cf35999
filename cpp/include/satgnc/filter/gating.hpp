#pragma once
/// @file gating.hpp
/// Chi-square quantiles for the Mahalanobis gate, computed without scipy: the regularized lower
/// incomplete gamma function P(a, x) (series for x < a + 1, Lentz continued fraction otherwise) and
/// its inverse by a Wilson-Hilferty start refined by Halley's method to full double precision.
/// Setup-time functions (they throw on bad input).

namespace satgnc::filter {

/// Regularized lower incomplete gamma P(a, x) = gamma(a, x) / Gamma(a), a > 0, x >= 0 (relative
/// accuracy ~1e-15). Throws std::invalid_argument on a <= 0, x < 0 or non-finite input.
double regularized_gamma_p(double a, double x);

/// Chi-square quantile: the x with P(dof / 2, x / 2) = probability. dof > 0 (integer or not),
/// probability in (0, 1) (open). Throws std::invalid_argument("probability: must be in (0, 1) ...")
/// or ("dof: ..."). Accuracy: |P(x) - p| <= 1e-14 (Halley to convergence).
double chi_square_quantile(double dof, double probability);

}  // namespace satgnc::filter
