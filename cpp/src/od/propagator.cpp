#include "satgnc/od/propagator.hpp"

#include "satgnc/core/validate.hpp"

namespace satgnc::od {

ShortArcStmPropagator::ShortArcStmPropagator(std::shared_ptr<StmPropagator> inner)
    : inner_(std::move(inner)) {
  core::require(inner_ != nullptr, "inner", "must not be null");
}

bool ShortArcStmPropagator::propagate(const Vec6& x0, const double* times, int n, Vec6* states, Mat6* stms) {
  if (!inner_->propagate(x0, times, n, states, stms)) return false;
  for (int i = 0; i < n; ++i) {
    stms[i].setIdentity();
    stms[i].topRightCorner<3, 3>() = times[i] * Mat3::Identity();
  }
  return true;
}

}  // namespace satgnc::od
