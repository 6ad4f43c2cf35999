"""The mission scenario: one TOML file read by :func:`satgnc.mission.run`.

One file describes the whole main job (docs/mission.md): the target's orbit at the epoch, the ground
tracking that observes it, the orbit determination, the rendezvous plan of a chaser relative to it,
and the truth force model the plan is flown on. Units at this level:

* orbit (``[target]``, ``[tracking]``, ``[od]``, ``[truth.drag]`` lengths): km, km/s, s, deg;
* relative motion (``[rendezvous]``): m, m/s, N, kg, s, in the target's CW frame of
  :mod:`satgnc.scenarios.l1_rendezvous` (y radial, z orbit normal, x = y cross z).

The schema is strict, like :func:`satgnc.scenarios.l1_rendezvous.load`: an unknown, missing or
mistyped key is a :class:`satgnc.FileFormatError` (a ``ValueError``) naming the file, the line, the
section and the key.
"""

from __future__ import annotations

import dataclasses
import math
import pathlib

import numpy as np

from .._results import Result
from .._validate import (
    FileFormatError,
    Key,
    check_toml_table,
    did_you_mean,
    load_toml,
    toml_line,
)

DEFAULT = pathlib.Path(__file__).with_name("mission_leo.toml")

_TOP = {
    "name": Key("string", required=False),
    "source": Key("string", required=False),
    "epoch": Key("string", unit="UTC, ISO-8601"),
}
_TARGET = {
    # either an ECI state ...
    "position": Key("vector", length=3, required=False, unit="km, ECI"),
    "velocity": Key("vector", length=3, required=False, unit="km/s, ECI"),
    # ... or classical elements
    "a": Key("number", required=False, positive=True, unit="km"),
    "e": Key("number", required=False, nonnegative=True, high=0.99, unit="-"),
    "i": Key("number", required=False, low=0.0, high=180.0, unit="deg"),
    "raan": Key("number", required=False, unit="deg"),
    "argp": Key("number", required=False, unit="deg"),
    "ta": Key("number", required=False, unit="deg (true anomaly)"),
}
_ELEMENTS = ("a", "e", "i", "raan", "argp", "ta")
_TRACKING = {
    "start": Key("number", nonnegative=True, unit="s from the epoch"),
    "stop": Key("number", positive=True, unit="s from the epoch"),
    "step": Key("number", positive=True, unit="s"),
    "types": Key("string", required=False, default="both", choices=("range", "range_rate", "both")),
    "sigma_range": Key("number", positive=True, unit="km"),
    "sigma_range_rate": Key("number", positive=True, unit="km/s"),
    "seed": Key("integer", low=0, unit="-"),
    "mask": Key("number", required=False, default=0.0, low=-90.0, high=90.0, unit="deg elevation"),
    "quick_thin": Key("integer", required=False, default=3, low=1, unit="keep every n-th time with --quick"),
}
_STATION = {
    "name": Key("string", required=False),
    "lat": Key("number", low=-90.0, high=90.0, unit="deg geodetic"),
    "lon": Key("number", unit="deg"),
    "height": Key("number", low=-1.0, high=100.0, unit="km"),
}
_OD = {
    "method": Key("string", required=False, default="levenberg_marquardt",
                  choices=("levenberg_marquardt", "gauss_newton")),
    "guess_offset": Key("vector", length=6, unit="km, km/s"),
    "propagator": Key("string", required=False, default="cvodes", choices=("kepler", "cvodes")),
    "j2": Key("bool", required=False, default=True),
}
# The same keys as scenarios/l1_rendezvous.toml where they mean the same thing (flattened: the
# file's [chaser] mass, [initial_state] position/velocity, [horizon] tf/knots, [cost] alpha/Qf/u_max,
# [discretization] method, [cases.*] rho/box/terminal_equality).
_RENDEZVOUS = {
    "start": Key("number", required=False, nonnegative=True,
                 unit="s from the epoch (default: tracking stop)"),
    "position": Key("vector", length=3, nonzero=True, unit="m, target CW frame"),
    "velocity": Key("vector", length=3, unit="m/s, target CW frame"),
    "mass": Key("number", positive=True, high=1e9, unit="kg"),
    "tf": Key("number", positive=True, high=1e7, unit="s"),
    "knots": Key("integer", low=2, high=10**5, unit="knot points"),
    "alpha": Key("number", nonnegative=True, unit="scaled units"),
    "Qf": Key("number", nonnegative=True, unit="scaled units"),
    "u_max": Key("number", positive=True, unit="N"),
    "box": Key("bool", required=False, default=True),
    "terminal_equality": Key("bool", required=False, default=False),
    "method": Key("string", required=False, default="zoh", choices=("midpoint", "zoh", "expm")),
    "rho": Key("number", required=False, default=0.1, positive=True, unit="scaled units"),
    "miss_tolerance": Key("number", positive=True, unit="m"),
}
_TRUTH = {
    "j2": Key("bool", required=False, default=True),
}
# ExponentialDrag's parameters (satgnc.dynamics.ExponentialDrag), for the target; the chaser has the
# same cd and atmosphere and its own area.
_DRAG = {
    "rho0": Key("number", nonnegative=True, unit="kg/m^3 at h0"),
    "h0": Key("number", unit="km"),
    "scale_height": Key("number", positive=True, unit="km"),
    "cd": Key("number", required=False, default=2.2, nonnegative=True, unit="-"),
    "area": Key("number", nonnegative=True, unit="m^2 (target)"),
    "mass": Key("number", positive=True, unit="kg (target)"),
    "chaser_area": Key("number", nonnegative=True, unit="m^2"),
}
_SECTIONS = {"target": _TARGET, "tracking": _TRACKING, "od": _OD, "rendezvous": _RENDEZVOUS, "truth": _TRUTH}


