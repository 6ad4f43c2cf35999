"""Ground stations of the ``satgnc od`` TDM commands (``od batch`` and ``od filter`` share them).

Coordinates come from ``--stations FILE`` (TOML: one table per participant with ``latitude`` deg,
``longitude`` deg east, ``height`` km; or CSV ``name,latitude_deg,longitude_deg,height_km``) and
``--station NAME:lat,lon,h`` (overrides the file). The station model of both commands:

- ``itrf`` (default): WGS-84 geodetic stations fixed in the ITRF, carried to GCRF by IAU 2006/2000A with
  EOP (``--eop`` file, finals2000A or EOP 20 C04; default the astropy-iers-data table), 1 h
  interpolation grid of :class:`satgnc.frames.IauEarthRotation` over the data span plus one hour;
- ``paper``: the Gao-Luo paper's station, its inertial position at the epoch from GMST (IAU 1982, UT1 =
  UTC) rotating about +z at the Earth's rate (no precession, nutation or polar motion: 21.7 km off the
  IAU chain in 2016, docs/od.md), for reproductions only.
"""

from __future__ import annotations

import csv
import datetime as _dt
import math
import os
import pathlib
import re
from typing import Any

#: Station models of the TDM commands.
STATION_MODELS = ("itrf", "paper")

_STATION_KEYS = ("latitude", "longitude", "height")
_CSV_HEADER = ("name", "latitude_deg", "longitude_deg", "height_km")


def floats(text: str, n: int, name: str) -> list[float]:
    """``n`` finite comma-separated numbers of an option; ValueError naming it."""
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise ValueError(f"{name}: expected {n} comma-separated numbers, got {text!r}") from None
    if len(vals) != n or not all(math.isfinite(v) for v in vals):
        raise ValueError(f"{name}: expected {n} finite comma-separated numbers, got {text!r}")
    return vals


def _check_site(lat: float, lon: float, h: float, where: str) -> None:
    if not -90.0 <= lat <= 90.0:
        raise ValueError(f"{where}: latitude {lat} deg outside [-90, 90]")
    if not -360.0 <= lon <= 360.0:
        raise ValueError(f"{where}: longitude {lon} deg outside [-360, 360]")
    if not -0.5 <= h <= 9.0:  # km: below the Dead Sea shore or above Everest is not a ground station
        raise ValueError(f"{where}: height {h} km outside [-0.5, 9] (hint: km above the WGS-84 ellipsoid)")


def _key_line(text: str, section: str, key: str | None) -> int | None:
    """1-based line of ``key`` inside ``[section]`` of a TOML text (of the header when key is None)."""
    inside = False
    for i, line in enumerate(text.splitlines(), 1):
        s = line.split("#", 1)[0].strip()
        m = re.fullmatch(r"\[\s*\"?([^\]\"]+)\"?\s*\]", s)
        if m:
            inside = m.group(1).strip() == section
            if inside and key is None:
                return i
            continue
        if inside and key is not None and re.match(rf"\"?{re.escape(key)}\"?\s*=", s):
            return i
    return None


