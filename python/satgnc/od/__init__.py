"""satgnc.od: orbit determination from range and range-rate of ground stations.

Units: km, km/s, s; angles in degrees at this level unless a name ends in ``_rad``. The epoch t = 0
of every time is the epoch of the initial state being estimated.

Measurement model: instantaneous range ``|r - R|`` and range-rate ``(r - R).(v - V)/|r - R|`` with
no light time, aberration or refraction (simulate and fit with the same model).

Main entry points
-----------------
- :func:`station_geodetic`, :func:`station_inertial`: stations (GMST IAU-1982 Earth rotation).
- :func:`predict`: an observable and its partials w.r.t. the satellite state.
- :class:`Observations`: a table of (t, type, value, sigma, station); :func:`read_csv`,
  :func:`satgnc.od.tdm.read_tdm`.
- :func:`solve`: weighted batch least squares (Gauss-Newton or Levenberg-Marquardt).
- :func:`solve_six_point`: the paper's Newton-Raphson on six implicit boundary conditions.
- :func:`root_search`: every distinct solution reached from guesses in a box, with an ambiguity flag.
- :func:`simulate`: seeded synthetic observations (noise, biases, elevation mask).
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import math
from collections.abc import Sequence

import numpy as np

from .. import _satgnc as _c
from .._validate import (
    FileFormatError,
    as_bool,
    as_int,
    as_real,
    as_real_array,
    as_series,
    as_vector,
    did_you_mean,
    read_text_file,
)

# The Earth constants are defined once, in C++ (core/constants.hpp), and exported by the extension.
EARTH_MU = _c.EARTH_MU  #: km^3/s^2 (EGM-96)
EARTH_OMEGA = _c.EARTH_OMEGA  #: rad/s
EARTH_RADIUS = _c.EARTH_RADIUS  #: km

Station = _c.Station
Ellipsoid = _c.Ellipsoid
MeasurementType = _c.MeasurementType
OdStatus = _c.OdStatus
OdMethod = _c.OdMethod
OdSettings = _c.OdSettings
OdResult = _c.OdResult
OdSolver = _c.OdSolver
ConditionType = _c.ConditionType
BoundaryCondition = _c.BoundaryCondition
KeplerStmPropagator = _c.KeplerStmPropagator
CvodesStmPropagator = _c.CvodesStmPropagator
ShortArcStmPropagator = _c.ShortArcStmPropagator
RootSearchSettings = _c.RootSearchSettings

__all__ = [
    "EARTH_MU",
    "EARTH_OMEGA",
    "EARTH_RADIUS",
    "Station",
    "Ellipsoid",
    "MeasurementType",
    "OdStatus",
    "OdMethod",
    "OdSettings",
    "OdResult",
    "OdSolver",
    "ConditionType",
    "BoundaryCondition",
    "KeplerStmPropagator",
    "CvodesStmPropagator",
    "ShortArcStmPropagator",
    "RootSearchSettings",
    "julian_date",
    "gmst",
    "ellipsoid",
    "geodetic_to_ecef",
    "station_geodetic",
    "station_inertial",
    "implied_rotation_rate",
    "predict",
    "make_propagator",
    "Observations",
    "read_csv",
    "read_csv_names",
    "solve",
    "six_point_conditions",
    "solve_six_point",
    "root_search",
    "box_guesses",
    "simulate",
    "settings",
    # batch least squares on tracking data (issue 13 item 6; satgnc.od.batch)
    "BatchResult",
    "TrackingData",
    "batch_estimate",
    "batch_residuals",
    "read_tracking_tdm",
    "tracking_data",
]

from .batch import (  # noqa: E402  (after the names batch.py does not need)
    BatchResult,
    TrackingData,
    batch_estimate,
    batch_residuals,
    read_tracking_tdm,
    tracking_data,
)

_METHODS = {
    "newton": OdMethod.newton,
    "gauss_newton": OdMethod.gauss_newton,
    "gn": OdMethod.gauss_newton,
    "levenberg_marquardt": OdMethod.levenberg_marquardt,
    "lm": OdMethod.levenberg_marquardt,
}


# ----------------------------------------------------------------------------- time and stations
_JD_MIN = 2415079.5  # 1900-03-01T00:00 (od_julian_date's lower bound)
_JD_MAX = 2488069.5  # 2100-03-01T00:00
_MAX_DUT1 = 0.9  # s, IERS bound on |UT1 - UTC|


def julian_date(epoch) -> float:
    """Julian date of a UTC epoch.

    Parameters
    ----------
    epoch : datetime.datetime, str or float
        A :class:`datetime.datetime` (naive = UTC; an aware one is converted to UTC), an ISO-8601
        string ('1981-03-21T06:00:00'), or a Julian date (days, returned as is).

    Returns
    -------
    float
        The Julian date (days), 1900-03-01 .. 2100-02-28.

    Raises
    ------
    ValueError
        A string that is not ISO-8601, or a date outside 1900-03-01 .. 2100-02-28.
    TypeError
        Any other type.

    Examples
    --------
    >>> from satgnc import od
    >>> od.julian_date("2000-01-01T12:00:00")
    2451545.0
    """
    if isinstance(epoch, (float, int, np.floating, np.integer)) and not isinstance(epoch, (bool, np.bool_)):
        v = float(epoch)
        if not math.isfinite(v) or v < _JD_MIN or v >= _JD_MAX:
            raise ValueError(f"epoch: a Julian date must be finite and in [{_JD_MIN}, {_JD_MAX}) "
                             f"(1900-03-01 .. 2100-02-28, the calendar range of julian_date), got {v}")
        return v
    if isinstance(epoch, str):
        try:
            epoch = _dt.datetime.fromisoformat(epoch.strip().replace("Z", "+00:00"))
        except ValueError:
            raise ValueError(f"epoch: not an ISO-8601 date-time: {epoch!r}") from None
    if not isinstance(epoch, _dt.datetime):
        raise TypeError(f"epoch: must be a datetime, ISO string or Julian date, got {type(epoch).__name__}")
    if epoch.tzinfo is not None:
        epoch = epoch.astimezone(_dt.timezone.utc).replace(tzinfo=None)
    sec = epoch.second + epoch.microsecond * 1e-6
    try:
        return _c.od_julian_date(epoch.year, epoch.month, epoch.day, epoch.hour, epoch.minute, sec)
    except ValueError as e:  # "year: must be in 1900..2100" named a field the user never passed
        raise ValueError(f"epoch: {epoch.isoformat()} is out of range ({e})") from None


def _ut1_minus_utc(value) -> float:
    v = as_real(value, "ut1_minus_utc")
    if not abs(v) < _MAX_DUT1:  # 5 s was accepted: a unit or sign error, never a real offset
        raise ValueError(f"ut1_minus_utc: |UT1 - UTC| must be < {_MAX_DUT1} s (IERS keeps it so with leap "
                         f"seconds), got {v} s")
    return v


def gmst(epoch, ut1_minus_utc: float = 0.0) -> float:
    """Greenwich mean sidereal time (IAU-1982) at a UTC epoch.

    Parameters
    ----------
    epoch : datetime.datetime, str or float
        UTC epoch (see :func:`julian_date`).
    ut1_minus_utc : float, optional
        UT1 - UTC (s), ``|UT1 - UTC| < 0.9`` (IERS); default 0.

    Returns
    -------
    float
        GMST (rad) in [0, 2 pi).

    Raises
    ------
    ValueError
        A bad epoch (see :func:`julian_date`) or ``|ut1_minus_utc| >= 0.9`` s.

    Examples
    --------
    Vallado's Example 3-5 (152.578787886 deg):

    >>> import math
    >>> from satgnc import od
    >>> round(math.degrees(od.gmst("1992-08-20T12:14:00")), 6)
    152.578788
    """
    return _c.od_gmst_from_utc(julian_date(epoch), _ut1_minus_utc(ut1_minus_utc))


def ellipsoid(name: str = "WGS-84") -> Ellipsoid:
    """A named reference ellipsoid.

    Parameters
    ----------
    name : str, optional
        "WGS-84" (default), "GRS-80", "IAU-1976", "Krassovsky" or "sphere".

    Returns
    -------
    Ellipsoid
        Equatorial radius (km) and flattening.

    Raises
    ------
    ValueError
        An unknown name.
    TypeError
        A name that is not a str.

    Examples
    --------
    >>> from satgnc import od
    >>> e = od.ellipsoid("WGS-84")
    >>> e
    Ellipsoid(...)
    """
    if not isinstance(name, str):
        raise TypeError(f"ellipsoid: must be a name (str), got {type(name).__name__}")
    return _c.od_ellipsoid_by_name(name)


def _as_ellipsoid(e) -> Ellipsoid:
    return e if isinstance(e, Ellipsoid) else ellipsoid(e)


def geodetic_to_ecef(lat_deg: float, lon_deg: float, height_km: float, ellipsoid="WGS-84") -> np.ndarray:
    """Earth-fixed (ITRF-like, body-fixed) position of a geodetic point.

    Parameters
    ----------
    lat_deg : float
        Geodetic latitude (deg, in [-90, 90]).
    lon_deg : float
        Longitude (deg, east positive).
    height_km : float
        Height above the ellipsoid (km).
    ellipsoid : str or Ellipsoid, optional
        The ellipsoid (default "WGS-84", see :func:`ellipsoid`).

    Returns
    -------
    numpy.ndarray
        Position (3,), km, Earth-fixed.

    Raises
    ------
    ValueError
        A latitude outside [-90, 90] deg, a non-finite value, an unknown ellipsoid.

    Examples
    --------
    >>> from satgnc import od
    >>> od.geodetic_to_ecef(0.0, 0.0, 0.0)
    array([6378.137,    0.   ,    0.   ])
    """
    lat = as_real(lat_deg, "lat_deg")
    lon = as_real(lon_deg, "lon_deg")
    if abs(lat) > 90:
        raise ValueError(f"lat_deg: must be within [-90, 90], got {lat}")
    return np.asarray(
        _c.od_geodetic_to_ecef(
            math.radians(lat),
            math.radians(lon),
            as_real(height_km, "height_km"),
            _as_ellipsoid(ellipsoid),
        )
    )


def station_geodetic(
    lat_deg: float,
    lon_deg: float,
    height_km: float,
    epoch,
    ut1_minus_utc: float = 0.0,
    ellipsoid="WGS-84",
    omega: float = EARTH_OMEGA,
) -> Station:
    """A ground station from geodetic coordinates, rotating with the Earth.

    Its inertial position at the UTC ``epoch`` (t = 0) comes from GMST (IAU-1982); it then rotates
    about +z at ``omega``.

    Parameters
    ----------
    lat_deg, lon_deg : float
        Geodetic latitude (deg, in [-90, 90]) and east longitude (deg).
    height_km : float
        Height above the ellipsoid (km).
    epoch : datetime.datetime, str or float
        UTC epoch of t = 0 (see :func:`julian_date`).
    ut1_minus_utc : float, optional
        UT1 - UTC (s, ``|.| < 0.9``; default 0).
    ellipsoid : str or Ellipsoid, optional
        Default "WGS-84" (see :func:`ellipsoid`).
    omega : float, optional
        Rotation rate (rad/s; default :data:`EARTH_OMEGA`).

    Returns
    -------
    Station
        ``station.state(t)`` gives its inertial state [R km, V km/s] at t (s from the epoch).

    Raises
    ------
    ValueError
        A latitude outside [-90, 90] deg, a bad epoch or UT1 - UTC, an unknown ellipsoid.

    Examples
    --------
    >>> from satgnc import od
    >>> st = od.station_geodetic(40.0, -105.25, 1.6, "2024-03-01T00:00:00")
    >>> st.state(0.0).shape
    (6,)
    """
    lat = as_real(lat_deg, "lat_deg")
    if abs(lat) > 90:
        raise ValueError(f"lat_deg: must be within [-90, 90], got {lat}")
    return Station.from_geodetic(
        lat,
        as_real(lon_deg, "lon_deg"),
        as_real(height_km, "height_km"),
        julian_date(epoch),
        _ut1_minus_utc(ut1_minus_utc),
        _as_ellipsoid(ellipsoid),
        as_real(omega, "omega"),
    )


def station_inertial(r0, omega: float = EARTH_OMEGA) -> Station:
    """A station given by its inertial position at t = 0, rotating about +z (the paper's station).

    Parameters
    ----------
    r0 : array_like
        Inertial position (3,) at t = 0, km.
    omega : float, optional
        Rotation rate (rad/s; default :data:`EARTH_OMEGA`).

    Returns
    -------
    Station
        ``station.state(t)``: inertial [R km, V km/s] at t (s).

    Raises
    ------
    ValueError
        ``r0`` not 3 finite numbers, a non-finite ``omega``.

    Examples
    --------
    >>> from satgnc import od
    >>> st = od.station_inertial([5463.14996, 2139.12637, 2493.7785])
    >>> st.state(0.0)[3:].round(5).tolist()
    [-0.15599, 0.39838, 0.0]
    """
    return Station.from_inertial(as_vector(r0, 3, "r0"), as_real(omega, "omega"))


def implied_rotation_rate(station_state) -> float:
    """The rotation rate that makes a printed station state satisfy V = omega z x R.

    Parameters
    ----------
    station_state : array_like
        Station state [R km, V km/s] (6,), inertial.

    Returns
    -------
    float
        omega (rad/s), least squares over the x and y components.

    Raises
    ------
    ValueError
        Not 6 finite numbers, or R on the z axis.

    Examples
    --------
    The paper's Table 3 implies 7.27e-5 rad/s, not the Earth's 7.292e-5:

    >>> from satgnc import od
    >>> round(od.implied_rotation_rate([5463.14996, 2139.12637, 2493.7785, -0.15551, 0.39717, 0.0]), 7)
    7.27e-05
    """
    return _c.od_implied_rotation_rate(as_vector(station_state, 6, "station_state"))


def _mtype(kind, name: str = "type") -> MeasurementType:
    if isinstance(kind, MeasurementType):
        return kind
    if not isinstance(kind, str):
        raise TypeError(f"{name}: must be 'range' or 'range_rate', got {type(kind).__name__}")
    try:
        return _c.od_parse_measurement_type(kind)
    except ValueError as e:
        raise ValueError(f"{name}: {e}") from None


def predict(kind, x, station_state) -> tuple[float, np.ndarray]:
    """Predicted instantaneous range or range-rate and its partials.

    Parameters
    ----------
    kind : {"range", "range_rate"} or MeasurementType
        The observable.
    x : array_like
        Satellite state (6,): km, km/s, inertial.
    station_state : array_like
        Station state (6,): km, km/s, same inertial frame.

    Returns
    -------
    value : float
        Range (km) or range-rate (km/s).
    partials : numpy.ndarray
        d value / d x (6,).

    Raises
    ------
    ValueError
        An unknown ``kind``, wrong shapes, or the satellite at the station.

    Examples
    --------
    >>> from satgnc import od
    >>> x = [5836.8907, 1265.616, 3411.496, 0.3146, 6.9401, -3.1125]
    >>> R = [5463.14996, 2139.12637, 2493.7785, -0.15551, 0.39717, 0.0]
    >>> rho, d = od.predict("range", x, R)
    >>> round(rho, 2), d.shape
    (1320.95, (6,))
    """
    v, g = _c.od_predict_measurement(
        _mtype(kind, "kind"), as_vector(x, 6, "x"), as_vector(station_state, 6, "station_state")
    )
    return float(v), np.asarray(g).ravel()


def make_propagator(kind: str = "kepler", mu: float = EARTH_MU, j2: bool = False, force_model=None):
    """A state + STM propagator for the OD solvers.

    Parameters
    ----------
    kind : {"kepler", "cvodes"} or propagator object, optional
        "kepler" (analytic two-body, default) or "cvodes" (numerical; ``j2`` optional). A propagator
        object (KeplerStmPropagator, CvodesStmPropagator, ShortArcStmPropagator) is returned as is.
    mu : float, optional
        Gravitational parameter (km^3/s^2; default :data:`EARTH_MU`).
    j2 : bool, optional
        Add the Earth's J2 ("cvodes" only).
    force_model : satgnc.ForceModel, optional
        For "cvodes": point mass + optional ``J2Gravity`` + optional ``ExponentialDrag`` (km, km/s,
        s; the drag's density kg/m^3, area m^2, mass kg); states and STM (with the drag's analytic
        Jacobians) are integrated on it. It replaces ``mu`` and ``j2``: give J2 in the model, and
        leave ``mu`` at :data:`EARTH_MU` or equal to ``force_model.mu``.

    Returns
    -------
    KeplerStmPropagator or CvodesStmPropagator or ShortArcStmPropagator
        ``propagate(x0, times) -> (states, stms)``: states (km, km/s) and 6x6 STMs at ``times`` (s),
        inertial.

    Raises
    ------
    ValueError
        An unknown ``kind``, ``j2`` with "kepler", a ``force_model`` with "kepler" or beside ``j2``,
        a ``mu`` different from ``force_model.mu``, a model that fails ``ForceModel.validate``.
    TypeError
        ``kind`` or ``force_model`` of another type.

    Examples
    --------
    >>> from satgnc import od
    >>> prop = od.make_propagator("kepler")
    >>> states, stms = prop.propagate([7000.0, 0, 0, 0, 7.546, 0], [0.0, 60.0])
    >>> len(states), stms[1].shape
    (2, (6, 6))
    """
    return _make_propagator(kind, mu, j2, "kind", force_model)


def _make_propagator(kind, mu, j2=False, name: str = "propagator", force_model=None):
    """make_propagator with errors naming the caller's argument (``propagator`` in solve/simulate)."""
    mu = as_real(mu, "mu", positive=True)
    j2 = as_bool(j2, "j2")  # bool("no") is True
    if force_model is not None:
        return _force_model_propagator(kind, mu, j2, name, force_model)
    if isinstance(kind, _c.StmPropagator):
        return kind  # already a propagator object
    if not isinstance(kind, str):  # 3 was returned as the "propagator" and failed later
        raise TypeError(f"{name}: must be 'kepler', 'cvodes' or a propagator object (KeplerStmPropagator, "
                        f"CvodesStmPropagator, ShortArcStmPropagator), got {type(kind).__name__}")
    if kind == "kepler":
        if j2:
            raise ValueError("j2: the Kepler propagator is two-body only (hint: propagator='cvodes')")
        return KeplerStmPropagator(mu)
    if kind == "cvodes":
        return CvodesStmPropagator(mu, bool(j2))
    raise ValueError(f"{name}: unknown propagator {kind!r} (hint: 'kepler' or 'cvodes')")


def _force_model_propagator(kind, mu: float, j2: bool, name: str, fm):
    """CvodesStmPropagator(force_model) with the rules of :func:`make_propagator`."""
    if not isinstance(fm, _c.ForceModel):
        raise TypeError(f"force_model: must be a satgnc.ForceModel (mu, j2, drag), got {type(fm).__name__}")
    if not (isinstance(kind, str) and kind == "cvodes"):
        shown = repr(kind) if isinstance(kind, str) else type(kind).__name__
        raise ValueError(f"{name}: a force_model needs the 'cvodes' propagator, got {shown}")
    if j2:
        raise ValueError("j2: give J2 in force_model (ForceModel(j2=J2Gravity(...))), not beside it")
    if mu != EARTH_MU and mu != fm.mu:
        raise ValueError(f"mu: {mu} km^3/s^2 differs from force_model.mu = {fm.mu} km^3/s^2 (hint: leave "
                         "mu out; the force model's is used)")
    try:
        fm.validate()
    except ValueError as e:
        raise ValueError(f"force_model: {e}") from None
    return CvodesStmPropagator(force_model=fm)  # by keyword: the first overload takes mu first


def settings(method: str = "levenberg_marquardt", **kw) -> OdSettings:
    """:class:`OdSettings` from keyword arguments.

    Parameters
    ----------
    method : str or OdMethod, optional
        "levenberg_marquardt" (default, alias "lm"), "gauss_newton" ("gn") or "newton".
    **kw
        :class:`OdSettings` fields, e.g. ``max_iterations`` (count), ``cost_tol`` (relative),
        ``mu`` (km^3/s^2).

    Returns
    -------
    OdSettings
        The validated settings.

    Raises
    ------
    ValueError
        An unknown method, or a field value that fails ``OdSettings.validate``.
    TypeError
        An unknown field name.

    Examples
    --------
    >>> from satgnc import od
    >>> od.settings("gauss_newton", max_iterations=50).max_iterations
    50
    """
    s = OdSettings()
    if isinstance(method, OdMethod):
        s.method = method
    elif method in _METHODS:
        s.method = _METHODS[method]
    else:
        raise ValueError(f"method: unknown {method!r} (hint: newton, gauss_newton, levenberg_marquardt)")
    for k, v in kw.items():
        if not hasattr(s, k) or k.startswith("_"):
            raise TypeError(f"settings: unknown setting {k!r}")
        setattr(s, k, v)
    s.validate()
    return s


# ----------------------------------------------------------------------------- observations
@dataclasses.dataclass
class Observations:
    """A table of observations: time (s from the epoch), type, value (km or km/s), sigma (same unit)
    and station index.

    ``type`` may be given as the strings ``'range'`` / ``'range_rate'`` or as ``MeasurementType``
    members; it is stored as ``MeasurementType`` members (kept so for existing scripts:
    ``k == MeasurementType.range``, ``k.value``). ``type_names()`` returns the strings."""

    t: np.ndarray
    type: list
    value: np.ndarray
    sigma: np.ndarray
    station: np.ndarray

    def __post_init__(self):
        self.t = as_series(self.t, "t")
        n = self.t.size
        self.value = as_series(self.value, "value")
        sig = as_real_array(self.sigma, "sigma", finite=False)  # complex sigma was truncated silently
        self.sigma = np.full(n, float(sig)) if sig.ndim == 0 else as_series(sig, "sigma")
        st = np.asarray(self.station)
        if st.dtype.kind not in "iu" and not (st.dtype.kind == "f" and np.all(st == np.round(st))):
            raise TypeError("station: must be integer station indices")
        self.station = np.full(n, int(st)) if st.ndim == 0 else st.astype(int)
        kinds = [self.type] * n if isinstance(self.type, (str, MeasurementType)) else list(self.type)
        self.type = [_mtype(k) for k in kinds]
        for name in ("value", "sigma", "station"):
            if getattr(self, name).shape != (n,):
                raise ValueError(f"{name}: must have the length of t ({n}), got {getattr(self, name).shape}")
        if len(self.type) != n:
            raise ValueError(f"type: must have the length of t ({n}), got {len(self.type)}")
        bad = np.flatnonzero(~np.isfinite(self.sigma) | (self.sigma <= 0))
        if bad.size:
            raise ValueError(f"sigma: must be finite and > 0 (row {bad[0]}: {self.sigma[bad[0]]})")
        bad = np.flatnonzero(~np.isfinite(self.t) | ~np.isfinite(self.value))
        if bad.size:
            raise ValueError(f"t/value: must be finite (row {bad[0]})")
        bad = np.flatnonzero(self.station < 0)
        if bad.size:
            raise ValueError(f"station: indices must be >= 0 (row {bad[0]}: {self.station[bad[0]]})")
        # A range is a distance: a negative one was accepted here (read_csv / read_tdm refuse it);
        # a zero range is left to the solver, which names it "zero range".
        rng = np.array([k == MeasurementType.range for k in self.type], dtype=bool)
        bad = np.flatnonzero(rng & (self.value < 0))
        if bad.size:
            raise ValueError(f"value: a range must be >= 0 km (row {bad[0]}: {self.value[bad[0]]})")

    def __len__(self) -> int:
        return int(self.t.size)

    def __repr__(self) -> str:
        """A one-line summary: count, count per type, stations and time span (never the arrays)."""
        n = len(self)
        if n == 0:
            return "Observations(n=0)"
        names = self.type_names()
        kinds = ", ".join(f"{k}: {names.count(k)}" for k in ("range", "range_rate") if k in names)
        st = np.unique(self.station)
        sts = ", ".join(str(int(i)) for i in st[:6]) + (", ..." if st.size > 6 else "")
        return (f"Observations(n={n}, types={{{kinds}}}, stations=[{sts}], "
                f"t={float(self.t.min()):.6g} .. {float(self.t.max()):.6g} s)")

    def measurements(self) -> list:
        return [
            _c.Measurement(float(t), k, float(v), float(s), int(st))
            for t, k, v, s, st in zip(self.t, self.type, self.value, self.sigma, self.station)
        ]

    def select(self, mask) -> Observations:
        m = np.asarray(mask, dtype=bool)
        return Observations(
            self.t[m],
            [k for k, keep in zip(self.type, m) if keep],
            self.value[m],
            self.sigma[m],
            self.station[m],
        )

    def type_names(self) -> list[str]:
        """The measurement types as the strings 'range' / 'range_rate' (``type`` holds the enums)."""
        return ["range" if k == MeasurementType.range else "range_rate" for k in self.type]

    def write_csv(self, path, station_names: Sequence[str] | None = None):
        """Write the table as CSV (``t,type,value,sigma,station``; t in s, value and sigma in km or km/s,
        17 significant digits) that :func:`read_csv` reads back exactly. ``station_names``: write names
        (``station_names[i]`` for index i) instead of indices. Returns the path."""
        import pathlib as _pathlib

        if station_names is not None:
            if isinstance(station_names, str) or not all(isinstance(n, str) and n for n in station_names):
                raise TypeError("station_names: must be a list of non-empty names (str)")
            if len(set(station_names)) != len(station_names):
                raise ValueError(f"station_names: names must be unique, got {list(station_names)}")
            bad = [n for n in station_names if not (n[0].isalpha() or n[0] == "_") or "," in n]
            if bad:
                raise ValueError(f"station_names: a name starts with a letter and has no comma, "
                                 f"got {bad[0]!r}")
            if len(self) and int(self.station.max()) >= len(station_names):
                raise ValueError(f"station_names: {len(station_names)} name(s) for station index "
                                 f"{int(self.station.max())}")
        out = _pathlib.Path(path)
        lines = ["t,type,value,sigma,station"]
        for t, k, v, sg, st in zip(self.t, self.type_names(), self.value, self.sigma, self.station):
            who = station_names[int(st)] if station_names is not None else str(int(st))
            lines.append(f"{float(t)!r},{k},{float(v)!r},{float(sg)!r},{who}")
        out.write_text("\n".join(lines) + "\n")
        return out


_CSV_COLUMNS = ("t", "type", "value", "sigma", "station")


def _csv_float(cell: str, column: str, p, lineno: int) -> float:
    try:
        if "_" in cell:  # Python's float() reads "1_000" as 1000; no CSV writer means that
            raise ValueError
        v = float(cell)
    except ValueError:
        raise FileFormatError(p, lineno, f"column '{column}': not a number: {cell!r}", key=column) from None
    if not math.isfinite(v):
        raise FileFormatError(p, lineno, f"column '{column}': must be finite, got {cell!r}", key=column)
    return v


def read_csv(path) -> Observations:
    """Observations from a CSV file.

    The header holds ``t,type,value,sigma[,station]`` in any order: t in s from the epoch; type
    range / range_rate; value and sigma in km or km/s; station a 0-based index (default 0) or a
    station name (names are numbered 0, 1, ... in order of first appearance, see
    :func:`read_csv_names`; a file uses indices or names, not both). Blank lines and lines starting
    with ``#`` are skipped; UTF-8 with or without a byte-order mark, LF or CRLF line ends. Rows need
    not be time-ordered.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file.

    Returns
    -------
    Observations
        The table (t s, value and sigma km or km/s, station indices).

    Raises
    ------
    satgnc.FileFormatError
        (a ``ValueError``) naming the file, the line and the column: unknown, duplicated or missing
        header columns, a wrong number of cells, a non-numeric or non-finite cell, a range <= 0, a
        sigma <= 0, a negative station index, and two rows with the same time, type and station
        (both lines named).
    OSError
        The file cannot be read.

    Examples
    --------
    >>> import pathlib
    >>> from satgnc import od
    >>> _ = pathlib.Path("obs.csv").write_text("t,type,value,sigma\\n0,range,1321.104,0.001\\n")
    >>> obs = od.read_csv("obs.csv")
    >>> len(obs), obs.type_names()
    (1, ['range'])
    """
    return read_csv_names(path)[0]


def read_csv_names(path) -> tuple[Observations, list[str] | None]:
    """:func:`read_csv` and the station names of a file whose station column holds names.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file (format of :func:`read_csv`; station names such as ``BOULDER``).

    Returns
    -------
    observations : Observations
        The table (t s, value and sigma km or km/s); ``observations.station[i]`` indexes ``names``.
    names : list of str or None
        Station names in order of first appearance; None when the column holds indices (or is
        absent).

    Raises
    ------
    satgnc.FileFormatError
        As :func:`read_csv`, and a file that mixes names and indices (both lines named).
    OSError
        The file cannot be read.

    Examples
    --------
    >>> import pathlib
    >>> from satgnc import od
    >>> text = "t,type,value,sigma,station\\n0,range,1321.1,0.001,BOULDER\\n0,range,900.0,0.001,HAWAII\\n"
    >>> _ = pathlib.Path("named.csv").write_text(text)
    >>> obs, names = od.read_csv_names("named.csv")
    >>> names, obs.station.tolist()
    (['BOULDER', 'HAWAII'], [0, 1])
    """
    import csv

    p, text = read_text_file(path)
    header = None
    names: list[str] = []
    name_line: int | None = None  # the first row that named its station (a file mixing both is refused)
    index_line: int | None = None
    rows = {"t": [], "type": [], "value": [], "sigma": [], "station": []}
    seen: dict[tuple, int] = {}
    for lineno, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        rec = [c.strip() for c in next(csv.reader([line]))]
        if header is None:
            header = [h.lower() for h in rec]
            for i, h in enumerate(header):
                if not h:
                    raise FileFormatError(p, lineno, f"header: column {i + 1} has no name", key="header")
                if h not in _CSV_COLUMNS:
                    raise FileFormatError(
                        p, lineno, f"header: unknown column '{h}'{did_you_mean(h, _CSV_COLUMNS)} "
                        f"(columns: t, type, value, sigma, optional station)", key=h,
                    )
                if header.index(h) != i:
                    raise FileFormatError(
                        p, lineno, f"header: column '{h}' appears twice (columns {header.index(h) + 1} "
                        f"and {i + 1})", key=h,
                    )
            missing = [h for h in _CSV_COLUMNS[:4] if h not in header]
            if missing:
                raise FileFormatError(
                    p, lineno, f"header: missing column(s) {', '.join(missing)} (need t, type, value, "
                    f"sigma, optional station; got {', '.join(header)})", key=missing[0],
                )
            continue
        if len(rec) != len(header):
            raise FileFormatError(
                p, lineno, f"expected {len(header)} cells ({','.join(header)}), got {len(rec)}"
            )
        d = dict(zip(header, rec))
        t = _csv_float(d["t"], "t", p, lineno)
        try:
            kind = _mtype(d["type"])
        except ValueError as e:
            raise FileFormatError(p, lineno, f"column 'type': {e}", key="type") from None
        value = _csv_float(d["value"], "value", p, lineno)
        if kind == MeasurementType.range and not value > 0:
            raise FileFormatError(p, lineno, f"column 'value': a range must be > 0 km, got {d['value']}",
                                  key="value")
        sigma = _csv_float(d["sigma"], "sigma", p, lineno)
        if not sigma > 0:
            raise FileFormatError(p, lineno, f"column 'sigma': must be > 0, got {d['sigma']}", key="sigma")
        if sigma < 1e-150:  # the weight 1/sigma^2 must be a finite double
            raise FileFormatError(p, lineno, f"column 'sigma': too small, got {d['sigma']} (1/sigma^2 "
                                  "overflows)", key="sigma")
        cell = d.get("station", "0")
        if cell and not cell.lstrip("+-").isdigit() and (cell[0].isalpha() or cell[0] == "_"):
            if index_line is not None:
                raise FileFormatError(p, lineno, f"column 'station': a station name ({cell!r}) in a file "
                                      f"that uses indices (line {index_line}); use one or the other",
                                      key="station")
            name_line = lineno if name_line is None else name_line
            if cell not in names:
                names.append(cell)
            cell = str(names.index(cell))
        elif "station" in d:
            if name_line is not None:
                raise FileFormatError(p, lineno, f"column 'station': an index ({cell!r}) in a file that "
                                      f"names its stations (line {name_line}); use one or the other",
                                      key="station")
            index_line = lineno if index_line is None else index_line
        try:
            if "_" in cell:
                raise ValueError
            station = int(cell)
        except ValueError:
            hint = " (an empty cell; 0 is the first station)" if not cell else ""
            raise FileFormatError(p, lineno, f"column 'station': must be an integer index or a station "
                                  f"name, got {cell!r}{hint}", key="station") from None
        if not 0 <= station < 2**31 - 1:
            raise FileFormatError(p, lineno, f"column 'station': must be in [0, 2^31 - 1), got {station}",
                                  key="station")
        key = (t, int(kind), station)
        if key in seen:
            raise FileFormatError(
                p, lineno, f"duplicate observation: same t, type and station as line {seen[key]}", key="t"
            )
        seen[key] = lineno
        for k, v in (("t", t), ("type", kind), ("value", value), ("sigma", sigma), ("station", station)):
            rows[k].append(v)
    if header is None:
        raise FileFormatError(p, None, "empty file (hint: a header t,type,value,sigma[,station] and rows)")
    if not rows["t"]:
        raise FileFormatError(p, None, "no observations after the header")
    obs = Observations(rows["t"], rows["type"], rows["value"], rows["sigma"], rows["station"])
    return obs, (names or None)


def _stations(stations) -> list:
    if isinstance(stations, Station):
        return [stations]
    if isinstance(stations, (str, bytes)) or not hasattr(stations, "__iter__"):
        raise TypeError(f"stations: must be a Station or a list of Stations, got {type(stations).__name__}")
    st = list(stations)
    if not st:
        raise ValueError("stations: need at least one station")
    for i, s in enumerate(st):
        if not isinstance(s, Station):
            raise TypeError(f"stations[{i}]: must be a Station, got {type(s).__name__}")
    return st


def solver(
    observations: Observations,
    stations,
    method: str = "levenberg_marquardt",
    propagator="kepler",
    mu: float = EARTH_MU,
    **kw,
) -> OdSolver:
    """Build a reusable batch solver (see :func:`solve`)."""
    if not isinstance(observations, Observations):
        raise TypeError(f"observations: must be an Observations table, got {type(observations).__name__}")
    return OdSolver.from_measurements(
        _stations(stations),
        observations.measurements(),
        _make_propagator(propagator, mu),
        settings(method, mu=mu, **kw),
    )


def solve(
    observations: Observations,
    stations,
    x0_guess,
    method: str = "levenberg_marquardt",
    propagator="kepler",
    mu: float = EARTH_MU,
    **kw,
) -> OdResult:
    """Weighted batch least squares for the state at t = 0 from >= 6 observations of one or several
    stations.

    Parameters
    ----------
    observations : Observations
        The table (t s from the epoch, values km or km/s, station indices into ``stations``).
    stations : Station or list of Station
        The stations (inertial, see :func:`station_geodetic`).
    x0_guess : array_like
        First guess of the state at t = 0 (6,): km, km/s, inertial.
    method : str, optional
        "levenberg_marquardt" (default), "gauss_newton" (line search) or "newton" (the paper's
        undamped method, exactly 6 observations).
    propagator : str or propagator object, optional
        See :func:`make_propagator` (default "kepler").
    mu : float, optional
        Gravitational parameter (km^3/s^2; default :data:`EARTH_MU`).
    **kw
        :class:`OdSettings` fields, e.g. ``max_iterations`` = 100, ``cost_tol`` = 1e-6,
        ``geodesic`` = True, ``valley_corrections`` = 3, ``extrapolate`` = True.

    Returns
    -------
    OdResult
        ``status`` (``converged`` only when the convergence test holds at x0 with rank 6;
        ``singular``, ``stalled``, ``max_iterations``, ... otherwise, see docs/od.md), ``x0`` the best
        iterate (km, km/s) with its cost, residuals and covariance (km^2, ...), and a history of
        ``iterations + 1`` rows. Solver outcomes never raise: check ``status``.

    Raises
    ------
    ValueError
        Fewer than 6 observations, a station index without a station, a bad guess or setting.
    TypeError
        ``observations`` not an :class:`Observations`, a station of another type, an unknown
        setting.

    Examples
    --------
    Two stations, 5 min of range and range-rate every 10 s (1 m, 1 mm/s noise):

    >>> import numpy as np
    >>> from satgnc import od
    >>> x = np.array([5836.8907, 1265.616, 3411.496, 0.3146, 6.9401, -3.1125])
    >>> st = [od.station_inertial([5463.14996, 2139.12637, 2493.7785]),
    ...       od.station_inertial([5200.0, 3000.0, 1900.0])]
    >>> obs = od.simulate(x, st, np.arange(0.0, 301.0, 10.0), seed=3)
    >>> r = od.solve(obs, st, x + [10.0, -5.0, 3.0, 0.01, 0.0, -0.01])
    >>> sigma = np.sqrt(np.diag(np.asarray(r.covariance)))
    >>> r.status.name, len(obs), bool(np.all(np.abs(np.asarray(r.x0) - x) < 5 * sigma))
    ('converged', 124, True)
    """
    x0 = as_vector(x0_guess, 6, "x0_guess")
    return solver(observations, stations, method, propagator, mu, **kw).solve(x0)


def six_point_conditions(
    t,
    rho,
    rhodot=None,
    mode="doppler",
    sigma_range: float = 1e-3,
    sigma_range_rate: float = 1e-6,
    station: int = 0,
) -> list:
    """The paper's six implicit boundary conditions (Gao & Luo, eqs. 9 and 11).

    Parameters
    ----------
    t : array_like
        Six observation times (s from the epoch).
    rho : array_like
        Six observed ranges (km, > 0).
    rhodot : array_like, optional
        Six observed range-rates (km/s); required by Doppler conditions.
    mode : {"doppler", "range"} or list of 6, optional
        "doppler" (eq. 11 with the observed range, default), "range" (eq. 9) or one per time.
    sigma_range : float, optional
        Range sigma (km; default 1e-3).
    sigma_range_rate : float, optional
        Range-rate sigma (km/s; default 1e-6).
    station : int, optional
        Station index (default 0).

    Returns
    -------
    list of BoundaryCondition
        Six conditions for ``OdSolver.from_conditions``.

    Raises
    ------
    ValueError
        Not six times or ranges, non-finite values, a range <= 0, an unknown mode, missing
        ``rhodot`` for Doppler conditions, duplicate times.
    TypeError
        A ``mode`` that is not a string or a list.

    Examples
    --------
    >>> from satgnc import od
    >>> t = [0, 60, 120, 180, 240, 300]
    >>> rho = [1321.104, 953.7183, 647.715, 526.5433, 695.2631, 1018.447]
    >>> len(od.six_point_conditions(t, rho, mode="range"))
    6
    """
    t = as_series(t, "t")
    rho = as_series(rho, "rho")
    if not np.all(np.isfinite(t)):
        raise ValueError("t: must be finite (no NaN or Inf)")
    if not np.all(np.isfinite(rho)) or np.any(rho <= 0):
        raise ValueError(f"rho: ranges must be finite and > 0 km, got {rho.tolist()}")
    station = as_int(station, "station", low=0, high=2**31 - 1)
    if t.size != 6:
        raise ValueError(f"t: the six-point solver needs exactly 6 observation times, got {t.size}")
    if rho.shape != t.shape:
        raise ValueError(f"rho: must have 6 values, got {rho.size}")
    if not isinstance(mode, str) and (isinstance(mode, bytes) or not isinstance(mode, Sequence)):
        raise TypeError(f"mode: must be 'doppler', 'range' or a list of 6 of them, got {type(mode).__name__}")
    modes = [mode] * 6 if isinstance(mode, str) else list(mode)
    if len(modes) != 6:
        raise ValueError(f"mode: need 6 condition types, got {len(modes)}")
    types = []
    for i, md in enumerate(modes):
        if md not in ("doppler", "range"):
            raise ValueError(f"mode[{i}]: unknown condition type {md!r} (hint: 'doppler' or 'range')")
        types.append(ConditionType.doppler if md == "doppler" else ConditionType.range)
    if any(ty == ConditionType.doppler for ty in types):
        if rhodot is None:
            raise ValueError("rhodot: Doppler conditions need the observed range-rates")
        rhodot = as_series(rhodot, "rhodot")
        if rhodot.shape != t.shape:
            raise ValueError(f"rhodot: must have 6 values, got {rhodot.size}")
        if not np.all(np.isfinite(rhodot)):
            raise ValueError("rhodot: must be finite (no NaN or Inf)")
    else:
        rhodot = np.zeros(6)
    if len(np.unique(t)) != 6 and len({(a, b) for a, b in zip(t, modes)}) != 6:
        raise ValueError("t: duplicate times for the same condition type")
    sr = as_real(sigma_range, "sigma_range", positive=True)
    srr = as_real(sigma_range_rate, "sigma_range_rate", positive=True)
    return [
        BoundaryCondition(float(t[i]), types[i], float(rho[i]), float(rhodot[i]), sr, srr, int(station))
        for i in range(6)
    ]


def six_point_solver(
    t,
    rho,
    rhodot,
    station,
    mode="doppler",
    method: str = "newton",
    propagator="kepler",
    mu: float = EARTH_MU,
    sigma_range: float = 1e-3,
    sigma_range_rate: float = 1e-6,
    **kw,
) -> OdSolver:
    """Reusable solver for the paper's six-point problem (see :func:`solve_six_point`)."""
    conds = six_point_conditions(t, rho, rhodot, mode, sigma_range, sigma_range_rate)
    return OdSolver.from_conditions(
        _stations(station), conds, _make_propagator(propagator, mu), settings(method, mu=mu, **kw)
    )


def solve_six_point(
    t,
    rho,
    rhodot,
    station,
    x0_guess,
    mode="doppler",
    method: str = "newton",
    propagator="kepler",
    mu: float = EARTH_MU,
    **kw,
) -> OdResult:
    """The paper's Newton-Raphson on six implicit boundary conditions (eqs. 9-18) with the exact STM.

    Parameters
    ----------
    t : array_like
        Six observation times (s from the epoch).
    rho : array_like
        Six observed ranges (km).
    rhodot : array_like or None
        Six observed range-rates (km/s); None with ``mode="range"``.
    station : Station
        The observing station (inertial, rotating).
    x0_guess : array_like
        First guess of the state at t = 0 (6,): km, km/s, inertial.
    mode : {"doppler", "range"} or list of 6, optional
        Condition types (see :func:`six_point_conditions`).
    method : str, optional
        "newton" (default, the paper's), "gauss_newton" or "levenberg_marquardt".
    propagator : str or propagator object, optional
        See :func:`make_propagator` (default "kepler").
    mu : float, optional
        Gravitational parameter (km^3/s^2; default :data:`EARTH_MU`).
    **kw
        ``sigma_range`` (km), ``sigma_range_rate`` (km/s) and :class:`OdSettings` fields.

    Returns
    -------
    OdResult
        Status, the best iterate ``x0`` (km, km/s), residuals, covariance and history.

    Raises
    ------
    ValueError
        Bad conditions (see :func:`six_point_conditions`), guess or settings.
    TypeError
        A station of another type, an unknown setting.

    Examples
    --------
    Six noise-free range / range-rate pairs of one pass, from a guess 10 km off in x:

    >>> import numpy as np
    >>> from satgnc import od
    >>> x = np.array([5836.8907, 1265.616, 3411.496, 0.3146, 6.9401, -3.1125])
    >>> st = od.station_inertial([5463.14996, 2139.12637, 2493.7785])
    >>> t = np.arange(0.0, 301.0, 60.0)
    >>> obs = od.simulate(x, st, t, seed=None)  # rows: range, range_rate per time
    >>> r = od.solve_six_point(t, obs.value[0::2], obs.value[1::2], st, x + [10.0, 0, 0, 0, 0, 0])
    >>> r.status.name, bool(np.max(np.abs(np.asarray(r.x0) - x)) < 1e-5)
    ('converged', True)
    """
    x0 = as_vector(x0_guess, 6, "x0_guess")
    return six_point_solver(t, rho, rhodot, station, mode, method, propagator, mu, **kw).solve(x0)


def box_guesses(center, half_width, n: int, seed: int = 0) -> np.ndarray:
    """Guesses drawn uniformly in a box about a state.

    Parameters
    ----------
    center : array_like
        Centre state (6,): km, km/s, inertial (the frame of the guesses).
    half_width : array_like
        Half widths (6,), >= 0: km, km/s.
    n : int
        Number of guesses (1 .. 1e7).
    seed : int, optional
        Random seed (>= 0; default 0): the same seed gives the same guesses.

    Returns
    -------
    numpy.ndarray
        Guesses (n, 6): km, km/s.

    Raises
    ------
    ValueError
        ``n`` < 1 or > 1e7, a negative half width or seed, wrong shapes.

    Examples
    --------
    >>> from satgnc import od
    >>> g = od.box_guesses([7000.0, 0, 0, 0, 7.5, 0], [10, 10, 10, 0.01, 0.01, 0.01], 4, seed=1)
    >>> g.shape
    (4, 6)
    """
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"n: must be an integer >= 1, got {n!r}")
    hw = as_vector(half_width, 6, "half_width")
    if np.any(hw < 0):
        raise ValueError("half_width: must be >= 0")
    seed = as_int(seed, "seed", low=0, high=2**64 - 1)  # was a pybind11 signature dump for seed=-1
    if n > 10**7:
        raise ValueError(f"n: must be <= 1e7 guesses ({48 * n / 1e9:.3g} GB), got {n}")
    return np.asarray(_c.od_box_guesses(as_vector(center, 6, "center"), hw, int(n), seed))


