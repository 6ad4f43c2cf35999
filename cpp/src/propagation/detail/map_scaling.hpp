#pragma once
// Private to the propagation room: the diagonal scaling checks shared by TwoSatelliteMap and
// PropagatedTwoSatelliteMap (state 12 entries, m or m/s per unit; control 3 entries, N per unit).
#include <Eigen/Core>

#include "satgnc/core/validate.hpp"
#include "satgnc/dynamics/two_satellite.hpp"

namespace satgnc::propagation::detail {

/// sx = state_scale and su = control_scale, or ones where a scale is empty. Throws
/// std::invalid_argument naming state_scale / control_scale on a wrong size or an entry that is not
/// finite and > 0.
inline void set_map_scaling(const Eigen::VectorXd& state_scale, const Eigen::VectorXd& control_scale,
                            dynamics::Vec12& sx, Vec3& su) {
  using core::require;
  require(state_scale.size() == 0 || state_scale.size() == 12, "state_scale",
          "must be empty or have 12 entries");
  require(control_scale.size() == 0 || control_scale.size() == 3, "control_scale",
          "must be empty or have 3 entries");
  sx.setOnes();
  su.setOnes();
  if (state_scale.size() == 12) sx = state_scale;
  if (control_scale.size() == 3) su = control_scale;
  require(sx.allFinite() && (sx.array() > 0.0).all(), "state_scale", "entries must be finite and > 0");
  require(su.allFinite() && (su.array() > 0.0).all(), "control_scale", "entries must be finite and > 0");
}

}  // namespace satgnc::propagation::detail
