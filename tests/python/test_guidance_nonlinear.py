"""Nonlinear L1 rendezvous guidance: drift and Table 1 reproduction, discrete-map Jacobians, SCP
optimality against an independent local solver (scipy SLSQP), flying the plans, bad input."""

import numpy as np
import pytest
from satgnc import _satgnc as _c
from satgnc.papers import l1_admm_rendezvous as nl
from scipy.optimize import minimize


@pytest.fixture(scope="module")
def uncons():
    return nl.paper_case(False)


@pytest.fixture(scope="module")
def cons():
    return nl.paper_case(True)


def test_drift_reproduces_published_relative_state():
    x = nl.drift_state()
    cw = np.asarray(_c.cw_relative_state_published(x, nl.MU))
    expected = [-9477.311, -1999.979, -43.046, -3.477486, 1.007149, -0.090170]
    # l1_scenario.md prints 1e-3 m and 1e-6 m/s: half a unit of the last digit
    np.testing.assert_allclose(cw[:3], expected[:3], rtol=0, atol=0.5e-3)
    np.testing.assert_allclose(cw[3:], expected[3:], rtol=0, atol=0.5e-6)


def test_published_scaling_units(uncons):
    # l1_scenario.md: time unit 324.48 s, force unit 0.42318 N (printed digits)
    assert abs(uncons.scaling.time_scale - 324.48) <= 0.005
    assert abs(uncons.scaling.control_scale[0] - 0.42318) <= 0.000005


def test_discrete_map_jacobians_match_finite_differences(uncons):
    x = np.asarray(uncons.problem.x0)
    u = np.array([0.02, -0.01, 0.005])
    xn, A, B = uncons.dmap.step(3, x, u)
    for j in range(12):
        h = 1e-6 * max(abs(x[j]), 1.0)
        e = np.zeros(12)
        e[j] = h
        col = (uncons.dmap.step(3, x + e, u)[0] - uncons.dmap.step(3, x - e, u)[0]) / (2 * h)
        assert np.max(np.abs(col - A[:, j])) <= 1e-7 * max(np.max(np.abs(A[:, j])), 1e-300)
    for j in range(3):
        e = np.zeros(3)
        e[j] = 1e-6
        col = (uncons.dmap.step(3, x, u + e)[0] - uncons.dmap.step(3, x, u - e)[0]) / 2e-6
        assert np.max(np.abs(col - B[:, j])) <= 1e-7 * np.max(np.abs(B[:, j]))


def test_paper_unconstrained_60_iterations_and_kilometre_miss(uncons):
    sol = nl.solve_paper(uncons)
    info = sol.info
    assert info.status == _c.IlqrAdmmStatus.solved
    assert info.iterations == 60  # Table 1: 120 LQR passes = 2 x 60 ADMM iterations
    assert info.lqr_passes == 120
    assert info.paper_criterion <= 6e-5
    y = nl.summarize(uncons, sol.Y)
    u = nl.summarize(uncons, sol.U)
    # the sparse iterate at the paper's stop misses by ~9 km; the dense LQR iterate by metres
    assert 8000.0 < y["miss_position"] < 10000.0
    assert u["miss_position"] < 10.0
    assert u["sparsity"] == 0.0  # the figure's control is the dense iterate, nowhere zero


@pytest.mark.parametrize("constrained", [False, True])
def test_scp_reaches_optimum_in_few_outer_iterations(constrained, uncons, cons):
    case = cons if constrained else uncons
    s = nl.solve_scp(case, eps=1e-7, tol=1e-8)
    assert s.info.status == _c.ScpStatus.solved
    assert s.info.outer_iterations <= 5
    paper = nl.solve_paper(case)
    # the converged objective beats the paper's stopping point (its dense U)
    assert s.info.objective < paper.info.objective_u
    summ = nl.summarize(case, s.U)
    assert summ["miss_position"] < 10.0
    if constrained:
        assert summ["u_max"] <= nl.U_MAX * (1 + 1e-12)
        assert summ["sparsity"] > 0.8  # bang-off-bang
    else:
        assert summ["nonzero_intervals"] <= 6  # impulsive: first and last intervals
        assert summ["sparsity"] > 0.95


def _small_case(constrained):
    # 10 intervals of 600 s, RK3 with 60 s substeps (a single 600 s RK3 step is not a usable map)
    return nl.paper_case(constrained, horizon=10, substeps=10)


