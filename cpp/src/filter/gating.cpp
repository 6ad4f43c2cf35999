// Chi-square quantiles for the gate: regularized incomplete gamma P(a, x) and its inverse.
// P: series sum x^a e^-x / Gamma(a+1) * sum x^k / ((a+1)...(a+k)) for x < a + 1, else
// 1 - Q with Q from the modified-Lentz continued fraction (the standard split, e.g. Press et al.,
// Numerical Recipes, section 6.2). Inverse: Wilson-Hilferty start, then Halley iterations on
// P(a, x) - p (dP/dx = x^(a-1) e^-x / Gamma(a)).
#include "satgnc/filter/gating.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::filter {

namespace {

double gamma_series(double a, double x) {
  double sum = 1.0 / a;
  double term = sum;
  for (int k = 1; k < 10000; ++k) {
    term *= x / (a + k);
    sum += term;
    if (std::fabs(term) < std::fabs(sum) * 1e-17) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

double gamma_cf_q(double a, double x) {
  const double tiny = 1e-300;
  double b = x + 1.0 - a;
  double c = 1.0 / tiny;
  double d = 1.0 / b;
  double h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < 1e-17) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

double p_unchecked(double a, double x) {
  if (x <= 0.0) return 0.0;
  return x < a + 1.0 ? gamma_series(a, x) : 1.0 - gamma_cf_q(a, x);
}

}  // namespace

double regularized_gamma_p(double a, double x) {
  core::require(std::isfinite(a) && a > 0.0, "a", "must be finite and > 0, got " + std::to_string(a));
  core::require(std::isfinite(x) && x >= 0.0, "x", "must be finite and >= 0, got " + std::to_string(x));
  return p_unchecked(a, x);
}

double chi_square_quantile(double dof, double probability) {
  core::require(std::isfinite(dof) && dof > 0.0, "dof", "must be finite and > 0, got " + std::to_string(dof));
  core::require(std::isfinite(probability) && probability > 0.0 && probability < 1.0, "probability",
                "must be in (0, 1), got " + std::to_string(probability));
  const double a = 0.5 * dof;
  // Wilson-Hilferty: chi2_p ~ dof (1 - 2/(9 dof) + z sqrt(2/(9 dof)))^3, z the normal quantile
  // (Acklam-free: a few Newton steps on the normal CDF via erfc).
  double zq = 0.0;
  for (int i = 0; i < 50; ++i) {
    const double cdf = 0.5 * std::erfc(-zq / std::sqrt(2.0));
    const double pdf = std::exp(-0.5 * zq * zq) / std::sqrt(2.0 * 3.14159265358979323846);
    const double step = (cdf - probability) / pdf;
    zq -= step;
    if (std::fabs(step) < 1e-14 * (1.0 + std::fabs(zq))) break;
  }
  const double c = 2.0 / (9.0 * dof);
  double x = dof * std::pow(std::max(1.0 - c + zq * std::sqrt(c), 0.1), 3);  // chi-square value
  // Halley on F(u) = P(a, u) - p with u = x / 2.
  double u = 0.5 * x;
  for (int i = 0; i < 100; ++i) {
    const double f = p_unchecked(a, u) - probability;
    const double logpdf = (a - 1.0) * std::log(u) - u - std::lgamma(a);
    const double fp = std::exp(logpdf);
    if (!(fp > 0.0)) break;
    const double newton = f / fp;
    const double fpp_over_fp = (a - 1.0) / u - 1.0;
    double step = newton / (1.0 - 0.5 * newton * fpp_over_fp);
    if (!std::isfinite(step)) step = newton;
    double un = u - step;
    if (un <= 0.0) un = 0.5 * u;
    const double change = std::fabs(un - u);
    u = un;
    if (change <= 1e-15 * u) break;
  }
  return 2.0 * u;
}

}  // namespace satgnc::filter
