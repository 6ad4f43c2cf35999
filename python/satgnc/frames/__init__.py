"""satgnc.frames: Earth orientation (IAU 2006/2000A, CIO-based, with EOP), EME2000, ground stations.

- :class:`EopTable`: daily EOP (xp, yp arcsec; UT1-UTC, LOD s; dX, dY arcsec) from the IERS files
  (``finals2000A.all/.data``: Bulletin B where present, else A; EOP 20 C04), 4-point Lagrange
  interpolation (UT1 as UT1-TAI across leap seconds), out-of-range policy ``"error"`` (default),
  ``"hold_last"`` or ``"zero"``. :func:`default_eop` reads the table shipped by the PyPI package
  ``astropy-iers-data``; :func:`load_eop` reads any file (the C++ reader: a flight program reads the
  same files without Python).
- :func:`gcrs_to_itrs`, :func:`itrs_to_gcrs`: position (3,) km or state (6,) km, km/s at an
  :class:`satgnc.time.Epoch`; velocities include the Earth-rotation term with LOD (the
  precession-nutation and polar-motion rates, < 1e-7 km/s, are left out). :func:`gcrs_to_eme2000`:
  the frame bias (eraBp06).
- :class:`IauEarthRotation`: the same chain for a propagation (grid + exact ERA, 2.9e-12 rad).
- :class:`GroundStation`: WGS-84 geodetic station in the ITRF, its GCRF state, look angles
  (:class:`LookAngles`, rad, km, with rates) and an elevation mask; a height below -0.5 km is refused.

Files with a malformed line raise :class:`satgnc.FileFormatError` (``path:line: reason``).
"""

from __future__ import annotations

import functools
import os
import pathlib
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _satgnc as _s
from .._validate import FileFormatError, one_of

EopTable = _s.EopTable
EopValues = _s.EopValues
EarthOrientation = _s.EarthOrientation
IauEarthRotation = _s.IauEarthRotation
GroundStation = _s.GroundStation
LookAngles = _s.LookAngles

POLICIES: tuple[str, ...] = ("error", "hold_last", "zero")
FORMATS: tuple[str, ...] = ("auto", "finals2000a", "c04")
MIN_STATION_HEIGHT_KM = -0.5  # km: the Dead Sea shore is -0.43 km (C++ frames::kMinStationHeightKm)

__all__ = [
    "EopTable", "EopValues", "EarthOrientation", "IauEarthRotation", "GroundStation", "LookAngles",
    "earth_orientation", "gcrs_to_itrs", "itrs_to_gcrs", "gcrs_to_itrs_matrix", "gcrs_to_eme2000",
    "eme2000_to_gcrs", "gcrs_to_eme2000_matrix", "load_eop", "default_eop", "default_eop_path",
    "POLICIES", "FORMATS", "MIN_STATION_HEIGHT_KM",
]


def _file_error(path: str, err: ValueError) -> Exception:
    """The C++ reader's ``"<path>:<line>: <reason>"`` as a FileFormatError; other errors unchanged."""
    msg = str(err)
    prefix = path + ":"
    if msg.startswith(prefix):
        line_text, _, reason = msg[len(prefix):].partition(": ")
        if line_text.isdigit():
            return FileFormatError(path, int(line_text), reason)
    return err


