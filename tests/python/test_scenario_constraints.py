"""Scenario TOML keys of the state constraints (issue 16 items 1 and 5): ``[approach_cone]``,
``[state_box]``, ``[closing_velocity]``, ``[[half_spaces]]``; strict (every bad key or value names file,
line and key); the fuel-optimal plan under them (``satgnc.guidance.constrained``) against cvxpy +
Clarabel; ``satgnc rendezvous --constrained`` on the shipped example ``cone_approach.toml``."""

from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest
from _helpers import write
from satgnc import FileFormatError, cli
from satgnc.guidance.constrained import constrained_plan, constraint_violation
from satgnc.scenarios import rendezvous

EXAMPLE = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python" / "cone_approach.toml"
BOX = """
[state_box]             # stay below 150 m radial and within +-20 m out of plane the whole way
lower = [-inf, -inf, -20.0, -inf, -inf, -inf]
upper = [inf, 150.0, 20.0, inf, inf, inf]
"""
TEXT = EXAMPLE.read_text() + BOX
N = 40  # knots - 1 of the example
CASE = TEXT.split("[cases.dock]")[1].split("[state_box]")[0]

HS = """
[[half_spaces]]         # stay below y = 140 m at nodes 1..5
a = [0.0, 1.0, 0.0, 0.0, 0.0, 0.0]
b = 140.0
nodes = [1, 2, 3, 4, 5]
[[half_spaces]]         # x <= 0 (behind the target) from node 30 on
a = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]
b = 0.0
from_node = 30
"""


def test_every_key_reads_with_units_and_defaults(tmp_path):
    sc = rendezvous.load(write(tmp_path, TEXT + HS))
    s = sc.sections
    assert s["approach_cone"] == {"axis": [-1.0, 0.0, 0.0], "half_angle_deg": 15.0, "apex_offset": -5.0,
                                  "nodes": list(range(20, N + 1))}
    assert s["closing_velocity"] == {"axis": [-1.0, 0.0, 0.0], "intercept": [0.05], "slope": [0.002],
                                     "nodes": list(range(20, N + 1))}
    assert s["state_box"]["lower"] == [-np.inf, -np.inf, -20.0, -np.inf, -np.inf, -np.inf]
    assert s["state_box"]["upper"] == [np.inf, 150.0, 20.0, np.inf, np.inf, np.inf]
    assert s["state_box"]["nodes"] == list(range(1, N + 1))  # neither nodes nor from_node: every node
    assert [h["nodes"] for h in s["half_spaces"]] == [[1, 2, 3, 4, 5], list(range(30, N + 1))]
    kw = rendezvous.state_constraints(sc)
    assert sorted(kw) == ["approach_cone", "closing_velocity", "half_spaces", "state_box_nodes",
                          "state_lower", "state_upper"]
    assert kw["half_spaces"]["a"].shape == (5 + 11, 6)
    assert kw["half_spaces"]["b"].tolist()[4:6] == [140.0, 0.0]
    assert kw["approach_cone"]["half_angle_deg"] == 15.0
    # a file without them reads as before and gives no keywords
    base = TEXT.split("[approach_cone]")[0] + "[cases.dock]" + CASE
    sc0 = rendezvous.load(write(tmp_path, base, "b.toml"))
    assert all(sc0.sections[k] is None for k in rendezvous.CONSTRAINT_SECTIONS)
    assert rendezvous.state_constraints(sc0) == {}


def test_apex_offset_and_per_segment_limits(tmp_path):
    t = TEXT.replace("apex_offset = -5.0 ", "apex_offset = -2.5").replace(
        "intercept = [0.05] ", "intercept = [0.05, 0.2]").replace("slope = [0.002] ", "slope = [0.002, 0.0]")
    s = rendezvous.load(write(tmp_path, t)).sections
    assert s["approach_cone"]["apex_offset"] == -2.5
    assert s["closing_velocity"]["intercept"] == [0.05, 0.2]
    assert s["closing_velocity"]["slope"] == [0.002, 0.0]


