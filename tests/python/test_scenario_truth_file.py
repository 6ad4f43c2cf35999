"""Issue 14: the rendezvous scenario's ``[truth] force_model`` names a force-model TOML (relative to
the scenario file) that sets the two-satellite truth. The truth read from the file equals the truth
built by hand from the same numbers bit for bit (every field, an RK4 propagation and a CVODES
flight); every bad file is a one-line error naming the file, the line and the key."""

from __future__ import annotations

import math

import numpy as np
import pytest
import satgnc
from satgnc import _satgnc as _c
from satgnc import cli
from satgnc.guidance import fly, satellite_params
from satgnc.scenarios import rendezvous as rv

SCENARIO = """
name = "truth_from_file"

[orbit]
mu = 3.986004418e14     # m^3/s^2
radius = 6778.0e3       # m

[chaser]
mass = 12.0             # kg

[initial_state]
position = [-400.0, 120.0, 15.0]   # m
velocity = [0.35, -0.12, 0.01]     # m/s

[horizon]
tf = 1200.0
knots = 13

[cost]
alpha = 1.0
Qf = 1000.0
u_max = 2.0e-2

[truth]
force_model = "models/truth.toml"
atmosphere = "co_rotating"

[cases.hop]
rho = 0.1
eps = 1.0e-4
box = true
"""

FORCE_MODEL = """
[central_body]
mu = 398600.4418        # km^3/s^2
radius = 6378.1363      # km

[gravity]
model = "j2"
j2 = 1.08262668e-3

[drag]
atmosphere = "exponential"
area = 0.05             # m^2
mass = 12.0             # kg
cd = 2.2
rho0 = 3.725e-12        # kg/m^3 at h0
h0 = 400.0              # km
scale_height = 58.515   # km
"""

FIELDS = ("mu", "j2_on", "j2", "j2_radius", "drag_on", "rho0", "density_decay", "density_radius",
          "mass_chaser", "mass_target", "cd_chaser", "cd_target", "area_chaser", "area_target")


def _write(tmp_path, scenario=SCENARIO, force_model=FORCE_MODEL):
    (tmp_path / "models").mkdir(exist_ok=True)
    (tmp_path / "models" / "truth.toml").write_text(force_model)
    p = tmp_path / "scenario.toml"
    p.write_text(scenario)
    return p


def _hand_built():
    """The same truth typed by hand: the file's numbers in SI, the drag rewritten as the
    two-satellite model's rho0 exp(-decay (|r| - radius)) (docs/force_models.md)."""
    p = satellite_params(3.986004418e14, j2=True, drag=True, mass=12.0)
    p.mu = 398600.4418 * 1e9
    p.j2 = 1.08262668e-3
    p.j2_radius = 6378.1363 * 1e3
    p.rho0 = 3.725e-12 * math.exp(400.0 / 58.515)  # libm exp, as std::exp in the reader
    p.density_decay = 1.0 / (58.515 * 1e3)
    p.density_radius = 6378.1363 * 1e3
    p.omega = np.array([0.0, 0.0, 7.292115e-5])  # the force model's co-rotating atmosphere
    p.mass_target = 12.0
    p.cd_chaser = p.cd_target = 2.2
    p.area_chaser = p.area_target = 0.05
    return p


def test_truth_from_file_equals_hand_built_bit_for_bit(tmp_path):
    sc = rv.load(_write(tmp_path))
    assert rv.truth_force_model(sc) == (tmp_path / "models" / "truth.toml").resolve()
    tf, th = rv.truth_params(sc), _hand_built()
    for f in FIELDS:
        assert getattr(tf, f) == getattr(th, f), f  # bit for bit, field by field
    np.testing.assert_array_equal(tf.omega, th.omega)
    assert (tf.atmosphere, tf.control_frame) == (th.atmosphere, th.control_frame)
    x0 = rv.problem(sc, "hop", "nonlinear").state_eci()
    xf = np.asarray(_c.TwoSatelliteModel(tf).propagate(4, x0, 1200.0, 120))
    np.testing.assert_array_equal(xf, np.asarray(_c.TwoSatelliteModel(th).propagate(4, x0, 1200.0, 120)))
    U = np.full((12, 3), 1e-3)
    ff, fh = fly(tf, x0, U, 100.0), fly(th, x0, U, 100.0)
    assert ff.X.shape == (13, 12)
    np.testing.assert_array_equal(ff.X, fh.X)  # the CVODES flight, bit for bit
    # the file's truth is not the default [truth] (J2 + the 6731 km exponential): the flights differ
    fd = fly(satellite_params(3.986004418e14, j2=True, drag=True, mass=12.0), x0, U, 100.0)
    assert np.abs(fd.X[-1] - ff.X[-1]).max() > 1.0  # m: 20 min of a different drag
    # the drag term is live: without it the target ends elsewhere (3.7e-12 kg/m^3 at 400 km, Cd A/m
    # 9.2e-3 m^2/kg: about 1e-6 m/s^2, 0.5 a t^2 = 0.7 m in 20 min)
    th.drag_on = False
    assert np.abs(fly(th, x0, U, 100.0).X[-1, 3:6] - ff.X[-1, 3:6]).max() > 0.1  # m


