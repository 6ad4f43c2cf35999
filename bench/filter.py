"""Orbit filter bench (issue 15): a whole two-station tracking arc (6 h, two passes of each station,
220 two-way range / range-rate records, J2, light time) filtered by

- satgnc: ``satgnc.od.filter`` (C++ EKF: DOP853 state + STM between records, SNC noise by
  Gauss-Legendre quadrature, Joseph update, chi-square gate), one call;
- filterpy: ``filterpy.kalman.ExtendedKalmanFilter`` driven from Python with the same models:
  propagation of the state and the STM by ``scipy.integrate.solve_ivp(method="DOP853")`` on a numpy
  point-mass + J2 right-hand side with its analytic Jacobian (same tolerances), the SNC noise by the
  force-free closed form, and the measurement (two-way light-time range / range-rate and partials) by
  satgnc's observation model called from Python once per record (``satgnc.observation.predict``).

Both start from the same 1.5 km initial error; the bench prints the wall time of each (best of
``--repeat``), the ratio (goal >= 50x) and the difference of the final estimates against the
1-sigma. ``--write-tdm PATH`` instead writes the scenario's tracking as a CCSDS TDM (the file
tests/data/filter/two_station.tdm was made so).

Run: ``.venv/bin/python bench/filter.py`` (needs filterpy: requirements-bench.txt).
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import pathlib
import sys
import time

import numpy as np
import satgnc
import satgnc.observation
from satgnc.od import filter_sim as fsim

_G = satgnc._satgnc.J2Gravity()  # the same constants as the C++ force model
MU, J2, RE = float(_G.mu), float(_G.j2), float(_G.radius)
RTOL, ATOL = 1e-10, 1e-12
DX0 = np.array([0.8, -1.2, 0.5, 4e-4, -6e-4, 2e-4])
P0 = np.diag([1.0] * 3 + [1e-6] * 3)
SNC = 1e-15  # km^2/s^3, isotropic
EPOCH = dt.datetime(2023, 2, 25)  # UTC of t = 0 (fsim.EPOCH_JD)


def scenario():
    sc = fsim.two_station_scenario()
    sim = fsim.simulate_tracking(
        sc.x0, sc.stations, np.arange(20.0, 6 * 3600.0 + 1, 20.0), seed=11, force_model=sc.force_model
    )
    return sc, sim


def write_tdm(path: pathlib.Path) -> None:
    """The scenario's tracking as a CCSDS TDM KVN (one segment per station, PATH 1,2,1)."""
    sc, sim = scenario()
    kw = {0: "RANGE", 1: "DOPPLER_INSTANTANEOUS"}
    lines = [
        "CCSDS_TDM_VERS = 2.0",
        "COMMENT satgnc two-station scenario (satgnc.od.filter_sim, seed 11): 500 km 51.6 deg LEO, J2 truth,",
        "COMMENT two-way light-time range (5 m noise) and range-rate (1 mm/s), 20 s, elevation > 10 deg.",
        "COMMENT Stations: STN_A 40 N 105 W 1.6 km, STN_B 35 S 149 E 0.7 km (WGS-84).",
        "COMMENT Made by bench/filter.py --write-tdm.",
        "CREATION_DATE = 2026-12-02T00:00:00",
        "ORIGINATOR = SATGNC",
    ]
    for s, name in enumerate(("STN_A", "STN_B")):
        lines += [
            "META_START",
            "TIME_SYSTEM = UTC",
            f"PARTICIPANT_1 = {name}",
            "PARTICIPANT_2 = SAT",
            "MODE = SEQUENTIAL",
            "PATH = 1,2,1",
            "RANGE_UNITS = km",
            "META_STOP",
            "DATA_START",
        ]
        for t, st, ob, v in zip(sim["t"], sim["station"], sim["observable"], sim["value"][:, 0]):
            if st != s:
                continue
            ep = (EPOCH + dt.timedelta(seconds=float(t))).isoformat(timespec="milliseconds")
            lines.append(f"{kw[int(ob)]} = {ep} {float(v)!r}")
        lines.append("DATA_STOP")
    path.write_text("\n".join(lines) + "\n")
    print(f"wrote {sim['t'].size} observations to {path}")


def run_satgnc(sc, sim):
    return satgnc.od.filter(
        sim["t"],
        sim["station"],
        sim["observable"],
        sim["value"],
        stations=list(sc.stations),
        x0=sc.x0 + DX0,
        P0=P0,
        force_model=sc.force_model,
        snc_psd_ric=SNC,
        rtol=RTOL,
        atol=ATOL,
    )


