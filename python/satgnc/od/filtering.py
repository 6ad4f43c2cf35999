"""Sequential orbit determination: the orbit extended Kalman filter and RTS smoother (issue 15).

:func:`filter` runs the C++ filter of ``satgnc/filter/orbit_filter.hpp`` over ground-station
measurements with light time (the :mod:`satgnc.observation` models) and returns a frozen
:class:`FilterResult` of time-major arrays; :func:`smooth` is the same run followed by the
Rauch-Tung-Striebel smoother.

State (GCRF; the layout is ``FilterResult.state_names``)::

    [x, y, z (km), vx, vy, vz (km/s) | w_x, w_y, w_z (km/s^2, DMC only) |
     range bias per station (km, if estimated) | time bias per station (s, if estimated) |
     Cd, Cr (if estimated)]

Between measurements the state and its STM are propagated with DOP853 on ``force_model``; process
noise is state-noise compensation (white acceleration, PSD ``snc_psd_ric`` in km^2/s^3 along the
radial / in-track / cross-track axes) and, optionally, dynamic-model compensation (first-order
Gauss-Markov accelerations with time constants ``dmc_tau`` s and steady-state sigmas ``dmc_sigma``
km/s^2), discretized with the STM by Gauss-Legendre quadrature. Each measurement passes a chi-square
gate of probability ``gate_probability`` (after ``warmup`` ungated ones); a rejected measurement is
listed (``edited``, ``normalized_residual``), never dropped silently.

Times are seconds on the stations' time axis, which must be the force model's (s after one epoch).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import Any

import numpy as np

from .. import _satgnc as _c
from .._results import Result
from .._validate import as_bool, as_int, as_real, as_real_array, one_of
from ..observation import (
    OBSERVABLES,  # the names the filter accepts: km, km, km/s, km/s, rad pairs
    measurement_model,
)

__all__ = ["FilterResult", "OBSERVABLES", "filter", "smooth", "process_noise"]

STEP_STATUS = tuple(str(s) for s in _c.FILTER_STEP_STATUS)


@dataclasses.dataclass(frozen=True)
class FilterResult(Result):
    """Time-major result of :func:`filter` / :func:`smooth` (K measurements, n states).

    ``status``: "completed" (every step run) or the step status that stopped the filter
    ("propagation_failed", "not_positive_definite"); ``iterations``: steps run.
    Per step k: ``t`` (s), ``station``, ``observable`` (index into ``observables``), ``state`` (K, n),
    ``covariance`` (K, n, n) a posteriori; ``prefit`` / ``postfit`` residuals (K, 2), measured minus
    predicted (second column NaN for scalar observables), ``sigma`` (K, 2), ``nis`` (K,) normalized
    innovation squared, ``normalized_residual`` = sqrt(nis), ``gate`` (K,) the chi-square threshold
    applied (0: ungated), ``edited`` (K,) bool (rejected by the gate), ``step_status`` (K,) names.
    ``rejected``: indices of the edited measurements. ``smoothed_*``: the RTS smoother's states and
    covariances at the same rows and at ``t0`` (None unless smoothed)."""

    status: str
    message: str
    iterations: int
    state_names: tuple[str, ...]
    observables: tuple[str, ...]
    t0: float
    t: np.ndarray
    station: np.ndarray
    observable: np.ndarray
    state: np.ndarray
    covariance: np.ndarray
    prefit: np.ndarray
    postfit: np.ndarray
    sigma: np.ndarray
    nis: np.ndarray
    normalized_residual: np.ndarray
    gate: np.ndarray
    edited: np.ndarray
    step_status: tuple[str, ...]
    rejected: np.ndarray
    propagation_steps: int
    solve_time: float
    smoothed_state: np.ndarray | None = None
    smoothed_covariance: np.ndarray | None = None
    smoothed_initial_state: np.ndarray | None = None
    smoothed_initial_covariance: np.ndarray | None = None

    @property
    def sigma_state(self) -> np.ndarray:
        """(K, n) one-sigma of every state (sqrt of the covariance diagonal)."""
        return np.sqrt(np.diagonal(self.covariance, axis1=1, axis2=2))


def _observable_names(observables: Any) -> tuple[str, ...]:
    if isinstance(observables, str):
        observables = (observables,)
    if not isinstance(observables, Sequence) or len(observables) == 0:
        raise TypeError(f"observables: must be a non-empty list of names from {list(OBSERVABLES)}")
    out = []
    for i, o in enumerate(observables):
        if not isinstance(o, str) or o not in OBSERVABLES:
            raise ValueError(f"observables[{i}]: unknown measurement type {o!r} "
                             f"(hint: one of {list(OBSERVABLES)})")
        out.append(o)
    if len(set(out)) != len(out):
        raise ValueError(f"observables: a type is repeated in {out}")
    return tuple(out)


def _nonneg3(v: Any, name: str) -> np.ndarray:
    a = np.broadcast_to(as_real_array(v, name, ndim=(0, 1)), (3,)).astype(float) if np.ndim(v) == 0 else \
        as_real_array(v, name, shape=(3,))
    if np.any(a < 0):
        raise ValueError(f"{name}: process noise must be >= 0, got {a.tolist()}")
    return np.array(a, dtype=float)


def _process_dict(
    snc_psd_ric: Any, dmc_tau: Any, dmc_sigma: Any, parameters: int, noise_step: Any,
    quadrature_nodes: Any, rtol: Any, atol: Any,
) -> dict[str, Any]:
    dmc = dmc_tau is not None or dmc_sigma is not None
    tau = np.full(3, 600.0) if dmc_tau is None else _nonneg3(dmc_tau, "dmc_tau")
    if np.any(tau <= 0):
        raise ValueError(f"dmc_tau: time constants must be > 0 s, got {tau.tolist()}")
    return {
        "snc_psd_ric": _nonneg3(snc_psd_ric, "snc_psd_ric"),
        "dmc": dmc,
        "dmc_tau": tau,
        "dmc_sigma": np.zeros(3) if dmc_sigma is None else _nonneg3(dmc_sigma, "dmc_sigma"),
        "parameters": parameters,
        "noise_step": as_real(noise_step, "noise_step", positive=True),
        "quadrature_nodes": as_int(quadrature_nodes, "quadrature_nodes", low=1, high=5),
        "rtol": as_real(rtol, "rtol", positive=True),
        "atol": as_real(atol, "atol", positive=True),
    }


def _force_model(fm: Any) -> Any:
    if fm is None:
        fm = _c.ForceModel()
        fm.j2 = _c.J2Gravity()
        return fm
    if not isinstance(fm, _c.ForceModel):
        raise TypeError(f"force_model: must be a satgnc.ForceModel, got {type(fm).__name__}")
    try:
        fm.validate()
    except ValueError as e:
        raise ValueError(f"force_model: {e}") from None
    return fm


def process_noise(
    x: Any,
    t0: float,
    t1: float,
    *,
    force_model: Any = None,
    snc_psd_ric: Any = 0.0,
    dmc_tau: Any = None,
    dmc_sigma: Any = None,
    noise_step: float = 300.0,
    quadrature_nodes: int = 5,
    rtol: float = 1e-12,
    atol: float = 1e-14,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The filter's process model alone: ``(x(t1), Phi, Q)`` from ``x`` at ``t0`` (s) for the state
    [r, v (, w)] (km, km/s (, km/s^2)); Q is the discrete SNC (+ DMC) noise. ValueError for negative
    noise or a failed propagation."""
    proc = _process_dict(snc_psd_ric, dmc_tau, dmc_sigma, 0, noise_step, quadrature_nodes, rtol, atol)
    n = 9 if proc["dmc"] else 6
    xv = as_real_array(x, "x", shape=(n,))
    y, phi, q, status, _ = _c.filter_orbit_propagate(
        _force_model(force_model), proc, as_real(t0, "t0"), as_real(t1, "t1"), xv
    )
    if status != "success":
        raise ValueError(f"x: propagation from t0 to t1 failed ({status})")
    return np.asarray(y), np.asarray(phi), np.asarray(q)


