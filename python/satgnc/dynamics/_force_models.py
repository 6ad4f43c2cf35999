"""Gravity field, Sun and Moon, solar radiation pressure (issue 14 items 1-3, 5).

Units: km, km/s, s; accelerations km/s^2; SRP area m^2, mass kg, pressure N/m^2 at 1 AU.
"""

from __future__ import annotations

import os
import pathlib

from .. import _satgnc as _c
from .._validate import as_real_array

EarthRotationModel = _c.EarthRotationModel
UniformRotation = _c.UniformRotation
GravityCoefficients = _c.GravityCoefficients
GravityField = _c.GravityField
ThirdBodies = _c.ThirdBodies
SolarRadiationPressure = _c.SolarRadiationPressure
SpkEphemeris = _c.SpkEphemeris
sun_position = _c.sun_position
moon_position = _c.moon_position

#: The shipped EGM2008 coefficients (NGA, public domain; tide-free, fully normalized) to degree 70.
EGM2008_PATH: pathlib.Path = pathlib.Path(__file__).resolve().parent.parent / "data" / "egm2008_70.gfc"


def load_gfc(path: str | pathlib.Path, max_degree: int = -1) -> GravityCoefficients:
    """Read an ICGEM ``.gfc`` file (static field, fully normalized) up to ``max_degree`` (-1: the
    file's). ``ValueError`` names the file, the line and the keyword of a malformed entry, and refuses
    a ``max_degree`` above the file's."""
    return _c.load_gfc(str(path), int(max_degree))


def egm2008(max_degree: int = 70) -> GravityCoefficients:
    """EGM2008 coefficients (Pavlis et al. 2012; GM 398600.4415 km^3/s^2, radius 6378.1363 km) to
    ``max_degree`` <= 70 (the shipped file's degree)."""
    return load_gfc(EGM2008_PATH, max_degree)


def load_spk(
    path: str | os.PathLike[str], pairs: list[tuple[int, int]] | None = None
) -> SpkEphemeris:
    """Open a JPL DE ephemeris (NAIF SPK ``.bsp``: Chebyshev segment types 2 and 3) for the
    ``(target, center)`` pairs of NAIF codes ``pairs`` (default the geocentric Sun ``(10, 399)`` and
    Moon ``(301, 399)``), chained through the file's segments (Moon = EMB->Moon - EMB->Earth).

    Epochs are TDB seconds past J2000, positions km, velocities km/s, J2000 (ICRF) axes. ``ValueError``
    names the file and what is wrong (not a DAF, wrong endianness, an unsupported segment type on a
    chain, no chain linking a pair); evaluating outside the coverage names the epoch and the coverage.
    The data of the chains are read once; evaluations allocate nothing.

    Examples
    --------
    >>> from satgnc.dynamics import load_spk
    >>> eph = load_spk("de421.bsp")  # doctest: +SKIP
    >>> eph.position(301, 399, 0.0)  # the Moon from the Earth at J2000 TDB, km  # doctest: +SKIP
    """
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path: must be a str or os.PathLike, got {type(path).__name__}")
    if pairs is None:
        return _c.SpkEphemeris(os.fspath(path))
    checked: list[tuple[int, int]] = []
    for p in pairs:
        if (not isinstance(p, tuple) or len(p) != 2
                or not all(isinstance(b, int) and not isinstance(b, bool) for b in p)):
            raise TypeError(
                f"pairs: must be a list of (target, center) tuples of NAIF integer codes, got {p!r}")
        checked.append((int(p[0]), int(p[1])))
    if not checked:
        raise ValueError("pairs: must name at least one (target, center) pair")
    return _c.SpkEphemeris(os.fspath(path), checked)


def force_model(
    *,
    mu: float | None = None,
    j2=None,
    drag=None,
    gravity: GravityField | None = None,
    third_body: ThirdBodies | None = None,
    srp: SolarRadiationPressure | None = None,
    atmosphere_drag: _c.AtmosphereDrag | None = None,
    epoch_jd: tuple[float, float] | float = (2451545.0, 0.0),
    epoch: _c.Epoch | None = None,
    ephemeris: str | os.PathLike[str] | SpkEphemeris | None = None,
) -> _c.ForceModel:
    """A :class:`satgnc.ForceModel` with the precise terms set.

    mu (km^3/s^2) defaults to the gravity field's GM when a field is given (else Earth's EGM-96
    value); ``epoch_jd`` is the TT Julian date of t = 0 (one number or two parts, days), used by the
    Sun, the Moon, SRP and the atmosphere drag's Sun (one epoch); ``epoch`` (a
    :class:`satgnc.time.Epoch`), when given, replaces it. ``ephemeris`` (a JPL DE ``.bsp`` path or an
    opened :class:`SpkEphemeris`) replaces ERFA's Sun and Moon (third bodies, SRP, the drag's Sun);
    the epoch must lie in its coverage. The result is validated (``ValueError`` names the field)."""
    if mu is None:
        mu = gravity.mu if gravity is not None else _c.EARTH_MU
    jd = as_real_array(epoch_jd, "epoch_jd", ndim=(0, 1))
    if jd.ndim == 1 and jd.shape != (2,):
        raise ValueError(f"epoch_jd: must be one number or two parts (jd1, jd2), got shape {jd.shape}")
    parts = (float(jd), 0.0) if jd.ndim == 0 else (float(jd[0]), float(jd[1]))
    fm = _c.ForceModel(mu=mu, j2=j2, drag=drag, epoch_jd1=parts[0], epoch_jd2=parts[1])
    fm.gravity = gravity
    fm.third_body = third_body
    fm.srp = srp
    if epoch is not None:
        fm.set_epoch(epoch)
    if ephemeris is not None:
        fm.spk_ephemeris = ephemeris if isinstance(ephemeris, SpkEphemeris) else load_spk(ephemeris)
    fm.atmosphere_drag = atmosphere_drag  # after the epoch: an ErfaSun must carry the model's epoch
    fm.validate()
    return fm
