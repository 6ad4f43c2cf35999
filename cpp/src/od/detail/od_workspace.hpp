#pragma once
// Private to the od room (not installed): every buffer of od::OdSolver, sized once in
// OdSolver::setup so that solve() does not allocate. Units: states km, km/s; residuals raw (km,
// km/s, km^2, km^2/s) or normalized (divided by the row sigma).
#include <Eigen/Dense>
#include <vector>

#include "householder_qr.hpp"
#include "satgnc/core/types.hpp"

namespace satgnc::od::detail {

/// OdSolver's workspace (rows m = OdSolver::rows(), nt unique observation times).
struct OdWorkspace {
  std::vector<Vec6> states_;               ///< nt propagated states
  std::vector<Mat6> stms_;                 ///< nt state transition matrices
  Eigen::VectorXd r_, rn_, rr_, rrr_;      ///< m: raw, normalized, range and range-rate residuals
  Eigen::MatrixXd jn_;                     ///< m x 6: normalized Jacobian
  Eigen::VectorXd rn0_, gw_;               ///< m: geodesic probe: residuals at x, work vector
  Eigen::MatrixXd jn0_;                    ///< m x 6: geodesic probe: Jacobian at x
  Eigen::MatrixXd aug_;                    ///< m x 7: [Jn | rn], then its QR in place (factor())
  HouseholderQrWorkspace qr_;              ///< for aug_
  Eigen::VectorXd rs_, rns_, rrs_, rrrs_;  ///< m: valley corrector: saved buffers of the best point
  Eigen::MatrixXd jns_;                    ///< m x 6
  Eigen::MatrixXd augc_;                   ///< m x 6: [Jn P | rn] of the corrector, then its QR
  HouseholderQrWorkspace qrc_;             ///< for augc_
  Mat6 R_ = Mat6::Zero();                  ///< R of the QR of [Jn | rn]
  Vec6 c_ = Vec6::Zero();                  ///< Q^T rn (first 6 entries)
  Eigen::JacobiSVD<Mat6> svd_;             ///< of R_

  /// Size every buffer (allocates).
  void resize(Eigen::Index m, std::size_t nt) {
    states_.assign(nt, Vec6::Zero());
    stms_.assign(nt, Mat6::Identity());
    for (Eigen::VectorXd* v : {&r_, &rn_, &rr_, &rrr_, &rn0_, &gw_, &rs_, &rns_, &rrs_, &rrrs_})
      v->setZero(m);
    for (Eigen::MatrixXd* a : {&jn_, &jn0_, &jns_, &augc_}) a->setZero(m, 6);
    aug_.setZero(m, 7);
    qr_.resize(m, 7);
    qrc_.resize(m, 6);
  }
};

}  // namespace satgnc::od::detail
