"""Plume-impingement cone in the keep-out SCP (satgnc.guidance.keep_out, issue 16 item 1, optional):
thrusters whose exhaust would hit the target near it are inhibited; the returned plan is re-checked
on the truth flight's samples."""

from __future__ import annotations

import numpy as np
import pytest
from satgnc.guidance import RendezvousProblem
from satgnc.guidance.keep_out import keep_out_plan, plume_inhibited
from satgnc.guidance.safety import KeepOut
from satgnc.guidance.thrusters import axis_layout, cube_layout

MU, R = 3.986004418e14, 7231.0e3
PLUME = {"half_angle_deg": 45.0, "range": 200.0}


def braking_problem():
    # closing at 0.2 m/s from 150 m on the V-bar to a hold point 40 m out (20 m sphere), 1200 s: braking
    # pushes away from the target, i.e. exhausts toward it
    return RendezvousProblem(mu=MU, radius=R, mass=100.0, x0=np.array([150.0, 0, 0, -0.2, 0, 0]), tf=1200.0,
                             horizon=20, alpha=1.0, Qf=0.0, u_max=0.5, terminal_equality=True)


def test_plume_geometry_by_hand():
    lay = axis_layout(0.5)  # +x, -x, +y, -y, +z, -z
    P = np.array([[100.0, 0, 0], [100.0, 0, 0]])
    hit = plume_inhibited(P, lay.directions, 45.0, 200.0)[0]
    # at +100 m on x the +x thruster's exhaust (-x) points at the target; no other does
    assert hit.tolist() == [True, False, False, False, False, False]
    assert not plume_inhibited(P * 3.0, lay.directions, 45.0, 200.0).any()  # 300 m: beyond the range
    # the half-angle: a chaser 44 deg off the +x axis is inside the 45 deg cone of +x, 46 deg is not
    for ang, inside in ((44.0, True), (46.0, False)):
        p = 100.0 * np.array([np.cos(np.radians(ang)), np.sin(np.radians(ang)), 0.0])
        assert plume_inhibited(np.array([p, p]), lay.directions, 45.0, 200.0)[0, 0] == inside


def test_plume_cone_on_the_cube_layout():
    pb, lay, ko = braking_problem(), cube_layout(0.5), KeepOut.sphere(20.0)
    kw = dict(xf=[40.0, 0, 0, 0, 0, 0], layout=lay)
    free = keep_out_plan(pb, ko, **kw)
    fire = free.U > 1e-9 * 0.5
    # measured 2026-12-03: the plan without the cone fires impinging thrusters 16 times (5 since the
    # state IPM's best-bound certificate: the fuel optimum is degenerate, so which optimal plan is
    # returned, and how many of its firings impinge, follows the solver's path); what matters: it does
    assert np.sum(fire & plume_inhibited(free.X[:, :3], lay.directions, 45.0, 200.0)) >= 1
    r = keep_out_plan(pb, ko, plume=PLUME, **kw)
    assert r.status == "solved" and r.converged
    assert r.plume_violations == 0  # none at the nodes nor at any flown sample between them
    assert r.satisfied_nodes and r.satisfied_flown
    assert r.fuel >= free.fuel  # measured 29.46 -> 56.11 N s
    assert r.plume_inhibited.shape == (20, 12) and r.plume_inhibited.sum() > 0
    ref = keep_out_plan(pb, ko, plume=PLUME, solver="cvxpy", truth=False, **kw)
    assert ref.status == "solved" and ref.iterations == r.iterations
    assert abs(r.fuel - ref.fuel) <= 1e-5 * ref.fuel
    assert np.array_equal(ref.plume_inhibited, r.plume_inhibited)


def test_plume_cone_infeasible_on_the_axis_layout_is_reported():
    # with one thruster per axis direction only +x can brake, and it is inhibited: the subproblem is
    # primal infeasible (the engine's checked certificate; Clarabel agrees); the SCP stops unconverged,
    # returns the last plan and counts its impinging firings (measured 6)
    pb, lay, ko = braking_problem(), axis_layout(0.5), KeepOut.sphere(20.0)
    kw = dict(xf=[40.0, 0, 0, 0, 0, 0], layout=lay, plume=PLUME, truth=False)
    r = keep_out_plan(pb, ko, **kw)
    ref = keep_out_plan(pb, ko, solver="cvxpy", **kw)
    assert r.status == ref.status == "primal_infeasible"
    assert not r.converged and not ref.converged
    assert r.plume_violations > 0


