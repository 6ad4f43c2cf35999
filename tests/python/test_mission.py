"""satgnc.mission: the main job as one path on the packaged mission_leo.toml (quick variant).

tracking -> OD -> relative state -> L1 plan -> flight on the J2 + drag truth -> checks."""

import dataclasses
import math
import pathlib

import numpy as np
import pytest
import satgnc
from satgnc import mission
from satgnc._results import Result
from satgnc.cli import main
from satgnc.scenarios import mission as scen

DEFAULT = scen.DEFAULT


@pytest.fixture(scope="module")
def run():
    return mission.run(None, quick=True)


def test_every_stage_status(run):
    assert run.statuses == {"tracking": "success", "od": "converged", "relative": "success",
                            "plan": "solved", "flight": "success", "checks": "success"}
    assert run.estimate.rank == 6
    assert run.tracking.t.size > 50  # three passes, range and range-rate, every 30 s (quick)


def test_full_mission_without_quick():
    r = mission.run(DEFAULT)
    assert set(r.statuses.values()) == {"success", "converged", "solved"}
    assert r.tracking.t.size == 170 and not r.quick
    assert np.all(np.abs(r.estimate.error) <= 3.0 * r.estimate.sigma)
    assert r.flight.miss_position < r.scenario.miss_tolerance
    # wall times (s) per stage: reported, not asserted
    assert set(r.timings) == {"tracking", "od", "relative", "plan", "flight", "checks"}


def test_od_error_within_three_sigma_of_its_covariance(run):
    """Seeded (seed = 12): every component of x0 - truth is inside 3 sigma of the OD covariance, and so
    is the relative-state error inside 3 sigma of the mapped covariance (m, m/s)."""
    est = run.estimate
    assert np.all(np.abs(est.error) <= 3.0 * est.sigma), est.error / est.sigma
    rel = run.relative
    sig = np.sqrt(np.diag(rel.covariance))
    assert np.all(np.abs(rel.error) <= 3.0 * sig), rel.error / sig
    # The truth relative state is the file's (m, m/s, CW): two_satellite_state / cw_relative_state invert.
    sc = run.scenario
    np.testing.assert_allclose(rel.x_true, np.r_[sc.p0, sc.v0], rtol=0, atol=1e-6)
    # km -> m: the Jacobian of the relative position w.r.t. the target position is about -1000 R^T.
    assert abs(abs(np.linalg.det(rel.jacobian[:3, :3])) - 1e9) < 1e6


def test_flown_miss_below_the_scenario_tolerance(run):
    """Tolerance 1000 m (mission_leo.toml). The plan is flown open loop from the TRUE relative state on
    the J2 + drag two-satellite truth, so the miss has three sources (docs/mission.md, measured): the
    CW model's nonlinearity from 9.7 km over 6000 s (~240 m on a two-body truth), the unmodelled J2
    (~300 m more at 500 km altitude; drag < 2 m) and the OD error of the planning start
    (flight.predicted_3sigma, ~25 m). Measured here: 476 m; the tolerance is about twice that."""
    fl, sc = run.flight, run.scenario
    assert sc.miss_tolerance == 1000.0
    assert fl.miss_position < sc.miss_tolerance
    assert 200.0 < fl.miss_position  # the open-loop CW model error is real, not hidden
    assert 5.0 < fl.predicted_3sigma < 100.0
    assert np.linalg.norm(run.plan.X[-1, :3]) < 1e-3  # terminal_equality: x_N = 0 on the CW model
    assert fl.X.shape == (sc.knots, 12) and fl.X_cw.shape == (sc.knots, 6)
    assert run.plan.U.shape == (sc.knots - 1, 3)
    assert np.max(np.abs(run.plan.U)) <= sc.u_max * (1 + 1e-9)  # the box bound (N)
    # The plan and the flight start from different states by exactly the relative-state error.
    np.testing.assert_allclose(run.plan.X[0] - fl.X_cw[0], run.relative.error, atol=1e-6)


