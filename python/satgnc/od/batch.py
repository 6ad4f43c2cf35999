"""Batch least-squares orbit determination on real tracking data (issue 13 item 6).

:func:`batch_estimate` estimates the GCRF state at an epoch (km, km/s) and per-station range (km) and
time (s) biases from two-way / one-way range, range-rate, azimuth/elevation and RA/Dec measured by
several ground stations (:class:`satgnc.observation.StationEphemeris`, e.g. a
:class:`satgnc.frames.GroundStation` on the IAU 2006/2000A chain with EOP), with the light-time
models of :mod:`satgnc.observation`, satgnc's DOP853 with the STM on any
:class:`satgnc.dynamics.ForceModel`, Gauss-Newton with a backtracking line search and the stated
convergence test (the remaining Gauss-Newton step is at most ``sigma_tol`` formal sigmas long).
C++: ``satgnc/od/batch.hpp``; docs/od.md "Batch least squares on tracking data".

Measurements come as a :class:`TrackingData` (:func:`tracking_data` from arrays,
:func:`read_tracking_tdm` from a CCSDS TDM) or a TDM file path.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .. import _satgnc
from .._results import Result, adopt
from .._validate import as_bool, as_int, as_real, as_real_array, one_of
from ..observation import OBSERVABLES  # names in the order of their integer codes (ObservableType)
from ..observation import STATUS_NAMES as _OBS_STATUS

TrackingData = _satgnc.TrackingData

_PAIRS = (4, 5)

__all__ = [
    "OBSERVABLES",
    "BatchResult",
    "TrackingData",
    "batch_estimate",
    "batch_residuals",
    "read_tracking_tdm",
    "tracking_data",
]


def _epoch(value: Any, name: str = "epoch") -> Any:
    if not isinstance(value, _satgnc.Epoch):
        raise TypeError(f"{name}: must be a satgnc.time.Epoch, got {type(value).__name__}")
    return value


def _type_codes(types: Any, n: int) -> np.ndarray:
    if isinstance(types, str):
        types = [types] * n
    seq = list(types)
    if len(seq) != n:
        raise ValueError(f"types: must have one entry per measurement ({n}), got {len(seq)}")
    codes = np.empty(n, dtype=np.int32)
    for i, v in enumerate(seq):
        if isinstance(v, str):
            if v not in OBSERVABLES:
                raise ValueError(f"types[{i}]: must be one of {list(OBSERVABLES)}, got {v!r}")
            codes[i] = OBSERVABLES.index(v)
        else:
            codes[i] = as_int(v, f"types[{i}]", low=0, high=5)
    return codes


def tracking_data(
    t: Any,
    types: Any,
    stations: Any,
    values: Any,
    sigmas: Any,
    *,
    epoch: Any,
    n_stations: int | None = None,
    corrections: Any = None,
    order: str = "sort",
) -> Any:
    """A :class:`TrackingData` from arrays.

    Parameters
    ----------
    t : array_like
        (n,) reception tags, s after ``epoch``.
    types : str, int or sequence
        One observable name of :data:`OBSERVABLES` (or its code) per measurement, or one for all.
    stations : array_like of int
        (n,) station indices.
    values : array_like
        (n,) or (n, 2): km, km/s, rad (angle pairs need 2 columns).
    sigmas : float or array_like
        A number, (n,) or (n, 2), > 0, in the units of the values.
    epoch : satgnc.time.Epoch
        The epoch of t = 0 (keyword only).
    n_stations : int, optional
        Number of stations (default: the largest index + 1).
    corrections : array_like of int, optional
        (n,) flags of corrections already applied (1 troposphere, 2 Shapiro; range and range-rate
        observables).
    order : {"sort", "require_sorted"}, optional
        "sort" (stable sort by time, default) or "require_sorted" (an error names the first index out
        of order).

    Returns
    -------
    TrackingData
        The validated, time-sorted measurements.

    Raises
    ------
    ValueError
        Naming the argument (and the index): wrong shapes, an unknown observable, a sigma <= 0, a
        non-finite value, an unsorted tag with ``order="require_sorted"``.
    TypeError
        ``epoch`` not an Epoch, non-numeric arrays.

    Examples
    --------
    >>> import numpy as np
    >>> from satgnc import od
    >>> from satgnc.od.filter_sim import simulate_tracking, two_station_scenario
    >>> from satgnc.time import Epoch
    >>> sc = two_station_scenario()  # 500 km LEO (J2), two stations, 6 h: 76 measurements
    >>> m = simulate_tracking(sc.x0, sc.stations, np.arange(60.0, 21601.0, 60.0), sigma=(1e-3, 1e-6),
    ...                       force_model=sc.force_model, seed=1)
    >>> names = [("two_way_range", "two_way_range_rate")[k] for k in m["observable"]]
    >>> epoch = Epoch.parse("2023-02-25T00:00:00", "UTC")
    >>> data = od.tracking_data(m["t"], names, m["station"], m["value"][:, 0],
    ...                         np.where(m["observable"] == 0, 1e-3, 1e-6), epoch=epoch, n_stations=2)
    >>> len(data) == m["t"].size
    True
    """
    ep = _epoch(epoch)
    tt = as_real_array(t, "t", ndim=1)
    n = tt.size
    codes = _type_codes(types, n)
    st = np.asarray(stations)
    if st.shape != (n,) or st.dtype.kind not in "iu":
        raise ValueError(f"stations: must be an integer array of shape ({n},), got {st.dtype} {st.shape}")
    vals = as_real_array(values, "values", ndim=(1, 2), finite=False)
    if vals.ndim == 1:
        if np.any(np.isin(codes, _PAIRS)):
            raise ValueError(
                "values: angle pairs (azimuth_elevation, right_ascension_declination) need shape (n, 2)"
            )
        vals = np.stack([vals, np.zeros_like(vals)], axis=1)
    if vals.shape != (n, 2):
        raise ValueError(f"values: must have shape ({n},) or ({n}, 2), got {vals.shape}")
    sig = as_real_array(sigmas, "sigmas", ndim=(0, 1, 2), finite=False)
    sig = (
        np.broadcast_to(sig.reshape(-1, 1) if sig.ndim == 1 else sig, (n, 2)).astype(float)
        if sig.ndim < 2
        else sig
    )
    if sig.shape != (n, 2):
        raise ValueError(f"sigmas: must be a number, ({n},) or ({n}, 2), got {sig.shape}")
    corr = np.zeros(n, dtype=np.int32) if corrections is None else np.asarray(corrections, dtype=np.int32)
    if corr.shape != (n,):
        raise ValueError(f"corrections: must have shape ({n},), got {corr.shape}")
    ns = int(st.max()) + 1 if n_stations is None and n > 0 else (1 if n_stations is None else n_stations)
    ns = as_int(ns, "n_stations", low=1)
    if order not in ("sort", "require_sorted"):
        raise ValueError(f"order: must be one of ['sort', 'require_sorted'], got {order!r}")
    return TrackingData.from_arrays(
        ep,
        tt,
        codes,
        st.astype(np.int32),
        vals,
        np.ascontiguousarray(sig),
        corr,
        ns,
        order == "require_sorted",
    )


def read_tracking_tdm(
    path: str | os.PathLike[str],
    stations: Mapping[str, int] | Sequence[str],
    *,
    n_stations: int | None = None,
    sigma_range: float = 1e-3,
    sigma_range_rate: float = 1e-6,
    sigma_angle: float = 1e-4,
) -> Any:
    """The measurements of a CCSDS TDM file (KVN or XML) as :class:`TrackingData`.

    Parameters
    ----------
    path : str or os.PathLike
        The TDM file.
    stations : mapping of str to int, or sequence of str
        Each receiving participant's name and its station index (or the names in index order).
    n_stations : int, optional
        Number of stations (default: the largest index + 1).
    sigma_range : float, optional
        A TDM carries no sigmas: the range sigma (km; default 1e-3).
    sigma_range_rate : float, optional
        Range-rate sigma (km/s; default 1e-6).
    sigma_angle : float, optional
        Angle sigma (rad; default 1e-4).

    Returns
    -------
    TrackingData
        Tags in s after the file's first epoch (``data.epoch``).

    Raises
    ------
    ValueError
        A participant missing from ``stations`` (named); file errors name the file and the line.
    OSError
        The file cannot be read.

    Examples
    --------
    >>> import datetime
    >>> from satgnc import od
    >>> from satgnc.od.tdm import write_tdm
    >>> obs = od.Observations([0.0, 60.0], "range", [1321.104, 953.7183], 1e-3, 0)
    >>> _ = write_tdm("pass.tdm", obs, datetime.datetime(2023, 2, 25), ["BOULDER"])
    >>> data = od.read_tracking_tdm("pass.tdm", ["BOULDER"])
    >>> len(data)
    2
    """
    names = _station_map(stations)
    ns = max(names.values()) + 1 if n_stations is None else as_int(n_stations, "n_stations", low=1)
    return TrackingData.from_tdm(
        os.fspath(path),
        list(names.keys()),
        list(names.values()),
        ns,
        as_real(sigma_range, "sigma_range", positive=True),
        as_real(sigma_range_rate, "sigma_range_rate", positive=True),
        as_real(sigma_angle, "sigma_angle", positive=True),
    )


def _station_map(stations: Any) -> dict[str, int]:
    if isinstance(stations, Mapping):
        out = {}
        for k, v in stations.items():
            if not isinstance(k, str):
                raise TypeError(f"stations: keys must be participant names (str), got {type(k).__name__}")
            out[k] = as_int(v, f"stations[{k!r}]", low=0)
        return out
    if isinstance(stations, str) or not isinstance(stations, Sequence):
        raise TypeError("stations: must be a mapping {participant name: index} or a sequence of names")
    return {as_name(s, i): i for i, s in enumerate(stations)}


def as_name(s: Any, i: int) -> str:
    if not isinstance(s, str):
        raise TypeError(f"stations[{i}]: must be a participant name (str), got {type(s).__name__}")
    return s


@dataclasses.dataclass(frozen=True)
class BatchResult(Result):
    """Result of :func:`batch_estimate`.

    ``state``: (6,) GCRF state at the epoch, km, km/s; ``parameters``: [state, estimated biases]
    named by ``parameter_names``; ``covariance`` / ``correlation``: formal, of the parameters
    (km, km/s, km, s); ``sigma``: their standard deviations; ``range_bias`` (km) / ``time_bias`` (s):
    per station, estimated or fixed; ``residuals``: (n, 2) post-fit O - C per measurement in time
    order (km, km/s, rad; column 1 NaN for scalar observables), ``normalized`` the same / sigma;
    ``measurement_status``: per measurement; ``rms``: RMS of the normalized residuals; ``status``:
    ``"converged"`` (the remaining Gauss-Newton step ``step_sigma`` <= sigma_tol formal sigmas),
    ``"max_iterations"``, ``"singular"``, ``"stalled"``, ``"diverged"``, ``"propagation_failed"``,
    ``"degenerate_geometry"``: whatever the status, the best iterate."""

    status: str
    message: str
    iterations: int
    evaluations: int
    state: np.ndarray
    parameters: np.ndarray
    parameter_names: tuple[str, ...]
    covariance: np.ndarray
    correlation: np.ndarray
    sigma: np.ndarray
    range_bias: np.ndarray
    time_bias: np.ndarray
    residuals: np.ndarray
    normalized: np.ndarray
    measurement_status: tuple[str, ...]
    rms: float
    cost: float
    rank: int
    condition_number: float
    history_cost: np.ndarray
    step_sigma: float
    solve_time: float

    @property
    def converged(self) -> bool:
        """Whether the status is ``"converged"``."""
        return self.status == "converged"


def _indices(value: Any, name: str, n: int, names: Sequence[str]) -> list[bool]:
    """Stations chosen by index or name -> one bool per station."""
    if isinstance(value, (bool, np.bool_)):
        return [bool(value)] * n
    if isinstance(value, (str, int)):
        value = [value]
    out = [False] * n
    for j, v in enumerate(value):
        if isinstance(v, str):
            if v not in names:
                raise ValueError(f"{name}[{j}]: unknown station {v!r} (stations: {list(names)})")
            out[list(names).index(v)] = True
        else:
            k = as_int(v, f"{name}[{j}]")
            if not 0 <= k < n:
                raise ValueError(f"{name}[{j}]: unknown station {k} (there are {n} stations)")
            out[k] = True
    return out


def _per_station(value: Any, name: str, n: int) -> list[float]:
    if value is None:
        return [0.0] * n
    arr = as_real_array(value, name, ndim=(0, 1))
    if arr.ndim == 0:
        return [float(arr)] * n
    if arr.shape != (n,):
        raise ValueError(f"{name}: must be a number or one per station ({n},), got shape {arr.shape}")
    return [float(v) for v in arr]


TROPOSPHERE_MODELS: tuple[str, ...] = ("saastamoinen", "mendes_pavlis", "marini_murray")


def _troposphere(value: Any) -> tuple[bool, str]:
    """``troposphere`` argument -> (on, model name): a bool (True: Saastamoinen) or a model's name."""
    if isinstance(value, str):
        return True, one_of(value, "troposphere", TROPOSPHERE_MODELS)
    return as_bool(value, "troposphere"), "saastamoinen"


