"""State constraints in the L1 ADMM (issue 16 item 1): half-spaces, state boxes with a closing-velocity
limit, the approach cone, and all of them together, each on >= 30 seeded random Clohessy-Wiltshire
problems, against cvxpy + Clarabel solving the same problem in its own formulation (states as
variables, the cone as a cvxpy SOC). Every problem is built around its zero-thrust drift, which
satisfies the constraints by construction (so it is feasible), while the constraints are tight on
that drift (so they are active at the optimum).

Asserted per problem: a "solved" plan has its objective within 1e-6 relative of Clarabel's (run at
1e-10 tolerances) and violates the constraints by <= 1e-7 scaled by ||X_flown||_inf (the solver's
tolerance is eps_abs 1e-10 + eps_rel 1e-8 of that scale, so 1e-7 leaves a margin of 10); no false
"solved"; the dual bound is below Clarabel's optimum (weak duality, up to Clarabel's 1e-8 relative
accuracy) on every outcome; the solved share per family is at least the measured floor MIN_SOLVED.
Infeasible combinations (cone + box + a terminal state outside the cone; a control box too small to
reach the terminal state) end "primal_infeasible" (Clarabel agrees), never "solved".
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from satgnc import guidance as g

MU = 3.986004418e14  # m^3/s^2
RE = 6378.137e3  # m
TIGHT = dict(eps_abs=1e-10, eps_rel=1e-8, eps_gap=1e-8, max_iterations=200000)
COUNT = 30  # problems per family (issue 16: >= 30)


def _drift(A, x0, N):
    X = np.zeros((N + 1, 6))
    X[0] = x0
    for k in range(N):
        X[k + 1] = A @ X[k]
    return X


def draw(rng: np.random.Generator, family: str) -> dict:
    """A random CW problem (scenario frame of cw_discretize: position entries 0..2, velocity 3..5)
    and its state constraints, feasible through the zero plan. Family "coupled": the mixed
    constraints on a non-CW model, A = A_cw (I + 1e-3 D R D^-1) with R standard normal (every state
    coupled, D the velocity scale 1 / (N dt) on entries 3..5)
    and a fourth, skewed thruster B v (|v| = 1): (nx, nu) = (6, 4) runs the IPM's dynamic-size stage
    path (factor_stages), not the (6, 3) kernel riccati_63."""
    coupled = family == "coupled"
    family = "mixed" if coupled else family
    alt = rng.uniform(400e3, 36000e3)
    n = np.sqrt(MU / (RE + alt) ** 3)
    dt = rng.uniform(20.0, 120.0)
    N = int(rng.integers(8, 31))
    A, B = g.cw_discretize(n, 1.0, dt, "zoh")
    if coupled:
        D = np.r_[np.ones(3), np.full(3, 1.0 / (N * dt))]  # velocities on the position scale
        A = A @ (np.eye(6) + 1e-3 * D[:, None] * rng.normal(size=(6, 6)) / D[None, :])
        v = rng.normal(size=3)
        B = np.column_stack([B, B @ (v / np.linalg.norm(v))])
    nu = B.shape[1]
    pos = rng.uniform(20.0, 500.0)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    p0 = pos * (axis + 0.2 * rng.normal(size=3))
    v0 = -p0 / (N * dt) * rng.uniform(0.2, 1.0) + 0.01 * pos / (N * dt) * rng.normal(size=3)
    x0 = np.concatenate([p0, v0])
    X0 = _drift(A, x0, N)
    need = 4.0 * pos / (N * dt) ** 2
    umax = need * rng.uniform(1.0, 10.0)
    kw = dict(A=A, B=B, x0=x0, horizon=N, Qf=rng.uniform(1e-3, 1.0) * np.eye(6),
              l1_weights=rng.uniform(0.3, 3.0, nu), u_lower=-umax * np.ones(nu), u_upper=umax * np.ones(nu))
    nodes = np.arange(1, N + 1)
    if family in ("half_space", "mixed"):
        M = int(rng.integers(3, 2 * N))
        hn = rng.integers(1, N + 1, size=M)
        a = rng.normal(size=(M, 6))
        a[:, 3:] *= N * dt  # velocity entries on the position scale
        b = np.einsum("ij,ij->i", a, X0[hn]) + rng.uniform(0.0, 0.05, M) * np.abs(a @ np.r_[p0, v0])
        kw["half_spaces"] = dict(nodes=hn, a=a, b=b)
    if family in ("box", "mixed"):
        sel = rng.integers(1, N + 1, size=max(2, N // 2))
        sel = np.unique(sel)
        lo = np.full((sel.size, 6), -np.inf)
        hi = np.full((sel.size, 6), np.inf)
        for e in range(6):
            if rng.uniform() < 0.5:
                span = np.abs(X0[sel, e]) * rng.uniform(0.0, 0.2) + 1e-3 * (pos if e < 3 else pos / (N * dt))
                lo[:, e] = X0[sel, e] - span
                hi[:, e] = X0[sel, e] + span
        kw["state_lower"], kw["state_upper"], kw["state_box_nodes"] = lo, hi, sel
        # closing velocity |a.v| <= min(c0 + s0 r, c1 + s1 r) along the initial line of sight
        r_along = X0[1:, :3] @ axis
        v_along = np.abs(X0[1:, 3:] @ axis)
        slopes = np.sort(rng.uniform(0.0, 2.0 / (N * dt), 2))
        inter = np.array([np.max(v_along - s * r_along) for s in slopes])
        inter = inter + np.abs(inter) * rng.uniform(0.0, 0.1)
        inter = inter + 1e-6 * pos / (N * dt)
        kw["closing_velocity"] = dict(nodes=nodes, axis=axis, intercept=inter, slope=slopes)
    if family in ("cone", "mixed"):
        ax = X0[0, :3] / np.linalg.norm(X0[0, :3])
        along = X0[1:, :3] @ ax
        perp = np.linalg.norm(X0[1:, :3] - np.outer(along, ax), axis=1)
        d = min(along.min(), 0.0) - rng.uniform(0.05, 0.5) * pos
        tan = np.max(perp / (along - d)) * (1.0 + rng.uniform(0.0, 0.05)) + 1e-3
        ang = np.degrees(np.arctan(tan))
        kw["approach_cone"] = dict(nodes=nodes, axis=ax, half_angle_deg=ang, apex_offset=d)
    return kw


def clarabel(kw):
    """Optimum of the same problem by cvxpy + Clarabel (states as variables)."""
    import cvxpy as cp

    A, B, x0, N = kw["A"], kw["B"], kw["x0"], kw["horizon"]
    X = cp.Variable((N + 1, 6))
    U = cp.Variable((N, B.shape[1]))
    cons = [X[0] == x0, X[1:].T == A @ X[:-1].T + B @ U.T]
    cons += [U <= kw["u_upper"], U >= kw["u_lower"]]
    obj = 0.5 * cp.quad_form(X[N], kw["Qf"]) + cp.sum(cp.abs(U) @ kw["l1_weights"])
    if kw.get("terminal_equality"):
        cons.append(X[N] == 0)
    if "half_spaces" in kw:
        h = kw["half_spaces"]
        for k, a, b in zip(h["nodes"], h["a"], h["b"]):
            cons.append(a @ X[k] <= b)
    if "state_lower" in kw:
        for i, k in enumerate(kw["state_box_nodes"]):
            for e in range(6):
                if np.isfinite(kw["state_lower"][i, e]):
                    cons.append(X[k, e] >= kw["state_lower"][i, e])
                if np.isfinite(kw["state_upper"][i, e]):
                    cons.append(X[k, e] <= kw["state_upper"][i, e])
    if "closing_velocity" in kw:
        c = kw["closing_velocity"]
        a = c["axis"] / np.linalg.norm(c["axis"])
        for k in c["nodes"]:
            for ic, s in zip(c["intercept"], c["slope"]):
                cons.append(cp.abs(X[k, 3:] @ a) <= ic + s * (X[k, :3] @ a))
    if "approach_cone" in kw:
        c = kw["approach_cone"]
        a = c["axis"] / np.linalg.norm(c["axis"])
        t = np.tan(np.radians(c["half_angle_deg"]))
        P = np.eye(3) - np.outer(a, a)
        for k in c["nodes"]:
            cons.append(cp.SOC(t * (X[k, :3] @ a - c["apex_offset"]), P @ X[k, :3]))
    prob = cp.Problem(cp.Minimize(obj), cons)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prob.solve(solver=cp.CLARABEL, tol_gap_abs=1e-10, tol_gap_rel=1e-10, tol_feas=1e-10, max_iter=400)
    return prob.status, (None if prob.value is None else float(prob.value))


def violation(kw, X):
    """Largest violation of the constraints by the trajectory X (N+1, 6), recomputed here."""
    v = 0.0
    if "half_spaces" in kw:
        h = kw["half_spaces"]
        a = np.asarray(h["a"])
        v = max(v, np.max((np.einsum("ij,ij->i", a, X[h["nodes"]]) - h["b"]) / np.linalg.norm(a, axis=1)))
    if "state_lower" in kw:
        Xs = X[kw["state_box_nodes"]]
        v = max(v, np.max(kw["state_lower"] - Xs), np.max(Xs - kw["state_upper"]))
    if "closing_velocity" in kw:
        c = kw["closing_velocity"]
        a = c["axis"] / np.linalg.norm(c["axis"])
        for k in c["nodes"]:
            for ic, s in zip(c["intercept"], c["slope"]):
                e = abs(X[k, 3:] @ a) - ic - s * (X[k, :3] @ a)
                v = max(v, e / np.sqrt(1.0 + s * s))
    if "approach_cone" in kw:
        c = kw["approach_cone"]
        a = c["axis"] / np.linalg.norm(c["axis"])
        ang = np.radians(c["half_angle_deg"])
        for k in c["nodes"]:
            p = X[k, :3]
            e = np.linalg.norm(p - (p @ a) * a) - np.tan(ang) * (p @ a - c["apex_offset"])
            v = max(v, e * np.cos(ang))
    return max(v, 0.0)


# Solved share measured on these seeds (2026-12-03): the Riccati-structured interior-point method runs first
# (state_ipm.cpp) and its plan is accepted only by the same violation and Fenchel-gap tests; otherwise ADMM
# + polish go on (5000 iterations). Session 11 (cone start depth; adaptive fraction to the boundary without
# interval rows): the same counts but coupled 28/30 (case 16 lost, 2 and 7 gained).
# Session 10 (these floors): the bias of the IPM's dual regularization removed from the corrector's Newton
# direction (it had kept an active row's violation from closing):
# half-spaces 30/30, cones 30/30, boxes + closing velocity 30/30, mixed 29/30 (all by the IPM; case 29 not
# certified), "coupled" (the mixed constraints on a non-CW model with four thrusters: the IPM's
# dynamic-size path, whose Riccati update is now in the PSD form too) 27/30 (was 23/30 by the IPM alone on
# main). Session 9, second round: the IPM's Riccati update in the
# PSD form (A - BK)'P(A - BK) + K'Rd K + Q (the difference form made Quu indefinite and stopped 5 runs on a
# failed factorization): half-spaces 30/30 (30 by the IPM), cones 30/30 (30), boxes + closing velocity 29/30
# (29), mixed 27/30 (27). Session 9, first round: the IPM's interval rows are dual-regularized (barrier
# weight 1 / (s/z + 1e-6)) and each Newton solve is iteratively refined: on the box and mixed failures the
# IPM had stopped on a failed factorization mid-way (barrier weights of the degenerate active rows ~1e12,
# the Riccati recursion lost its digits). Now half-spaces 30/30 (30 by the IPM), cones 30/30 (30), boxes +
# closing velocity 28/30 (28), mixed 25/30 (25). Third session: 29 (29) / 30 (30) / 12 (12) / 9 (9) with
# least-squares multipliers on the plan's active set (recover_dual) and an active-set polish of the IPM's
# plan (ipm_polish); second 27 (21) / 30 (30) / 7 (6) / 5 (5); first 26 (20) / 30 (29) / 6 (5) / 2 (2);
# before the IPM 21+/21+/2/0. Goal 95 %: not met for boxes (93 %) and mixed (83 %) then; now met for boxes
# (97 %), not for mixed (90 %); the remaining failures end uncertified (gap 1e-7..1e-3), never a false
# "solved". The floors are the measured shares minus a margin; the hard requirement is that no "solved" is
# false.
MIN_SOLVED = {"half_space": 0.95, "box": 0.95, "cone": 0.95, "mixed": 0.95, "coupled": 0.9}
MIN_IPM = dict(MIN_SOLVED)  # share certified by the IPM
MAX_ITER = 5000
FAMILY_ITER = {"mixed": 1500, "coupled": 1500}  # bounds the test's run time (the most rows)


def _family(family: str, seed: int):
    rng = np.random.default_rng(seed)
    stats = []
    for _ in range(COUNT):
        kw = draw(rng, family)
        assert violation(kw, _drift(kw["A"], kw["x0"], kw["horizon"])) <= 1e-9  # feasible by construction
        st, ref = clarabel(kw)
        assert st == "optimal", st
        r = g.solve_l1(**kw, settings=dict(TIGHT, max_iterations=FAMILY_ITER.get(family, MAX_ITER)))
        assert r.status in ("solved", "solved_inaccurate", "max_iterations"), r.status
        # weak duality: D <= optimum for every returned iterate (Clarabel accurate to ~1e-9 relative)
        assert r.dual_objective <= ref + 1e-8 * abs(ref)
        scale = np.max(np.abs(r.X_flown))
        # rolled out here, independently of the solver's own X_flown
        X = _drift(kw["A"], kw["x0"], kw["horizon"])
        for k in range(kw["horizon"]):
            X[k + 1] = kw["A"] @ X[k] + kw["B"] @ r.Y[k]
        assert np.allclose(X, r.X_flown, rtol=0, atol=1e-9 * scale)
        viol = violation(kw, X) / scale
        rel = abs(r.objective - ref) / abs(ref)
        if r.status == "solved":
            assert viol <= 1e-7, (family, viol)
            # 1e-6 relative; or, where ours is below Clarabel's value, the certificate decides: our
            # dual bound D is a proven lower bound on the optimum within eps_gap of our objective, so
            # Clarabel's plan is the less accurate one (seen once in 30 cone problems: 2e-6 at an
            # objective of 6e-3; Clarabel's tolerances are absolute in these units)
            below = r.objective < ref and r.dual_objective <= ref and abs(r.duality_gap) <= 1e-8
            assert rel <= 1e-6 or (below and rel <= 1e-5), (family, r.objective, ref, rel)
        stats.append((r.status == "solved", rel, viol, r.iterations, r.ipm_solved))
    return np.array(stats, dtype=float)


FAMILY_SEEDS = [("half_space", 1), ("box", 2), ("cone", 3), ("mixed", 4), ("coupled", 5)]


@pytest.mark.parametrize("family,seed", FAMILY_SEEDS)
def test_family_against_clarabel(family, seed):
    stats = _family(family, seed)
    assert stats.shape == (COUNT, 5)
    assert stats[:, 0].mean() >= MIN_SOLVED[family], (family, stats[:, 0].mean())
    # an IPM plan is always a certified "solved" one (ipm_solved implies solved)
    assert np.all(stats[stats[:, 4] == 1, 0] == 1)
    assert stats[:, 4].mean() >= MIN_IPM[family], (family, stats[:, 4].mean())


def test_constraints_are_active():
    """At least half of the drawn half-space problems have an optimum different from the unconstrained
    one (the constraints matter), else the comparison above would test nothing."""
    rng = np.random.default_rng(1)
    differs = 0
    for _ in range(10):
        kw = draw(rng, "half_space")
        state_keys = ("half_spaces", "state_lower", "state_upper", "state_box_nodes", "closing_velocity",
                      "approach_cone")
        base = {k: v for k, v in kw.items() if k not in state_keys}
        r0 = g.solve_l1(**base, settings=dict(TIGHT, max_iterations=MAX_ITER))
        r1 = g.solve_l1(**kw, settings=dict(TIGHT, max_iterations=MAX_ITER))
        differs += (r1.objective - r0.objective) > 1e-6 * abs(r1.objective)
    assert differs >= 5


def _infeasible_cases():
    rng = np.random.default_rng(7)
    out = []
    for _ in range(6):
        kw = draw(rng, "mixed")
        N = kw["horizon"]
        # terminal state x_N = 0 outside the approach cone at node N: apex beyond the target
        kw["terminal_equality"] = True
        c = dict(kw["approach_cone"])
        c["apex_offset"] = abs(c["apex_offset"]) + 1.0
        c["nodes"] = [N]
        kw["approach_cone"] = c
        kw.pop("half_spaces")
        out.append(kw)
    for _ in range(4):
        kw = draw(rng, "box")
        kw["terminal_equality"] = True
        kw["u_lower"] = kw["u_lower"] * 1e-3  # far too weak to reach x_N = 0
        kw["u_upper"] = kw["u_upper"] * 1e-3
        out.append(kw)
    return out


@pytest.mark.parametrize("i", range(10))
def test_infeasible_combinations_are_certified(i):
    kw = _infeasible_cases()[i]
    st, _ = clarabel(kw)
    assert st in ("infeasible", "infeasible_inaccurate"), st
    r = g.solve_l1(**kw, settings=dict(max_iterations=20000))
    assert r.status == "primal_infeasible", (r.status, r.iterations)
    y = r.infeasibility_certificate
    assert np.isclose(np.linalg.norm(y), 1.0, atol=1e-12)  # unit multiplier over the constraint rows


@pytest.mark.parametrize("hard", [True, False])
def test_cone_bench_plan_is_certified_by_the_ipm(hard):
    """The issue-16 bench plan (bench/guidance_safety.py cone_problem: CW, N = 100, approach cone at
    every node, |u| <= 0.01 m/s^2), with x_N = 0 exactly (dt 30 s) or the soft terminal Qf = I
    (dt 12 s): certified by the interior-point method alone, objective = Clarabel's (1e-10
    tolerances) to 1e-6 relative. Measured 2026-12-03: x_N = 0 31 IPM iterations (was 55-59 and, before
    the padded Schur factor, not certified), soft 26 (was 32); both within 3e-9 relative of Clarabel.
    Session 11 (cone slacks started 0.3 r inside, adaptive fraction to the boundary): 20 / 18."""
    N, dt = 100, (30.0 if hard else 12.0)
    A, B = g.cw_discretize(0.0011, 1.0, dt, "zoh")
    kw = dict(A=A, B=B, x0=np.array([150.0, 25.0, -10.0, -0.08, 0.0, 0.01]), horizon=N,
              Qf=(0.0 if hard else 1.0) * np.eye(6), l1_weights=np.ones(3), u_lower=-0.01 * np.ones(3),
              u_upper=0.01 * np.ones(3),
              approach_cone=dict(nodes=np.arange(1, N + 1), axis=[1.0, 0.0, 0.0], half_angle_deg=20.0,
                                 apex_offset=-20.0))
    if hard:
        kw["terminal_equality"] = True
    st, ref = clarabel(kw)
    assert st == "optimal", st
    r = g.solve_l1(**kw, settings=dict(eps_gap=1e-8, max_iterations=2000))
    assert r.status == "solved" and r.ipm_solved and r.iterations == 0
    assert r.ipm_iterations <= 26  # measured 20 (hard) / 18 (soft); 31 / 26 before session 11
    assert abs(r.duality_gap) <= 1e-8
    assert abs(r.objective - ref) <= 1e-6 * abs(ref), (r.objective, ref)
    assert r.dual_objective <= ref + 1e-8 * abs(ref)  # weak duality (Clarabel to ~1e-9 relative)
    assert r.max_violation <= r.violation_tolerance
    if hard:
        assert np.max(np.abs(r.X_flown[-1])) <= 1e-6


def test_half_space_update_matches_a_fresh_solve():
    """set_half_space (SCP: moved supporting half-spaces) gives the fresh solver's optimum."""
    rng = np.random.default_rng(1)
    kw = draw(rng, "half_space")  # the first problem of the half-space suite (solved, polished)
    s = g.L1Solver(**kw, settings=TIGHT)
    assert s.solve().status == "solved"
    h = kw["half_spaces"]
    new_b = np.array(h["b"], dtype=float)
    new_b[0] += 0.01 * abs(new_b[0]) + 1.0
    s.set_half_space(0, int(h["nodes"][0]), h["a"][0], new_b[0])
    r1 = s.solve()
    kw2 = dict(kw, half_spaces=dict(h, b=new_b))
    r2 = g.solve_l1(**kw2, settings=TIGHT)
    assert r1.status == r2.status == "solved"
    assert abs(r1.objective - r2.objective) <= 1e-6 * abs(r2.objective)


