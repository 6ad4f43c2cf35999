#pragma once
// Private to the guidance room (not installed): every buffer of guidance::IlqrAdmmSolver, sized
// once in its constructor so that solve() does not allocate. Units are the model's (see
// ilqr_admm.hpp); nx states, nu controls, N intervals.
#include <Eigen/Core>
#include <vector>

namespace satgnc::guidance::detail {

/// IlqrAdmmSolver's workspace.
struct IlqrAdmmWorkspace {
  std::vector<Eigen::MatrixXd> A_, B_;                      ///< N Jacobians along (X, U): nx x nx, nx x nu
  std::vector<Eigen::MatrixXd> K_;                          ///< N feedback gains, nu x nx
  Eigen::MatrixXd d_;                                       ///< nu x N feed-forward steps
  Eigen::MatrixXd Xn_, Xtmp_, Xbest_;                       ///< nx x (N+1): trial, scratch and best rollouts
  Eigen::MatrixXd Un_, Yprev_, Ubest_, Ybest_, Lbest_, V_;  ///< nu x N
  Eigen::MatrixXd S_, Qxx_, SA_;                            ///< nx x nx: backward pass
  Eigen::MatrixXd SB_;                                      ///< nx x nu
  Eigen::MatrixXd Quu_, L_;                                 ///< nu x nu
  Eigen::MatrixXd Qux_, QuuK_;                              ///< nu x nx
  Eigen::VectorXd s_, Qx_, dx_, tmpx_;                      ///< nx
  Eigen::VectorXd Qu_, tmpu_;                               ///< nu
};

}  // namespace satgnc::guidance::detail
