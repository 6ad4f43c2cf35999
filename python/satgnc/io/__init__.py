"""satgnc.io: CCSDS navigation data messages (the C++ io room; docs/io.md).

- TDM, Tracking Data Message (CCSDS 503.0-B-2), KVN and XML: :func:`read_tdm`, :func:`parse_tdm`,
  :func:`write_tdm`, :func:`format_tdm`; model :class:`Tdm` > :class:`TdmSegment` >
  :class:`TdmMetadata`.
- OEM, Orbit Ephemeris Message (CCSDS 502.0-B-3 section 5), KVN: :func:`read_oem`, :func:`write_oem`;
  model :class:`Oem` > :class:`OemSegment` (epochs, states (n, 6) km and km/s, covariances).
- OPM, Orbit Parameter Message (CCSDS 502.0-B-3 section 3), KVN: :func:`read_opm`, :func:`write_opm`;
  model :class:`Opm`.

Every model is a frozen dataclass (arrays read-only); build a changed copy with
``dataclasses.replace``. Epochs are the file's strings (``YYYY-MM-DDThh:mm:ss[.f]`` or
``YYYY-DDDThh:mm:ss[.f]``) in the segment's ``time_system`` ("UTC", "TAI", "TT", "GPS", "TDB").
Units: km, km/s, deg, Hz, s as the standards give them (:attr:`TdmSegment.units`).

A malformed file raises :class:`satgnc.FileFormatError` (a ``ValueError``) whose ``path``,
``line`` and ``key`` name the file, the line and the keyword; the C++ readers raise
``satgnc::io::FormatError`` with the same three. Writers refuse a model that would not read back
(``ValueError`` naming the field or the keyword).
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
from typing import Any, Callable, TypeVar

import numpy as np

from .. import _satgnc as _c
from .. import time as _time
from .._results import Result
from .._validate import FileFormatError, as_real_array, one_of, read_text_file

__all__ = [
    "TIME_SYSTEMS",
    "FileFormatError",
    "Header",
    "TdmMetadata",
    "TdmSegment",
    "Tdm",
    "OemMetadata",
    "OemCovariance",
    "OemSegment",
    "Oem",
    "OpmKeplerian",
    "OpmSpacecraft",
    "OpmManeuver",
    "Opm",
    "read_tdm",
    "parse_tdm",
    "format_tdm",
    "write_tdm",
    "read_oem",
    "parse_oem",
    "format_oem",
    "write_oem",
    "read_opm",
    "parse_opm",
    "format_opm",
    "write_opm",
    "format_oem_xml",
    "write_oem_xml",
    "format_opm_xml",
    "write_opm_xml",
    "epoch_seconds",
    "epochs_at",
]

TIME_SYSTEMS = ("UTC", "TAI", "TT", "GPS", "TDB")  #: TIME_SYSTEM values read and written

_M = TypeVar("_M")
_F = TypeVar("_F", bound=Callable[..., Any])


def _strings(value: Any, name: str) -> tuple[str, ...]:
    if isinstance(value, str) or not all(isinstance(v, str) for v in value):
        raise TypeError(f"{name}: must be a sequence of strings, got {type(value).__name__}")
    return tuple(value)


def _epochs(value: Any, name: str) -> tuple[str, ...]:
    """Epoch strings (checked by the C++ reader / writer); an empty one is refused here because the
    C++ writer would print its unset core::Epoch instead."""
    out = _strings(value, name)
    if any(not e.strip() for e in out):
        raise ValueError(f"{name}: epochs must not be empty strings")
    return out


def _set(obj: Any, **fields: Any) -> None:
    for k, v in fields.items():
        object.__setattr__(obj, k, v)


def _field_dict(obj: Any) -> dict[str, Any]:
    """The fields of a model dataclass as a dict (values as they are: the C++ side converts them)."""
    return {f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)}


def _require_model(value: Any, name: str, cls: type) -> None:
    if not isinstance(value, cls):
        raise TypeError(f"{name}: must be a satgnc.io.{cls.__name__}, got {type(value).__name__}")


def _checked_text(text: Any) -> str:
    if not isinstance(text, str):
        raise TypeError(f"text: must be a str, got {type(text).__name__}")
    return text


def _read_with(path: str | os.PathLike[str], parse: Callable[[str, str], _M]) -> _M:
    """``parse(text, path)`` of the text of the file at ``path``."""
    p, text = read_text_file(path)
    return parse(text, str(p))


def _write_text(path: str | os.PathLike[str], text: str) -> pathlib.Path:
    p = pathlib.Path(path)
    p.write_text(text, encoding="utf-8")
    return p


def _opt_float(value: Any, name: str) -> float | None:
    if value is None:
        return None
    return float(as_real_array(value, name, shape=()))


# The four entry points of each message type share their docstrings (numpy style), filled in per type.
_PARSE_DOC = """A :class:`{cls}` from {kind} ({enc}) text.

    Parameters
    ----------
    text : str
        The whole file's text.
    source : str, optional
        Name used in error messages (default ``"<string>"``).

    Returns
    -------
    {cls}
        {returns}

    Raises
    ------
    satgnc.FileFormatError
        A malformed message, naming ``source``, the line and the keyword.
    TypeError
        ``text`` is not a str.
    """

_READ_DOC = """Read a {kind} ({enc}) file.

    Parameters
    ----------
    path : str or os.PathLike
        The file to read (UTF-8).

    Returns
    -------
    {cls}
        {returns}

    Raises
    ------
    FileNotFoundError
        ``path`` does not exist.
    satgnc.FileFormatError
        A malformed file, naming the file, the line and the keyword.
    """

_FORMAT_DOC = """The {kind} text of ``{arg}`` ({enc}).

    Parameters
    ----------
    {arg} : {cls}
        The message to write (numbers in the shortest form that reads back to the same double; units in
        brackets after each dimensioned value).{format_param}

    Returns
    -------
    str
        The message text.

    Raises
    ------
    TypeError
        ``{arg}`` is not a :class:`{cls}`.
    ValueError
        A model that would not read back (e.g. a PATH naming an undefined participant){format_error}.
    """

_WRITE_DOC = """Write ``{arg}`` to ``path`` (:func:`format_{arg}`'s text).

    Parameters
    ----------
    path : str or os.PathLike
        The file to write (replaced if it exists).
    {arg} : {cls}
        The message.{format_param}

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    TypeError, ValueError
        As :func:`format_{arg}`.
    """

_FORMAT_PARAM = """
    format : {"kvn", "xml"}, optional
        The CCSDS encoding (keyword only; default ``"kvn"``)."""

_TDM_READER = {"kind": "TDM", "cls": "Tdm", "enc": "KVN or XML, told by a leading ``<``",
               "returns": "The parsed message: values in the units of their keywords "
                          "(km, km/s, deg, Hz, ...)."}
_OEM_READER = {"kind": "OEM", "cls": "Oem", "enc": "KVN",
               "returns": "The parsed message: states (n, 6) in km and km/s, accelerations km/s**2, "
                          "covariances km**2...."}
_OPM_READER = {"kind": "OPM", "cls": "Opm", "enc": "KVN",
               "returns": "The parsed message: state (6,) in km and km/s in ``ref_frame``, "
                          "covariance km**2...."}


def _doc(template: str, **fields: str) -> Callable[[_F], _F]:
    """Decorator: the function's docstring is ``template`` filled with ``fields``."""
    fields.setdefault("format_param", "")
    fields.setdefault("format_error", "")

    def deco(f: _F) -> _F:
        f.__doc__ = template.format(**fields)
        return f

    return deco


@dataclasses.dataclass(frozen=True)
class Header(Result):
    """The header of a TDM, OEM or OPM: ``CCSDS_xxx_VERS`` (``version``), ``CREATION_DATE``,
    ``ORIGINATOR``, optional ``MESSAGE_ID`` / ``CLASSIFICATION`` ("" when absent), COMMENT lines."""

    creation_date: str
    originator: str
    version: str = "2.0"
    message_id: str = ""
    classification: str = ""
    comments: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        _set(self, comments=_strings(self.comments, "comments"))
        super().__post_init__()


def epoch_seconds(epochs: Any, origin: str, time_system: str = "UTC") -> np.ndarray:
    """Seconds from ``origin`` to each epoch text, read by the C++ ``core::Epoch``.

    Leap seconds are counted: 2016-12-31T23:59:59 to 2017-01-01T00:00:00 UTC is 2 s. These are the times
    an OD or a propagation uses, from a file's epochs.

    Parameters
    ----------
    epochs : sequence of str
        ISO-8601 epoch texts (``YYYY-MM-DDThh:mm:ss[.f]`` or ``YYYY-DDDThh:mm:ss[.f]``).
    origin : str
        The epoch of t = 0, same format.
    time_system : str, optional
        The CCSDS time system both are read in (default ``"UTC"``; e.g. ``"TAI"``, ``"TT"``, ``"GPS"``).

    Returns
    -------
    numpy.ndarray
        (n,) float64, seconds (s) of SI time from ``origin``.

    Raises
    ------
    ValueError
        An unknown time system or a malformed epoch text.
    TypeError
        ``origin`` is not a str.
    """
    one_of(time_system, "time_system", TIME_SYSTEMS)
    if not isinstance(origin, str):
        raise TypeError(f"origin: must be an epoch string, got {type(origin).__name__}")
    return np.asarray(_c.io_epoch_seconds(list(_strings(epochs, "epochs")), origin, time_system))


def epochs_at(origin: str, seconds: Any, time_system: str = "UTC") -> tuple[str, ...]:
    """The epoch texts ``origin + seconds[i]`` in ``time_system``.

    ISO-8601 with up to 12 fraction digits, trailing zeros dropped; ``23:59:60.x`` inside a UTC leap
    second: the epochs of a propagated trajectory for :class:`OemSegment`.

    Parameters
    ----------
    origin : str
        The epoch of t = 0 (ISO-8601).
    seconds : float or array_like
        Times after ``origin`` (s), finite.
    time_system : str, optional
        The CCSDS time system (default ``"UTC"``).

    Returns
    -------
    tuple of str
        One epoch text per time.

    Raises
    ------
    ValueError
        An unknown time system, a malformed origin or a non-finite time.
    TypeError
        ``origin`` is not a str.
    """
    one_of(time_system, "time_system", TIME_SYSTEMS)
    if not isinstance(origin, str):
        raise TypeError(f"origin: must be an epoch string, got {type(origin).__name__}")
    s = np.atleast_1d(as_real_array(seconds, "seconds"))
    if s.ndim != 1:
        raise ValueError(f"seconds: must be one-dimensional, got shape {s.shape}")
    return tuple(_c.io_epochs_at(origin, s, time_system))


# ----------------------------------------------------------------------------------------------- TDM
@dataclasses.dataclass(frozen=True)
class TdmMetadata(Result):
    """A TDM metadata section. ``participants[i]`` is ``PARTICIPANT_{i+1}``; ``path`` the PATH as
    1-based participant indices (``(1, 2, 1)`` two-way, ``(2, 1)`` one-way down-leg) with
    ``mode="SEQUENTIAL"``; ``range_units`` "km" or "" (the standard's default km); ``angle_type``
    "AZEL", "RADEC" or ""; ``integration_interval`` in s or None; ``other`` every other metadata
    keyword (corrections, delays, bands, ...) as ``(keyword, value)`` text pairs, in file order."""

    time_system: str
    participants: tuple[str, ...]
    mode: str = ""
    path: tuple[int, ...] = ()
    start_time: str = ""
    stop_time: str = ""
    integration_interval: float | None = None
    integration_ref: str = ""
    range_units: str = ""
    angle_type: str = ""
    other: tuple[tuple[str, str], ...] = ()
    comments: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        one_of(self.time_system, "time_system", TIME_SYSTEMS)
        _set(
            self,
            participants=_strings(self.participants, "participants"),
            path=tuple(int(p) for p in self.path),
            integration_interval=_opt_float(self.integration_interval, "integration_interval"),
            other=tuple((str(k), str(v)) for k, v in self.other),
            comments=_strings(self.comments, "comments"),
        )
        super().__post_init__()


@dataclasses.dataclass(frozen=True)
class TdmSegment(Result):
    """A TDM segment: its metadata and its observations as parallel columns — ``keywords`` (e.g.
    "RANGE", "DOPPLER_INTEGRATED", "ANGLE_1"), ``epochs`` (time tags as in the file), ``values``
    (float64, in ``units``: km, km/s, deg, Hz, ...). Writers recompute ``units`` from the keywords."""

    metadata: TdmMetadata
    keywords: tuple[str, ...]
    epochs: tuple[str, ...]
    values: np.ndarray
    units: tuple[str, ...] = ()
    comments: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not isinstance(self.metadata, TdmMetadata):
            raise TypeError(f"metadata: must be a TdmMetadata, got {type(self.metadata).__name__}")
        kw = _strings(self.keywords, "keywords")
        ep = _epochs(self.epochs, "epochs")
        values = as_real_array(self.values, "values", ndim=1)
        if not len(kw) == len(ep) == values.shape[0]:
            raise ValueError(
                f"keywords, epochs, values: must have the same length, got {len(kw)}, {len(ep)}, "
                f"{values.shape[0]}"
            )
        units = _strings(self.units, "units") if self.units else ("",) * len(kw)
        _set(
            self,
            keywords=kw,
            epochs=ep,
            values=values,
            units=units,
            comments=_strings(self.comments, "comments"),
        )
        super().__post_init__()

    def seconds_since(self, origin: str) -> np.ndarray:
        """Seconds from ``origin`` (an epoch text in this segment's time system) to every
        observation (:func:`epoch_seconds`)."""
        return epoch_seconds(self.epochs, origin, self.metadata.time_system)

    def times(self) -> tuple[_time.Epoch, ...]:
        """The observations' time tags as :class:`satgnc.time.Epoch` instants (read in the
        segment's time system)."""
        return tuple(_time.parse(e, self.metadata.time_system) for e in self.epochs)

    def select(self, keyword: str) -> tuple[tuple[str, ...], np.ndarray]:
        """``(epochs, values)`` of the observations of one keyword, in file order."""
        idx = [i for i, k in enumerate(self.keywords) if k == keyword]
        return tuple(self.epochs[i] for i in idx), self.values[idx]


@dataclasses.dataclass(frozen=True)
class Tdm(Result):
    """A whole TDM: header and one or more segments."""

    header: Header
    segments: tuple[TdmSegment, ...]

    def __post_init__(self) -> None:
        _set(self, segments=tuple(self.segments))
        super().__post_init__()


def _header(d: dict[str, Any]) -> Header:
    return Header(**d)


def _tdm_from(d: dict[str, Any]) -> Tdm:
    segs = [
        TdmSegment(
            metadata=TdmMetadata(**s["metadata"]),
            keywords=s["keywords"],
            epochs=s["epochs"],
            values=s["values"],
            units=s["units"],
            comments=s["comments"],
        )
        for s in d["segments"]
    ]
    return Tdm(header=_header(d["header"]), segments=tuple(segs))


def _header_dict(h: Header) -> dict[str, Any]:
    _require_model(h, "header", Header)
    return _field_dict(h)


def _tdm_dict(t: Tdm) -> dict[str, Any]:
    _require_model(t, "tdm", Tdm)
    segs = []
    for s in t.segments:
        segs.append(
            {
                "metadata": _field_dict(s.metadata),
                "keywords": s.keywords,
                "epochs": s.epochs,
                "values": s.values,
                "units": s.units,
                "comments": s.comments,
            }
        )
    return {"header": _header_dict(t.header), "segments": segs}


@_doc(_PARSE_DOC, **_TDM_READER)
def parse_tdm(text: str, source: str = "<string>") -> Tdm:
    return _tdm_from(_c.io_parse_tdm(_checked_text(text), str(source)))


@_doc(_READ_DOC, **_TDM_READER)
def read_tdm(path: str | os.PathLike[str]) -> Tdm:
    return _read_with(path, parse_tdm)


@_doc(_FORMAT_DOC, kind="TDM", cls="Tdm", arg="tdm", enc="KVN or XML", format_param=_FORMAT_PARAM,
      format_error=", or an unknown format")
def format_tdm(tdm: Tdm, *, format: str = "kvn") -> str:  # noqa: A002 (the CCSDS word)
    one_of(format, "format", ("kvn", "xml"))
    return str(_c.io_format_tdm(_tdm_dict(tdm), format == "xml"))


@_doc(_WRITE_DOC, cls="Tdm", arg="tdm", format_param=_FORMAT_PARAM)
def write_tdm(path: str | os.PathLike[str], tdm: Tdm, *, format: str = "kvn") -> pathlib.Path:  # noqa: A002
    return _write_text(path, format_tdm(tdm, format=format))


# ----------------------------------------------------------------------------------------------- OEM
@dataclasses.dataclass(frozen=True)
class OemMetadata(Result):
    """OEM metadata; mandatory: object, center, ``ref_frame`` (e.g. "EME2000", "GCRF"), time system,
    ``start_time`` / ``stop_time``; the others "" or None when absent."""

    object_name: str
    object_id: str
    center_name: str
    ref_frame: str
    time_system: str
    start_time: str
    stop_time: str
    ref_frame_epoch: str = ""
    useable_start_time: str = ""
    useable_stop_time: str = ""
    interpolation: str = ""
    interpolation_degree: int | None = None
    comments: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        one_of(self.time_system, "time_system", TIME_SYSTEMS)
        _set(self, comments=_strings(self.comments, "comments"))
        super().__post_init__()


@dataclasses.dataclass(frozen=True)
class OemCovariance(Result):
    """A 6 x 6 state covariance (km**2, km**2/s, km**2/s**2) at ``epoch``; ``cov_ref_frame`` "" means
    the segment's REF_FRAME."""

    epoch: str
    matrix: np.ndarray
    cov_ref_frame: str = ""
    comments: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        _epochs((self.epoch,), "epoch")
        m = as_real_array(self.matrix, "matrix", shape=(6, 6))
        if not np.array_equal(m, m.T):
            raise ValueError("matrix: must be symmetric")
        _set(self, matrix=m, comments=_strings(self.comments, "comments"))
        super().__post_init__()


@dataclasses.dataclass(frozen=True)
class OemSegment(Result):
    """An OEM segment: ``epochs`` (n strings), ``states`` (n, 6) position km and velocity km/s,
    ``accelerations`` (n, 3) km/s**2 or None (NaN rows: lines without one), covariances."""

    metadata: OemMetadata
    epochs: tuple[str, ...]
    states: np.ndarray
    accelerations: np.ndarray | None = None
    covariances: tuple[OemCovariance, ...] = ()
    comments: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        ep = _epochs(self.epochs, "epochs")
        states = as_real_array(self.states, "states", shape=(len(ep), 6))
        acc = None
        if self.accelerations is not None:
            acc = as_real_array(self.accelerations, "accelerations", shape=(len(ep), 3), finite=False)
        _set(
            self,
            epochs=ep,
            states=states,
            accelerations=acc,
            covariances=tuple(self.covariances),
            comments=_strings(self.comments, "comments"),
        )
        super().__post_init__()

    def times(self) -> tuple[_time.Epoch, ...]:
        """The ephemeris epochs as :class:`satgnc.time.Epoch` instants (segment's time system)."""
        return tuple(_time.parse(e, self.metadata.time_system) for e in self.epochs)


@dataclasses.dataclass(frozen=True)
class Oem(Result):
    """A whole OEM: header and one or more segments."""

    header: Header
    segments: tuple[OemSegment, ...]

    def __post_init__(self) -> None:
        _set(self, segments=tuple(self.segments))
        super().__post_init__()


def _oem_from(d: dict[str, Any]) -> Oem:
    segs = []
    for s in d["segments"]:
        covs = tuple(OemCovariance(**c) for c in s["covariances"])
        segs.append(
            OemSegment(
                metadata=OemMetadata(**s["metadata"]),
                epochs=s["epochs"],
                states=s["states"],
                accelerations=s["accelerations"],
                covariances=covs,
                comments=s["comments"],
            )
        )
    return Oem(header=_header(d["header"]), segments=tuple(segs))


def _oem_dict(o: Oem) -> dict[str, Any]:
    _require_model(o, "oem", Oem)
    segs = []
    for s in o.segments:
        segs.append(
            {
                "metadata": _field_dict(s.metadata),
                "epochs": s.epochs,
                "states": s.states,
                "accelerations": s.accelerations,
                "covariances": [
                    {
                        "epoch": c.epoch,
                        "matrix": c.matrix,
                        "cov_ref_frame": c.cov_ref_frame,
                        "comments": c.comments,
                    }
                    for c in s.covariances
                ],
                "comments": s.comments,
            }
        )
    return {"header": _header_dict(o.header), "segments": segs}


@_doc(_PARSE_DOC, **_OEM_READER)
def parse_oem(text: str, source: str = "<string>") -> Oem:
    return _oem_from(_c.io_parse_oem(_checked_text(text), str(source)))


@_doc(_READ_DOC, **_OEM_READER)
def read_oem(path: str | os.PathLike[str]) -> Oem:
    return _read_with(path, parse_oem)


@_doc(_FORMAT_DOC, kind="OEM", cls="Oem", arg="oem", enc="KVN")
def format_oem(oem: Oem) -> str:
    return str(_c.io_format_oem(_oem_dict(oem)))


@_doc(_WRITE_DOC, cls="Oem", arg="oem")
def write_oem(path: str | os.PathLike[str], oem: Oem) -> pathlib.Path:
    return _write_text(path, format_oem(oem))


# ----------------------------------------------------------------------------------------------- OPM
@dataclasses.dataclass(frozen=True)
class OpmKeplerian(Result):
    """Osculating Keplerian elements: km, deg, km**3/s**2; exactly one of the two anomalies."""

    semi_major_axis: float
    eccentricity: float
    inclination: float
    ra_of_asc_node: float
    arg_of_pericenter: float
    gm: float
    true_anomaly: float | None = None
    mean_anomaly: float | None = None


@dataclasses.dataclass(frozen=True)
class OpmSpacecraft(Result):
    """Spacecraft parameters: mass kg, areas m**2, coefficients; None when absent."""

    mass: float | None = None
    solar_rad_area: float | None = None
    solar_rad_coeff: float | None = None
    drag_area: float | None = None
    drag_coeff: float | None = None


@dataclasses.dataclass(frozen=True)
class OpmManeuver(Result):
    """A maneuver: ignition epoch, duration s, delta mass kg (<= 0), frame, delta-v (3,) km/s."""

    epoch_ignition: str
    duration: float
    delta_mass: float
    ref_frame: str
    dv: tuple[float, float, float]
    comments: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        _epochs((self.epoch_ignition,), "epoch_ignition")
        dv = as_real_array(self.dv, "dv", shape=(3,))
        _set(self, dv=tuple(float(x) for x in dv), comments=_strings(self.comments, "comments"))
        super().__post_init__()


@dataclasses.dataclass(frozen=True)
class Opm(Result):
    """A whole OPM: state vector (6,) km and km/s at ``epoch`` in ``ref_frame``, optional Keplerian
    elements, spacecraft parameters, covariance (6, 6) and maneuvers."""

    header: Header
    object_name: str
    object_id: str
    center_name: str
    ref_frame: str
    time_system: str
    epoch: str
    state: np.ndarray
    ref_frame_epoch: str = ""
    keplerian: OpmKeplerian | None = None
    spacecraft: OpmSpacecraft | None = None
    covariance: np.ndarray | None = None
    cov_ref_frame: str = ""
    maneuvers: tuple[OpmManeuver, ...] = ()
    user_defined: tuple[tuple[str, str], ...] = ()
    metadata_comments: tuple[str, ...] = ()
    comments: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        one_of(self.time_system, "time_system", TIME_SYSTEMS)
        _epochs((self.epoch,), "epoch")
        cov = None
        if self.covariance is not None:
            cov = as_real_array(self.covariance, "covariance", shape=(6, 6))
            if not np.array_equal(cov, cov.T):
                raise ValueError("covariance: must be symmetric")
        _set(
            self,
            state=as_real_array(self.state, "state", shape=(6,)),
            covariance=cov,
            maneuvers=tuple(self.maneuvers),
            user_defined=tuple((str(k), str(v)) for k, v in self.user_defined),
            metadata_comments=_strings(self.metadata_comments, "metadata_comments"),
            comments=_strings(self.comments, "comments"),
        )
        super().__post_init__()


def _opm_from(d: dict[str, Any]) -> Opm:
    d = dict(d)
    d["header"] = _header(d["header"])
    d["keplerian"] = OpmKeplerian(**d["keplerian"]) if d["keplerian"] is not None else None
    d["spacecraft"] = OpmSpacecraft(**d["spacecraft"]) if d["spacecraft"] is not None else None
    d["maneuvers"] = tuple(OpmManeuver(**m) for m in d["maneuvers"])
    return Opm(**d)


def _opm_dict(o: Opm) -> dict[str, Any]:
    _require_model(o, "opm", Opm)
    d = _field_dict(o)
    d["header"] = _header_dict(o.header)
    d["keplerian"] = dataclasses.asdict(o.keplerian) if o.keplerian is not None else None
    d["spacecraft"] = dataclasses.asdict(o.spacecraft) if o.spacecraft is not None else None
    d["maneuvers"] = [_field_dict(m) for m in o.maneuvers]
    return d


@_doc(_PARSE_DOC, **_OPM_READER)
def parse_opm(text: str, source: str = "<string>") -> Opm:
    return _opm_from(_c.io_parse_opm(_checked_text(text), str(source)))


@_doc(_READ_DOC, **_OPM_READER)
def read_opm(path: str | os.PathLike[str]) -> Opm:
    return _read_with(path, parse_opm)


@_doc(_FORMAT_DOC, kind="OPM", cls="Opm", arg="opm", enc="KVN")
def format_opm(opm: Opm) -> str:
    return str(_c.io_format_opm(_opm_dict(opm)))


@_doc(_WRITE_DOC, cls="Opm", arg="opm")
def write_opm(path: str | os.PathLike[str], opm: Opm) -> pathlib.Path:
    return _write_text(path, format_opm(opm))


_FORMAT_XML_DOC = """The {kind} text of ``{arg}`` in XML (CCSDS NDM/XML 2.0{elements}).

    :func:`parse_{arg}` and :func:`read_{arg}` read it back (they tell XML by its first character), to the
    same model bit for bit.

    Parameters
    ----------
    {arg} : {cls}
        The message to write (numbers in the shortest form that reads back to the same double; {units}).

    Returns
    -------
    str
        The XML text.

    Raises
    ------
    TypeError
        ``{arg}`` is not a :class:`{cls}`.
    ValueError
        A model that would not read back.
    """

_WRITE_XML_DOC = """Write ``{arg}`` to ``path`` in XML (:func:`format_{arg}_xml`'s text).

    Parameters
    ----------
    path : str or os.PathLike
        The file to write (replaced if it exists).
    {arg} : {cls}
        The message.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    TypeError, ValueError
        As :func:`format_{arg}_xml`.
    """


@_doc(_FORMAT_XML_DOC, kind="OEM", arg="oem", cls="Oem",
      elements=": ``<stateVector>``, ``<covarianceMatrix>``", units="km, km/s,\n        km/s**2, km**2....")
def format_oem_xml(oem: Oem) -> str:
    return str(_c.io_format_oem_xml(_oem_dict(oem)))


@_doc(_WRITE_XML_DOC, arg="oem", cls="Oem")
def write_oem_xml(path: str | os.PathLike[str], oem: Oem) -> pathlib.Path:
    return _write_text(path, format_oem_xml(oem))


@_doc(_FORMAT_XML_DOC, kind="OPM", arg="opm", cls="Opm", elements=", ``<opm>``",
      units="km, km/s,\n        kg, m**2, km**2....")
def format_opm_xml(opm: Opm) -> str:
    return str(_c.io_format_opm_xml(_opm_dict(opm)))


@_doc(_WRITE_XML_DOC, arg="opm", cls="Opm")
def write_opm_xml(path: str | os.PathLike[str], opm: Opm) -> pathlib.Path:
    return _write_text(path, format_opm_xml(opm))


from .._namespace import public_dir as _public_dir  # noqa: E402

__dir__ = _public_dir(__name__)  # dir(): the API, not the imported modules (np, math, ...)
