"""One rendezvous scenario file, read by both models (linear CW and nonlinear two-satellite).

Schema (strict: an unknown, missing or mistyped key is a :class:`satgnc.FileFormatError` naming the
file, the line, the key and its section). SI units (m, m/s, N, kg, s) except where marked.

* ``[orbit]`` ``mu`` (m^3/s^2), ``radius`` (m): the target's circular orbit;
* ``[chaser]`` ``mass`` (kg);
* ``[initial_state]`` ``position`` (m), ``velocity`` (m/s): the chaser relative to the target in the
  target's CW frame (y radial, z normal, x = y cross z);
* optional ``[release]`` ``relative_position`` (m), ``relative_velocity`` (m/s), ``drift_time`` (s),
  ``drift_steps``: the nonlinear model's start: target minus chaser (ECI) at release, the target at
  ``[radius, 0, 0]`` on its circular equatorial orbit, then ``drift_time`` s of uncontrolled RK4
  (``drift_steps`` steps) on the planner model; without it the nonlinear start is ``[initial_state]``;
* ``[horizon]`` ``tf`` (s), ``knots`` (knot points: knots - 1 control intervals);
* ``[cost]`` ``alpha``, ``Qf`` (scaled units), ``u_max`` (N per axis, applied by cases with ``box``);
* optional ``[discretization]`` ``method`` (linear: midpoint / zoh / expm), ``nonlinear``
  (rk3 / rk4 / dop853), ``substeps`` (RK steps per interval);
* optional ``[planner]`` and ``[truth]`` ``j2``, ``drag``, ``atmosphere`` (co_rotating / published): the
  nonlinear planning model (default: point mass) and the flight's truth model (default: J2 and drag,
  co-rotating); both take ``mu`` from ``[orbit]`` and the chaser's mass from ``[chaser]``, the rest from
  the engine's ``TwoSatelliteParams`` defaults (drag: the l1 scenario's exponential density with its
  6731 km reference radius, target 4.6 kg, 0.01 m^2);
* optional ``[truth]`` ``force_model``: a force-model TOML (docs/force_models.md; path relative to the
  scenario file) that sets the truth's mu, J2 and exponential drag instead of ``j2`` / ``drag`` (which
  it excludes): see :func:`truth_force_model`;
* ``[cases.<name>]`` ``rho``, ``eps``, ``box``, ``terminal_equality``, ``paper_lqr_passes`` (the linear
  model's ADMM settings), and optional ``[cases.<name>.nonlinear]`` ``rho``, ``eps``,
  ``terminal_equality``: the nonlinear model's iLQR-ADMM settings (paper stopping rule) and its
  terminal condition (default: the case's).

Issue 16 (all optional; a file without them reads as before):

* ``[[thrusters]]`` (an array of tables, one per thruster): ``direction`` (unit vector, CW frame:
  the chaser's body axes are held aligned with it), ``max_thrust`` (N, > 0), ``min_impulse_bit``
  (N s, >= 0, default 0), ``position`` (m from the centre of mass, default [0, 0, 0]), ``name``
  (default ``T<i>``): the layout of :class:`satgnc.guidance.thrusters.ThrusterLayout`; a non-unit
  direction is an error naming the thruster;
* ``[keep_out]`` ``semi_axes`` (m, > 0, along the CW axes), ``center`` (m, default [0, 0, 0]): the
  keep-out ellipsoid (:class:`satgnc.guidance.safety.KeepOut`); ``hold_point`` (m, optional): the
  keep-out plan's end, a V-bar hold point outside the zone (``satgnc rendezvous --keep-out``);
  ``margin`` (relative, default 0.05): the zone's inflation for the planning;
* ``[passive_safety]`` ``drift_time`` (s, > 0), ``samples`` (default 100): the free drift checked from
  each node (:func:`satgnc.guidance.safety.passive_safety`);
* ``[plume]`` ``half_angle_deg`` (deg, in (0, 90]), ``range`` (m, > 0): the plume-impingement cone of
  the keep-out plan (``satgnc rendezvous --keep-out``; needs ``[[thrusters]]``): a thruster whose
  exhaust points within the half-angle of the target while the chaser is within the range is
  inhibited (:func:`satgnc.guidance.keep_out.keep_out_plan`, ``plume``);
* ``[failures]`` ``pairs`` (default false): the thruster-loss table also loses every pair
  (``satgnc rendezvous --failures``; needs ``[[thrusters]]``);
* state constraints (:func:`state_constraints`, ``satgnc rendezvous --constrained``), each with
  ``nodes`` (integers in 1..knots-1) or ``from_node`` (from_node..knots-1), default every node:
  ``[approach_cone]`` ``axis`` (CW frame), ``half_angle_deg`` (deg, in (0, 90)), ``apex_offset`` (m,
  default 0); ``[state_box]`` ``lower`` / ``upper`` (6 numbers, m and m/s, ``-inf`` / ``inf`` for
  none); ``[closing_velocity]`` ``axis``, ``intercept`` (m/s), ``slope`` (1/s), one entry per segment:
  |a.v| <= min_i(intercept_i + slope_i a.p); ``[[half_spaces]]`` ``a`` (6 numbers), ``b``: a'x <= b.
"""