def _setup(
    data: Any, stations: Any, epoch: Any, force_model: Any, station_names: Any, tdm_sigmas: dict[str, float]
):
    ep = _epoch(epoch)
    if isinstance(stations, _satgnc.StationEphemeris) or not isinstance(stations, Sequence) or not stations:
        raise TypeError("stations: must be a non-empty sequence of satgnc.observation.StationEphemeris")
    for k, s in enumerate(stations):
        if not isinstance(s, _satgnc.StationEphemeris):
            raise TypeError(
                f"stations[{k}]: must be a satgnc.observation.StationEphemeris, got {type(s).__name__}"
            )
    n = len(stations)
    if station_names is None:
        names = [str(k) for k in range(n)]
    else:
        names = [as_name(s, i) for i, s in enumerate(station_names)]
        if len(names) != n:
            raise ValueError(f"station_names: must have one name per station ({n}), got {len(names)}")
    if isinstance(data, (str, os.PathLike)):
        if station_names is None:
            raise ValueError("station_names: needed with a TDM file (the participant name of each station)")
        data = read_tracking_tdm(data, names, n_stations=n, **tdm_sigmas)
    if not isinstance(data, TrackingData):
        raise TypeError(
            f"data: must be a satgnc.od.TrackingData or a TDM file path, got {type(data).__name__}"
        )
    fm = _satgnc.ForceModel() if force_model is None else force_model
    if not isinstance(fm, _satgnc.ForceModel):
        raise TypeError(f"force_model: must be a satgnc.dynamics.ForceModel, got {type(fm).__name__}")
    return ep, list(stations), names, data, fm