@dataclasses.dataclass(frozen=True)
class StationSpec:
    """A ground station: geodetic latitude/longitude (deg) and height (km) on WGS-84."""

    name: str
    lat: float
    lon: float
    height: float


@dataclasses.dataclass(frozen=True)
class DragSpec:
    """Exponential atmosphere rho0 exp(-(h - h0) / scale_height) (kg/m^3, km), the target's cd, area
    (m^2) and mass (kg), and the chaser's area (m^2; its cd is the target's, its mass the plan's)."""

    rho0: float
    h0: float
    scale_height: float
    cd: float
    area: float
    mass: float
    chaser_area: float


@dataclasses.dataclass(frozen=True)
class MissionScenario(Result):
    """A checked mission scenario (see the module docstring for units and frames)."""

    path: pathlib.Path
    name: str
    epoch: str  #: UTC, ISO-8601
    x0: np.ndarray  #: target ECI state at the epoch [km, km/s] (6,)
    stations: tuple  #: StationSpec per station
    times: np.ndarray  #: tracking times, s from the epoch
    types: tuple  #: ("range", "range_rate") or one of them
    sigma_range: float  #: km
    sigma_range_rate: float  #: km/s
    seed: int
    mask: float  #: deg elevation
    quick_thin: int
    od_method: str
    guess_offset: np.ndarray  #: km, km/s (6,)
    od_propagator: str
    od_j2: bool
    start: float  #: s from the epoch: the plan's first knot
    p0: np.ndarray  #: m, target CW frame (3,)
    v0: np.ndarray  #: m/s, target CW frame (3,)
    mass: float  #: kg, chaser
    tf: float  #: s
    knots: int
    alpha: float
    Qf: float
    u_max: float  #: N per axis
    box: bool
    terminal_equality: bool
    method: str  #: CW discretization
    rho: float  #: ADMM penalty (scaled units)
    miss_tolerance: float  #: m
    truth_j2: bool
    drag: DragSpec | None



