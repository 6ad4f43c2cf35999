"""Scenario TOML of issue 16 ([[thrusters]], [keep_out], [passive_safety], [failures]) and the CLI
``satgnc rendezvous --scenario X.toml --failures / --passive-safety / --min-time``."""

from __future__ import annotations

import json

import numpy as np
import pytest
from _helpers import write
from satgnc import FileFormatError, cli
from satgnc.scenarios import rendezvous

BASE = """name = "guid16"
[orbit]
mu = 3.986004418e14     # m^3/s^2
radius = 7231.0e3       # m
[chaser]
mass = 100.0            # kg
[initial_state]
position = [120.0, -60.0, 30.0]   # m
velocity = [0.0, 0.0, 0.001]      # m/s
[horizon]
tf = 2400.0             # s
knots = 41
[cost]
alpha = 1.0
Qf = 0.0
u_max = 0.5             # N
[cases.hard]
rho = 1.0
eps = 1e-6
box = true
terminal_equality = true
"""

THRUSTERS = """
[[thrusters]]
name = "+x"
direction = [1.0, 0.0, 0.0]
max_thrust = 0.5        # N
min_impulse_bit = 0.01  # N s
[[thrusters]]
name = "-x"
direction = [-1.0, 0.0, 0.0]
max_thrust = 0.5
[[thrusters]]
name = "+y"
direction = [0.0, 1.0, 0.0]
max_thrust = 0.5
position = [0.0, -0.5, 0.0]
[[thrusters]]
name = "-y"
direction = [0.0, -1.0, 0.0]
max_thrust = 0.5
[[thrusters]]
name = "+z"
direction = [0.0, 0.0, 1.0]
max_thrust = 0.5
[keep_out]
semi_axes = [20.0, 20.0, 20.0]   # m
[passive_safety]
drift_time = 1800.0     # s
samples = 60
[failures]
pairs = false
"""


def test_sections_read_with_units_and_defaults(tmp_path):
    sc = rendezvous.load(write(tmp_path, BASE + THRUSTERS))
    lay = rendezvous.thruster_layout(sc)
    assert lay.names == ("+x", "-x", "+y", "-y", "+z")
    assert lay.min_impulse_bit.tolist() == [0.01, 0.0, 0.0, 0.0, 0.0]
    assert lay.positions[2].tolist() == [0.0, -0.5, 0.0]
    ko = rendezvous.keep_out(sc)
    assert ko.semi_axes.tolist() == [20.0] * 3 and ko.center.tolist() == [0.0] * 3
    assert sc.sections["passive_safety"] == {"drift_time": 1800.0, "samples": 60}
    # a file without them reads as before
    sc0 = rendezvous.load(write(tmp_path, BASE, "b.toml"))
    assert rendezvous.thruster_layout(sc0) is None and rendezvous.keep_out(sc0) is None
    assert sc0.sections["failures"] == {"pairs": False}


@pytest.mark.parametrize(
    "old, new, msg",
    [
        ("max_thrust = 0.5        # N", "max_thrust = 0.5\nthrust = 1.0",
         "unknown key 'thrust' in section [thrusters]"),
        ("direction = [1.0, 0.0, 0.0]", "direction = [1.0, 1.0, 0.0]",
         "key 'direction' in [[thrusters]] number 1: must be a unit vector, got norm 1.4142135623730951"),
        ("max_thrust = 0.5        # N", "max_thrust = -0.5",
         "key 'max_thrust' in section [thrusters] (N): must be > 0"),
        ("semi_axes = [20.0, 20.0, 20.0]   # m", "semi_axes = [20.0, 0.0, 20.0]",
         "key 'semi_axes' in section [keep_out] (m): must be > 0"),
        ("samples = 60", "samples = 60\nhorizon = 3", "unknown key 'horizon' in section [passive_safety]"),
        ("pairs = false", "pair = false", "unknown key 'pair' in section [failures]"),
        ('name = "-x"', 'name = "+x"', "key 'name' in [[thrusters]]: names must be unique, '+x' repeats"),
    ],
)
def test_bad_keys_name_the_key_section_and_line(tmp_path, old, new, msg):
    text = BASE + THRUSTERS
    assert old in text
    p = write(tmp_path, text.replace(old, new, 1))
    with pytest.raises(FileFormatError) as e:
        rendezvous.load(p)
    assert msg in str(e.value)
    assert str(p) in str(e.value)
    if "number 1" in msg:  # the line of the first [[thrusters]]' direction
        line = (text.replace(old, new, 1)).splitlines().index("direction = [1.0, 1.0, 0.0]") + 1
        assert f":{line}" in str(e.value) or f"line {line}" in str(e.value)