from __future__ import annotations

import dataclasses
import pathlib

import numpy as np

from .._validate import (
    FileFormatError,
    Key,
    check_toml_table,
    did_you_mean,
    load_toml,
    read_text_file,
    toml_line,
)

__all__ = [
    "RendezvousScenario", "load", "problem", "truth_params", "truth_force_model", "thruster_layout",
    "keep_out", "plume", "state_constraints", "DEFAULT",
]

DEFAULT = pathlib.Path(__file__).with_name("l1_rendezvous.toml")

_ATMOSPHERES = ("co_rotating", "published")
_TOP = {"name": Key("string", required=False), "source": Key("string", required=False)}
SECTIONS = {
    "orbit": {
        "mu": Key("number", positive=True, low=1.0, high=1e22, unit="m^3/s^2"),
        "radius": Key("number", positive=True, low=1.0, high=1e13, unit="m"),
    },
    "chaser": {"mass": Key("number", positive=True, high=1e9, unit="kg")},
    "initial_state": {
        "position": Key("vector", length=3, nonzero=True, unit="m"),
        "velocity": Key("vector", length=3, nonzero=True, unit="m/s"),
    },
    "release": {
        "relative_position": Key("vector", length=3, unit="m"),
        "relative_velocity": Key("vector", length=3, unit="m/s"),
        "drift_time": Key("number", required=False, default=0.0, nonnegative=True, high=1e9, unit="s"),
        "drift_steps": Key("integer", required=False, default=1, low=1, high=10**7, unit="RK4 steps"),
    },
    "horizon": {
        "tf": Key("number", positive=True, high=1e9, unit="s"),
        "knots": Key("integer", low=2, high=10**6, unit="knot points"),
    },
    "cost": {
        "alpha": Key("number", nonnegative=True, unit="scaled units"),
        "Qf": Key("number", nonnegative=True, unit="scaled units"),
        "u_max": Key("number", positive=True, unit="N"),
    },
    "discretization": {
        "method": Key("string", required=False, default="midpoint", choices=("midpoint", "zoh", "expm")),
        "nonlinear": Key("string", required=False, default="rk3", choices=("rk3", "rk4", "dop853")),
        "substeps": Key("integer", required=False, default=1, low=1, high=10**6),
    },
    "planner": {
        "j2": Key("bool", required=False, default=False),
        "drag": Key("bool", required=False, default=False),
        "atmosphere": Key("string", required=False, default="co_rotating", choices=_ATMOSPHERES),
    },
    "truth": {
        "j2": Key("bool", required=False, default=True),
        "drag": Key("bool", required=False, default=True),
        "atmosphere": Key("string", required=False, default="co_rotating", choices=_ATMOSPHERES),
        "force_model": Key("string", required=False, unit="path of a force-model TOML"),
    },
    "keep_out": {
        "semi_axes": Key("vector", length=3, positive=True, unit="m"),
        "center": Key("vector", length=3, required=False, default=[0.0, 0.0, 0.0], unit="m"),
        "hold_point": Key("vector", length=3, required=False, unit="m"),
        "margin": Key("number", required=False, default=0.05, nonnegative=True, high=10.0, unit="relative"),
    },
    "passive_safety": {
        "drift_time": Key("number", positive=True, high=1e9, unit="s"),
        "samples": Key("integer", required=False, default=100, low=1, high=10**6, unit="samples per drift"),
    },
    "failures": {"pairs": Key("bool", required=False, default=False)},
    "plume": {
        "half_angle_deg": Key("number", positive=True, high=90.0, unit="deg"),
        "range": Key("number", positive=True, high=1e9, unit="m"),
    },
}
#: sections a file may leave out (all their keys have defaults; [release], [keep_out],
#: [passive_safety] and [plume] absent mean none).
OPTIONAL_SECTIONS = (
    "release", "discretization", "planner", "truth", "keep_out", "passive_safety", "failures", "plume"
)
#: sections whose absence reads as None (no defaults to fill in).
ABSENT_IS_NONE = ("release", "keep_out", "passive_safety", "plume")
#: one ``[[thrusters]]`` table (issue 16).
THRUSTER = {
    "direction": Key("vector", length=3, nonzero=True, unit="unit vector, CW frame"),
    "max_thrust": Key("number", positive=True, high=1e9, unit="N"),
    "min_impulse_bit": Key("number", required=False, default=0.0, nonnegative=True, unit="N s"),
    "position": Key("vector", length=3, required=False, default=[0.0, 0.0, 0.0], unit="m"),
    "name": Key("string", required=False),
}
#: issue 16 item 1: the state-constraint sections (:func:`read_state_constraints`), CW frame, SI.
#: Each also takes ``nodes`` (integers in 1..knots-1) or ``from_node`` (nodes from_node..knots-1);
#: neither: every node 1..knots-1 (x_0 is given).
APPROACH_CONE = {
    "axis": Key("vector", length=3, nonzero=True, unit="docking axis, CW frame"),
    "half_angle_deg": Key("number", positive=True, high=89.999999, unit="deg"),
    "apex_offset": Key("number", required=False, default=0.0, unit="m"),
}
STATE_BOX = {
    "lower": Key("vector", length=6, required=False, finite=False, unit="m, m/s; -inf: no bound"),
    "upper": Key("vector", length=6, required=False, finite=False, unit="m, m/s; inf: no bound"),
}
CLOSING_VELOCITY = {
    "axis": Key("vector", length=3, nonzero=True, unit="range axis, CW frame"),
    "intercept": Key("vector", unit="m/s, one per segment"),
    "slope": Key("vector", unit="1/s, one per segment"),
}
HALF_SPACE = {
    "a": Key("vector", length=6, nonzero=True, unit="row on [position m, velocity m/s]"),
    "b": Key("number", unit="units of a'x"),
}
CONSTRAINT_SECTIONS = {"approach_cone": APPROACH_CONE, "state_box": STATE_BOX,
                       "closing_velocity": CLOSING_VELOCITY, "half_spaces": HALF_SPACE}