def test_existing_l1_numbers_unchanged_without_state_constraints():
    """No state keyword: the original solver runs (same result object, no state fields)."""
    rng = np.random.default_rng(3)
    kw = draw(rng, "cone")
    kw.pop("approach_cone")
    r = g.solve_l1(**kw)
    assert np.isnan(r.max_violation) and r.state_multipliers is None


def _cone(**kw):
    return dict(approach_cone={"nodes": [1], "axis": [1, 0, 0], "half_angle_deg": 30.0, **kw})


def _hs(**kw):
    return dict(half_spaces={"nodes": [1], "a": np.ones((1, 6)), "b": [0.0], **kw})


NODES = r"nodes must be in 1..N = 10"


@pytest.mark.parametrize("kwargs,match", [
    (_cone(half_angle_deg=0.0), r"approach_cone.half_angle_deg: must be in \(0, 90\)"),
    (_cone(half_angle_deg=90.0), r"approach_cone.half_angle_deg: must be in \(0, 90\)"),
    (_cone(half_angle_deg=120.0), r"approach_cone.half_angle_deg"),
    (_cone(axis=[0, 0, 0]), r"approach_cone.axis: must be nonzero"),
    (_cone(nodes=[0]), r"approach_cone.nodes: " + NODES),
    (_cone(nodes=[11]), r"approach_cone.nodes: " + NODES),
    (_cone(apex=1.0), r"approach_cone: unknown key 'apex'"),
    (dict(state_lower=np.ones(6), state_upper=np.zeros(6)),
     r"state_lower: must be <= state_upper \(node 1, entry 0"),
    (dict(state_lower=np.zeros(5)), r"state_lower: must have shape \(6,\)"),
    (dict(state_lower=-np.ones(6), state_box_nodes=[0, 3]), r"state_box_nodes: " + NODES),
    (dict(state_box_nodes=[1]), r"state_box_nodes: given without state_lower"),
    (_hs(nodes=[11]), r"half_spaces.nodes: " + NODES),
    (_hs(a=np.zeros((1, 6))), r"half_spaces.a: a row is zero"),
    (_hs(nodes=[1, 2]), r"half_spaces.a: must have shape \(2, 6\)"),
    (dict(half_spaces={"nodes": [1], "a": np.ones((1, 6))}), r"half_spaces: missing key 'b'"),
    (dict(closing_velocity=dict(nodes=[1], axis=[1, 0, 0], intercept=[1.0, 2.0], slope=[0.1])),
     r"closing_velocity.intercept: must have one entry per segment"),
    (dict(_hs(b=[1.0]), R=np.ones((3, 3))), r"R: must be diagonal with state constraints"),
])
def test_bad_arguments_name_the_argument(kwargs, match):
    A, B = g.cw_discretize(0.001, 1.0, 10.0, "zoh")
    with pytest.raises(ValueError, match=match):
        g.L1Solver(A, B, np.ones(6), horizon=10, Qf=np.eye(6), **kwargs)


