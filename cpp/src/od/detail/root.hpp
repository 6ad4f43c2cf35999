#pragma once
// Private to the od room (not installed): root_search's copy of a solver result into a Root.
#include "satgnc/od/solver.hpp"

namespace satgnc::od::detail {

/// Copy the solution of r (x0 km, km/s; covariance; raw and normalized residuals; misfit; condition
/// number; fit and convergence flags) into root. hits and first_guess are left to the caller.
inline void take_solution(const OdResult& r, Root& root) {
  root.x0 = r.x0;
  root.covariance = r.covariance;
  root.residuals = r.residuals;
  root.normalized = r.normalized;
  root.max_abs_normalized = r.max_abs_normalized;
  root.condition_number = r.condition_number;
  root.fits = r.fits;
  root.converged = r.status == OdStatus::converged;
}

}  // namespace satgnc::od::detail
