"""The plume-impingement cone in the scenario TOML (issue 16): ``[plume] half_angle_deg, range`` read
with units, strict (unknown keys and bad values name file, line, key and section), passed by
``satgnc rendezvous --keep-out`` to the keep-out SCP (satgnc.guidance.keep_out.keep_out_plan, plume)."""

from __future__ import annotations

import json

import pytest
from _helpers import write
from satgnc import FileFormatError, cli
from satgnc.guidance.thrusters import cube_layout
from satgnc.scenarios import rendezvous

# the braking case of test_keep_out_plume.py: closing at 0.2 m/s from 150 m on the V-bar to a hold
# point 40 m out, 20 m sphere, 1200 s in 20 intervals, 0.5 N thrusters
BASE = """name = "plume"
[orbit]
mu = 3.986004418e14     # m^3/s^2
radius = 7231.0e3       # m
[chaser]
mass = 100.0            # kg
[initial_state]
position = [150.0, 0.0, 0.0]   # m
velocity = [-0.2, 0.0, 0.0]    # m/s
[horizon]
tf = 1200.0             # s
knots = 21
[cost]
alpha = 1.0
Qf = 0.0
u_max = 0.5             # N
[cases.hard]
rho = 1.0
eps = 1e-6
box = true
terminal_equality = true
[keep_out]
semi_axes = [20.0, 20.0, 20.0]   # m
hold_point = [40.0, 0.0, 0.0]    # m
"""
PLUME = """[plume]
half_angle_deg = 45.0   # deg
range = 200.0           # m
"""


def thrusters() -> str:
    """The canted 12-thruster cube of satgnc.guidance.thrusters.cube_layout(0.5) as [[thrusters]]."""
    lay = cube_layout(0.5)
    return "".join(f'[[thrusters]]\nname = "{n}"\ndirection = [{", ".join(repr(float(c)) for c in d)}]\n'
                   "max_thrust = 0.5\n" for n, d in zip(lay.names, lay.directions))


def test_plume_section_read_with_units(tmp_path):
    sc = rendezvous.load(write(tmp_path, BASE + thrusters() + PLUME))
    assert rendezvous.plume(sc) == {"half_angle_deg": 45.0, "range": 200.0}
    assert sc.sections["plume"] == {"half_angle_deg": 45.0, "range": 200.0}
    # absent: None, and the file reads as before
    sc0 = rendezvous.load(write(tmp_path, BASE + thrusters(), "b.toml"))
    assert rendezvous.plume(sc0) is None and sc0.sections["plume"] is None


@pytest.mark.parametrize(
    "old, new, msg",
    [
        ("range = 200.0           # m", "range = 200.0\nangle = 3.0",
         "unknown key 'angle' in section [plume]"),
        ("half_angle_deg = 45.0   # deg", "half_angle_deg = 95.0",
         "key 'half_angle_deg' in section [plume] (deg): must be <= 90"),
        ("range = 200.0           # m", "range = 0.0", "key 'range' in section [plume] (m): must be > 0"),
        ("range = 200.0           # m", 'range = "far"', "key 'range' in section [plume]"),
        ("range = 200.0           # m", "", "missing key 'range' in section [plume]"),
    ],
)
def test_bad_plume_keys_name_file_line_key_and_section(tmp_path, old, new, msg):
    text = BASE + thrusters() + PLUME
    assert old in text
    bad = text.replace(old, new, 1)
    p = write(tmp_path, bad)
    with pytest.raises(FileFormatError) as e:
        rendezvous.load(p)
    assert msg in str(e.value), str(e.value)
    assert str(p) in str(e.value)
    if new.startswith(("range", "half_angle_deg")) or "angle =" in new:  # the line of the offending key
        key = new.split("\n")[-1].split("=")[0].strip()
        line = bad.splitlines().index(next(s for s in bad.splitlines() if s.startswith(key + " ="))) + 1
        assert e.value.line == line, (e.value.line, line)


def test_plume_without_thrusters_is_an_error_naming_the_section(tmp_path):
    text = BASE + PLUME
    p = write(tmp_path, text)
    with pytest.raises(FileFormatError) as e:
        rendezvous.load(p)
    assert "[plume]: needs [[thrusters]]" in str(e.value) and str(p) in str(e.value)
    assert e.value.line == text.splitlines().index("[plume]") + 1


def test_cli_keep_out_with_the_plume_cone(tmp_path, capsys):
    # the keep-out plan of the scenario with its [plume]: the json carries the cone and its outcome;
    # measured 2026-12-03 (as test_keep_out_plume.py's cube case): solved, inhibitions > 0, no impinging
    # firing on the returned plan (nodes and every flown sample)
    p = write(tmp_path, BASE + thrusters() + PLUME)
    out = tmp_path / "out"
    assert cli.main(["rendezvous", "--scenario", str(p), "--keep-out", "--out", str(out)]) == 0
    d = json.loads((out / "keep_out_hard.json").read_text())
    assert d["plume_half_angle_deg"] == 45.0 and d["plume_range_m"] == 200.0
    assert d["status"] == "solved" and d["converged"] and d["satisfied_nodes"] and d["satisfied_flown"]
    assert d["plume_inhibited"] > 0 and d["plume_violations"] == 0
    assert "plume cone 45 deg within 200 m" in capsys.readouterr().out