@pytest.mark.parametrize("kw, msg", [
    (dict(plume=PLUME, layout=None), "plume: needs a thruster layout"),
    (dict(plume={"half_angle_deg": 45.0}, layout=axis_layout(0.5)), "plume: must be a dict"),
    (dict(plume={"half_angle_deg": 95.0, "range": 10.0}, layout=axis_layout(0.5)), "half_angle_deg"),
    (dict(plume={"half_angle_deg": 45.0, "range": 0.0}, layout=axis_layout(0.5)), "plume.range"),
])
def test_bad_plume_input(kw, msg):
    with pytest.raises(ValueError, match=msg):
        keep_out_plan(braking_problem(), KeepOut.sphere(20.0), xf=[40.0, 0, 0, 0, 0, 0], truth=False, **kw)


def test_seeded_plume_problems_match_clarabel():
    # seeded braking problems (start 120-180 m within +-20 deg closing at 0.1-0.25 m/s, hold point 30-50 m
    # out, 15-25 m sphere, cone 30-60 deg within 100-200 m, cube layout): engine SCP = Clarabel SCP in
    # status, iterations, inhibitions and fuel (1e-5); a solved plan has no impinging firing
    rng = np.random.default_rng(163)
    lay = cube_layout(0.5)
    for _ in range(3):
        ang, r0, v = rng.uniform(-0.35, 0.35), rng.uniform(120, 180), rng.uniform(0.1, 0.25)
        x0 = np.array([r0 * np.cos(ang), r0 * np.sin(ang), 0.0, -v * np.cos(ang), -v * np.sin(ang), 0.0])
        pb = RendezvousProblem(mu=MU, radius=R, mass=100.0, x0=x0, tf=1200.0, horizon=20, alpha=1.0, Qf=0.0,
                               u_max=0.5, terminal_equality=True)
        plume = {"half_angle_deg": float(rng.uniform(30, 60)), "range": float(rng.uniform(100, 200))}
        kw = dict(xf=[float(rng.uniform(30, 50)), 0, 0, 0, 0, 0], layout=lay, plume=plume, truth=False)
        ko = KeepOut.sphere(float(rng.uniform(15, 25)))
        r = keep_out_plan(pb, ko, **kw)
        ref = keep_out_plan(pb, ko, solver="cvxpy", **kw)
        assert r.status == ref.status and r.iterations == ref.iterations
        assert np.array_equal(r.plume_inhibited, ref.plume_inhibited)
        assert abs(r.fuel - ref.fuel) <= 1e-5 * ref.fuel
        if r.status == "solved":
            assert r.converged and r.plume_violations == 0


def test_plume_cone_with_passive_safety():
    # both options in one SCP (slack state + time-varying B): solved, no impinging firing, every drift
    # safe on the truth (measured smallest radius 1.026, fuel 57.875 N s). The Clarabel SCP converged one
    # iteration earlier here (4 vs 5: the inhibition and nearest-row selections follow the iterates), so
    # the fuel is compared at 1e-4 (measured 1.3e-5)
    pb, lay, ko = braking_problem(), cube_layout(0.5), KeepOut.sphere(20.0)
    kw = dict(xf=[40.0, 0, 0, 0, 0, 0], layout=lay, plume=PLUME, drift_time=1200.0)
    r = keep_out_plan(pb, ko, **kw)
    # Was a known defect (issue 16, 2026-12-03): the 5th subproblem (elastic drift rows + trust region)
    # stalled in the state IPM (60 steps, gap 1.2e-3) and in ADMM, and the SCP stopped "max_iterations"
    # (fuel 57.8758). Since session 9 the IPM's dual regularization certifies it: "solved" after 6 SCP
    # iterations, fuel 57.875037 (main at 8828dc5 without it: 4 iterations, 57.875034).
    assert r.status == "solved", r.status
    assert r.converged == (r.status == "solved")
    assert r.plume_violations == 0
    assert r.passive.all_safe and r.drift_slack <= 1e-6 and r.satisfied_flown
    ref = keep_out_plan(pb, ko, solver="cvxpy", truth=False, **kw)
    assert ref.status == "solved" and ref.converged and ref.plume_violations == 0
    assert abs(r.fuel - ref.fuel) <= 1e-4 * ref.fuel