def batch_estimate(
    data: Any,
    stations: Sequence[Any],
    x0_guess: Any,
    *,
    epoch: Any,
    force_model: Any = None,
    station_names: Sequence[str] | None = None,
    estimate_range_bias: Any = (),
    estimate_time_bias: Any = (),
    range_bias: Any = None,
    time_bias: Any = None,
    light_time: bool = True,
    troposphere: bool | str = False,
    shapiro: bool = False,
    relative_humidity: float = 0.5,
    max_iterations: int = 25,
    sigma_tol: float = 1e-3,
    method: str = "gauss_newton",
    rtol: float = 3e-12,
    atol: float = 3e-14,
    sigma_range: float = 1e-3,
    sigma_range_rate: float = 1e-6,
    sigma_angle: float = 1e-4,
    wavelength_um: float = 0.532,
) -> BatchResult:
    """Batch least squares: the GCRF state at ``epoch`` and per-station biases from ``data``.

    Parameters
    ----------
    data : TrackingData or str or os.PathLike
        The measurements, or a CCSDS TDM path (then ``station_names`` gives each station's
        participant name and ``sigma_range``, ``sigma_range_rate``, ``sigma_angle`` weight it).
    stations : sequence of satgnc.observation.StationEphemeris
        One per station index, whose t = 0 is ``epoch`` (GCRF, km, km/s).
    x0_guess : array_like
        (6,) GCRF km, km/s at ``epoch``.
    epoch : satgnc.time.Epoch
        The epoch of the estimated state (keyword only).
    force_model : satgnc.dynamics.ForceModel, optional
        Default: point mass; set its epoch to ``epoch`` for the Sun and Moon.
    station_names : sequence of str, optional
        Participant names per station (with a TDM path; also accepted by the bias arguments).
    estimate_range_bias, estimate_time_bias : sequence of int or str, or bool, optional
        Station indices or names (or True for all) whose range (km) / time (s) bias is estimated.
    range_bias : float or sequence of float, optional
        Fixed values or initial guesses (km), one number or one per station.
    time_bias : float or sequence of float, optional
        Fixed values or initial guesses (s), one number or one per station.
    light_time : bool, optional
        Light-time models (default True; False: the instantaneous geometry).
    troposphere : bool or {"saastamoinen", "mendes_pavlis", "marini_murray"}, optional
        Model the troposphere in this run (default False; True or ``"saastamoinen"``: radio;
        ``"mendes_pavlis"`` or ``"marini_murray"``: laser ranging at ``wavelength_um``).
    wavelength_um : float, optional
        Laser wavelength in micrometres for ``"mendes_pavlis"`` / ``"marini_murray"`` (default 0.532).
    shapiro : bool, optional
        Model the Shapiro delay in this run (default False).
    relative_humidity : float, optional
        For the troposphere, in [0, 1] (default 0.5).
    max_iterations : int, optional
        Default 25.
    sigma_tol : float, optional
        Convergence: the remaining step is at most this many formal sigmas (default 1e-3).
    method : {"gauss_newton", "levenberg_marquardt"}, optional
        Gauss-Newton with backtracking (default) or Levenberg-Marquardt (Moré scaling; robust from a
        far guess, e.g. hundreds of km off in a LEO).
    rtol, atol : float, optional
        DOP853 tolerances (relative; km and km/s).
    sigma_range, sigma_range_rate, sigma_angle : float, optional
        Sigmas of a TDM's measurements (km, km/s, rad).

    Returns
    -------
    BatchResult
        ``status`` ("converged" only when the step test holds), ``state`` (GCRF km, km/s at
        ``epoch``), ``parameters`` with ``covariance``, ``sigma``, biases (km, s), residuals, ``rms``,
        ``rank`` and the cost history; always the best iterate.

    Raises
    ------
    ValueError
        Naming the argument: wrong shapes, unknown station names, non-positive tolerances.
    TypeError
        ``data``, ``stations`` or ``force_model`` of another type.

    Examples
    --------
    >>> import numpy as np
    >>> from satgnc import od
    >>> from satgnc.od.filter_sim import simulate_tracking, two_station_scenario
    >>> from satgnc.time import Epoch
    >>> sc = two_station_scenario()  # 500 km LEO (J2), two stations, 6 h: 76 measurements
    >>> m = simulate_tracking(sc.x0, sc.stations, np.arange(60.0, 21601.0, 60.0), sigma=(1e-3, 1e-6),
    ...                       force_model=sc.force_model, seed=1)
    >>> names = [("two_way_range", "two_way_range_rate")[k] for k in m["observable"]]
    >>> epoch = Epoch.parse("2023-02-25T00:00:00", "UTC")
    >>> data = od.tracking_data(m["t"], names, m["station"], m["value"][:, 0],
    ...                         np.where(m["observable"] == 0, 1e-3, 1e-6), epoch=epoch, n_stations=2)
    >>> r = od.batch_estimate(data, list(sc.stations), sc.x0 + [1.0, -1.0, 0.5, 1e-3, 0, 0], epoch=epoch,
    ...                       force_model=sc.force_model)
    >>> r.status, bool(np.all(np.abs(r.state - sc.x0) < 5 * r.sigma[:6]))
    ('converged', True)
    """
    ep, sts, names, td, fm = _setup(
        data,
        stations,
        epoch,
        force_model,
        station_names,
        {"sigma_range": sigma_range, "sigma_range_rate": sigma_range_rate, "sigma_angle": sigma_angle},
    )
    n = len(sts)
    guess = as_real_array(x0_guess, "x0_guess", shape=(6,))
    er = _indices(estimate_range_bias, "estimate_range_bias", n, names)
    et = _indices(estimate_time_bias, "estimate_time_bias", n, names)
    rb = _per_station(range_bias, "range_bias", n)
    tb = _per_station(time_bias, "time_bias", n)
    tropo_on, tropo_model = _troposphere(troposphere)
    out = _satgnc.od_batch_estimate(
        td,
        ep,
        sts,
        guess,
        fm,
        er,
        et,
        rb,
        tb,
        names,
        as_int(max_iterations, "max_iterations", low=1),
        as_real(sigma_tol, "sigma_tol", positive=True),
        as_bool(light_time, "light_time"),
        tropo_on,
        as_bool(shapiro, "shapiro"),
        as_real(relative_humidity, "relative_humidity", low=0.0, high=1.0),
        as_real(rtol, "rtol", positive=True),
        as_real(atol, "atol", nonnegative=True),
        one_of(method, "method", ("gauss_newton", "levenberg_marquardt")),
        tropo_model,
        as_real(wavelength_um, "wavelength_um", low=0.3, high=1.7),
    )
    return adopt(
        BatchResult,
        status=out["status"],
        message=out["message"],
        iterations=int(out["iterations"]),
        evaluations=int(out["evaluations"]),
        state=out["x0"],
        parameters=out["parameters"],
        parameter_names=tuple(out["parameter_names"]),
        covariance=out["covariance"],
        correlation=out["correlation"],
        sigma=out["sigma"],
        range_bias=out["range_bias"],
        time_bias=out["time_bias"],
        residuals=out["residuals"],
        normalized=out["normalized"],
        measurement_status=tuple(_OBS_STATUS.get(int(s), "unknown") for s in out["measurement_status"]),
        rms=float(out["rms"]),
        cost=float(out["cost"]),
        rank=int(out["rank"]),
        condition_number=float(out["condition_number"]),
        history_cost=out["history_cost"],
        step_sigma=float(out["step_sigma"]),
        solve_time=float(out["solve_time"]),
    )


