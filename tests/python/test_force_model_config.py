"""The force-model TOML (issue 14 item 8): the shipped example equals the hand-built ForceModel
(acceleration and Jacobians at 5 states identical), IAU 2006 + EOP and a .gfc file by path, every
schema error names the file, the line, the [section] key and the rule (20 bad files), and the same
file drives propagation, OD (the od CLI's --force-model) and the guidance two-satellite truth."""

from __future__ import annotations

import math
import pathlib

import numpy as np
import pytest
import satgnc
from satgnc import FileFormatError
from satgnc.dynamics import (
    AtmosphereDrag,
    GravityField,
    HarrisPriester,
    SolarRadiationPressure,
    ThirdBodies,
    UniformRotation,
    egm2008,
    force_model,
)
from satgnc.forcemodel import load_force_model_config, two_satellite_params
from satgnc.time import Epoch

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "force_model.toml"
EOP = ROOT / "tests" / "data" / "eop" / "finals2000A_2016-12.txt"

STATES = [
    (0.0, [6778.0, 0.0, 0.0, 0.0, 7.6, 1.0]),
    (900.0, [0.0, 6900.0, 100.0, -7.5, 0.0, 1.2]),
    (1800.0, [-4000.0, 4000.0, 3500.0, -4.0, -4.0, 4.0]),
    (3600.0, [3000.0, -5000.0, -3000.0, 5.0, 4.0, -3.0]),
    (7200.0, [-6700.0, -500.0, 800.0, 0.5, -7.4, 1.0]),
]


def hand_built_example() -> satgnc.ForceModel:
    """examples/force_model.toml written out by hand."""
    rot = UniformRotation(0.0, satgnc.EARTH_OMEGA)
    coeffs = egm2008(20)
    drag = AtmosphereDrag(HarrisPriester(n=2.0, lag=math.radians(30.0)), cd=2.2, area=2.0, mass=500.0,
                          earth_rotation=rot)
    return force_model(mu=coeffs.mu, gravity=GravityField(coeffs, 20, 20, rotation=rot),
                       third_body=ThirdBodies(), srp=SolarRadiationPressure(area=2.0, mass=500.0, cr=1.3),
                       epoch=Epoch.parse("2024-03-20T12:00:00", "UTC"), atmosphere_drag=drag)


def test_example_equals_the_hand_built_model_at_five_states():
    cfg = load_force_model_config(EXAMPLE)
    fm, ref = cfg.model, hand_built_example()
    assert cfg.gravity_model == "egm2008" and cfg.atmosphere == "harris_priester"
    assert (fm.epoch_jd1, fm.epoch_jd2) == (ref.epoch_jd1, ref.epoch_jd2)
    assert fm.mu == ref.mu == 398600.4415  # the EGM2008 file's GM (no [central_body] mu given)
    for t, x in STATES:
        r, v = np.array(x[:3]), np.array(x[3:])
        a = np.asarray(fm.acceleration(r, v, t))
        b = np.asarray(ref.acceleration(r, v, t))
        assert np.array_equal(a, b)  # bit-identical: the same terms with the same numbers
        assert np.linalg.norm(a) > 7e-3  # a real LEO acceleration, km/s^2
    assert cfg.space_weather.f107 == 150.0 and cfg.space_weather.ap == 4.0