def read_stations(path: str | os.PathLike[str]) -> dict[str, tuple[float, float, float]]:
    """Stations of a TOML or CSV file: {participant name: (latitude deg, longitude deg, height km)}.
    Errors are :class:`satgnc.FileFormatError` naming the file, the line and the key."""
    from .._validate import FileFormatError, load_toml, read_text_file

    p = pathlib.Path(path)
    out: dict[str, tuple[float, float, float]] = {}
    if p.suffix.lower() == ".csv":
        p, text = read_text_file(p, "--stations")
        rows = list(csv.reader(text.splitlines()))
        if not rows or tuple(c.strip() for c in rows[0]) != _CSV_HEADER:
            raise FileFormatError(p, 1, f"header: must be {','.join(_CSV_HEADER)}", "header")
        for i, row in enumerate(rows[1:], 2):
            if not row or not "".join(row).strip():
                continue
            if len(row) != 4:
                raise FileFormatError(p, i, f"expected 4 columns ({','.join(_CSV_HEADER)}), got {len(row)}")
            name = row[0].strip()
            vals = []
            for col, v in zip(_CSV_HEADER[1:], row[1:]):
                try:
                    x = float(v)
                except ValueError:
                    raise FileFormatError(p, i, f"{col}: not a number: {v.strip()!r}", col) from None
                if not math.isfinite(x):
                    raise FileFormatError(p, i, f"{col}: must be finite, got {v.strip()!r}", col)
                vals.append(x)
            if not name or name in out:
                raise FileFormatError(
                    p, i, f"name: {'empty' if not name else f'{name!r} given twice'}", "name"
                )
            try:
                _check_site(*vals, where=name)
            except ValueError as e:
                raise FileFormatError(p, i, str(e)) from None
            out[name] = (vals[0], vals[1], vals[2])
    else:
        p, text, doc = load_toml(p, "--stations")
        for name, table in doc.items():
            line = _key_line(text, name, None)
            if not isinstance(table, dict):
                raise FileFormatError(
                    p,
                    _key_line(text, "", name),
                    f"{name}: expected a table [{name}] with latitude, longitude, height",
                    name,
                )
            for key in table:
                if key not in _STATION_KEYS:
                    raise FileFormatError(
                        p,
                        _key_line(text, name, key),
                        f"[{name}] {key}: unknown key (hint: latitude deg, longitude deg, height km)",
                        key,
                    )
            vals = []
            for key in _STATION_KEYS:
                if key not in table:
                    raise FileFormatError(p, line, f"[{name}] {key}: missing", key)
                v = table[key]
                if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                    raise FileFormatError(
                        p,
                        _key_line(text, name, key),
                        f"[{name}] {key}: must be a finite number, got {v!r}",
                        key,
                    )
                vals.append(float(v))
            try:
                _check_site(*vals, where=f"[{name}]")
            except ValueError as e:
                raise FileFormatError(p, line, str(e)) from None
            out[name] = (vals[0], vals[1], vals[2])
    if not out:
        raise FileFormatError(p, None, "no station in the file")
    return out


def receivers(tdm_path: str) -> list[str]:
    """Receiving participant names of a TDM, in order of first appearance (where PATH ends)."""
    from .. import io as _io

    names: list[str] = []
    for seg in _io.read_tdm(tdm_path).segments:
        md = seg.metadata
        k = md.path[-1] if md.path else 1
        if 1 <= k <= len(md.participants) and md.participants[k - 1] not in names:
            names.append(md.participants[k - 1])
    return names


def site_coordinates(
    stations_file: str | None, specs: list[str] | None, receivers: list[str]
) -> dict[str, tuple[float, float, float]]:
    """{name: (lat deg, lon deg, h km)} from ``--stations`` and ``--station`` (the command line wins);
    ValueError naming the option when a receiving participant has no coordinates."""
    sites: dict[str, tuple[float, float, float]] = {}
    if stations_file:
        sites.update(read_stations(stations_file))
    for spec in specs or []:
        label, _, coords = spec.rpartition(":")
        if not label:
            raise ValueError(f"--station: expected NAME:lat,lon,height (deg, deg, km), got {spec!r}")
        lat, lon, h = floats(coords, 3, "--station")
        _check_site(lat, lon, h, f"--station {label}")
        sites[label] = (lat, lon, h)
    missing = [n for n in receivers if n not in sites]
    if missing:
        raise ValueError(
            f"--stations/--station: no coordinates for the TDM's receiving participant(s) {missing} "
            f"(hint: --station {missing[0]}:lat,lon,height)"
        )
    return sites


def station_ephemerides(
    model: str,
    sites: dict[str, tuple[float, float, float]],
    names: list[str],
    epoch: Any,
    t_min: float,
    t_max: float,
    eop_path: str | None = None,
) -> list[Any]:
    """Station ephemerides (t = s after the UTC ``epoch``, a :class:`satgnc.time.Epoch`) of ``names``
    in the ``model`` of the module docstring, valid over [t_min, t_max] s (itrf: +- 1 h margin)."""
    from .. import _satgnc, frames
    from ..observation import EarthFixedStationEphemeris

    if model == "paper":
        from . import station_geodetic

        utc = _dt.datetime.fromisoformat(epoch.to_iso("UTC", 6))
        return [_satgnc.RotatingStationEphemeris(station_geodetic(*sites[n], utc), "WGS-84") for n in names]
    if model != "itrf":
        raise ValueError(f"--station-model: must be one of {list(STATION_MODELS)}, got {model!r}")
    eop = frames.default_eop() if eop_path is None else frames.load_eop(eop_path)
    margin = 3600.0
    try:
        rotation = frames.IauEarthRotation(epoch, eop, min(t_min, 0.0) - margin, max(t_max, 0.0) + margin)
    except ValueError as e:
        raise ValueError(f"--eop: {e}") from None
    return [
        EarthFixedStationEphemeris.from_ground_station(frames.GroundStation(*sites[n], 0.0, n), rotation)
        for n in names
    ]
