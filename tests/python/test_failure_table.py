"""Thruster-loss table (satgnc.mission.failures, issue 16 item 3): the analysis room's verdicts on the
survivors, a hand-derived case, the replan against cvxpy + Clarabel and the 12-thruster table."""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest
from satgnc import analysis
from satgnc.guidance import RendezvousProblem, cw_discretize, cw_matrices
from satgnc.guidance.thrusters import axis_layout, cube_layout
from satgnc.mission.failures import failure_table, nnls, replan, sign_condition
from scipy.optimize import nnls as scipy_nnls

MU, R = 3.986004418e14, 7231.0e3  # the l1 scenario's orbit (its drag density is referenced to 6731 km)


def problem(x0=(120.0, -60.0, 30.0, 0.0, 0.0, 0.0), horizon=40, tf=2400.0, mass=100.0):
    return RendezvousProblem(mu=MU, radius=R, mass=mass, x0=np.array(x0), tf=tf, horizon=horizon, alpha=1.0,
                             Qf=0.0, terminal_equality=True)


def test_nnls_matches_scipy():
    rng = np.random.default_rng(3)
    for _ in range(20):
        A = rng.normal(size=(4, 7))
        b = rng.normal(size=4)
        x, res = nnls(A, b)
        xs, rs = scipy_nnls(A, b)
        assert np.all(x >= 0)
        # same residual (the minimizer may differ on degenerate sets): 1e-10 relative to ||b||
        assert abs(res - rs) <= 1e-10 * np.linalg.norm(b)


def test_sign_condition_hand_derived():
    # CW (paper frame, x = minus along-track): the left eigenvector of eigenvalue 0 is the along-track
    # drift integral, v' B ~ the along-track force; a one-sided along-track layout fails, radial and
    # out-of-plane signs do not matter (oscillators).
    A, B = cw_matrices(1.0, 1.0)
    assert sign_condition(A, B @ axis_layout().allocation())
    assert not sign_condition(A, B @ axis_layout(skip=["+x"]).allocation())
    assert sign_condition(A, B @ axis_layout(skip=["+y", "+z"]).allocation())


def test_hand_derived_loss_of_the_only_z_thruster():
    # five thrusters: +-x, +-y and +z only. Losing +z leaves the out-of-plane pair (z, vz) without
    # input: rank 4 of 6 and distance to uncontrollability 0 to round-off (the exact null vector of
    # [A - i I, B] at the z oscillator's eigenvalue). Losing +x leaves rank 6 but one-sided along-track
    # thrust (Brammer's sign condition fails); losing a radial thruster keeps everything.
    lay = axis_layout(1.0, skip=["-z"])
    t = failure_table(problem(), lay, fly_truth=False)
    rows = {r.failed: r for r in t.rows}
    nominal, lost_z, lost_x, lost_y = rows[()], rows[("+z",)], rows[("+x",)], rows[("+y",)]
    assert (nominal.rank, nominal.verdict, nominal.sign_ok) == (6, "full rank", True) and nominal.controllable
    assert (lost_z.rank, lost_z.verdict, lost_z.controllable, lost_z.status) == (4, "rank deficient", False,
                                                                                  "not_run")
    assert lost_z.distance <= 1e-12  # round-off of an exact zero (data of order 1)
    assert nominal.distance > 1e-2  # a controllable layout sits away from the uncontrollable set
    # the analysis room's own verdicts, called directly on the same survivors
    A1, B1 = cw_matrices(1.0, 1.0)
    rep = analysis.controllability(A1, B1 @ lay.without([4]).allocation())
    assert (rep.rank, rep.verdict) == (lost_z.rank, lost_z.verdict)
    assert (lost_x.rank, lost_x.sign_ok, lost_x.controllable) == (6, False, False)
    assert (lost_y.rank, lost_y.sign_ok, lost_y.controllable) == (6, True, True)
    assert nominal.status == "solved" and nominal.certified and lost_y.certified
    # the survivors' feasible set is a subset: the replan's optimum cannot be cheaper (1e-7 relative,
    # the gap tolerance of the replans)
    assert lost_y.fuel >= nominal.fuel * (1 - 1e-7)