def test_iau2006_with_eop_and_a_gfc_file_by_relative_path(tmp_path):
    (tmp_path / "eop.txt").write_text(EOP.read_text())
    gfc = tmp_path / "grav.gfc"
    gfc.write_text(satgnc.dynamics.EGM2008_PATH.read_text())
    (tmp_path / "fm.toml").write_text(
        '[epoch]\ntime = "2016-12-10T00:00:00"\n[earth_orientation]\nmodel = "iau2006"\neop = "eop.txt"\n'
        'days = 2\n[gravity]\nmodel = "file"\nfile = "grav.gfc"\ndegree = 8\n')
    cfg = load_force_model_config(tmp_path / "fm.toml")
    assert cfg.earth_orientation == "iau2006"
    assert cfg.eop_file == str(tmp_path / "eop.txt")
    assert cfg.model.gravity.degree == 8 and cfg.model.gravity.order == 8
    # Same field and rotation built by hand: identical accelerations.
    from satgnc import frames

    rot = frames.IauEarthRotation(Epoch.parse("2016-12-10T00:00:00", "UTC"), frames.load_eop(EOP), -86400.0,
                                  2 * 86400.0)
    ref = force_model(gravity=GravityField(egm2008(8), 8, 8, rotation=rot))
    r, v = np.array([7000.0, 100.0, 200.0]), np.zeros(3)
    a = np.asarray(cfg.model.acceleration(r, v, 600.0))
    assert np.array_equal(a, np.asarray(ref.acceleration(r, v, 600.0)))


GOOD_SRP = "[srp]\narea = 1.0\nmass = 10.0\n"
BAD_FILES = [
    # (text, line, message)
    ("[srp]\narea = 1.0\nmass = 10.0\naera = 2.0\n", 4,
     "[srp] aera: unknown key (known in [srp]: area, mass, cr, shadow)"),
    ("[gravty]\nmodel = \"j2\"\n", 1, "[gravty]: unknown section (known: central_body, epoch"),
    ("mu = 398600.0\n", 1, "mu: must be a [section] (a table), got a number (every setting belongs"),
    ("[srp]\narea = -1.0\nmass = 10.0\n", 2, "[srp] area: must be >= 0 m^2, got -1"),
    ("[srp]\narea = 1.0\nmass = 0.0\n", 3, "[srp] mass: must be > 0 kg, got 0"),
    ("[drag]\narea = 1.0\nmass = -5\n", 3, "[drag] mass: must be > 0 kg, got -5"),
    ("[drag]\narea = \"big\"\nmass = 5\n", 2, "[drag] area: must be a number, got a string"),
    ("[srp]\nmass = 10.0\n", 1, "[srp] area: missing (required in [srp], m^2)"),
    ("[space_weather]\nf107 = 900\n", 2, "[space_weather] f107: must be in [0, 400] sfu, got 900"),
    ("[space_weather]\nap = -3\n", 2, "[space_weather] ap: must be in [0, 400], got -3"),
    ("[space_weather]\nf107a = 1e3\n", 2, "[space_weather] f107a: must be in [0, 400] sfu, got 1000"),
    ("[drag]\narea = 1.0\nmass = 10.0\natmosphere = \"nrlmsise00\"\nhp_n = 3\n", 5,
     "[drag] hp_n: only with atmosphere = \"harris_priester\""),
    ("[drag]\narea = 1.0\nmass = 10.0\natmosphere = \"jacchia\"\n", 4,
     "[drag] atmosphere: unknown value 'jacchia' (choices: harris_priester, exponential, nrlmsise00)"),
    ("[drag]\narea = 1.0\nmass = 10.0\natmosphere = \"exponential\"\nrho0 = 1e-12\nh0 = 400\n", 1,
     "[drag] scale_height: missing (required in [drag], km)"),
    ("[drag]\narea = 1.0\nmass = 10.0\nrho0 = 1e-12\n", 4,
     "[drag] rho0: only with atmosphere = \"exponential\""),
    ("[gravity]\nmodel = \"egm2008\"\ndegree = 80\n", 3, "[gravity] degree: "),
    ("[gravity]\nmodel = \"egm2008\"\ndegree = 20\norder = 21\n", 4,
     "[gravity] order: must be in [0, degree], got 21"),
    ("[gravity]\nmodel = \"egm2008\"\ndegree = 20.5\n", 3,
     "[gravity] degree: must be an integer, got a number"),
    ("[gravity]\nmodel = \"file\"\nfile = \"missing.gfc\"\n", 3, "[gravity] file: "),
    ("[third_body]\nsun = \"yes\"\n", 2, "[third_body] sun: must be true or false, got a string"),
    ("[epoch]\ntime = \"2024-13-01T00:00:00\"\n", 2, "[epoch] time: "),
    ("[epoch]\ntime = \"2024-01-01T00:00:00\"\nscale = \"ut1\"\n", 3, "[epoch] scale: unknown value 'ut1'"),
    ("[earth_orientation]\nmodel = \"iau2006\"\neop = \"x.txt\"\n", 2,
     "[earth_orientation] model: \"iau2006\" needs an [epoch] section"),
    ("[srp]\narea = 1.0\nmass = 10.0\ncr = 7\n", 4, "[srp] cr: must be in [0, 3], got 7"),
    ("[srp]\narea = 1.0\nmass = 10.0\nshadow = \"dual\"\n", 4, "[srp] shadow: unknown value 'dual'"),
    ("[central_body]\nmu = -1\n", 2, "[central_body] mu: must be > 0 km^3/s^2, got -1"),
    ("[srp\narea = 1.0\n", 1, "TOML syntax: "),
]


