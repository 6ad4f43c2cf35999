"""CCSDS Tracking Data Message (TDM, CCSDS 503.0-B) reader and writer, KVN only, a documented subset.

Supported:
- header: ``CCSDS_TDM_VERS`` (1.0 or 2.0, must be the first keyword), then the other header keywords
  of the standard (CLASSIFICATION, CREATION_DATE, ORIGINATOR, MESSAGE_ID; read and not used);
  ``COMMENT`` lines anywhere; blank lines; UTF-8 with or without a byte-order mark, LF or CRLF;
- one or more ``META_START``/``META_STOP`` + ``DATA_START``/``DATA_STOP`` segments;
- metadata: ``TIME_SYSTEM`` (required, must be UTC), ``PARTICIPANT_1`` (required: the station; its
  name maps to a station), ``RANGE_UNITS`` (must be km if present); the other metadata keywords of
  the standard are read and not used, except corrections and delays, which must be zero (or the
  corrections flagged ``CORRECTIONS_APPLIED = YES``) because this reader applies none;
- data: ``RANGE = <epoch> <value km>`` (> 0) and ``DOPPLER_INSTANTANEOUS = <epoch> <value km/s>``
  (instantaneous range-rate); epochs ``YYYY-MM-DDThh:mm:ss[.f]`` or ``YYYY-DDDThh:mm:ss[.f]``.
Anything else (ANGLE_1, RECEIVE_FREQ, an unknown or misspelt keyword, ...) is a
:class:`satgnc.FileFormatError` naming the file, the line and the keyword: data this reader cannot
interpret are not silently dropped. TDM carries no per-observation sigma; the caller supplies one per
type.
"""

from __future__ import annotations

import datetime as _dt
import pathlib
import re

import numpy as np

from . import MeasurementType, Observations

_KV = re.compile(r"^\s*([A-Z0-9_]+)\s*=\s*(.*?)\s*$")


def parse_epoch(text: str) -> _dt.datetime:
    """A TDM epoch (calendar or day-of-year form), as a naive UTC datetime.

    Parameters
    ----------
    text : str
        ``YYYY-MM-DDThh:mm:ss[.f]`` or ``YYYY-DDDThh:mm:ss[.f]`` (UTC; a trailing Z allowed).

    Returns
    -------
    datetime.datetime
        Naive, UTC (seconds, s, to a resolution of 1 us).

    Raises
    ------
    ValueError
        Another form, a day beyond the year, or a leap second (:60).
    TypeError
        ``text`` not a str.

    Examples
    --------
    >>> from satgnc.od.tdm import parse_epoch
    >>> parse_epoch("2023-056T00:00:30.5")
    datetime.datetime(2023, 2, 25, 0, 0, 30, 500000)
    """
    if not isinstance(text, str):  # was AttributeError: 'int' object has no attribute 'strip'
        raise TypeError(f"text: must be an epoch string (YYYY-MM-DDThh:mm:ss), got {type(text).__name__}")
    try:
        return _parse_epoch(text)
    except ValueError as e:  # "bad epoch 'x'" did not name the argument
        raise ValueError(f"text: {e}") from None


def _parse_epoch(text: str) -> _dt.datetime:
    """parse_epoch without the argument's name in its errors (the file readers add file and line)."""
    s = text.strip().rstrip("Z")
    if re.search(r"T\d\d:\d\d:60", s):
        raise ValueError(f"epoch {text!r} is a leap second (not supported: UTC is read without leap seconds)")
    for fmt in ("%Y-%m-%dT%H:%M:%S.%f", "%Y-%m-%dT%H:%M:%S", "%Y-%jT%H:%M:%S.%f", "%Y-%jT%H:%M:%S"):
        try:
            when = _dt.datetime.strptime(s, fmt)
        except ValueError:
            continue
        if "%j" in fmt and when.year != int(s[:4]):  # strptime rolls day 366 of a common year over
            raise ValueError(f"bad epoch {text!r}: {s[:4]} has no day {s[5:8]}")
        return when
    raise ValueError(f"bad epoch {text!r} (hint: YYYY-MM-DDThh:mm:ss or YYYY-DDDThh:mm:ss)")


