#include "satgnc/dynamics/polar.hpp"

#include <cmath>

#include "satgnc/core/validate.hpp"

namespace satgnc::dynamics {

PolarModel::PolarModel(double sigma, double omega) : sigma_(sigma), omega_(omega) {
  core::require_positive(sigma, "sigma");
  core::require_positive(omega, "omega");
}

PolarModel PolarModel::from_mu(double sigma, double mu) {
  core::require_positive(sigma, "sigma");
  core::require_positive(mu, "mu");
  return PolarModel(sigma, std::sqrt(mu / (sigma * sigma * sigma)));
}

PolarModel::State PolarModel::rhs(double, const State& s, const Input& u) const {
  const double r = s(0), rd = s(1), thd = s(3);
  State f;
  f(0) = rd;
  f(1) = r * thd * thd - k() / (r * r) + u(0);
  f(2) = thd;
  f(3) = (-2.0 * thd * rd + u(1)) / r;
  return f;
}

void PolarModel::jacobians(double, const State& s, const Input& u, MatA& dfds, MatB& dfdu) const {
  const double r = s(0), rd = s(1), thd = s(3);
  dfds.setZero();
  dfdu.setZero();
  dfds(0, 1) = 1.0;
  dfds(1, 0) = thd * thd + 2.0 * k() / (r * r * r);
  dfds(1, 3) = 2.0 * r * thd;
  dfds(2, 3) = 1.0;
  dfds(3, 0) = (2.0 * thd * rd - u(1)) / (r * r);
  dfds(3, 1) = -2.0 * thd / r;
  dfds(3, 3) = -2.0 * rd / r;
  dfdu(1, 0) = 1.0;
  dfdu(3, 1) = 1.0 / r;
}

PolarModel::State PolarModel::reference(double t) const { return State(sigma_, 0.0, omega_ * t, omega_); }

namespace {
// x = T (s - s_ref): the angular pair is multiplied by sigma in the paper's coordinates.
double angle_scale(double sigma, PolarCoordinates c) { return c == PolarCoordinates::scaled ? sigma : 1.0; }
}  // namespace

PolarModel::State PolarModel::to_deviation(double t, const State& s, PolarCoordinates c) const {
  State x = s - reference(t);
  x.tail<2>() *= angle_scale(sigma_, c);
  return x;
}

PolarModel::State PolarModel::from_deviation(double t, const State& x, PolarCoordinates c) const {
  State s = x;
  s.tail<2>() /= angle_scale(sigma_, c);
  return s + reference(t);
}

PolarModel::State PolarModel::deviation_rhs(double t, const State& x, const Input& u,
                                            PolarCoordinates c) const {
  const State s = from_deviation(t, x, c);
  State g = rhs(t, s, u);
  g(2) -= omega_;  // d/dt (theta - omega t)
  g.tail<2>() *= angle_scale(sigma_, c);
  return g;
}

// Derivation (general sigma). Partial derivatives of eqs. 3-4 at r = sigma, r' = 0, theta' = omega,
// u = 0:  d r''/dr = omega^2 + 2k/sigma^3 (= 3 omega^2 when k = sigma^3 omega^2),
// d r''/d theta' = 2 sigma omega,  d theta''/d r' = -2 omega / sigma,  d theta''/du2 = 1 / sigma,
// and d theta''/dr = (2 theta' r' - u2)/r^2 = 0. In deviation coordinates x = T (s - s_ref) with
// T = diag(1, 1, a, a), a = sigma (scaled) or 1 (raw): A = T J T^{-1}, B = T J_u. For a = sigma the
// sigma factors cancel, which is why the paper's sigma = 1 matrix is in fact valid for every sigma.
PolarModel::MatA PolarModel::A(PolarCoordinates c) const {
  const double a = angle_scale(sigma_, c);
  const double s3 = sigma_ * sigma_ * sigma_;
  MatA A = MatA::Zero();
  A(0, 1) = 1.0;
  A(1, 0) = omega_ * omega_ + 2.0 * k() / s3;
  A(1, 3) = 2.0 * sigma_ * omega_ / a;
  A(2, 3) = 1.0;
  A(3, 1) = a * (-2.0 * omega_ / sigma_);
  return A;
}

PolarModel::MatB PolarModel::B(PolarCoordinates c) const {
  const double a = angle_scale(sigma_, c);
  MatB B = MatB::Zero();
  B(1, 0) = 1.0;
  B(3, 1) = a / sigma_;
  return B;
}

}  // namespace satgnc::dynamics
