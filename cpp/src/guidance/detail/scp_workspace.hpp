#pragma once
// Private to the guidance room (not installed): the scratch buffers of guidance::ScpSolver, sized
// once in its constructor so that solve() does not allocate. Units are the model's (see scp.hpp);
// nx states, nu controls, N intervals. The problem data (bounds, subproblems, inner solvers) stay
// members of ScpSolver.
#include <Eigen/Core>

namespace satgnc::guidance::detail {

/// ScpSolver's scratch buffers.
struct ScpWorkspace {
  Eigen::MatrixXd Ytmp_, Utmp_, Ucand_, Zu_;  ///< nu x N: control scratch, candidate, warm copies
  Eigen::MatrixXd Ywarm_, Lwarm_;             ///< nu x N: warm start of the next subproblem
  Eigen::MatrixXd Xtmp_, Xlin_;               ///< nx x (N+1): scratch rollout, linearization point
  Eigen::MatrixXd Tlo_, Thi_;                 ///< nu x N: trust-region stage bounds
  Eigen::VectorXd lam_, lam2_, su_;           ///< costate scratch (inner nx, inner nx, nu)
};

}  // namespace satgnc::guidance::detail
