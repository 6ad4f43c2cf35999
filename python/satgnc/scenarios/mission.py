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
from ..propagation import elements_to_state
from . import rendezvous as _rv

DEFAULT = pathlib.Path(__file__).with_name("mission_leo.toml")

#: the six stages, in order (satgnc.mission.run runs first_stage..last_stage).
STAGES = ("track", "estimate", "relative_state", "plan", "fly", "check")
#: where a partial chain may start: the tracking, or a plan from a rendezvous scenario file.
ENTRY_STAGES = ("track", "plan")
#: how a [[tracking.stations]] table places its station
STATION_FRAMES = ("geodetic", "inertial")
#: [od] method: batch least squares, or the six-point Newton-Raphson of Gao & Luo (exactly six times
#: of range and range-rate from one station, od.six_point_solver in Doppler mode)
OD_METHODS = ("levenberg_marquardt", "gauss_newton", "newton_six_point")
_TOP = {
    "name": Key("string", required=False),
    "source": Key("string", required=False),
    "epoch": Key("string", required=False, unit="UTC, ISO-8601 (needed by the tracking)"),
    "first_stage": Key("string", required=False, default="track", choices=ENTRY_STAGES),
    "last_stage": Key("string", required=False, default="check", choices=STAGES),
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
    # either a regular grid start..stop by step ...
    "start": Key("number", required=False, nonnegative=True, unit="s from the epoch"),
    "stop": Key("number", required=False, positive=True, unit="s from the epoch"),
    "step": Key("number", required=False, positive=True, unit="s"),
    # ... or the tracking times themselves (e.g. a paper's table)
    "times": Key("vector", required=False, nonnegative=True, unit="s from the epoch, increasing"),
    # false: noise-free observations (the sigmas still weight the OD)
    "noise": Key("bool", required=False, default=True),
    "types": Key("string", required=False, default="both", choices=("range", "range_rate", "both")),
    "sigma_range": Key("number", positive=True, unit="km"),
    "sigma_range_rate": Key("number", positive=True, unit="km/s"),
    "seed": Key("integer", required=False, low=0, unit="- (needed unless noise = false)"),
    "mask": Key("number", required=False, default=0.0, low=-90.0, high=90.0, unit="deg elevation"),
    "quick_thin": Key("integer", required=False, default=3, low=1, unit="keep every n-th time with --quick"),
}
_STATION = {
    "name": Key("string", required=False),
    # "geodetic": lat, lon, height on WGS-84 with the GMST of the epoch; "inertial": the ECI position
    # at the epoch turning about z at omega (od.station_inertial, e.g. a paper's printed station)
    "frame": Key("string", required=False, default="geodetic", choices=STATION_FRAMES),
    "lat": Key("number", required=False, low=-90.0, high=90.0, unit="deg geodetic"),
    "lon": Key("number", required=False, unit="deg"),
    "height": Key("number", required=False, low=-1.0, high=100.0, unit="km"),
    "position": Key("vector", required=False, length=3, unit="km, ECI at the epoch (frame = 'inertial')"),
    "omega": Key("number", required=False, unit="rad/s about z (frame = 'inertial'; default the Earth's)"),
}
_STATION_KEYS = {"geodetic": ("lat", "lon", "height"), "inertial": ("position",)}
_OD = {
    "method": Key("string", required=False, default="levenberg_marquardt", choices=OD_METHODS),
    "guess_offset": Key("vector", length=6, unit="km, km/s"),
    "propagator": Key("string", required=False, default="cvodes", choices=("kepler", "cvodes")),
    "j2": Key("bool", required=False, default=True),
    # the truth's [truth.drag] atmosphere in the OD model (known exactly); needs propagator "cvodes"
    "drag": Key("bool", required=False, default=False),
}
# [rendezvous]: the keys that mean what they mean in a rendezvous scenario file
# (scenarios/rendezvous.py, e.g. l1_rendezvous.toml) are that schema's keys, flattened: [chaser] mass,
# [initial_state] position / velocity, [horizon] tf / knots, [cost] alpha / Qf / u_max,
# [discretization] method, [cases.*] box / terminal_equality. Or `scenario` names such a file and
# `case` one of its cases: the file is read by scenarios.rendezvous.load (one reader) and gives every
# one of those keys; the mission file then gives only the keys below that the file has no meaning for.
_RVS, _RVC = _rv.SECTIONS, _rv.CASE
_SHARED = {
    "position": _RVS["initial_state"]["position"],
    # a zero relative velocity is a valid start here (the rendezvous file requires nonzero)
    "velocity": dataclasses.replace(_RVS["initial_state"]["velocity"], nonzero=False),
    "mass": _RVS["chaser"]["mass"],
    "tf": _RVS["horizon"]["tf"],
    "knots": _RVS["horizon"]["knots"],
    "alpha": _RVS["cost"]["alpha"],
    "Qf": _RVS["cost"]["Qf"],
    "u_max": _RVS["cost"]["u_max"],
    "box": dataclasses.replace(_RVC["box"], default=True),
    "terminal_equality": _RVC["terminal_equality"],
}
_RENDEZVOUS = {
    # required (and defaulted) as in _SHARED when there is no `scenario`
    **{k: dataclasses.replace(v, required=False, default=None) for k, v in _SHARED.items()},
    "method": dataclasses.replace(_RVS["discretization"]["method"], required=False, default=None),
    "scenario": Key("string", required=False, unit="a rendezvous scenario TOML (relative to this file)"),
    "case": Key("string", required=False, unit="a [cases.<name>] of that file"),
    "start": Key("number", required=False, nonnegative=True,
                 unit="s from the epoch (default: tracking stop)"),
    "model": Key("string", required=False, default="linear", choices=("linear", "nonlinear")),
    "closed_loop": Key("bool", required=False, default=False),
    "miss_tolerance": Key("number", positive=True, unit="m"),
}
_TRUTH = {
    "j2": Key("bool", required=False, default=True),
    # "kepler": the analytic two-body truth (j2 = false and no [truth.drag] only)
    "propagator": Key("string", required=False, default="cvodes", choices=("cvodes", "kepler")),
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
    """A ground station: geodetic latitude/longitude (deg) and height (km) on WGS-84, or (``frame``
    "inertial") an ECI ``position`` (km) at the epoch turning about z at ``omega`` (rad/s)."""

    name: str
    lat: float | None
    lon: float | None
    height: float | None
    frame: str = "geodetic"
    position: tuple | None = None  #: km, ECI at the epoch (frame "inertial")
    omega: float | None = None  #: rad/s (frame "inertial")


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
    """A checked mission scenario (see the module docstring for units and frames). The fields of a
    section the chain does not read (``first_stage`` .. ``last_stage``) and that the file leaves out
    are None."""

    path: pathlib.Path
    name: str
    first_stage: str = "track"  #: one of ENTRY_STAGES
    last_stage: str = "check"  #: one of STAGES
    epoch: str | None = None  #: UTC, ISO-8601
    x0: np.ndarray | None = None  #: target ECI state at the epoch [km, km/s] (6,)
    stations: tuple | None = None  #: StationSpec per station
    times: np.ndarray | None = None  #: tracking times, s from the epoch
    types: tuple | None = None  #: ("range", "range_rate") or one of them
    sigma_range: float | None = None  #: km
    sigma_range_rate: float | None = None  #: km/s
    seed: int | None = None
    mask: float | None = None  #: deg elevation
    quick_thin: int | None = None
    od_method: str | None = None
    guess_offset: np.ndarray | None = None  #: km, km/s (6,)
    od_propagator: str | None = None
    od_j2: bool | None = None
    od_drag: bool | None = None  #: the OD model has the truth's drag ([truth.drag])
    start: float | None = None  #: s from the epoch: the plan's first knot
    p0: np.ndarray | None = None  #: m, target CW frame (3,)
    v0: np.ndarray | None = None  #: m/s, target CW frame (3,)
    mass: float | None = None  #: kg, chaser
    tf: float | None = None  #: s
    knots: int | None = None
    alpha: float | None = None
    Qf: float | None = None
    u_max: float | None = None  #: N per axis
    box: bool | None = None
    terminal_equality: bool | None = None
    method: str | None = None  #: CW discretization
    miss_tolerance: float | None = None  #: m
    model: str | None = None  #: the plan's model, "linear" (CW) or "nonlinear" (two-satellite)
    closed_loop: bool | None = None  #: fly with guidance.mpc too
    rendezvous: object | None = None  #: the RendezvousScenario of [rendezvous] scenario, else None
    case: str | None = None  #: its case
    truth_j2: bool | None = None
    drag: DragSpec | None = None
    noise: bool | None = None  #: false: noise-free tracking
    truth_propagator: str | None = None  #: "cvodes" or "kepler" (two-body truth)

    @property
    def stages(self) -> tuple:
        """The stages :func:`satgnc.mission.run` runs, in order."""
        return STAGES[STAGES.index(self.first_stage): STAGES.index(self.last_stage) + 1]


def _fail(p, text, section, key, reason):
    line = toml_line(text, section, key) if key else toml_line(text, section)
    raise FileFormatError(p, line, reason, key=key or section)


def load(path: str | pathlib.Path | None = None, name: str = "path") -> MissionScenario:
    """Read a mission scenario TOML (default: the packaged ``mission_leo.toml``).

    Sections: ``[target]`` (``position``/``velocity`` km, km/s ECI, or elements ``a e i raan argp ta``
    in km and deg), ``[tracking]`` with one or more ``[[tracking.stations]]`` (deg, deg, km), ``[od]``,
    ``[rendezvous]`` (m, m/s, N, kg, s), ``[truth]`` with an optional ``[truth.drag]``; the top-level
    ``first_stage`` / ``last_stage`` (see :data:`STAGES`) choose a partial chain, and only the
    sections its stages read are required (docs/scenarios.md).

    Parameters
    ----------
    path : str or pathlib.Path, optional
        The TOML file (default: the packaged ``mission_leo.toml``).
    name : str, optional
        The caller's argument name in errors about the path itself (default "path").

    Returns
    -------
    MissionScenario
        The validated scenario.

    Raises
    ------
    satgnc.FileFormatError
        (a ValueError) naming the file, the line and the key: unknown keys and sections, wrong types
        or ranges, missing keys.
    FileNotFoundError
        A missing file.

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()
    >>> sc.name, len(sc.stations)
    ('mission_leo', 3)
    """
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
    first, last = top["first_stage"], top["last_stage"]
    if STAGES.index(last) < STAGES.index(first):
        _fail(p, text, "", "last_stage", f"key 'last_stage': {last!r} comes before first_stage = {first!r} "
              f"(stages in order: {', '.join(STAGES)})")
    runs = STAGES[STAGES.index(first): STAGES.index(last) + 1]
    rv_raw = d.get("rendezvous")
    from_file = isinstance(rv_raw, dict) and "scenario" in rv_raw
    needed = {"target": "track" in runs, "tracking": "track" in runs, "od": "estimate" in runs,
              "rendezvous": len(runs) > 2 or first == "plan",
              "truth": "track" in runs or (first == "track" and len(runs) > 3)}
    if needed["tracking"] and top["epoch"] is None:
        _fail(p, text, "", None, "missing key 'epoch' (UTC, ISO-8601): the tracking needs it")
    if top["epoch"] is not None:
        try:
            julian_date(top["epoch"])
        except ValueError as e:
            _fail(p, text, "", "epoch", f"key 'epoch' (UTC, ISO-8601): {str(e).removeprefix('epoch: ')}")
    for sec in _SECTIONS:
        if needed[sec] and sec not in d:
            raise FileFormatError(p, None, f"missing section [{sec}] (keys: {', '.join(_SECTIONS[sec])}; "
                                  f"stages {', '.join(runs)})", key=sec)
    if first == "plan" and not from_file:
        _fail(p, text, "rendezvous" if "rendezvous" in d else "", None,
              "first_stage = 'plan' needs [rendezvous] scenario = <a rendezvous scenario TOML> and case "
              "(the plan's start without the tracking and the OD)")
    if first == "track" and from_file:
        _fail(p, text, "rendezvous", "scenario", "key 'scenario' in section [rendezvous]: a rendezvous "
              "scenario file gives its own orbit; it starts the chain at first_stage = 'plan'")
    if from_file and "truth" in d:
        _fail(p, text, "truth", None, "section [truth]: with [rendezvous] scenario, the flight's truth is "
              "that file's [truth] (remove this section)")
    f: dict = {"first_stage": first, "last_stage": last, "epoch": top["epoch"]}
    if "track" in runs or "target" in d:
        f.update(_target(p, text, d, EARTH_MU, EARTH_RADIUS))
    if "track" in runs or "tracking" in d:
        f.update(_tracking(p, text, d))
    if "estimate" in runs or "od" in d:
        od = check_toml_table(d["od"], _OD, "od", p, text)
        f.update(od_method=od["method"], guess_offset=np.array(od["guess_offset"]),
                 od_propagator=od["propagator"], od_j2=od["j2"], od_drag=od["drag"])
    if "truth" in d:
        truth_raw = dict(d["truth"]) if isinstance(d["truth"], dict) else d["truth"]
        drag_raw = truth_raw.pop("drag", None) if isinstance(truth_raw, dict) else None
        tru = check_toml_table(truth_raw, _TRUTH, "truth", p, text)
        drag = None if drag_raw is None else DragSpec(
            **check_toml_table(drag_raw, _DRAG, "truth.drag", p, text))
        f.update(truth_j2=tru["j2"], drag=drag, truth_propagator=tru["propagator"])
        if tru["propagator"] == "kepler" and (tru["j2"] or drag is not None):
            _fail(p, text, "truth", "propagator", "key 'propagator' in section [truth]: 'kepler' is the "
                  "two-body truth; it needs j2 = false and no [truth.drag]")
    if f.get("od_drag") and f.get("drag") is None:
        _fail(p, text, "od", "drag", "key 'drag' in section [od]: drag = true takes the atmosphere of "
              "[truth.drag], which the file does not have")
    if f.get("od_drag") and f["od_propagator"] != "cvodes":
        _fail(p, text, "od", "drag", "key 'drag' in section [od]: drag = true needs propagator = 'cvodes' "
              "(the Kepler propagator is two-body only)")
    if f.get("od_method") == "newton_six_point":
        _six_point_rules(p, text, f)
    if needed["rendezvous"] or "rendezvous" in d:
        f.update(_rendezvous(p, text, d["rendezvous"], f.get("times")))
    return MissionScenario(path=p, name=top["name"] or p.stem, **f)


def _six_point_rules(p, text, f) -> None:
    """[od] method = "newton_six_point" solves six conditions: six times, both types, one station."""
    why = None
    if f.get("times") is None:
        why = "it needs a [tracking] section"
    elif f["times"].size != 6:
        why = f"it needs exactly 6 tracking times, [tracking] gives {f['times'].size}"
    elif f["types"] != ("range", "range_rate"):
        why = "it needs types = 'both' in [tracking] (a range and a range-rate per time)"
    elif len(f["stations"]) != 1:
        why = f"it needs one station, [tracking] gives {len(f['stations'])}"
    if why:
        _fail(p, text, "od", "method", f"key 'method' in section [od]: 'newton_six_point' (Gao & Luo's "
              f"six conditions): {why}")


def _target(p, text, d, mu, radius) -> dict:
    tgt = check_toml_table(d["target"], _TARGET, "target", p, text)
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
        x0 = elements_to_state(*(tgt[k] for k in _ELEMENTS), mu=mu)
    if not np.linalg.norm(x0[:3]) > radius:
        _fail(p, text, "target", "position" if has_state else "a",
              "section [target]: the target is below the Earth's surface "
              f"(|r| = {np.linalg.norm(x0[:3]):.6g} km)")
    return {"x0": x0}


def _tracking(p, text, d) -> dict:
    tr_raw = dict(d["tracking"]) if isinstance(d["tracking"], dict) else d["tracking"]
    stations_raw = tr_raw.pop("stations", None) if isinstance(tr_raw, dict) else None
    trk = check_toml_table(tr_raw, _TRACKING, "tracking", p, text)
    times = _tracking_times(p, text, trk)
    if trk["noise"] and trk["seed"] is None:
        _fail(p, text, "tracking", None, "missing key 'seed' in section [tracking] (the noise seed; or "
              "noise = false for noise-free tracking)")
    if times.size > 100_000:
        _fail(p, text, "tracking", "step", f"key 'step' in section [tracking] (s): {times.size} tracking "
              "times; at most 100000")
    if not isinstance(stations_raw, list) or not stations_raw:
        raise FileFormatError(p, toml_line(text, "tracking"), "section [tracking]: needs at least one "
                              "[[tracking.stations]] table (lat, lon deg; height km)", key="stations")
    stations = []
    for k, s in enumerate(stations_raw):
        c = check_toml_table(s, _STATION, "tracking.stations", p, text)
        stations.append(_station(p, text, c, k))
    types = ("range", "range_rate") if trk["types"] == "both" else (trk["types"],)
    return dict(stations=tuple(stations), times=times, types=types, sigma_range=trk["sigma_range"],
                sigma_range_rate=trk["sigma_range_rate"], seed=trk["seed"], mask=trk["mask"],
                quick_thin=trk["quick_thin"], noise=trk["noise"])


def _tracking_times(p, text, trk) -> np.ndarray:
    """[tracking]'s times: the ``times`` list, or start..stop by step (one of the two forms)."""
    grid = [k for k in ("start", "stop", "step") if trk[k] is not None]
    if trk["times"] is not None:
        if grid:
            _fail(p, text, "tracking", grid[0], f"key '{grid[0]}' in section [tracking]: give either "
                  "times or start, stop and step, not both")
        times = np.array(trk["times"])
        if times.size == 0 or np.any(np.diff(times) <= 0):
            _fail(p, text, "tracking", "times", "key 'times' in section [tracking] (s from the epoch): "
                  f"must be a non-empty, strictly increasing list, got {trk['times']}")
        return times
    missing = [k for k in ("start", "stop", "step") if trk[k] is None]
    if missing:
        _fail(p, text, "tracking", None, f"missing key '{missing[0]}' in section [tracking] (s): give "
              "start, stop and step, or times")
    if not trk["stop"] > trk["start"]:
        _fail(p, text, "tracking", "stop", f"key 'stop' in section [tracking] (s): must be > start = "
              f"{trk['start']}, got {trk['stop']}")
    return np.arange(trk["start"], trk["stop"] + 0.5 * trk["step"], trk["step"])


def _station(p, text, c, k) -> StationSpec:
    """One [[tracking.stations]] table: the keys of its frame and none of the other frame's."""
    frame = c["frame"]
    other = "inertial" if frame == "geodetic" else "geodetic"
    extra = [key for key in (*_STATION_KEYS[other], "omega") if c[key] is not None
             and not (key == "omega" and frame == "inertial")]
    if extra:
        _fail(p, text, "tracking.stations", extra[0], f"key '{extra[0]}' in [[tracking.stations]] "
              f"number {k + 1}: not a key of frame = '{frame}' (keys: {', '.join(_STATION_KEYS[frame])}"
              + (", omega" if frame == "inertial" else "") + ")")
    missing = [key for key in _STATION_KEYS[frame] if c[key] is None]
    if missing:
        _fail(p, text, "tracking.stations", None, f"missing key '{missing[0]}' in [[tracking.stations]] "
              f"number {k + 1} (frame = '{frame}' needs {', '.join(_STATION_KEYS[frame])})")
    name = c["name"] or f"station {k}"
    if frame == "inertial":
        return StationSpec(name, None, None, None, frame, tuple(c["position"]), c["omega"])
    return StationSpec(name, c["lat"], c["lon"], c["height"])


def _rendezvous(p, text, raw, times) -> dict:
    rv = check_toml_table(raw, _RENDEZVOUS, "rendezvous", p, text)
    out = dict(model=rv["model"], closed_loop=rv["closed_loop"],
               miss_tolerance=rv["miss_tolerance"])
    if rv["scenario"] is not None:
        given = [k for k in _SHARED if rv[k] is not None] + [k for k in ("start",) if rv[k] is not None]
        if given:
            _fail(p, text, "rendezvous", given[0], f"key '{given[0]}' in section [rendezvous]: the "
                  f"rendezvous scenario {rv['scenario']!r} gives it (with `scenario`, only case, method, "
                  "model, closed_loop and miss_tolerance)")
        if rv["case"] is None:
            _fail(p, text, "rendezvous", None, "missing key 'case' in section [rendezvous]: a case of the "
                  "rendezvous scenario file")
        rp = pathlib.Path(rv["scenario"])
        rp = rp if rp.is_absolute() else (p.parent / rp)
        rsc = _rv.load(rp, "scenario")
        if rv["case"] not in rsc.cases:
            _fail(p, text, "rendezvous", "case", f"key 'case' in section [rendezvous]: unknown case "
                  f"{rv['case']!r} of {rp.name}; choose from {sorted(rsc.cases)}")
        sec, case = rsc.sections, rsc.cases[rv["case"]]
        out.update(rendezvous=rsc, case=rv["case"], start=0.0,
                   p0=np.array(sec["initial_state"]["position"]),
                   v0=np.array(sec["initial_state"]["velocity"]), mass=sec["chaser"]["mass"],
                   tf=sec["horizon"]["tf"], knots=sec["horizon"]["knots"], alpha=sec["cost"]["alpha"],
                   Qf=sec["cost"]["Qf"], u_max=sec["cost"]["u_max"], box=case["box"],
                   terminal_equality=case["terminal_equality"],
                   method=rv["method"] or sec["discretization"]["method"])
        return out
    if rv["case"] is not None:
        _fail(p, text, "rendezvous", "case", "key 'case' in section [rendezvous]: only with `scenario`")
    for k, key in _SHARED.items():
        if rv[k] is None and key.required:
            unit = f" ({key.unit})" if key.unit else ""
            _fail(p, text, "rendezvous", None, f"missing key '{k}' in section [rendezvous]{unit}")
        if rv[k] is None:
            rv[k] = key.default
    stop = float(times[-1]) if times is not None else 0.0
    start = stop if rv["start"] is None else rv["start"]
    if start < stop:
        _fail(p, text, "rendezvous", "start", f"key 'start' in section [rendezvous] (s): the plan starts "
              f"after the tracking ends (stop = {stop} s), got {start}")
    out.update(start=float(start), p0=np.array(rv["position"]), v0=np.array(rv["velocity"]),
               mass=rv["mass"], tf=rv["tf"], knots=rv["knots"], alpha=rv["alpha"], Qf=rv["Qf"],
               u_max=rv["u_max"], box=rv["box"],
               terminal_equality=rv["terminal_equality"], method=rv["method"] or "zoh")
    return out
