// DOP853 propagation with the satgnc ForceModel (point mass + optional J2 and drag).
#include <cmath>
#include <optional>

#include "detail/force_model_accel.hpp"
#include "satgnc/core/validate.hpp"
#include "satgnc/propagation/dop853.hpp"

namespace satgnc::propagation {

Trajectory propagate_dop853(const dynamics::ForceModel& force_model, const Vec6& x0, double t0,
                            const std::vector<double>& times, const Dop853Settings& settings, bool with_stm,
                            double surface_radius) {
  force_model.validate();
  // A gravity field and the ephemeris cache evaluate into their own workspace: a private copy keeps
  // concurrent propagations of one ForceModel (the Python module releases the GIL) apart.
  std::optional<dynamics::ForceModel> own;
  if (force_model.gravity || force_model.third_body || force_model.srp || force_model.atmosphere_drag)
    own.emplace(force_model);
  return detail::with_force_model_accel(own ? *own : force_model,
                                        [&](const auto& accel, auto velocity_dependent) {
                                          return propagate_dop853_with<decltype(velocity_dependent)::value>(
                                              accel, x0, t0, times, settings, with_stm, surface_radius);
                                        });
}

}  // namespace satgnc::propagation
