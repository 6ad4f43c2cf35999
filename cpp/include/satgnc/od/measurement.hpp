#pragma once
/// @file measurement.hpp
/// Forwarding header (issue 12): the measurement models moved to satgnc/dynamics/measurement.hpp,
/// namespace satgnc::dynamics. The old satgnc::od names stay available through the using-declarations
/// below.
#include "satgnc/dynamics/measurement.hpp"

namespace satgnc::od {
using dynamics::Measurement;
using dynamics::measurement_type_name;
using dynamics::MeasurementType;
using dynamics::parse_measurement_type;
using dynamics::predict_measurement;
using dynamics::Row6;
using dynamics::validate_measurements;
}  // namespace satgnc::od
