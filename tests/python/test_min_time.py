"""Minimum time by bisection on N with the infeasibility certificate, and the fuel-time curve
(satgnc.guidance.min_time, issue 16 item 4). Checked against a linear scan, cvxpy + Clarabel and the
waiting argument (fuel never rises with N)."""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest
from satgnc.guidance import RendezvousProblem, cw_discretize
from satgnc.guidance.min_time import (
    check_certificate,
    fuel_time_curve,
    minimum_horizon,
    reach,
    trade_figure,
)
from satgnc.guidance.thrusters import axis_layout

MU, R = 3.986004418e14, 7231.0e3  # the l1 scenario's orbit (its drag density is referenced to 6731 km)


def problem(u_max=0.05, horizon=30, tf=1800.0):
    return RendezvousProblem(mu=MU, radius=R, mass=100.0, x0=np.array([300.0, -80.0, 40.0, 0.1, 0.0, -0.05]),
                             tf=tf, horizon=horizon, alpha=1.0, Qf=0.0, u_max=u_max, terminal_equality=True)


def cvx_fuel(pb, N):
    Ad, Bd = cw_discretize(pb.n, pb.mass, pb.dt, "zoh")
    U = cp.Variable((N, 3))
    x = np.asarray(pb.x0)
    for k in range(N):
        x = Ad @ x + Bd @ U[k]
    prob = cp.Problem(cp.Minimize(cp.sum(cp.abs(U)) * pb.dt), [cp.abs(U) <= pb.u_max, x == 0])
    prob.solve(solver=cp.CLARABEL)
    return prob.status, prob.value


def test_minimum_horizon_matches_a_linear_scan_and_clarabel():
    pb = problem()
    m = minimum_horizon(pb)
    assert m.monotone_at_bracket
    N = m.horizon
    assert 1 < N < pb.horizon
    assert m.transfer_time == pytest.approx(N * pb.dt, rel=1e-15)
    # linear scan of every N up to N_min + 1: unreachable below, reachable from N_min (the bisection's answer)
    scan = [reach(pb, k).status for k in range(1, N + 2)]
    # below the controllability index no plan arrives even unbounded (terminal_unreachable), above it the
    # box stops it (primal_infeasible, Farkas certificate)
    assert set(scan[: N - 1]) <= {"primal_infeasible", "terminal_unreachable"}
    assert scan[N - 2] == "primal_infeasible"
    assert scan[N - 1:] == ["solved", "solved"]
    # Clarabel agrees at the bracket: infeasible at N_min - 1, the same fuel at N_min (1e-6 relative)
    st, _ = cvx_fuel(pb, N - 1)
    assert st == "infeasible"
    st, val = cvx_fuel(pb, N)
    fuel = {p.horizon: p for p in m.points}[N].fuel
    assert st == "optimal" and abs(fuel - val) <= 1e-6 * val


def test_certificate_is_verified_independently():
    pb = problem()
    r = reach(pb, 3)
    assert r.status == "primal_infeasible"
    # the margin recomputed from M = [A^(N-1-k) B] with numpy is positive: no plan in the box arrives
    assert check_certificate(pb, 3, r.infeasibility_certificate) > 0
    # a wrong certificate (the negated one) is not accepted
    assert check_certificate(pb, 3, -np.asarray(r.infeasibility_certificate)) < 0


def test_fuel_time_curve_never_rises_and_is_certified(tmp_path):
    pb = problem()
    m = minimum_horizon(pb)
    c = fuel_time_curve(pb, range(m.horizon - 1, pb.horizon + 1, 2))
    solved = [p for p in c.points if p.status == "solved"]
    assert c.points[0].status == "primal_infeasible" and c.points[0].certified
    assert all(p.certified for p in c.points)
    # waiting at the target costs nothing, so the optimum cannot rise with N (1e-6: the gap tolerance)
    for a, b in zip(solved, solved[1:]):
        assert b.fuel <= a.fuel * (1 + 1e-6)
    # each point is an L1 optimum: compare the longest one with Clarabel (1e-6 relative)
    st, val = cvx_fuel(pb, solved[-1].horizon)
    assert st == "optimal" and abs(solved[-1].fuel - val) <= 1e-6 * val
    assert c.markdown().count("\n") == len(c.points) + 1
    trade_figure(c, tmp_path / "trade.png", m)
    assert (tmp_path / "trade.png").stat().st_size > 10_000


def test_thruster_layout_minimum_time_is_longer_after_a_loss():
    pb = problem()
    lay = axis_layout(0.05)
    full = minimum_horizon(pb, lay)
    lost = minimum_horizon(pb, lay.without([3]), max_horizon=90)  # -y (radial) lost
    assert full.monotone_at_bracket and lost.monotone_at_bracket
    assert 0 < full.horizon <= pb.horizon < lost.horizon <= 90
    # fewer thrusters cannot arrive sooner (a subset of the admissible plans)
    assert lost.horizon >= full.horizon


def test_bad_input():
    pb = problem()
    with pytest.raises(ValueError) as e:
        minimum_horizon(RendezvousProblem(mu=MU, radius=R, mass=100.0, x0=np.ones(6), tf=100.0, horizon=5,
                                          alpha=1.0, Qf=0.0))
    assert str(e.value) == ("problem.u_max: required without a thruster layout (the minimum time of an "
                            "unbounded control is 1 interval)")
    with pytest.raises(ValueError) as e:
        fuel_time_curve(pb, [])
    assert str(e.value) == "horizons: must hold at least one horizon"
    with pytest.raises(TypeError) as e:
        minimum_horizon(pb, layout="axis")
    assert str(e.value) == "layout: must be a ThrusterLayout or None, got str"
    m = minimum_horizon(pb, max_horizon=2)
    assert m.horizon == 0 and not m.monotone_at_bracket