def _slsqp(case):
    """Independent local solver: SLSQP on u = p - m, p, m >= 0 (smooth), gradients by the chain rule
    through the map's Jacobians."""
    pr = case.problem
    Nh, w = pr.horizon, pr.stage_weight
    Qf = np.asarray(pr.Qf)
    ub = np.asarray(pr.u_max) if case.constrained else np.full(3, np.inf)

    # variables v = z / scale in [0, 1] (constrained) so that SLSQP sees a well-scaled problem
    scale = np.tile(ub if case.constrained else np.ones(3), 2 * Nh)

    def fg(v):
        z = v * scale
        U = (z[: 3 * Nh] - z[3 * Nh :]).reshape(Nh, 3).T
        x = np.asarray(pr.x0)
        As, Bs = [], []
        for k in range(Nh):
            x, A, B = case.dmap.step(k, x, U[:, k])
            As.append(A)
            Bs.append(B)
        e = x - np.asarray(pr.x_target)
        J = 0.5 * e @ Qf @ e + w * z.sum()
        lam = Qf @ e
        gU = np.zeros((3, Nh))
        for k in range(Nh - 1, -1, -1):
            gU[:, k] = Bs[k].T @ lam
            lam = As[k].T @ lam
        g = gU.T.ravel()
        return J, np.concatenate([g + w, -g + w]) * scale

    bounds = [(0, 1.0 if case.constrained else None)] * (6 * Nh)
    r = minimize(
        fg,
        np.zeros(6 * Nh),
        jac=True,
        method="SLSQP",
        bounds=bounds,
        options={"ftol": 1e-15, "maxiter": 3000},
    )
    return r.fun if r.success else float("nan")


@pytest.mark.parametrize("constrained", [False, True])
def test_scp_matches_independent_slsqp_on_small_horizon(constrained):
    case = _small_case(constrained)
    s = nl.solve_scp(case, eps=1e-9, tol=1e-10)
    assert s.info.status == _c.ScpStatus.solved
    assert s.info.outer_iterations <= 5
    j_slsqp = _slsqp(case)
    # same local optimum from the same (zero) start: objectives within 1e-3 relative
    assert abs(s.info.objective - j_slsqp) <= 1e-3 * abs(j_slsqp)


def test_ilqr_admm_converged_matches_scp_on_small_horizon():
    case = _small_case(False)
    s = nl.solve_scp(case, eps=1e-9, tol=1e-10)
    st = _c.IlqrAdmmSettings()
    st.rho = 1.0
    st.eps_abs = 1e-9
    st.eps_rel = 1e-9
    st.adaptive_rho = True
    st.max_iter = 20000
    sol = _c.IlqrAdmmSolver(case.dmap, case.problem, st)
    sol.set_initial_controls(np.zeros((3, case.problem.horizon)))
    sol.solve()
    assert abs(sol.info.objective_y - s.info.objective) <= 1e-4 * s.info.objective


def test_flying_linear_plan_misses_by_hundreds_of_metres(uncons):
    lin = nl.linear_cw_plan(uncons, eps=1e-8)
    s = nl.solve_scp(uncons, eps=1e-7, tol=1e-8)
    m_lin = nl.miss(uncons.rollout_si(lin["U"]))[0]
    m_nl = nl.miss(uncons.rollout_si(uncons.to_si(s.U)))[0]
    # issue 6 facts: the CW optimum flown on the nonlinear model misses by ~220 m, the nonlinear
    # optimum by a few metres (its terminal cost is soft)
    assert 150.0 < m_lin < 300.0
    assert m_nl < 10.0


def test_bad_input_errors(uncons):
    pr = _c.NonlinearL1Problem()
    pr.horizon = 5
    pr.x0 = np.zeros(11)
    pr.Qf = np.eye(12)
    pr.alpha = np.ones(3)
    with pytest.raises(ValueError, match="x0"):
        _c.IlqrAdmmSolver(uncons.dmap, pr)
    pr.x0 = np.asarray(uncons.problem.x0)
    pr.alpha = np.ones(2)
    with pytest.raises(ValueError, match="alpha"):
        _c.IlqrAdmmSolver(uncons.dmap, pr)
    pr.alpha = np.ones(3)
    st = _c.IlqrAdmmSettings()
    with pytest.raises(ValueError, match="rho"):  # refused at assignment (issue 11)
        st.rho = -1.0
        _c.IlqrAdmmSolver(uncons.dmap, pr, st)
    ms = _c.TwoSatelliteMapSettings()
    ms.scheme = 5
    with pytest.raises(ValueError, match="scheme"):
        _c.TwoSatelliteMap(uncons.model, ms)
    p = _c.TwoSatelliteParams()
    with pytest.raises(ValueError, match="mass_chaser"):  # refused at assignment (issue 11)
        p.mass_chaser = 0.0
        _c.TwoSatelliteModel(p)


