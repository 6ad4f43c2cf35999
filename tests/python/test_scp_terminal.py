"""SCP with a hard terminal state (NonlinearL1Problem.terminal_equality) and its time limit.

A seeded suite of random two-satellite rendezvous with x_N = x_f on the chaser's relative state is
checked against an independent reference: cvxpy + Clarabel on the final linearization (exact map
Jacobians along the returned plan, themselves checked by central finite differences), and an
independent rollout of the plan for the terminal miss. Unreachable targets (a box of 1 uN per axis)
must end ``inner_infeasible`` with a Farkas margin > 0 that Clarabel confirms."""

import time

import numpy as np
import pytest
from satgnc import _satgnc as _c
from satgnc.papers import l1_admm_rendezvous as nl
from test_guidance_nonlinear import _random_rendezvous

ENDO = np.array([0, 1, 2, 6, 7, 8])  # the chaser's relative position and velocity (constrained)
SEED = 1103


def _true_cost(case, U):
    x = np.asarray(case.problem.x0, dtype=float)
    for k in range(U.shape[1]):
        x = np.asarray(case.dmap.step(k, x, U[:, k])[0])
    e = x - np.asarray(case.problem.x_target)
    J = 0.5 * e @ np.asarray(case.problem.Qf) @ e + case.problem.stage_weight * (
        np.asarray(case.problem.alpha) @ np.abs(U).sum(axis=1))
    return J, x


def _linearize(case, U):
    pr = case.problem
    x = np.asarray(pr.x0, dtype=float)
    As, Bs, cs = [], [], []
    for k in range(pr.horizon):
        xn, A, B = case.dmap.step(k, x, U[:, k])
        A, B, xn = np.asarray(A), np.asarray(B), np.asarray(xn)
        As.append(A)
        Bs.append(B)
        cs.append(xn - A @ x - B @ U[:, k])
        x = xn
    return As, Bs, cs


def _fd_check(case, U, As, Bs, k):
    """Central differences of the map at interval k against the Jacobians of the linearization."""
    pr = case.problem
    x = np.asarray(pr.x0, dtype=float)
    for j in range(k):
        x = np.asarray(case.dmap.step(j, x, U[:, j])[0])
    u = U[:, k]
    f = lambda xx, uu: np.asarray(case.dmap.step(k, xx, uu)[0])  # noqa: E731
    # h = 1e-4: the scaled map subtracts the two orbits (l_target / l_ego ~ 1e4), so rounding
    # dominates central differences below ~1e-5 (measured: 3e-8 at 1e-5, 3e-6 at 1e-7)
    hs = 1e-4 * np.maximum(1.0, np.abs(x))
    Afd = np.column_stack([(f(x + h * e, u) - f(x - h * e, u)) / (2 * h) for h, e in zip(hs, np.eye(12))])
    Bfd = np.column_stack([(f(x, u + 1e-4 * e) - f(x, u - 1e-4 * e)) / 2e-4 for e in np.eye(3)])
    assert np.abs(Afd - As[k]).max() <= 1e-6 * max(1.0, np.abs(As[k]).max())
    assert np.abs(Bfd - Bs[k]).max() <= 1e-6 * max(1.0, np.abs(Bs[k]).max())


def _clarabel_hard(case, U):
    """min cost s.t. the linearization at U, the box, and x_N = x_f on the constrained states."""
    import cvxpy as cp

    pr = case.problem
    n = pr.horizon
    As, Bs, cs = _linearize(case, U)
    Xv = cp.Variable((12, n + 1))
    Uv = cp.Variable((3, n))
    cons = [Xv[:, 0] == np.asarray(pr.x0)]
    cons += [Xv[:, k + 1] == As[k] @ Xv[:, k] + Bs[k] @ Uv[:, k] + cs[k] for k in range(n)]
    cons += [Xv[ENDO, n] == np.asarray(pr.x_target)[ENDO]]
    if case.constrained:
        cons += [Uv <= np.asarray(pr.u_max)[:, None], Uv >= np.asarray(pr.u_min)[:, None]]
    # the terminal cost is constant on the feasible set (zero here: Qf weighs the constrained states)
    obj = pr.stage_weight * cp.sum(cp.multiply(np.asarray(pr.alpha)[:, None], cp.abs(Uv)))
    prob = cp.Problem(cp.Minimize(obj), cons)
    prob.solve(solver=cp.CLARABEL, tol_gap_abs=1e-12, tol_gap_rel=1e-12, tol_feas=1e-12)
    return prob.status, prob.value, (As, Bs)