# KVN keywords of CCSDS 503.0-B-2. Header and metadata keywords not listed are errors (a typo must
# not be dropped silently); listed ones this reader does not model are accepted when they cannot
# change the meaning of RANGE and DOPPLER_INSTANTANEOUS values.
_HEADER_KEYS = {"CCSDS_TDM_VERS", "CLASSIFICATION", "CREATION_DATE", "ORIGINATOR", "MESSAGE_ID"}
_META_KEYS = {
    "TRACK_ID", "DATA_TYPES", "TIME_SYSTEM", "START_TIME", "STOP_TIME", "MODE", "PATH", "PATH_1",
    "PATH_2", "TRANSMIT_BAND", "RECEIVE_BAND", "TURNAROUND_NUMERATOR", "TURNAROUND_DENOMINATOR",
    "TIMETAG_REF", "INTEGRATION_INTERVAL", "INTEGRATION_REF", "FREQ_OFFSET", "RANGE_MODE",
    "RANGE_MODULUS", "RANGE_UNITS", "ANGLE_TYPE", "REFERENCE_FRAME", "INTERPOLATION",
    "INTERPOLATION_DEGREE", "DOPPLER_COUNT_BIAS", "DOPPLER_COUNT_SCALE", "DOPPLER_COUNT_ROLLOVER",
    "DATA_QUALITY", "CORRECTION_ANGLE_1", "CORRECTION_ANGLE_2", "CORRECTION_DOPPLER", "CORRECTION_MAG",
    "CORRECTION_RANGE", "CORRECTION_RCS", "CORRECTION_RECEIVE", "CORRECTION_TRANSMIT",
    "CORRECTION_ABERRATION_YEARLY", "CORRECTION_ABERRATION_DIURNAL", "CORRECTIONS_APPLIED",
    *(f"{k}_{i}" for k in ("PARTICIPANT", "EPHEMERIS_NAME", "TRANSMIT_DELAY", "RECEIVE_DELAY")
      for i in range(1, 6)),
}
# Corrections and delays shift the values; this reader applies none, so non-zero ones are errors.
_MUST_BE_ZERO = ("CORRECTION_RANGE", "CORRECTION_DOPPLER",
                 *(f"{k}_{i}" for k in ("TRANSMIT_DELAY", "RECEIVE_DELAY") for i in range(1, 6)))


def _as_epoch(epoch) -> _dt.datetime:
    """The ``epoch`` argument as a naive UTC datetime, or an error naming ``epoch``."""
    if isinstance(epoch, _dt.datetime):
        if epoch.tzinfo is not None:
            epoch = epoch.astimezone(_dt.timezone.utc).replace(tzinfo=None)
        return epoch
    if isinstance(epoch, str):
        try:
            return _parse_epoch(epoch)
        except ValueError:
            pass
        try:
            return _as_epoch(_dt.datetime.fromisoformat(epoch.strip().replace("Z", "+00:00")))
        except ValueError:
            raise ValueError(
                f"epoch: not a UTC date-time: {epoch!r} (hint: YYYY-MM-DDThh:mm:ss or YYYY-DDDThh:mm:ss)"
            ) from None
    raise TypeError(f"epoch: must be None, a datetime or an ISO string, got {type(epoch).__name__}")


