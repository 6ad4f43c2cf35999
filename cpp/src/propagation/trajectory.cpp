// Orbit-arc input checks shared by the propagators.
#include "satgnc/propagation/trajectory.hpp"

#include <cmath>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::propagation {

void validate_state_magnitude(const Vec6& x0) {
  if (!(x0.cwiseAbs().maxCoeff() < kMaxStateComponent))
    core::require(false, "x0",
                  "every component must be below 1e100 in magnitude (km, km/s): |r|^3 overflows double "
                  "precision in the force model",
                  "check the units: x0 = [r km, v km/s]");
}

void validate_orbit_arc_input(const Vec6& x0, double t0, const std::vector<double>& times,
                              const char* singular_hint) {
  core::require_finite(x0, "x0");
  core::require(x0.head<3>().norm() > 0.0, "x0", "position must be non-zero (|r0| = 0)", singular_hint);
  validate_state_magnitude(x0);
  core::require_finite(t0, "t0");
  const bool ascending = times.size() < 2 || times.front() <= times.back();
  for (std::size_t i = 0; i < times.size(); ++i) {
    core::require(std::isfinite(times[i]), "times",
                  "must be finite (no NaN or Inf), entry " + std::to_string(i) + " is not");
    core::require(i == 0 || (ascending ? times[i] >= times[i - 1] : times[i] <= times[i - 1]), "times",
                  "must be monotone (sorted increasing or decreasing), entry " + std::to_string(i) +
                      " breaks the order",
                  "sort the output times; they may lie on either side of t0");
  }
}

}  // namespace satgnc::propagation