def _check_ipm_alone(kw, ref):
    """IPM alone (method="ipm"): a certified plan within 1e-6 of Clarabel; an uncertified one returned as
    the IPM's last plan with its true cost (1e-4 of Clarabel's), never the starting (zero) plan with
    the cost of the drift. Returns whether it was certified."""
    r = g.solve_l1(**kw, settings=dict(TIGHT, method="ipm"))
    assert r.iterations == 0 and r.ipm_iterations > 0, r.status
    assert r.dual_objective <= ref + 1e-8 * abs(ref)  # weak duality of the reported bound
    if r.status == "solved":
        assert r.ipm_solved
        assert abs(r.objective - ref) <= 1e-6 * abs(ref), (r.objective, ref)
        return True
    assert np.abs(r.Y).max() > 0.0
    X = _drift(kw["A"], kw["x0"], kw["horizon"])
    for k in range(kw["horizon"]):
        X[k + 1] = kw["A"] @ X[k] + kw["B"] @ r.Y[k]
    scale = np.max(np.abs(X))
    assert np.allclose(X, r.X_flown, rtol=0, atol=1e-9 * scale)
    assert np.isfinite(r.objective) and abs(r.objective - ref) <= 1e-4 * abs(ref), (r.objective, ref)
    return False


def test_ipm_alone_uncertified_returns_its_last_plan_not_the_start():
    """method="ipm" without ADMM: a plan the IPM does not certify is returned as its last plan with its
    true cost. Box + closing-velocity family (seed 2), measured 2026-12-03: before the IPM's dual
    regularization 18 of 30 ended max_iterations; since session 9 (row weights 1 / (s/z + 1e-6),
    refined Newton solves) 28 of 30 certified (cases 10 and 23 not); since the PSD Riccati update case
    10 too; since session 10 (the regularization's bias removed from each Newton direction) case 23 too
    (it had needed 101 IPM iterations): all of the first 24 certified. The uncertified branch is
    exercised on the mixed family (seed 4), whose case 29 the IPM alone still does not certify (a
    near-parallel pair of closing-velocity rows at one node, one left 6e-4 (scaled) outside its bound
    while the other's slack collapsed to 1e-20: the IPM jams, objective 8e-7 relative above Clarabel's)."""
    rng = np.random.default_rng(2)
    uncertified = []
    for case in range(24):
        kw = draw(rng, "box")
        st, ref = clarabel(kw)
        assert st == "optimal", st
        if not _check_ipm_alone(kw, ref):
            uncertified.append(case)
    assert uncertified == [], uncertified
    rng = np.random.default_rng(4)
    for case in range(30):
        kw = draw(rng, "mixed")
        if case != 29:
            continue
        st, ref = clarabel(kw)
        assert st == "optimal", st
        assert not _check_ipm_alone(kw, ref), case