@pytest.mark.parametrize(("text", "line", "message"), BAD_FILES, ids=[str(i) for i in range(len(BAD_FILES))])
def test_bad_file_names_file_line_section_and_key(tmp_path, text, line, message):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(FileFormatError) as err:
        satgnc.load_force_model(path)
    e = err.value
    assert e.line == line
    assert e.path == path
    assert str(e).startswith(f"{path}:{line}: ")
    assert message in str(e)


def test_model_level_error_and_missing_file(tmp_path):
    # J2 given with a gravity field would double C20: the ForceModel's own rule, no single line.
    p = tmp_path / "mu.toml"
    p.write_text("[central_body]\nmu = 398000.0\n[gravity]\nmodel = \"egm2008\"\ndegree = 4\n")
    with pytest.raises(FileFormatError, match="the force model it describes is invalid: .*gravity") as err:
        satgnc.load_force_model(p)
    assert err.value.line is None
    with pytest.raises(FileNotFoundError, match="path: no force-model TOML at"):
        satgnc.load_force_model(tmp_path / "nope.toml")
    with pytest.raises(TypeError, match="path: must be a path"):
        satgnc.load_force_model(3)  # type: ignore[arg-type]


TRUTH_TOML = """# the guidance truth's terms: J2 and exponential drag
[central_body]
mu = 398600.4418
[gravity]
model = "j2"
[drag]
area = 0.01
mass = 4.6
cd = 1.0
atmosphere = "exponential"
rho0 = 3.725e-12
h0 = 400.0
scale_height = 58.515
"""