def test_controllability_and_observability_verdicts(run):
    ck = run.checks
    assert ck.controllability == "full rank" and ck.controllability_rank == 6
    assert ck.observability == "full rank" and ck.observability_rank == 6
    assert ck.controllability_sv[0] == 1.0 and ck.observability_sv.size == 6
    assert np.isfinite(ck.gramian_condition) and ck.gramian_condition > 1


def test_handoff_table_units(run):
    units = {(h.stage, h.quantity.split(" (")[0]): h.unit for h in run.handoff}
    assert [h.stage[0] for h in run.handoff] == sorted(h.stage[0] for h in run.handoff)
    assert {h.stage[0] for h in run.handoff} == set("123456")
    assert all(h.unit and h.frame for h in run.handoff)
    assert units[("2 OD", "x0 estimate")] == "km, km/s"
    assert units[("3 relative", "chaser relative state at t = 900 s")] == "m, m/s"
    flight = ("5 flight", "open-loop miss at tf = 6000 s on point mass + J2 + exponential drag")
    assert units[flight] == "m, m/s"
    assert any(h.unit == "m/s, N" and h.stage == "4 plan" for h in run.handoff)
    md = run.handoff_markdown()
    assert md.startswith("| stage | hands on | value | unit | frame |")
    assert md.count("\n") == len(run.handoff) + 1
    assert all(line.count("|") == 6 for line in md.splitlines())  # no stray "|" inside a cell


def test_results_are_read_only(run):
    with pytest.raises(ValueError, match="read-only"):
        run.estimate.x0[0] = 0.0
    with pytest.raises(ValueError, match="read-only"):
        run.plan.U[0, 0] = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        run.flight.miss_position = 0.0
    assert not run.scenario.x0.flags.writeable
    assert run.tracking.station.dtype.kind == "i"
    for stage in (run.tracking, run.estimate, run.relative, run.plan, run.flight, run.checks, run):
        assert isinstance(stage, Result)


def test_bad_arguments_and_stage_failures(tmp_path):
    with pytest.raises(TypeError, match=r"scenario: must be a path, a MissionScenario or None, got int"):
        mission.run(3)
    with pytest.raises(TypeError, match=r"quick: must be true or false \(a bool\), got str"):
        mission.run(None, quick="yes")
    p = _bad(tmp_path, "mask = 10.0", "mask = 89.9")
    with pytest.raises(ValueError, match=r"tracking: [0-5] observations above the 89.9 deg mask .*least 6"):
        mission.run(p)


def test_quick_mission_time(run):
    assert sum(run.timings.values()) < 20.0, run.timings  # the brief's bound on this machine


def test_elements_and_state_give_the_same_target(tmp_path):
    sc = scen.load()
    assert abs(np.linalg.norm(sc.x0[:3]) - 6878.137 * (1 - 0.0005)) < 1e-9  # ta = 0: perigee
    text = DEFAULT.read_text()
    elements = ("a", "e", "i", "raan", "argp", "ta")
    lines = [ln for ln in text.splitlines() if ln.split("=")[0].strip() not in elements]
    pos = ", ".join(repr(float(x)) for x in sc.x0[:3])
    vel = ", ".join(repr(float(x)) for x in sc.x0[3:])
    out = "\n".join(lines).replace("[target]", f"[target]\nposition = [{pos}]\nvelocity = [{vel}]")
    p = tmp_path / "state.toml"
    p.write_text(out)
    np.testing.assert_array_equal(scen.load(p).x0, sc.x0)
    v = np.linalg.norm(sc.x0[3:])
    assert abs(v - math.sqrt(satgnc.EARTH_MU * (1 + 0.0005) / (6878.137 * (1 - 0.0005)))) < 1e-12


def test_truth_density_is_the_same_in_both_truths():
    """The two-satellite truth's atmosphere (SI) equals the orbit truth's ExponentialDrag (km)."""
    sc = scen.load()
    p = mission.truth_params(sc)
    d = sc.drag
    drag = satgnc.ExponentialDrag(rho0=d.rho0, h0=d.h0, scale_height=d.scale_height)
    for r_km in (6678.0, 6878.137, 7078.0):
        rho_ts = p.rho0 * math.exp(-p.density_decay * (r_km * 1e3 - p.density_radius))
        assert rho_ts == pytest.approx(drag.density(r_km), rel=1e-12)
    assert p.mu == pytest.approx(satgnc.EARTH_MU * 1e9, rel=1e-15)


