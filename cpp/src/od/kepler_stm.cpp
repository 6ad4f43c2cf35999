#include <cmath>

#include "satgnc/core/validate.hpp"
#include "satgnc/od/propagator.hpp"
#include "satgnc/propagation/kepler.hpp"

namespace satgnc::od {

KeplerStmPropagator::KeplerStmPropagator(double mu) : mu_(mu) { core::require_positive(mu, "mu"); }

bool KeplerStmPropagator::propagate(const Vec6& x0, const double* times, int n, Vec6* states, Mat6* stms) {
  for (int i = 0; i < n; ++i)
    if (propagation::kepler_step(x0, times[i], mu_, states[i], &stms[i]) !=
        propagation::KeplerStatus::success)
      return false;
  return true;
}

CvodesStmPropagator::CvodesStmPropagator(const dynamics::ForceModel& model,
                                         const propagation::CvodesSettings& settings)
    : prop_(model, [&] {
        auto s = settings;
        s.with_stm = true;
        return s;
      }()) {}

bool CvodesStmPropagator::propagate(const Vec6& x0, const double* times, int n, Vec6* states, Mat6* stms) {
  // CVODES returns x0 and the identity for t = 0; it wants strictly monotone times on one side.
  t_.assign(times, times + n);
  try {
    prop_.propagate(x0, 0.0, t_, out_);
  } catch (const std::exception&) {
    return false;
  }
  if (out_.status != propagation::PropagationStatus::success ||
      out_.states.size() != static_cast<std::size_t>(n) || out_.stms.size() != static_cast<std::size_t>(n))
    return false;
  for (int i = 0; i < n; ++i) {
    states[i] = out_.states[static_cast<std::size_t>(i)];
    stms[i] = out_.stms[static_cast<std::size_t>(i)];
  }
  return true;
}

}  // namespace satgnc::od
