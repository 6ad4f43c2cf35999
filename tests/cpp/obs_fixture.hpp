#pragma once
// Shared scenario of the observation tests: a station at 40 N, 105 W, 1.6 km on WGS-84 (the paper's
// rotating model, dynamics::Station) and a LEO state passing close to it, both at t = 0; the converged
// measurement model and the central-difference check of its state partials that the tests share.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "satgnc/core/constants.hpp"
#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/station.hpp"
#include "satgnc/observation/measurement_model.hpp"
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

// A measurement model of `type` (troposphere `tm` when `tropo`, Shapiro when `shapiro`) with the light
// time converged to rounding, so that finite differences see no iteration noise.
inline satgnc::observation::MeasurementModel converged_model(
    satgnc::observation::ObservableType type, bool tropo = false, bool shapiro = false,
    satgnc::observation::TroposphereModel tm = satgnc::observation::TroposphereModel::saastamoinen) {
  satgnc::observation::MeasurementSettings s;
  s.type = type;
  s.troposphere = tropo;
  s.troposphere_model = tm;
  s.shapiro = shapiro;
  s.light_time.tolerance = 1e-16;
  return satgnc::observation::MeasurementModel(s);
}

// Tolerance of a central difference with step h: 1e-7 relative (truncation h^2/6 |f'''|: the third
// derivatives scale as 1/rho^2 ~ 1e-6 / km^2, so < 1e-10 here) plus the rounding of the differenced
// values, 4 eps |value| / h.
inline double fd_tolerance(double fd, double value, double h) {
  return 1e-7 * std::abs(fd) + 4.0 * 2.2e-16 * std::max(std::abs(value), 1.0) / h;
}

// a - b for angles, in [-pi, pi].
inline double angle_diff(double a, double b) { return std::remainder(a - b, 2.0 * 3.14159265358979323846); }

// Every row of m's state partials at (t, x, b) against central differences (h = 1e-2 km, km/s) within
// fd_tolerance; the first row of a two-row (angle) observable is differenced modulo 2 pi.
inline void expect_dx_matches_central_difference(const satgnc::observation::MeasurementModel& m,
                                                 const satgnc::observation::StationEphemeris& st, double t,
                                                 const satgnc::Vec6& x, const satgnc::observation::Biases& b,
                                                 const std::string& label) {
  satgnc::observation::Prediction p;
  m.predict(st, t, x, b, p);
  ASSERT_EQ(p.status, satgnc::core::ObservationStatus::success) << label;
  const bool angles = p.size == 2;
  for (int k = 0; k < 6; ++k) {
    const double h = 1e-2;
    satgnc::Vec6 xp = x, xm = x;
    xp(k) += h;
    xm(k) -= h;
    satgnc::observation::Prediction pp, pm;
    m.predict(st, t, xp, b, pp);
    m.predict(st, t, xm, b, pm);
    for (int i = 0; i < p.size; ++i) {
      const double d = (angles && i == 0) ? angle_diff(pp.value(i), pm.value(i)) : pp.value(i) - pm.value(i);
      const double fd = d / (2.0 * h);
      EXPECT_LT(std::abs(p.dx(i, k) - fd), fd_tolerance(fd, p.value(i), h))
          << label << " row " << i << " col " << k << ": analytic " << p.dx(i, k) << " fd " << fd;
    }
  }
}

}  // namespace obs_fixture
