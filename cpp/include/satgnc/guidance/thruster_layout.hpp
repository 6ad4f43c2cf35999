#pragma once
/// @file thruster_layout.hpp
/// A chaser's thruster layout and its allocation: each thruster pushes along a fixed unit direction
/// with a nonnegative thrust T_i in [0, max_thrust_i] (N), so the force on the chaser is
/// F = D T (N), D = [d_1 ... d_m] (3 x m), and the L1 cost sum_i T_i dt of a plan whose controls are
/// the thrusts is its fuel (total impulse, N s; delta-v = impulse / mass).
///
/// Body frame: for now the chaser's body axes are held aligned with the target's CW frame of the
/// rendezvous scenario (the paper frame: y radial, z orbit normal, x = y cross z), so the
/// directions are given in that frame. Positions (m, body frame, from the centre of mass) give the
/// torque arms (torque_allocation); the translational allocation does not use them.
///
/// Usage:
///   ThrusterLayout layout(thrusters);             // validates (std::invalid_argument)
///   Eigen::MatrixXd Bt = layout.input_matrix(B);  // B (nx x 3, per newton of force) -> nx x m
///   ThrusterLayout s = layout.without({2, 5});    // the survivors after thrusters 2 and 5 fail
#include <Eigen/Core>
#include <string>
#include <vector>

#include "satgnc/core/types.hpp"

namespace satgnc::guidance {

/// One thruster.
struct Thruster {
  Vec3 direction = Vec3::UnitX();  ///< unit thrust direction (the force on the chaser), body frame
  Vec3 position = Vec3::Zero();    ///< thruster position from the centre of mass, m, body frame
  double max_thrust = 1.0;         ///< largest thrust, N (> 0)
  double min_impulse_bit = 0.0;    ///< smallest impulse one firing can give, N s (>= 0; 0 = none)
  std::string name;                ///< label for tables (default "T<index>")
};

/// Validated layout of m >= 1 thrusters.
class ThrusterLayout {
 public:
  /// Tolerance on |direction| - 1 accepted by the constructor (directions are then normalized).
  static constexpr double kUnitTolerance = 1e-9;

  /// Validate every thruster: direction finite with | |d| - 1 | <= kUnitTolerance, position finite,
  /// max_thrust finite and > 0, min_impulse_bit finite and >= 0; names unique (empty -> "T<i>").
  /// @throws std::invalid_argument("thrusters[i].<field>: rule (hint: ...)")
  explicit ThrusterLayout(std::vector<Thruster> thrusters);

  /// Number of thrusters m.
  int size() const { return static_cast<int>(thrusters_.size()); }
  /// The thrusters as validated (directions normalized).
  const std::vector<Thruster>& thrusters() const { return thrusters_; }
  /// D (3 x m): force (N) per newton of each thruster's thrust, body frame.
  Eigen::MatrixXd allocation() const;
  /// Torque per newton of thrust, r_i x d_i (3 x m, N m per N), body frame.
  Eigen::MatrixXd torque_allocation() const;
  /// B_force * D (nx x m): the input matrix whose controls are the thrusts (N).
  /// @throws std::invalid_argument if B_force does not have 3 columns or is not finite
  Eigen::MatrixXd input_matrix(const Eigen::Ref<const Eigen::MatrixXd>& B_force) const;
  /// Upper bounds of the thrusts (m, N).
  Eigen::VectorXd max_thrust() const;
  /// Minimum impulse bits (m, N s).
  Eigen::VectorXd min_impulse_bit() const;
  /// Names (m).
  std::vector<std::string> names() const;
  /// Indices of the thrusters left when those in `failed` are lost (ascending).
  /// @throws std::invalid_argument on an index out of range or repeated, or if none survives
  std::vector<int> survivors(const std::vector<int>& failed) const;
  /// The layout of the survivors (names kept).
  ThrusterLayout without(const std::vector<int>& failed) const;

 private:
  std::vector<Thruster> thrusters_;
};

}  // namespace satgnc::guidance
