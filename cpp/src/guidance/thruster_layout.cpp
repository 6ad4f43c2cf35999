// Thruster layout: validation and allocation (see satgnc/guidance/thruster_layout.hpp).
#include "satgnc/guidance/thruster_layout.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <utility>

#include "satgnc/core/validate.hpp"

namespace satgnc::guidance {

namespace {
std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
}  // namespace

ThrusterLayout::ThrusterLayout(std::vector<Thruster> thrusters) : thrusters_(std::move(thrusters)) {
  core::require(!thrusters_.empty(), "thrusters", "must hold at least one thruster");
  std::set<std::string> seen;
  for (std::size_t i = 0; i < thrusters_.size(); ++i) {
    Thruster& t = thrusters_[i];
    const std::string p = "thrusters[" + std::to_string(i) + "]";
    core::require_finite(t.direction, p + ".direction");
    const double norm = t.direction.norm();
    core::require(std::abs(norm - 1.0) <= kUnitTolerance, p + ".direction",
                  "must be a unit vector, got norm " + fmt(norm),
                  "divide the direction by its norm; tolerance 1e-9");
    t.direction /= norm;
    core::require_finite(t.position, p + ".position");
    core::require(std::isfinite(t.max_thrust) && t.max_thrust > 0.0, p + ".max_thrust",
                  "must be finite and > 0 N, got " + fmt(t.max_thrust));
    core::require(std::isfinite(t.min_impulse_bit) && t.min_impulse_bit >= 0.0, p + ".min_impulse_bit",
                  "must be finite and >= 0 N s, got " + fmt(t.min_impulse_bit));
    if (t.name.empty()) t.name = "T" + std::to_string(i);
    core::require(seen.insert(t.name).second, p + ".name", "must be unique, '" + t.name + "' repeats");
  }
}

Eigen::MatrixXd ThrusterLayout::allocation() const {
  Eigen::MatrixXd D(3, size());
  for (int i = 0; i < size(); ++i) D.col(i) = thrusters_[static_cast<std::size_t>(i)].direction;
  return D;
}

Eigen::MatrixXd ThrusterLayout::torque_allocation() const {
  Eigen::MatrixXd T(3, size());
  for (int i = 0; i < size(); ++i) {
    const Thruster& t = thrusters_[static_cast<std::size_t>(i)];
    T.col(i) = t.position.cross(t.direction);
  }
  return T;
}

Eigen::MatrixXd ThrusterLayout::input_matrix(const Eigen::Ref<const Eigen::MatrixXd>& B_force) const {
  core::require(B_force.cols() == 3, "B_force",
                "must have 3 columns (force components, N), got " + std::to_string(B_force.cols()));
  core::require_finite(B_force, "B_force");
  return B_force * allocation();
}

Eigen::VectorXd ThrusterLayout::max_thrust() const {
  Eigen::VectorXd v(size());
  for (int i = 0; i < size(); ++i) v(i) = thrusters_[static_cast<std::size_t>(i)].max_thrust;
  return v;
}

Eigen::VectorXd ThrusterLayout::min_impulse_bit() const {
  Eigen::VectorXd v(size());
  for (int i = 0; i < size(); ++i) v(i) = thrusters_[static_cast<std::size_t>(i)].min_impulse_bit;
  return v;
}

std::vector<std::string> ThrusterLayout::names() const {
  std::vector<std::string> n;
  n.reserve(thrusters_.size());
  for (const Thruster& t : thrusters_) n.push_back(t.name);
  return n;
}

std::vector<int> ThrusterLayout::survivors(const std::vector<int>& failed) const {
  std::vector<bool> lost(thrusters_.size(), false);
  for (std::size_t j = 0; j < failed.size(); ++j) {
    const int i = failed[j];
    const std::string p = "failed[" + std::to_string(j) + "]";
    core::require(
        i >= 0 && i < size(), p,
        "must be a thruster index in [0, " + std::to_string(size()) + "), got " + std::to_string(i));
    core::require(!lost[static_cast<std::size_t>(i)], p, "repeats thruster " + std::to_string(i));
    lost[static_cast<std::size_t>(i)] = true;
  }
  std::vector<int> keep;
  for (int i = 0; i < size(); ++i)
    if (!lost[static_cast<std::size_t>(i)]) keep.push_back(i);
  core::require(!keep.empty(), "failed", "loses every thruster (no layout survives)");
  return keep;
}

ThrusterLayout ThrusterLayout::without(const std::vector<int>& failed) const {
  std::vector<Thruster> keep;
  for (int i : survivors(failed)) keep.push_back(thrusters_[static_cast<std::size_t>(i)]);
  return ThrusterLayout(std::move(keep));
}

}  // namespace satgnc::guidance
