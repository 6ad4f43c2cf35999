// Setup-time validation and status mapping shared by the DOP853 orbital wrappers.
#include "satgnc/propagation/dop853.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::propagation {

void dop853_validate_settings(const Dop853Settings& s) {
  core::require_positive(s.rtol, "rtol");
  core::require(s.rtol < 1.0, "rtol", "must be < 1 (a relative tolerance of 100 % controls nothing)");
  core::require_nonnegative(s.atol, "atol");
  core::require(s.max_steps > 0, "max_steps", "must be > 0, got " + std::to_string(s.max_steps));
  core::require_nonnegative(s.h0, "h0");
  core::require_nonnegative(s.h_max, "h_max");
  core::require(s.safety > 1e-4 && s.safety < 1.0, "safety", "must lie in (1e-4, 1)");
  core::require(s.fac_min > 0.0 && s.fac_min <= 1.0, "fac_min", "must lie in (0, 1]");
  core::require(std::isfinite(s.fac_max) && s.fac_max >= 1.0, "fac_max", "must be finite and >= 1");
  core::require(s.beta >= 0.0 && s.beta <= 0.2, "beta", "must lie in [0, 0.2]");
  core::require(s.rtol > 10.0 * std::numeric_limits<double>::epsilon(), "rtol",
                "must exceed 10 machine epsilons (2.2e-15)", "double precision cannot deliver less");
}

// The ranges of dop853_check_settings (the integrator's own, looser than the orbit wrapper's
// dop853_validate_settings: rtol = 1 is a fixed-step run), one field at a time.
void Dop853Settings::validate() const {
  // Each message is built only on failure: the integrator's constructor calls this, and an ensemble
  // builds one integrator per member (no allocation on the success path).
  using core::require;
  if (!(std::isfinite(rtol) && rtol > 10.0 * std::numeric_limits<double>::epsilon()))
    require(false, "rtol",
            "must be finite and exceed 10 machine epsilons (2.2e-15), got " + std::to_string(rtol));
  if (!(std::isfinite(atol) && atol >= 0.0))
    require(false, "atol", "must be finite and >= 0, got " + std::to_string(atol));
  if (!(max_steps > 0)) require(false, "max_steps", "must be > 0, got " + std::to_string(max_steps));
  if (!(std::isfinite(h0) && h0 >= 0.0)) require(false, "h0", "must be finite and >= 0 (0 = automatic)");
  if (!(std::isfinite(h_max) && h_max >= 0.0))
    require(false, "h_max", "must be finite and >= 0 (0 = |t_end - t0|)");
  if (!(safety > 1e-4 && safety < 1.0)) require(false, "safety", "must lie in (1e-4, 1)");
  if (!(fac_min > 0.0 && fac_min <= 1.0)) require(false, "fac_min", "must lie in (0, 1]");
  if (!(std::isfinite(fac_max) && fac_max >= 1.0)) require(false, "fac_max", "must be finite and >= 1");
  if (!(beta >= 0.0 && beta <= 0.2)) require(false, "beta", "must lie in [0, 0.2]");
}

void dop853_validate_surface(const Vec6& x0, double surface_radius) {
  core::require_nonnegative(surface_radius, "surface_radius");
  if (surface_radius > 0.0 && !(x0.head<3>().norm() > surface_radius))
    core::require(false, "x0",
                  "starts at or below the surface: |r0| = " + std::to_string(x0.head<3>().norm()) +
                      " km <= surface_radius = " + std::to_string(surface_radius) + " km",
                  "x0 = [r km, v km/s]; surface_radius = 0 disables the surface");
}

PropagationStatus dop853_to_propagation_status(Dop853Status s) {
  switch (s) {
    case Dop853Status::success:
      return PropagationStatus::success;
    case Dop853Status::max_steps:
      return PropagationStatus::too_much_work;
    case Dop853Status::step_size_too_small:
      return PropagationStatus::error_test_failures;
    case Dop853Status::rhs_failure:
      return PropagationStatus::rhs_failure;
    case Dop853Status::event:
      return PropagationStatus::impact;
    case Dop853Status::unsolved:
    case Dop853Status::invalid_settings:
    case Dop853Status::invalid_input:
      return PropagationStatus::solver_failure;
  }
  return PropagationStatus::solver_failure;
}

}  // namespace satgnc::propagation