def _bad(tmp_path, old, new) -> pathlib.Path:
    text = DEFAULT.read_text()
    assert old in text
    p = tmp_path / "bad.toml"
    p.write_text(text.replace(old, new, 1))
    return p


def test_unknown_key_names_the_file_and_the_key(tmp_path):
    p = _bad(tmp_path, 'method = "levenberg_marquardt"', 'methd = "levenberg_marquardt"')
    with pytest.raises(satgnc.FileFormatError, match=r"unknown key 'methd' in section \[od\] \(did you mean "
                       r"'method'\?\)") as e:
        scen.load(p)
    assert e.value.path == p and e.value.key == "methd" and e.value.line is not None
    p = _bad(tmp_path, "[[tracking.stations]]\nname = \"Dubai\"", "[[tracking.stations]]\nnme = \"Dubai\"")
    with pytest.raises(satgnc.FileFormatError, match=r"unknown key 'nme' in section \[tracking.stations\]"):
        scen.load(p)
    p = _bad(tmp_path, "chaser_area = 0.05", "chaser_area = -1.0")
    with pytest.raises(satgnc.FileFormatError, match=r"key 'chaser_area' in section \[truth.drag\].*>= 0"):
        scen.load(p)
    p = _bad(tmp_path, "a = 6878.137", "position = [7000.0, 0.0, 0.0]")
    with pytest.raises(satgnc.FileFormatError, match="give either position and velocity or the elements"):
        scen.load(p)


def test_cli_writes_the_report(tmp_path, capsys):
    assert main(["mission", "--quick", "--out", str(tmp_path / "m")]) == 0
    out = capsys.readouterr().out
    assert "OD converged" in out and "plan solved" in out and "report written to" in out
    md = (tmp_path / "m" / "mission.md").read_text()
    assert "| 2 OD | x0 estimate" in md and "![mission](figures/mission.png)" in md
    assert (tmp_path / "m" / "figures" / "mission.png").stat().st_size > 10_000
    assert (tmp_path / "m" / "mission_summary.json").exists()


