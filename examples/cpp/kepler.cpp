// Flight-style use of the analytic two-body propagator: links only the installed static satgnc core.
// Propagates Vallado's Example 2-4 state by 40 min with the STM and prints the result.
#include "satgnc/propagation/kepler.hpp"

#include <Eigen/Dense>  // determinant() lives in Eigen/LU
#include <cstdio>

int main() {
  satgnc::Vec6 x0;
  x0 << 1131.340, -2282.343, 6672.423, -5.64305, 4.30333, 2.42879;  // km, km/s
  satgnc::Vec6 x;
  satgnc::Mat6 stm;
  satgnc::propagation::KeplerInfo info;
  const auto st = satgnc::propagation::kepler_step(x0, 2400.0, 398600.4418, x, &stm, &info);
  if (st != satgnc::propagation::KeplerStatus::success) {
    std::printf("kepler_step failed: %s\n", satgnc::core::status_message(st));
    return 1;
  }
  std::printf("r = [%.4f, %.4f, %.4f] km\nv = [%.6f, %.6f, %.6f] km/s\n", x(0), x(1), x(2), x(3), x(4), x(5));
  std::printf("det(STM) = %.15f, Kepler iterations = %d\n", stm.determinant(), info.iterations);
  return 0;
}