CASE = {
    "rho": Key("number", positive=True),
    "eps": Key("number", positive=True),
    "box": Key("bool", required=False, default=False),
    "terminal_equality": Key("bool", required=False, default=False),
    "paper_lqr_passes": Key("integer", required=False, low=0),
}
CASE_NONLINEAR = {
    "rho": Key("number", positive=True),
    "eps": Key("number", positive=True),
    "terminal_equality": Key("bool", required=False),
}


def read(path, name: str = "path"):
    """``(path, text, top, sections, cases)`` of a scenario file, every entry checked; a case's
    ``"nonlinear"`` entry is its checked ``[cases.<name>.nonlinear]`` table or None; an absent
    ``[release]`` is None. ``name`` is the caller's argument in errors about the path itself."""
    p, text, d = load_toml(path, name)
    known = [*_TOP, *SECTIONS, "cases", "thrusters", *CONSTRAINT_SECTIONS]
    for key, value in d.items():
        if key not in known:
            what = "section" if isinstance(value, dict) else "key"
            shown = f"[{key}]" if what == "section" else f"'{key}'"
            line = toml_line(text, key) if what == "section" else toml_line(text, "", key)
            hint = did_you_mean(key, known, "[{}]" if what == "section" else "'{}'")
            raise FileFormatError(
                p,
                line,
                f"unknown {what} {shown} at the top level{hint}; known sections: "
                + ", ".join(f"[{k}]" for k in [*SECTIONS, "cases"]),
                key=key,
            )
    top = check_toml_table({k: v for k, v in d.items() if k in _TOP}, _TOP, "", p, text)
    secs = {}
    for sec, schema in SECTIONS.items():
        if sec not in d:
            if sec not in OPTIONAL_SECTIONS:
                raise FileFormatError(
                    p, None, f"missing section [{sec}] (keys: {', '.join(schema)})", key=sec
                )
            secs[sec] = None if sec in ABSENT_IS_NONE else check_toml_table({}, schema, sec, p, text)
            continue
        secs[sec] = check_toml_table(d[sec], schema, sec, p, text)
    secs["thrusters"] = read_thrusters(d.get("thrusters"), p, text)
    if secs["plume"] is not None and secs["thrusters"] is None:
        raise FileFormatError(p, toml_line(text, "plume"), "[plume]: needs [[thrusters]] (the plume cone "
                              "inhibits thrusters; the per-axis box has none)", key="plume")
    secs["truth"]["force_model"] = read_truth_force_model(d.get("truth"), secs, p, text)
    secs.update(read_state_constraints(d, p, text, secs["horizon"]["knots"] - 1))
    cases_raw = d.get("cases")
    if cases_raw is None:
        raise FileFormatError(
            p, None, "missing section [cases.<name>]: the scenario needs at least one case", key="cases"
        )
    if not isinstance(cases_raw, dict) or not cases_raw:
        raise FileFormatError(
            p, toml_line(text, "cases"), "[cases] must hold at least one [cases.<name>] table", key="cases"
        )
    cases = {}
    for cname, c in cases_raw.items():
        nl = None
        if isinstance(c, dict) and "nonlinear" in c:
            c = dict(c)
            nl = check_toml_table(c.pop("nonlinear"), CASE_NONLINEAR, f"cases.{cname}.nonlinear", p, text)
        checked = check_toml_table(c, CASE, f"cases.{cname}", p, text)
        checked["nonlinear"] = nl
        cases[cname] = checked
    n = float(np.sqrt(secs["orbit"]["mu"] / secs["orbit"]["radius"] ** 3))
    if n * secs["horizon"]["tf"] > 1e9:  # the CW matrices' bound (guidance.cw_stm); the error named "dt"
        raise FileFormatError(
            p,
            toml_line(read_text_file(p)[1], "horizon", "tf"),
            f"key 'tf' in section [horizon] (s): n tf = {n * secs['horizon']['tf']:.3g} rad exceeds 1e9 rad "
            f"(n = sqrt(mu / radius^3) = {n:.3g} rad/s): the CW matrices keep no correct digit",
            key="tf",
        )
    return p, text, top, secs, cases


