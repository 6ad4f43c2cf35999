#pragma once
/// @file validate.hpp
/// Setup-time argument checks shared by every room. They throw std::invalid_argument whose
/// message names the argument, the rule and a hint; solve paths never call them.
#include <Eigen/Core>
#include <cmath>
#include <stdexcept>
#include <string>

namespace satgnc::core {

/// Throw std::invalid_argument("<name>: <rule>" + hint) unless cond holds.
inline void require(bool cond, const std::string& name, const std::string& rule,
                    const std::string& hint = "") {
  if (!cond) {
    std::string msg = name + ": " + rule;
    if (!hint.empty()) msg += " (hint: " + hint + ")";
    throw std::invalid_argument(msg);
  }
}

/// Throw unless every coefficient of x is finite. The rule text is built only on failure, so a
/// passing check does not allocate (warm starts call it between allocation-free solves).
template <typename Derived>
void require_finite(const Eigen::DenseBase<Derived>& x, const std::string& name) {
  if (!x.allFinite()) require(false, name, "must be finite (no NaN or Inf)");
}

/// Throw unless value is finite.
inline void require_finite(double value, const std::string& name) {
  require(std::isfinite(value), name, "must be finite (no NaN or Inf)");
}

/// Throw unless value is finite and > 0.
inline void require_positive(double value, const std::string& name) {
  require(std::isfinite(value) && value > 0.0, name, "must be finite and > 0, got " + std::to_string(value));
}

/// Throw unless value is finite and >= 0.
inline void require_nonnegative(double value, const std::string& name) {
  require(std::isfinite(value) && value >= 0.0, name,
          "must be finite and >= 0, got " + std::to_string(value));
}

}  // namespace satgnc::core