def root_search(
    solver_: OdSolver,
    guesses,
    distinct_sigma: float = 1.0,
    distinct_position_km: float = 1e-3,
    distinct_velocity_kms: float = 1e-6,
):
    """Solve from every guess and list the distinct converged solutions.

    Parameters
    ----------
    solver_ : OdSolver
        A reusable solver (``od.solver(...)`` or ``od.six_point_solver(...)``).
    guesses : array_like
        Guesses (n, 6): km, km/s (e.g. :func:`box_guesses`).
    distinct_sigma : float, optional
        Solutions closer than this many formal sigmas are the same (default 1).
    distinct_position_km : float, optional
        ... or closer than this in position (km, > 0; default 1e-3).
    distinct_velocity_kms : float, optional
        ... and in velocity (km/s, > 0; default 1e-6).

    Returns
    -------
    RootSearchResult
        The distinct solutions (fitting ones first) with residuals and covariance, the outcome of
        every guess, and ``ambiguous`` when two or more fit the data.

    Raises
    ------
    ValueError
        Guesses not (n, 6) or not finite, non-positive distinctness thresholds.
    TypeError
        ``solver_`` not an :class:`OdSolver`, guesses of a non-numeric type.

    Examples
    --------
    >>> import numpy as np
    >>> from satgnc import od
    >>> x = np.array([5836.8907, 1265.616, 3411.496, 0.3146, 6.9401, -3.1125])
    >>> st = od.station_inertial([5463.14996, 2139.12637, 2493.7785])
    >>> t = np.arange(0.0, 301.0, 60.0)
    >>> obs = od.simulate(x, st, t, seed=None)  # rows: range, range_rate per time
    >>> sv = od.six_point_solver(t, obs.value[0::2], obs.value[1::2], st)
    >>> res = od.root_search(sv, od.box_guesses(x, [20, 20, 20, 0.02, 0.02, 0.02], 8))
    >>> len(res.roots) >= 1, len(res.guess_status)
    (True, 8)
    """
    if not isinstance(solver_, OdSolver):
        raise TypeError(f"solver: must be an OdSolver, got {type(solver_).__name__}")
    if isinstance(guesses, (str, bytes)):
        raise TypeError(f"guesses: must be an (n, 6) array of states, got {type(guesses).__name__}")
    g = as_real_array(guesses, "guesses", finite=False)  # complex / boolean: TypeError (was truncated)
    if g.ndim != 2 or g.shape[1] != 6 or g.shape[0] < 1:
        raise ValueError(f"guesses: must have shape (n, 6), got {g.shape}")
    if not np.all(np.isfinite(g)):
        raise ValueError("guesses: must be finite")
    s = RootSearchSettings()
    s.distinct_sigma = as_real(distinct_sigma, "distinct_sigma")
    s.distinct_position_km = as_real(distinct_position_km, "distinct_position_km", positive=True)
    s.distinct_velocity_kms = as_real(distinct_velocity_kms, "distinct_velocity_kms", positive=True)
    return _c.od_root_search(solver_, np.ascontiguousarray(g), s)


