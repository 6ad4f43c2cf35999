"""One rendezvous scenario file read by both models (issue 12): a scenario that is not the paper's
(its own orbit, horizon, bounds and initial state) plans on the linear and the nonlinear model with
the file's values; the paper's file gives exactly the paper's nonlinear transcription; bad files are
one-line errors naming the file and the key."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
import satgnc
from satgnc import _satgnc as _c
from satgnc import cli
from satgnc._results import Result
from satgnc.guidance import Flight, Plan, RendezvousProblem, fly, mpc, plan, satellite_params
from satgnc.guidance.planning import transcribe
from satgnc.papers import l1_admm_rendezvous as paper
from satgnc.scenarios import rendezvous as rv

X0 = [-400.0, 120.0, 15.0, 0.35, -0.12, 0.01]
OTHER = """
name = "short_leo_hop"

[orbit]
mu = 3.986004418e14     # m^3/s^2
radius = 6878.0e3       # m

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

[discretization]
method = "zoh"

[truth]
j2 = true
drag = false

[cases.hop]
rho = 0.1
eps = 1.0e-4
box = true

[cases.hop.nonlinear]
rho = 1.0
eps = 1.0e-5
"""


@pytest.fixture(scope="module")
def other(tmp_path_factory):
    p = tmp_path_factory.mktemp("scen") / "hop.toml"
    p.write_text(OTHER)
    return p


def test_other_scenario_both_models_use_the_files_values(other):
    sc = rv.load(other)
    assert sc.nonlinear_cases() == ["hop"] and sc.sections["release"] is None
    for model, nx in (("linear", 6), ("nonlinear", 12)):
        pb = rv.problem(sc, "hop", model)
        assert (pb.horizon, pb.tf, pb.u_max, pb.mass, pb.mu) == (12, 1200.0, 0.02, 12.0, 3.986004418e14)
        np.testing.assert_array_equal(pb.x0, X0)
        p = plan(pb, model)
        assert isinstance(p, Plan) and p.model == model
        assert p.U.shape == (12, 3) and p.X.shape == (13, nx) and p.horizon == 12
        assert p.dt == pytest.approx(100.0, rel=1e-15)
        assert np.abs(p.U).max() <= 0.02 * (1 + 1e-9)  # the file's bound
        x0_cw = p.X[0] if model == "linear" else np.asarray(_c.cw_relative_state(p.X[0]))
        np.testing.assert_allclose(x0_cw, X0, rtol=1e-9, atol=1e-9)  # the file's initial state
        assert p.status in ("solved", "solved_inaccurate"), p.status
        assert p.miss()[0] < 5.0, p.summary()  # 400 m closed to a few metres at most
        s = p.summary()
        assert s["delta_v"] > 0 and 0 <= s["sparsity"] <= 1 and s["u_max"] <= 0.02 * (1 + 1e-9)
        with pytest.raises(ValueError, match="read-only"):
            p.U[0, 0] = 1.0
        assert isinstance(p, Result)
        msg = r"Plan\['X'\] \(dict access\) is deprecated; use the attribute"
        with pytest.warns(DeprecationWarning, match=msg):
            assert p["X"] is p.X
        with pytest.raises(dataclasses_frozen_error()):
            p.status = "x"


def dataclasses_frozen_error():
    import dataclasses

    return dataclasses.FrozenInstanceError


def test_other_scenario_flight_uses_the_files_truth(other):
    sc = rv.load(other)
    tp = rv.truth_params(sc)
    assert (tp.j2_on, tp.drag_on, tp.mu, tp.mass_chaser) == (True, False, 3.986004418e14, 12.0)
    pb = rv.problem(sc, "hop", "nonlinear")
    p = plan(pb, "nonlinear")
    f = fly(tp, pb.state_eci(), p.U, pb.dt)
    assert isinstance(f, Flight) and f.X.shape == (13, 12) and f.t[-1] == pytest.approx(1200.0)
    assert f.miss[0] < 5.0  # J2 over 20 min moves the open-loop arrival by metres, not hundreds
    np.testing.assert_array_equal(f.X[0], pb.state_eci())
    m = mpc(pb, truth=tp, max_iter=5, first_max_iter=200)
    assert m.X.shape == (13, 12) and m.U.shape == (12, 3) and len(m.solve_times) == len(m.iterations) == 3
    assert m.miss[0] < f.miss[0] + 1.0


def test_cli_other_scenario_nonlinear_and_linear(other, tmp_path, capsys):
    out = tmp_path / "nl"
    assert (
        cli.main(
            [
                "rendezvous",
                "--scenario",
                str(other),
                "--model",
                "nonlinear",
                "--out",
                str(out),
                "--closed-loop",
            ]
        )
        == 0
    )
    s = json.loads((out / "nonlinear_summary.json").read_text())["nonlinear_hop"]
    assert s["horizon"] == 12 and s["opt_u_max"] <= 0.02 * (1 + 1e-9)
    assert s["ilqr_admm_iterations"] >= 1 and s["truth_miss_MPC"] < 1.0  # a user's case: no paper_* key
    assert s["truth_miss_CW plan, open loop"] < 5.0 and s["truth_miss_nonlinear plan, open loop"] < 5.0
    assert (out / "nonlinear_hop.png").exists() and (out / "nonlinear_hop_flight.png").exists()
    out2 = tmp_path / "lin"
    assert cli.main(["rendezvous", "--scenario", str(other), "--model", "linear", "--out", str(out2),
                     "--closed-loop"]) == 0
    lin = json.loads((out2 / "summary.json").read_text())["hop"]
    assert lin["max_abs_u_N"] <= 0.02 * (1 + 1e-9)
    assert lin["conv_miss_m"] < 5.0 and lin["truth_miss_open_loop_m"] < 5.0  # the truth: J2 only, 20 min
    assert (out2 / "hop_flight.png").exists()
    text = capsys.readouterr().out
    assert "nonlinear hop: iLQR-ADMM (rho = 1, eps = 1e-05) stops after" in text and "paper" not in text


def test_paper_file_is_the_paper_transcription():
    """The packaged TOML through the schema gives the nonlinear paper case bit for bit."""
    sc = rv.load()
    for name, constrained in (("unconstrained", False), ("constrained", True)):
        tr = transcribe(rv.problem(sc, name, "nonlinear"))
        case = paper.paper_case(constrained)
        np.testing.assert_array_equal(tr.x0_si, case.x0_si)
        np.testing.assert_array_equal(np.asarray(tr.problem.Qf), np.asarray(case.problem.Qf))
        assert tr.problem.stage_weight == case.problem.stage_weight and tr.dt == case.dt
        assert tr.constrained == constrained and not tr.problem.terminal_equality
        nl = sc.cases[name]["nonlinear"]
        assert (
            (nl["rho"], nl["eps"]) == (case.rho, case.eps) == ((10.0, 5e-6) if constrained else (0.1, 6e-5))
        )
    assert (paper.MU, paper.R_TARGET, paper.MASS, paper.TF, paper.N, paper.U_MAX) == (
        3.99e14,
        7231.0e3,
        4.6,
        6000.0,
        99,
        5e-3,
    )


def test_library_plan_equals_the_paper_solvers():
    sc = rv.load()
    pb = rv.problem(sc, "unconstrained", "nonlinear")
    case = paper.paper_case(False)
    p = plan(pb, "nonlinear", "scp", eps=1e-7, tol=1e-8)
    ref = paper.solve_scp(case, eps=1e-7, tol=1e-8)
    np.testing.assert_array_equal(p.U, case.to_si(ref.U).T)
    assert p.iterations == ref.info.outer_iterations
    s_old = paper.summarize(case, ref.U)
    s_new = p.summary()
    for k in ("miss_position", "miss_velocity", "objective", "nonzero_intervals", "sparsity"):
        assert s_new[k] == pytest.approx(s_old[k], rel=1e-12, abs=1e-15), k
    pp = plan(pb, "nonlinear", "ilqr_admm", rho=0.1, eps=6e-5, stop="paper")
    assert pp.iterations == 60  # the paper's 120 passes, as test_guidance_nonlinear has it
    # the linear plan is the old linear_cw_plan (exact ZOH) of the same case
    lin = plan(pb, "linear", discretization="zoh")
    np.testing.assert_array_equal(lin.U, paper.linear_cw_plan(case)["U"].T)
    # the library's flight is the old one, time-major
    f = fly(paper.model_params(published=False, j2=True, drag=True), case.x0_si, p.U, case.dt)
    np.testing.assert_array_equal(f.X, paper.fly(case, p.U.T).T)


def test_problem_checks_name_the_field():
    kw = dict(mu=3.986e14, radius=7.0e6, mass=10.0, x0=np.ones(6), tf=600.0, horizon=6, alpha=1.0, Qf=10.0)
    RendezvousProblem(**kw)
    for bad, exc, msg in (
        (dict(x0=np.ones(5)), ValueError, "x0: must have shape"),
        (dict(horizon=2.5), TypeError, "horizon: must be an integer"),
        (dict(u_max=0.0), ValueError, "u_max: must be > 0"),
        (dict(planner=3), TypeError, "planner: must be TwoSatelliteParams"),
        (dict(planner=satellite_params(3.986e14)), ValueError, "planner: mass_chaser = 4.6 kg"),
        (dict(nonlinear_discretization="euler"), ValueError, "nonlinear_discretization"),
    ):
        with pytest.raises(exc, match=msg):
            RendezvousProblem(**{**kw, **bad})
    pb = RendezvousProblem(**kw)
    with pytest.raises(ValueError, match="model"):
        plan(pb, "quantum")
    with pytest.raises(TypeError, match="rho: not an option of method 'scp'"):
        plan(pb, "nonlinear", rho=1.0)
    with pytest.raises(TypeError, match="problem: must be a RendezvousProblem"):
        plan("x")


BAD = [
    (
        "[cases.hop.nonlinear]\nrho = 1.0",
        "[cases.hop.nonlinear]\nrh = 1.0",
        ["unknown key 'rh'", "[cases.hop.nonlinear]", "did you mean 'rho'"],
    ),
    ("[truth]\nj2 = true", '[truth]\nj2 = "yes"', ["key 'j2'", "[truth]", "true or false"]),
    ("[truth]\n", '[truth]\natmosphere = "rotating"\n', ["key 'atmosphere'", "[truth]", "must be one of"]),
    ("[discretization]\n", '[discretization]\nnonlinear = "rk2"\n', ["key 'nonlinear'", "[discretization]"]),
    (
        "[truth]\n",
        "[release]\nrelative_position = [1.0, 2.0]\nrelative_velocity = [0.0, 0.0, 0.0]\n\n[truth]\n",
        ["key 'relative_position'", "[release]"],
    ),
    (
        "[truth]\n",
        "[releas]\ndrift_time = 1.0\n\n[truth]\n",
        ["unknown section [releas]", "did you mean [release]"],
    ),
]


@pytest.mark.parametrize("old,new,frags", BAD, ids=[b[2][0] for b in BAD])
@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_bad_scenario_is_one_line_exit_2(tmp_path, capsys, old, new, frags, model):
    assert old in OTHER
    p = tmp_path / "bad.toml"
    p.write_text(OTHER.replace(old, new, 1))
    rc = cli.main(["rendezvous", "--scenario", str(p), "--model", model, "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.startswith("satgnc: error: ") and err.count("\n") == 1, err
    assert f"{p}:" in err, err
    for f in frags:
        assert f in err, (f, err)
    with pytest.raises(satgnc.FileFormatError):
        rv.load(p)


def test_nonlinear_shim_keeps_all_names_with_warnings():
    import satgnc.guidance.nonlinear as old

    names = [
        "Case",
        "drift_state",
        "fly",
        "linear_cw_plan",
        "make_map",
        "miss",
        "model_params",
        "mpc",
        "paper_case",
        "release_state",
        "run_cli",
        "solve_paper",
        "solve_scp",
        "summarize",
    ]
    for name in names:
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            value = getattr(old, name)
        assert len(w) == 1 and w[0].category is DeprecationWarning
        msg = str(w[0].message)
        assert msg.startswith(f"satgnc.guidance.nonlinear.{name} is deprecated; use satgnc."), msg
        if name == "make_map":
            from satgnc.guidance.planning import make_map

            assert value is make_map
        else:
            assert value is getattr(paper, name)
    with pytest.warns(DeprecationWarning, match="satgnc.guidance.fly"):
        old.fly  # noqa: B018
    with pytest.warns(DeprecationWarning):
        assert old.MU == 3.99e14 and old.N == 99
    # old orientation kept: the plan is 3 x N, the flight 12 x (N + 1)
    with pytest.warns(DeprecationWarning):
        case = old.paper_case(horizon=4, tf=240.0)
    with pytest.warns(DeprecationWarning):
        X = old.fly(case, np.zeros((3, 4)), integrator="rk4", substeps=4)
    assert X.shape == (12, 5)


def test_fly_and_mpc_checks_name_the_argument():
    tp = satellite_params(3.986e14, mass=10.0)
    x0 = np.r_[10.0, 0, 0, 7.0e6, 0, 0, 0, 0, 0, 0, 7.5e3, 0]
    U = np.zeros((4, 3))
    for kw, exc, msg in (
        (dict(params=3), TypeError, "params: must be TwoSatelliteParams"),
        (dict(U=np.zeros((3, 4))), ValueError, r"U: must have shape \(n, 3\)"),
        (dict(U=U + 0j), TypeError, "U: must be a real numeric array"),
        (dict(dt=-1.0), ValueError, "dt: must be > 0"),
        (dict(integrator="euler"), ValueError, "integrator"),
        (dict(x0=np.r_[0.0, 0, 0, 6.0e6, 0, 0, 0, 0, 0, 0, 7.5e3, 0]), ValueError,
         "x0: the target starts at or below the Earth's surface"),
    ):
        args = dict(params=tp, x0=x0, U=U, dt=60.0)
        args.update(kw)
        with pytest.raises(exc, match=msg):
            fly(**args)
    f = fly(tp, x0, U, 60.0, integrator="rk4", substeps=4)
    assert f.X.shape == (5, 12) and f.U.shape == (4, 3) and f.t[-1] == 240.0
    pb = RendezvousProblem(mu=3.986e14, radius=7.0e6, mass=10.0, x0=np.r_[-50.0, 10, 0, 0.05, 0, 0], tf=600.0,
                           horizon=6, alpha=1.0, Qf=100.0)
    with pytest.raises(TypeError, match="truth: must be TwoSatelliteParams"):
        mpc(pb, truth=3)
    with pytest.raises(TypeError, match="replan_every"):
        mpc(pb, replan_every=1.5)
