// Orbit-arc input checks shared by the propagators.
#include "satgnc/propagation/trajectory.hpp"

#include <cmath>
#include <cstdio>
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

namespace {

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

std::string entry(std::size_t i, double t) { return "times[" + std::to_string(i) + "] = " + fmt(t); }

// Whether b may follow a: in increasing (ascending) or decreasing order, strictly or not. Comparisons,
// not the sign of (b - a) * dir as CVODES's check had it (the two agree on finite input).
bool ordered(double a, double b, bool ascending, bool strict) {
  if (strict) return ascending ? b > a : b < a;
  return ascending ? b >= a : b <= a;
}

}  // namespace

void validate_orbit_arc_input(const Vec6& x0, double t0, const std::vector<double>& times, ArcRules rules,
                              const char* singular_hint) {
  // Every check is `if (!ok) throw`, so the success path builds no string and allocates nothing.
  using core::require;
  core::require_finite(x0, "x0");
  if (!(x0.head<3>().squaredNorm() > 0.0))
    require(false, "x0", "position must be non-zero (|r0| = 0)",
            singular_hint != nullptr ? singular_hint : "");
  validate_state_magnitude(x0);
  if (!std::isfinite(t0)) require(false, "t0", "must be finite (no NaN or Inf)");
  if (rules.non_empty && times.empty())
    require(false, "times", "must not be empty", "give at least one output time, s");
  for (std::size_t i = 0; i < times.size(); ++i)
    if (!std::isfinite(times[i]))
      require(false, "times", "must be finite (no NaN or Inf), times[" + std::to_string(i) + "] is not");
  if (times.empty()) return;
  bool ascending = times.front() <= times.back();
  if (rules.one_sided) {
    ascending = times.back() >= t0;  // the direction of propagation
    if (ascending ? times.front() < t0 : times.front() > t0)
      require(false, "times",
              "must all lie on one side of t0 (forward or backward), times[0] = " + fmt(times.front()) +
                  ", t0 = " + fmt(t0),
              "propagate the arcs before and after t0 in two calls");
  }
  for (std::size_t i = 1; i < times.size(); ++i)
    if (!ordered(times[i - 1], times[i], ascending, rules.strict))
      require(false, "times",
              std::string(rules.strict ? "must be strictly monotone (sorted, no duplicates)"
                                       : "must be monotone (sorted increasing or decreasing)") +
                  (rules.one_sided ? " in the direction of propagation" : "") + ", " +
                  entry(i - 1, times[i - 1]) + ", " + entry(i, times[i]),
              rules.one_sided ? "increasing after t0, decreasing before it"
                              : "sort the output times; they may lie on either side of t0");
}

}  // namespace satgnc::propagation
