"""Scenarios for the orbit filter: simulated multi-station tracking and a NEES / NIS Monte Carlo.

- :func:`two_station_scenario`: a 500 km, 51.6 deg LEO (J2) seen by two stations (40 N 105 W and
  35 S 149 E, the paper's rotating-Earth model) -- the data of tests/python/test_orbit_filter.py,
  bench/filter.py and docs/orbit_filter.md;
- :func:`simulate_tracking`: measurements of the observation room's light-time models on a truth
  trajectory, above an elevation mask, with seeded Gaussian noise and range biases;
- :func:`monte_carlo_nees`: N seeded runs of :func:`satgnc.od.filter` (initial error drawn from P0,
  fresh measurement noise) returning NEES and NIS per run and step, on the executors of
  :mod:`satgnc.od.sweep` ("serial", "process" or "dask").
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .. import _satgnc as _c
from .._results import Result
from .._validate import as_int, as_real, as_real_array
from . import filtering as _f
from . import sweep as _sweep

__all__ = ["Scenario", "two_station_scenario", "simulate_tracking", "MonteCarloNees", "monte_carlo_nees",
           "chi2_mean_band"]

#: UTC Julian date of t = 0 of the scenario (2023-02-25T00:00).
EPOCH_JD = 2460000.5


@dataclasses.dataclass(frozen=True)
class Scenario(Result):
    """A tracking scenario: truth state ``x0`` (GCRF km, km/s at t = 0), the stations
    (StationEphemeris, t = s after :data:`EPOCH_JD`) and the truth force model (J2)."""

    x0: np.ndarray
    stations: tuple[Any, ...]
    force_model: Any


def two_station_scenario() -> Scenario:
    """The two-station LEO scenario (see the module doc)."""
    fm = _c.ForceModel()
    fm.j2 = _c.J2Gravity()
    st = []
    for lat, lon, h in ((40.0, -105.0, 1.6), (-35.0, 149.0, 0.7)):
        wgs = _c.od_ellipsoid_by_name("WGS-84")
        s = _c.Station.from_geodetic(lat, lon, h, EPOCH_JD, 0.0, wgs, _c.EARTH_OMEGA)
        st.append(_c.RotatingStationEphemeris(s, "WGS-84"))
    x0 = np.array([6878.0, 0.0, 0.0, 0.0, 4.737, 5.987])
    return Scenario(x0=x0, stations=tuple(st), force_model=fm)


def _truth(x0: np.ndarray, times: np.ndarray, fm: Any) -> np.ndarray:
    proc = _f._process_dict(0.0, None, None, 0, 300.0, 5, 1e-12, 1e-14)
    out = np.empty((times.size, 6))
    x = np.asarray(x0, dtype=float)
    t = 0.0
    for i, tk in enumerate(times):
        x, _, _, status, _ = _c.filter_orbit_propagate(fm, proc, t, float(tk), x)
        if status != "success":
            raise ValueError(f"x0: truth propagation failed at t = {tk} s ({status})")
        x = np.asarray(x)
        out[i] = x
        t = float(tk)
    return out


def simulate_tracking(
    x0: Any,
    stations: Sequence[Any],
    times: Any,
    *,
    observables: Sequence[str] = ("two_way_range", "two_way_range_rate"),
    sigma: Any = (0.005, 1e-6),
    force_model: Any = None,
    seed: int | None = 0,
    min_elevation_deg: float = 10.0,
    range_bias: Any = 0.0,
) -> dict[str, np.ndarray]:
    """Measurements of every observable by every station above ``min_elevation_deg`` at ``times``
    (s, increasing): dict with ``t``, ``station``, ``observable`` (index), ``value`` (K, 2) and
    ``truth`` (K, 6), the true state at each tag. ``sigma``: per observable (km, km/s, rad);
    ``range_bias``: km, scalar or per station, added to the range observables; ``seed=None``: no
    noise."""
    obs = _f._observable_names(observables)
    tt = np.atleast_1d(as_real_array(times, "times", ndim=(0, 1)))
    if np.any(np.diff(tt) <= 0) or tt.size == 0 or tt[0] <= 0:
        raise ValueError("times: must be > 0 and strictly increasing")
    sig = np.broadcast_to(as_real_array(sigma, "sigma", ndim=(0, 1)), (len(obs),))
    rb = np.broadcast_to(as_real_array(range_bias, "range_bias", ndim=(0, 1)), (len(stations),))
    mask = math.radians(as_real(min_elevation_deg, "min_elevation_deg", low=-90.0, high=90.0))
    fm = _f._force_model(force_model)
    truth = _truth(np.asarray(x0, dtype=float), tt, fm)
    rng = np.random.default_rng(seed) if seed is not None else None
    azel = _c.MeasurementModel("azimuth_elevation")
    models = [_c.MeasurementModel(o) for o in obs]
    rows: dict[str, list[Any]] = {"t": [], "station": [], "observable": [], "value": [], "truth": []}
    for si, s in enumerate(stations):
        el = azel.predict_many(s, tt.tolist(), truth, 0.0, 0.0)
        vis = (np.asarray(el["status"]) == 0) & (np.asarray(el["value"])[:, 1] >= mask)
        idx = np.flatnonzero(vis)
        if idx.size == 0:
            continue
        for oi, (o, m) in enumerate(zip(obs, models)):
            bias = float(rb[si]) if "range" in o and "rate" not in o else 0.0
            p = m.predict_many(s, tt[idx].tolist(), truth[idx], bias, 0.0)
            v = np.asarray(p["value"]).copy()
            if rng is not None:
                v += rng.normal(0.0, sig[oi], size=v.shape)
            if int(m.size) == 1:
                v[:, 1] = 0.0
            for j, k in enumerate(idx):
                rows["t"].append(tt[k])
                rows["station"].append(si)
                rows["observable"].append(oi)
                rows["value"].append(v[j])
                rows["truth"].append(truth[k])
    if not rows["t"]:
        raise ValueError("min_elevation_deg: no station sees the satellite at any of times")
    t = np.asarray(rows["t"])
    order = np.lexsort((np.asarray(rows["observable"]), np.asarray(rows["station"]), t))
    return {
        "t": t[order],
        "station": np.asarray(rows["station"], dtype=np.int64)[order],
        "observable": np.asarray(rows["observable"], dtype=np.int64)[order],
        "value": np.asarray(rows["value"])[order],
        "truth": np.asarray(rows["truth"])[order],
    }


def chi2_mean_band(dof: int, runs: int, p: float = 0.95) -> tuple[float, float]:
    """Two-sided ``p`` band of the mean of ``runs`` independent chi-square(``dof``) variables
    (chi2(runs * dof) / runs quantiles, from scipy)."""
    from scipy.stats import chi2

    a = (1.0 - p) / 2.0
    n = runs * dof
    return float(chi2.ppf(a, n) / runs), float(chi2.ppf(1.0 - a, n) / runs)


@dataclasses.dataclass(frozen=True)
class MonteCarloNees(Result):
    """NEES (runs, K) of the 6 orbit states and NIS (runs, K) per run and step; ``t`` (K,) tags;
    ``band`` the 95 % band of the mean NEES over the runs; ``executor`` used."""

    t: np.ndarray
    nees: np.ndarray
    nis: np.ndarray
    size: np.ndarray
    band: tuple[float, float]
    executor: str


def _mc_chunk(job: tuple[dict[str, Any], list[int]]) -> list[tuple[np.ndarray, np.ndarray]]:
    """One chunk of Monte Carlo runs (top level: picklable for the process and Dask executors)."""
    cfg, seeds = job
    sc = two_station_scenario()
    out = []
    for seed in seeds:
        rng = np.random.default_rng(seed)
        sim = simulate_tracking(sc.x0, sc.stations, cfg["times"], seed=int(rng.integers(2**31)),
                                force_model=sc.force_model)
        p0 = np.asarray(cfg["P0"])
        x0 = sc.x0 + np.linalg.cholesky(p0) @ rng.standard_normal(6)
        r = _f.filter(sim["t"], sim["station"], sim["observable"], sim["value"], stations=list(sc.stations),
                      x0=x0, P0=p0, force_model=sc.force_model, gating=False, rtol=1e-12, atol=1e-14,
                      method=cfg.get("method", "ekf"), snc_psd_ric=cfg.get("snc_psd_ric", 0.0))
        e = r.state[:, :6] - sim["truth"]
        nees = np.einsum("ki,ki->k", e, np.linalg.solve(r.covariance[:, :6, :6], e[..., None])[..., 0])
        out.append((nees, np.asarray(r.nis)))
    return out


def monte_carlo_nees(
    runs: int = 100,
    *,
    duration: float = 900.0,
    step: float = 20.0,
    start: float = 0.0,
    P0: Any = None,
    seed: int = 0,
    executor: str = "serial",
    workers: int | None = None,
    client: Any = None,
    method: str = "ekf",
    snc_psd_ric: Any = 0.0,
) -> MonteCarloNees:
    """``runs`` seeded filter runs over the two-station scenario between ``start`` and ``start +
    duration`` s (tags every ``step`` s, the stations' visibility deciding which exist), initial error
    ~ N(0, P0) (default 100 m, 0.1 m/s per axis), no process noise (the filter's model is the truth);
    NEES of the orbit states and NIS per run and step. ``executor``: "serial", "process" or "dask"
    (:func:`satgnc.od.sweep.run_chunks`). ``method`` ("ekf" or "ukf") and ``snc_psd_ric``
    (km^2/s^3, default 0: the filter's model is the truth) are passed to :func:`satgnc.od.filter`."""
    runs = as_int(runs, "runs", low=1)
    seed = as_int(seed, "seed", low=0)
    if P0 is None:
        P0 = np.diag([0.1**2] * 3 + [1e-4**2] * 3)
    p0 = as_real_array(P0, "P0", shape=(6, 6))
    times = np.arange(start + step, start + duration + 1e-9, as_real(step, "step", positive=True))
    seeds = [int(s) for s in np.random.SeedSequence(seed).generate_state(runs)]
    nchunks = 1 if executor == "serial" else min(runs, 2 * (workers or 2))
    if method not in ("ekf", "ukf"):
        raise ValueError(f"method: must be 'ekf' or 'ukf', got {method!r}")
    cfg = {"times": times, "P0": p0, "method": method, "snc_psd_ric": snc_psd_ric}
    jobs = [(cfg, list(c)) for c in _sweep.split(seeds, nchunks)]
    res = _sweep.run_chunks(_mc_chunk, jobs, executor=executor, workers=workers, progress=False,
                            label="filter MC", client=client)
    flat = [x for chunk in res for x in chunk]
    nees = np.array([a for a, _ in flat])
    nis = np.array([b for _, b in flat])
    sc = two_station_scenario()
    sim = simulate_tracking(sc.x0, sc.stations, times, seed=None, force_model=sc.force_model)
    sizes = np.ones(sim["t"].size, dtype=np.int64)
    return MonteCarloNees(t=sim["t"], nees=nees, nis=nis, size=sizes, band=chi2_mean_band(6, runs),
                          executor=executor)