def test_truth_file_without_drag_keeps_the_chaser_mass(tmp_path):
    fm = FORCE_MODEL.split("[drag]")[0]
    sc = rv.load(_write(tmp_path, force_model=fm))
    tp = rv.truth_params(sc)
    assert (tp.j2_on, tp.drag_on, tp.mass_chaser, tp.mu) == (True, False, 12.0, 398600.4418e9)


def test_cli_title_names_the_file(tmp_path):
    from satgnc.guidance.cli import _truth_title

    sc = rv.load(_write(tmp_path))
    assert _truth_title(sc) == "Flying the plans on the truth model (J2 + drag from truth.toml, CVODES)"


BAD = [
    # (scenario edit, force-model edit, file at fault, line, fragments)
    (('force_model = "models/truth.toml"', 'force_model = "models/truth.toml"\nj2 = true'), None,
     "scenario.toml", 26, ["key 'j2' in section [truth]", "not with 'force_model'"]),
    (('force_model = "models/truth.toml"', 'force_model = "models/none.toml"'), None,
     "scenario.toml", 25, ["key 'force_model' in section [truth]", "no file at", "none.toml"]),
    (('force_model = "models/truth.toml"', "force_model = 3"), None,
     "scenario.toml", 25, ["key 'force_model' in section [truth]", "a string"]),
    (("mu = 3.986004418e14", "mu = 3.99e14"), None,
     "scenario.toml", 25, ["[central_body] mu = 398600441800000.0", "[orbit] mu is 399000000000000.0"]),
    (("mass = 12.0", "mass = 10.0"), None,
     "scenario.toml", 25, ["[drag] mass = 12.0 kg", "[chaser] mass is 10.0 kg"]),
    (None, ('model = "j2"\nj2 = 1.08262668e-3', 'model = "egm2008"\ndegree = 4'),
     "truth.toml", 6, ["[gravity]", "no spherical-harmonic field"]),
    (None, ("cd = 2.2", "cd = 2.2\ncdd = 1"),
     "truth.toml", 15, ["[drag] cdd", "unknown key"]),
    (None, ("area = 0.05", "area = -0.05"),
     "truth.toml", 12, ["[drag] area", "must be >= 0"]),
    (None, ("[drag]", "[srp]\narea = 1.0\nmass = 12.0\n\n[drag]"),
     "truth.toml", 10, ["[srp]", "no solar radiation pressure"]),
]


@pytest.mark.parametrize("scen,fm,where,line,frags", BAD, ids=[b[4][0] for b in BAD])
def test_bad_truth_file_is_an_error_with_file_line_key(tmp_path, capsys, scen, fm, where, line, frags):
    s = SCENARIO if scen is None else SCENARIO.replace(*scen, 1)
    f = FORCE_MODEL if fm is None else FORCE_MODEL.replace(*fm, 1)
    assert s != SCENARIO or f != FORCE_MODEL
    p = _write(tmp_path, s, f)
    with pytest.raises(satgnc.FileFormatError) as e:
        rv.load(p)
    assert e.value.path.name == where and e.value.line == line, str(e.value)
    for frag in frags:
        assert frag in str(e.value), (frag, str(e.value))
    rc = cli.main(["rendezvous", "--scenario", str(p), "--model", "nonlinear", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("satgnc: error: ") and err.count("\n") == 1, err
    assert f"{where}:{line}:" in err, err