def _nth_table_line(text: str, section: str, n: int, key: str) -> int | None:
    """Line of ``key`` in the ``n``-th (0-based) ``[[section]]`` table of a TOML text, or None."""
    count, inside = -1, False
    for i, raw in enumerate(text.splitlines(), start=1):
        s = raw.strip()
        if s.startswith("["):
            name = s.lstrip("[").split("]")[0].strip()
            inside = s.startswith("[[") and name == section
            count += inside
            inside = inside and count == n
        elif inside and s.split("=")[0].strip().strip('"') == key:
            return i
    return None


def read_thrusters(raw, p, text: str) -> list[dict] | None:
    """The checked ``[[thrusters]]`` tables (None when absent): each against :data:`THRUSTER`, a
    direction more than 1e-9 from unit length named by its table number and line."""
    if raw is None:
        return None
    line = toml_line(text, "thrusters")
    if not isinstance(raw, list) or not raw or not all(isinstance(t, dict) for t in raw):
        raise FileFormatError(p, line, "thrusters: must be an array of tables [[thrusters]], one per "
                              "thruster (direction, max_thrust, ...)", key="thrusters")
    out = []
    for i, t in enumerate(raw):
        row = check_toml_table(t, THRUSTER, "thrusters", p, text)
        norm = float(np.linalg.norm(row["direction"]))
        if abs(norm - 1.0) > 1e-9:
            raise FileFormatError(
                p, _nth_table_line(text, "thrusters", i, "direction"),
                f"key 'direction' in [[thrusters]] number {i + 1}: must be a unit vector, got norm {norm!r} "
                "(tolerance 1e-9)", key="direction")
        if row["name"] is None:
            row["name"] = f"T{i}"
        out.append(row)
    names = [r["name"] for r in out]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise FileFormatError(p, line,
                              f"key 'name' in [[thrusters]]: names must be unique, {dup[0]!r} repeats",
                              key="name")
    return out


