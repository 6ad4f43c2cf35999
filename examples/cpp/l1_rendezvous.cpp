// Flight-style use of the installed static library: plan the fuel-optimal rendezvous of
// l1_admm_rendezvous.md (linear, per-axis |u| <= 5 mN, terminal cost), print status, iterations,
// delta-v and terminal miss. No Python, no heap allocation inside solve().
#include <cmath>
#include <cstdio>

#include "satgnc/dynamics/cw.hpp"
#include "satgnc/guidance/admm.hpp"

int main() {
  using satgnc::guidance::AdmmSolver;
  using satgnc::guidance::AdmmStatus;
  // Scenario (python/satgnc/data/l1_scenario.md), SI units.
  const double mu = 3.99e14, radius = 7231e3, mass = 4.6, tf = 6000.0, u_max = 5e-3;
  const int N = 99;  // 100 knots
  const Eigen::Vector3d p(-9477.311, -1999.979, -43.046), v(-3.477486, 1.007149, -0.090170);
  // the published implementation's scaling (well-conditioned units for the solver)
  const double l_ref = p.norm(), v_ref = v.norm(), t_ref = l_ref / v_ref;
  const double u_ref = l_ref / (t_ref * t_ref) * mass, dt = tf / N / t_ref;
  const double n = std::sqrt(mu / (radius * radius * radius)) * t_ref;

  const satgnc::dynamics::CwModel cw(n, 1.0);
  const auto d = satgnc::dynamics::cw_discretize_zoh(cw, dt);  // exact zero-order hold
  satgnc::guidance::LtvProblem prob;
  prob.dynamics.A = {Eigen::MatrixXd(d.Ad)};
  prob.dynamics.B = {Eigen::MatrixXd(d.Bd)};
  prob.dynamics.horizon = N;
  prob.x0.resize(6);
  prob.x0 << p / l_ref, v / v_ref;
  prob.xf = Eigen::VectorXd::Zero(6);
  prob.Qf = 1000.0 / dt * Eigen::MatrixXd::Identity(6, 6);
  prob.l1_weights = Eigen::VectorXd::Ones(3);
  prob.u_lower = Eigen::VectorXd::Constant(3, -u_max / u_ref);
  prob.u_upper = Eigen::VectorXd::Constant(3, u_max / u_ref);

  AdmmSolver solver(prob);  // validates and allocates; throws std::invalid_argument on bad data
  const auto& r = solver.solve();
  double dv = 0.0;
  for (int k = 0; k < N; ++k) dv += r.Y.col(k).cwiseAbs().sum() * u_ref * (tf / N) / mass;
  const double miss = r.X_flown.col(N).head<3>().norm() * l_ref;
  std::printf("status: %s\niterations: %d (polished: %s)\ndelta-v: %.4f m/s\nterminal miss: %.2f m\n",
              satgnc::guidance::status_message(r.info.status), r.info.iterations,
              r.info.polished ? "yes" : "no", dv, miss);
  return r.info.status == AdmmStatus::solved ? 0 : 1;
}
