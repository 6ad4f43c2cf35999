"""Tracking measurements with light time and analytic partials (issue 13 item 4).

Orekit's estimation architecture in three concepts:

* a **station ephemeris** (:class:`StationEphemeris`): where the station is in GCRF (km, km/s) at
  t seconds after the ephemeris' epoch; :func:`rotating_station` wraps the paper's rotating
  :class:`satgnc.od.Station`; :class:`EarthFixedStationEphemeris` is a WGS-84 geodetic station fixed in
  the ITRF, carried to GCRF by an Earth rotation model;
* a **measurement model** (:class:`MeasurementModel`, built once, settings checked there): the
  observable (``"one_way_range"``, ``"two_way_range"``, ``"one_way_range_rate"``,
  ``"two_way_range_rate"``, ``"azimuth_elevation"``, ``"right_ascension_declination"``) and its
  modifiers (``troposphere``: Saastamoinen + Black-Eisner mapping in a standard atmosphere;
  ``shapiro``: the Earth's relativistic delay), both for range observables (on range-rates: the
  delays' rate);
* :func:`predict`: the model over arrays of reception tags and spacecraft GCRF states at those tags,
  returning :class:`Predictions` (values, partials d value / d state, d value / d [range bias km,
  time bias s], light times, statuses).

Units: km, km/s, s, rad. Measurements are tagged at reception; the up leg uses the station at its
transmit time; the spacecraft state at the bounce is the two-body Taylor shift of the state at the
tag. docs/observation.md gives the equations, the tolerances and what is left out. The
instantaneous model of the Gao-Luo paper stays :func:`satgnc.od.predict`.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from .. import _satgnc
from .._results import Result, adopt
from .._validate import as_real, one_of

MeasurementModel = _satgnc.MeasurementModel
StationEphemeris = _satgnc.StationEphemeris
RotatingStationEphemeris = _satgnc.RotatingStationEphemeris
EarthFixedStationEphemeris = _satgnc.EarthFixedStationEphemeris
ObservationStatus = _satgnc.ObservationStatus
SPEED_OF_LIGHT: float = _satgnc.SPEED_OF_LIGHT  # km/s

OBSERVABLES: tuple[str, ...] = (
    "one_way_range",
    "two_way_range",
    "one_way_range_rate",
    "two_way_range_rate",
    "azimuth_elevation",
    "right_ascension_declination",
)
#: {value: name} of the prediction statuses (read from the C++ table).
STATUS_NAMES: dict[int, str] = {int(v): k for k, v in ObservationStatus.__members__.items()}

__all__ = [
    "OBSERVABLES",
    "STATUS_NAMES",
    "SPEED_OF_LIGHT",
    "EarthFixedStationEphemeris",
    "MeasurementModel",
    "ObservationStatus",
    "Predictions",
    "RotatingStationEphemeris",
    "StationEphemeris",
    "marini_murray_delay",
    "measurement_model",
    "predict",
    "rotating_station",
    "saastamoinen_zenith_delay",
    "shapiro_delay",
    "shift_state",
    "standard_atmosphere",
    "tropo_mapping",
]


@dataclasses.dataclass(frozen=True)
class Predictions(Result):
    """One prediction per tag. ``m`` = 1 (range, range-rate) or 2 (angle pairs).

    ``value``: (n,) km or km/s, or (n, 2) rad, biases and modifiers included; ``dx``: (n, 6) or
    (n, 2, 6), d value / d state at the tag (km, km/s); ``dbias``: (n, 2) or (n, 2, 2), d value /
    d [range bias (km), time bias (s)]; ``tau_down``, ``tau_up`` (s), ``troposphere``, ``shapiro``
    (km, included in value), ``iterations`` (light-time updates); ``status``: one name per tag
    (``"success"``, ``"no_convergence"``, ``"degenerate_geometry"``, ``"invalid_input"``)."""

    observable: str
    value: np.ndarray
    dx: np.ndarray
    dbias: np.ndarray
    tau_down: np.ndarray
    tau_up: np.ndarray
    troposphere: np.ndarray
    shapiro: np.ndarray
    iterations: np.ndarray
    status: tuple[str, ...]

    @property
    def ok(self) -> bool:
        """Whether every tag has status ``"success"``."""
        return all(s == "success" for s in self.status)


def rotating_station(station: Any, ellipsoid: str = "WGS-84") -> Any:
    """The paper's rotating station as a :class:`StationEphemeris`.

    Parameters
    ----------
    station : satgnc.od.Station
        Inertial position r0 (km, GCRF) at t = 0 rotating about +z at omega (rad/s).
    ellipsoid : str, optional
        Ellipsoid of the geodetic topocentric axes (default ``"WGS-84"``).

    Returns
    -------
    RotatingStationEphemeris
        Station position (km) and velocity (km/s) in GCRF at t seconds after the station's epoch.

    Raises
    ------
    TypeError
        ``station`` is not a :class:`satgnc.od.Station`.
    """
    if not isinstance(station, _satgnc.Station):
        raise TypeError(f"station: must be a satgnc.od.Station, got {type(station).__name__}")
    return RotatingStationEphemeris(station, ellipsoid)


def measurement_model(
    observable: str,
    *,
    troposphere: bool | str = False,
    shapiro: bool = False,
    relative_humidity: float = 0.5,
    tolerance: float = 1e-14,
    max_iterations: int = 10,
    mu: float = float(_satgnc.EARTH_MU),
    min_range: float = 1e-3,
    time_bias_partials: bool = True,
    wavelength_um: float = 0.532,
) -> Any:
    """A :class:`MeasurementModel` for ``observable``, its settings checked once here.

    Parameters
    ----------
    observable : str
        One of :data:`OBSERVABLES`: ``"one_way_range"``, ``"two_way_range"`` (km),
        ``"one_way_range_rate"``, ``"two_way_range_rate"`` (km/s), ``"azimuth_elevation"``,
        ``"right_ascension_declination"`` (rad).
    troposphere : bool or str, optional
        Add the tropospheric delay (range observables) or its rate (range-rate observables); default
        False. True or ``"saastamoinen"``: Saastamoinen with the Black-Eisner mapping (radio);
        ``"mendes_pavlis"``: Mendes-Pavlis with the FCULa mapping at ``wavelength_um`` (laser ranging,
        the IERS Conventions 2010 model); ``"marini_murray"``: Marini-Murray at ``wavelength_um`` (laser
        ranging, the IERS Conventions 1996 model, elevations above 10 deg).
    shapiro : bool, optional
        Add the Earth's Shapiro delay (range observables only; default False).
    relative_humidity : float, optional
        Of the standard atmosphere, in [0, 1] (default 0.5).
    tolerance : float, optional
        Light-time iteration stop of each leg (s; default 1e-14).
    max_iterations : int, optional
        Light-time iterations per leg at most (default 10).
    mu : float, optional
        Gravitational parameter of the bounce-time shift and the Shapiro delay (km^3/s^2; default
        EARTH_MU).
    min_range : float, optional
        A smaller range is degenerate geometry (km; default 1e-3).
    time_bias_partials : bool, optional
        Compute d value / d time bias (default True).
    wavelength_um : float, optional
        Laser wavelength of Mendes-Pavlis / Marini-Murray, micrometres, in [0.3, 1.7] (default 0.532).

    Returns
    -------
    MeasurementModel
        The model, reusable for any number of :func:`predict` calls.

    Raises
    ------
    ValueError
        Naming the argument: an unknown observable, a modifier on a non-range observable, a humidity
        outside [0, 1], a non-positive tolerance, ...
    """
    name = one_of(observable, "observable", OBSERVABLES)
    try:
        return MeasurementModel(
            name,
            troposphere=troposphere,
            shapiro=shapiro,
            relative_humidity=relative_humidity,
            tolerance=tolerance,
            max_iterations=max_iterations,
            mu=mu,
            min_range=min_range,
            time_bias_partials=time_bias_partials,
            wavelength_um=wavelength_um,
        )
    except ValueError as e:  # C++ std::invalid_argument "field: rule": name the Python argument
        msg = str(e)
        for field in ("tolerance", "max_iterations"):
            msg = msg.replace(f"light_time.{field}", field)
        raise ValueError(msg) from None


def _tags_as_seconds(t: Any, epoch: Any) -> Any:
    """Tags as seconds after ``epoch`` when they are Epochs; numbers pass through unchanged."""
    epoch_type = _satgnc.Epoch
    tags = [t] if isinstance(t, epoch_type) else t
    is_epochs = isinstance(tags, (list, tuple)) and len(tags) > 0 and isinstance(tags[0], epoch_type)
    if not is_epochs:
        if epoch is not None:
            raise TypeError("epoch: give it only with tags that are satgnc.time.Epoch values")
        return t
    if not isinstance(epoch, epoch_type):
        raise TypeError(f"epoch: tags are Epochs, so epoch must be the satgnc.time.Epoch of t = 0, got "
                        f"{type(epoch).__name__}")
    if not all(isinstance(tag, epoch_type) for tag in tags):
        raise TypeError("t: mixes Epoch values and numbers")
    return np.array([tag - epoch for tag in tags], dtype=float)


def predict(
    model: Any,
    station: Any,
    t: Any,
    states: Any,
    *,
    range_bias: Any = 0.0,
    time_bias: Any = 0.0,
    epoch: Any = None,
) -> Predictions:
    """Predict ``model``'s observable for each reception tag.

    Failures are statuses, not exceptions.

    Parameters
    ----------
    model : MeasurementModel
        From :func:`measurement_model`.
    station : StationEphemeris
        The station (GCRF, km, km/s) on its own time axis.
    t : float, array_like or satgnc.time.Epoch
        Reception tags (s after the station ephemeris' epoch), scalar or (n,); or Epoch values (one or a
        sequence) when ``epoch`` is given: t = tag - epoch.
    states : array_like
        Spacecraft GCRF states at the tags, (6,) or (n, 6): km, km/s.
    range_bias : float or array_like, optional
        Range bias (km), one number or one per tag (default 0).
    time_bias : float or array_like, optional
        Time-tag bias (s), one number or one per tag (default 0).
    epoch : satgnc.time.Epoch, optional
        The epoch of t = 0 of the station ephemeris, when the tags are Epochs.

    Returns
    -------
    Predictions
        ``value`` (n,) km or km/s or (n, 2) rad, ``dx`` d value / d state (km, km/s), ``dbias``,
        light times ``tau_down`` / ``tau_up`` (s), delays (km) and one ``status`` per tag.

    Raises
    ------
    TypeError
        ``model`` or ``station`` of the wrong type, or tags mixing Epochs and numbers.
    ValueError
        Shapes or values that are not finite, naming the argument.
    """
    t = _tags_as_seconds(t, epoch)
    if not isinstance(model, MeasurementModel):
        raise TypeError(f"model: must be a satgnc.observation.MeasurementModel, got {type(model).__name__}")
    if not isinstance(station, StationEphemeris):
        got = type(station).__name__
        raise TypeError(f"station: must be a satgnc.observation.StationEphemeris, got {got}")
    if np.ndim(t) == 0:
        t = [as_real(t, "t")]
    out = model.predict_many(station, t, states, range_bias, time_bias)
    m = int(model.size)
    value = out["value"][:, :m]
    dx = out["dx"][:, :m, :]
    dbias = out["dbias"][:, :m, :]
    if m == 1:
        value, dx, dbias = value[:, 0], dx[:, 0, :], dbias[:, 0, :]
    return adopt(
        Predictions,
        observable=str(model.type),
        value=np.ascontiguousarray(value),
        dx=np.ascontiguousarray(dx),
        dbias=np.ascontiguousarray(dbias),
        tau_down=out["tau_down"],
        tau_up=out["tau_up"],
        troposphere=out["troposphere"],
        shapiro=out["shapiro"],
        iterations=out["iterations"],
        status=tuple(STATUS_NAMES[int(s)] for s in out["status"]),
    )




# ------------------------------------------------------------------ the models' building blocks (C++)
# Thin wrappers of the compiled functions, for their numpy-style sections with units (a compiled
# function's docstring cannot be replaced at import). Scalars in, scalars out.
def shift_state(x: Any, dt: float, mu: float = float(_satgnc.EARTH_MU)) -> tuple[np.ndarray, np.ndarray]:
    """Third-order two-body Taylor shift of a state by ``dt`` (the bounce-time shift of two-way models).

    Parameters
    ----------
    x : array_like
        GCRF state (6,): km, km/s.
    dt : float
        Shift (s), small against the orbital period (light times: < 0.1 s).
    mu : float, optional
        Gravitational parameter (km^3/s^2; default EARTH_MU).

    Returns
    -------
    x_shifted : numpy.ndarray
        (6,) km, km/s at t + dt.
    jacobian : numpy.ndarray
        (6, 6) d x_shifted / d x (km, km/s, s blocks).

    Raises
    ------
    ValueError
        ``x`` not of shape (6,) or not finite.
    """
    x1, jac = _satgnc.shift_state(x, dt, mu)
    return np.asarray(x1), np.asarray(jac)


def standard_atmosphere(height: float, relative_humidity: float = 0.5) -> tuple[float, float, float]:
    """Surface meteorology of the standard atmosphere at a station height (the troposphere's input).

    Parameters
    ----------
    height : float
        Station height above the ellipsoid (km).
    relative_humidity : float, optional
        In [0, 1] (default 0.5).

    Returns
    -------
    tuple of float
        (pressure hPa, temperature K, water-vapour partial pressure hPa).
    """
    p, t, e = _satgnc.standard_atmosphere(height, relative_humidity)
    return float(p), float(t), float(e)


def saastamoinen_zenith_delay(pressure: float, temperature: float, water_vapour: float, latitude: float,
                              height: float) -> float:
    """Saastamoinen zenith delay of the troposphere (dry plus wet).

    Parameters
    ----------
    pressure : float
        Surface pressure (hPa, >= 0).
    temperature : float
        Surface temperature (K).
    water_vapour : float
        Water-vapour partial pressure (hPa).
    latitude : float
        Geodetic latitude (rad).
    height : float
        Height above the ellipsoid (km).

    Returns
    -------
    float
        The zenith delay as a path length (km); about 0.0024 km at sea level.

    Raises
    ------
    ValueError
        A negative pressure or a non-finite input, naming it.
    """
    return float(_satgnc.saastamoinen_zenith_delay(pressure, temperature, water_vapour, latitude, height))


def marini_murray_delay(
    pressure: float,
    temperature: float,
    water_vapour: float,
    latitude: float,
    height: float,
    wavelength_um: float,
    elevation: float,
) -> tuple[float, float]:
    """Marini-Murray tropospheric range delay for laser ranging (IERS Conventions 1996, TN 21 ch. 9).

    Parameters
    ----------
    pressure : float
        Surface pressure (hPa, >= 0).
    temperature : float
        Surface temperature (K).
    water_vapour : float
        Water-vapour partial pressure (hPa).
    latitude : float
        Geodetic latitude (rad).
    height : float
        Height above the ellipsoid (km).
    wavelength_um : float
        Laser wavelength (micrometres, in [0.3, 1.7]).
    elevation : float
        Elevation of the line of sight (rad; the model is stated above 10 deg).

    Returns
    -------
    tuple of float
        (delay km, d delay / d elevation km/rad); about 0.0133 km at 10 deg for a ruby laser at sea level.

    Raises
    ------
    ValueError
        A negative pressure, a wavelength outside [0.3, 1.7] or a non-finite input, naming it.
    """
    d, dd = _satgnc.marini_murray_delay(pressure, temperature, water_vapour, latitude, height, wavelength_um,
                                        elevation)
    return float(d), float(dd)


def tropo_mapping(elevation: float) -> float:
    """Black-Eisner mapping function: slant delay / zenith delay at an elevation.

    Parameters
    ----------
    elevation : float
        Elevation of the line of sight (rad).

    Returns
    -------
    float
        The unit-free factor (1 at the zenith, about 10 at 5 deg).

    Raises
    ------
    TypeError
        ``elevation`` is not a real number (arrays are not taken).
    """
    return float(_satgnc.tropo_mapping(elevation))


def shapiro_delay(r1: float, r2: float, rho: float, mu: float = float(_satgnc.EARTH_MU)) -> float:
    """One-way Shapiro (relativistic) delay of the Earth's field between two points.

    Parameters
    ----------
    r1, r2 : float
        Geocentric distances of the two ends (km).
    rho : float
        Distance between them (km).
    mu : float, optional
        Gravitational parameter (km^3/s^2; default EARTH_MU).

    Returns
    -------
    float
        The delay as a path length (km); about 2e-6 km from a 400 km orbit at 1500 km range.
    """
    return float(_satgnc.shapiro_delay(r1, r2, rho, mu))


from .._namespace import public_dir as _public_dir  # noqa: E402

__dir__ = _public_dir(__name__)  # dir(): the API, not the imported modules (np, math, ...)
