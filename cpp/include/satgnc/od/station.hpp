#pragma once
/// @file station.hpp
/// Forwarding header (issue 12): stations and ellipsoids moved to satgnc/dynamics/station.hpp,
/// namespace satgnc::dynamics. The old satgnc::od names stay available through the using-declarations
/// below.
#include "satgnc/dynamics/station.hpp"

namespace satgnc::od {
using dynamics::Ellipsoid;
using dynamics::ellipsoid_by_name;
using dynamics::geodetic_to_ecef;
using dynamics::implied_rotation_rate;
using dynamics::rot_z;
using dynamics::Station;
namespace ellipsoids {
using dynamics::ellipsoids::grs80;
using dynamics::ellipsoids::iau1976;
using dynamics::ellipsoids::krassovsky;
using dynamics::ellipsoids::sphere;
using dynamics::ellipsoids::wgs84;
}  // namespace ellipsoids
}  // namespace satgnc::od
