"""
Receding-horizon (MPC) rendezvous
=================================

Fly the scenario's ``approach`` case closed loop: re-plan the remaining horizon every 3 intervals
from the measured truth state (warm-started iLQR-ADMM on the nonlinear model) and fly the plan on
the truth (J2). The thrust bound holds at every step. Units: m, m/s, N, kg, s.
"""

import pathlib

import numpy as np
from satgnc.guidance.flight import mpc
from satgnc.scenarios import rendezvous

here = pathlib.Path(__file__).resolve().parent if "__file__" in globals() else pathlib.Path.cwd()
scenario = rendezvous.load(here / "user_rendezvous.toml")
problem = rendezvous.problem(scenario, "approach", "nonlinear")
truth = rendezvous.truth_params(scenario)
run = mpc(problem, truth=truth, replan_every=3)
u_max = scenario.sections["cost"]["u_max"]
print(f"MPC: miss {run.miss[0]:.3f} m, {1e3 * run.miss[1]:.3f} mm/s; "
      f"max |u| {1e3 * float(np.abs(run.U).max()):.2f} mN (bound {1e3 * u_max:.0f} mN); "
      f"dv {float(np.abs(run.U).sum()) * problem.dt / problem.mass:.4f} m/s; "
      f"re-plan time median {1e3 * float(np.median(run.solve_times)):.2f} ms")