def load_eop(path: Any, policy: str = "error", format: str = "auto") -> EopTable:
    """Read an IERS Earth orientation file into an :class:`EopTable`.

    Parameters
    ----------
    path : str or os.PathLike
        ``finals2000A.all/.data/.daily`` or EOP 20 C04 (xp, yp in arcsec; UT1-UTC, LOD in s; dX, dY in
        arcsec).
    policy : {"error", "hold_last", "zero"}, optional
        What the table does outside its span (default ``"error"``).
    format : {"auto", "finals2000a", "c04"}, optional
        ``"auto"`` (default) detects it from the first data line.

    Returns
    -------
    EopTable
        Daily rows, 4-point Lagrange interpolation.

    Raises
    ------
    FileNotFoundError
        ``path`` does not exist.
    satgnc.FileFormatError
        A malformed file, naming the file and the line.
    ValueError
        An unknown ``policy`` or ``format``.
    TypeError
        ``path`` is not a str or os.PathLike.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path: must be a str or os.PathLike, got {type(path).__name__}")
    one_of(policy, "policy", POLICIES)
    one_of(format, "format", FORMATS)
    p = pathlib.Path(path)
    if not p.is_file():
        raise FileNotFoundError(f"path: EOP file '{p}' does not exist")
    readers = {"auto": EopTable.read, "finals2000a": EopTable.read_finals2000a, "c04": EopTable.read_c04}
    reader = readers[format]
    try:
        return reader(str(p), policy)
    except ValueError as err:
        raise _file_error(str(p), err) from None


def default_eop_path() -> pathlib.Path:
    """Path of ``finals2000A.all`` inside the installed PyPI package ``astropy-iers-data``.

    Returns
    -------
    pathlib.Path
        The file :func:`default_eop` reads.
    """
    import astropy_iers_data  # type: ignore[import-untyped]  # a dependency of satgnc (pyproject.toml)

    return pathlib.Path(str(astropy_iers_data.IERS_A_FILE))


@functools.cache
def default_eop(policy: str = "error") -> EopTable:
    """The EOP table of the installed ``astropy-iers-data`` (``finals2000A.all``).

    IERS Bulletin B values where present, Bulletin A and its one-year prediction after. Read once per
    policy and cached (tables are immutable). Update the table with ``pip install -U astropy-iers-data``.

    Parameters
    ----------
    policy : {"error", "hold_last", "zero"}, optional
        What the table does outside its span (default ``"error"``).

    Returns
    -------
    EopTable
        xp, yp (arcsec), UT1-UTC, LOD (s), dX, dY (arcsec) per day.

    Raises
    ------
    ValueError
        An unknown ``policy``.
    """
    one_of(policy, "policy", POLICIES)
    return load_eop(default_eop_path(), policy)


# ------------------------------------------------------------------ frame transformations (ERFA, C++)
# Thin wrappers of the compiled functions: they add the numpy-style sections with units (a compiled
# function's docstring cannot be replaced at import).
_EPOCH_EOP = """epoch : satgnc.time.Epoch
    The instant (any time scale; UT1 from the table's UT1-UTC).
eop : EopTable
    Earth orientation parameters (e.g. :func:`default_eop`); its policy applies outside its span."""
_EOP_RAISES = """ValueError
    An epoch outside the EOP table under the policy ``"error"`` (the message gives the span and the fix)."""


def earth_orientation(epoch: _s.Epoch, eop: EopTable) -> EarthOrientation:
    """The IAU 2006/2000A (CIO-based) GCRS -> ITRS factors at ``epoch``, full series.

    Parameters
    ----------
    {epoch_eop}

    Returns
    -------
    EarthOrientation
        ``gcrs_to_itrs`` (3, 3), the Earth rotation angle ``era`` (rad), the CIO quantities and the
        Earth's angular velocity ``omega`` (rad/s).

    Raises
    ------
    {raises}
    """
    return _s.earth_orientation(epoch, eop)


def gcrs_to_itrs(x: npt.ArrayLike, epoch: _s.Epoch, eop: EopTable) -> npt.NDArray[np.float64]:
    """A GCRS (GCRF) position or state in the ITRS (ITRF) at ``epoch``.

    The velocity includes the Earth-rotation term with LOD; the precession-nutation and polar-motion
    rates (< 1e-7 km/s) are left out.

    Parameters
    ----------
    x : array_like
        Position (3,) km, or state (6,) km and km/s, in GCRS.
    {epoch_eop}

    Returns
    -------
    numpy.ndarray
        The same shape in ITRS: km (and km/s).

    Raises
    ------
    ValueError
        ``x`` not of shape (3,) or (6,).
    {raises}
    """
    return np.asarray(_s.gcrs_to_itrs(x, epoch, eop))


def itrs_to_gcrs(x: npt.ArrayLike, epoch: _s.Epoch, eop: EopTable) -> npt.NDArray[np.float64]:
    """An ITRS (ITRF) position or state in the GCRS (GCRF) at ``epoch``; inverse of :func:`gcrs_to_itrs`.

    Parameters
    ----------
    x : array_like
        Position (3,) km, or state (6,) km and km/s, in ITRS.
    {epoch_eop}

    Returns
    -------
    numpy.ndarray
        The same shape in GCRS: km (and km/s).

    Raises
    ------
    ValueError
        ``x`` not of shape (3,) or (6,).
    {raises}
    """
    return np.asarray(_s.itrs_to_gcrs(x, epoch, eop))


def gcrs_to_itrs_matrix(epoch: _s.Epoch, eop: EopTable) -> npt.NDArray[np.float64]:
    """The GCRS -> ITRS rotation matrix at ``epoch`` (IAU 2006/2000A, CIO-based, with polar motion).

    Parameters
    ----------
    {epoch_eop}

    Returns
    -------
    numpy.ndarray
        (3, 3) unit-free rotation: r_itrs = M r_gcrs.

    Raises
    ------
    {raises}
    """
    return np.asarray(_s.gcrs_to_itrs_matrix(epoch, eop))


def gcrs_to_eme2000(x: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """A GCRS position or state in EME2000 (J2000 mean equator and equinox): the frame bias (eraBp06).

    Parameters
    ----------
    x : array_like
        Position (3,) km, or state (6,) km and km/s, in GCRS.

    Returns
    -------
    numpy.ndarray
        The same shape in EME2000 (the bias is constant: velocities rotate like positions).

    Raises
    ------
    ValueError
        ``x`` not of shape (3,) or (6,).
    """
    return np.asarray(_s.gcrs_to_eme2000(x))


def eme2000_to_gcrs(x: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """An EME2000 position or state in GCRS; inverse of :func:`gcrs_to_eme2000`.

    Parameters
    ----------
    x : array_like
        Position (3,) km, or state (6,) km and km/s, in EME2000.

    Returns
    -------
    numpy.ndarray
        The same shape in GCRS.

    Raises
    ------
    ValueError
        ``x`` not of shape (3,) or (6,).
    """
    return np.asarray(_s.eme2000_to_gcrs(x))


def gcrs_to_eme2000_matrix() -> npt.NDArray[np.float64]:
    """The constant GCRS -> EME2000 frame-bias matrix (eraBp06's rb).

    Returns
    -------
    numpy.ndarray
        (3, 3) unit-free rotation: r_eme2000 = B r_gcrs.
    """
    return np.asarray(_s.gcrs_to_eme2000_matrix())


for _f in (earth_orientation, gcrs_to_itrs, itrs_to_gcrs, gcrs_to_itrs_matrix):
    _f.__doc__ = (_f.__doc__ or "").replace("{epoch_eop}", _EPOCH_EOP.replace("\n", "\n    ")).replace(
        "{raises}", _EOP_RAISES.replace("\n", "\n    "))
del _f

from .._namespace import public_dir as _public_dir  # noqa: E402

__dir__ = _public_dir(__name__)  # dir(): the API, not the imported modules (np, math, ...)
