// Linear time-varying discrete model (see discrete_model.hpp).
#include "satgnc/dynamics/discrete_model.hpp"

#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::dynamics {

using core::require;

LinearDiscreteModel::LinearDiscreteModel(std::vector<Eigen::MatrixXd> A, std::vector<Eigen::MatrixXd> B,
                                         std::vector<Eigen::VectorXd> c)
    : A_(std::move(A)), B_(std::move(B)), c_(std::move(c)) {
  require(!A_.empty(), "A", "needs at least one matrix");
  require(B_.size() == A_.size(), "B", "needs as many matrices as A (" + std::to_string(A_.size()) + ")");
  require(c_.empty() || c_.size() == A_.size(), "c", "must be empty or have as many vectors as A");
  nx_ = static_cast<int>(A_[0].rows());
  nu_ = static_cast<int>(B_[0].cols());
  require(nx_ > 0 && nu_ > 0, "A/B", "need at least one state and one control");
  for (size_t k = 0; k < A_.size(); ++k) {
    const std::string ks = "[" + std::to_string(k) + "]";
    require(A_[k].rows() == nx_ && A_[k].cols() == nx_, "A" + ks, "must be nx x nx with nx = A[0].rows()");
    require(B_[k].rows() == nx_ && B_[k].cols() == nu_, "B" + ks, "must be nx x nu");
    core::require_finite(A_[k], "A" + ks);
    core::require_finite(B_[k], "B" + ks);
    if (!c_.empty()) {
      require(c_[k].size() == nx_, "c" + ks, "must have nx entries");
      core::require_finite(c_[k], "c" + ks);
    }
  }
}

bool LinearDiscreteModel::step(int k, const double* x, const double* u, double* x_next, double* A,
                               double* B) const {
  const int i = A_.size() == 1 ? 0 : k;
  if (i < 0 || i >= static_cast<int>(A_.size())) return false;
  Eigen::Map<const Eigen::VectorXd> xv(x, nx_), uv(u, nu_);
  Eigen::Map<Eigen::VectorXd> xn(x_next, nx_);
  xn.noalias() = A_[i] * xv;
  xn.noalias() += B_[i] * uv;
  if (!c_.empty()) xn += c_[i];
  if (A != nullptr) Eigen::Map<Eigen::MatrixXd>(A, nx_, nx_) = A_[i];
  if (B != nullptr) Eigen::Map<Eigen::MatrixXd>(B, nx_, nu_) = B_[i];
  return xn.allFinite();
}

bool LinearDiscreteModel::set(int k, const Eigen::Ref<const Eigen::MatrixXd>& A,
                              const Eigen::Ref<const Eigen::MatrixXd>& B,
                              const Eigen::Ref<const Eigen::VectorXd>& c) {
  if (k < 0 || k >= static_cast<int>(A_.size())) return false;
  if (A.rows() != nx_ || A.cols() != nx_ || B.rows() != nx_ || B.cols() != nu_) return false;
  if (c_.empty() ? c.size() != 0 : c.size() != nx_) return false;
  A_[k] = A;
  B_[k] = B;
  if (!c_.empty()) c_[k] = c;
  return true;
}

}  // namespace satgnc::dynamics
