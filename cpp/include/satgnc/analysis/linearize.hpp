#pragma once
/// @file linearize.hpp
/// Linear models x' = A x + B u, y = C x: a generic linearizer (analytic Jacobians checked against
/// central finite differences), unit scaling (dimensionless units), the Clohessy-Wiltshire model in a
/// Hill frame, the polar model of satgnc/dynamics/polar.hpp, and the linear model of the
/// orbit-determination problem (two-body A(t), range / range-rate partials).
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "satgnc/dynamics/polar.hpp"

namespace satgnc::analysis {

/// Continuous-time LTI model x' = A x + B u, y = C x. B or C may have zero columns / rows.
struct LinearModel {
  Eigen::MatrixXd A;  ///< n x n
  Eigen::MatrixXd B;  ///< n x m
  Eigen::MatrixXd C;  ///< p x n
  /// Throw std::invalid_argument unless A is square and finite, B has n rows, C has n columns.
  void validate() const;
};

/// Units for nondimensionalization: physical x = diag(state) x~, t = time t~, u = diag(input) u~,
/// y = diag(output) y~. Then A~ = time Dx^-1 A Dx, B~ = time Dx^-1 B Du, C~ = Dy^-1 C Dx.
/// Empty input / output vectors mean unit scales.
struct Units {
  double time = 1.0;       ///< s per dimensionless time unit (e.g. 1 / omega)
  Eigen::VectorXd state;   ///< unit of each state component (size n)
  Eigen::VectorXd input;   ///< unit of each input (size m or empty)
  Eigen::VectorXd output;  ///< unit of each output (size p or empty)
};

/// The model in the units `u` (validated: positive finite scales of matching sizes).
LinearModel nondimensionalize(const LinearModel& model, const Units& u);

/// Polar model units: time 1/omega (s), length sigma (km): states [sigma, sigma omega, sigma,
/// sigma omega] (paper's scaled coordinates), inputs sigma omega^2 (km/s^2); outputs: lengths.
Units polar_units(double sigma, double omega, int n_outputs = 0);
/// CW units: time 1/n (s), length `length` (m): states [L, L, L, L n, L n, L n], inputs L n^2.
Units cw_units(double mean_motion, double length, int n_outputs = 0);

/// x' = f(t, x, u) with x in R^n, u in R^m.
using ModelFn = std::function<Eigen::VectorXd(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u)>;
/// Analytic Jacobians A = df/dx (n x n), B = df/du (n x m), written into A and B.
using JacobianFn = std::function<void(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                      Eigen::MatrixXd& A, Eigen::MatrixXd& B)>;

/// Central finite-difference settings. Step for component j: rel_step * max(|z_j|, scale_j).
struct FdSettings {
  double rel_step = 6.0554544523933395e-06;  ///< cbrt(machine epsilon): optimal for central FD
  Eigen::VectorXd x_scale;                   ///< typical magnitude of each state (empty: 1)
  Eigen::VectorXd u_scale;                   ///< typical magnitude of each input (empty: 1)
};

/// Central finite-difference Jacobians of f at (t, x, u); A is n x n, B is n x m.
void fd_jacobian(const ModelFn& f, double t, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                 Eigen::MatrixXd& A, Eigen::MatrixXd& B, const FdSettings& fd = {});

/// Linearization with its finite-difference check.
struct Linearization {
  Eigen::MatrixXd A, B;        ///< analytic Jacobians
  Eigen::MatrixXd A_fd, B_fd;  ///< central finite differences
  double rel_err_A = 0.0;      ///< max |A - A_fd| / max(max|A|, tiny)
  double rel_err_B = 0.0;      ///< same for B
};

/// Linearize f about (t, x, u) with the analytic jac and check it against central differences.
/// Throws std::invalid_argument on non-finite points or Jacobians of the wrong shape.
Linearization linearize(const ModelFn& f, const JacobianFn& jac, double t, const Eigen::VectorXd& x,
                        const Eigen::VectorXd& u, const FdSettings& fd = {});

/// The polar model's LinearModel (A, B from PolarModel; C = measured rows of the identity: e.g.
/// {0, 2} for the paper's radius and angle).
LinearModel polar_linear_model(const dynamics::PolarModel& m, const std::vector<int>& measured = {0, 2},
                               dynamics::PolarCoordinates c = dynamics::PolarCoordinates::scaled);

/// Clohessy-Wiltshire model in a Hill frame: x radial (outward), y along-track (direction of the
/// target's velocity), z orbit normal (angular momentum). State [x y z vx vy vz] (m, m/s), inputs
/// thrust accelerations [ax ay az] (m/s^2), mean motion n (rad/s):
///   x'' = 3 n^2 x + 2 n y' + ax,  y'' = -2 n x' + ay,  z'' = -n^2 z + az.
/// C = rows of the identity for `measured` (default: the three relative-position components).
/// Built from dynamics::CwModel(n, 1 kg) by dynamics::cw_linear_model(..., CwFrame::hill): the same
/// entries as the paper-frame model, permuted. Throws std::invalid_argument naming mean_motion unless
/// n > 0 (and, from CwModel, n in [1e-100, 1e100] rad/s), or naming measured on a bad index.
LinearModel cw_model(double mean_motion, const std::vector<int>& measured = {0, 1, 2});

/// Two-body variational matrix A(t) = [[0, I], [mu/r^3 (3 r r^T / r^2 - I), 0]] at position r (km).
Eigen::Matrix<double, 6, 6> two_body_jacobian(const Eigen::Vector3d& r, double mu);

/// Range rho = |r - R| (km) and its partial d rho / d[r v] (1 x 6): a thin wrapper of
/// dynamics::predict_measurement (satgnc/dynamics/measurement.hpp, the one measurement model) that
/// throws std::invalid_argument naming r when the satellite coincides with the station (rho = 0).
double range_partial(const Eigen::Vector3d& r, const Eigen::Vector3d& R, Eigen::Matrix<double, 1, 6>& H);
/// Range rate rho' = (r - R).(v - V) / rho (km/s) and its partial d rho' / d[r v] (1 x 6); wrapper of
/// dynamics::predict_measurement as range_partial (same exception at rho = 0).
double range_rate_partial(const Eigen::Vector3d& r, const Eigen::Vector3d& v, const Eigen::Vector3d& R,
                          const Eigen::Vector3d& V, Eigen::Matrix<double, 1, 6>& H);

}  // namespace satgnc::analysis
