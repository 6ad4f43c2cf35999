"""NRLMSISE-00 neutral atmosphere (issue 14 item 4): Picone, Hedin, Drob, Aikin (2002), JGR 107(A12) 1468.

Implemented in C++ from the published model; coefficients from the NRL tables (public domain), compiled
in from ``cpp/data/nrlmsise00_coefficients.txt``. Checked against the model's 17 published test cases.

- :class:`Nrlmsise00`: an :class:`~satgnc.dynamics.AtmosphereModel` for
  :class:`~satgnc.dynamics.AtmosphereDrag`; density in kg/m^3 at an ITRF position (km), with the day of
  year and UT from the epoch (two-part TT Julian date) + t (s) and the local apparent solar time from the
  Sun direction. Below 0 km it returns the 0 km density; above 1000 km the model's exospheric profile.
- :func:`nrlmsise00`: one evaluation at the model's own inputs, every species (m^-3), mass density
  (kg/m^3) and the two temperatures (K); inputs range-checked (altitude 0-1000 km, F10.7 and Ap 0-400).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

from .. import _validate
from .._results import Result
from .._satgnc import Nrlmsise00, _nrlmsise00_evaluate

__all__ = ["Nrlmsise00", "Nrlmsise00Result", "nrlmsise00"]


@dataclasses.dataclass(frozen=True)
class Nrlmsise00Result(Result):
    """One NRLMSISE-00 evaluation. Number densities in m^-3, mass density kg/m^3, temperatures K."""

    he: float
    o: float
    n2: float
    o2: float
    ar: float
    h: float
    n: float
    anomalous_o: float
    mass_density: float  # GTD7D drag density if anomalous_oxygen else GTD7 total mass density
    exospheric_temperature: float
    temperature: float


def _floats(value: Sequence[float] | None, n: int, name: str) -> list[float] | None:
    if value is None:
        return None
    arr = _validate.as_vector(value, n, name)
    return [float(x) for x in arr]


def nrlmsise00(
    *,
    day_of_year: int,
    ut_seconds: float,
    altitude: float,
    latitude: float,
    longitude: float,
    local_solar_time: float | None = None,
    f107a: float = 150.0,
    f107: float = 150.0,
    ap: float = 4.0,
    ap_history: Sequence[float] | None = None,
    anomalous_oxygen: bool = False,
    switches: Sequence[float] | None = None,
) -> Nrlmsise00Result:
    """NRLMSISE-00 at one point (GTD7, or GTD7D's drag density with ``anomalous_oxygen=True``).

    day_of_year 1-366; ut_seconds s of the day (0-86400); altitude geodetic km (0-1000); latitude,
    longitude geodetic deg; local_solar_time hours (default the model's recommendation
    ut_seconds/3600 + longitude/15, wrapped to [0, 24)); f107a, f107 sfu (0-400, 81-day mean and the
    previous day); ap daily Ap (0-400); ap_history 7 values (daily, 3-h now, -3, -6, -9 h, means of
    12-33 h and 36-57 h before): given, switch 9 becomes -1; switches: the model's 23 switches 1..23
    (0, 1, 2; switch 9 also -1). Raises ValueError naming the argument out of range."""
    doy = _validate.as_int(day_of_year, "day_of_year", low=1, high=366)
    ut = _validate.as_real(ut_seconds, "ut_seconds")
    lon = _validate.as_real(longitude, "longitude")
    if local_solar_time is None:
        lst = (ut / 3600.0 + lon / 15.0) % 24.0
    else:
        lst = _validate.as_real(local_solar_time, "local_solar_time")
    try:
        out = _nrlmsise00_evaluate(
            doy,
            ut,
            _validate.as_real(altitude, "altitude"),
            _validate.as_real(latitude, "latitude"),
            lon,
            lst,
            _validate.as_real(f107a, "f107a"),
            _validate.as_real(f107, "f107"),
            _validate.as_real(ap, "ap"),
            _floats(ap_history, 7, "ap_history"),
            _validate.as_bool(anomalous_oxygen, "anomalous_oxygen"),
            _floats(switches, 23, "switches"),
        )
    except ValueError as exc:  # "nrlmsise00.altitude: ..." -> "altitude: ..."
        raise ValueError(str(exc).removeprefix("nrlmsise00.")) from None
    return Nrlmsise00Result(**out)