def read_tdm(path, sigma_range: float = 1e-3, sigma_range_rate: float = 1e-6, epoch=None):
    """Read a KVN TDM (RANGE and DOPPLER_INSTANTANEOUS) as :class:`satgnc.od.Observations`.

    Parameters
    ----------
    path : str or os.PathLike
        The TDM file.
    sigma_range : float, optional
        Sigma given to every range (km; default 1e-3).
    sigma_range_rate : float, optional
        Sigma given to every range-rate (km/s; default 1e-6).
    epoch : datetime.datetime or str, optional
        UTC epoch of t = 0 (default: the first observation).

    Returns
    -------
    observations : Observations
        Times in s after ``epoch``, values km and km/s; station indices follow ``station_names``.
    station_names : list of str
        PARTICIPANT_1 names in order of first appearance.
    epoch : datetime.datetime
        The epoch of t = 0 (naive UTC).

    Raises
    ------
    satgnc.FileFormatError
        (a ``ValueError``) reading ``"<file>:<line>: ..."`` and naming the keyword: a keyword outside
        its section or unknown to TDM (with a suggestion), a segment without TIME_SYSTEM or
        PARTICIPANT_1, a repeated metadata keyword, a non-zero correction or delay (not applied by
        this reader), a bad epoch, a non-finite value, a range <= 0, and two observations with the
        same epoch, type and station (both lines named).
    TypeError
        An ``epoch`` of another type.

    Examples
    --------
    >>> import datetime
    >>> from satgnc import od
    >>> from satgnc.od.tdm import read_tdm, write_tdm
    >>> obs = od.Observations([0.0, 60.0], "range", [1321.104, 953.7183], 1e-3, 0)
    >>> _ = write_tdm("pass.tdm", obs, datetime.datetime(1981, 3, 21, 6), ["STATION"])
    >>> back, names, epoch = read_tdm("pass.tdm")
    >>> back.t.tolist(), names, epoch.isoformat()
    ([0.0, 60.0], ['STATION'], '1981-03-21T06:00:00')
    """
    from .._validate import FileFormatError, as_real, did_you_mean, read_text_file

    sigma_range = as_real(sigma_range, "sigma_range", positive=True)
    sigma_range_rate = as_real(sigma_range_rate, "sigma_range_rate", positive=True)
    if epoch is not None:
        epoch = _as_epoch(epoch)
    p, text = read_text_file(path)
    state = "header"
    seen_version = False
    header_seen: dict[str, int] = {}
    station = None
    meta: dict[str, tuple[int, str]] = {}  # keyword -> (line, value), per segment
    names: list[str] = []
    rows = []  # (datetime, type, value, station)
    seen: dict[tuple, int] = {}
    lines = text.splitlines()
    for lineno, raw in enumerate(lines, start=1):
        line = raw.strip()

        def fail(reason: str, key: str | None = None, lineno=lineno):
            raise FileFormatError(p, lineno, reason, key=key)

        if not line or line.startswith("COMMENT"):
            continue
        if line in ("META_START", "META_STOP", "DATA_START", "DATA_STOP"):
            expected = {
                "META_START": ("header", "after_data"),
                "META_STOP": ("meta",),
                "DATA_START": ("after_meta",),
                "DATA_STOP": ("data",),
            }[line]
            if line == "META_START" and not seen_version:
                fail("CCSDS_TDM_VERS must come first", "CCSDS_TDM_VERS")
            if state not in expected:
                fail(f"unexpected {line} (after {state.replace('_', ' ')})", line)
            if line == "META_STOP":
                for need in ("TIME_SYSTEM", "PARTICIPANT_1"):
                    if need not in meta:
                        fail(f"metadata without {need}", need)
                applied = meta.get("CORRECTIONS_APPLIED", (0, "NO"))[1].upper() == "YES"
                for k in _MUST_BE_ZERO:
                    if k in meta and float(meta[k][1]) != 0.0 and not (applied and k.startswith("CORR")):
                        fail(f"{k} = {meta[k][1]} is not supported: this reader applies no correction "
                             "or delay (hint: apply it and set CORRECTIONS_APPLIED = YES, or remove it)",
                             k, meta[k][0])
            state = {
                "META_START": "meta",
                "META_STOP": "after_meta",
                "DATA_START": "data",
                "DATA_STOP": "after_data",
            }[line]
            if line == "META_START":
                station = None
                meta = {}
            continue
        m = _KV.match(line)
        if not m:
            low = re.match(r"^\s*([A-Za-z0-9_]+)\s*=", line)
            if low:
                fail(f"keyword {low.group(1)!r} must be upper case ({low.group(1).upper()})", low.group(1))
            fail(f"malformed line {raw.strip()!r} (hint: KEYWORD = value)")
        key, val = m.group(1), m.group(2)
        if state == "header":
            if key in header_seen:
                fail(f"{key} repeated in the header (also line {header_seen[key]})", key)
            header_seen[key] = lineno
            if key == "CCSDS_TDM_VERS":
                if not re.fullmatch(r"[12]\.0", val):
                    fail(f"CCSDS_TDM_VERS: unsupported version {val!r} (hint: 1.0 or 2.0)", key)
                seen_version = True
            elif not seen_version:
                fail("CCSDS_TDM_VERS must come first", "CCSDS_TDM_VERS")
            elif key not in _HEADER_KEYS:
                fail(f"unknown header keyword {key}{did_you_mean(key, _HEADER_KEYS, '{}')}", key)
            continue
        if state == "meta":
            if key not in _META_KEYS:
                fail(f"unknown metadata keyword {key}{did_you_mean(key, _META_KEYS, '{}')}", key)
            if key in meta:
                fail(f"{key} repeated in one metadata section (also line {meta[key][0]})", key)
            meta[key] = (lineno, val)
            if key == "TIME_SYSTEM" and val.upper() != "UTC":
                fail(f"TIME_SYSTEM {val} not supported (hint: UTC)", key)
            if key == "RANGE_UNITS" and val.lower() != "km":
                fail(f"RANGE_UNITS {val} not supported (hint: km)", key)
            if key in _MUST_BE_ZERO:
                try:
                    float(val)
                except ValueError:
                    fail(f"{key}: not a number: {val!r}", key)
            if key == "CORRECTIONS_APPLIED" and val.upper() not in ("YES", "NO"):
                fail(f"CORRECTIONS_APPLIED must be YES or NO, got {val!r}", key)
            if key == "PARTICIPANT_1":
                if not val:
                    fail("PARTICIPANT_1 must name the station", key)
                station = val
                if val not in names:
                    names.append(val)
            continue
        if state != "data":
            fail(f"keyword {key} outside a META or DATA section", key)
        if key not in ("RANGE", "DOPPLER_INSTANTANEOUS"):
            fail(f"data keyword {key} not supported (hint: RANGE, DOPPLER_INSTANTANEOUS)", key)
        parts = val.split()
        if len(parts) != 2:
            fail(f"{key}: expected '<epoch> <value>', got {val!r}", key)
        try:
            when = _parse_epoch(parts[0])
        except ValueError as e:
            fail(f"{key}: {e}", key)
        try:
            value = float(parts[1])
        except ValueError:
            fail(f"{key}: value is not a number: {parts[1]!r}", key)
        if not np.isfinite(value):
            fail(f"{key}: value must be finite, got {parts[1]!r}", key)
        if key == "RANGE" and not value > 0:
            fail(f"RANGE: must be > 0 km, got {parts[1]}", key)
        kind = MeasurementType.range if key == "RANGE" else MeasurementType.range_rate
        k = (when, key, station)
        if k in seen:
            fail(f"duplicate {key} at {parts[0]} for {station} (also line {seen[k]})", key)
        seen[k] = lineno
        rows.append((when, kind, value, names.index(station)))
    if state != "after_data":
        hint = {"header": "no META_START", "meta": "no META_STOP", "after_meta": "no DATA_START",
                "data": "no DATA_STOP"}[state]
        raise FileFormatError(p, len(lines) or None, f"incomplete file: {hint} (hint: end with DATA_STOP)")
    if not rows:
        raise FileFormatError(p, None, "no RANGE or DOPPLER_INSTANTANEOUS data")
    if epoch is None:
        epoch = min(r[0] for r in rows)
    t = [(r[0] - epoch).total_seconds() for r in rows]
    kinds = [r[1] for r in rows]
    sig = [sigma_range if k == MeasurementType.range else sigma_range_rate for k in kinds]
    obs = Observations(t, kinds, [r[2] for r in rows], sig, [r[3] for r in rows])
    return obs, names, epoch


