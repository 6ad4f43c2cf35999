#pragma once
// Shared scenario of the observation tests: a station at 40 N, 105 W, 1.6 km on WGS-84 (the paper's
// rotating model, dynamics::Station) and a LEO state passing close to it, both at t = 0.
#include <cmath>

#include "satgnc/core/constants.hpp"
#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/station.hpp"
#include "satgnc/observation/station_ephemeris.hpp"

namespace obs_fixture {

inline constexpr double kMu = satgnc::core::earth::mu;
inline constexpr double kJdEpoch = 2460000.5;  // UTC Julian date of t = 0 (2023-02-25)

inline satgnc::dynamics::Station station() {
  return satgnc::dynamics::Station::from_geodetic(40.0, -105.0, 1.6, kJdEpoch);
}

// Circular orbit of radius `radius` (km) whose position at t = 0 is the station's zenith direction
// turned by `offset` rad about an inclined axis, so the station sees it at high elevation.
inline satgnc::Vec6 pass_state(double radius = 7000.0, double offset = 0.05) {
  using satgnc::Vec3;
  const Vec3 up = station().r0.normalized();
  const Vec3 axis = (Vec3(0.3, -0.2, 1.0).cross(up)).normalized();  // orbit normal, inclined
  const Vec3 rhat = Eigen::AngleAxisd(offset, axis) * up;
  const Vec3 vhat = axis.cross(rhat).normalized();
  satgnc::Vec6 x;
  x << radius * rhat, std::sqrt(kMu / radius) * vhat;
  return x;
}

}  // namespace obs_fixture
