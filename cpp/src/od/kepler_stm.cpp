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

void CvodesStmPropagator::reserve(int max_times) {
  core::require(max_times >= 0, "max_times", "must be >= 0");
  const auto n = static_cast<std::size_t>(max_times);
  t_.reserve(n);
  t_back_.reserve(n);
  for (propagation::Trajectory* out : {&out_, &out_back_}) {
    out->times.reserve(n);
    out->states.reserve(n);
    out->stms.reserve(n);
  }
}

bool CvodesStmPropagator::propagate(const Vec6& x0, const double* times, int n, Vec6* states, Mat6* stms) {
  // CVODES wants strictly monotone times on one side of t0 (t0 itself returns x0 and the identity):
  // the times before the epoch run backward from 0, in reverse order.
  if (n <= 0) return n == 0;
  int n_back = 0;
  while (n_back < n && times[n_back] < 0.0) ++n_back;
  t_.assign(times + n_back, times + n);
  t_back_.clear();
  for (int i = n_back - 1; i >= 0; --i) t_back_.push_back(times[i]);
  const auto run = [this, &x0](const std::vector<double>& t, propagation::Trajectory& out) {
    if (t.empty()) return true;
    try {
      prop_.propagate(x0, 0.0, t, out);
    } catch (const std::exception&) {
      return false;
    }
    return out.status == propagation::PropagationStatus::success && out.states.size() == t.size() &&
           out.stms.size() == t.size();
  };
  if (!run(t_back_, out_back_) || !run(t_, out_)) return false;
  for (int i = 0; i < n_back; ++i) {
    const auto k = static_cast<std::size_t>(n_back - 1 - i);
    states[i] = out_back_.states[k];
    stms[i] = out_back_.stms[k];
  }
  for (int i = n_back; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i - n_back);
    states[i] = out_.states[k];
    stms[i] = out_.stms[k];
  }
  return true;
}

}  // namespace satgnc::od
