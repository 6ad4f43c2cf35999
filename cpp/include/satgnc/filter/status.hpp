#pragma once
/// @file status.hpp
/// Statuses of the filter room, declared with core/status.hpp's generator (`SATGNC_DEFINE_STATUS_`):
/// one X-macro list `X(name, value, "message")` per enum gives the enum (values stable: Python keys
/// results by them; new rows are appended), `status_name`, `status_message` and
/// `core::status_table<E>()`. Like every status enum they live in satgnc::core and are re-exported
/// into satgnc::filter.
///
/// - `FilterStatus`: the outcome of one filter step (predict and/or update) and of a whole run.
/// - `ModelStatus`: what a ProcessModel or MeasurementFunction reports for one call.
/// - `EditFlag`: the editing decision for one measurement record (never dropped silently).
/// - `OrbitStepStatus`: the outcome of one step of filter::OrbitFilter (filter/orbit_filter.hpp).
#include "satgnc/core/status.hpp"

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
/// OrbitStepStatus rows (`not_run`, a step after the filter stopped, plays the part of `unsolved`).
#define SATGNC_FILTER_ORBIT_STEP_STATUS(X)                                                               \
  X(not_run, 5, "not run: a step after the filter stopped")                                               \
  X(updated, 0, "updated: the measurement was used")                                                      \
  X(rejected, 1, "rejected: edited out by the gate (state unchanged), listed with its residual")          \
  X(propagation_failed, 2, "the process model failed: the filter stops here (later steps keep this "      \
                           "status)")                                                                     \
  X(measurement_failed, 3, "the measurement model failed (light time, geometry): skipped, state "         \
                           "unchanged")                                                                   \
  X(not_positive_definite, 4, "the covariance lost positive definiteness after the update: the filter "    \
                              "stops")
// clang-format on

namespace satgnc::core {
// Outcome of one filter step and of a run.
SATGNC_DEFINE_STATUS_(FilterStatus, SATGNC_FILTER_STATUS, SATGNC_NO_ALIASES_)
// Outcome of one call of a ProcessModel or MeasurementFunction.
SATGNC_DEFINE_STATUS_(ModelStatus, SATGNC_FILTER_MODEL_STATUS, SATGNC_NO_ALIASES_)
// Editing decision for one measurement record.
SATGNC_DEFINE_STATUS_(EditFlag, SATGNC_FILTER_EDIT_FLAG, SATGNC_NO_ALIASES_)
// Outcome of one step of filter::OrbitFilter.
SATGNC_DEFINE_STATUS_(OrbitStepStatus, SATGNC_FILTER_ORBIT_STEP_STATUS, SATGNC_NO_ALIASES_)
}  // namespace satgnc::core

namespace satgnc::filter {
using core::EditFlag;
using core::FilterStatus;
using core::ModelStatus;
using core::OrbitStepStatus;
using core::status_message;
using core::status_name;
}  // namespace satgnc::filter
