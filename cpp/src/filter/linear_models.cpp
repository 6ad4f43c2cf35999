// Generic models of filter/linear_models.hpp.
#include "satgnc/filter/linear_models.hpp"

#include <Eigen/Eigenvalues>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::filter {

using core::require;

LinearProcessModel::LinearProcessModel(const Eigen::MatrixXd& phi, const Eigen::MatrixXd& qd)
    : phi_(phi), qd_(qd) {
  require(phi.rows() >= 1 && phi.rows() == phi.cols(), "phi", "must be square and non-empty");
  core::require_finite(phi, "phi");
  require(qd.rows() == phi.rows() && qd.cols() == phi.cols(), "qd", "must have the shape of phi");
  core::require_finite(qd, "qd");
  const double scale = std::max(qd.cwiseAbs().maxCoeff(), 1e-300);
  require((qd - qd.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * scale, "qd", "must be symmetric");
  const double lmin =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(qd, Eigen::EigenvaluesOnly).eigenvalues()(0);
  require(lmin >= -1e-12 * scale, "qd",
          "must be positive semidefinite (negative process noise: smallest eigenvalue " +
              std::to_string(lmin) + ")");
}

ModelStatus LinearProcessModel::propagate(const Eigen::Ref<const Eigen::VectorXd>& x0, double, double,
                                          Eigen::Ref<Eigen::VectorXd> x1, Eigen::Ref<Eigen::MatrixXd> phi,
                                          Eigen::Ref<Eigen::MatrixXd> qd, bool with_jacobian) noexcept {
  x1.noalias() = phi_ * x0;
  if (with_jacobian) phi = phi_;
  qd = qd_;
  return ModelStatus::success;
}

LinearMeasurementFunction::LinearMeasurementFunction(const std::vector<Eigen::MatrixXd>& h_by_type)
    : h_(h_by_type) {
  require(!h_.empty(), "h_by_type", "must hold at least one matrix");
  for (std::size_t i = 0; i < h_.size(); ++i) {
    const std::string name = "h_by_type[" + std::to_string(i) + "]";
    require(h_[i].rows() >= 1 && h_[i].rows() <= kMaxMeasurementDim, name,
            "must have 1.." + std::to_string(kMaxMeasurementDim) + " rows");
    require(h_[i].cols() == h_[0].cols() && h_[i].cols() >= 1, name,
            "every matrix must have the same n >= 1 columns");
    core::require_finite(h_[i], name);
  }
}

int LinearMeasurementFunction::dimension(int type) const noexcept {
  if (type < 0 || type >= static_cast<int>(h_.size())) return 0;
  return static_cast<int>(h_[static_cast<std::size_t>(type)].rows());
}

ModelStatus LinearMeasurementFunction::measure(const Eigen::Ref<const Eigen::VectorXd>& x,
                                               const MeasurementRecord& record,
                                               Eigen::Ref<Eigen::VectorXd> z_pred,
                                               Eigen::Ref<Eigen::MatrixXd> h, bool with_jacobian) noexcept {
  if (dimension(record.type) == 0 || x.size() != h_[0].cols()) return ModelStatus::failed;
  const Eigen::MatrixXd& hm = h_[static_cast<std::size_t>(record.type)];
  z_pred.noalias() = hm * x;
  if (with_jacobian) h = hm;
  return ModelStatus::success;
}

BeaconRangeFunction::BeaconRangeFunction(const Eigen::MatrixXd& beacons, int n) : beacons_(beacons), n_(n) {
  require(beacons.rows() == 2 || beacons.rows() == 3, "beacons",
          "must have 2 or 3 rows (the position dimension d)");
  require(beacons.cols() >= 1, "beacons", "must hold at least one beacon (column)");
  core::require_finite(beacons, "beacons");
  require(n >= beacons.rows(), "n", "must be >= the beacon dimension");
}

ModelStatus BeaconRangeFunction::measure(const Eigen::Ref<const Eigen::VectorXd>& x,
                                         const MeasurementRecord& record, Eigen::Ref<Eigen::VectorXd> z_pred,
                                         Eigen::Ref<Eigen::MatrixXd> h, bool with_jacobian) noexcept {
  if (record.type != 0 || record.station < 0 || record.station >= beacons_.cols() || x.size() != n_) {
    return ModelStatus::failed;
  }
  const Eigen::Index d = beacons_.rows();
  double rho2 = 0.0;
  for (Eigen::Index i = 0; i < d; ++i) {
    const double e = x(i) - beacons_(i, record.station);
    rho2 += e * e;
  }
  const double rho = std::sqrt(rho2);
  if (!(rho > 0.0)) return ModelStatus::failed;
  z_pred(0) = rho;
  if (with_jacobian) {
    h.setZero();
    for (Eigen::Index i = 0; i < d; ++i) h(0, i) = (x(i) - beacons_(i, record.station)) / rho;
  }
  return ModelStatus::success;
}

}  // namespace satgnc::filter