#: keys of [truth] that a force-model file replaces (the file names the truth's gravity and drag).
_TRUTH_FROM_FILE = ("j2", "drag")


def read_truth_force_model(raw, secs: dict, p: pathlib.Path, text: str) -> pathlib.Path | None:
    """The checked ``[truth] force_model`` path (absolute), or None when the key is absent.

    The path is taken from the scenario file's folder. Errors (:class:`FileFormatError`): ``j2`` or
    ``drag`` beside it (scenario file and line), no such file (scenario line), anything the force-model
    reader or the two-satellite model refuses (the force-model file, its line and ``[section] key``),
    and a file whose mu (km^3/s^2 x 1e9) or ``[drag] mass`` differs from the scenario's ``[orbit] mu``
    or ``[chaser] mass`` by more than 1e-12 relative: one truth, one mu and one chaser mass."""
    name = secs["truth"]["force_model"]
    if name is None:
        return None
    line = toml_line(text, "truth", "force_model")
    for key in _TRUTH_FROM_FILE:
        if key in raw:
            raise FileFormatError(
                p, toml_line(text, "truth", key),
                f"key '{key}' in section [truth]: not with 'force_model' (the force-model file "
                f"{name!r} sets the truth's gravity and drag; remove '{key}')", key=key)
    fm = (p.parent / name).resolve()
    if not fm.is_file():
        raise FileFormatError(p, line, f"key 'force_model' in section [truth]: no file at {fm} "
                              "(a path relative to the scenario file)", key="force_model")
    tp = _truth_from_file(fm, secs)
    checks = ((tp.mu, secs["orbit"]["mu"], "[central_body] mu", "[orbit] mu", "m^3/s^2"),)
    if tp.drag_on:
        checks += ((tp.mass_target, secs["chaser"]["mass"], "[drag] mass", "[chaser] mass", "kg"),)
    for got, want, where, ours, unit in checks:
        if abs(got - want) > 1e-12 * abs(want):
            raise FileFormatError(
                p, line,
                f"key 'force_model' in section [truth]: {fm.name} gives {where} = {got!r} {unit} (SI), the "
                f"scenario's {ours} is {want!r} {unit}: the truth and the scenario must agree (relative "
                "1e-12); set it in one of the files", key="force_model")
    return fm


def _truth_from_file(fm: pathlib.Path, secs: dict):
    """TwoSatelliteParams of a force-model file (mu, J2, drag; the chaser's mass from [chaser], the
    atmosphere rotation from [truth]); errors name the force-model file, its line and key."""
    from .. import _satgnc as _c
    from ..forcemodel import load_force_model_config
    from ..guidance.problem import satellite_params

    base = satellite_params(secs["orbit"]["mu"], j2=False, drag=False,
                            atmosphere=secs["truth"]["atmosphere"], mass=secs["chaser"]["mass"])
    cfg = load_force_model_config(fm)
    try:
        tp = _c.two_satellite_params_from_config(cfg, base)
    except FileFormatError as e:  # the model's refusal names a section, not a line: find it
        if e.line is not None or e.key is None:
            raise
        sec, _, key = e.key.strip().partition(" ")
        line = toml_line(read_text_file(fm)[1], sec.strip("[]"), key or None)
        raise FileFormatError(fm, line, e.reason, key=e.key) from None
    tp.mass_chaser = secs["chaser"]["mass"]  # the control's mass (= the file's [drag] mass, checked)
    return tp


@dataclasses.dataclass(frozen=True)
class RendezvousScenario:
    """A checked scenario file: ``path``, ``name``, ``sections`` (section -> {key: value}; ``release``
    None when absent) and ``cases`` (case -> {key: value}, ``"nonlinear"`` a table or None)."""

    path: pathlib.Path
    name: str | None
    sections: dict
    cases: dict

    def nonlinear_cases(self) -> list[str]:
        """The cases with a ``[cases.<name>.nonlinear]`` table, or every case when none has one."""
        named = [c for c, v in self.cases.items() if v["nonlinear"] is not None]
        return named or list(self.cases)