def test_cli_bad_key_is_one_line_and_exit_code_2(tmp_path, capsys):
    p = _bad(tmp_path, "seed = 12", "sead = 12")
    assert main(["mission", "--scenario", str(p), "--out", str(tmp_path / "m")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("satgnc: error: ")
    assert str(p) in err and "unknown key 'sead' in section [tracking]" in err
    assert main(["mission", "--scenario", str(tmp_path / "missing.toml")]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_tracking_is_od_simulate_on_the_truth_force_model():
    """Stage 1 is od.simulate with the truth ForceModel (J2 + drag): same observations, bit for bit,
    ordered by time then station; without the drag in the truth the range-rates change."""
    sc = scen.load()
    tr = mission.track(sc, quick=True)
    fm, forces = mission.truth_force_model(sc)
    assert forces == "point mass + J2 + exponential drag" and fm.drag is not None and fm.j2 is not None
    obs = satgnc.od.simulate(sc.x0, list(tr.stations), sc.times[:: sc.quick_thin], types=sc.types,
                             sigma_range=sc.sigma_range, sigma_range_rate=sc.sigma_range_rate,
                             elevation_mask_deg=sc.mask, seed=sc.seed, propagator="cvodes", force_model=fm)
    assert len(obs) == tr.t.size == 58
    a = np.lexsort((obs.station, obs.t))  # simulate orders by station, then time
    np.testing.assert_array_equal(obs.t[a], tr.t)
    np.testing.assert_array_equal(obs.station[a], tr.station)
    np.testing.assert_array_equal(obs.value[a], tr.value)
    assert [str(k).split(".")[-1] for k in np.array(obs.type, dtype=object)[a]] == list(tr.type)
    no_drag = mission.track(dataclasses.replace(sc, drag=None), quick=True)
    rr = np.array([k == "range_rate" for k in tr.type])
    d = np.abs(no_drag.value - tr.value)[rr].max()
    assert 1e-7 < d < 1e-5, d  # measured 1.3e-6 km/s: drag moves a range-rate by up to 1.3 sigma (1 mm/s)


def _drag_model():
    return satgnc.ForceModel(mu=satgnc.EARTH_MU, j2=satgnc.J2Gravity(),
                             drag=satgnc.ExponentialDrag(rho0=6.967e-13, h0=500.0, scale_height=63.822,
                                                         cd=2.2, area=1.0, mass=100.0))


def test_make_propagator_takes_a_force_model_with_drag():
    """od.make_propagator("cvodes", force_model=...) propagates the state and the STM on J2 + drag: the
    states agree with satgnc.propagate on the same terms, and the STM with central differences."""
    fm = _drag_model()
    prop = satgnc.od.make_propagator("cvodes", force_model=fm)
    assert isinstance(prop, satgnc.od.CvodesStmPropagator)
    x0 = scen.load().x0
    times = [600.0, 5400.0]
    xs, phis = prop.propagate(x0, times)
    traj = satgnc.propagate(x0, np.array(times), mu=fm.mu, forces=[fm.j2, fm.drag], t0=0.0,
                            with_stm=False, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(xs), np.asarray(traj.states), rtol=0, atol=2e-6)  # km, km/s
    # drag is in the model: its state after 1.5 h differs from J2 alone by metres, not by 0
    xj, _ = satgnc.od.make_propagator("cvodes", j2=True).propagate(x0, times)
    assert 1e-3 < np.linalg.norm(np.asarray(xs)[1, :3] - np.asarray(xj)[1, :3]) < 1.0  # km
    Phi = np.asarray(phis[1])
    fd = np.zeros((6, 6))
    for j, h in enumerate([1e-3] * 3 + [1e-6] * 3):  # km, km/s
        e = np.zeros(6)
        e[j] = h
        xp, _ = prop.propagate(x0 + e, [5400.0])
        xm, _ = prop.propagate(x0 - e, [5400.0])
        fd[:, j] = (np.asarray(xp[0]) - np.asarray(xm[0])) / (2 * h)
    np.testing.assert_allclose(Phi, fd, rtol=1e-5, atol=1e-6 * np.abs(Phi).max())
    assert abs(np.linalg.det(Phi) - 1.0) > 1e-12  # not symplectic: drag dissipates


def test_make_propagator_force_model_errors():
    fm = _drag_model()
    mp = satgnc.od.make_propagator
    with pytest.raises(TypeError, match=r"force_model: must be a satgnc.ForceModel \(mu, j2, drag\), got "
                       r"dict"):
        mp("cvodes", force_model={})
    with pytest.raises(ValueError, match=r"kind: a force_model needs the 'cvodes' propagator, got 'kepler'"):
        mp("kepler", force_model=fm)
    with pytest.raises(ValueError, match=r"j2: give J2 in force_model"):
        mp("cvodes", j2=True, force_model=fm)
    with pytest.raises(ValueError, match=r"mu: 1.0 km\^3/s\^2 differs from force_model.mu = 398600.4418"):
        mp("cvodes", mu=1.0, force_model=fm)
    with pytest.raises(ValueError, match=r"propagator: a force_model needs the 'cvodes' propagator"):
        satgnc.od.simulate(scen.load().x0, [satgnc.od.station_geodetic(0.0, 0.0, 0.0, "2026-03-20T12:00:00")],
                           [10.0], force_model=fm)


def test_od_covariance_consistency_over_seeds():
    """NEES e' P^-1 e of the OD estimate over 30 seeds (quick tracking; chi-square(6): mean 6, and
    6 +- 3 sqrt(12 / 30) = [4.1, 7.9] is the 3-sigma band of a 30-seed mean). Measured
    (docs/mission.md): truth J2, OD J2: 6.92; truth J2 + drag, OD J2 only (the scenario's default
    [od] drag = false): 12.1, biased and optimistic; truth and OD both J2 + drag ([od] drag = true,
    od.make_propagator(force_model=...)): 6.92 again."""
    sc0 = scen.load()
    assert not sc0.od_drag

    def mean_nees(**kw):
        out = []
        for seed in range(30):
            sc = dataclasses.replace(sc0, seed=seed, **kw)
            est = mission.estimate(sc, mission.track(sc, quick=True))
            out.append(est.error @ np.linalg.solve(est.covariance, est.error))
        return float(np.mean(out))

    assert 4.1 < mean_nees(drag=None) < 7.9
    assert 9.0 < mean_nees() < 16.0
    assert 4.1 < mean_nees(od_drag=True) < 7.9


def test_od_drag_key(tmp_path):
    p = _bad(tmp_path, "drag = false", "drag = true")
    sc = scen.load(p)
    assert sc.od_drag
    est = mission.estimate(sc, mission.track(sc, quick=True))
    assert est.model == "point mass + J2 + exponential drag" and est.status == "converged"
    text = p.read_text()
    p2 = tmp_path / "nodrag.toml"
    p2.write_text(text[: text.index("[truth.drag]")])
    with pytest.raises(satgnc.FileFormatError, match=r"key 'drag' in section \[od\]: drag = true takes the "
                       r"atmosphere of \[truth.drag\]"):
        scen.load(p2)
    p3 = tmp_path / "kepler.toml"
    p3.write_text(text.replace('propagator = "cvodes"', 'propagator = "kepler"'))
    with pytest.raises(satgnc.FileFormatError, match=r"drag = true needs propagator = 'cvodes'"):
        scen.load(p3)


def test_a_stage_that_fails_stops_the_mission_with_one_line(tmp_path, capsys):
    """A guess 5 km/s off: the OD ends 'diverged'; the mission stops there (MissionError, a ValueError)
    and the CLI prints one line with exit code 2."""
    old = "guess_offset = [5.0, -5.0, 3.0, 0.005, -0.004, 0.003]"
    p = _bad(tmp_path, old, "guess_offset = [0.0, 0.0, 0.0, -5.0, 0.0, 0.0]")
    with pytest.raises(mission.MissionError, match=r"od: the estimate did not converge \(status diverged\)"):
        mission.run(p, quick=True)
    assert main(["mission", "--quick", "--scenario", str(p), "--out", str(tmp_path / "m")]) == 2
    err = capsys.readouterr().err
    assert err == "satgnc: error: od: the estimate did not converge (status diverged); the mission stops\n"


# ----------------------------------------------------------------------------- stages 4-5 through the library
L1_PAPER = DEFAULT.with_name("mission_l1_paper.toml")


def test_plan_and_flight_go_through_guidance(run):
    """Stage 4 is guidance.plan of mission.problem (the estimated relative state and CW orbit) and
    stage 5 guidance.fly of its U from the true 12-state: the same numbers, bit for bit."""
    pb = mission.problem(run.scenario, run.relative)
    assert isinstance(pb, satgnc.guidance.RendezvousProblem)
    np.testing.assert_array_equal(pb.x0_eci, run.relative.x12)
    assert pb.radius == run.relative.radius and pb.horizon == run.scenario.knots - 1
    ref = satgnc.guidance.plan(pb, "linear")
    np.testing.assert_array_equal(run.plan.U, ref.U)
    assert run.plan.model == "linear" and run.plan.status == ref.status == "solved"
    fl = satgnc.guidance.fly(mission.truth_params(run.scenario), run.relative.x12_true, ref.U, ref.dt)
    np.testing.assert_array_equal(run.flight.X, fl.X)
    assert run.flight.miss_position == fl.miss[0]
    assert run.closed_loop is None and "closed_loop" not in run.statuses  # the file says false


@pytest.fixture(scope="module")
def closed():
    return mission.run(None, quick=True, closed_loop=True)


def test_closed_loop_reaches_the_target(closed, run):
    """guidance.mpc from the TRUE 12-state on the J2 + drag truth, re-planning every 3 intervals from
    the true state on the truth's own model: measured 0.93 m (quick and full: the MPC does not see the
    OD), against 476 m open loop. Bound 5 m: about 5x the measurement, still 100x below the open-loop
    miss; what is left is the last re-plan's horizon (1-3 intervals of 61 s) with |u| <= 5 mN."""
    cl = closed.closed_loop
    assert closed.statuses["closed_loop"] == "success"
    assert cl.miss_position < 5.0, cl.miss_position
    assert cl.miss_velocity < 0.05
    assert closed.flight.miss_position > 200.0  # the open-loop flight of the same run
    np.testing.assert_array_equal(closed.flight.X, run.flight.X)  # closing the loop leaves it alone
    assert cl.X.shape == (closed.scenario.knots, 12) and cl.U.shape == (closed.scenario.knots - 1, 3)
    np.testing.assert_array_equal(cl.X[0], closed.relative.x12_true)  # the MPC starts from the truth
    assert np.max(np.abs(cl.U)) <= closed.scenario.u_max * (1 + 1e-9)
    assert 0.8 < cl.delta_v / closed.plan.delta_v < 1.2  # measured 2.87 vs 2.96 m/s
    assert cl.replans == 33 and cl.replan_every == 3
    rows = [h for h in closed.handoff if h.quantity.startswith("closed-loop miss")]
    assert len(rows) == 1 and rows[0].unit == "m, m/s"
    assert rows[0].value.startswith(f"{cl.miss_position:.2f} m")


def test_cli_closed_loop(tmp_path, capsys):
    assert main(["mission", "--quick", "--closed-loop", "--out", str(tmp_path / "m")]) == 0
    md = (tmp_path / "m" / "mission.md").read_text()
    assert "| 5 flight | closed-loop miss (guidance.mpc" in md and "| 5 flight | open-loop miss" in md
    import json

    js = json.loads((tmp_path / "m" / "mission_summary.json").read_text())
    assert js["closed_loop_miss_position_m"] < 5.0 and js["miss_position_m"] > 200.0
    with pytest.raises(TypeError, match=r"closed_loop: must be None, true or false \(a bool\), got str"):
        mission.run(None, closed_loop="yes")


# ----------------------------------------------------------------------------- partial chains
def test_l1_paper_linear_case_as_mission_stages_4_to_6():
    """mission_l1_paper.toml: the paper's rendezvous file (read by scenarios.rendezvous) through stages
    4-6. Its plan is the reproduction's linear CW plan of the unconstrained case
    (papers.l1_admm_rendezvous.linear_cw_plan): same Y to 1e-12 (measured: equal, 0.0)."""
    from satgnc.papers import l1_admm_rendezvous as paper

    r = mission.run(L1_PAPER)
    assert r.scenario.stages == ("plan", "fly", "check")
    assert r.statuses == {"plan": "solved", "flight": "success", "checks": "success"}
    assert r.tracking is None and r.estimate is None and r.relative is None and r.closed_loop is None
    ref = paper.linear_cw_plan(paper.paper_case(False))
    np.testing.assert_allclose(r.plan.Y.T, np.asarray(ref["result"]["Y"]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(r.plan.U.T, ref["U"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(r.plan.X[0], ref["x0_cw"], rtol=0, atol=1e-9)
    # the flight starts from the paper's drifted release state on the file's [truth] (J2 + drag)
    np.testing.assert_array_equal(r.flight.X[0], paper.drift_state())
    assert r.flight.truth == "point mass + J2 + exponential drag"
    assert 100.0 < r.flight.miss_position < r.scenario.miss_tolerance == 400.0  # measured 159 m
    assert r.flight.predicted_3sigma == 0.0  # no OD in this chain
    assert r.checks.controllability == "full rank" and r.checks.observability == "not run"
    assert [h.stage for h in r.handoff] == ["4 plan", "4 plan", "5 flight", "6 checks"]


def test_l1_paper_closed_loop_and_report(tmp_path):
    r = mission.run(L1_PAPER, closed_loop=True)
    assert r.closed_loop.miss_position < 1.0  # measured 0.048 m (open loop 159 m)
    from satgnc.report import mission as report

    path = report.write(r, tmp_path / "l1")
    assert "stages plan, fly, check" in path.read_text()
    assert (tmp_path / "l1" / "figures" / "mission.png").stat().st_size > 10_000


def test_od_paper_shape_chain_tracking_and_od_only(tmp_path):
    """first_stage = 'track', last_stage = 'estimate' (the OD paper's pipeline shape: stages 1-2): the
    rendezvous section is not read; the estimate equals the full run's."""
    text = DEFAULT.read_text()
    p = tmp_path / "od_only.toml"
    p.write_text('last_stage = "estimate"\n' + text[: text.index("[rendezvous]")]
                 + text[text.index("[truth]"):])
    r = mission.run(p, quick=True)
    assert r.statuses == {"tracking": "success", "od": "converged"}
    assert r.plan is None and r.flight is None and r.checks is None
    full = mission.run(None, quick=True)
    np.testing.assert_array_equal(r.estimate.x0, full.estimate.x0)
    assert {h.stage for h in r.handoff} == {"1 tracking", "2 OD"}


def test_partial_chain_errors(tmp_path):
    text = DEFAULT.read_text()
    p = tmp_path / "a.toml"
    p.write_text('first_stage = "plan"\n' + text)
    with pytest.raises(satgnc.FileFormatError, match=r"first_stage = 'plan' needs \[rendezvous\] scenario"):
        scen.load(p)
    p.write_text('first_stage = "track"\nlast_stage = "fly"\n' + text.replace("[rendezvous]\n",
                 '[rendezvous]\nscenario = "l1_rendezvous.toml"\ncase = "unconstrained"\n'))
    with pytest.raises(satgnc.FileFormatError, match=r"key 'scenario' in section \[rendezvous\]: a "
                       r"rendezvous scenario file gives its own orbit"):
        scen.load(p)
    no_truth = text[: text.index("[truth]")]
    p.write_text('first_stage = "plan"\nlast_stage = "fly"\n' + no_truth.replace("[rendezvous]\n",
                 '[rendezvous]\nscenario = "l1_rendezvous.toml"\ncase = "unconstrained"\n'))
    with pytest.raises(satgnc.FileFormatError, match=r"key 'position' in section \[rendezvous\]: the "
                       r"rendezvous scenario 'l1_rendezvous.toml' gives it"):
        scen.load(p)
    absolute = repr(str(DEFAULT.with_name("l1_rendezvous.toml")))
    l1 = L1_PAPER.read_text().replace('"l1_rendezvous.toml"', absolute)
    p.write_text(l1.replace('last_stage = "check"', 'last_stage = "estimate"'))
    with pytest.raises(satgnc.FileFormatError, match=r"key 'last_stage': 'estimate' comes before "
                       r"first_stage"):
        scen.load(p)
    p.write_text(l1)
    assert scen.load(p).rendezvous.path == DEFAULT.with_name("l1_rendezvous.toml")
    p.write_text(l1.replace('case = "unconstrained"', 'case = "unconstraind"'))
    with pytest.raises(satgnc.FileFormatError, match=r"unknown case 'unconstraind' of l1_rendezvous.toml"):
        scen.load(p)
    p.write_text(l1.replace('first_stage = "plan"', 'first_stage = "fly"'))
    with pytest.raises(satgnc.FileFormatError, match=r"first_stage.*'track', 'plan'"):
        scen.load(p)


def test_nonlinear_plan_leaves_the_od_error():
    """model = "nonlinear": guidance.plan's SCP on the two-satellite model with the truth's terms, from
    the OD estimate, flown open loop: measured 17 m (quick), against 476 m for the CW plan; the OD
    error's 3 sigma at tf is 25 m. Bound 50 m: 3x the measurement, 10x below the CW plan's miss."""
    sc = dataclasses.replace(scen.load(), model="nonlinear")
    r = mission.run(sc, quick=True)
    assert r.plan.model == "nonlinear" and r.plan.status == "solved"
    assert r.flight.miss_position < 50.0, r.flight.miss_position
    assert r.plan.X.shape == (sc.knots, 6) and r.plan.Y.shape == (sc.knots - 1, 3)
