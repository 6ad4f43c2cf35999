"""Every public function of satgnc, satgnc.od, satgnc.guidance, satgnc.analysis and satgnc.propagation,
called once with small valid inputs; each call asserts its result's type and shape.

Both a pytest and a type-check target: ``mypy --strict tests/python/test_api_surface.py`` (make lint) checks
these calls against the package's annotations and the complete ``_satgnc.pyi``. Units: orbits km, km/s, s;
relative motion m, m/s, N, kg."""

from __future__ import annotations

import inspect
import math
import pathlib
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import satgnc
from satgnc import _satgnc, od
from satgnc import analysis as an
from satgnc import guidance as g
from satgnc import propagation as prop

X_LEO = np.array([7000.0, 0.0, 0.0, 0.0, 7.5, 1.0])  # km, km/s
N_MEAN = 0.0011  # rad/s


# ----------------------------------------------------------------------------- satgnc, satgnc.propagation
def test_propagate_and_methods() -> None:
    for mod in (satgnc, prop):
        tr = mod.propagate(X_LEO, [0.0, 30.0, 60.0])
        assert isinstance(tr, satgnc.Trajectory)
        assert tr.states.shape == (3, 6) and tr.status == "success"
        methods = mod.available_methods()
        assert isinstance(methods, list) and "adams" in methods
        x = mod.elements_to_state(7000.0, 0.01, 51.6, 30.0, 40.0, 10.0)
        assert isinstance(x, np.ndarray) and x.shape == (6,)


def test_propagate_sensitivity_and_load_force_model() -> None:
    r = satgnc.propagate_sensitivity(X_LEO, [0.0, 30.0, 60.0], ["mu"])
    assert isinstance(r, satgnc.SensitivityResult) and r.parameters == ("mu",)
    assert r.sensitivities.shape == (3, 6, 1) and r.stms.shape == (3, 6, 6)
    example = pathlib.Path(__file__).resolve().parents[2] / "examples" / "force_model.toml"
    fm = satgnc.load_force_model(example)
    assert isinstance(fm, satgnc.ForceModel) and fm.gravity is not None


def test_propagate_ensemble() -> None:
    states = np.array([X_LEO, X_LEO * 1.001])
    r = prop.propagate_ensemble(states, [0.0, 30.0, 60.0], satgnc.J2Gravity(), threads=2)
    assert isinstance(r, prop.EnsembleResult) and r.all_success
    assert r.states.shape == (2, 3, 6) and r.stms is not None and r.stms.shape == (2, 3, 6, 6)
    assert r.status == ("success", "success")