def load(path=None, name: str = "path") -> RendezvousScenario:
    """Read and check a rendezvous scenario file (default: the packaged l1_rendezvous.toml)."""
    p, _, top, secs, cases = read(DEFAULT if path is None else path, name)
    return RendezvousScenario(p, top.get("name"), secs, cases)


def _params(sc: RendezvousScenario, section: str):
    """TwoSatelliteParams of ``[planner]`` or ``[truth]`` with the file's mu and chaser mass."""
    from ..guidance.problem import satellite_params

    t = sc.sections[section]
    mu, mass = sc.sections["orbit"]["mu"], sc.sections["chaser"]["mass"]
    return satellite_params(mu, j2=t["j2"], drag=t["drag"], atmosphere=t["atmosphere"], mass=mass)


def truth_params(sc: RendezvousScenario):
    """``TwoSatelliteParams`` (SI) of the scenario's ``[truth]`` model: from its ``force_model`` file
    when named (:func:`truth_force_model`), else ``j2`` / ``drag`` / ``atmosphere`` with mu from
    ``[orbit]`` and the chaser's mass from ``[chaser]``."""
    fm = truth_force_model(sc)
    if fm is not None:
        return _truth_from_file(fm, sc.sections)
    return _params(sc, "truth")


def truth_force_model(sc: RendezvousScenario) -> pathlib.Path | None:
    """The ``[truth] force_model`` file (absolute path) or None. With it the truth is
    ``satgnc.forcemodel.two_satellite_params(file)``: the file's mu (must equal ``[orbit] mu``), J2
    (``[gravity] model = "j2"``) and radius, its exponential ``[drag]`` (cd, area, mass for both bodies;
    the mass must equal ``[chaser] mass``); ``[truth] atmosphere`` and the control frame as without it.
    The two-satellite model has no gravity field, Sun, Moon, SRP or density table: a file with one is
    an error naming its section."""
    return sc.sections["truth"].get("force_model")


def release_state(sc: RendezvousScenario) -> np.ndarray | None:
    """The ``[release]`` 12-state ``[r_t - r_c, r_t, v_t - v_c, v_t]`` (m, m/s, ECI) before the drift:
    target at ``[radius, 0, 0]`` with velocity ``[0, sqrt(mu / radius), 0]``; None without [release]."""
    rel = sc.sections["release"]
    if rel is None:
        return None
    mu, R = sc.sections["orbit"]["mu"], sc.sections["orbit"]["radius"]
    vc = np.sqrt(mu / R)
    d, w = rel["relative_position"], rel["relative_velocity"]
    return np.array([d[0], d[1], d[2], R, 0, 0, w[0], w[1], w[2], 0, vc, 0])


def start_state(sc: RendezvousScenario, planner=None) -> np.ndarray | None:
    """The nonlinear start: the release state after ``drift_time`` s of RK4 (``drift_steps`` steps) on
    the planner model (default: the scenario's ``[planner]``); None without [release]."""
    from .. import _satgnc as _c

    x = release_state(sc)
    if x is None:
        return None
    rel = sc.sections["release"]
    if rel["drift_time"] == 0.0:
        return x
    p = _params(sc, "planner") if planner is None else planner
    return np.asarray(_c.TwoSatelliteModel(p).propagate(4, x, rel["drift_time"], rel["drift_steps"]))