def filter(  # noqa: A001 (satgnc.od.filter is the public name the issue asks for)
    t: Any,
    station: Any,
    observable: Any,
    value: Any,
    *,
    stations: Sequence[Any],
    x0: Any,
    P0: Any,
    t0: float = 0.0,
    method: str = "ekf",
    observables: Sequence[str] = ("two_way_range", "two_way_range_rate"),
    sigma: Any = (0.005, 1e-6),
    force_model: Any = None,
    snc_psd_ric: Any = 0.0,
    dmc_tau: Any = None,
    dmc_sigma: Any = None,
    estimate_range_bias: bool = False,
    estimate_time_bias: bool = False,
    estimate_cd: bool = False,
    estimate_cr: bool = False,
    cd_sigma: float = 0.2,
    cr_sigma: float = 0.2,
    range_bias: Any = 0.0,
    time_bias: Any = 0.0,
    range_bias_sigma: float = 0.01,
    time_bias_sigma: float = 1e-3,
    consider: Sequence[str] = (),
    gating: bool = True,
    gate_probability: float = 0.9973,
    warmup: int = 0,
    noise_step: float = 300.0,
    quadrature_nodes: int = 5,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    troposphere: bool | str = False,
    wavelength_um: float = 0.532,
    relative_humidity: float = 0.5,
    _smooth: bool = False,
) -> FilterResult:
    """Run the orbit EKF (or UKF) over K measurements.

    Parameters
    ----------
    t : array_like
        (K,) measurement tags, s after ``t0``'s epoch (non-decreasing, >= ``t0``).
    station : array_like of int
        (K,) indices into ``stations``.
    observable : array_like of str or int
        (K,) names from ``observables`` or indices into it.
    value : array_like
        (K,) or (K, 2) (angle pairs, rad): km, km/s, rad.
    stations : sequence of StationEphemeris
        :class:`satgnc.observation.RotatingStationEphemeris` or ``EarthFixedStationEphemeris`` (GCRF
        km, km/s; keyword only, as all that follow).
    x0 : array_like
        (6,) GCRF km, km/s at ``t0`` (or the whole state, ``FilterResult.state_names`` order).
    P0 : array_like
        (6, 6) km^2, ... (the DMC and bias priors appended from ``dmc_sigma``, ``range_bias_sigma``
        and ``time_bias_sigma``) or (n, n); symmetric positive definite.
    t0 : float, optional
        Time of ``x0`` (s; default 0).
    method : {"ekf", "ukf"}, optional
        "ekf" (STM covariance propagation, Joseph-form update; default) or "ukf" (2n + 1 sigma points
        through DOP853 and the measurement model; alpha = 1, beta = 2, kappa = 0).
    observables : sequence of str, optional
        The observables set up (names of :data:`OBSERVABLES`; default two-way range and range-rate).
    sigma : array_like, optional
        One value per observable (all stations) or a (stations, observables) array, in the units of
        the observable (default 5 m, 1 mm/s as km, km/s).
    force_model : satgnc.dynamics.ForceModel, optional
        The filter's dynamics (default point mass).
    snc_psd_ric : float or array_like, optional
        SNC white-acceleration PSD, scalar or 3 (km^2/s^3; radial / in-track / cross-track).
    dmc_tau, dmc_sigma : float or array_like, optional
        Dynamic-model compensation: time constant (s) and steady-state sigma (km/s^2).
    estimate_range_bias, estimate_time_bias : bool, optional
        Add one range (km) / time (s) bias state per station.
    estimate_cd, estimate_cr : bool, optional
        Append the drag / SRP coefficients (unit-free; initial values from ``force_model``); their
        STM columns come from the force model's parameter partials.
    cd_sigma, cr_sigma : float, optional
        A priori sigmas of Cd / Cr (unit-free; default 0.2).
    range_bias, time_bias : float or array_like, optional
        Fixed values or initial estimates (km, s), scalar or per station.
    range_bias_sigma, time_bias_sigma : float, optional
        A priori sigmas (km, s; defaults 0.01 km, 1e-3 s).
    consider : sequence of str, optional
        Groups held as consider parameters ("range_bias", "time_bias", "cd", "cr"): not updated, the
        covariance carries their effect.
    gating : bool, optional
        Chi-square editing of measurements (default True).
    gate_probability : float, optional
        The gate's probability in (0, 1) (default 0.9973).
    warmup : int, optional
        Measurements processed before gating starts (default 0).
    noise_step : float, optional
        Longest step of the process-noise discretization (s; default 300).
    quadrature_nodes : int, optional
        Gauss-Legendre nodes of the process-noise integral (default 5).
    rtol, atol : float, optional
        DOP853 tolerances (relative; km and km/s).
    troposphere : bool or {"saastamoinen", "mendes_pavlis", "marini_murray"}, optional
        Model the tropospheric delay on the range observables and its rate on the range-rates
        (default False; True: Saastamoinen, radio; the other two: laser ranging at ``wavelength_um``),
        as :func:`satgnc.observation.measurement_model`.
    wavelength_um : float, optional
        Laser wavelength (micrometres, in [0.3, 1.7]; default 0.532).
    relative_humidity : float, optional
        Of the stations' standard atmosphere, in [0, 1] (default 0.5).

    Returns
    -------
    FilterResult
        Time-major: ``state`` (K, n), ``covariance`` (K, n, n) a posteriori, pre/post-fit residuals,
        NIS, gate and editing flags per step; ``status`` "completed" or the status that stopped it.

    Raises
    ------
    ValueError
        Naming the argument: a P0 that is not positive definite, negative process noise, unsorted
        times, an unknown measurement type or one not in ``observables``, a gate probability outside
        (0, 1), an unknown station index.
    TypeError
        ``stations`` of another type.

    Examples
    --------
    >>> import numpy as np
    >>> from satgnc import od
    >>> from satgnc.od.filter_sim import simulate_tracking, two_station_scenario
    >>> sc = two_station_scenario()  # 500 km LEO (J2) over two stations
    >>> m = simulate_tracking(sc.x0, sc.stations, np.arange(60.0, 1201.0, 60.0),
    ...                       force_model=sc.force_model, seed=1)
    >>> P0 = np.diag([1.0, 1.0, 1.0, 1e-3, 1e-3, 1e-3]) ** 2  # km^2, (km/s)^2
    >>> r = od.filter(m["t"], m["station"], m["observable"], m["value"], stations=list(sc.stations),
    ...               x0=sc.x0 + [0.5, -0.5, 0.2, 0, 0, 0], P0=P0, force_model=sc.force_model)
    >>> err = r.state[-1, :6] - m["truth"][-1]
    >>> r.status, bool(np.all(np.abs(err) < 5 * r.sigma_state[-1, :6]))
    ('completed', True)
    """
    obs_names = _observable_names(observables)
    if not isinstance(stations, Sequence) or isinstance(stations, str) or len(stations) == 0:
        raise TypeError("stations: must be a non-empty list of station ephemerides")
    for i, s in enumerate(stations):
        if not isinstance(s, (_c.RotatingStationEphemeris, _c.EarthFixedStationEphemeris)):
            raise TypeError(f"stations[{i}]: must be a RotatingStationEphemeris or "
                            f"EarthFixedStationEphemeris (satgnc.observation), got {type(s).__name__}")
    ns, no = len(stations), len(obs_names)
    tt = np.atleast_1d(as_real_array(t, "t", ndim=(0, 1)))
    k = tt.size
    if k == 0:
        raise ValueError("t: needs at least one measurement")
    if np.any(np.diff(tt) < 0):
        i = int(np.flatnonzero(np.diff(tt) < 0)[0]) + 1
        raise ValueError(f"t: measurement times must be non-decreasing (sort them), t[{i}] = {tt[i]} < "
                         f"t[{i - 1}] = {tt[i - 1]}")
    t0 = as_real(t0, "t0")
    if tt[0] < t0:
        raise ValueError(f"t: the first measurement ({tt[0]} s) is before t0 = {t0} s")
    st = np.atleast_1d(np.asarray(station))
    if st.shape != (k,) or st.dtype.kind not in "iu":
        raise ValueError(f"station: must be ({k},) integer indices into stations, got shape {st.shape}")
    if np.any((st < 0) | (st >= ns)):
        raise ValueError(f"station: indices must be in [0, {ns}), got {int(st.min())}..{int(st.max())}")
    ob_in = np.atleast_1d(np.asarray(observable))
    if ob_in.shape != (k,):
        raise ValueError(f"observable: must have shape ({k},), got {ob_in.shape}")
    if ob_in.dtype.kind in "iu":
        ob = ob_in.astype(np.int64)
        if np.any((ob < 0) | (ob >= no)):
            raise ValueError(f"observable: indices must be in [0, {no}) (the observables set up)")
    else:
        index = {n: i for i, n in enumerate(obs_names)}
        ob = np.empty(k, dtype=np.int64)
        for i, name in enumerate(ob_in.tolist()):
            if name not in index:
                hint = "unknown measurement type" if name not in OBSERVABLES else "not set up"
                raise ValueError(f"observable[{i}]: {hint}: {name!r} "
                                 f"(the filter was set up for {list(obs_names)})")
            ob[i] = index[name]
    val = as_real_array(value, "value", ndim=(1, 2))
    if val.ndim == 1:
        val = np.stack([val, np.zeros_like(val)], axis=1)
    if val.shape != (k, 2) and not (val.ndim == 2 and val.shape == (k, 1)):
        raise ValueError(f"value: must have shape ({k},) or ({k}, 2), got {val.shape}")
    if val.shape[1] == 1:
        val = np.hstack([val, np.zeros((k, 1))])
    sig = as_real_array(sigma, "sigma", ndim=(0, 1, 2))
    sig = np.broadcast_to(sig, (ns, no)) if sig.ndim < 2 else sig
    if sig.shape != (ns, no):
        raise ValueError(f"sigma: must be one value per observable ({no},) or ({ns}, {no}), got {sig.shape}")
    if np.any(sig <= 0):
        raise ValueError("sigma: measurement sigmas must be > 0")
    er = as_bool(estimate_range_bias, "estimate_range_bias")
    et = as_bool(estimate_time_bias, "estimate_time_bias")
    rb = np.broadcast_to(as_real_array(range_bias, "range_bias", ndim=(0, 1)), (ns,)).astype(float)
    tb = np.broadcast_to(as_real_array(time_bias, "time_bias", ndim=(0, 1)), (ns,)).astype(float)
    dmc = dmc_tau is not None or dmc_sigma is not None
    off = 9 if dmc else 6
    names = ["x", "y", "z", "vx", "vy", "vz"] + (["w_x", "w_y", "w_z"] if dmc else [])
    rbs = [-1] * ns
    tbs = [-1] * ns
    if er:
        rbs = list(range(off, off + ns))
        names += [f"range_bias_{i}" for i in range(ns)]
        off += ns
    if et:
        tbs = list(range(off, off + ns))
        names += [f"time_bias_{i}" for i in range(ns)]
        off += ns
    fmodel = _force_model(force_model)
    cd_i = cr_i = -1
    if as_bool(estimate_cd, "estimate_cd"):
        if fmodel.drag is None and fmodel.atmosphere_drag is None:
            raise ValueError("estimate_cd: the force model has no drag term (drag or atmosphere_drag)")
        cd_i, off = off, off + 1
        names.append("cd")
    if as_bool(estimate_cr, "estimate_cr"):
        if fmodel.srp is None:
            raise ValueError("estimate_cr: the force model has no SRP term (srp)")
        cr_i, off = off, off + 1
        names.append("cr")
    n = off
    proc = _process_dict(snc_psd_ric, dmc_tau, dmc_sigma, n - (9 if dmc else 6), noise_step, quadrature_nodes,
                         rtol, atol)
    proc["cd_state"], proc["cr_state"] = cd_i, cr_i
    cons: list[int] = []
    if isinstance(consider, str):
        consider = (consider,)
    for i, c in enumerate(consider):
        if c == "range_bias" and er:
            cons += rbs
        elif c == "time_bias" and et:
            cons += tbs
        elif c == "cd" and cd_i >= 0:
            cons.append(cd_i)
        elif c == "cr" and cr_i >= 0:
            cons.append(cr_i)
        else:
            raise ValueError(f"consider[{i}]: must be 'range_bias', 'time_bias', 'cd' or 'cr' with the "
                             f"matching estimate_*=True, got {c!r}")
    x0v = as_real_array(x0, "x0", ndim=1)
    if x0v.size == 6:
        full = np.zeros(n)
        full[:6] = x0v
        for i in range(ns):
            if rbs[i] >= 0:
                full[rbs[i]] = rb[i]
            if tbs[i] >= 0:
                full[tbs[i]] = tb[i]
        if cd_i >= 0:
            full[cd_i] = fmodel.drag.cd if fmodel.drag is not None else fmodel.atmosphere_drag.cd
        if cr_i >= 0:
            full[cr_i] = fmodel.srp.cr
        x0v = full
    if x0v.size != n:
        raise ValueError(f"x0: must have 6 or {n} entries ({names}), got {x0v.size}")
    p0 = as_real_array(P0, "P0", ndim=2)
    if p0.shape == (6, 6) and n > 6:
        full_p = np.zeros((n, n))
        full_p[:6, :6] = p0
        if dmc:
            full_p[6:9, 6:9] = np.diag(np.maximum(proc["dmc_sigma"], 1e-30) ** 2)
        rs = as_real(range_bias_sigma, "range_bias_sigma", positive=True)
        ts = as_real(time_bias_sigma, "time_bias_sigma", positive=True)
        for i in range(ns):
            if rbs[i] >= 0:
                full_p[rbs[i], rbs[i]] = rs * rs
            if tbs[i] >= 0:
                full_p[tbs[i], tbs[i]] = ts * ts
        if cd_i >= 0:
            full_p[cd_i, cd_i] = as_real(cd_sigma, "cd_sigma", positive=True) ** 2
        if cr_i >= 0:
            full_p[cr_i, cr_i] = as_real(cr_sigma, "cr_sigma", positive=True) ** 2
        p0 = full_p
    if p0.shape != (n, n):
        raise ValueError(f"P0: must have shape (6, 6) or ({n}, {n}), got {p0.shape}")
    if not np.allclose(p0, p0.T, rtol=0, atol=1e-12 * np.abs(p0).max()):
        raise ValueError("P0: must be symmetric")
    try:
        np.linalg.cholesky(p0)
    except np.linalg.LinAlgError:
        ev = float(np.linalg.eigvalsh(p0).min())
        raise ValueError(f"P0: must be positive definite (smallest eigenvalue {ev:.3g})") from None
    fs = {
        "method": one_of(method, "method", ("ekf", "ukf")),
        "gating": as_bool(gating, "gating"),
        "gate_probability": as_real(gate_probability, "gate_probability"),
        "warmup": as_int(warmup, "warmup", low=0),
        "consider": cons,
    }
    if not 0.0 < fs["gate_probability"] < 1.0:
        raise ValueError(f"gate_probability: must be in (0, 1), got {fs['gate_probability']}")
    angles = ("azimuth_elevation", "right_ascension_declination")
    models = [
        measurement_model(o, troposphere=False if o in angles else troposphere, wavelength_um=wavelength_um,
                          relative_humidity=relative_humidity)
        for o in obs_names
    ]
    stn = {"sigma": np.ascontiguousarray(sig, dtype=float), "range_bias_state": rbs, "time_bias_state": tbs,
           "range_bias": rb.tolist(), "time_bias": tb.tolist()}
    d = _c.filter_orbit_run(
        fmodel, list(stations), models, proc, stn, fs, t0, x0v, p0, tt.tolist(),
        st.astype(int).tolist(), ob.astype(int).tolist(), np.ascontiguousarray(val), bool(_smooth),
    )
    codes = np.asarray(d["status"])
    step_status = tuple(STEP_STATUS[c] for c in codes)
    stop = [s for s in step_status if s in ("propagation_failed", "not_positive_definite")]
    status = stop[0] if stop else "completed"
    edited = codes == 1
    msg = (f"{int(d['steps_run'])} of {k} measurements processed, {int(edited.sum())} rejected by the gate"
           + (f"; stopped: {status}" if stop else ""))
    extra: dict[str, Any] = {}
    if _smooth and "smoothed_state" in d:
        extra = {
            "smoothed_state": np.asarray(d["smoothed_state"]),
            "smoothed_covariance": np.asarray(d["smoothed_covariance"]),
            "smoothed_initial_state": np.asarray(d["smoothed_initial_state"]),
            "smoothed_initial_covariance": np.asarray(d["smoothed_initial_covariance"]),
        }
    return FilterResult(
        status=status,
        message=msg,
        iterations=int(d["steps_run"]),
        state_names=tuple(names),
        observables=obs_names,
        t0=t0,
        t=np.asarray(d["t"]),
        station=np.asarray(d["station"]),
        observable=np.asarray(d["observable"]),
        state=np.asarray(d["state"]),
        covariance=np.asarray(d["covariance"]),
        prefit=np.asarray(d["prefit"]),
        postfit=np.asarray(d["postfit"]),
        sigma=np.asarray(d["sigma"]),
        nis=np.asarray(d["nis"]),
        normalized_residual=np.asarray(d["normalized_residual"]),
        gate=np.asarray(d["gate"]),
        edited=edited,
        step_status=step_status,
        rejected=np.flatnonzero(edited),
        propagation_steps=int(d["propagation_steps"]),
        solve_time=float(d["solve_time"]),
        **extra,
    )