def elements_to_state(a: float, e: float, i: float, raan: float, argp: float, ta: float,
                      mu: float) -> np.ndarray:
    """ECI state [km, km/s] of classical elements (a km, angles deg, true anomaly ``ta``), mu km^3/s^2.

    Not in the library today (docs/mission.md lists it as missing); the standard perifocal rotation."""
    i, raan, argp, ta = (math.radians(x) for x in (i, raan, argp, ta))
    p = a * (1.0 - e * e)
    r = p / (1.0 + e * math.cos(ta))
    r_pf = np.array([r * math.cos(ta), r * math.sin(ta), 0.0])
    v_pf = math.sqrt(mu / p) * np.array([-math.sin(ta), e + math.cos(ta), 0.0])
    cO, sO, ci, si, cw, sw = (math.cos(raan), math.sin(raan), math.cos(i), math.sin(i), math.cos(argp),
                              math.sin(argp))
    R = np.array([
        [cO * cw - sO * sw * ci, -cO * sw - sO * cw * ci, sO * si],
        [sO * cw + cO * sw * ci, -sO * sw + cO * cw * ci, -cO * si],
        [sw * si, cw * si, ci],
    ])
    return np.concatenate([R @ r_pf, R @ v_pf])


def _fail(p, text, section, key, reason):
    line = toml_line(text, section, key) if key else toml_line(text, section)
    raise FileFormatError(p, line, reason, key=key or section)