def test_hard_terminal_random_suite_against_clarabel():
    import cvxpy  # noqa: F401  (requirements-dev: the independent Clarabel check never skips)
    rng = np.random.default_rng(SEED)
    counts = {}
    feasible = solved = reached = infeasible = infeasible_reported = false_solved = 0
    for t in range(40):
        case = _random_rendezvous(rng, bound_n=1e-6 if t % 4 == 3 else None)
        case.problem.terminal_equality = True
        s = nl.solve_scp(case, tol=1e-9, eps=1e-9, globalization=("trust_region", "line_search")[t % 2])
        info = s.info
        U = np.asarray(s.U)
        name = nl.SCP_STATUS_NAMES[int(info.status)]
        counts[name] = counts.get(name, 0) + 1
        # whatever the status: the true cost and the constraint miss of the returned plan
        J, xN = _true_cost(case, U)
        assert np.isfinite(info.objective) and abs(J - info.objective) <= 1e-9 * max(1.0, J)
        miss = np.linalg.norm(xN[ENDO] - np.asarray(case.problem.x_target)[ENDO])
        assert abs(miss - info.terminal_constraint_miss) <= 1e-12 * max(1.0, info.terminal_reference)
        assert np.all(np.isfinite(info.merit_history)) and info.bound_violation == 0.0
        if info.penalty_updates == 0 and info.restoration_steps == 0:
            assert np.all(np.diff(info.merit_history) <= 0.0)
        status, ref, (As, Bs) = _clarabel_hard(case, U)
        if status in ("infeasible", "infeasible_inaccurate"):
            infeasible += 1
            assert info.status == _c.ScpStatus.inner_infeasible, (t, name)
            infeasible_reported += 1
            assert info.infeasibility_margin > 0.0
            assert abs(np.linalg.norm(info.infeasibility_certificate) - 1.0) <= 1e-9
            continue
        assert status == "optimal", status
        assert info.status != _c.ScpStatus.inner_infeasible, t
        feasible += 1
        reached += miss <= 1e-6 * info.terminal_reference
        if info.status != _c.ScpStatus.solved:
            continue
        solved += 1
        assert miss <= 1e-6 * info.terminal_reference
        _fd_check(case, U, As, Bs, int(rng.integers(case.problem.horizon)))
        # at an SCP solution the linearized problem's optimum is the plan's own cost
        if abs(ref - info.objective) > 1e-6 * abs(ref):
            false_solved += 1
    print(f"hard-terminal rendezvous suite: {counts}; feasible {feasible} (target reached {reached}, "
          f"solved {solved}), unreachable {infeasible} (inner_infeasible {infeasible_reported})")
    assert false_solved == 0
    assert infeasible >= 10 and infeasible_reported == infeasible
    assert solved >= feasible - 1 and reached >= feasible - 1, counts  # measured: see docs


def test_paper_case_exact_arrival_costs_at_least_the_soft_optimum():
    hard = nl.paper_case(False, terminal_equality=True)
    s = nl.solve_scp(hard, tol=1e-9, eps=1e-9)
    assert s.info.status == _c.ScpStatus.solved, s.info.message
    assert s.info.terminal_constraint_miss <= 1e-6 * s.info.terminal_reference
    soft = nl.solve_scp(nl.paper_case(False), tol=1e-9, eps=1e-9)
    assert soft.info.status in nl.SCP_SUCCESS
    # the soft optimum min g + 1/2 e'Qf e is at most g(U_hard) + 0
    assert soft.info.objective <= s.info.objective * (1 + 1e-9)
    assert s.info.penalty > 0.0
    with pytest.raises(ValueError, match="terminal_equality: not supported by IlqrAdmmSolver.*ScpSolver"):
        nl.solve_paper(hard)
    with pytest.raises(TypeError, match="terminal_equality"):
        hard.problem.terminal_equality = "yes"


