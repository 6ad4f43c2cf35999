#pragma once
// Test-only analytic references for elliptic two-body motion (independent of satgnc's propagators).
#include <Eigen/Geometry>
#include <cmath>

#include "satgnc/dynamics/types.hpp"

namespace satgnc::testing {

/// State from classical elements: a km, e, angles rad (inclination, RAAN, argument of perigee, true anomaly).
inline Vec6 coe_to_state(double mu, double a, double e, double inc, double raan, double argp, double nu) {
  const double p = a * (1 - e * e);
  const double r = p / (1 + e * std::cos(nu));
  const Eigen::Vector3d rp(r * std::cos(nu), r * std::sin(nu), 0.0);
  const Eigen::Vector3d vp(-std::sqrt(mu / p) * std::sin(nu), std::sqrt(mu / p) * (e + std::cos(nu)), 0.0);
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(raan, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(inc, Eigen::Vector3d::UnitX()) *
       Eigen::AngleAxisd(argp, Eigen::Vector3d::UnitZ()))
          .toRotationMatrix();
  Vec6 x;
  x << R * rp, R * vp;
  return x;
}

/// Elliptic Kepler propagation by Kepler's equation and Lagrange f, g (dt s, any sign, many revolutions).
/// g is written without the Delta-t cancellation: g = (sin dE - e (sin E - sin E0)) / n.
inline Vec6 kepler_ellipse(const Vec6& x0, double dt, double mu) {
  const Eigen::Vector3d r0 = x0.head<3>(), v0 = x0.tail<3>();
  const double rn0 = r0.norm();
  const double a = 1.0 / (2.0 / rn0 - v0.squaredNorm() / mu);
  const double n = std::sqrt(mu / (a * a * a));
  const double ecos = 1.0 - rn0 / a;
  const double esin = r0.dot(v0) / std::sqrt(mu * a);
  const double e = std::hypot(ecos, esin);
  const double E0 = std::atan2(esin, ecos);
  const double M0 = E0 - esin;
  const double M = std::remainder(M0 + n * dt, 2.0 * M_PI);
  double E = M + e * std::sin(M);
  for (int k = 0; k < 50; ++k) {
    const double dE = (E - e * std::sin(E) - M) / (1.0 - e * std::cos(E));
    E -= dE;
    if (std::abs(dE) < 1e-16) break;
  }
  const double dE = E - E0;
  const double f = 1.0 - a / rn0 * (1.0 - std::cos(dE));
  const double g = (std::sin(dE) - e * (std::sin(E) - std::sin(E0))) / n;
  const Eigen::Vector3d r = f * r0 + g * v0;
  const double rn = r.norm();
  const double fdot = -std::sqrt(mu * a) * std::sin(dE) / (rn * rn0);
  const double gdot = 1.0 - a / rn * (1.0 - std::cos(dE));
  Vec6 x;
  x << r, fdot * r0 + gdot * v0;
  return x;
}

}  // namespace satgnc::testing
