#pragma once
/// @file linear_models.hpp
/// Simple generic models for the filter engine (tests, examples, the Python engine checks):
/// - LinearProcessModel: x1 = Phi x0 with one constant (Phi, Qd) per propagation interval
///   (a discrete-time model: every call with t1 > t0 applies one step, whatever t1 - t0);
/// - LinearMeasurementFunction: z = H_type x, one matrix per type id (0, 1, ...);
/// - BeaconRangeFunction: z = || x[0:d] - b_station || (d = 2 or 3), a nonlinear scalar range to
///   fixed beacons (station id = beacon index), type id 0.
/// Units are the caller's. Their methods are noexcept and allocation-free.
#include <Eigen/Core>
#include <vector>

#include "satgnc/filter/measurement_function.hpp"
#include "satgnc/filter/process_model.hpp"

namespace satgnc::filter {

/// x1 = Phi x0, Qd constant, per interval.
class LinearProcessModel : public ProcessModel {
 public:
  /// phi: n x n finite; qd: n x n symmetric positive semidefinite (throws "qd: ..." on negative
  /// process noise, i.e. a negative eigenvalue below -1e-12 ||qd||, or asymmetry).
  LinearProcessModel(const Eigen::MatrixXd& phi, const Eigen::MatrixXd& qd);
  /// n
  int state_dimension() const noexcept override { return static_cast<int>(phi_.rows()); }
  /// One discrete step: x1 = Phi x0, phi = Phi, qd = Qd.
  ModelStatus propagate(const Eigen::Ref<const Eigen::VectorXd>& x0, double t0, double t1,
                        Eigen::Ref<Eigen::VectorXd> x1, Eigen::Ref<Eigen::MatrixXd> phi,
                        Eigen::Ref<Eigen::MatrixXd> qd, bool with_jacobian) noexcept override;

 private:
  Eigen::MatrixXd phi_, qd_;
};

/// z = H_type x.
class LinearMeasurementFunction : public MeasurementFunction {
 public:
  /// h_by_type[type]: m x n (1 <= m <= kMaxMeasurementDim), all with the same n. Throws.
  explicit LinearMeasurementFunction(const std::vector<Eigen::MatrixXd>& h_by_type);
  /// m of the type, 0 when type is outside [0, size).
  int dimension(int type) const noexcept override;
  /// z = H_type x, h = H_type.
  ModelStatus measure(const Eigen::Ref<const Eigen::VectorXd>& x, const MeasurementRecord& record,
                      Eigen::Ref<Eigen::VectorXd> z_pred, Eigen::Ref<Eigen::MatrixXd> h,
                      bool with_jacobian) noexcept override;

 private:
  std::vector<Eigen::MatrixXd> h_;
};

/// z = || x[0:d] - beacons.col(station) ||, type 0 only (dimension 1).
class BeaconRangeFunction : public MeasurementFunction {
 public:
  /// beacons: d x B (d = 2 or 3, B >= 1, finite); n: state dimension (>= d). Throws.
  BeaconRangeFunction(const Eigen::MatrixXd& beacons, int n);
  /// 1 for type 0, else 0.
  int dimension(int type) const noexcept override { return type == 0 ? 1 : 0; }
  /// Range and its gradient; failed for a station outside [0, B) or a zero range.
  ModelStatus measure(const Eigen::Ref<const Eigen::VectorXd>& x, const MeasurementRecord& record,
                      Eigen::Ref<Eigen::VectorXd> z_pred, Eigen::Ref<Eigen::MatrixXd> h,
                      bool with_jacobian) noexcept override;

 private:
  Eigen::MatrixXd beacons_;
  int n_;
};

}  // namespace satgnc::filter
