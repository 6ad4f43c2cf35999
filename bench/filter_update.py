"""One EKF update, 9 states, one scalar measurement: satgnc's C++ update against filterpy's
KalmanFilter.update (Joseph form, numpy) on the same matrices (same run, same machine; the ratio is
the figure, absolute times move with the load). Goal (issue 15): <= 1 us per update in C++.

satgnc is timed by its private C++ loop (``_satgnc._filter_bench_update``: repeated updates at one
epoch, best of 25 blocks, no gate and no PD check, i.e. the bare update filterpy also does);
filterpy per call with bench/_timing.py (P reset each call, which filterpy's update reads).
Both updates are checked to agree first (1e-12 relative on x and P).
Usage: python bench/filter_update.py (needs filterpy: requirements-bench.txt).
"""

from __future__ import annotations

import os

import numpy as np
from _timing import timeit
from filterpy.kalman import KalmanFilter
from satgnc import _satgnc
from satgnc import filter as sf

n = 9
rng = np.random.default_rng(1)
a = rng.standard_normal((n, n))
p0 = a @ a.T + n * np.eye(n)
h = rng.standard_normal((1, n))
sigma, z = 1.0, 1.0

kf = KalmanFilter(dim_x=n, dim_z=1)
kf.H = h
kf.R = np.array([[sigma**2]])
kf.P = p0.copy()
kf.x = np.zeros((n, 1))
kf.update(np.array([[z]]))
ours = sf.run_filter(phi=np.eye(n), qd=np.zeros((n, n)), x0=np.zeros(n), p0=p0, t=[0.0], value=[z],
                     sigma=[sigma], h=[h], gating=False)
assert np.max(np.abs(ours.states[0] - kf.x[:, 0])) <= 1e-12 * np.max(np.abs(kf.x))
assert np.max(np.abs(ours.covariances[0] - kf.P)) <= 1e-12 * np.max(np.abs(kf.P))


def filterpy_update() -> None:
    kf.x = np.zeros((n, 1))
    kf.P = p0.copy()
    kf.update(np.array([[z]]))


t_fp = timeit(filterpy_update)
t_j = _satgnc._filter_bench_update(p0, h[0], sigma, z, 20000, 25, "joseph") * 1e-9
t_ud = _satgnc._filter_bench_update(p0, h[0], sigma, z, 20000, 25, "ud") * 1e-9
print(f"EKF update, n = 9, one scalar measurement (best block); {os.cpu_count()} cores shared, "
      f"load average {os.getloadavg()[0]:.1f}")
print(f"  filterpy KalmanFilter.update : {t_fp * 1e9:10.0f} ns")
print(f"  satgnc Joseph (C++)          : {t_j * 1e9:10.1f} ns   ({t_fp / t_j:6.0f}x)")
print(f"  satgnc UD (C++)              : {t_ud * 1e9:10.1f} ns   ({t_fp / t_ud:6.0f}x)")
print(f"  goal <= 1000 ns: {'met' if t_j <= 1e-6 else 'NOT met'}")
