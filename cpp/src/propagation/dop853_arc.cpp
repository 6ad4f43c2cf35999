// Allocation-free single DOP853 arc on a ForceModel (propagation/dop853_arc.hpp): the dispatch and
// arc runner of propagate_dop853, with caller-owned outputs.
#include "satgnc/propagation/dop853_arc.hpp"

#include "detail/force_model_accel.hpp"

namespace satgnc::propagation {

Dop853Info propagate_dop853_arc(const dynamics::ForceModel& force_model, const Vec6& x0, double t0,
                                const double* times, std::size_t n, const Dop853Settings& settings,
                                Vec6* states, Mat6* stms) {
  Dop853Info info;
  detail::with_force_model_accel(force_model, [&](const auto& accel, auto velocity_dependent) {
    constexpr bool vd = decltype(velocity_dependent)::value;
    if (stms != nullptr)
      detail::run_arc<true, vd>(accel, x0, t0, times, n, settings, states, stms, info, 0.0);
    else
      detail::run_arc<false, vd>(accel, x0, t0, times, n, settings, states, nullptr, info, 0.0);
    return 0;
  });
  return info;
}

}  // namespace satgnc::propagation
