#pragma once
// Shared set-up of the two-satellite tests: a circular 853 km target orbit (SI units) and a chaser
// released tens of metres away with a small relative velocity.
#include <cmath>

#include "satgnc/dynamics/two_satellite.hpp"

namespace satgnc::testing {

constexpr double kMu = 3.99e14;  ///< m^3/s^2, the scenario's value
constexpr double kR = 7231.0e3;  ///< target orbit radius, m

/// x = [d = r_t - r_c (m), r_t (m), w = v_t - v_c (m/s), v_t (m/s)].
inline dynamics::Vec12 release_state() {
  dynamics::Vec12 x;
  x << 20.0, 30.0, 10.0, kR, 0.0, 0.0, 0.4, 0.6, -0.1, 0.0, std::sqrt(kMu / kR), 0.0;
  return x;
}

}  // namespace satgnc::testing
