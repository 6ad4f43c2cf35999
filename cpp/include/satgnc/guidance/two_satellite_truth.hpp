#pragma once
/// @file two_satellite_truth.hpp
/// Forwarding header (issue 12): the two-satellite truth flight moved to
/// satgnc/propagation/two_satellite_truth.hpp, namespace satgnc::propagation. The old
/// satgnc::guidance names stay available through the using-declarations below.
#include "satgnc/propagation/two_satellite_truth.hpp"

namespace satgnc::guidance {
using propagation::default_truth_settings;
using propagation::TruthFlight;
using propagation::TwoSatelliteTruth;
}  // namespace satgnc::guidance
