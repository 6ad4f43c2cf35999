#pragma once
/// @file polar.hpp
/// Planar unit-mass satellite in polar coordinates (Purwanti, Supriatna & Anggriani, eqs. 3-4):
///   r''     = r theta'^2 - k / r^2 + u1          (u1 radial thrust acceleration, km/s^2)
///   theta'' = -2 theta' r' / r + u2 / r          (u2 tangential thrust acceleration, km/s^2)
/// With u = 0 and k = sigma^3 omega^2 the circle r = sigma, theta = omega t is a solution.
/// Units: r km, r' km/s, theta rad, theta' rad/s, k km^3/s^2 (any consistent set works, e.g.
/// sigma = omega = 1 for the paper's dimensionless case).
#include <Eigen/Core>

namespace satgnc::dynamics {

/// Deviation coordinates about the circular reference.
enum class PolarCoordinates {
  /// Paper's choice: x = [r - sigma, r', sigma (theta - omega t), sigma (theta' - omega)]
  /// (km, km/s, km, km/s). Here A and B come out independent of sigma.
  scaled,
  /// x = [r - sigma, r', theta - omega t, theta' - omega] (km, km/s, rad, rad/s): sigma stays in
  /// A(1,3) = 2 sigma omega, A(3,1) = -2 omega / sigma, B(3,1) = 1 / sigma. Similar to `scaled`
  /// through diag(1, 1, sigma, sigma).
  raw,
};

/// Polar model about the circular orbit of radius sigma (km) and rate omega (rad/s).
class PolarModel {
 public:
  using State = Eigen::Vector4d;  ///< [r km, r' km/s, theta rad, theta' rad/s]
  using Input = Eigen::Vector2d;  ///< [u1 radial, u2 tangential] km/s^2
  using MatA = Eigen::Matrix4d;
  using MatB = Eigen::Matrix<double, 4, 2>;

  /// sigma > 0 (km), omega > 0 (rad/s), finite; throws std::invalid_argument otherwise.
  PolarModel(double sigma, double omega);
  /// Circular orbit of radius sigma (km) about a body of gravitational parameter mu (km^3/s^2).
  static PolarModel from_mu(double sigma, double mu);

  double sigma() const { return sigma_; }                                  ///< km
  double omega() const { return omega_; }                                  ///< rad/s
  double k() const { return sigma_ * sigma_ * sigma_ * omega_ * omega_; }  ///< km^3/s^2

  /// Nonlinear right-hand side ds/dt (eqs. 3-4). r must be nonzero (returns NaN-free only for r != 0).
  State rhs(double t, const State& s, const Input& u) const;
  /// Analytic Jacobians df/ds (4x4) and df/du (4x2) of rhs.
  void jacobians(double t, const State& s, const Input& u, MatA& dfds, MatB& dfdu) const;

  /// Reference solution [sigma, 0, omega t, omega] at time t (s).
  State reference(double t) const;
  /// Deviation x from the reference at time t, in the chosen coordinates.
  State to_deviation(double t, const State& s, PolarCoordinates c = PolarCoordinates::scaled) const;
  /// Inverse of to_deviation.
  State from_deviation(double t, const State& x, PolarCoordinates c = PolarCoordinates::scaled) const;
  /// Nonlinear dynamics written in deviation coordinates: dx/dt = g(t, x, u), g(t, 0, 0) = 0.
  State deviation_rhs(double t, const State& x, const Input& u,
                      PolarCoordinates c = PolarCoordinates::scaled) const;

  /// Analytic linearization A = dg/dx at x = 0, u = 0 (general sigma; derived in polar.cpp).
  MatA A(PolarCoordinates c = PolarCoordinates::scaled) const;
  /// Analytic input matrix B = dg/du at x = 0, u = 0.
  MatB B(PolarCoordinates c = PolarCoordinates::scaled) const;

 private:
  double sigma_;
  double omega_;
};

}  // namespace satgnc::dynamics