CONE = "half_angle_deg = 15.0"
FN = "from_node = 20          # active"
IN_CONE = "in section [approach_cone]"
BAD = [
    # (old, new, the message, the key whose line is named)
    ("apex_offset = -5.0 ", "apex_offset = -5.0\nangle = 3.0 ", f"unknown key 'angle' {IN_CONE}",
     "angle"),
    (CONE, "half_angle_deg = 90.0", "key 'half_angle_deg' in section [approach_cone] (deg): must be <= 89.99",
     "half_angle_deg"),
    (CONE, "half_angle_deg = 0.0", "key 'half_angle_deg' in section [approach_cone] (deg): must be > 0",
     "half_angle_deg"),
    (CONE, 'half_angle_deg = "15"', f"key 'half_angle_deg' {IN_CONE} (deg): expected a number",
     "half_angle_deg"),
    ("axis = [-1.0, 0.0, 0.0]\nhalf", "axis = [0.0, 0.0, 0.0]\nhalf",
     "key 'axis' in section [approach_cone] (docking axis, CW frame): must not be all zero", "axis"),
    ("axis = [-1.0, 0.0, 0.0]\nhalf", "axis = [-1.0, 0.0]\nhalf",
     f"key 'axis' {IN_CONE} (docking axis, CW frame): expected an array of 3 numbers", "axis"),
    ("apex_offset = -5.0 ", "apex_offset = true ", f"key 'apex_offset' {IN_CONE} (m): expected "
     "a number, got boolean true", "apex_offset"),
    (FN, "from_node = 0          # active",
     "key 'from_node' in section [approach_cone]: must be in 1..40", "from_node"),
    (FN, "from_node = 20.0        # active",
     "key 'from_node' in section [approach_cone]: expected an integer", "from_node"),
    (FN, "nodes = [0, 1]  # active", f"key 'nodes' {IN_CONE}: nodes must "
     "be in 1..40", "nodes"),
    (FN, "nodes = [39, 41]  # active", f"key 'nodes' {IN_CONE}: nodes "
     "must be in 1..40", "nodes"),
    (FN, "nodes = [3, 3]  # active", f"key 'nodes' {IN_CONE}: a node "
     "repeats", "nodes"),
    (FN, "nodes = [3.0]  # active", f"key 'nodes' {IN_CONE}: expected a "
     "non-empty array of integers", "nodes"),
    (FN, "nodes = []  # active", f"key 'nodes' {IN_CONE}: expected a "
     "non-empty array of integers", "nodes"),
    (FN, "from_node = 20\nnodes = [21]  # active", f"key 'from_node' {IN_CONE}: "
     "give nodes or from_node, not both", "from_node"),
    ("slope = [0.002] ", "slope = [0.002, 0.001]", "key 'slope' in [closing_velocity]: must have one entry "
     "per segment, as intercept (2 vs 1)", "slope"),
    ("intercept = [0.05] ", "intercept = []", "key 'intercept' in [closing_velocity]: must hold at least one "
     "segment", "intercept"),
    ("slope = [0.002] ", "slope = [nan]", "key 'slope' in section [closing_velocity] (1/s, one per segment): "
     "must be finite", "slope"),
    ("slope = [0.002] ", "slopes = [0.002]", "unknown key 'slopes' in section [closing_velocity]", "slopes"),
    ("lower = [-inf, -inf, -20.0,", "lower = [-inf, -inf, 30.0,", "key 'lower' in [state_box]: must be <= "
     "upper, entry 2: 30.0 > 20.0", "lower"),
    ("lower = [-inf, -inf, -20.0,", "lower = [nan, -inf, -20.0,", "key 'lower' in section [state_box] "
     "(m, m/s; -inf: no bound): must not hold nan", "lower"),
    ("lower = [-inf, -inf, -20.0, -inf, -inf, -inf]", "lower = [-inf, -inf, -20.0]", "key 'lower' in "
     "section [state_box] (m, m/s; -inf: no bound): expected an array of 6 numbers", "lower"),
    ("upper = [inf, 150.0, 20.0, inf, inf, inf]", "upper = [inf, 150.0, 20.0, inf, inf, -inf]",
     "key 'upper' in [state_box]: a bound of +inf below or -inf above admits no state", "upper"),
    ("lower = [-inf, -inf, -20.0, -inf, -inf, -inf]\nupper = [inf, 150.0, 20.0, inf, inf, inf]",
     "from_node = 2", "[state_box]: give lower, upper or both", "[state_box]"),
]


@pytest.mark.parametrize("old, new, msg, key", BAD)
def test_bad_keys_name_file_line_and_key(tmp_path, old, new, msg, key):
    assert old in TEXT, old
    text = TEXT.replace(old, new, 1)
    p = write(tmp_path, text)
    with pytest.raises(FileFormatError) as e:
        rendezvous.load(p)
    s = str(e.value)
    assert msg in s and str(p) in s
    # the line named is the key's (or the section header's) line in the file
    lines = text.splitlines()
    want = next(i for i, ln in enumerate(lines, 1) if ln.startswith(key))
    assert f":{want}:" in s, (s, want)


