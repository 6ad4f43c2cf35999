"""Keep-out ellipsoid by SCP with supporting half-spaces and a trust region (satgnc.guidance.keep_out,
issue 16 item 1): the plan stays out at every node and between nodes on the J2 + drag truth."""

from __future__ import annotations

import numpy as np
import pytest
from satgnc.guidance import RendezvousProblem, cw_discretize, solve_l1
from satgnc.guidance.keep_out import keep_out_plan, supporting_half_spaces
from satgnc.guidance.safety import KeepOut

MU, R = 3.986004418e14, 7231.0e3  # the l1 scenario's orbit (its drag density is referenced to 6731 km)


def problem(tf=600.0, N=20):
    # from the V-bar 150 m ahead to a hold point 60 m behind in 600 s: the unconstrained L1 plan cuts
    # straight through a 40 m sphere about the target
    return RendezvousProblem(mu=MU, radius=R, mass=100.0, x0=np.array([150.0, 0, 0, 0, 0, 0]), tf=tf,
                             horizon=N, alpha=1.0, Qf=0.0, u_max=0.5, terminal_equality=True)


XF = [-60.0, 0, 0, 0, 0, 0]


def test_supporting_half_spaces_exclude_the_ellipsoid():
    rng = np.random.default_rng(7)
    ko = KeepOut([5.0, -3.0, 1.0], [40.0, 25.0, 10.0])
    P = ko.center + rng.normal(size=(200, 3)) * 60.0
    a, b = supporting_half_spaces(P, ko)
    # each point outside satisfies its own half-space (a'p - b = -(rho - 1) <= 0, round-off 1e-9)
    out = ko.rho(P) >= 1.0
    assert np.all(np.einsum("ij,ij->i", a, P)[out] - b[out] <= 1e-9)
    # no point of the ellipsoid satisfies any half-space strictly: sample its interior and surface
    u = rng.normal(size=(2000, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    inside = ko.center + u * ko.semi_axes * rng.uniform(0, 1, size=(2000, 1)) ** (1 / 3)
    worst = np.max(inside @ a.T - b[None, :], axis=0)  # per half-space, the best point of the zone
    assert np.all(worst >= -1e-9)


def test_keep_out_scp_with_clarabel_subproblems():
    pb = problem()
    ko = KeepOut.sphere(40.0)
    r = keep_out_plan(pb, ko, xf=XF, solver="cvxpy")
    # the unconstrained plan (fuel_history[0]) enters the zone: the constraint is active
    Ad, Bd = cw_discretize(pb.n, pb.mass, pb.dt, "zoh")
    # compared with Clarabel's fuel at 1e-6 below: certified to a gap of 1e-7 (the default 1e-5 let the
    # IPM stop 2.9e-6 above it, an honest certificate but not a 1e-6 comparison)
    free = solve_l1(Ad, Bd, np.asarray(pb.x0), horizon=pb.horizon, xf=np.array(XF),
                    l1_weights=np.full(3, pb.dt), u_lower=-0.5 * np.ones(3), u_upper=0.5 * np.ones(3),
                    terminal_equality=True, settings=dict(eps_gap=1e-7))
    assert free.status == "solved" and ko.rho(free.X_flown[:, :3]).min() < 0.7  # 0.60: 24 m from the target
    assert float(np.abs(free.Y).sum() * pb.dt) == pytest.approx(r.fuel_history[0], rel=1e-6)
    assert r.converged and r.status == "solved"
    # every constrained node of the plan is outside the inflated zone (half-spaces exact; Clarabel 1e-7)
    assert r.node_rho[1:].min() >= 1.05 - 1e-6
    assert r.satisfied_nodes and r.satisfied_flown
    # between nodes on the J2 + drag truth (20 samples per interval): still out of the true zone
    assert r.flown_rho_min >= 1.0
    # after the first constrained iterate the fuel never rises (the previous plan stays feasible)
    h = r.fuel_history[1:]
    assert np.all(np.diff(h) <= 1e-6 * h[:-1])
    assert r.fuel >= r.fuel_history[0] * (1 - 1e-6)  # the zone costs fuel


def test_bad_input():
    pb = problem()
    ko = KeepOut.sphere(40.0)
    with pytest.raises(ValueError) as e:
        keep_out_plan(pb, ko, solver="cvxpy")
    assert str(e.value).startswith("xf: the hold point [0.0, 0.0, 0.0] m lies inside the (inflated) "
                                   "keep-out zone")
    with pytest.raises(ValueError) as e:
        keep_out_plan(pb, KeepOut.sphere(200.0), xf=[-300.0, 0, 0, 0, 0, 0], solver="cvxpy")
    assert str(e.value) == "problem.x0: the start lies inside the keep-out zone"
    with pytest.raises(ValueError) as e:
        keep_out_plan(pb, ko, xf=XF, solver="osqp")
    assert str(e.value).startswith("solver: must be one of")
    with pytest.raises(TypeError) as e:
        keep_out_plan(pb, 40.0, xf=XF)
    assert str(e.value) == "keep_out: must be a KeepOut, got float"


def test_without_trust_region_the_same_plan():
    # trust_radius = inf: no trust rows; the iterates are still feasible and the fuel still never rises,
    # and on this case they reach the same optimum as with the trust region (1e-6 relative)
    pb = problem()
    ko = KeepOut.sphere(40.0)
    a = keep_out_plan(pb, ko, xf=XF, solver="cvxpy", truth=False)
    b = keep_out_plan(pb, ko, xf=XF, solver="cvxpy", truth=False, trust_radius=float("inf"))
    assert b.converged and b.satisfied_nodes
    assert abs(a.fuel - b.fuel) <= 1e-6 * a.fuel


def test_keep_out_scp_on_the_engine_matches_clarabel():
    # the same SCP with satgnc's state-constrained ADMM (GUID16A's half-spaces and boxes) as subproblem
    pb = problem()
    ko = KeepOut.sphere(40.0)
    ref = keep_out_plan(pb, ko, xf=XF, solver="cvxpy", truth=False)
    r = keep_out_plan(pb, ko, xf=XF, solver="admm")
    assert r.converged and r.status == "solved"
    assert r.node_rho[1:].min() >= 1.05 - 1e-6  # the engine's violation tolerance is 1e-7 relative
    assert r.satisfied_nodes and r.satisfied_flown
    # each subproblem is a certified optimum of the same convex problem as Clarabel's: the SCP iterates,
    # and so the final fuel, agree to the subproblems' tolerance compounded over the iterations (1e-5)
    assert r.iterations == ref.iterations
    assert abs(r.fuel - ref.fuel) <= 1e-5 * ref.fuel
    # every subproblem certified by the engine's interior-point method (its default, method admm_ipm)
    assert r.ipm_subproblems == r.iterations


def test_engine_scp_with_admm_only_matches_clarabel():
    # method "admm" (the interior-point method skipped): the ADMM fallback of each subproblem reaches
    # the same SCP iterates (fuel 1e-5, as above) and no subproblem is counted as the IPM's
    pb = problem()
    ko = KeepOut.sphere(40.0)
    ref = keep_out_plan(pb, ko, xf=XF, solver="cvxpy", truth=False)
    r = keep_out_plan(pb, ko, xf=XF, truth=False, settings={"method": "admm", "eps_gap": 1e-7})
    assert r.converged and r.status == "solved" and r.iterations == ref.iterations
    assert abs(r.fuel - ref.fuel) <= 1e-5 * ref.fuel
    assert r.ipm_subproblems == 0


@pytest.mark.parametrize("st", [{"method": "admm", "eps_gap": 1e-7}, {"eps_gap": 1e-7}], ids=["admm", "ipm"])
def test_lazy_trust_region_subproblem_equals_the_trust_region_one(st):
    # one SCP subproblem linearized at positions P pushed 15 sin(pi k / N) m out of plane: without the
    # trust rows its minimizer returns to the plane (a step > 8 m), so the lazy engine solves it again
    # with them; the plan must equal Clarabel's on the trust-region subproblem (fuel 1e-6 relative)
    from satgnc.guidance.keep_out import _LazyTrustRegion, _solve_cvxpy
    from satgnc.guidance.min_time import _controls

    pb = problem()
    ko = KeepOut.sphere(40.0)
    base = keep_out_plan(pb, ko, xf=XF, solver="cvxpy", truth=False)
    N, tr = pb.horizon, 8.0
    idx = list(range(1, N + 1))
    P = base.X[idx, :3].copy()
    P[:, 2] += 15.0 * np.sin(np.pi * np.arange(1, N + 1) / N)
    Ad, B, lo, hi = _controls(pb, None)
    w = np.full(3, pb.dt)
    lazy = _LazyTrustRegion(Ad, B, np.asarray(pb.x0), np.array(XF), N, w, lo, hi, st, idx, ko, 0.05, tr)
    Xp = base.X.copy()
    Xp[idx, :3] = P
    status, U, X, _ = lazy.solve(Xp)
    assert lazy.with_trust == 1 and status == "solved"
    a3, b = supporting_half_spaces(P, ko, 0.05)
    a = np.zeros((N, 6))
    a[:, :3] = a3
    L, H = np.full((N, 6), -np.inf), np.full((N, 6), np.inf)
    L[:, :3], H[:, :3] = P - tr, P + tr
    st_ref, U_ref, X_ref, _ = _solve_cvxpy(Ad, B, np.asarray(pb.x0), np.array(XF), N, w, lo, hi, (idx, a, b),
                                           (idx, L, H), st)
    assert st_ref == "solved"
    assert abs(np.abs(U).sum() - np.abs(U_ref).sum()) <= 1e-6 * np.abs(U_ref).sum()
    assert np.max(np.abs(X[idx, :3] - P)) <= tr * (1 + 1e-6)  # inside the trust region
    assert np.max(np.abs(X_ref[idx, :3] - P)) >= tr * (1 - 1e-6)  # and it binds


def test_engine_scp_on_seeded_problems_matches_clarabel():
    # seeded keep-out problems (start 120-200 m ahead within +-23 deg, hold point 60-100 m behind, sphere
    # 30-45 m, 600-1000 s): the engine SCP and the Clarabel SCP agree on status, iterations and fuel
    rng = np.random.default_rng(16)
    for _ in range(6):
        ang, r0 = rng.uniform(-0.4, 0.4), rng.uniform(120, 200)
        x0 = np.array([r0 * np.cos(ang), r0 * np.sin(ang), rng.uniform(-10, 10), 0, 0, 0])
        xf = np.array([-rng.uniform(60, 100), rng.uniform(-10, 10), 0, 0, 0, 0])
        rad, tf = rng.uniform(30, 45), float(rng.choice([600.0, 800.0, 1000.0]))
        pb = RendezvousProblem(mu=MU, radius=R, mass=100.0, x0=x0, tf=tf, horizon=20, alpha=1.0, Qf=0.0,
                               u_max=0.5, terminal_equality=True)
        ref = keep_out_plan(pb, KeepOut.sphere(rad), xf=xf, solver="cvxpy", truth=False)
        r = keep_out_plan(pb, KeepOut.sphere(rad), xf=xf, truth=False)
        assert r.status == ref.status == "solved" and r.converged
        assert r.iterations == ref.iterations
        assert abs(r.fuel - ref.fuel) <= 1e-5 * ref.fuel
        assert r.satisfied_nodes and r.node_rho[1:].min() >= 1.05 - 1e-6


def test_plan_without_the_zone_falls_back_to_the_row_free_solver(monkeypatch):
    # if the relaxed-row solve of the plan without the zone does not end solved, the row-free L1 solver
    # gives it: the same SCP result (fuel 1e-6 relative to the normal path)
    from satgnc.guidance import keep_out as ko_mod

    pb, ko = problem(), KeepOut.sphere(40.0)
    normal = keep_out_plan(pb, ko, xf=XF, truth=False)
    orig = ko_mod._EngineSubproblem.solve
    calls = []

    def first_fails(self, rows):
        calls.append(1)
        status, U, X, t = orig(self, rows)
        return ("max_iterations", U, X, t) if len(calls) == 1 else (status, U, X, t)

    monkeypatch.setattr(ko_mod._EngineSubproblem, "solve", first_fails)
    r = keep_out_plan(pb, ko, xf=XF, truth=False)
    assert len(calls) == r.iterations + 1  # the failed relaxed solve, then one per SCP iteration
    assert r.status == "solved" and r.converged
    assert abs(r.fuel_history[0] - normal.fuel_history[0]) <= 1e-6 * normal.fuel_history[0]
    assert abs(r.fuel - normal.fuel) <= 1e-6 * normal.fuel
