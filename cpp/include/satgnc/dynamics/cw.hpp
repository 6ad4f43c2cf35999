#pragma once
/// @file cw.hpp
/// Clohessy-Wiltshire (Hill) relative motion in the frame of l1_admm_rendezvous.md's published
/// implementation: y radial (outward), z orbit normal, x = y cross z (minus along-track).
///   x'' =  2 n y'            + u1 / m
///   y'' = -2 n x' + 3 n^2 y  + u2 / m
///   z'' = -n^2 z             + u3 / m
/// State [x, y, z, x', y', z'] (m, m/s), control u = force (N), mass m (kg), mean motion n (rad/s).
/// (The paper's printed eq. (27) differs from this; see docs/guidance.md and test_cw.cpp.)
/// Any consistent unit system works (e.g. the implementation's scaled units with m = 1).
#include <Eigen/Core>

#include "satgnc/core/types.hpp"

namespace satgnc::dynamics {

using Mat63 = Eigen::Matrix<double, 6, 3>;

/// Largest |n t| (rad, ~1.6e8 revolutions) accepted by the CW time functions (stm, input_integral,
/// cw_discretize_*). Rounding n t costs eps |n t| rad in every trigonometric entry: 2e-7 rad here,
/// and no correct digit at all past ~4.5e15 rad (cw_stm(t = 1e300) returned entries of 1e300).
inline constexpr double kCwMaxAngle = 1e9;

/// Continuous-time CW matrices of x' = A x + B u.
struct CwModel {
  double n = 0.0;     ///< mean motion of the target orbit (rad/s), > 0
  double mass = 1.0;  ///< chaser mass (kg), > 0

  /// Validates 1e-100 <= n <= 1e100 and mass > 0 (std::invalid_argument with a hint).
  CwModel(double mean_motion, double chaser_mass);

  Mat6 A() const;   ///< 6x6 state matrix (1/s, 1/s^2)
  Mat63 B() const;  ///< 6x3 input matrix (1/kg)
  /// Right-hand side x' = A x + B u; x (m, m/s), u (N); returns (m/s, m/s^2).
  Vec6 rhs(const Vec6& x, const Vec3& u) const;
  /// Analytic state transition matrix Phi(t) = exp(A t), t (s), any sign with |n t| <= kCwMaxAngle
  /// (std::invalid_argument naming t otherwise).
  Mat6 stm(double t) const;
  /// Analytic input integral Gamma(t) = int_0^t Phi(s) ds B (zero-order hold over t seconds),
  /// |n t| <= kCwMaxAngle.
  Mat63 input_integral(double t) const;
};

/// Frame of a CW state. paper: the frame above (y radial, z orbit normal, x = y cross z, minus
/// along-track). hill: x radial (outward), y along-track (direction of the target's velocity), z orbit
/// normal; state [x y z vx vy vz] (m, m/s).
enum class CwFrame { paper, hill };

/// Continuous-time CW matrices x' = A x + B u in one frame: A (1/s, 1/s^2), B (1/kg, control = force N).
struct CwMatrices {
  Mat6 A;
  Mat63 B;
};

/// The model's A() and B() in `frame`. The hill matrices are the paper ones with the radial and
/// along-track axes exchanged and the along-track sign flipped (hill x = paper y, hill y = -paper x):
/// the same entries, only permuted (no arithmetic; no negative zeros). No allocation.
CwMatrices cw_linear_model(const CwModel& model, CwFrame frame = CwFrame::paper);

/// Discrete model x_{k+1} = Ad x_k + Bd u_k for a zero-order-held control over dt seconds.
struct CwDiscrete {
  Mat6 Ad;
  Mat63 Bd;
};

/// Exact zero-order hold by the analytic CW state transition matrix and its input integral.
/// Each cw_discretize_* throws std::invalid_argument naming dt unless dt > 0 and |n dt| <= kCwMaxAngle.
CwDiscrete cw_discretize_zoh(const CwModel& model, double dt);
/// Exact zero-order hold by Van Loan's block matrix exponential exp([[A, B], [0, 0]] dt).
CwDiscrete cw_discretize_expm(const CwModel& model, double dt);
/// One explicit-midpoint step with u held (what the published implementation used):
/// Ad = I + dt A + dt^2 A^2 / 2, Bd = dt (I + dt A / 2) B. Second-order accurate.
CwDiscrete cw_discretize_midpoint(const CwModel& model, double dt);

/// Matrix exponential of a square matrix (scaling and squaring with a degree-18 Taylor
/// polynomial; relative accuracy ~1e-15 for the small well-scaled matrices used here).
Eigen::MatrixXd expm(const Eigen::MatrixXd& M);

}  // namespace satgnc::dynamics