def write_tdm(
    path,
    observations: Observations,
    epoch: _dt.datetime,
    station_names: list[str],
    originator: str = "satgnc",
) -> pathlib.Path:
    """Write observations as a KVN TDM, one segment per station.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write.
    observations : Observations
        Times in s after ``epoch``; values km and km/s.
    epoch : datetime.datetime
        UTC epoch of t = 0 (naive = UTC).
    station_names : list of str
        ``station_names[i]`` names station index i (PARTICIPANT_1): every index used has a name (no
        observation is dropped), names are unique, non-empty and fit on a KVN line.
    originator : str, optional
        The ORIGINATOR line (default "satgnc").

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    ValueError
        A missing, repeated or invalid station name, or a bad originator.
    TypeError
        ``observations``, ``epoch`` or ``station_names`` of another type.

    Examples
    --------
    >>> import datetime
    >>> from satgnc import od
    >>> from satgnc.od.tdm import write_tdm
    >>> obs = od.Observations([0.0, 60.0], "range_rate", [-6.35643, -5.79697], 1e-6, 0)
    >>> write_tdm("doppler.tdm", obs, datetime.datetime(1981, 3, 21, 6), ["STATION"]).name
    'doppler.tdm'
    """
    if not isinstance(observations, Observations):
        raise TypeError(f"observations: must be an Observations table, got {type(observations).__name__}")
    if not isinstance(epoch, _dt.datetime):
        raise TypeError(f"epoch: must be a datetime (UTC), got {type(epoch).__name__}")
    if epoch.tzinfo is not None:
        epoch = epoch.astimezone(_dt.timezone.utc).replace(tzinfo=None)
    if isinstance(station_names, str) or not all(isinstance(n, str) for n in station_names):
        raise TypeError("station_names: must be a list of names (str)")
    station_names = list(station_names)
    for n in station_names:
        if not n.strip() or n != n.strip() or any(c in n for c in "\r\n="):
            raise ValueError(f"station_names: {n!r} is not a valid PARTICIPANT_1 value")
    if len(set(station_names)) != len(station_names):
        raise ValueError(f"station_names: names must be unique, got {station_names}")
    if len(observations) and int(np.max(observations.station)) >= len(station_names):
        raise ValueError(
            f"station_names: observations use station index {int(np.max(observations.station))}, "
            f"only {len(station_names)} name(s) given"
        )
    if not isinstance(originator, str) or not originator.strip() or "\n" in originator:
        raise ValueError(f"originator: must be a one-line non-empty string, got {originator!r}")
    p = pathlib.Path(path)
    lines = [
        "CCSDS_TDM_VERS = 2.0",
        f"CREATION_DATE = {_dt.datetime.now(_dt.timezone.utc):%Y-%m-%dT%H:%M:%S}",
        f"ORIGINATOR = {originator}",
    ]
    for i, name in enumerate(station_names):
        sel = observations.station == i
        if not np.any(sel):
            continue
        lines += [
            "META_START",
            "TIME_SYSTEM = UTC",
            f"PARTICIPANT_1 = {name}",
            "PARTICIPANT_2 = SATELLITE",
            "MODE = SEQUENTIAL",
            "PATH = 1,2,1",
            "RANGE_UNITS = km",
            "META_STOP",
            "DATA_START",
        ]
        for t, k, v in zip(
            observations.t[sel], np.array(observations.type, dtype=object)[sel], observations.value[sel]
        ):
            when = epoch + _dt.timedelta(seconds=float(t))
            key = "RANGE" if k == MeasurementType.range else "DOPPLER_INSTANTANEOUS"
            lines.append(f"{key} = {when:%Y-%m-%dT%H:%M:%S.%f} {v:.12e}")
        lines.append("DATA_STOP")
    p.write_text("\n".join(lines) + "\n")
    return p
