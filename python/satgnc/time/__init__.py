"""satgnc.time: time scales and the Epoch type (C++ ``satgnc::core::Epoch`` over ERFA).

An :class:`Epoch` is an instant stored in TAI as whole seconds plus a fraction since J2000 TAI, so
differences and shifts keep ~1e-16 s over decades. Scales: ``TAI``, ``TT`` (TAI + 32.184 s), ``UTC``
(leap seconds from ERFA's table; ``23:59:60`` is valid on a leap-second day), ``GPS`` (TAI - 19 s) and
``TDB`` (TT + ERFA's eraDtdb at the geocentre). UT1 needs Earth orientation parameters:
:meth:`satgnc.frames.EopTable.ut1_minus_utc`.

A ``scale`` argument is a :class:`TimeScale` or its name (case-insensitive). Bad input raises
``ValueError`` naming the argument or the text, e.g. ``time_scale: unknown time system 'GMT' (choices:
TAI, TT, UTC, GPS, TDB)``.
"""

from __future__ import annotations

from .. import _satgnc as _s

Epoch = _s.Epoch
TimeScale = _s.TimeScale
time_scale_from_name = _s.time_scale_from_name

SCALES: tuple[str, ...] = ("TAI", "TT", "UTC", "GPS", "TDB")

__all__ = ["Epoch", "TimeScale", "time_scale_from_name", "SCALES", "parse"]


def parse(text: str, scale: str | TimeScale = "UTC") -> Epoch:
    """An :class:`Epoch` from an ISO-8601 text (:meth:`Epoch.parse`).

    Parameters
    ----------
    text : str
        ``YYYY-MM-DDThh:mm:ss[.f]`` or ``YYYY-DDDThh:mm:ss[.f]`` (``23:59:60`` valid on a UTC leap-second
        day).
    scale : str or TimeScale, optional
        The time scale of the text: ``"TAI"``, ``"TT"``, ``"UTC"`` (default), ``"GPS"`` or ``"TDB"``
        (case-insensitive).

    Returns
    -------
    Epoch
        The instant (stored as TAI seconds (s) since J2000 TAI, whole plus fraction).

    Raises
    ------
    TypeError
        ``text`` is not a str.
    ValueError
        A malformed text or an unknown scale, naming it.
    """
    if not isinstance(text, str):
        raise TypeError(f"text: must be a str, got {type(text).__name__}")
    return Epoch.parse(text, scale)