def problem(sc: RendezvousScenario, case: str, model: str = "linear", x0_eci=None):
    """The :class:`satgnc.guidance.RendezvousProblem` of ``case`` for ``model`` (``"linear"`` or
    ``"nonlinear"``: the nonlinear model takes the case's ``[cases.<name>.nonlinear]`` terminal
    condition when given). ``x0_eci``: the nonlinear start (default: :func:`start_state`)."""
    from .._validate import one_of
    from ..guidance.problem import RendezvousProblem

    if not isinstance(sc, RendezvousScenario):
        raise TypeError(f"sc: must be a RendezvousScenario (see load()), got {type(sc).__name__}")
    model = one_of(model, "model", ("linear", "nonlinear"))
    if not isinstance(case, str):
        raise TypeError(f"case: must be a case name (str), got {type(case).__name__}")
    if case not in sc.cases:
        raise ValueError(f"case: unknown {case!r}; choose from {sorted(sc.cases)}")
    s, c = sc.sections, sc.cases[case]
    te = c["terminal_equality"]
    if (
        model == "nonlinear"
        and c["nonlinear"] is not None
        and c["nonlinear"]["terminal_equality"] is not None
    ):
        te = c["nonlinear"]["terminal_equality"]
    planner = _params(sc, "planner")
    return RendezvousProblem(
        mu=s["orbit"]["mu"],
        radius=s["orbit"]["radius"],
        mass=s["chaser"]["mass"],
        x0=np.r_[s["initial_state"]["position"], s["initial_state"]["velocity"]],
        tf=s["horizon"]["tf"],
        horizon=s["horizon"]["knots"] - 1,
        alpha=s["cost"]["alpha"],
        Qf=s["cost"]["Qf"],
        u_max=s["cost"]["u_max"] if c["box"] else None,
        terminal_equality=te,
        x0_eci=start_state(sc, planner) if x0_eci is None else x0_eci,
        planner=planner,
        linear_discretization=s["discretization"]["method"],
        nonlinear_discretization=s["discretization"]["nonlinear"],
        substeps=s["discretization"]["substeps"],
    )


def thruster_layout(sc: RendezvousScenario):
    """The scenario's ``[[thrusters]]`` as a :class:`satgnc.guidance.thrusters.ThrusterLayout`, or None."""
    from ..guidance.thrusters import ThrusterLayout

    rows = sc.sections.get("thrusters")
    return None if rows is None else ThrusterLayout.from_table(rows)


def keep_out(sc: RendezvousScenario):
    """The scenario's ``[keep_out]`` as a :class:`satgnc.guidance.safety.KeepOut`, or None."""
    from ..guidance.safety import KeepOut

    k = sc.sections.get("keep_out")
    return None if k is None else KeepOut(np.array(k["center"]), np.array(k["semi_axes"]))


def plume(sc: RendezvousScenario) -> dict | None:
    """The scenario's ``[plume]`` as the ``plume`` argument of :func:`satgnc.guidance.keep_out.keep_out_plan`
    (``half_angle_deg`` deg, ``range`` m), or None."""
    k = sc.sections.get("plume")
    return None if k is None else {"half_angle_deg": k["half_angle_deg"], "range": k["range"]}


def _constraint_nodes(t: dict, section: str, p, text: str, horizon: int, line) -> tuple[dict, list[int]]:
    """Pop ``nodes`` / ``from_node`` from one state-constraint table: (the rest, the node list)."""
    t = dict(t)
    nodes, start = t.pop("nodes", None), t.pop("from_node", None)

    def fail(key: str, rule: str) -> None:
        raise FileFormatError(p, line(key), f"key '{key}' in section [{section}]: {rule}", key=key)

    if nodes is not None and start is not None:
        fail("from_node", "give nodes or from_node, not both")
    if start is not None:
        if isinstance(start, bool) or not isinstance(start, int):
            fail("from_node", f"expected an integer, got {start!r}")
        if not 1 <= start <= horizon:
            fail("from_node", f"must be in 1..{horizon} (knots - 1; x_0 is given), got {start}")
        return t, list(range(start, horizon + 1))
    if nodes is None:
        return t, list(range(1, horizon + 1))
    if not isinstance(nodes, list) or not nodes or any(isinstance(k, bool) or not isinstance(k, int)
                                                        for k in nodes):
        fail("nodes", f"expected a non-empty array of integers, got {nodes!r}")
    bad = [k for k in nodes if not 1 <= k <= horizon]
    if bad:
        fail("nodes", f"nodes must be in 1..{horizon} (knots - 1; x_0 is given), got {bad[0]}")
    if len(set(nodes)) != len(nodes):
        fail("nodes", "a node repeats")
    return t, sorted(nodes)


