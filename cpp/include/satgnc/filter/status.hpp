#pragma once
/// @file status.hpp
/// Statuses of the filter room, in the style of core/status.hpp: one X-macro list
/// `X(name, value, "message")` per enum gives the enum (values stable: Python keys results by them;
/// new rows are appended), `status_name`, `status_message` and `core::status_table<E>()`.
///
/// - `FilterStatus`: the outcome of one filter step (predict and/or update) and of a whole run.
/// - `ModelStatus`: what a ProcessModel or MeasurementFunction reports for one call.
/// - `EditFlag`: the editing decision for one measurement record (never dropped silently).
#include "satgnc/core/status.hpp"

namespace satgnc::filter {

// clang-format off
/// FilterStatus rows: name, stable value, message.
#define SATGNC_FILTER_STATUS(X)                                                                          \
  X(unsolved, 9, "not run yet")                                                                          \
  X(success, 0, "success: the step was processed and the covariance is positive definite")              \
  X(rejected, 1, "the measurement failed the chi-square gate: state and covariance unchanged, the "     \
                 "record lists its normalized residual")                                                 \
  X(covariance_not_pd, 2, "the covariance lost positive definiteness (Cholesky failed or a UD "         \
                          "diagonal <= 0); the step's numbers are kept for inspection")                 \
  X(innovation_not_pd, 3, "the innovation covariance H P H' + R is not positive definite; no update")   \
  X(process_failed, 4, "the process model failed, returned non-finite values or negative process "      \
                       "noise (diag Qd < 0); the run stops")                                             \
  X(measurement_failed, 5, "the measurement function failed or returned non-finite values; no update")  \
  X(not_converged, 6, "the iterated EKF did not meet its tolerance within max_iterations; the last "    \
                      "iterate is kept")                                                                 \
  X(unknown_measurement_type, 7, "the record's type is not set up by the measurement function "         \
                                 "(dimension(type) == 0); no update")                                    \
  X(invalid_time, 8, "a non-finite time, or a record time before the filter time; no update")
/// ModelStatus rows.
#define SATGNC_FILTER_MODEL_STATUS(X)                                         \
  X(unsolved, 2, "not called yet")                                            \
  X(success, 0, "success: the outputs are set")                               \
  X(failed, 1, "the model failed (propagation or measurement not available)")
/// EditFlag rows.
#define SATGNC_FILTER_EDIT_FLAG(X)                                                                     \
  X(unsolved, 4, "not processed yet")                                                                  \
  X(accepted, 0, "accepted: passed the gate and used in the update")                                  \
  X(rejected, 1, "rejected by the chi-square gate (Mahalanobis distance above the quantile)")         \
  X(warm_up, 2, "used without gating: inside the warm-up period (or gating off)")                     \
  X(failed, 3, "not used: the measurement function failed, the type is unknown or S is not PD")
// clang-format on

#define SATGNC_FILTER_ENUMERATOR_(name, value, message) name = value,
#define SATGNC_FILTER_NAME_CASE_(name, value, message) \
  case E_::name:                                       \
    return #name;
#define SATGNC_FILTER_MESSAGE_CASE_(name, value, message) \
  case E_::name:                                          \
    return message;

/// Outcome of one filter step and of a run (see SATGNC_FILTER_STATUS for the messages).
enum class FilterStatus : int { SATGNC_FILTER_STATUS(SATGNC_FILTER_ENUMERATOR_) };
/// Outcome of one call of a ProcessModel or MeasurementFunction.
enum class ModelStatus : int { SATGNC_FILTER_MODEL_STATUS(SATGNC_FILTER_ENUMERATOR_) };
/// Editing decision for one measurement record.
enum class EditFlag : int { SATGNC_FILTER_EDIT_FLAG(SATGNC_FILTER_ENUMERATOR_) };

/// Enumerator name of a FilterStatus ("unknown" outside the table).
constexpr const char* status_name(FilterStatus s) noexcept {
  using E_ = FilterStatus;
  switch (s) { SATGNC_FILTER_STATUS(SATGNC_FILTER_NAME_CASE_) }
  return "unknown";
}
/// One-sentence message of a FilterStatus.
constexpr const char* status_message(FilterStatus s) noexcept {
  using E_ = FilterStatus;
  switch (s) { SATGNC_FILTER_STATUS(SATGNC_FILTER_MESSAGE_CASE_) }
  return "unknown status";
}
/// Enumerator name of a ModelStatus.
constexpr const char* status_name(ModelStatus s) noexcept {
  using E_ = ModelStatus;
  switch (s) { SATGNC_FILTER_MODEL_STATUS(SATGNC_FILTER_NAME_CASE_) }
  return "unknown";
}
/// One-sentence message of a ModelStatus.
constexpr const char* status_message(ModelStatus s) noexcept {
  using E_ = ModelStatus;
  switch (s) { SATGNC_FILTER_MODEL_STATUS(SATGNC_FILTER_MESSAGE_CASE_) }
  return "unknown status";
}
/// Enumerator name of an EditFlag.
constexpr const char* status_name(EditFlag s) noexcept {
  using E_ = EditFlag;
  switch (s) { SATGNC_FILTER_EDIT_FLAG(SATGNC_FILTER_NAME_CASE_) }
  return "unknown";
}
/// One-sentence message of an EditFlag.
constexpr const char* status_message(EditFlag s) noexcept {
  using E_ = EditFlag;
  switch (s) { SATGNC_FILTER_EDIT_FLAG(SATGNC_FILTER_MESSAGE_CASE_) }
  return "unknown status";
}

}  // namespace satgnc::filter

#define SATGNC_FILTER_ROW_(name, value, message) StatusEntry{value, #name, message},
namespace satgnc::core {
/// Status table of filter::FilterStatus.
template <>
struct StatusTraits<filter::FilterStatus> {
  static constexpr bool is_status = true;                                       ///< a status enum
  static constexpr std::array table{SATGNC_FILTER_STATUS(SATGNC_FILTER_ROW_)};  ///< rows
};
/// Status table of filter::ModelStatus.
template <>
struct StatusTraits<filter::ModelStatus> {
  static constexpr bool is_status = true;                                             ///< a status enum
  static constexpr std::array table{SATGNC_FILTER_MODEL_STATUS(SATGNC_FILTER_ROW_)};  ///< rows
};
/// Status table of filter::EditFlag.
template <>
struct StatusTraits<filter::EditFlag> {
  static constexpr bool is_status = true;                                          ///< a status enum
  static constexpr std::array table{SATGNC_FILTER_EDIT_FLAG(SATGNC_FILTER_ROW_)};  ///< rows
};
}  // namespace satgnc::core

#undef SATGNC_FILTER_ROW_
#undef SATGNC_FILTER_ENUMERATOR_
#undef SATGNC_FILTER_NAME_CASE_
#undef SATGNC_FILTER_MESSAGE_CASE_
