"""
Plan an L1 rendezvous from a user scenario file
===============================================

Load a rendezvous scenario (TOML, SI units; schema in :mod:`satgnc.scenarios.rendezvous`) with a
case named ``approach``, build its problem on the linear Clohessy-Wiltshire model and plan the
fuel-optimal (L1) thrust by ADMM. Units: m, m/s, N, kg, s.
"""

import pathlib

import numpy as np
from satgnc.guidance.planning import plan
from satgnc.scenarios import rendezvous

here = pathlib.Path(__file__).resolve().parent if "__file__" in globals() else pathlib.Path.cwd()
scenario = rendezvous.load(here / "user_rendezvous.toml")
problem = rendezvous.problem(scenario, "approach", "linear")
p = plan(problem, "linear")
s = p.summary()
print(f"{p.status} in {p.iterations} ADMM iterations: dv = {s['delta_v']:.4f} m/s, "
      f"miss = {s['miss_position']:.3g} m, {s['nonzero_intervals']} of {p.horizon} intervals thrust, "
      f"max |u| = {1e3 * s['u_max']:.2f} mN (bound {1e3 * scenario.sections['cost']['u_max']:.0f} mN)")
burns = np.flatnonzero(np.abs(p.U).max(axis=1) > 1e-6 * np.abs(p.U).max())
print("thrusting intervals:", burns.tolist())
