#pragma once
/// @file two_satellite.hpp
/// Nonlinear two-satellite (chaser + target) rendezvous model of Le Cleac'h & Manchester, eq. (33):
/// both bodies in an Earth-centred inertial frame under point-mass gravity, optional J2 and
/// exponential drag, the chaser also under a control force. SI units throughout (m, m/s, N, kg, s),
/// unlike the orbit-level ForceModel (km).
///
/// State (12), as in the scenario's published implementation:
///   x = [d = r_t - r_c (m), r_t (m), w = v_t - v_c (m/s), v_t (m/s)]
/// where r_c, v_c are the chaser's and r_t, v_t the target's inertial position and velocity.
/// Control (3): chaser force, N, either in the inertial frame or in the target's CW frame (the
/// implementation's choice: e_y = r_t/|r_t| radial, e_z = e_y x v_t / |.| orbit normal,
/// e_x = e_y x e_z, i.e. minus along-track).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "satgnc/core/types.hpp"

namespace satgnc::dynamics {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat12x3 = Eigen::Matrix<double, 12, 3>;

/// Frame in which the control force u is given.
enum class ControlFrame {
  inertial = 0,   ///< u is the inertial (ECI) force on the chaser
  target_cw = 1,  ///< u in the target's CW frame [e_x, e_y, e_z] (radial e_y, normal e_z)
};

/// Sign of the atmosphere rotation in the drag's relative velocity.
enum class AtmosphereRotation {
  /// v_rel = v - omega x r: the atmosphere co-rotates with the Earth. This is the physical
  /// convention and what the paper's eq. (32) writes (v_rel = pdot + p x omega = v - omega x r).
  co_rotating = 0,
  /// v_rel = v + omega x r: what the published implementation computes (counter-rotating); kept
  /// only for reproduction. At the scenario's altitude the density is ~3e-16 kg/m^3 and the
  /// difference is below 1e-9 m over the 1 h drift.
  published = 1,
};

/// Physical parameters of the two-satellite model. Defaults are the scenario's (l1_scenario.md).
struct TwoSatelliteParams {
  double mu = 3.99e14;               ///< gravitational parameter, m^3/s^2
  bool j2_on = false;                ///< include the J2 zonal term for both bodies
  double j2 = 1.0826266835e-3;       ///< unnormalized J2, dimensionless
  double j2_radius = 6378.1363e3;    ///< equatorial radius used by J2, m
  bool drag_on = true;               ///< include drag for both bodies
  double rho0 = 9.201e-5;            ///< density at h = 0, kg/m^3 (SMAD "min" fit)
  double density_decay = 5.301e-5;   ///< density = rho0 exp(-decay h), 1/m
  double density_radius = 6731.0e3;  ///< h = |r| - density_radius, m (the implementation's 6731 km)
  Vec3 omega = Vec3(0.0, 0.0, 2.0 * 3.14159265358979323846 / 86164.0);  ///< Earth rate, rad/s
  AtmosphereRotation atmosphere = AtmosphereRotation::co_rotating;
  double mass_chaser = 4.6;   ///< kg
  double mass_target = 4.6;   ///< kg
  double cd_chaser = 1.0;     ///< drag coefficient
  double cd_target = 1.0;     ///< drag coefficient
  double area_chaser = 0.01;  ///< m^2
  double area_target = 0.01;  ///< m^2
  ControlFrame control_frame = ControlFrame::target_cw;

  /// Throw std::invalid_argument naming the field on non-positive mu, masses, areas, etc.
  void validate() const;
};

/// Continuous model xdot = f(x, u) with analytic Jacobians. Stateless apart from its parameters.
class TwoSatelliteModel {
 public:
  /// Validates params (throws std::invalid_argument).
  explicit TwoSatelliteModel(const TwoSatelliteParams& params = TwoSatelliteParams());

  const TwoSatelliteParams& params() const { return p_; }

  /// xdot = f(x, u); x as documented above (m, m/s), u in N. Returns false (xdot untouched or
  /// partially written) when a radius is zero or a result is non-finite.
  bool rhs(const Vec12& x, const Vec3& u, Vec12& xdot) const;
  /// xdot and the Jacobians A = df/dx (12x12) and B = df/du (12x3, 1/kg).
  bool rhs_jacobians(const Vec12& x, const Vec3& u, Vec12& xdot, Mat12& A, Mat12x3& B) const;

  /// One explicit Runge-Kutta step of length h (s) with u held constant. scheme: 3 = Kutta's RK3
  /// (the published implementation's "rk3": k3 at x - k1 + 2 k2, weights 1/6, 4/6, 1/6), 4 = classic
  /// RK4. If A, B are non-null they receive the exact derivatives of the discrete map (the stages
  /// differentiated, not finite differences). Returns false on a model failure.
  bool rk_step(int scheme, double h, const Vec12& x, const Vec3& u, Vec12& x_next, Mat12* A = nullptr,
               Mat12x3* B = nullptr) const;

  /// Acceleration of one body (gravity + J2 + drag, no control), m/s^2, and optionally its Jacobians.
  bool body_acceleration(const Vec3& r, const Vec3& v, double cd_area_over_mass, Vec3& a,
                         Mat3* da_dr = nullptr, Mat3* da_dv = nullptr) const;

  /// Rotation R (columns e_x, e_y, e_z) from the target's CW frame to the inertial frame.
  static bool cw_frame(const Vec3& r_t, const Vec3& v_t, Mat3& R);

 private:
  // The nonzero 3x3 blocks of df/dx and df/du (rows w' and v_t'; the others are 0 or I).
  struct JacobianBlocks {
    Mat3 wd, ww, wr, wv;  // dw'/dd, dw'/dw, dw'/dr_t, dw'/dv_t
    Mat3 vr, vv;          // dv_t'/dr_t, dv_t'/dv_t
    Mat3 wu;              // dw'/du
  };
  bool rhs_blocks(const Vec12& x, const Vec3& u, Vec12& xdot, JacobianBlocks& J) const;
  bool rk_step_jacobian(int scheme, double h, const Vec12& x, const Vec3& u, Vec12& x_next, Mat12& A,
                        Mat12x3& B) const;
  // cw_frame and d(R u)/dr_t, d(R u)/dv_t for the CW control frame.
  static bool cw_frame_derivatives(const Vec3& r_t, const Vec3& v_t, const Vec3& u, Mat3& R, Mat3& dRu_dr,
                                   Mat3& dRu_dv);
  TwoSatelliteParams p_;
};

/// Chaser relative to target in the CW frame of l1_scenario.md: p = R^T (r_c - r_t) (m) and
/// v = R^T (v_c - v_t) - omega_f x p (m/s) with the frame rate omega_f = (r_t x v_t) / |r_t|^2
/// expressed in the CW frame (the exact rotation rate of the target's radial/normal frame).
Vec6 cw_relative_state(const Vec12& x);

/// The same conversion as the published implementation's full_to_cw (for reproduction only): the
/// frame rate is taken along the CHASER's angular momentum (inertial components, applied to the CW
/// components) with magnitude sqrt(mu / |r_t|^3). Differs from cw_relative_state by ~1e-4 m/s.
Vec6 cw_relative_state_published(const Vec12& x, double mu);

/// Inverse of cw_relative_state: given the target's inertial state and the chaser's CW state,
/// the 12-state x.
Vec12 two_satellite_state(const Vec3& r_t, const Vec3& v_t, const Vec6& cw);

}  // namespace satgnc::dynamics