BAD_HS = [
    ("b = 140.0", "b = 140.0\nc = 1.0", "unknown key 'c' in section [half_spaces]"),
    ("b = 140.0", "", "missing key 'b' in section [half_spaces]"),
    ("a = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]", "a = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]",
     "key 'a' in section [half_spaces] (row on [position m, velocity m/s]): must not be all zero"),
    ("a = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]", "a = [1.0, 0.0, 0.0]",
     "key 'a' in section [half_spaces] (row on [position m, velocity m/s]): expected an array of 6 numbers"),
    ("from_node = 30", "from_node = 41", "key 'from_node' in section [half_spaces]: must be in 1..40"),
    ("[[half_spaces]]         # x", "[half_spaces.x]         # x", "half_spaces: must be an array of tables "
     "[[half_spaces]]"),
]


@pytest.mark.parametrize("old, new, msg", BAD_HS)
def test_bad_half_spaces(tmp_path, old, new, msg):
    text = TEXT + HS
    assert old in text
    if new.startswith("[half_spaces.x]"):  # a table instead of an array of tables
        text = TEXT + "\n[half_spaces]\na = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]\nb = 0.0\n"
    else:
        text = text.replace(old, new, 1)
    p = write(tmp_path, text)
    with pytest.raises(FileFormatError) as e:
        rendezvous.load(p)
    assert msg in str(e.value) and str(p) in str(e.value)
    if "from_node" in msg:  # the line of the second [[half_spaces]]' from_node
        line = text.splitlines().index("from_node = 41") + 1
        assert f":{line}:" in str(e.value)


def _clarabel(pb, kw):
    """The same LP (fuel, exact arrival, per-axis box) with the same constraints in cvxpy + Clarabel."""
    cp = pytest.importorskip("cvxpy")
    from satgnc.guidance import cw_discretize

    Ad, Bd = cw_discretize(pb.n, pb.mass, pb.dt, "zoh")
    X, U = cp.Variable((pb.horizon + 1, 6)), cp.Variable((pb.horizon, 3))
    cons = [X[0] == pb.x0, X[pb.horizon] == 0, cp.abs(U) <= pb.u_max]
    cons += [X[k + 1] == Ad @ X[k] + Bd @ U[k] for k in range(pb.horizon)]
    c = kw.get("approach_cone")
    if c:
        ax = np.asarray(c["axis"]) / np.linalg.norm(c["axis"])
        t = np.tan(np.deg2rad(c["half_angle_deg"]))
        for k in c["nodes"]:
            p = X[k, :3]
            cons.append(cp.norm(p - (ax @ p) * ax) <= t * (ax @ p - c["apex_offset"]))
    v = kw.get("closing_velocity")
    if v:
        ax = np.asarray(v["axis"]) / np.linalg.norm(v["axis"])
        for k in v["nodes"]:
            for i0, s0 in zip(v["intercept"], v["slope"], strict=True):
                cons.append(cp.abs(ax @ X[k, 3:]) <= i0 + s0 * (ax @ X[k, :3]))
    if "state_lower" in kw:
        lo, hi = kw["state_lower"], kw["state_upper"]
        for k in kw["state_box_nodes"]:
            for i in range(6):
                if np.isfinite(lo[i]):
                    cons.append(X[k, i] >= lo[i])
                if np.isfinite(hi[i]):
                    cons.append(X[k, i] <= hi[i])
    h = kw.get("half_spaces")
    if h:
        cons += [h["a"][i] @ X[k] <= h["b"][i] for i, k in enumerate(h["nodes"])]
    prob = cp.Problem(cp.Minimize(pb.dt * cp.sum(cp.abs(U))), cons)
    prob.solve(solver=cp.CLARABEL)
    return prob.status, prob.value


@pytest.mark.parametrize("family", ["approach_cone", "closing_velocity", "state_box", "half_spaces",
                                    "cone+closing_velocity"])
def test_plan_under_each_family_matches_clarabel(tmp_path, family):
    sc = rendezvous.load(write(tmp_path, TEXT + HS))
    kw = rendezvous.state_constraints(sc)
    keys = {"state_box": ("state_lower", "state_upper", "state_box_nodes"),
            "cone+closing_velocity": ("approach_cone", "closing_velocity")}.get(family, (family,))
    kw = {k: kw[k] for k in keys}
    pb = rendezvous.problem(sc, "dock", "linear")
    r = constrained_plan(pb, **kw)
    st, ref = _clarabel(pb, kw)
    assert st == "optimal"
    # an honest status: solved only with violation, residuals and gap within their tolerances; any other
    # status still reports the true cost of its plan
    assert r.status in ("solved", "max_iterations", "solved_inaccurate"), r.status
    assert r.fuel == pytest.approx(float(np.abs(r.U).sum() * pb.dt), rel=1e-12)
    if r.status == "solved":
        assert abs(r.fuel - ref) <= 1e-6 * ref  # the 1e-6 relative objective check
        # re-checked in numpy at the nodes: within the engine's tolerance (eps_abs + eps_rel |X|inf)
        assert max(r.violation.values()) <= r.violation_tolerance
        assert r.violation_tolerance <= 1e-5 * max(1.0, float(np.abs(r.X).max()))
    else:  # what holds is reported: never a better-than-optimal cost with the constraints met
        assert r.fuel >= ref * (1 - 1e-6) or max(r.violation.values()) > 0