def test_propagation_failure_status_names_interval(uncons):
    # a chaser sent through the Earth's centre: the relative state equal to r_t makes r_c = 0
    pr = _c.NonlinearL1Problem()
    pr.horizon = 4
    x0 = np.asarray(uncons.problem.x0).copy()
    x0[0:3] = (
        x0[3:6] * np.asarray(uncons.scaling.state_scale)[3:6] / np.asarray(uncons.scaling.state_scale)[0:3]
    )
    pr.x0 = x0
    pr.Qf = np.eye(12)
    pr.alpha = np.ones(3)
    sol = _c.IlqrAdmmSolver(uncons.dmap, pr)
    sol.set_initial_controls(np.zeros((3, 4)))
    assert sol.solve() == _c.IlqrAdmmStatus.propagation_failed
    assert sol.info.failed_interval == 0
    assert "failed_interval" in sol.info.message
    scp = _c.ScpSolver(uncons.dmap, pr)
    assert scp.solve() == _c.ScpStatus.propagation_failed
    assert scp.info.failed_interval == 0


def test_non_converging_solve_returns_best_iterate(uncons):
    st = _c.IlqrAdmmSettings()
    st.max_iter = 5
    sol = _c.IlqrAdmmSolver(uncons.dmap, uncons.problem, st)
    sol.set_initial_controls(np.zeros((3, nl.N)))
    assert sol.solve() == _c.IlqrAdmmStatus.max_iterations
    assert sol.info.iterations == 5
    assert np.isclose(sol.info.primal_residual, np.linalg.norm(np.asarray(sol.U) - np.asarray(sol.Y)))
    assert np.all(np.isfinite(sol.U))


