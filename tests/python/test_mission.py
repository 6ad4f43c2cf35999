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
    assert sum(r.timings.values()) < 20.0, r.timings


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
    assert units[("5 flight", "miss at tf = 6000 s on point mass + J2 + exponential drag")] == "m, m/s"
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


def test_tracking_is_od_simulate_on_the_truth_states():
    """Without drag (which od.simulate cannot take), stage 1 gives od.simulate's observations: same
    noise draws (seed), mask and measurement model; the states differ only by the two CVODES set-ups."""
    import dataclasses as dc

    sc = dc.replace(scen.load(), drag=None)
    tr = mission.track(sc, quick=True)
    times = sc.times[:: sc.quick_thin]
    obs = satgnc.od.simulate(sc.x0, list(tr.stations), times, types=sc.types, sigma_range=sc.sigma_range,
                             sigma_range_rate=sc.sigma_range_rate, elevation_mask_deg=sc.mask, seed=sc.seed,
                             propagator=satgnc.od.make_propagator("cvodes", j2=True))
    assert len(obs) == tr.t.size == 58
    a = np.lexsort((obs.station, obs.t))  # simulate orders by station, then time
    np.testing.assert_array_equal(obs.t[a], tr.t)
    np.testing.assert_array_equal(obs.station[a], tr.station)
    np.testing.assert_array_equal(obs.sigma[a], tr.sigma)
    rng = np.array([k == "range" for k in tr.type])
    assert [str(k).split(".")[-1] for k in np.array(obs.type, dtype=object)[a]] == list(tr.type)
    # 1 mm in range (sigma 5 m) and 1e-9 km/s in range-rate (sigma 1e-6): the two CVODES tolerances
    np.testing.assert_allclose(obs.value[a][rng], tr.value[rng], rtol=0, atol=1e-6)
    np.testing.assert_allclose(obs.value[a][~rng], tr.value[~rng], rtol=0, atol=1e-9)


def test_od_covariance_consistency_over_seeds():
    """NEES e' P^-1 e of the OD estimate over 30 seeds (quick tracking). With the truth the OD model can
    represent (J2, no drag) its mean is chi-square(6)'s: 6 +- 3 * sqrt(12 / 30) = [4.1, 7.9]. With the
    scenario's drag, which the OD model lacks (od.make_propagator takes mu and J2 only), the estimate is
    biased and the covariance optimistic: measured mean 12.1 (docs/mission.md)."""
    import dataclasses as dc

    sc0 = scen.load()

    def mean_nees(**kw):
        out = []
        for seed in range(30):
            sc = dc.replace(sc0, seed=seed, **kw)
            est = mission.estimate(sc, mission.track(sc, quick=True))
            out.append(est.error @ np.linalg.solve(est.covariance, est.error))
        return float(np.mean(out))

    assert 4.1 < mean_nees(drag=None) < 7.9
    assert 9.0 < mean_nees() < 16.0


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
