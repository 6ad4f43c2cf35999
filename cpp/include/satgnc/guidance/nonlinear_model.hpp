#pragma once
/// @file nonlinear_model.hpp
/// Forwarding header (issue 12): the discrete-model interface moved to
/// satgnc/dynamics/discrete_model.hpp (namespace satgnc::dynamics), the two-satellite maps to
/// satgnc/propagation/two_satellite_map.hpp and satgnc/propagation/propagated_map.hpp (namespace
/// satgnc::propagation). The old satgnc::guidance names stay available through the using-declarations
/// below.
#include "satgnc/dynamics/discrete_model.hpp"
#include "satgnc/propagation/propagated_map.hpp"
#include "satgnc/propagation/two_satellite_map.hpp"

namespace satgnc::guidance {
using dynamics::DiscreteModel;
using dynamics::LinearDiscreteModel;
using propagation::PropagatedMapInfo;
using propagation::PropagatedMapSettings;
using propagation::PropagatedTwoSatelliteMap;
using propagation::published_scaling;
using propagation::ReferenceScaling;
using propagation::TwoSatelliteMap;
using propagation::TwoSatelliteMapSettings;
}  // namespace satgnc::guidance
