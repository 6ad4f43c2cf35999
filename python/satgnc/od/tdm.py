"""CCSDS Tracking Data Message (TDM, CCSDS 503.0-B) reader and writer, KVN only, a documented subset.

Supported:
- header: ``CCSDS_TDM_VERS`` (must be the first keyword), other header keywords ignored; ``COMMENT``
  lines anywhere; blank lines;
- one or more ``META_START``/``META_STOP`` + ``DATA_START``/``DATA_STOP`` segments;
- metadata: ``TIME_SYSTEM`` (must be UTC), ``PARTICIPANT_1`` (the station; its name maps to a station),
  ``RANGE_UNITS`` (must be km if present); other metadata keywords are ignored;
- data: ``RANGE = <epoch> <value km>`` and ``DOPPLER_INSTANTANEOUS = <epoch> <value km/s>``
  (instantaneous range-rate); epochs ``YYYY-MM-DDThh:mm:ss[.f]`` or ``YYYY-DDDThh:mm:ss[.f]``.
Anything else in a data section (ANGLE_1, RECEIVE_FREQ, ...) is an error naming the line: data this
reader cannot interpret are not silently dropped. TDM carries no per-observation sigma; the caller
supplies one per type.
"""

from __future__ import annotations

import datetime as _dt
import pathlib
import re

import numpy as np

from . import MeasurementType, Observations

_KV = re.compile(r"^\s*([A-Z0-9_]+)\s*=\s*(.*?)\s*$")


def parse_epoch(text: str) -> _dt.datetime:
    """A TDM epoch (calendar or day-of-year form), as a naive UTC datetime."""
    s = text.strip().rstrip("Z")
    for fmt in ("%Y-%m-%dT%H:%M:%S.%f", "%Y-%m-%dT%H:%M:%S", "%Y-%jT%H:%M:%S.%f", "%Y-%jT%H:%M:%S"):
        try:
            return _dt.datetime.strptime(s, fmt)
        except ValueError:
            continue
    raise ValueError(f"bad epoch {text!r} (hint: YYYY-MM-DDThh:mm:ss or YYYY-DDDThh:mm:ss)")


def read_tdm(path, sigma_range: float = 1e-3, sigma_range_rate: float = 1e-6, epoch=None):
    """Read a KVN TDM. Returns ``(observations, station_names, epoch)``: times are seconds after
    ``epoch`` (default: the first observation), station indices follow ``station_names`` (order of
    first appearance of PARTICIPANT_1). Errors are ValueError("<file>:<line>: ...")."""
    p = pathlib.Path(path)
    if not p.exists():
        raise FileNotFoundError(f"path: {p} does not exist")
    for name, v in (("sigma_range", sigma_range), ("sigma_range_rate", sigma_range_rate)):
        if not (isinstance(v, (int, float)) and np.isfinite(v) and v > 0):
            raise ValueError(f"{name}: must be finite and > 0, got {v!r}")
    state = "header"
    seen_version = False
    station = None
    names: list[str] = []
    rows = []  # (datetime, type, value, station)
    for lineno, raw in enumerate(p.read_text().splitlines(), start=1):
        line = raw.strip()
        where = f"{p}:{lineno}"
        if not line or line.startswith("COMMENT"):
            continue
        if line in ("META_START", "META_STOP", "DATA_START", "DATA_STOP"):
            expected = {
                "META_START": ("header", "after_data"),
                "META_STOP": ("meta",),
                "DATA_START": ("after_meta",),
                "DATA_STOP": ("data",),
            }[line]
            if state not in expected:
                raise ValueError(f"{where}: unexpected {line}")
            if line == "META_START" and not seen_version:
                raise ValueError(f"{where}: CCSDS_TDM_VERS must come first")
            if line == "META_STOP" and station is None:
                raise ValueError(f"{where}: metadata without PARTICIPANT_1")
            state = {
                "META_START": "meta",
                "META_STOP": "after_meta",
                "DATA_START": "data",
                "DATA_STOP": "after_data",
            }[line]
            if line == "META_START":
                station = None
            continue
        m = _KV.match(line)
        if not m:
            raise ValueError(f"{where}: malformed line {raw!r} (hint: KEYWORD = value)")
        key, val = m.group(1), m.group(2)
        if state == "header":
            if key == "CCSDS_TDM_VERS":
                seen_version = True
            elif not seen_version:
                raise ValueError(f"{where}: CCSDS_TDM_VERS must come first")
            continue
        if state == "meta":
            if key == "TIME_SYSTEM" and val.upper() != "UTC":
                raise ValueError(f"{where}: TIME_SYSTEM {val} not supported (hint: UTC)")
            if key == "RANGE_UNITS" and val.lower() != "km":
                raise ValueError(f"{where}: RANGE_UNITS {val} not supported (hint: km)")
            if key == "PARTICIPANT_1":
                station = val
                if val not in names:
                    names.append(val)
            continue
        if state != "data":
            raise ValueError(f"{where}: keyword {key} outside a META or DATA section")
        if key not in ("RANGE", "DOPPLER_INSTANTANEOUS"):
            raise ValueError(
                f"{where}: data keyword {key} not supported (hint: RANGE, DOPPLER_INSTANTANEOUS)"
            )
        parts = val.split()
        if len(parts) != 2:
            raise ValueError(f"{where}: expected '<epoch> <value>', got {val!r}")
        try:
            when = parse_epoch(parts[0])
            value = float(parts[1])
        except ValueError as e:
            raise ValueError(f"{where}: {e}") from None
        if not np.isfinite(value):
            raise ValueError(f"{where}: value must be finite")
        kind = MeasurementType.range if key == "RANGE" else MeasurementType.range_rate
        rows.append((when, kind, value, names.index(station)))
    if state not in ("after_data",):
        raise ValueError(f"{p}: incomplete file (state {state}; hint: end with DATA_STOP)")
    if not rows:
        raise ValueError(f"{p}: no RANGE or DOPPLER_INSTANTANEOUS data")
    if epoch is None:
        epoch = min(r[0] for r in rows)
    elif isinstance(epoch, str):
        epoch = parse_epoch(epoch) if "T" in epoch and "-" in epoch[:5] else _dt.datetime.fromisoformat(epoch)
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
    """Write observations (times relative to ``epoch``) as a KVN TDM, one segment per station."""
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
