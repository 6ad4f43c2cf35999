"""satgnc.guidance.L1Solver on seeded random Clohessy-Wiltshire problems nobody tuned it to.

Each problem is drawn by the test (altitude 300-36000 km, dt 10-300 s, N 3-120, position scale
0.1 m-10 km, terminal weight 1e-3-1e3, per-axis fuel weights 0.1-10, a third box-bounded, a quarter
with a hard terminal state; QP variants with R > 0, a stage Q on the Riccati path, several unit
systems) and solved independently by cvxpy + Clarabel. Default settings. Asserted: no false
"solved" (solved => objective within 1e-4 of Clarabel and the constraints hold), the dual bound below
every feasible plan's objective, the solved share (issue 11 asks 98 %; see MIN_SOLVED), infeasible
problems reported "primal_infeasible" with a checked Farkas certificate.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
from satgnc import guidance as g

MU = 3.986004418e14  # m^3/s^2
RE = 6378.137e3  # m


@dataclasses.dataclass
class Case:
    kind: str
    kw: dict


def _log_uniform(rng, lo, hi):
    return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))


def draw(rng: np.random.Generator, kind: str = "l1") -> Case:
    """One random problem. kind: l1 (the issue's mix), qp (R > 0, no L1), stage_q (Q > 0 with L1),
    units_km (x km, u kN), units_mm (x m, u mm/s^2)."""
    alt = rng.uniform(300e3, 36000e3)
    n = np.sqrt(MU / (RE + alt) ** 3)
    dt = rng.uniform(10.0, 300.0)
    N = int(rng.integers(3, 121))
    mass = 1.0
    ufac = 1.0  # control unit: u_user = ufac * u_SI(acceleration)
    xfac = 1.0  # length unit: x_user = xfac * x_SI
    if kind == "units_mm":
        ufac = 1e3
    elif kind == "units_km":
        mass = _log_uniform(rng, 100.0, 5000.0)
        xfac = 1e-3
    A, B = g.cw_discretize(n, mass, dt, "zoh")
    if kind == "units_mm":
        B = B / ufac
    pos = _log_uniform(rng, 0.1, 1e4)
    T = N * dt
    vel = pos * _log_uniform(rng, 0.1, 3.0) / T
    x0 = np.concatenate([rng.normal(size=3) * pos, rng.normal(size=3) * vel]) * xfac
    qf = _log_uniform(rng, 1e-3, 1e3)
    w = np.array([_log_uniform(rng, 0.1, 10.0) for _ in range(3)])
    kw = dict(A=A, B=B, x0=x0, horizon=N, Qf=qf * np.eye(6), l1_weights=w)
    if kind == "units_km":
        kw["Qf"] = kw["Qf"] * 1e6  # same physics per km^2
    if rng.uniform() < 1.0 / 3.0:
        # bound of the order of the acceleration that reaches the target in the horizon
        need = 4.0 * np.linalg.norm(x0[:3]) / T**2 * mass * (ufac if kind == "units_mm" else 1.0)
        need = max(need, 1e-12)
        umax = need * _log_uniform(rng, 0.3, 30.0)
        kw["u_lower"] = -umax * np.ones(3)
        kw["u_upper"] = umax * np.ones(3)
    if rng.uniform() < 0.25 and N >= 3:
        kw["terminal_equality"] = True
    if kind == "qp":
        kw["R"] = _log_uniform(rng, 1e-3, 1e3) * np.diag(rng.uniform(0.5, 2.0, 3))
        kw["l1_weights"] = np.zeros(3)
    elif kind == "stage_q":
        kw["Q"] = _log_uniform(rng, 1e-4, 1.0) * qf * np.eye(6)
    return Case(kind, kw)


def clarabel(kw):
    """Exact optimum by cvxpy + Clarabel on the condensed problem (vectorized, time-invariant).

    Clarabel's tolerances are absolute in the units it is given, and raw units here span 1e-8..1e8:
    it is run on the raw and on a normalized formulation, and the plan with the lower true objective
    (satgnc's objective_of, an independent evaluation of a feasible plan) is the reference."""
    best, statuses = None, []
    for normalized in (False, True):
        out, st = _clarabel(kw, normalized)
        statuses.append(st)
        if out is not None:
            true = g.L1Solver(**kw).objective_of(out[1])
            if best is None or true < best[0]:
                best = (true, out[1], out[2])
    if best is not None:
        return best, "optimal"
    return None, "infeasible" if "infeasible" in statuses else statuses[0]


def _clarabel(kw, normalized):
    import cvxpy as cp

    A, B, x0, N = kw["A"], kw["B"], kw["x0"], kw["horizon"]
    nx, nu = B.shape
    # x_k = A^k x0 + sum_j A^(k-1-j) B u_j
    Apow = [np.eye(nx)]
    for _ in range(N):
        Apow.append(A @ Apow[-1])
    G = np.zeros((N + 1, nx, N * nu))
    for k in range(1, N + 1):
        for j in range(k):
            G[k, :, j * nu:(j + 1) * nu] = Apow[k - 1 - j] @ B
    free = np.array([Apow[k] @ x0 for k in range(N + 1)])
    # solve in normalized variables (u = su * v, cost / J0): raw units span 1e-8..1e8 and Clarabel's
    # tolerances are absolute there
    term = bool(kw.get("terminal_equality"))
    W = np.eye(nx) if term else kw["Qf"]
    GN = G[N].reshape(nx, N, nu)
    h = np.einsum("ikj,il,lkj->j", GN, W, GN) / N
    if kw.get("R") is not None:
        h = h + np.diag(kw["R"])
    # v = O(1) at the optimum: the controls that cancel the free terminal state, spread over N steps
    mag = np.sqrt(max(free[N] @ W @ free[N], 1e-300))
    su = np.tile(mag / np.sqrt(N * np.maximum(h, 1e-300)), N) if normalized else np.ones(N * nu)
    J0 = 0.0 if term else 0.5 * free[N] @ kw["Qf"] @ free[N]
    if kw.get("Q") is not None:
        J0 += 0.5 * kw["Q"][0, 0] * np.sum(free[1:N] ** 2)
    w0 = np.tile(kw["l1_weights"], N)
    J0 = J0 if J0 > 0 else max(float(np.sum(w0 * su)), 1e-300)
    cs = 1.0 / J0 if normalized else 1.0
    v = cp.Variable(N * nu)  # u = su * v
    xN = free[N] + (G[N] * su) @ v
    obj = 0
    cons = []
    if term:
        scale_x = 1.0 / max(np.linalg.norm(free[N]), 1e-300) if normalized else 1.0
        cons.append(scale_x * xN == 0)
    else:
        obj += 0.5 * cs * kw["Qf"][0, 0] * cp.sum_squares(xN)
    if kw.get("Q") is not None:
        q = kw["Q"][0, 0]
        Gs = G[1:N].reshape(-1, N * nu) * su
        obj += 0.5 * cs * q * cp.sum_squares(free[1:N].reshape(-1) + Gs @ v)
    if kw.get("R") is not None:
        rd = np.tile(np.diag(kw["R"]), N)
        obj += 0.5 * cs * cp.sum_squares(cp.multiply(np.sqrt(rd) * su, v))
    w = np.tile(kw["l1_weights"], N)
    if np.any(w > 0):
        obj += (cs * w * su) @ cp.abs(v)
    if "u_lower" in kw:
        cons += [v >= np.tile(kw["u_lower"], N) / su, v <= np.tile(kw["u_upper"], N) / su]
    prob = cp.Problem(cp.Minimize(obj), cons)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # "solution may be inaccurate": the status says so
            prob.solve(solver=cp.CLARABEL, tol_gap_abs=1e-10, tol_gap_rel=1e-10, tol_feas=1e-10, max_iter=400)
    except cp.error.SolverError:
        return None, "error"
    if prob.status in ("infeasible", "infeasible_inaccurate"):
        return None, "infeasible"
    if prob.status != "optimal":
        return None, prob.status
    t = prob.solver_stats.solve_time if prob.solver_stats is not None else float("nan")
    return (float(prob.value) / cs, (su * v.value).reshape(N, nu), t), "optimal"


def suite(seed: int = 11, counts=None):
    """Yield (case, solver result, reference) over the seeded suite."""
    counts = counts or {"l1": 300, "qp": 30, "stage_q": 30, "units_km": 20, "units_mm": 20}
    rng = np.random.default_rng(seed)
    for kind, m in counts.items():
        for _ in range(m):
            case = draw(rng, kind)
            yield case


def check(case, res, ref, status_ref):
    """Classify one outcome: 'ok', 'false_solved', 'unsolved', 'infeasible_ok', 'infeasible_missed',
    'ref_failed'. Returns (label, relative objective gap)."""
    kw = case.kw
    if status_ref == "infeasible":
        if res.status != "primal_infeasible":
            return "infeasible_missed", np.nan
        y = res.infeasibility_certificate
        # Farkas: y'(xf - x_N(0)) > max over the box of y' dx_N/dU U
        A, B, x0, N = kw["A"], kw["B"], kw["x0"], kw["horizon"]
        xN0 = np.linalg.matrix_power(A, N) @ x0
        lam = y.copy()
        sig = 0.0
        for _ in range(N):  # k = N-1 .. 0: m_k = B' Phi(N, k+1)' y
            m = B.T @ lam
            sig += np.sum(np.maximum(m * kw["u_lower"], m * kw["u_upper"]))
            lam = A.T @ lam
        assert -y @ xN0 > sig
        return "infeasible_ok", np.nan
    if status_ref != "optimal":
        return "ref_failed", np.nan
    _, Uref, _ = ref
    solver = g.L1Solver(**kw)
    # the true objective of Clarabel's plan (a feasible point up to its 1e-10 tolerances): on badly
    # scaled problems its reported optimum can be above ours, and then ours is not a false "solved"
    obj = solver.objective_of(Uref)
    J0 = abs(solver.objective_of(np.zeros((kw["horizon"], 3))))
    rel = (res.objective - obj) / max(abs(obj), 1e-12 * J0, 1e-300)
    # weak duality: the dual bound never exceeds the objective of any feasible plan
    assert res.dual_objective <= obj + 1e-7 * max(abs(obj), 1e-12 * J0), (res.dual_objective, obj)
    if res.status == "primal_infeasible":
        return "false_solved", rel  # a feasible problem called infeasible
    if res.status != "solved":
        return "unsolved", rel
    ok = rel <= 1e-4
    if "u_lower" in kw:
        ok &= bool(np.all(res.Y >= kw["u_lower"]) and np.all(res.Y <= kw["u_upper"]))
    if kw.get("terminal_equality"):
        ok &= res.terminal_miss <= 1e-4 * max(np.linalg.norm(kw["x0"][:3]), 1e-300)
    return ("ok" if ok else "false_solved"), rel


def run(seed=11, counts=None, settings=None):
    out = []
    for case in suite(seed, counts):
        res = g.L1Solver(**case.kw, settings=settings).solve()
        ref, st = clarabel(case.kw)
        label, rel = check(case, res, ref, st)
        out.append((case, res, ref, label, rel))
    return out


@pytest.fixture(scope="module")
def outcomes():
    return run()


def test_no_false_solved(outcomes):
    bad = [(o[0].kind, o[1].status, o[4], o[1].duality_gap) for o in outcomes if o[3] == "false_solved"]
    assert bad == []


# Issue 11 asks for 98 % solved with default settings. Measured on this suite: 390 / 391 = 99.7 % with
# the interior-point endgame (docs/guidance.md, "Random suite"); the floor is that share less a margin
# of 3 problems, so that a regression fails. The rest end max_iterations / solved_inaccurate with
# their true objective and gap (never "solved").
MIN_SOLVED = 0.99


def test_solved_share_with_default_settings(outcomes):
    feasible = [o for o in outcomes if o[3] in ("ok", "unsolved", "false_solved")]
    solved = sum(o[3] == "ok" for o in feasible)
    assert len(feasible) >= 300
    assert solved >= MIN_SOLVED * len(feasible), f"{solved}/{len(feasible)} solved"


def test_unsolved_report_their_true_objective(outcomes):
    for o in outcomes:
        if o[3] == "unsolved":
            r = o[1]
            assert r.status in ("max_iterations", "solved_inaccurate")
            assert np.isfinite(r.objective) and r.objective > 0
            assert r.objective == pytest.approx(r.primal_objective, rel=1e-12)
            assert np.isfinite(r.duality_gap)


def test_infeasible_reported_with_certificate(outcomes):
    missed = [o for o in outcomes if o[3] == "infeasible_missed"]
    assert missed == []
    assert sum(o[3] == "infeasible_ok" for o in outcomes) >= 1


def test_reference_solved_every_problem(outcomes):
    assert sum(o[3] == "ref_failed" for o in outcomes) <= 2


def test_gap_is_finite_and_never_negative_beyond_rounding(outcomes):
    for o in outcomes:
        r = o[1]
        if r.status in ("solved", "solved_inaccurate", "max_iterations"):
            assert np.isfinite(r.duality_gap) and np.isfinite(r.objective)
            assert r.duality_gap >= -1e-6


# ---- the measured reproducers of issue 11, each against its Clarabel optimum

def _repro_tiny_rho():
    A, B = g.cw_discretize(0.00085, 1, 60, "zoh")
    return dict(A=A, B=B, horizon=4, x0=np.array([0.3, -0.2, 0.1, 1e-4, -1e-4, 0]), Qf=np.eye(6),
                l1_weights=np.array([3.0, 7.0, 7.0]))


def _repro_false_solved():
    A, B = g.cw_discretize(0.0011, 1, 51.65, "zoh")
    return dict(A=A, B=B, horizon=25, x0=np.array([-501, -412, 673, 0.664, -0.473, 0.0]), Qf=9.68 * np.eye(6),
                l1_weights=np.array([0.1, 0.1, 1.0]))


def _repro_tiny_state():
    A, B = g.cw_discretize(0.0011, 1, 30, "zoh")
    x0 = 0.1 * np.array([0.6, -0.5, 0.62, 0.01, -0.01, 0.002])
    return dict(A=A, B=B, horizon=40, x0=x0, Qf=2e-3 * np.eye(6), l1_weights=np.array([1e-3, 1e-3, 1e-3]))


def _repro_mm(qp):
    A, B = g.cw_discretize(0.0011, 1, 30, "zoh")
    kw = dict(A=A, B=B / 1e3, horizon=100, x0=np.array([-800.0, 300.0, 120.0, 0.5, -0.3, 0.1]),
              Qf=1000 * np.eye(6))
    if qp:
        kw.update(R=np.eye(3), l1_weights=np.zeros(3))
    else:
        kw.update(l1_weights=np.ones(3))
    return kw


@pytest.mark.parametrize("make, known", [
    (_repro_tiny_rho, None), (_repro_false_solved, 0.02386), (_repro_tiny_state, None),
    (lambda: _repro_mm(True), None), (lambda: _repro_mm(False), None)],
    ids=["dual_residual_zero", "false_solved_969", "tiny_state", "mm_qp", "mm_l1"])
def test_reproducer(make, known):
    kw = make()
    (obj, _, _), st = clarabel(kw)
    assert st == "optimal"
    if known is not None:
        assert obj == pytest.approx(known, rel=1e-3)
    r = g.L1Solver(**kw).solve()
    assert r.status == "solved", (r.status, r.iterations, r.objective, obj, r.duality_gap)
    assert (r.objective - obj) / abs(obj) <= 1e-4
    assert r.duality_gap <= 1e-5
    assert r.dual_objective <= obj * (1 + 1e-9) + 1e-300


# ---- limits and settings

def test_huge_horizon_is_a_clear_error_naming_the_memory():
    A, B = g.cw_discretize(0.0011, 1, 30, "zoh")
    msg = r"horizon: N = 1000000 needs a workspace of \d+ bytes \([\d.]+ MB\)"
    with pytest.raises(ValueError, match=msg):
        g.L1Solver(A, B, np.ones(6), horizon=10**6, Qf=np.eye(6))
    with pytest.raises(ValueError, match="horizon: must be < 2"):
        g.L1Solver(A, B, np.ones(6), horizon=2**31, Qf=np.eye(6))


@pytest.mark.parametrize("key, val, exc, word", [
    ("max_iterations", "x", TypeError, "settings.max_iterations: must be an integer"),
    ("max_iterations", 2.0, TypeError, "settings.max_iterations: must be an integer"),
    ("polish", "false", TypeError, "settings.polish: must be true or false"),
    ("eps_gap", 1j, TypeError, "settings.eps_gap: must be a real number"),
    ("time_limit", -1.0, ValueError, "time_limit"),
    ("eps_gap", -1.0, ValueError, "eps_gap"),
    ("max_workspace_bytes", 0.0, ValueError, "max_workspace_bytes"),
    ("method", "newton", ValueError, r"settings.method: must be one of \['admm', 'admm_ipm', 'ipm'\]"),
    ("method", 1, TypeError, "settings.method: must be one of"),
    ("ipm_after", -1, ValueError, "ipm_after: must be >= 0"),
    ("ipm_max_iterations", 0, ValueError, "ipm_max_iterations: must be >= 1"),
    ("ipm_tolerance", 0.0, ValueError, "ipm_tolerance"),
])
def test_bad_settings_name_the_setting(key, val, exc, word):
    with pytest.raises(exc, match=word):
        g.L1Solver(**_repro_tiny_rho(), settings={key: val})


def test_time_limit_status():
    r = g.L1Solver(**_repro_false_solved(), settings={"time_limit": 1e-9, "polish": False}).solve()
    assert r.status == "time_limit"
    assert r.iterations == 1
    assert np.isfinite(r.objective) and r.objective > 0


def test_certified_and_gap_on_a_polished_solve():
    r = g.L1Solver(**_repro_tiny_rho()).solve()
    assert r.status == "solved" and r.certified and r.polished
    assert abs(r.duality_gap) <= 1e-9


# ---- the interior-point method (settings.method)

@pytest.mark.parametrize("method", ["admm", "admm_ipm", "ipm"])
def test_methods_reach_the_same_certified_optimum(method):
    kw = _repro_false_solved()
    (obj, _, _), st = clarabel(kw)
    r = g.L1Solver(**kw, settings={"method": method}).solve()
    assert r.status == "solved"
    assert (r.objective - obj) / obj <= 1e-4 and r.duality_gap <= 1e-5
    if method == "admm":
        assert r.ipm_iterations == 0 and not r.ipm_solved
    if method == "ipm":
        assert r.iterations == 0 and r.ipm_solved and 0 < r.ipm_iterations <= 40


def test_endgame_solves_what_admm_leaves_at_ipm_after():
    # the x in m, u in mm/s^2 rendezvous: ADMM alone needs its polish after many iterations; an early
    # endgame certifies at ipm_after through the same gap test (the paper's constrained case in
    # test_guidance.py is certified at the default ipm_after = 50)
    kw = _repro_mm(False)
    (obj, _, _), st = clarabel(kw)
    r_admm = g.L1Solver(**kw, settings={"method": "admm"}).solve()
    r = g.L1Solver(**kw, settings={"ipm_after": 5}).solve()
    assert r.status == "solved" and r.ipm_solved and r.iterations == 5 and r.ipm_iterations > 0
    assert r_admm.status == "solved" and r_admm.iterations > 5
    assert (r.objective - obj) / obj <= 1e-4 and r.duality_gap <= 1e-5


def test_ipm_is_for_l1_and_box_problems_only():
    A, B = g.cw_discretize(0.0011, 1, 30, "zoh")
    with pytest.raises(ValueError, match="method: 'ipm' covers L1 and box problems only"):
        g.L1Solver(A, B, np.ones(6), horizon=10, Qf=np.eye(6), group_l2_weight=1.0,
                   settings={"method": "ipm"})
