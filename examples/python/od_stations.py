"""
Orbit determination from one and from several stations
======================================================

Simulate range and range-rate of a LEO satellite from ground stations (noise, 0 deg elevation mask),
then estimate its state at the epoch by batch least squares (Levenberg-Marquardt), once from one
station and once from three. One pass of under six minutes leaves the orbit poorly determined
(a position sigma of kilometres); three passes over a revolution bring it to centimetres. Units: km,
km/s, s; angles in degrees.
"""

import numpy as np
from satgnc import od

epoch = "2026-03-20T12:00:00"
truth = np.array([6778.137, 0.0, 0.0, 0.0, 4.7302, 6.0354])  # km, km/s at the epoch (t = 0)
# Three stations under the first revolution's ground track (lat, lon in deg, height in km); each sees
# one pass of 6-10 minutes above 0 deg elevation (od.simulate's default mask).
sites = {"EQUATOR": (0.0, 5.0, 0.0), "NORTH": (45.0, 40.0, 0.2), "SOUTH": (-33.0, -70.0, 0.7)}
stations = [od.station_geodetic(lat, lon, h, epoch) for lat, lon, h in sites.values()]
times = np.arange(0.0, 6000.0, 20.0)  # s: one revolution, every 20 s

guess = truth + np.array([20.0, -20.0, 10.0, 0.01, -0.01, 0.005])  # 30 km, 15 m/s off
for used in ([stations[0]], stations):
    obs = od.simulate(truth, used, times, sigma_range=1e-3, sigma_range_rate=1e-6, seed=1)
    fit = od.solve(obs, used, guess)
    err_m = 1e3 * float(np.linalg.norm(fit.x0[:3] - truth[:3]))
    print(f"{len(used)} station(s), {len(obs)} observations above the horizon: {fit.status.name} in "
          f"{fit.iterations} iterations, position error {err_m:.2f} m, "
          f"1-sigma {1e3 * float(np.sqrt(np.trace(fit.covariance[:3, :3]))):.2f} m")