def load(path: str | pathlib.Path | None = None, name: str = "path") -> MissionScenario:
    """Read a mission scenario TOML (default: the packaged ``mission_leo.toml``).

    Sections: ``[target]`` (``position``/``velocity`` km, km/s ECI, or elements ``a e i raan argp ta``),
    ``[tracking]`` with one or more ``[[tracking.stations]]``, ``[od]``, ``[rendezvous]``, ``[truth]``
    with an optional ``[truth.drag]``. Every error is a :class:`satgnc.FileFormatError` naming the
    file, the line and the key; a missing file is ``FileNotFoundError``. ``name`` is the caller's
    argument in errors about the path itself."""
    from ..od import EARTH_MU, EARTH_RADIUS, julian_date

    p, text, d = load_toml(DEFAULT if path is None else path, name)
    known = [*_TOP, *_SECTIONS]
    for key, value in d.items():
        if key not in known:
            sec = isinstance(value, dict)
            shown = f"[{key}]" if sec else f"'{key}'"
            hint = did_you_mean(key, known, "[{}]" if sec else "'{}'")
            raise FileFormatError(
                p, toml_line(text, key) if sec else toml_line(text, "", key),
                f"unknown {'section' if sec else 'key'} {shown} at the top level{hint}; known sections: "
                + ", ".join(f"[{k}]" for k in _SECTIONS), key=key)
    top = check_toml_table({k: v for k, v in d.items() if k in _TOP}, _TOP, "", p, text)
    try:
        julian_date(top["epoch"])
    except ValueError as e:
        _fail(p, text, "", "epoch", f"key 'epoch' (UTC, ISO-8601): {str(e).removeprefix('epoch: ')}")
    for sec in _SECTIONS:
        if sec not in d:
            raise FileFormatError(p, None, f"missing section [{sec}] (keys: {', '.join(_SECTIONS[sec])})",
                                  key=sec)
    tr_raw = dict(d["tracking"]) if isinstance(d["tracking"], dict) else d["tracking"]
    stations_raw = tr_raw.pop("stations", None) if isinstance(tr_raw, dict) else None
    truth_raw = dict(d["truth"]) if isinstance(d["truth"], dict) else d["truth"]
    drag_raw = truth_raw.pop("drag", None) if isinstance(truth_raw, dict) else None
    tgt = check_toml_table(d["target"], _TARGET, "target", p, text)
    trk = check_toml_table(tr_raw, _TRACKING, "tracking", p, text)
    od = check_toml_table(d["od"], _OD, "od", p, text)
    rv = check_toml_table(d["rendezvous"], _RENDEZVOUS, "rendezvous", p, text)
    tru = check_toml_table(truth_raw, _TRUTH, "truth", p, text)

    has_state = tgt["position"] is not None or tgt["velocity"] is not None
    given = [k for k in _ELEMENTS if tgt[k] is not None]
    if has_state and given:
        _fail(p, text, "target", given[0], f"key '{given[0]}' in section [target]: give either position "
              "and velocity or the elements a, e, i, raan, argp, ta, not both")
    if has_state:
        for k in ("position", "velocity"):
            if tgt[k] is None:
                unit = "km/s" if k == "velocity" else "km"
                _fail(p, text, "target", None, f"missing key '{k}' in section [target] ({unit}, ECI): "
                      "position and velocity go together")
        x0 = np.array(tgt["position"] + tgt["velocity"])
    else:
        missing = [k for k in _ELEMENTS if tgt[k] is None]
        if missing:
            _fail(p, text, "target", None, f"missing key '{missing[0]}' in section [target]: give position "
                  "and velocity (km, km/s) or all six elements a, e, i, raan, argp, ta (km, deg)")
        x0 = elements_to_state(*(tgt[k] for k in _ELEMENTS), mu=EARTH_MU)
    if not np.linalg.norm(x0[:3]) > EARTH_RADIUS:
        _fail(p, text, "target", "position" if has_state else "a",
              "section [target]: the target is below the Earth's surface "
              f"(|r| = {np.linalg.norm(x0[:3]):.6g} km)")

    if not trk["stop"] > trk["start"]:
        _fail(p, text, "tracking", "stop", f"key 'stop' in section [tracking] (s): must be > start = "
              f"{trk['start']}, got {trk['stop']}")
    times = np.arange(trk["start"], trk["stop"] + 0.5 * trk["step"], trk["step"])
    if times.size > 100_000:
        _fail(p, text, "tracking", "step", f"key 'step' in section [tracking] (s): {times.size} tracking "
              "times; at most 100000")
    if not isinstance(stations_raw, list) or not stations_raw:
        raise FileFormatError(p, toml_line(text, "tracking"), "section [tracking]: needs at least one "
                              "[[tracking.stations]] table (lat, lon deg; height km)", key="stations")
    stations = []
    for k, s in enumerate(stations_raw):
        c = check_toml_table(s, _STATION, "tracking.stations", p, text)
        stations.append(StationSpec(c["name"] or f"station {k}", c["lat"], c["lon"], c["height"]))
    types = ("range", "range_rate") if trk["types"] == "both" else (trk["types"],)

    drag = None
    if drag_raw is not None:
        c = check_toml_table(drag_raw, _DRAG, "truth.drag", p, text)
        drag = DragSpec(**c)
    start = trk["stop"] if rv["start"] is None else rv["start"]
    if start < trk["stop"]:
        _fail(p, text, "rendezvous", "start", f"key 'start' in section [rendezvous] (s): the plan starts "
              f"after the tracking ends (stop = {trk['stop']} s), got {start}")
    return MissionScenario(
        path=p, name=top["name"] or p.stem, epoch=top["epoch"], x0=x0, stations=tuple(stations),
        times=times, types=types, sigma_range=trk["sigma_range"], sigma_range_rate=trk["sigma_range_rate"],
        seed=trk["seed"], mask=trk["mask"], quick_thin=trk["quick_thin"], od_method=od["method"],
        guess_offset=np.array(od["guess_offset"]), od_propagator=od["propagator"], od_j2=od["j2"],
        start=float(start), p0=np.array(rv["position"]), v0=np.array(rv["velocity"]), mass=rv["mass"],
        tf=rv["tf"], knots=rv["knots"], alpha=rv["alpha"], Qf=rv["Qf"], u_max=rv["u_max"], box=rv["box"],
        terminal_equality=rv["terminal_equality"], method=rv["method"], rho=rv["rho"],
        miss_tolerance=rv["miss_tolerance"], truth_j2=tru["j2"], drag=drag,
    )
