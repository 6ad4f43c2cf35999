"""satgnc.od API: stations, measurements and partials, solvers, OD Jacobian, bad input, CSV/TDM, CLI."""

from __future__ import annotations

import math

import numpy as np
import pytest
from satgnc import od
from satgnc.od.tdm import read_tdm, write_tdm
from satgnc.papers import od_newton_raphson as paper


def test_gmst_vallado_example_3_5():
    # Vallado, Fundamentals of Astrodynamics and Applications, 4th ed., Example 3-5:
    # 1992-08-20 12:14 UT1 -> GMST 152.578787886 deg (printed to 1e-9 deg; printings differ at 1e-7).
    assert math.degrees(od.gmst("1992-08-20T12:14:00")) == pytest.approx(152.578787886, abs=1e-6)


def test_station_geodetic_rotates_with_earth():
    st = od.station_geodetic(23 + 10 / 60, 113.25, 0.15, "1981-03-21T06:00:00", ellipsoid="Krassovsky")
    x0 = st.state(0.0)
    assert np.linalg.norm(x0[3:] - od.EARTH_OMEGA * np.array([-x0[1], x0[0], 0.0])) < 1e-15
    assert np.linalg.norm(st.state(86164.0905)[:3] - x0[:3]) < 0.5  # one sidereal day: back within 0.5 km


@pytest.mark.parametrize("kind", ["range", "range_rate"])
def test_partials_match_finite_differences(kind):
    x = paper.truth()
    R = paper.station_state_table3()
    _, g = od.predict(kind, x, R)
    fd = np.zeros(6)
    for i in range(6):
        h = 1e-3 if i < 3 else 1e-6
        e = np.zeros(6)
        e[i] = h
        fd[i] = (od.predict(kind, x + e, R)[0] - od.predict(kind, x - e, R)[0]) / (2 * h)
    # Central differences: ~1e-8 relative for these step sizes.
    np.testing.assert_allclose(g, fd, rtol=1e-7, atol=1e-12)


def test_whole_od_jacobian_matches_finite_differences():
    obs = od.simulate(paper.truth(), paper.station(), np.arange(0, 301, 30.0), seed=None)
    sv = od.solver(obs, paper.station(), "gauss_newton")
    x = paper.truth() + np.array([5.0, -3.0, 2.0, 0.002, 0.001, -0.003])
    st, r0, J = sv.evaluate(x)
    assert st == od.OdStatus.converged
    assert J.shape == (len(obs), 6)
    fd = np.zeros_like(J)
    for i in range(6):
        h = 1e-3 if i < 3 else 1e-6
        e = np.zeros(6)
        e[i] = h
        fd[:, i] = (sv.evaluate(x + e)[1] - sv.evaluate(x - e)[1]) / (2 * h)
    # Exact Kepler STM against differences of the Kepler map: ~1e-7 relative per column.
    for i in range(6):
        assert np.max(np.abs(J[:, i] - fd[:, i])) <= 1e-6 * np.max(np.abs(fd[:, i]))


def test_batch_two_stations_and_covariance():
    st = [paper.station(), od.station_inertial([5200.0, 3000.0, 1900.0])]
    obs = od.simulate(paper.truth(), st, np.arange(0, 301, 10.0), seed=3)
    r = od.solve(obs, st, paper.truth() + np.array([30, -20, 10, 0.01, -0.01, 0.02]))
    assert r.status == od.OdStatus.converged
    assert r.fits
    P = np.asarray(r.covariance)
    assert np.allclose(P, P.T, rtol=1e-10, atol=0)
    assert np.all(np.linalg.eigvalsh(P) > 0)
    np.testing.assert_allclose(np.diag(r.correlation), 1.0, atol=1e-12)
    err = np.asarray(r.x0) - paper.truth()
    assert np.all(np.abs(err) < 5 * np.sqrt(np.diag(P)))  # within 5 formal sigma
    assert r.history_residuals.shape == (r.iterations + 1, len(obs))


def test_six_point_newton_paper_offsets():
    rho, rhodot = paper.observe()
    for d in (10.0, 20.0, 30.0, 40.0):
        g = paper.truth().copy()
        g[0] += d
        r = od.solve_six_point(paper.times(), rho, rhodot, paper.station(), g)
        assert r.status == od.OdStatus.converged
        assert r.iterations <= 5  # issue goal
        assert abs(r.x0[0] - paper.truth()[0]) < 1e-4  # < 10 cm