def test_mpc_constrained_closed_loop_submetre_with_bounds(cons):
    m = nl.mpc(cons)  # re-plan every 3 intervals, warm-started, CVODES truth with J2 + drag
    mp, _ = nl.miss(m["X"])
    assert mp < 1.0  # issue 6 goal: closed-loop terminal miss under 1 m
    assert np.abs(m["U"]).max() <= nl.U_MAX * (1 + 1e-12)  # bounds respected at every step
    # budget 10 N / remaining iterations, capped at 120: constant cost per re-plan
    rem = nl.N - 3 * np.arange(1, len(m["iterations"]) + 1)
    assert np.array_equal(m["iterations"], np.minimum(120, -(-10 * nl.N // rem)))
    # open loop, the same nonlinear optimum misses by tens of metres on this truth (J2 unmodelled)
    s = nl.solve_scp(cons, eps=1e-7, tol=1e-8)
    assert nl.miss(nl.fly(cons, cons.to_si(s.U)))[0] > 10.0


def test_mpc_unconstrained_closed_loop_submetre():
    case = nl.paper_case(False)
    m = nl.mpc(case)  # CVODES truth with J2 + drag, iteration budget growing as the horizon shrinks
    # issue 6 goal: closed-loop terminal miss under 1 m (measured 0.05 m; 1.24 m with a fixed
    # 10-iteration budget, see docs/guidance_nonlinear.md)
    assert nl.miss(m["X"])[0] < 1.0
    assert np.all(m["iterations"] <= 120)
    fixed = nl.mpc(case, scale_iterations=False)
    assert nl.miss(fixed["X"])[0] > nl.miss(m["X"])[0]


def test_cvodes_truth_agrees_with_fine_rk4_truth(uncons):
    s = nl.solve_scp(uncons, eps=1e-7, tol=1e-8)
    U = uncons.to_si(s.U)
    Xc = nl.fly(uncons, U)  # CVODES, re-initialised at each interval, J2 + drag
    Xr = nl.fly(uncons, U, integrator="rk4", substeps=60)  # RK4 at 1 s
    # RK4 at 1 s is accurate to ~1e-4 m over the 6000 s flight; CVODES to rtol 1e-11
    assert np.abs(Xc[0:3] - Xr[0:3]).max() < 1e-3
    assert np.abs(Xc[6:9] - Xr[6:9]).max() < 1e-6


def test_dop853_map_plan_is_flown_exactly_and_rk3_is_not(uncons):
    """The propagated map is the flow: its optimum flown on the same physics lands where it planned;
    the RK3 transcription's optimum does not (the cost of the published discretization)."""
    same_physics = nl.model_params()  # planner's model: published drag sign, no J2
    d = nl.paper_case(False, discretization="dop853")
    sd = nl.solve_scp(d, eps=1e-7, tol=1e-8)
    assert sd.info.status == _c.ScpStatus.solved
    planned = nl.summarize(d, sd.U)["miss_position"]
    flown = nl.miss(nl.fly(d, d.to_si(sd.U), truth_params=same_physics))[0]
    assert abs(flown - planned) < 1e-3  # measured 2.907 m both
    s3 = nl.solve_scp(uncons, eps=1e-7, tol=1e-8)
    planned3 = nl.summarize(uncons, s3.U)["miss_position"]
    flown3 = nl.miss(nl.fly(uncons, uncons.to_si(s3.U), truth_params=same_physics))[0]
    assert abs(flown3 - planned3) > 0.3  # measured 2.91 m planned, 3.76 m flown


def test_new_options_reject_bad_input(uncons):
    with pytest.raises(ValueError, match="discretization"):
        nl.paper_case(False, discretization="euler")
    with pytest.raises(ValueError, match="integrator"):
        nl.fly(uncons, np.zeros((3, nl.N)), integrator="heun")
    with pytest.raises(ValueError, match="integrator"):
        nl.mpc(uncons, integrator="heun")
    ps = _c.PropagatedMapSettings()
    ps.rtol = 0.0
    with pytest.raises(ValueError, match="rtol"):
        _c.PropagatedTwoSatelliteMap(uncons.model, ps)
    truth = _c.TwoSatelliteTruth(uncons.model)
    U = np.zeros((3, 5))
    U[0, 3] = np.nan
    r = truth.fly(uncons.x0_si, U, 60.0)
    assert not r["ok"] and r["failed_interval"] == 3 and "interval 3" in r["message"]
    with pytest.raises(ValueError, match="U"):
        truth.fly(uncons.x0_si, np.zeros((2, 5)), 60.0)
    with pytest.raises(RuntimeError, match="TwoSatelliteTruth"):
        truth.step(np.full(12, np.nan), np.zeros(3), 60.0)


def test_cli_nonlinear_writes_summary(tmp_path):
    import json

    from satgnc.guidance import cli

    args = type(
        "A", (), {"model": "nonlinear", "closed_loop": False, "out": str(tmp_path), "scenario": None}
    )()
    assert cli._run(args) == 0
    summary = json.loads((tmp_path / "nonlinear_summary.json").read_text())
    assert summary["nonlinear_unconstrained"]["paper_comparison"]["iterations"] == 60
    assert (tmp_path / "nonlinear_unconstrained.png").exists()


def test_ilqr_admm_on_linear_dynamics_equals_linear_admm_solver():
    """One Gauss-Newton iLQR step on linear dynamics is the exact LQR step: iterate by iterate the
    nonlinear solver equals satgnc's linear ADMM solver (same rho, no relaxation, no adaptation)."""
    from satgnc import guidance as g

    dt, nh, rho, iters = 1.0, 20, 0.7, 25
    A = np.eye(6)
    A[:3, 3:] = dt * np.eye(3)
    B = np.vstack([0.5 * dt**2 * np.eye(3), dt * np.eye(3)])
    x0 = np.array([10.0, -5.0, 2.0, 0.1, 0.3, -0.2])
    Qf = 100.0 * np.eye(6)
    st = g.AdmmSettings()
    st.rho = rho
    st.relaxation = 1.0
    st.adaptive_rho = False
    st.stopping = _c.StoppingRule.paper
    st.paper_eps = 1e-300
    st.max_iterations = iters
    st.track_best = False
    ref = g.solve_l1(A, B, x0, horizon=nh, Qf=Qf, l1_weights=np.ones(3), settings=st)
    pr = _c.NonlinearL1Problem()
    pr.horizon = nh
    pr.x0 = x0
    pr.x_target = np.zeros(6)
    pr.Qf = Qf
    pr.alpha = np.ones(3)
    s2 = _c.IlqrAdmmSettings()
    s2.rho = rho
    s2.stop = _c.StopRule.paper
    s2.eps_paper = 0.0
    s2.max_iter = iters
    s2.return_best = False
    sol = _c.IlqrAdmmSolver(_c.LinearDiscreteModel([A], [B], []), pr, s2)
    sol.set_initial_controls(np.zeros((3, nh)))
    sol.solve()
    assert ref.iterations == iters
    scale = 1.0 + np.abs(ref.U).max()
    np.testing.assert_allclose(np.asarray(sol.U).T, ref.U, rtol=0, atol=1e-8 * scale)
    np.testing.assert_allclose(np.asarray(sol.Y).T, ref.Y, rtol=0, atol=1e-8 * scale)


# --- issue 11: honest SCP statuses and the trust region, on random rendezvous problems -------------


class _Rdv:
    """A random two-satellite rendezvous in the paper's scaled units (what solve_scp needs)."""

    def __init__(self, dmap, problem, constrained):
        self.dmap, self.problem, self.constrained = dmap, problem, constrained


def _random_rendezvous(rng, offset=None, bound_n=None, horizon=None):
    """Altitude 300-2000 km, N 8-30 over a quarter to a full orbit, offsets 10 m-5 km (position) and
    1e-3 of that per second, J2 on or off, no drag, half of them with a per-axis bound 0.5-5 mN."""
    p = nl.model_params(published=False, j2=bool(rng.integers(2)), drag=False)
    model = _c.TwoSatelliteModel(p)
    r = 6378.1363e3 + rng.uniform(300e3, 2000e3)
    period = 2 * np.pi * np.sqrt(r**3 / nl.MU)
    n = int(rng.integers(8, 31)) if horizon is None else horizon
    dt = rng.uniform(0.25, 1.0) * period / n
    off = 10 ** rng.uniform(1.0, 3.7) if offset is None else offset
    x0 = np.zeros(12)
    x0[0:3] = off * rng.uniform(-1, 1, 3)
    x0[6:9] = 1e-3 * off * rng.uniform(-1, 1, 3)
    x0[3] = r
    x0[10] = np.sqrt(nl.MU / r)
    sc = _c.published_scaling(x0, nl.MU, nl.MASS)
    dmap = nl.make_map(model, dt, sc, "rk4")
    pr = _c.NonlinearL1Problem()
    pr.horizon = n
    pr.x0 = x0 / np.asarray(sc.state_scale)
    pr.x_target = np.zeros(12)
    pr.Qf = 1000.0 * np.diag(nl.QF_MASK)
    pr.alpha = np.ones(3)
    pr.stage_weight = dt / sc.time_scale
    constrained = bound_n is not None or rng.uniform() < 0.5
    if constrained:
        b = (rng.uniform(0.5, 5.0) * 1e-3 if bound_n is None else bound_n) / np.asarray(sc.control_scale)
        pr.cost = _c.ControlCost.l1_box
        pr.u_min = -b
        pr.u_max = b
    return _Rdv(dmap, pr, constrained)


def _true_cost(case, U):
    """Independent evaluation: roll U out with the map's step and add the terminal and L1 costs."""
    x = np.asarray(case.problem.x0, dtype=float)
    for k in range(U.shape[1]):
        x = np.asarray(case.dmap.step(k, x, U[:, k])[0])
    e = x - np.asarray(case.problem.x_target)
    return 0.5 * e @ np.asarray(case.problem.Qf) @ e + case.problem.stage_weight * (
        np.asarray(case.problem.alpha) @ np.abs(U).sum(axis=1)
    )


def _check_honest(case, s):
    """Whatever the status: finite true cost of the returned plan, non-increasing merit history,
    bounds held."""
    info = s.info
    U = np.asarray(s.U)
    h = np.asarray(info.merit_history)
    assert h.size >= 1 and np.all(np.isfinite(h))
    assert np.all(np.diff(h) <= 0.0), h
    assert info.objective == h[-1]
    assert np.isfinite(info.objective) and info.objective > 0.0
    assert abs(_true_cost(case, U) - info.objective) <= 1e-9 * max(1.0, info.objective)
    assert info.bound_violation == 0.0
    if case.constrained:
        assert np.all(U <= np.asarray(case.problem.u_max)[:, None])
        assert np.all(U >= np.asarray(case.problem.u_min)[:, None])
    assert np.isfinite(info.terminal_miss)


def _reference(case, U, inner):
    """A long, tight run from the returned plan: the local optimum it sits at."""
    return nl.solve_scp(case, U0=U, tol=1e-12, eps=1e-10, max_outer=100, inner=inner)


SUITE_SEED = 1102


def test_scp_random_rendezvous_suite_never_falsely_solved():
    """24 random rendezvous with the defaults (linear ADMM inner, trust region), both
    globalizations; 4 small ones with the iLQR-ADMM inner, whose subproblems often stop at max_iter
    (they must then not be reported solved)."""
    rng = np.random.default_rng(SUITE_SEED)
    counts, false_solved = {}, 0
    for t in range(28):
        ilqr = t >= 24
        case = _random_rendezvous(rng, horizon=int(rng.integers(8, 13)) if ilqr else None)
        kw = {"eps": 1e-9}
        if ilqr:
            kw = {"inner": "ilqr_admm", "eps": 1e-6, "max_inner": 2000, "max_outer": 10}
        glob = ("trust_region", "line_search")[t % 2]
        s = nl.solve_scp(case, tol=1e-9, globalization=glob, **kw)
        _check_honest(case, s)
        name = ("ilqr: " if ilqr else "") + nl.SCP_STATUS_NAMES[int(s.info.status)]
        counts[name] = counts.get(name, 0) + 1
        if s.info.status == _c.ScpStatus.solved:
            assert s.info.inner_solved
            ref = _reference(case, np.asarray(s.U), kw.get("inner", "linear_admm"))
            if s.info.objective - ref.info.objective > 1e-6 * max(1.0, ref.info.objective):
                false_solved += 1
    print("random rendezvous suite:", counts)
    assert false_solved == 0
    assert counts.get("solved", 0) == 24, counts  # measured: 24 of 24 with the defaults


@pytest.mark.parametrize("kind", ["huge_offset", "tiny_bounds", "one_outer", "inner_starved"])
def test_scp_hard_cases_are_honest(kind):
    rng = np.random.default_rng(7)
    if kind == "huge_offset":  # 100 km: far outside the linear regime
        case = _random_rendezvous(rng, offset=1e5, horizon=20)
        s = nl.solve_scp(case, tol=1e-9, eps=1e-9, max_outer=60)
    elif kind == "tiny_bounds":  # 1 uN per axis: the target cannot be reached, the miss is large
        case = _random_rendezvous(rng, offset=3e3, bound_n=1e-6, horizon=15)
        s = nl.solve_scp(case, tol=1e-9, eps=1e-9)
        assert s.info.terminal_miss > 1.0  # scaled units: metres / max(|d0|, 1)
    elif kind == "one_outer":
        case = _random_rendezvous(rng, offset=2e3, horizon=20)
        s = nl.solve_scp(case, tol=1e-9, eps=1e-9, max_outer=1)
        assert s.info.status == _c.ScpStatus.max_outer
    else:  # every subproblem stops at max_iterations
        case = _random_rendezvous(rng, offset=2e3, horizon=20)
        s = nl.solve_scp(case, tol=1e-9, eps=1e-9, max_inner=3, inner="ilqr_admm")
        assert s.info.status not in nl.SCP_SUCCESS
        assert not s.info.inner_solved
        assert s.info.inner_ilqr_status == _c.IlqrAdmmStatus.max_iterations
    _check_honest(case, s)
    if s.info.status == _c.ScpStatus.solved:
        ref = _reference(case, np.asarray(s.U), "linear_admm")
        assert s.info.objective - ref.info.objective <= 1e-6 * max(1.0, ref.info.objective)


def _cvxpy_subproblem(case, U):
    """The convex subproblem at U (exact map Jacobians along the rollout) by cvxpy + Clarabel."""
    import cvxpy as cp

    pr = case.problem
    n = pr.horizon
    x = np.asarray(pr.x0, dtype=float)
    As, Bs, cs = [], [], []
    for k in range(n):
        xn, A, B = case.dmap.step(k, x, U[:, k])
        As.append(np.asarray(A))
        Bs.append(np.asarray(B))
        cs.append(np.asarray(xn) - np.asarray(A) @ x - np.asarray(B) @ U[:, k])
        x = np.asarray(xn)
    Xv = cp.Variable((12, n + 1))
    Uv = cp.Variable((3, n))
    cons = [Xv[:, 0] == np.asarray(pr.x0)]
    cons += [Xv[:, k + 1] == As[k] @ Xv[:, k] + Bs[k] @ Uv[:, k] + cs[k] for k in range(n)]
    if case.constrained:
        cons += [Uv <= np.asarray(pr.u_max)[:, None], Uv >= np.asarray(pr.u_min)[:, None]]
    idx = np.flatnonzero(np.diag(np.asarray(pr.Qf)))
    q = np.diag(np.asarray(pr.Qf))[idx]
    e = Xv[idx, n] - np.asarray(pr.x_target)[idx]
    obj = 0.5 * cp.sum(cp.multiply(q, cp.square(e))) + pr.stage_weight * cp.sum(
        cp.multiply(np.asarray(pr.alpha)[:, None], cp.abs(Uv))
    )
    prob = cp.Problem(cp.Minimize(obj), cons)
    prob.solve(solver=cp.CLARABEL, tol_gap_abs=1e-12, tol_gap_rel=1e-12, tol_feas=1e-12)
    return prob.value


def test_scp_converged_plans_match_clarabel_on_the_final_linearization():
    import cvxpy  # noqa: F401  (requirements-dev: the independent Clarabel check never skips)
    rng = np.random.default_rng(SUITE_SEED + 1)
    checked = 0
    for t in range(6):
        case = _random_rendezvous(rng, horizon=int(rng.integers(8, 16)))
        s = nl.solve_scp(case, tol=1e-10, eps=1e-10, globalization=("trust_region", "line_search")[t % 2])
        if s.info.status != _c.ScpStatus.solved:
            continue
        ref = _cvxpy_subproblem(case, np.asarray(s.U))
        # at an SCP solution the subproblem's optimum is the plan's own cost (no predicted decrease)
        assert abs(ref - s.info.objective) <= 1e-6 * abs(s.info.objective), (ref, s.info.objective)
        checked += 1
    assert checked >= 4


def test_scp_and_ilqr_statuses_are_exposed_and_validated(uncons):
    assert nl.SCP_STATUS_NAMES[int(_c.ScpStatus.solved)] == "solved"
    for name in ("solved_inaccurate", "inner_infeasible", "time_limit", "max_outer", "line_search_failed"):
        assert name in nl.SCP_STATUS_NAMES.values()
        assert _c.scp_status_message(getattr(_c.ScpStatus, name))
    for name in ("solved_inaccurate", "time_limit", "ilqr_failed"):
        assert name in nl.ILQR_ADMM_STATUS_NAMES.values()
    with pytest.raises(ValueError, match="globalization"):
        nl.solve_scp(uncons, globalization="dogleg")
    with pytest.raises(TypeError, match="tol"):
        nl.solve_scp(uncons, tol=1j)
    with pytest.raises(ValueError, match="time_limit"):
        nl.solve_scp(uncons, time_limit=-1.0)
    st = _c.ScpSettings()
    with pytest.raises(ValueError, match="tr_shrink"):  # refused at assignment, old value kept
        st.tr_shrink = 2.0
    assert 0.0 < st.tr_shrink < 1.0  # the C++ setup check itself is in tests/cpp/test_scp.cpp
    s = nl.solve_scp(uncons, time_limit=1e-12)
    assert s.info.status == _c.ScpStatus.time_limit
    assert s.info.objective > 0.0 and len(s.info.merit_history) == 1


def test_scp_line_search_option_reaches_the_trust_region_optimum(uncons):
    tr = nl.solve_scp(uncons, eps=1e-7, tol=1e-8)
    ls = nl.solve_scp(uncons, eps=1e-7, tol=1e-8, globalization="line_search")
    assert tr.info.status in nl.SCP_SUCCESS and ls.info.status in nl.SCP_SUCCESS
    assert abs(tr.info.objective - ls.info.objective) <= 1e-6 * tr.info.objective
