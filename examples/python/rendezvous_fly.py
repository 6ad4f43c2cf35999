"""
Fly a rendezvous plan on the nonlinear truth
============================================

Plan the scenario's ``approach`` case on the linear CW model and on the nonlinear two-satellite
model (sequential convex programming), then fly both plans open loop on the scenario's truth
(J2, integrated by CVODES) and compare the terminal miss. Units: m, m/s, N, kg, s.
"""

import pathlib

import numpy as np
from satgnc import plotting
from satgnc.guidance.flight import fly
from satgnc.guidance.planning import plan
from satgnc.scenarios import rendezvous

here = pathlib.Path(__file__).resolve().parent if "__file__" in globals() else pathlib.Path.cwd()
scenario = rendezvous.load(here / "user_rendezvous.toml")
truth = rendezvous.truth_params(scenario)
problem = rendezvous.problem(scenario, "approach", "nonlinear")
x0 = problem.state_eci()

linear = plan(rendezvous.problem(scenario, "approach", "linear"), "linear")
nonlinear = plan(problem, "nonlinear", "scp")
flights = {"CW plan": fly(truth, x0, linear.U, problem.dt), "nonlinear plan": fly(truth, x0, nonlinear.U,
                                                                                  problem.dt)}
for label, f in flights.items():
    print(f"{label}: flown on the truth, miss {f.miss[0]:.2f} m, {f.miss[1] * 1e3:.2f} mm/s")

plt = plotting.pyplot()  # satgnc's style: colour-blind-safe palette, grid
fig, ax = plt.subplots(figsize=(7, 4))
for label, f in flights.items():
    ax.semilogy(f.t, np.linalg.norm(f.X[:, 0:3], axis=1), label=label)  # X[:, 0:3]: relative position (m)
ax.set(xlabel="time (s)", ylabel="range to target (m)", title="Plans flown open loop on the J2 truth")
plotting.legend_outside(ax)
fig.tight_layout()