def test_mixed_conditions_range_and_doppler():
    rho, rhodot = paper.observe()
    g = paper.truth().copy()
    g[0] += 5.0
    r = od.solve_six_point(
        paper.times(),
        rho,
        rhodot,
        paper.station(),
        g,
        mode=["range", "doppler", "range", "doppler", "range", "doppler"],
    )
    assert r.status == od.OdStatus.converged
    assert np.linalg.norm(r.x0[:3] - paper.truth()[:3]) < 1e-3


def test_statuses_singular_and_diverged():
    rho, rhodot = paper.observe()
    inside = paper.truth().copy()
    inside[:3] *= 0.5
    r = od.solve_six_point(paper.times(), rho, rhodot, paper.station(), inside)
    assert r.status == od.OdStatus.diverged
    # Six ranges at one instant from six stations: velocity unobservable, rank 3.
    sts = [
        od.station_inertial(np.asarray(paper.station().r0) + [100.0 * i, -50.0 * i * i, 30.0 * i])
        for i in range(6)
    ]
    vals = [od.predict("range", paper.truth(), s.state(0.0))[0] for s in sts]
    obs = od.Observations([0.0] * 6, "range", vals, 1e-3, list(range(6)))
    r = od.solve(obs, sts, paper.truth() + 1e-3, method="gauss_newton")
    assert r.status == od.OdStatus.singular
    assert r.rank == 3


def test_root_search_lists_truth():
    rho, rhodot = paper.observe()
    sv = od.six_point_solver(
        paper.times(), rho, rhodot, paper.station(), method="levenberg_marquardt", max_iterations=200
    )
    g = od.box_guesses(paper.truth(), [50, 50, 50, 0.05, 0.05, 0.05], 6, seed=4)
    rs = od.root_search(sv, g)
    assert rs.fitting_roots >= 1
    assert any(np.linalg.norm(np.asarray(r.x0)[:3] - paper.truth()[:3]) < 1e-3 and r.fits for r in rs.roots)
    assert len(rs.guess_root) == 6


# ----------------------------------------------------------------------------- bad input
def test_bad_input_six_point():
    rho, rhodot = paper.observe()
    with pytest.raises(ValueError, match="exactly 6"):
        od.solve_six_point(paper.times()[:5], rho[:5], rhodot[:5], paper.station(), paper.truth())
    t = paper.times().copy()
    t[3] = t[2]
    with pytest.raises(ValueError, match="duplicate"):
        od.solve_six_point(t, rho, rhodot, paper.station(), paper.truth())
    with pytest.raises(ValueError, match="sigma_range_rate"):
        od.six_point_solver(paper.times(), rho, rhodot, paper.station(), sigma_range_rate=-1.0)
    with pytest.raises(ValueError, match="sigma_range"):
        od.six_point_solver(paper.times(), rho, rhodot, paper.station(), sigma_range=float("nan"))
    with pytest.raises(ValueError, match="mode"):
        od.solve_six_point(paper.times(), rho, rhodot, paper.station(), paper.truth(), mode="azimuth")
    with pytest.raises(ValueError, match="x0_guess"):
        od.solve_six_point(paper.times(), rho, rhodot, paper.station(), [1, 2, 3])
    with pytest.raises(TypeError, match="x0_guess"):
        od.solve_six_point(paper.times(), rho, rhodot, paper.station(), "abc")


def test_bad_input_observations():
    with pytest.raises(ValueError, match="sigma"):
        od.Observations([0, 1], "range", [1000.0, 1000.0], [1e-3, -1.0], 0)
    with pytest.raises(ValueError, match="sigma"):
        od.Observations([0, 1], "range", [1000.0, 1000.0], [1e-3, float("inf")], 0)
    with pytest.raises(ValueError, match="azimuth"):
        od.Observations([0, 1], ["range", "azimuth"], [1000.0, 1.0], 1e-3, 0)
    with pytest.raises(TypeError, match="type"):
        od.Observations([0], [3.5], [1.0], 1e-3, 0)
    obs = od.Observations(np.arange(6.0), "range", np.full(6, 1000.0), 1e-3, 0)
    obs.t[1] = 0.0
    with pytest.raises(ValueError, match="duplicate time"):
        od.solve(obs, paper.station(), paper.truth())
    obs5 = od.Observations(np.arange(5.0), "range", np.full(5, 1000.0), 1e-3, 0)
    with pytest.raises(ValueError, match="at least 6"):
        od.solve(obs5, paper.station(), paper.truth())
    zero = od.Observations(np.arange(6.0), "range", np.r_[0.0, np.full(5, 1000.0)], 1e-3, 0)
    with pytest.raises(ValueError, match="zero range"):
        od.solve(zero, paper.station(), paper.truth())
    with pytest.raises(TypeError, match="setting"):
        od.settings("lm", not_a_setting=1)
    with pytest.raises(ValueError, match="method"):
        od.settings("simplex")