def read_state_constraints(d: dict, p, text: str, horizon: int) -> dict:
    """The checked state-constraint sections (issue 16 item 1) of a parsed scenario: ``approach_cone``,
    ``state_box``, ``closing_velocity`` (tables) and ``half_spaces`` (array of tables), each None when
    absent, else its keys plus ``nodes`` (list). Strict as the rest of the file: an unknown key, a
    wrong type or a value out of range is a :class:`FileFormatError` naming file, line and key."""
    out: dict = {}
    for sec, schema in CONSTRAINT_SECTIONS.items():
        raw = d.get(sec)
        if raw is None:
            out[sec] = None
            continue
        many = sec == "half_spaces"
        if many != isinstance(raw, list):
            shape = f"an array of tables [[{sec}]]" if many else f"a table [{sec}]"
            raise FileFormatError(p, toml_line(text, sec) or toml_line(text, "", sec),
                                  f"{sec}: must be {shape}", key=sec)
        tables = raw if many else [raw]
        rows = []
        for i, t in enumerate(tables):
            if not isinstance(t, dict):
                shape = "an array of tables" if many else "a table"
                raise FileFormatError(p, toml_line(text, "", sec), f"{sec}: must be {shape}", key=sec)

            def line(key: str, i=i, sec=sec, many=many) -> int | None:
                return _nth_table_line(text, sec, i, key) if many else toml_line(text, sec, key)

            rest, nodes = _constraint_nodes(t, sec, p, text, horizon, line)
            row = check_toml_table(rest, schema, sec, p, text)
            where = f"[[{sec}]] number {i + 1}" if many else f"[{sec}]"

            def fail(key: str, rule: str, where=where, line=line) -> None:
                raise FileFormatError(p, line(key), f"key '{key}' in {where}: {rule}", key=key)

            if sec == "state_box":
                if row["lower"] is None and row["upper"] is None:
                    raise FileFormatError(p, toml_line(text, sec), "[state_box]: give lower, upper or both",
                                          key="state_box")
                lo = np.full(6, -np.inf) if row["lower"] is None else np.array(row["lower"])
                hi = np.full(6, np.inf) if row["upper"] is None else np.array(row["upper"])
                if np.any(lo > hi):
                    j = int(np.argmax(lo > hi))
                    fail("lower", f"must be <= upper, entry {j}: {lo[j]} > {hi[j]}")
                if np.any(lo == np.inf) or np.any(hi == -np.inf):
                    fail("lower" if np.any(lo == np.inf) else "upper", "a bound of +inf below or -inf above "
                         "admits no state")
                row["lower"], row["upper"] = lo.tolist(), hi.tolist()
            if sec == "closing_velocity":
                if not row["intercept"]:
                    fail("intercept", "must hold at least one segment")
                if len(row["intercept"]) != len(row["slope"]):
                    fail("slope", f"must have one entry per segment, as intercept ({len(row['slope'])} vs "
                         f"{len(row['intercept'])})")
            row["nodes"] = nodes
            rows.append(row)
        out[sec] = rows if many else rows[0]
    return out


def state_constraints(sc: RendezvousScenario) -> dict:
    """The scenario's state constraints as keyword arguments of :class:`satgnc.guidance.L1Solver`
    (``half_spaces``, ``state_lower`` / ``state_upper`` / ``state_box_nodes``, ``approach_cone``,
    ``closing_velocity``; units m, m/s on the CW state [position, velocity]); empty without any."""
    s, kw = sc.sections, {}
    hs = s.get("half_spaces")
    if hs:
        nodes = [k for h in hs for k in h["nodes"]]
        kw["half_spaces"] = {"nodes": nodes, "a": np.array([h["a"] for h in hs for _ in h["nodes"]]),
                             "b": np.array([h["b"] for h in hs for _ in h["nodes"]])}
    box = s.get("state_box")
    if box:
        kw.update(state_lower=np.array(box["lower"]), state_upper=np.array(box["upper"]),
                  state_box_nodes=box["nodes"])
    cone = s.get("approach_cone")
    if cone:
        kw["approach_cone"] = {"nodes": cone["nodes"], "axis": np.array(cone["axis"]),
                               "half_angle_deg": cone["half_angle_deg"], "apex_offset": cone["apex_offset"]}
    cv = s.get("closing_velocity")
    if cv:
        kw["closing_velocity"] = {"nodes": cv["nodes"], "axis": np.array(cv["axis"]),
                                  "intercept": np.array(cv["intercept"]), "slope": np.array(cv["slope"])}
    return kw
