#pragma once
/// @file earth_rotation.hpp
/// The orientation of the Earth-fixed frame seen by a propagation. Force models that live in the
/// Earth-fixed frame (a gravity field, a co-rotating atmosphere) take it through this interface, so a
/// propagation can run on the paper's uniform rotation or on the full IAU 2006/2000A chain with EOP.
#include "satgnc/core/constants.hpp"
#include "satgnc/core/types.hpp"

namespace satgnc::frames {

/// Orientation of the Earth-fixed frame (ITRF) with respect to the inertial frame of a propagation
/// (GCRF), as a function of t: seconds after the propagation's epoch. Implementations are immutable:
/// rotation() is const, thread-safe, allocates nothing and does not throw (a propagation's right-hand
/// side calls it at every stage).
class EarthRotationModel {
 public:
  virtual ~EarthRotationModel() = default;
  /// At t (s after the epoch): the rotation with r_itrf = gcrf_to_itrf * r_gcrf, and the angular
  /// velocity of ITRF with respect to GCRF, expressed in GCRF (rad/s), so that
  /// v_itrf = gcrf_to_itrf * (v_gcrf - omega_gcrf x r_gcrf).
  virtual void rotation(double t, Mat3& gcrf_to_itrf, Vec3& omega_gcrf) const noexcept = 0;
};

/// Uniform rotation about the inertial +z axis by the angle theta0 + omega t: the Gao-Luo paper's
/// model and the GMST-only one (no precession, nutation or polar motion).
class UniformRotation final : public EarthRotationModel {
 public:
  /// theta0: angle of the Earth-fixed x axis from the inertial x axis at t = 0 (rad); omega (rad/s).
  /// Throws std::invalid_argument naming the argument unless both are finite.
  explicit UniformRotation(double theta0 = 0.0, double omega = core::earth::omega);
  void rotation(double t, Mat3& gcrf_to_itrf, Vec3& omega_gcrf) const noexcept override;
  double theta0() const { return theta0_; }  ///< rad
  double omega() const { return omega_; }    ///< rad/s

 private:
  double theta0_;
  double omega_;
};

}  // namespace satgnc::frames
