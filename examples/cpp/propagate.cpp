// Flight-style use of the installed static core (no Python): propagate a LEO state with its STM over
// 2 h under J2 with CVODES, reusing one workspace, and check det(Phi) = 1 (J2 is conservative).
#include <Eigen/LU>
#include <cmath>
#include <cstdio>

#include "satgnc/propagation/cvodes.hpp"

int main() {
  namespace dyn = satgnc::dynamics;
  namespace prop = satgnc::propagation;

  dyn::ForceModel model;
  model.j2 = dyn::J2Gravity{};  // Earth EGM-96 constants

  prop::CvodesSettings settings;  // Adams, Newton corrector, rtol 1e-10, atol 1e-12, with STM
  prop::CvodesPropagator propagator(model, settings);  // all CVODES memory allocated here

  satgnc::Vec6 x0;
  x0 << 6778.137, 0.0, 0.0, 0.0, 4.7302, 6.0354;  // km, km/s: 400 km, i = 51.6 deg
  const std::vector<double> times = {1800.0, 3600.0, 7200.0};
  prop::Trajectory out;
  propagator.propagate(x0, 0.0, times, out);
  if (out.status != prop::PropagationStatus::success) {
    std::printf("propagation failed: %s\n", out.message.c_str());
    return 1;
  }
  const satgnc::Vec6& x = out.states.back();
  const double det = out.stms.back().determinant();
  std::printf("x(7200 s) = [%.6f %.6f %.6f] km, [%.9f %.9f %.9f] km/s\n", x[0], x[1], x[2], x[3], x[4], x[5]);
  std::printf("det(Phi) - 1 = %.3e, steps = %ld, rhs evaluations = %ld\n", det - 1.0, out.stats.steps,
              out.stats.rhs_evals);
  return std::abs(det - 1.0) < 1e-6 ? 0 : 1;
}
