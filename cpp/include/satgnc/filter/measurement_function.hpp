#pragma once
/// @file measurement_function.hpp
/// Measurement records and the measurement function a filter of this room updates with. Generic:
/// a record's `type` and `station` are integer ids that only the measurement function interprets
/// (the orbit layer maps them to range / Doppler / angles and to stations).
#include <Eigen/Core>
#include <array>

#include "satgnc/filter/status.hpp"

namespace satgnc::filter {

/// Largest measurement dimension m of one record (az/el and RA/Dec are 2; 3 leaves room for a
/// position fix). Fixed so that every per-record buffer is a fixed-size array (no allocation).
inline constexpr int kMaxMeasurementDim = 3;

/// One measurement record: m = MeasurementFunction::dimension(type) components, uncorrelated
/// (one sigma each: R = diag(sigma^2)), so the filter may process them one scalar at a time.
struct MeasurementRecord {
  double t = 0.0;   ///< epoch, s (same time origin as the ProcessModel)
  int type = 0;     ///< measurement type id (interpreted by the MeasurementFunction)
  int station = 0;  ///< station / sensor id (interpreted by the MeasurementFunction)
  std::array<double, kMaxMeasurementDim> value{};  ///< observed value, first m entries used (model's units)
  std::array<double, kMaxMeasurementDim> sigma{};  ///< 1-sigma noise per component, > 0 (same units)
};

/// Abstract measurement function z = h(x, t; record) with its Jacobian H = dh/dx.
///
/// Contract for implementers: `measure` is noexcept and allocation-free after the function's own
/// setup; z_pred (m) and H (m x n) are storage the filter sized at setup (m = dimension(type)).
/// Angles are returned so that `value - z_pred` is the residual the filter should use (wrap
/// inside `measure` if needed: the filter subtracts componentwise).
class MeasurementFunction {
 public:
  virtual ~MeasurementFunction() = default;
  /// Dimension m (1..kMaxMeasurementDim) of a measurement type, or 0 when the type is not set up.
  virtual int dimension(int type) const noexcept = 0;
  /// Predict the record's measurement from state x at time t (= record.t).
  /// @param x state (n)
  /// @param record the record (type, station, and the observed value if light time needs it)
  /// @param z_pred out: predicted measurement (m)
  /// @param h out: Jacobian dz/dx (m x n); may be left unset when with_jacobian is false
  /// @param with_jacobian false when only z_pred is needed (UKF sigma points, post-fit residuals)
  /// @return ModelStatus::success, or failed (outputs then undefined)
  virtual ModelStatus measure(const Eigen::Ref<const Eigen::VectorXd>& x, const MeasurementRecord& record,
                              Eigen::Ref<Eigen::VectorXd> z_pred, Eigen::Ref<Eigen::MatrixXd> h,
                              bool with_jacobian) noexcept = 0;
};

}  // namespace satgnc::filter