def test_propagation_od_and_guidance_truth_read_the_same_file(tmp_path):
    path = tmp_path / "truth.toml"
    path.write_text(TRUTH_TOML)
    fm = satgnc.load_force_model(path)
    x0 = np.array([6778.137, 0.0, 0.0, 0.0, 5.06, 5.77])
    t = np.linspace(0.0, 5400.0, 7)
    kw = dict(rtol=1e-13, atol=1e-15, with_stm=False)
    # Propagation: forces=<path> is the loaded model.
    by_path = satgnc.propagate(x0, t, forces=path, **kw)
    by_model = satgnc.propagate(x0, t, forces=fm, **kw)
    assert np.array_equal(by_path.states, by_model.states)
    # Guidance truth: the two-satellite model (SI) from the same file flies the target (zero thrust)
    # on the same orbit as satgnc.propagate. Both integrators at rtol 1e-13: measured 2.1e-7 km after
    # 1.5 h (at the truth's default rtol 1e-11 its own error is 8e-5 km); 1e-6 km (1 mm) bound.
    params = two_satellite_params(path)
    settings = satgnc._satgnc.default_truth_settings()
    settings.rtol = 1e-13
    truth = satgnc._satgnc.TwoSatelliteTruth(satgnc._satgnc.TwoSatelliteModel(params), settings)
    rt, vt = x0[:3] * 1e3, x0[3:] * 1e3
    chaser_r, chaser_v = rt + np.array([0.0, -100.0, 0.0]), vt
    X0 = np.concatenate([rt - chaser_r, rt, vt - chaser_v, vt])
    flight = truth.fly(X0, np.zeros((3, 6)), 900.0)
    X = np.asarray(flight["X"])
    assert flight["ok"]
    target_km = X[3:6, :].T / 1e3
    assert np.max(np.linalg.norm(target_km - by_model.states[:, :3], axis=1)) < 1e-6  # km (1 mm)
    # OD: the od CLI's --force-model builds its CVODES propagator from the same file; a batch solve on
    # range/range-rate simulated with that propagator recovers the state (2e-6 km: noise-free data).
    from argparse import Namespace

    from satgnc import od
    from satgnc.od.cli import _propagator

    prop = _propagator(Namespace(force_model=str(path), propagator=None))
    assert type(prop).__name__ == "CvodesStmPropagator"
    st = od.station_inertial([6378.1363, 0.0, 0.0])
    times = np.arange(0.0, 600.0, 20.0)
    # elevation_mask_deg=None: every sample (the default 0 deg mask keeps only the visible part)
    obs = od.simulate(x0, [st], times, seed=None, propagator=prop, elevation_mask_deg=None)
    guess = x0 + np.array([1.0, -1.0, 0.5, 1e-3, 0.0, -1e-3])
    r = od.solve(obs, [st], guess, propagator=prop)
    assert r.status.name == "converged"
    assert np.max(np.abs(np.asarray(r.x0) - x0)[:3]) < 2e-6
    with pytest.raises(ValueError, match="--force-model: needs --propagator cvodes"):
        _propagator(Namespace(force_model=str(path), propagator="kepler"))


def test_two_satellite_truth_refuses_terms_it_does_not_have():
    # The example's first such term is its gravity field.
    with pytest.raises(FileFormatError, match=r"\[gravity\]: the two-satellite truth model has no spherical"):
        two_satellite_params(EXAMPLE)


def test_od_cli_force_model_option_end_to_end(tmp_path, capsys):
    """`satgnc od solve --propagator cvodes --force-model FILE` on the paper's simulated (two-body) CSV: a
    point-mass TOML converges like the Kepler propagator; the kepler propagator beside the option and a
    bad file are one-line errors (exit 2) naming the option or the file and line."""
    from satgnc import cli
    from satgnc.papers import od_newton_raphson as paper

    obs = tmp_path / "obs.csv"
    sim = ["od", "simulate", "--out", str(obs), "--duration", "300", "--step", "30", "--no-noise"]
    assert cli.main(sim) == 0
    guess = ",".join(f"{v:.9g}" for v in paper.truth() + np.array([10, 0, 0, 0, 0, 0]))
    r0 = ",".join(f"{v:.9g}" for v in paper.station_state_table3()[:3])
    two_body = tmp_path / "two_body.toml"
    two_body.write_text('[central_body]\nmu = 398600.4418\n[gravity]\nmodel = "point_mass"\n')
    base = ["od", "solve", str(obs), "--station-inertial", f"STATION:{r0}", "--guess", guess]
    capsys.readouterr()
    assert cli.main([*base, "--propagator", "cvodes", "--force-model", str(two_body)]) == 0
    assert "converged" in capsys.readouterr().out
    assert cli.main([*base, "--propagator", "kepler", "--force-model", str(two_body)]) == 2
    assert "--force-model: needs --propagator cvodes" in capsys.readouterr().err
    bad = tmp_path / "bad.toml"
    bad.write_text("[srp]\narea = -2.0\nmass = 1.0\n")
    assert cli.main([*base, "--force-model", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and f"{bad}:2: [srp] area: must be >= 0 m^2, got -2" in err