def test_station_at_satellite_zero_range():
    x = paper.truth()
    with pytest.raises(ValueError, match="zero range"):
        od.predict("range_rate", x, x)
    # A solve whose satellite passes through the station reports degenerate geometry, no NaN.
    st = od.station_inertial(x[:3], 0.0)
    rho, rhodot = paper.observe()
    r = od.solve_six_point(paper.times(), rho, rhodot, st, x)
    assert r.status == od.OdStatus.degenerate_geometry
    with pytest.raises(ValueError, match="r0"):
        od.station_inertial([0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="r0"):
        od.station_inertial([1.0, float("nan"), 0.0])


# ----------------------------------------------------------------------------- files and CLI
def test_csv_and_tdm_round_trip(tmp_path):
    import datetime as dt

    obs = od.simulate(paper.truth(), paper.station(), np.arange(0, 301, 20.0), seed=None)
    p = write_tdm(tmp_path / "a.tdm", obs, dt.datetime(1981, 3, 21, 6), ["GZ"])
    back, names, epoch = read_tdm(p)
    assert names == ["GZ"]
    assert epoch == dt.datetime(1981, 3, 21, 6)
    np.testing.assert_allclose(back.t, obs.t, atol=1e-6)
    np.testing.assert_allclose(back.value, obs.value, rtol=1e-12)
    assert back.type_names() == obs.type_names()
    csv = tmp_path / "a.csv"
    csv.write_text("t,type,value,sigma,station\n0,range,1000.0,0.001,0\n# comment\n60,doppler,1.5,1e-6,0\n")
    c = od.read_csv(csv)
    assert c.type_names() == ["range", "range_rate"]


def test_tdm_errors_name_the_line(tmp_path):
    good = [
        "CCSDS_TDM_VERS = 2.0",
        "META_START",
        "TIME_SYSTEM = UTC",
        "PARTICIPANT_1 = GZ",
        "META_STOP",
        "DATA_START",
        "RANGE = 1981-080T06:00:00 1321.104",
        "DATA_STOP",
    ]
    p = tmp_path / "ok.tdm"
    p.write_text("\n".join(good))
    obs, _, _ = read_tdm(p)
    assert len(obs) == 1
    for lineno, bad in (
        (7, "RANGE 1981-080T06:00:00 1321.104"),
        (7, "RANGE = 1981-080T06:00:00"),
        (7, "ANGLE_1 = 1981-080T06:00:00 12.0"),
        (7, "RANGE = 1981-13-80T06:00:00 1.0"),
        (3, "TIME_SYSTEM = TAI"),
    ):
        lines = list(good)
        lines[lineno - 1] = bad
        p.write_text("\n".join(lines))
        with pytest.raises(ValueError, match=rf"ok\.tdm:{lineno}:"):
            read_tdm(p)
    csv = tmp_path / "bad.csv"
    csv.write_text("t,type,value,sigma\n0,range,1000,0.001\n5,range,abc,0.001\n")
    with pytest.raises(ValueError, match="bad.csv:3"):
        od.read_csv(csv)


def test_cli_simulate_and_solve(tmp_path, capsys):
    from satgnc.cli import main

    for ext in ("csv", "tdm"):
        f = tmp_path / f"obs.{ext}"
        assert main(["od", "simulate", "--out", str(f), "--seed", "1"]) == 0
        guess = ",".join(str(v) for v in paper.truth() + np.array([10, 0, 0, 0, 0, 0]))
        r0 = ",".join(str(v) for v in paper.station_state_table3()[:3])
        args = [
            "od",
            "solve",
            str(f),
            "--guess",
            guess,
            "--station-inertial",
            f"STATION:{r0}",
            "--plots",
            str(tmp_path / "plots"),
        ]
        if ext == "tdm":
            args += ["--epoch", "1981-03-21T06:00:00"]
        assert main(args) == 0
        out = capsys.readouterr().out
        assert "status      : converged" in out
        assert (tmp_path / "plots" / "residuals_range.png").exists()
    assert (
        main(
            [
                "od",
                "solve",
                str(tmp_path / "missing.csv"),
                "--guess",
                "1,2,3,4,5,6",
                "--station-inertial",
                "1,2,3",
            ]
        )
        == 2
    )


def test_simulate_noise_bias_and_elevation_mask():
    t = np.arange(0, 301, 30.0)
    clean = od.simulate(paper.truth(), paper.station(), t, seed=None)
    biased = od.simulate(paper.truth(), paper.station(), t, seed=None, bias_range=0.01, bias_range_rate=1e-4)
    rng_sel = np.array([k == "range" for k in clean.type_names()])
    np.testing.assert_allclose(biased.value[rng_sel] - clean.value[rng_sel], 0.01, atol=1e-12)
    np.testing.assert_allclose(biased.value[~rng_sel] - clean.value[~rng_sel], 1e-4, atol=1e-15)
    a = od.simulate(paper.truth(), paper.station(), t, seed=5)
    b = od.simulate(paper.truth(), paper.station(), t, seed=5)
    np.testing.assert_array_equal(a.value, b.value)  # seeded
    assert np.std((a.value - clean.value)[rng_sel]) < 3e-3
    elev = [od.elevation_deg(x, paper.station().state(tk))
            for x, tk in zip(od.make_propagator().propagate(paper.truth(), list(t))[0], t)]
    masked = od.simulate(paper.truth(), paper.station(), t, seed=None, elevation_mask_deg=30.0)
    assert len(masked) == 2 * int(np.sum(np.array(elev) >= 30.0))
    assert 0 < len(masked) < len(clean)
    with pytest.raises(ValueError, match="elevation_mask_deg"):
        od.simulate(paper.truth(), paper.station(), t, elevation_mask_deg=89.9)
    with pytest.raises(ValueError, match="times"):
        od.simulate(paper.truth(), paper.station(), [0.0, 0.0, 1.0])


def test_ellipsoids_and_ut1():
    assert od.ellipsoid("grs80").name == "GRS-80"
    assert od.ellipsoid("Krassovsky").a == pytest.approx(6378.245)
    with pytest.raises(ValueError, match="ellipsoid"):
        od.ellipsoid("bessel")
    g0 = od.gmst("1981-03-21T06:00:00")
    g1 = od.gmst("1981-03-21T06:00:00", ut1_minus_utc=0.5)
    assert math.degrees(g1 - g0) * 3600 == pytest.approx(0.5 * 15 * 1.0027379, abs=2e-3)
    with pytest.raises(ValueError, match="epoch"):
        od.gmst("21 March 1981")


def test_solver_settings_and_statuses():
    s = od.settings("gauss_newton")
    assert s.max_iterations == 100 and s.gn_max_halvings == 40 and s.geodesic is True
    assert s.step_sigma_tol == 1e-6 and s.cost_tol == 1e-6 and s.rank_tol == 1e-13
    with pytest.raises(ValueError, match="gn_max_halvings"):
        od.settings("gauss_newton", gn_max_halvings=-1)
    # Appended statuses keep the old values; every status has a message.
    assert [od.OdStatus.converged.value, od.OdStatus.degenerate_geometry.value] == [0, 5]
    assert od.OdStatus.unsolved.value == 6 and od.OdStatus.stalled.value == 7
    from satgnc import _satgnc

    assert "stalled" in _satgnc.od_status_message(od.OdStatus.stalled)
    # Without the geodesic acceleration GN still never raises the cost (line search).
    obs = od.simulate(paper.truth(), paper.station(), np.arange(0, 301, 10.0), seed=2)
    r = od.solve(obs, paper.station(), paper.truth(), "gauss_newton", geodesic=False, max_iterations=20)
    assert np.all(np.diff(r.history_cost) <= 0)
    assert r.history_x0.shape == (r.iterations + 1, 6)
    assert r.status in (od.OdStatus.converged, od.OdStatus.max_iterations, od.OdStatus.stalled)
