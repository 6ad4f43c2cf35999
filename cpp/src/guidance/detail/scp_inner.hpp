#pragma once
// Private to the guidance room (not installed): what ScpSolver does with the result of either inner
// solver (IlqrAdmmSolver or AdmmSolver) after a convex subproblem.
#include <Eigen/Core>

namespace satgnc::guidance::detail {

/// Take the inner result's Y and Lambda (nu x N, the inner solver's units) as the next warm start
/// when its outcome is usable (neither failed nor infeasible); otherwise keep the previous one.
/// No allocation once Y and Lambda have their sizes.
template <class InnerResult>
inline void keep_warm_start(const InnerResult& r, bool usable, Eigen::MatrixXd& Y, Eigen::MatrixXd& Lambda) {
  if (usable) {
    Y = r.Y;
    Lambda = r.Lambda;
  }
}

}  // namespace satgnc::guidance::detail