# ----------------------------------------------------------------------------- synthetic data
def elevation_deg(x, station_state) -> float:
    """Elevation (deg) of the satellite above the station's geocentric horizontal plane."""
    d = np.asarray(x[:3]) - np.asarray(station_state[:3])
    up = np.asarray(station_state[:3]) / np.linalg.norm(station_state[:3])
    return math.degrees(math.asin(float(np.dot(d, up) / np.linalg.norm(d))))


def simulate(
    x0,
    stations,
    times,
    types: Sequence[str] = ("range", "range_rate"),
    sigma_range: float = 1e-3,
    sigma_range_rate: float = 1e-6,
    bias_range: float = 0.0,
    bias_range_rate: float = 0.0,
    elevation_mask_deg: float | None = 0.0,
    seed: int | None = 0,
    propagator="kepler",
    mu: float = EARTH_MU,
    force_model=None,
) -> Observations:
    """Synthetic observations of the orbit from ``x0`` (at t = 0) by every station at ``times``.

    Parameters
    ----------
    x0 : array_like
        State at t = 0 (6,): km, km/s, inertial.
    stations : Station or list of Station
        The observing stations.
    times : array_like
        Strictly increasing times (s from the epoch).
    types : sequence of str, optional
        Observables per visible time: "range" and/or "range_rate" (default both).
    sigma_range, sigma_range_rate : float, optional
        Gaussian noise sigmas (km, km/s; defaults 1e-3, 1e-6); also the table's sigmas.
    bias_range, bias_range_rate : float, optional
        Constant biases added (km, km/s; default 0).
    elevation_mask_deg : float or None, optional
        Elevation mask (deg in [-90, 90], geocentric horizontal; default 0 deg: no observation
        through the Earth; None: no mask, every time observed).
    seed : int or None, optional
        Noise seed (>= 0; None: no noise).
    propagator : str or propagator object, optional
        See :func:`make_propagator` (default "kepler").
    mu : float, optional
        Gravitational parameter (km^3/s^2; default :data:`EARTH_MU`).
    force_model : satgnc.ForceModel, optional
        The truth the observed orbit follows (J2 and ``ExponentialDrag`` optional; km, km/s, s),
        integrated by ``propagator="cvodes"``; its ``mu`` is the orbit's.

    Returns
    -------
    Observations
        Rows ordered by station, then time, then type (value and sigma km or km/s).

    Raises
    ------
    ValueError
        Naming the argument: an orbit below the Earth's surface (:data:`EARTH_RADIUS`) at any of
        ``times`` when ``mu`` is the Earth's (r = 0 for any ``mu``), an empty or repeated ``types``,
        a NaN or out-of-range ``elevation_mask_deg``, non-finite biases, a negative ``seed``, a mask
        that leaves no observation.
    TypeError
        A station of another type.

    Examples
    --------
    >>> import numpy as np
    >>> from satgnc import od
    >>> x = [5836.8907, 1265.616, 3411.496, 0.3146, 6.9401, -3.1125]
    >>> st = od.station_inertial([5463.14996, 2139.12637, 2493.7785])
    >>> obs = od.simulate(x, st, np.arange(0.0, 301.0, 60.0), seed=None)
    >>> len(obs), round(float(obs.value[0]), 2), obs.type_names()[:2]
    (12, 1320.95, ['range', 'range_rate'])
    """
    x0 = as_vector(x0, 6, "x0")  # also bounds |x0_i| < 1e100 (a 1e300 state blamed the propagator)
    st = _stations(stations)
    times = as_real_array(times, "times", ndim=(0, 1))
    times = np.atleast_1d(times)
    if times.size == 0:
        raise ValueError("times: must not be empty")
    if np.any(np.diff(times) <= 0):
        raise ValueError("times: must be strictly increasing")
    sr = as_real(sigma_range, "sigma_range", positive=True)
    srr = as_real(sigma_range_rate, "sigma_range_rate", positive=True)
    bias_range = as_real(bias_range, "bias_range")
    bias_range_rate = as_real(bias_range_rate, "bias_range_rate")
    if elevation_mask_deg is not None:
        elevation_mask_deg = as_real(elevation_mask_deg, "elevation_mask_deg", low=-90.0, high=90.0)
    if seed is not None:
        seed = as_int(seed, "seed", low=0)
    if isinstance(types, (str, MeasurementType)):
        types = [types]
    if not isinstance(types, Sequence) or isinstance(types, bytes):
        raise TypeError(f"types: must be a list of 'range' / 'range_rate', got {type(types).__name__}")
    if len(types) == 0:
        raise ValueError("types: must name at least one measurement type ('range', 'range_rate')")
    kinds = []
    for i, k in enumerate(types):
        try:
            kinds.append(_mtype(k))
        except (TypeError, ValueError) as e:
            raise type(e)(f"types[{i}]: {str(e).removeprefix('type: ')}") from None
    if len(set(int(k) for k in kinds)) != len(kinds):
        raise ValueError(f"types: a measurement type is repeated in {list(types)}")
    mu = as_real(mu, "mu", positive=True)
    mu_orbit = float(force_model.mu) if isinstance(force_model, _c.ForceModel) else mu
    floor = EARTH_RADIUS if mu_orbit == EARTH_MU else 0.0
    r0 = float(np.linalg.norm(x0[:3]))
    if not r0 > floor:
        where = "below the Earth's surface" if floor else "at the centre of attraction"
        raise ValueError(f"x0: the satellite is {where} (|r| = {r0:.6g} km, Earth radius {floor} km)")
    prop = _make_propagator(propagator, mu, False, "propagator", force_model)
    try:
        states, _ = prop.propagate(x0, list(times))
    except ValueError:
        # The engine says only "x0: propagation failed"; name the first time it cannot reach
        # (times = [0, 1e300] blamed x0, before that the force model).
        for k, tk in enumerate(times):
            try:
                prop.propagate(x0, [float(tk)])
            except ValueError:
                who = "times" if abs(float(tk)) > 1e12 else "times, x0, mu"  # 1e12 s: ~3e4 years
                raise ValueError(
                    f"{who}: the {propagator} propagator could not propagate x0 to times[{k}] = "
                    f"{tk:.6g} s (hint: observation times are seconds from the epoch of x0; mu in km^3/s^2)"
                ) from None
        raise
    states = np.asarray(states)
    radii = np.linalg.norm(states[:, :3], axis=1)
    low = np.flatnonzero(~(radii > floor))
    if low.size:
        k = low[0]
        raise ValueError(
            f"x0: the orbit goes below the Earth's surface (|r| = {radii[k]:.6g} km < {floor} km at "
            f"t = {times[k]:.6g} s)" if floor else f"x0: the orbit reaches r = 0 at t = {times[k]:.6g} s"
        )
    rng = np.random.default_rng(seed) if seed is not None else None
    rows = {"t": [], "type": [], "value": [], "sigma": [], "station": []}
    for i, s in enumerate(st):
        for tk, xk in zip(times, states):
            R = s.state(float(tk))
            if elevation_mask_deg is not None and elevation_deg(xk, R) < float(elevation_mask_deg):
                continue
            for k in kinds:
                v, _ = predict(k, xk, R)
                sig = sr if k == MeasurementType.range else srr
                bias = bias_range if k == MeasurementType.range else bias_range_rate
                noise = rng.normal(0.0, sig) if rng is not None else 0.0
                rows["t"].append(float(tk))
                rows["type"].append(k)
                rows["value"].append(v + bias + noise)
                rows["sigma"].append(sig)
                rows["station"].append(i)
    if not rows["t"]:
        raise ValueError("elevation_mask_deg: no observation above the mask")
    neg = [j for j, (k, v) in enumerate(zip(rows["type"], rows["value"]))
           if k == MeasurementType.range and v < 0]
    if neg:  # the table's "value: a range must be >= 0 km" named no argument of simulate
        j = neg[0]
        raise ValueError(f"sigma_range, bias_range: the simulated noise and bias made range {j} negative "
                         f"({rows['value'][j]:.6g} km at t = {rows['t'][j]:.6g} s); they must stay well "
                         "below the ranges (km)")
    return Observations(rows["t"], rows["type"], rows["value"], rows["sigma"], rows["station"])


# ----------------------------------------------------------------------------- sequential OD (issue 15)
from .filtering import FilterResult, filter, smooth  # noqa: A004, E402

__all__ += ["FilterResult", "filter", "smooth"]

from .._namespace import public_dir as _public_dir  # noqa: E402

__dir__ = _public_dir(__name__)  # dir(): the API, not the imported modules (np, math, ...)