def _rhs(t, y):
    r = y[:3]
    v = y[3:6]
    x, yy, z = r
    r2 = r @ r
    rn = np.sqrt(r2)
    k = MU / (r2 * rn)
    a = -k * r
    da = 3 * k / r2 * np.outer(r, r) - k * np.eye(3)
    c = 1.5 * J2 * MU * RE**2 / rn**5
    zr = z * z / r2
    a = a - c * np.array([x * (1 - 5 * zr), yy * (1 - 5 * zr), z * (3 - 5 * zr)])
    # J2 Jacobian by a central difference of the closed-form acceleration (numpy-side model)
    h = 1e-3
    for j in range(3):
        rp = r.copy()
        rm = r.copy()
        rp[j] += h
        rm[j] -= h
        da[:, j] += (_j2(rp) - _j2(rm)) / (2 * h)
    phi = y[6:].reshape(6, 6)
    A = np.zeros((6, 6))
    A[:3, 3:] = np.eye(3)
    A[3:, :3] = da
    return np.concatenate([v, a, (A @ phi).ravel()])


def _j2(r):
    x, yy, z = r
    r2 = r @ r
    rn = np.sqrt(r2)
    c = 1.5 * J2 * MU * RE**2 / rn**5
    zr = z * z / r2
    return -c * np.array([x * (1 - 5 * zr), yy * (1 - 5 * zr), z * (3 - 5 * zr)])


def run_filterpy(sc, sim):
    from filterpy.kalman import ExtendedKalmanFilter
    from scipy.integrate import solve_ivp

    obs = satgnc.observation
    models = [obs.measurement_model("two_way_range"), obs.measurement_model("two_way_range_rate")]
    sig = [0.005, 1e-6]
    ekf = ExtendedKalmanFilter(dim_x=6, dim_z=1)
    ekf.x = (sc.x0 + DX0).reshape(6, 1)
    ekf.P = P0.copy()
    t = 0.0
    for tk, st, ob, v in zip(sim["t"], sim["station"], sim["observable"], sim["value"][:, 0]):
        dt_ = float(tk) - t
        if dt_ > 0:
            y0 = np.concatenate([ekf.x.ravel(), np.eye(6).ravel()])
            sol = solve_ivp(_rhs, (t, float(tk)), y0, method="DOP853", rtol=RTOL, atol=ATOL)
            y = sol.y[:, -1]
            ekf.F = y[6:].reshape(6, 6)
            q = np.zeros((6, 6))
            q[:3, :3] = SNC * dt_**3 / 3 * np.eye(3)
            q[:3, 3:] = q[3:, :3] = SNC * dt_**2 / 2 * np.eye(3)
            q[3:, 3:] = SNC * dt_ * np.eye(3)
            ekf.Q = q
            ekf.P = ekf.F @ ekf.P @ ekf.F.T + ekf.Q
            ekf.x = y[:6].reshape(6, 1)
            t = float(tk)
        m = models[int(ob)]
        station = sc.stations[int(st)]

        def hj(x, m=m, station=station, tk=tk):
            return obs.predict(m, station, float(tk), x.ravel()).dx.reshape(1, 6)

        def hx(x, m=m, station=station, tk=tk):
            return np.array([[obs.predict(m, station, float(tk), x.ravel()).value[0]]])

        ekf.update(np.array([[v]]), hj, hx, R=np.array([[sig[int(ob)] ** 2]]))
    return ekf


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--write-tdm", type=pathlib.Path)
    a = ap.parse_args()
    if a.write_tdm:
        write_tdm(a.write_tdm)
        return 0
    sc, sim = scenario()
    ts, tf = [], []
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        r = run_satgnc(sc, sim)
        ts.append(time.perf_counter() - t0)
    for _ in range(max(1, a.repeat // 3)):
        t0 = time.perf_counter()
        ekf = run_filterpy(sc, sim)
        tf.append(time.perf_counter() - t0)
    xs = r.state[-1, :6]
    xf = ekf.x.ravel()
    sig = r.sigma_state[-1, :6]
    k = sim["t"].size
    print(f"two-station arc: {k} records over 6 h, J2, light time; EKF from a 1.5 km error; "
          f"{os.cpu_count()} cores shared, load average {os.getloadavg()[0]:.1f}")
    print(
        f"satgnc.od.filter    : {min(ts) * 1e3:9.2f} ms (best of {len(ts)}), "
        f"{r.propagation_steps} DOP853 steps, "
        f"final position error {np.linalg.norm(xs[:3] - sim['truth'][-1, :3]) * 1e3:.3f} m"
    )
    print(
        f"filterpy EKF+scipy  : {min(tf) * 1e3:9.2f} ms (best of {len(tf)}), "
        f"final position error {np.linalg.norm(xf[:3] - sim['truth'][-1, :3]) * 1e3:.3f} m"
    )
    print(f"speed-up            : {min(tf) / min(ts):9.1f}x (goal >= 50x)")
    print(f"|satgnc - filterpy| / sigma, final state: max {np.max(np.abs(xs - xf) / sig):.3g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