def batch_residuals(
    data: Any,
    stations: Sequence[Any],
    parameters: Any,
    *,
    epoch: Any,
    force_model: Any = None,
    estimate_range_bias: Any = (),
    estimate_time_bias: Any = (),
    light_time: bool = True,
    troposphere: bool | str = False,
    shapiro: bool = False,
    rtol: float = 3e-12,
    atol: float = 3e-14,
    wavelength_um: float = 0.532,
) -> tuple[np.ndarray, np.ndarray]:
    """Whitened residuals and Jacobian of the batch problem at given parameters (for checks and tools).

    Parameters
    ----------
    data : TrackingData or str or os.PathLike
        As :func:`batch_estimate`.
    stations : sequence of satgnc.observation.StationEphemeris
        As :func:`batch_estimate`.
    parameters : array_like
        [state (GCRF km, km/s at ``epoch``), estimated biases (km, s)], as
        :attr:`BatchResult.parameters`; fixed biases are 0.
    epoch : satgnc.time.Epoch
        The epoch of the state (keyword only).
    force_model : satgnc.dynamics.ForceModel, optional
        Default: point mass.
    estimate_range_bias, estimate_time_bias : sequence of int or str, or bool, optional
        As :func:`batch_estimate`.
    light_time, shapiro : bool, optional
        Model options (defaults True, False).
    troposphere : bool or {"saastamoinen", "mendes_pavlis", "marini_murray"}, optional
        As :func:`batch_estimate` (default False).
    rtol, atol : float, optional
        DOP853 tolerances (relative; km and km/s).
    wavelength_um : float, optional
        Laser wavelength in micrometres for ``"mendes_pavlis"`` / ``"marini_murray"`` (default 0.532).

    Returns
    -------
    residuals : numpy.ndarray
        (O - C) / sigma, one per scalar measurement (unit-free).
    jacobian : numpy.ndarray
        d(predicted / sigma) / d parameters (per km, km/s, s).

    Raises
    ------
    ValueError
        A parameter vector of the wrong length, or an evaluation that fails (propagation, degenerate
        geometry).
    TypeError
        As :func:`batch_estimate`.

    Examples
    --------
    >>> import numpy as np
    >>> from satgnc import od
    >>> from satgnc.od.filter_sim import simulate_tracking, two_station_scenario
    >>> from satgnc.time import Epoch
    >>> sc = two_station_scenario()  # 500 km LEO (J2), two stations, 6 h: 76 measurements
    >>> m = simulate_tracking(sc.x0, sc.stations, np.arange(60.0, 21601.0, 60.0), sigma=(1e-3, 1e-6),
    ...                       force_model=sc.force_model, seed=1)
    >>> names = [("two_way_range", "two_way_range_rate")[k] for k in m["observable"]]
    >>> epoch = Epoch.parse("2023-02-25T00:00:00", "UTC")
    >>> data = od.tracking_data(m["t"], names, m["station"], m["value"][:, 0],
    ...                         np.where(m["observable"] == 0, 1e-3, 1e-6), epoch=epoch, n_stations=2)
    >>> r, J = od.batch_residuals(data, list(sc.stations), sc.x0, epoch=epoch, force_model=sc.force_model,
    ...                           light_time=False)
    >>> J.shape == (r.size, 6)
    True
    """
    ep, sts, names, td, fm = _setup(data, stations, epoch, force_model, None, {})
    n = len(sts)
    er = _indices(estimate_range_bias, "estimate_range_bias", n, names)
    et = _indices(estimate_time_bias, "estimate_time_bias", n, names)
    p = as_real_array(parameters, "parameters", ndim=1)
    if p.size != 6 + sum(er) + sum(et):
        raise ValueError(
            f"parameters: must have {6 + sum(er) + sum(et)} entries (state + estimated biases), got {p.size}"
        )
    tropo_on, tropo_model = _troposphere(troposphere)
    ok, r, jac = _satgnc.od_batch_evaluate(
        td,
        ep,
        sts,
        p,
        fm,
        er,
        et,
        as_bool(light_time, "light_time"),
        tropo_on,
        as_bool(shapiro, "shapiro"),
        as_real(rtol, "rtol", positive=True),
        as_real(atol, "atol", nonnegative=True),
        tropo_model,
        as_real(wavelength_um, "wavelength_um", low=0.3, high=1.7),
    )
    if not ok:
        raise ValueError(
            "parameters: the residuals cannot be evaluated there (propagation or geometry failed)"
        )
    return np.asarray(r), np.asarray(jac)