def smooth(t: Any, station: Any, observable: Any, value: Any, **kwargs: Any) -> FilterResult:
    """:func:`filter` followed by the fixed-interval Rauch-Tung-Striebel smoother.

    Parameters
    ----------
    t, station, observable, value : array_like
        The measurements, as :func:`filter`.
    **kwargs
        The keywords of :func:`filter` (``stations``, ``x0`` GCRF km, km/s, ``P0``, ...).

    Returns
    -------
    FilterResult
        With ``smoothed_state`` / ``smoothed_covariance`` (K rows; km, km/s) and
        ``smoothed_initial_state`` / ``smoothed_initial_covariance`` (at ``t0``) set.

    Raises
    ------
    ValueError
        As :func:`filter`.
    TypeError
        As :func:`filter`, and the private keyword ``_smooth``.

    Examples
    --------
    >>> import numpy as np
    >>> from satgnc import od
    >>> from satgnc.od.filter_sim import simulate_tracking, two_station_scenario
    >>> sc = two_station_scenario()  # 500 km LEO (J2) over two stations
    >>> m = simulate_tracking(sc.x0, sc.stations, np.arange(60.0, 1201.0, 60.0),
    ...                       force_model=sc.force_model, seed=1)
    >>> P0 = np.diag([1.0, 1.0, 1.0, 1e-3, 1e-3, 1e-3]) ** 2  # km^2, (km/s)^2
    >>> r = od.smooth(m["t"], m["station"], m["observable"], m["value"], stations=list(sc.stations),
    ...               x0=sc.x0 + [0.5, -0.5, 0.2, 0, 0, 0], P0=P0, force_model=sc.force_model)
    >>> sig0 = np.sqrt(np.diag(r.smoothed_initial_covariance))[:6]
    >>> bool(np.all(np.abs(r.smoothed_initial_state[:6] - sc.x0) < 5 * sig0))
    True
    """
    if "_smooth" in kwargs:
        raise TypeError("smooth: unexpected keyword '_smooth'")
    return filter(t, station, observable, value, _smooth=True, **kwargs)