@pytest.mark.parametrize("fmax, lost", [(1.0, [1]), (0.2, [3]), (0.2, [1])])
def test_replan_matches_cvxpy_clarabel(fmax, lost):
    # the replan's LP: min sum T dt, x_N = 0, 0 <= T <= fmax; the same with cvxpy + Clarabel
    pb = problem()
    lay = axis_layout(fmax).without(lost)
    r = replan(pb, lay)
    Ad, Bd = cw_discretize(pb.n, pb.mass, pb.dt, "zoh")
    Bt = Bd @ lay.allocation()
    T = cp.Variable((pb.horizon, lay.size))
    cons = [T >= 0, T <= lay.max_thrust[None, :]]
    xs = np.asarray(pb.x0)
    for k in range(pb.horizon):
        xs = Ad @ xs + Bt @ T[k]
    cons.append(xs == 0)
    prob = cp.Problem(cp.Minimize(cp.sum(T) * pb.dt), cons)
    prob.solve(solver=cp.CLARABEL)
    if prob.status == "infeasible":
        # one-sided along-track thrust at 0.2 N cannot stop the drift in 2400 s: both say so
        assert r.status == "primal_infeasible"
        return
    assert prob.status == "optimal" and r.status == "solved"
    fuel = float(np.sum(np.maximum(r.Y, 0)) * pb.dt)
    # objective within 1e-6 relative (the check; Clarabel's own tolerance is 1e-8)
    assert abs(fuel - prob.value) <= 1e-6 * abs(prob.value)
    # nonnegative thrust: the lower bound handed to the solver is exactly 0 (the plan is clipped to the box)
    assert np.min(r.Y) >= 0.0


def test_twelve_thruster_table_with_truth_miss():
    lay = cube_layout(0.5)
    t = failure_table(problem(), lay)
    assert len(t.rows) == 13  # nominal + 12 single losses
    for r in t.rows:
        # a canted cube keeps every axis after any single loss
        assert (r.rank, r.sign_ok, r.status) == (6, True, "solved")
        assert r.fuel >= t.rows[0].fuel * (1 - 1e-7)
        # flown open loop on J2 + drag over 2400 s from 140 m: the CW plan misses by metres, not km
        assert np.isfinite(r.miss) and r.miss < 50.0
    # the rows solved only with the tie-broken weights (failures.TIE_BREAK) against Clarabel on the exact
    # LP: the plan's fuel lies within its optimality_bound (+ 1e-6 for Clarabel's tolerance) above the optimum
    pb = problem()
    Ad, Bd = cw_discretize(pb.n, pb.mass, pb.dt, "zoh")
    for r in t.rows:
        if r.optimality_bound == 0.0:
            continue
        surv = lay.without([lay.names.index(n) for n in r.failed])
        T = cp.Variable((pb.horizon, surv.size))
        xs = np.asarray(pb.x0)
        for k in range(pb.horizon):
            xs = Ad @ xs + (Bd @ surv.allocation()) @ T[k]
        prob = cp.Problem(cp.Minimize(cp.sum(T) * pb.dt), [T >= 0, T <= surv.max_thrust[None, :], xs == 0])
        prob.solve(solver=cp.CLARABEL)
        assert prob.value * (1 - 1e-6) <= r.fuel <= prob.value * (1 + r.optimality_bound + 1e-6)
    md = t.markdown()
    assert md.count("\n") == 14 and "| +xa |" in md


def test_pairs_and_explicit_failures():
    lay = axis_layout(1.0)
    t = failure_table(problem(), lay, pairs=True, fly_truth=False)
    assert len(t.rows) == 1 + 6 + 15
    pair = {r.failed: r for r in t.rows}[("+z", "-z")]
    assert pair.rank == 4 and pair.distance <= 1e-12
    t2 = failure_table(problem(), lay, failures=[[0, 1]], fly_truth=False)
    assert [r.failed for r in t2.rows] == [(), ("+x", "-x")]
    # losing the along-track pair: radial + normal thrust reach rank 5 (docs/analysis.md's CW table:
    # {radial, normal} -> 5; the along-track drift is lost), distance 0 to round-off
    assert t2.rows[1].rank == 5 and t2.rows[1].distance <= 1e-12 and t2.rows[1].status == "not_run"


def test_bad_arguments():
    lay = axis_layout()
    with pytest.raises(ValueError) as e:
        failure_table(problem(), lay, failures=[[9]])
    assert str(e.value) == "failures[0]: failed[0]: must be a thruster index in [0, 6), got 9"
    with pytest.raises(TypeError) as e:
        failure_table(problem(), "layout")
    assert str(e.value) == "layout: must be a ThrusterLayout, got str"
    with pytest.raises(TypeError) as e:
        failure_table(problem(), lay, failures="01")
    assert str(e.value) == "failures: must be a list of lists of thruster indices, got str"


def test_rows_agree_with_the_analysis_loss_table():
    # the analysis room's own loss table on the same (A, B D): every single and pair loss of six axis
    # thrusters has the same rank and verdict as the failure table's row (the same staircase test)
    lay = axis_layout(1.0)
    A1, B1 = cw_matrices(1.0, 1.0)
    ref = {tuple(r.channels): r for r in analysis.loss_table(A1, B1 @ lay.allocation())}
    t = failure_table(problem(), lay, pairs=True, fly_truth=False)
    assert len(t.rows) == 22
    for r in t.rows:
        kept = tuple(i for i, n in enumerate(lay.names) if n not in r.failed)
        assert (r.rank, r.verdict) == (ref[kept].rank, ref[kept].verdict)