def test_cli_failures_table(tmp_path, capsys):
    p = write(tmp_path, BASE + THRUSTERS)
    out = tmp_path / "out"
    assert cli.main(["rendezvous", "--scenario", str(p), "--failures", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    # the hand-derived row: the only z thruster lost, rank 4, distance 0 to round-off
    row = next(line for line in text.splitlines() if line.startswith("| +z |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[1:3] == ["4/6", "rank deficient"] and float(cells[3]) <= 1e-12 and cells[5] == "not_run"
    d = json.loads((out / "failures_hard.json").read_text())
    assert len(d["rows"]) == 6
    nominal = d["rows"][0]
    assert nominal["status"] == "solved" and nominal["certified"] and np.isfinite(nominal["miss"])
    assert (out / "failures_hard.md").exists()


def test_cli_failures_without_thrusters_is_an_error(tmp_path, capsys):
    p = write(tmp_path, BASE)
    assert cli.main(["rendezvous", "--scenario", str(p), "--failures", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "--failures: the scenario" in err and "has no [[thrusters]] tables" in err


def test_cli_passive_safety_and_min_time(tmp_path, capsys):
    p = write(tmp_path, BASE + THRUSTERS)
    out = tmp_path / "out"
    argv = ["rendezvous", "--scenario", str(p), "--passive-safety", "--min-time", "--out", str(out)]
    assert cli.main(argv) == 0
    text = capsys.readouterr().out
    assert "passive safety over 1800 s" in text and "Minimum time" in text
    assert (out / "passive_safety_hard.png").stat().st_size > 10_000
    assert (out / "fuel_time_hard.png").stat().st_size > 10_000


def _hold_point_scenario(tmp_path):
    # The keep-out scenario with a hold point at -40 m on the V-bar, approached along it.
    text = (BASE + THRUSTERS).replace("semi_axes = [20.0, 20.0, 20.0]   # m",
                                      "semi_axes = [20.0, 20.0, 20.0]   # m\nhold_point = [-40.0, 0.0, 0.0]")
    text = text.replace("position = [120.0, -60.0, 30.0]", "position = [120.0, 0.0, 0.0]")
    return write(tmp_path, text.replace("velocity = [0.0, 0.0, 0.001]", "velocity = [-0.001, 0.0, 0.0]"))


def test_cli_keep_out_with_clarabel_subproblems(tmp_path, capsys):
    p = _hold_point_scenario(tmp_path)
    out = tmp_path / "out"
    argv = ["rendezvous", "--scenario", str(p), "--keep-out", "--subproblem", "cvxpy", "--out", str(out)]
    assert cli.main(argv) == 0
    d = json.loads((out / "keep_out_hard.json").read_text())
    assert d["satisfied_nodes"] and d["satisfied_flown"] and d["min_node_rho"] >= 1.05 - 1e-6


def test_cli_keep_out_with_passive_safety_imposed(tmp_path, capsys):
    # --keep-out --passive-safety: the scenario's [passive_safety] drift imposed in the keep-out SCP
    # (engine subproblems) and checked on the [truth]; the json carries the verdict, the figure is drawn
    p = _hold_point_scenario(tmp_path)
    out = tmp_path / "out"
    argv = ["rendezvous", "--scenario", str(p), "--keep-out", "--passive-safety", "--out", str(out)]
    assert cli.main(argv) == 0
    d = json.loads((out / "keep_out_hard.json").read_text())
    assert d["status"] == "solved" and d["satisfied_nodes"] and d["satisfied_flown"]
    assert d["passive_drift_time_s"] == 1800.0
    assert d["passive_nodes"] == 39  # nodes 1..N-1 of N = 40
    # measured 2026-12-03: all 39 drifts safe on the truth (smallest radius 1.78), no remaining slack
    assert d["passive_nodes_safe"] == 39 and d["passive_min_rho"] >= 1.0 and d["drift_slack_m"] <= 1e-6
    assert (out / "keep_out_passive_hard.png").stat().st_size > 10_000
    assert "drift nodes safe on the truth" in capsys.readouterr().out
