#include "satgnc/observation/light_time.hpp"

#include <cmath>

#include "satgnc/core/validate.hpp"

namespace satgnc::observation {

void LightTimeSettings::validate() const {
  core::require(std::isfinite(tolerance) && tolerance >= 1e-18 && tolerance <= 1e-3, "light_time.tolerance",
                "must be in [1e-18, 1e-3] s, got " + std::to_string(tolerance));
  core::require(max_iterations >= 1 && max_iterations <= 100, "light_time.max_iterations",
                "must be in [1, 100], got " + std::to_string(max_iterations));
}

namespace {
// Two-body acceleration a and its time derivative j at the state (r, v).
inline void two_body_aj(const Vec3& r, const Vec3& v, double mu, Vec3& a, Vec3& j) noexcept {
  const double r2 = r.squaredNorm();
  const double ir3 = 1.0 / (r2 * std::sqrt(r2));
  a = -mu * ir3 * r;
  j = -mu * ir3 * (v - (3.0 * r.dot(v) / r2) * r);
}
}  // namespace

void shift_state(const Vec6& x, double dt, double mu, Vec6& out, Mat6* dout_dx, Vec6* dout_ddt) noexcept {
  const Vec3 r = x.head<3>();
  const Vec3 v = x.tail<3>();
  Vec3 a, j;
  two_body_aj(r, v, mu, a, j);
  const double h2 = 0.5 * dt * dt, h3 = dt * dt * dt / 6.0;
  out.head<3>() = r + dt * v + h2 * a + h3 * j;
  out.tail<3>() = v + dt * a + h2 * j;
  if (dout_dx) {
    const double r2 = r.squaredNorm();
    const double rn = std::sqrt(r2);
    const double rv = r.dot(v);
    const Mat3 I = Mat3::Identity();
    const Mat3 A = -mu / (r2 * rn) * (I - (3.0 / r2) * r * r.transpose());
    const Mat3 Jr = 3.0 * mu / (r2 * r2 * rn) *
                    (v * r.transpose() + r * v.transpose() + rv * I - (5.0 * rv / r2) * r * r.transpose());
    dout_dx->block<3, 3>(0, 0) = I + h2 * A + h3 * Jr;
    dout_dx->block<3, 3>(0, 3) = dt * I + h3 * A;
    dout_dx->block<3, 3>(3, 0) = dt * A + h2 * Jr;
    dout_dx->block<3, 3>(3, 3) = I + h2 * A;
  }
  if (dout_ddt) {
    dout_ddt->head<3>() = out.tail<3>();
    dout_ddt->tail<3>() = a + dt * j;
  }
}

LightTimeLeg solve_down_leg(const Vec6& x, const Vec3& R, double mu, const LightTimeSettings& s) noexcept {
  const Vec3 r = x.head<3>();
  const Vec3 v = x.tail<3>();
  Vec3 a, j;
  two_body_aj(r, v, mu, a, j);
  LightTimeLeg leg;
  leg.tau = (r - R).norm() / speed_of_light;
  for (int it = 1; it <= s.max_iterations; ++it) {
    const double tau = leg.tau;
    const Vec3 rb = r - tau * v + (0.5 * tau * tau) * a - (tau * tau * tau / 6.0) * j;
    const double next = (rb - R).norm() / speed_of_light;
    const double change = std::abs(next - tau);
    leg.tau = next;
    leg.iterations = it;
    if (change <= s.tolerance) {
      leg.converged = true;
      break;
    }
  }
  return leg;
}

LightTimeLeg solve_up_leg(const Vec3& r_bounce, const StationEphemeris& station, double t_bounce,
                          double tau_guess, const LightTimeSettings& s, StationState& at_transmit) noexcept {
  LightTimeLeg leg;
  leg.tau = tau_guess;
  for (int it = 1; it <= s.max_iterations; ++it) {
    station.state(t_bounce - leg.tau, at_transmit);
    const double next = (r_bounce - at_transmit.r).norm() / speed_of_light;
    const double change = std::abs(next - leg.tau);
    leg.tau = next;
    leg.iterations = it;
    if (change <= s.tolerance) {
      leg.converged = true;
      break;
    }
  }
  station.state(t_bounce - leg.tau, at_transmit);  // the station where the final tau puts it
  return leg;
}

}  // namespace satgnc::observation