# ----------------------------------------------------------------------------- satgnc.guidance
def test_guidance_functions() -> None:
    A, B = g.cw_matrices(N_MEAN, 10.0)
    assert A.shape == (6, 6) and B.shape == (6, 3)
    Phi = g.cw_stm(N_MEAN, 60.0)
    assert Phi.shape == (6, 6)
    Ad, Bd = g.cw_discretize(N_MEAN, 1.0, 60.0)
    assert Ad.shape == (6, 6) and Bd.shape == (6, 3)
    h = g.cw_to_hill([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
    assert h.shape == (6,) and g.hill_to_cw(h).tolist() == [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    r = g.solve_l1(Ad, Bd, [100.0, 50.0, 0.0, 0.0, 0.0, 0.0], horizon=10, Qf=np.eye(6) * 1e4)
    assert isinstance(r, g.L1Result) and r.status == "solved"
    assert r.Y.shape == (10, 3) and r.X.shape == (11, 6) and isinstance(r.iterations, int)


def test_guidance_keyword_settings_and_solver() -> None:
    st = g.AdmmSettings(eps_abs=1e-6, max_iterations=500, stopping="residuals")
    assert st.eps_abs == 1e-6 and st.max_iterations == 500
    with pytest.raises(TypeError, match="eps_absolute: unknown keyword of AdmmSettings"):
        g.AdmmSettings(eps_absolute=1e-6)  # type: ignore[call-arg]
    Ad, Bd = g.cw_discretize(N_MEAN, 1.0, 60.0)
    x0 = [100.0, 50.0, 0.0, 0.0, 0.0, 0.0]
    solver = g.L1Solver(Ad, Bd, x0, horizon=10, Qf=np.eye(6) * 1e4, settings=st)
    r = solver.solve()
    assert r.status == "solved" and r.U.shape == (10, 3)
    problem = _satgnc.LtvProblem(A=[Ad], B=[Bd], horizon=10, x0=np.array(x0), Qf=np.eye(6) * 1e4,
                                 l1_weights=np.ones(3))
    assert (problem.nx, problem.nu, problem.horizon) == (6, 3, 10)
    d = _satgnc.AdmmSolver(problem, st).solve()
    with pytest.raises(TypeError, match="problem: must be LtvProblem, got str"):
        _satgnc.AdmmSolver(problem="x")  # type: ignore[call-overload]
    with pytest.raises(TypeError, match="settings: must be AdmmSettings, got int"):
        _satgnc.AdmmSolver(problem, 3)  # type: ignore[call-overload]
    empty = np.zeros(0)
    with pytest.raises(TypeError, match="A: must be a real numeric array, got a complex array"):
        _satgnc.AdmmSolver([Ad + 0j], [Bd], [], 10, np.array(x0), np.zeros(6), np.eye(6), np.zeros((0, 0)),
                           np.zeros((0, 0)), np.ones(3), 0.0, empty, empty, 0.0, False, st)  # still checked
    np.testing.assert_array_equal(np.asarray(d["Y"]).T, r.Y)  # the keyword binding solves the same problem
    for cls in (_satgnc.IlqrAdmmSettings, _satgnc.ScpSettings, od.OdSettings):
        with pytest.raises(TypeError, match=f"bogus: unknown keyword of {cls.__name__}"):
            cls(bogus=1)  # type: ignore[call-arg]
    assert _satgnc.IlqrAdmmSettings(rho=2.0).rho == 2.0
    assert od.OdSettings(max_iterations=7).max_iterations == 7
    assert od.OdSettings(method="gauss_newton").method == od.OdMethod.gauss_newton  # enum names as strings


def test_guidance_rendezvous_library() -> None:
    """plan / fly / mpc on a small explicit problem (m, m/s, N, kg, s; 12-states ECI)."""
    tp = g.satellite_params(3.986e14, j2=True, drag=False, mass=10.0)
    x0 = np.array([-50.0, 10.0, 0.0, 0.05, 0.0, 0.0])
    pb = g.RendezvousProblem(mu=3.986e14, radius=7.0e6, mass=10.0, x0=x0, tf=600.0, horizon=6, alpha=1.0,
                             Qf=100.0, u_max=0.05)
    for model, nx in (("linear", 6), ("nonlinear", 12)):
        p = g.plan(pb, model)
        assert isinstance(p, g.Plan) and p.U.shape == (6, 3) and p.X.shape == (7, nx)
        assert isinstance(p.status, str) and isinstance(p.summary()["delta_v"], float)
    f = g.fly(tp, pb.state_eci(), p.U, pb.dt)
    assert isinstance(f, g.Flight) and f.X.shape == (7, 12) and f.t.shape == (7,)
    m = g.mpc(pb, truth=tp, max_iter=3, first_max_iter=100)
    assert isinstance(m, g.MpcRun) and m.X.shape == (7, 12) and m.U.shape == (6, 3)


# ----------------------------------------------------------------------------- satgnc.od
def _station_obs() -> tuple[od.Station, od.Observations, npt.NDArray[np.float64]]:
    x0, r0 = an.paper_od_state()
    st = od.station_inertial(r0)
    obs = od.simulate(x0, st, np.arange(0.0, 301.0, 60.0), seed=None)
    return st, obs, x0


def _split(obs: od.Observations) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """(ranges km, range-rates km/s) of a simulated table, in time order."""
    is_range = np.array([k == od.MeasurementType.range for k in obs.type])
    return obs.value[is_range], obs.value[~is_range]


def test_od_time_and_stations() -> None:
    jd = od.julian_date("2000-01-01T12:00:00")
    assert jd == 2451545.0
    theta = od.gmst(jd)
    assert isinstance(theta, float) and 0.0 <= theta < 2 * math.pi
    e = od.ellipsoid("WGS-84")
    assert isinstance(e, od.Ellipsoid)
    ecef = od.geodetic_to_ecef(45.0, 10.0, 0.1)
    assert ecef.shape == (3,)
    st = od.station_geodetic(45.0, 10.0, 0.1, jd)
    assert isinstance(st, od.Station)
    st2 = od.station_inertial([6378.0, 0.0, 0.0])
    assert isinstance(st2, od.Station)
    rate = od.implied_rotation_rate(np.array([6378.0, 0.0, 0.0, 0.0, 0.465, 0.0]))
    assert isinstance(rate, float) and rate > 0
    v, partials = od.predict("range", X_LEO, np.array([6378.0, 0.0, 0.0, 0.0, 0.465, 0.0]))
    assert isinstance(v, float) and partials.shape == (6,)
    assert isinstance(od.make_propagator("kepler"), od.KeplerStmPropagator)
    s = od.settings("gauss_newton", max_iterations=20)
    assert isinstance(s, od.OdSettings) and s.max_iterations == 20


def test_od_solvers(tmp_path: pathlib.Path) -> None:
    st, obs, x0 = _station_obs()
    assert isinstance(obs, od.Observations) and len(obs) == 12
    r = od.solve(obs, st, x0 + np.array([1.0, -1.0, 0.5, 1e-3, -1e-3, 0.0]))
    assert r.status == od.OdStatus.converged and np.asarray(r.x0).shape == (6,)
    t = np.arange(0.0, 301.0, 60.0)
    rho, _ = _split(obs)
    conds = od.six_point_conditions(t, rho, mode="range")
    assert isinstance(conds, list) and len(conds) == 6
    csv = tmp_path / "obs.csv"
    csv.write_text("t,type,value,sigma\n" + "".join(f"{ti},range,{vi},0.001\n" for ti, vi in zip(t, rho)))
    back = od.read_csv(csv)
    assert isinstance(back, od.Observations) and len(back) == 6
    named = tmp_path / "named.csv"
    named.write_text("t,type,value,sigma,station\n" + "".join(
        f"{ti},range,{vi},0.001,{'BOULDER' if k % 2 else 'PERTH'}\n"
        for k, (ti, vi) in enumerate(zip(t, rho))))
    back, names = od.read_csv_names(named)
    assert names == ["PERTH", "BOULDER"] and back.station.tolist() == [0, 1, 0, 1, 0, 1]
    guesses = od.box_guesses(x0, [1.0, 1.0, 1.0, 1e-3, 1e-3, 1e-3], 3, seed=1)
    assert guesses.shape == (3, 6)
    found = od.root_search(od.solver(obs, st, "gauss_newton"), guesses)
    assert len(found.roots) >= 1


def test_od_six_point() -> None:
    x0, r0 = an.paper_od_state()
    st = od.station_inertial(r0)
    t = np.arange(0.0, 301.0, 60.0)
    rho, rhodot = _split(od.simulate(x0, st, t, seed=None))
    r = od.solve_six_point(t, rho, rhodot, st, x0 + 0.01 * np.array([1.0, 1.0, 1.0, 1e-3, 1e-3, 1e-3]))
    assert r.status == od.OdStatus.converged
    assert abs(r.x0[0] - x0[0]) < 1e-4  # km: the six exact observations pin the state (< 10 cm)


# ----------------------------------------------------------------------------- satgnc.analysis
def test_analysis_models_and_units() -> None:
    sigma, omega = an.orbit("leo")
    assert sigma > 6378.0 and omega > 0
    assert isinstance(an.polar_model(1.0, 1.0), an.PolarModel)
    A, B, C = an.polar_linear_model(1.0, 1.0)
    assert (A.shape, B.shape, C.shape) == ((4, 4), (4, 2), (2, 4))
    Acw, Bcw, Ccw = an.cw_model(N_MEAN)
    assert (np.shape(Acw), np.shape(Bcw), np.shape(Ccw)) == ((6, 6), (6, 3), (3, 6))
    u = an.polar_units(1.0, 1.0, n_outputs=2)
    assert isinstance(u, an.Units) and u.state.shape == (4,)
    ucw = an.cw_units(N_MEAN, 100.0, n_outputs=3)
    assert isinstance(ucw, an.Units) and ucw.time == pytest.approx(1.0 / N_MEAN)
    An, Bn, Cn = an.nondimensionalize(A, B, C, u)
    assert np.shape(An) == (4, 4) and np.shape(Bn) == (4, 2) and np.shape(Cn) == (2, 4)


def test_analysis_rank_tests() -> None:
    A, B, C = an.polar_linear_model(1.0, 1.0)
    sc = an.staircase(A, B)
    assert isinstance(sc, an.StaircaseReport) and sc.rank == 4
    assert an.controllability(A, B).full and an.observability(A, C).full
    pb = an.pbh(A, B)
    assert isinstance(pb, an.PbhReport) and pb.rank == 4
    kr = an.kalman_rank(A, B)
    assert isinstance(kr, an.RankReport) and kr.rank == 4
    assert an.kalman_matrix(A, B=B).shape == (4, 8)
    d = an.distance_to_uncontrollability(A, B)
    assert isinstance(d, an.DistanceReport) and 0 < d.refined <= d.upper_bound
    rows = an.loss_table(A, B=B)
    assert len(rows) == 3 and all(isinstance(r, an.LossRow) for r in rows)
    text = an.format_loss_table(rows, ["u1", "u2"], 4)
    assert text.count("\n") == 4


def test_analysis_gramians_and_jacobians() -> None:
    A, B, C = an.polar_linear_model(1.0, 1.0)
    Wc = an.controllability_gramian(A, B, 1.0)
    assert isinstance(Wc, an.GramianReport) and Wc.W.shape == (4, 4)
    Wo = an.observability_gramian(A, C, 1.0)
    assert Wo.W.shape == (4, 4)
    lt = an.ltv_observability_gramian([np.eye(4)] * 2, [C, C])
    assert lt.W.shape == (4, 4)
    e = an.minimum_energy(Wc.W, np.ones(4))
    assert isinstance(e, float) and e > 0
    assert an.expm(np.zeros((3, 3))).shape == (3, 3)
    m = an.polar_model(1.0, 1.0)

    def f(t: float, x: Any, u: Any) -> Any:
        return m.rhs(t, x, u)

    def jac(t: float, x: Any, u: Any) -> Any:
        return m.jacobians(t, x, u)

    x, u0 = np.array([1.0, 0.0, 0.0, 1.0]), np.zeros(2)
    Afd, Bfd = an.fd_jacobian(f, 0.0, x, u0)
    assert np.shape(Afd) == (4, 4) and np.shape(Bfd) == (4, 2)
    lin = an.linearize(f, jac, 0.0, x, u0)
    assert isinstance(lin, an.Linearization) and lin.rel_err_A < 1e-6
    og = an.od_gramian("range", np.arange(0.0, 301.0, 60.0))
    assert og.W.shape == (6, 6)
    rise, set_ = an.visibility_pass()
    assert rise < set_
    lm = an.od_linear_model([0.0, 60.0, 120.0])
    assert isinstance(lm, an.LinearModel) and lm.stms.shape == (3, 6, 6) and lm.transitions.shape == (2, 6, 6)


def test_od_batch_on_tracking_data(tmp_path: pathlib.Path) -> None:
    """satgnc.od.tracking_data / read_tracking_tdm / batch_estimate / batch_residuals (km, km/s, s, rad)."""
    from satgnc.observation import EarthFixedStationEphemeris
    from satgnc.time import Epoch

    epoch = Epoch.parse("2016-12-10T00:00:00", "UTC")
    st = EarthFixedStationEphemeris(0.0, 0.0, 0.0)
    x = np.array([7000.0, 0.0, 0.0, 0.0, 7.5, 0.0])
    t = np.arange(0.0, 70.0, 10.0)
    rng = [float(np.linalg.norm(x[:3] + x[3:] * tk - np.array(st.state(float(tk))[0]))) for tk in t]
    data = od.tracking_data(t, "two_way_range", np.zeros(7, dtype=int), rng, 1e-3, epoch=epoch)
    assert isinstance(data, od.TrackingData) and data.size == 7
    r, jac = od.batch_residuals(data, [st], x, epoch=epoch)
    assert r.shape == (7,) and jac.shape == (7, 6)
    res = od.batch_estimate(data, [st], x, epoch=epoch, max_iterations=1)
    assert isinstance(res, od.BatchResult) and res.state.shape == (6,) and res.residuals.shape == (7, 2)
    path = tmp_path / "t.tdm"
    path.write_text("CCSDS_TDM_VERS = 2.0\nCREATION_DATE = 2016-12-10T00:00:00\nORIGINATOR = X\n"
                    "META_START\nTIME_SYSTEM = UTC\nPARTICIPANT_1 = GS\nPARTICIPANT_2 = SC\n"
                    "MODE = SEQUENTIAL\nPATH = 1,2,1\n"
                    "META_STOP\nDATA_START\nRANGE = 2016-12-10T00:00:00 700.0\nDATA_STOP\n")
    assert od.read_tracking_tdm(path, ["GS"]).size == 1


def test_od_filter_and_smooth() -> None:
    """satgnc.od.filter / smooth (issue 15): the orbit EKF over two range records (km, km/s, s)."""
    from satgnc.observation import EarthFixedStationEphemeris

    st = EarthFixedStationEphemeris(0.0, 0.0, 0.0)
    x = np.array([7000.0, 0.0, 0.0, 0.0, 7.5, 0.0])
    t = np.array([10.0, 20.0])
    rng = [float(np.linalg.norm(x[:3] + x[3:] * tk - np.array(st.state(float(tk))[0]))) for tk in t]
    p0 = np.diag([1.0, 1.0, 1.0, 1e-6, 1e-6, 1e-6])
    f = od.filter(t, np.zeros(2, dtype=int), np.zeros(2, dtype=int), rng, stations=[st], x0=x, P0=p0,
                  observables=("one_way_range",), sigma=1e-3)
    assert isinstance(f, od.FilterResult) and f.state.shape == (2, 6) and f.covariance.shape == (2, 6, 6)
    s = od.smooth(t, np.zeros(2, dtype=int), np.zeros(2, dtype=int), rng, stations=[st], x0=x, P0=p0,
                  observables=("one_way_range",), sigma=1e-3)
    assert s.smoothed_state is not None and s.smoothed_state.shape == (2, 6)


# ----------------------------------------------------------------------------- completeness
CALLED = {
    "satgnc": {"propagate", "available_methods", "elements_to_state", "propagate_sensitivity",
               "load_force_model"},
    "satgnc.propagation": {"propagate", "available_methods", "elements_to_state", "propagate_ensemble"},
    "satgnc.guidance": {"cw_matrices", "cw_stm", "cw_discretize", "cw_to_hill", "hill_to_cw", "solve_l1",
                        "plan", "fly", "mpc", "satellite_params"},
    "satgnc.od": {
        "julian_date", "gmst", "ellipsoid", "geodetic_to_ecef", "station_geodetic", "station_inertial",
        "implied_rotation_rate", "predict", "make_propagator", "read_csv", "read_csv_names", "solve",
        "six_point_conditions",
        "solve_six_point", "root_search", "box_guesses", "simulate", "settings",
        "tracking_data", "read_tracking_tdm", "batch_estimate", "batch_residuals",
        "filter", "smooth",
    },
    "satgnc.analysis": {
        "orbit", "polar_model", "polar_linear_model", "cw_model", "polar_units", "cw_units",
        "nondimensionalize", "staircase", "controllability", "observability", "pbh", "kalman_rank",
        "kalman_matrix",
        "distance_to_uncontrollability", "loss_table", "format_loss_table", "controllability_gramian",
        "observability_gramian", "ltv_observability_gramian", "minimum_energy", "expm", "fd_jacobian",
        "linearize", "od_gramian", "visibility_pass", "od_linear_model",
    },
}


def test_every_public_function_is_called_here() -> None:
    for mod in (satgnc, prop, g, od, an):
        public = {n for n in mod.__all__ if inspect.isfunction(getattr(mod, n))}
        assert public == CALLED[mod.__name__], mod.__name__


def test_stub_names_every_compiled_name() -> None:
    """_satgnc.pyi is complete: every public name of the extension is declared (module level and class
    members). A binding added without regenerating the stub fails here (see the stub's header)."""
    import ast

    stub = pathlib.Path(_satgnc.__file__).with_name("_satgnc.pyi")
    tree = ast.parse(stub.read_text())
    declared: dict[str, set[str]] = {"": set()}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            declared[""].add(node.name)
            members = {n.name for n in node.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
            fields = {n.target.id for n in node.body
                      if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)}
            declared[node.name] = members | fields
        elif isinstance(node, ast.FunctionDef):
            declared[""].add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            declared[""].add(node.target.id)
    compiled = {n for n in dir(_satgnc) if not n.startswith("_")}
    assert compiled - declared[""] == set()
    assert len(compiled) >= 90
    for name in sorted(compiled):
        obj = getattr(_satgnc, name)
        if isinstance(obj, type) and not hasattr(obj, "__members__"):  # classes, not enums
            members = {m for m in vars(obj) if not m.startswith("_")}
            assert members - declared[name] == set(), name