def test_constraint_violation_is_independent_of_the_engine():
    X = np.zeros((3, 6))
    X[1, :3] = [-10.0, 5.0, 0.0]  # 26.6 deg off -x
    X[2, :3] = [-10.0, 1.0, 0.0]
    X[1, 3] = 0.5
    cone = {"nodes": [1, 2], "axis": [-1.0, 0.0, 0.0], "half_angle_deg": 15.0}
    v = constraint_violation(X, {"approach_cone": cone})
    assert v["approach_cone"] == pytest.approx(5.0 - np.tan(np.deg2rad(15.0)) * 10.0, rel=1e-12)
    cv = {"nodes": [1], "axis": [-1.0, 0.0, 0.0], "intercept": [0.05, 0.3], "slope": [0.002, 0.0]}
    # |a.v| = 0.5, limit min(0.05 + 0.02, 0.3) = 0.07
    assert constraint_violation(X, {"closing_velocity": cv})["closing_velocity"] == pytest.approx(0.43)
    box = {"state_lower": np.full(6, -np.inf), "state_upper": np.array([np.inf, 2.0, np.inf, 1, 1, 1]),
           "state_box_nodes": [1, 2]}
    assert constraint_violation(X, box)["state_box"] == pytest.approx(3.0)
    hs = {"nodes": [2], "a": np.array([[0.0, 1.0, 0, 0, 0, 0]]), "b": np.array([0.5])}
    assert constraint_violation(X, {"half_spaces": hs})["half_spaces"] == pytest.approx(0.5)


def test_cli_constrained_on_the_shipped_example(tmp_path, capsys):
    out = tmp_path / "out"
    assert cli.main(["rendezvous", "--scenario", str(EXAMPLE), "--constrained", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert text.startswith("dock: constrained plan (approach_cone, closing_velocity) solved in ")
    d = json.loads((out / "constrained_dock.json").read_text())
    assert d["status"] == "solved"
    assert max(d["violation"].values()) <= d["violation_tolerance"]
    assert d["fuel_Ns"] == pytest.approx(d["dv_mps"] * 100.0, rel=1e-12)
    assert d["truth_miss_m"] < 5.0  # the linear plan flown open loop on J2 (measured: see docs/scenarios.md)


def test_cli_constrained_without_constraints_is_one_line_exit_2(tmp_path, capsys):
    base = TEXT.split("[approach_cone]")[0] + "[cases.dock]" + CASE
    p = write(tmp_path, base)
    assert cli.main(["rendezvous", "--scenario", str(p), "--constrained", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert "has no [approach_cone], [state_box], [closing_velocity] or [[half_spaces]]" in err[0]


def test_cli_bad_constraint_key_is_one_line_exit_2(tmp_path, capsys):
    p = write(tmp_path, TEXT.replace("half_angle_deg = 15.0", "half_angle_deg = 95.0"))
    assert cli.main(["rendezvous", "--scenario", str(p), "--constrained", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "half_angle_deg" in err[0] and str(p) in err[0]


def test_plan_with_a_thruster_layout_equals_the_box_plan():
    # six one-sided thrusters of 0.5 N on +-x, +-y, +-z carry the same L1 optimum as the 0.5 N per-axis
    # box (|u| = T+ + T- at the optimum): the cone + closing-velocity example, fuel within 1e-6
    from satgnc.guidance.thrusters import axis_layout

    sc = rendezvous.load(EXAMPLE)
    kw = rendezvous.state_constraints(sc)
    pb = rendezvous.problem(sc, "dock", "linear")
    a = constrained_plan(pb, **kw)
    b = constrained_plan(pb, layout=axis_layout(0.5), **kw)
    assert a.status == b.status == "solved"
    assert b.U.shape == (N, 6) and np.all(b.U >= 0.0)
    assert abs(a.fuel - b.fuel) <= 1e-6 * a.fuel
    assert np.abs(b.forces).max() <= 0.5 + 1e-9
    assert max(b.violation.values()) <= b.violation_tolerance


def test_cli_without_constrained_says_the_constraints_are_not_applied(tmp_path, capsys):
    assert cli.main(["rendezvous", "--scenario", str(EXAMPLE), "--out", str(tmp_path / "o")]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == ("note: the scenario's [approach_cone], [closing_velocity] apply with --constrained; "
                        "the cases below are planned without them")
    assert lines[1].startswith("dock: solved")