def _untimed_settings(inner):
    st = _c.ScpSettings()
    st.inner_solver = getattr(_c.ScpInner, inner)
    ia = st.inner
    ia.eps_abs = ia.eps_rel = ia.eps_gap = 1e-300  # never met: the inner would run for minutes
    ia.polish = False
    ia.max_iterations = 10**8
    st.inner = ia
    ii = st.inner_ilqr
    ii.eps_abs = ii.eps_rel = 1e-300
    ii.max_iter = 10**8
    st.inner_ilqr = ii
    return st


@pytest.mark.parametrize("inner,hard", [("linear_admm", False), ("linear_admm", True), ("ilqr_admm", False)])
def test_time_limit_stops_the_inner_solver(inner, hard):
    rng = np.random.default_rng(SEED + 1)
    case = _random_rendezvous(rng, horizon=60)
    case.problem.terminal_equality = hard
    st = _untimed_settings(inner)
    st.time_limit = 0.05
    s = _c.ScpSolver(case.dmap, case.problem, st)
    t0 = time.perf_counter()
    s.solve()
    wall = time.perf_counter() - t0
    info = s.info
    assert info.status == _c.ScpStatus.time_limit
    if inner == "linear_admm":
        assert info.inner_status == _c.AdmmStatus.time_limit
    else:
        assert info.inner_ilqr_status == _c.IlqrAdmmStatus.time_limit
    assert wall < 5.0  # minutes without the inner limit; a bound, not a speed assertion
    J, _ = _true_cost(case, np.asarray(s.U))
    assert np.isfinite(info.objective) and abs(J - info.objective) <= 1e-9 * max(1.0, J)
    assert len(info.merit_history) >= 1 and np.all(np.isfinite(info.merit_history))


def test_ilqr_admm_time_limit_is_checked_between_ilqr_iterations(uncons_short):
    st = _c.IlqrAdmmSettings()
    st.ilqr_iters = 50
    st.ilqr_tol = 0.0
    st.time_limit = 1e-9  # over after the first iLQR iteration
    sol = _c.IlqrAdmmSolver(uncons_short.dmap, uncons_short.problem, st)
    sol.set_initial_controls(np.zeros((3, uncons_short.problem.horizon)))
    assert sol.solve() == _c.IlqrAdmmStatus.time_limit
    assert sol.info.iterations == 1 and sol.info.ilqr_iterations <= 1
    # control: without the limit the same first ADMM iteration runs several iLQR iterations
    st.time_limit = 0.0
    st.max_iter = 1
    ctl = _c.IlqrAdmmSolver(uncons_short.dmap, uncons_short.problem, st)
    ctl.set_initial_controls(np.zeros((3, uncons_short.problem.horizon)))
    ctl.solve()
    assert ctl.info.ilqr_iterations >= 3
    assert np.isfinite(sol.info.objective_u) and np.isfinite(sol.info.objective_y)
    with pytest.raises(ValueError, match="time_limit"):
        sol.set_time_limit(-1.0)


@pytest.fixture(scope="module")
def uncons_short():
    return nl.paper_case(False, horizon=20)


def test_terminal_settings_and_info_fields_are_validated_and_exposed():
    st = _c.ScpSettings()
    with pytest.raises(ValueError, match="terminal_tol: must be finite and > 0"):
        st.terminal_tol = 0.0
    with pytest.raises(ValueError, match="terminal_tol_inaccurate: must be finite and >= terminal_tol"):
        st.terminal_tol_inaccurate = 1e-9
    with pytest.raises(TypeError, match="terminal_tol"):
        st.terminal_tol = 1e-6 + 0j
    assert st.terminal_tol == 1e-6 and st.terminal_tol_inaccurate == 1e-4  # old values kept
    assert st.inner.terminal_tolerance == 1e-10
    pr = _c.NonlinearL1Problem()
    assert pr.terminal_equality is False  # default: today's soft terminal cost
    case = nl.paper_case(False, horizon=10)
    info = _c.ScpSolver(case.dmap, case.problem).info  # before solve()
    for name in ("terminal_constraint_miss", "terminal_reference", "penalty", "penalty_updates",
                 "infeasibility_margin"):
        assert getattr(info, name) == 0
    assert np.asarray(info.infeasibility_certificate).shape == (12,)
