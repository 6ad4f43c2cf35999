"""
Propagate with J2 and the state transition matrix
=================================================

Propagate a LEO state with its 6x6 state transition matrix under J2 and exponential drag
(km, km/s, s), and catch a propagation failure.
"""

import numpy as np
import satgnc

x0 = np.array([6778.137, 0.0, 0.0, 0.0, 4.7302, 6.0354])  # 400 km circular, i = 51.6 deg
drag = satgnc.ExponentialDrag(rho0=3.725e-12, h0=400.0, scale_height=58.515, cd=2.2, area=10.0, mass=500.0)
times = np.linspace(0.0, 7200.0, 5)

traj = satgnc.propagate(x0, times, forces=[satgnc.J2Gravity(), drag])
print("states (km, km/s):")
print(np.array2string(traj.states, precision=6, suppress_small=True))
assert traj.stms is not None  # with_stm=True (the default); None without the STM
print("det Phi(2 h) =", np.linalg.det(traj.stms[-1]), "(< 1: drag dissipates)")
print("stats:", traj.stats)

# Failures raise with the time reached and the partial trajectory.
try:
    satgnc.propagate(x0, [0.0, 86400.0], max_steps=50)
except satgnc.PropagationError as err:
    print("PropagationError:", err.status, "at t =", err.t_reached, "s")
