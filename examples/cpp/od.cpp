// Flight-style orbit determination: the paper's six Doppler conditions from one station, solved by
// Newton-Raphson with the exact two-body STM. Links only the installed static satgnc library.
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "satgnc/od/measurement.hpp"
#include "satgnc/od/propagator.hpp"
#include "satgnc/od/solver.hpp"
#include "satgnc/od/station.hpp"

int main() {
  using namespace satgnc;
  using namespace satgnc::od;
  constexpr double mu = 398600.4418;
  Vec6 truth;
  truth << 5836.89070, 1265.61600, 3411.49600, 0.31460, 6.94010, -3.11250;                   // paper Table 1
  const Station station = Station::from_inertial(Vec3(5463.14996, 2139.12637, 2493.77850));  // Table 3
  auto prop = std::make_shared<KeplerStmPropagator>(mu);

  // Synthetic full-precision observations at t = 0, 60, ..., 300 s (setup: allocation allowed).
  const double t[6] = {0, 60, 120, 180, 240, 300};
  Vec6 xs[6];
  Mat6 phi[6];
  if (!prop->propagate(truth, t, 6, xs, phi)) return 1;
  std::vector<BoundaryCondition> conds;
  for (int i = 0; i < 6; ++i) {
    double rho = 0, rhodot = 0;
    predict_measurement(MeasurementType::range, xs[i], station.state(t[i]), rho);
    predict_measurement(MeasurementType::range_rate, xs[i], station.state(t[i]), rhodot);
    conds.push_back({t[i], ConditionType::doppler, rho, rhodot, 1e-3, 1e-6, 0});
  }
  OdSettings settings;
  settings.method = OdMethod::newton;
  OdSolver solver = OdSolver::from_conditions({station}, conds, prop, settings);

  // On-board part: solve from a guess 10 km off in x (no allocation inside solve()).
  Vec6 guess = truth;
  guess(0) += 10.0;
  const OdResult& r = solver.solve(guess);
  std::printf("status: %s, iterations: %d, rank %d, cond %.2e\n", status_message(r.status), r.iterations,
              r.rank, r.condition_number);
  std::printf("x0 = [%.6f %.6f %.6f] km [%.8f %.8f %.8f] km/s\n", r.x0(0), r.x0(1), r.x0(2), r.x0(3), r.x0(4),
              r.x0(5));
  const double err_m = (r.x0 - truth).head<3>().norm() * 1e3;
  std::printf("position error vs truth: %.3e m\n", err_m);
  return (r.status == OdStatus::converged && err_m < 0.1) ? 0 : 1;
}
