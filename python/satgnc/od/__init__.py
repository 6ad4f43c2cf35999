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
    """Julian date of ``epoch``: a :class:`datetime.datetime` (naive = UTC), an ISO-8601 string
    ('1981-03-21T06:00:00'), or a float Julian date (returned as is)."""
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
    """Greenwich mean sidereal time (IAU-1982), rad in [0, 2 pi), at a UTC epoch (see :func:`julian_date`);
    ``ut1_minus_utc`` in s, ``|UT1 - UTC| < 0.9`` (IERS)."""
    return _c.od_gmst_from_utc(julian_date(epoch), _ut1_minus_utc(ut1_minus_utc))


def ellipsoid(name: str = "WGS-84") -> Ellipsoid:
    """Named ellipsoid: WGS-84 (default), GRS-80, IAU-1976, Krassovsky or sphere."""
    if not isinstance(name, str):
        raise TypeError(f"ellipsoid: must be a name (str), got {type(name).__name__}")
    return _c.od_ellipsoid_by_name(name)


def _as_ellipsoid(e) -> Ellipsoid:
    return e if isinstance(e, Ellipsoid) else ellipsoid(e)


def geodetic_to_ecef(lat_deg: float, lon_deg: float, height_km: float, ellipsoid="WGS-84") -> np.ndarray:
    """Earth-fixed position (km) of geodetic latitude/longitude (deg) and height (km)."""
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
    """Station at geodetic (deg, deg, km) on the named ellipsoid; inertial position at the UTC
    ``epoch`` through GMST (IAU-1982), rotating about +z at ``omega`` (rad/s)."""
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
    """The paper's station: inertial position ``r0`` (km) at t = 0 rotating about +z at ``omega``."""
    return Station.from_inertial(as_vector(r0, 3, "r0"), as_real(omega, "omega"))


def implied_rotation_rate(station_state) -> float:
    """Rotation rate (rad/s) that makes a printed station state [R, V] satisfy V = omega z x R."""
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
    """Predicted observable (km or km/s) of satellite state ``x`` from ``station_state`` and its
    partials d h / d x (6,). Raises ValueError when the satellite is at the station."""
    v, g = _c.od_predict_measurement(
        _mtype(kind, "kind"), as_vector(x, 6, "x"), as_vector(station_state, 6, "station_state")
    )
    return float(v), np.asarray(g).ravel()


def make_propagator(kind: str = "kepler", mu: float = EARTH_MU, j2: bool = False, force_model=None):
    """STM propagator: 'kepler' (analytic two-body, default) or 'cvodes' (numerical; ``j2`` optional).
    A propagator object (KeplerStmPropagator, CvodesStmPropagator, ShortArcStmPropagator) is returned
    as is.

    ``force_model``: a :class:`satgnc.ForceModel` (point mass + optional ``J2Gravity`` + optional
    ``ExponentialDrag``; km, km/s, s, drag's density kg/m^3, area m^2, mass kg) for ``"cvodes"``: the
    states and the STM (with the drag's analytic Jacobians) are integrated on that model. It replaces
    ``mu`` and ``j2``: give J2 in the model, and leave ``mu`` at :data:`EARTH_MU` or equal to
    ``force_model.mu`` (km^3/s^2). TypeError for another type; ValueError for ``"kepler"``, for
    ``j2=True`` beside it, for a different ``mu``, or for a model that fails ``ForceModel.validate``."""
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
    """OdSettings from keyword arguments (unknown names raise TypeError naming them)."""
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
    """Observations from a CSV file with a header holding ``t,type,value,sigma[,station]`` in any
    order (t in s from the epoch; type range/range_rate; value and sigma in km or km/s; station a
    0-based index, default 0, or a station name: names are numbered 0, 1, ... in order of first
    appearance, see :func:`read_csv_names`; a file uses indices or names, not both). Blank lines and
    lines starting with ``#`` are skipped; UTF-8 with or
    without a byte-order mark, LF or CRLF line ends.

    Every error in the content is a :class:`satgnc.FileFormatError` (a ``ValueError``) naming the
    file, the line and the column: unknown, duplicated or missing header columns, a wrong number of
    cells, a non-numeric or non-finite cell, a range <= 0, a sigma <= 0, a negative station index, and
    two rows with the same time, type and station (both lines named). Rows need not be time-ordered."""
    return read_csv_names(path)[0]


def read_csv_names(path) -> tuple[Observations, list[str] | None]:
    """:func:`read_csv` and the station names of a file whose station column holds names (e.g.
    ``BOULDER``): ``(observations, names)`` with ``observations.station[i]`` indexing ``names``;
    ``names`` is None when the column holds indices (or is absent)."""
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
    """Weighted batch least squares for the state at t = 0 from any number (>= 6) of observations of
    one or several stations. ``method``: 'levenberg_marquardt' (default), 'gauss_newton' (line
    search) or 'newton' (the paper's undamped method, exactly 6 observations). Extra keywords set
    :class:`OdSettings` fields (e.g. ``max_iterations`` = 100, ``cost_tol`` = 1e-6,
    ``geodesic`` = True, ``valley_corrections`` = 3, ``extrapolate`` = True). Returns the OdResult:
    status (``converged`` only when the convergence test holds at x0 with rank 6; ``singular``,
    ``stalled``, ``max_iterations``, ... otherwise, see
    docs/od.md), x0 = the best iterate with its cost, residuals and covariance, and a history of
    ``iterations + 1`` rows."""
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
    """The paper's six implicit conditions: ``mode`` 'doppler' (eq. 11 with the observed range),
    'range' (eq. 9) or a list of six of them (mixed)."""
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
    ``t`` six times (s), ``rho`` observed ranges (km), ``rhodot`` observed range-rates (km/s)."""
    x0 = as_vector(x0_guess, 6, "x0_guess")
    return six_point_solver(t, rho, rhodot, station, mode, method, propagator, mu, **kw).solve(x0)


def box_guesses(center, half_width, n: int, seed: int = 0) -> np.ndarray:
    """(n, 6) guesses uniform in ``center +- half_width`` (km, km/s), reproducible from ``seed``."""
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
    """Solve from every guess ((n, 6) array) and list the distinct converged solutions (fitting ones
    first) with residuals and covariance; ``result.ambiguous`` when two or more fit the data."""
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
    """Synthetic observations of the orbit from ``x0`` (at t = 0) by every station at ``times`` (s):
    each type in ``types`` per visible time, Gaussian noise (sigmas in km, km/s; seed=None for none),
    constant biases (km, km/s), and an elevation mask (deg in [-90, 90], geocentric horizontal; default
    0 deg: no observation through the Earth; ``None``: no mask, every time observed) that drops low
    passes. ``force_model``: the truth the observed orbit follows, a :class:`satgnc.ForceModel`
    (J2 and ``ExponentialDrag`` optional; km, km/s, s) integrated by ``propagator="cvodes"`` (see
    :func:`make_propagator`); its ``mu`` is the orbit's.

    Raises ``ValueError`` naming the argument for: an orbit that is below the Earth's surface
    (:data:`EARTH_RADIUS`) at any of ``times`` when ``mu`` is the Earth's (r = 0 for any ``mu``), an
    empty or repeated ``types``, a NaN or out-of-range ``elevation_mask_deg``, non-finite biases, a
    negative ``seed``, and a mask that leaves no observation."""
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
