"""Bad input to the nonlinear rendezvous helpers (satgnc.guidance.nonlinear) and the scenario module.

Rows: (callable, kwargs, exception type, message fragment naming the argument). Each row was found
by the issue-11 QA probe: silently accepted (complex truncated, bool read as 0/1, "no" read as
True), or an unclear error (ZeroDivisionError, AttributeError, a message naming "dt" or "x0")."""

from __future__ import annotations

import numpy as np
import pytest
from _bad_input import ARGNAMES, case_ids, check_bad_input
from satgnc.papers import l1_admm_rendezvous as nl
from satgnc.scenarios import l1_rendezvous as l1s

H = 6  # a short horizon keeps every row fast


@pytest.fixture(scope="module")
def case():
    return nl.paper_case(horizon=H)


def _pc(**kw):
    args = dict(horizon=H)
    args.update(kw)
    return nl.paper_case(**args)


U0 = np.zeros((3, H))

CASES = [
    # fuzz pass
    (nl.drift_state, dict(steps=2**70), ValueError, "steps: must be <="),  # blamed "scheme"
    (l1s.linear_problem, dict(sc=l1s.load(), implementation_weights="false"), TypeError,
     "implementation_weights: must be true or false"),  # "false" was True
    (l1s.linear_problem, dict(sc=l1s.load(), case=3), TypeError, "case: must be a case name"),
    (l1s.load, dict(path="no-such-file.toml"), FileNotFoundError, "path: no-such-file.toml does not exist"),
    (_pc, dict(x0_si=nl.drift_state() + 0j), TypeError, "x0_si:"),
    (_pc, dict(x0_si=np.ones(12, dtype=bool)), TypeError, "x0_si:"),
    (_pc, dict(x0_si=np.full(12, np.nan)), ValueError, "x0_si:"),
    (_pc, dict(x0_si=np.ones(6)), ValueError, "x0_si:"),
    (_pc, dict(x0_si=np.r_[0.0, 0, 0, 6.0e6, 0, 0, 0, 0, 0, 0, 7.5e3, 0]), ValueError,  # target inside
     "x0_si: the target starts at or below the Earth's surface"),
    (_pc, dict(x0_si=np.r_[7.0e6, 0, 0, 7.0e6, 0, 0, 0, 0, 0, 0, 7.5e3, 0]), ValueError,  # chaser at r = 0
     "x0_si: the chaser starts at or below the Earth's surface"),
    (_pc, dict(horizon=0), ValueError, "horizon:"),  # ZeroDivisionError
    (_pc, dict(horizon=-3), ValueError, "horizon:"),  # blamed dt
    (_pc, dict(horizon=2.5), TypeError, "horizon:"),
    (_pc, dict(tf=np.nan), ValueError, "tf:"),  # blamed dt
    (_pc, dict(tf=-1.0), ValueError, "tf:"),
    (_pc, dict(substeps=0), ValueError, "substeps:"),
    (_pc, dict(discretization="euler"), ValueError, "discretization:"),
    (_pc, dict(constrained="no"), TypeError, "constrained:"),  # "no" was True
    (_pc, dict(params=3), TypeError, "params:"),
    (_pc, dict(terminal_equality="yes"), TypeError, "terminal_equality:"),
    (_pc, dict(terminal_equality=1), TypeError, "terminal_equality:"),
    # a hard terminal state: iLQR-ADMM has none (setup error naming SCP), nor SCP's ilqr_admm inner
    (lambda **kw: nl.solve_paper(_pc(terminal_equality=True), **kw), dict(max_iter=5), ValueError,
     "terminal_equality: not supported by IlqrAdmmSolver"),
    (lambda **kw: nl.solve_scp(_pc(terminal_equality=True), **kw), dict(inner="ilqr_admm"), ValueError,
     "terminal_equality: needs ScpSettings::inner_solver = linear_admm"),
    (lambda **kw: nl.model_params(**kw), dict(j2="x"), TypeError, "j2:"),  # "x" was True
    (lambda **kw: nl.model_params(**kw), dict(drag="off"), TypeError, "drag:"),
    (lambda **kw: nl.model_params(**kw), dict(rho0=-1.0), ValueError, "rho0:"),
    (lambda **kw: nl.miss(**kw), dict(X=np.zeros((12, 3)) + 0j), TypeError, "X:"),  # gave (0, 0)
    (lambda **kw: nl.miss(**kw), dict(X=np.zeros(12)), ValueError, "X:"),  # IndexError
    (lambda **kw: nl.solve_scp(**kw), dict(case=None), TypeError, "case:"),  # AttributeError
    (lambda **kw: nl.solve_paper(**kw), dict(case=None), TypeError, "case:"),
    (lambda **kw: l1s.paper_settings(l1s.load(), **kw), dict(case="x"), ValueError, "case:"),  # KeyError
    (lambda **kw: l1s.linear_problem(**kw), dict(sc=None), TypeError, "sc:"),  # AttributeError
    # closed_loop="x" was True
    (lambda **kw: nl.run_cli("unused-out", **kw), dict(closed_loop="x"), TypeError, "closed_loop:"),
]


@pytest.mark.parametrize(ARGNAMES, CASES, ids=case_ids(CASES))
def test_bad_input_names_the_argument(fn, kwargs, exc, fragment):
    check_bad_input(fn, kwargs, exc, fragment)


CASE_ROWS = [
    # fuzz pass: eps errors named the solver field "eps_abs"; huge controls were a bare RuntimeError
    (nl.linear_cw_plan, dict(eps=np.nan), ValueError, "eps: must be finite"),
    (nl.linear_cw_plan, dict(eps=0.0), ValueError, "eps: must be > 0"),
    (nl.fly, dict(U_si=np.full((3, H), 1e300), integrator="rk4"), ValueError, "U_si: controls up to 1e+300"),
    (nl.summarize, dict(U_scaled=np.full((3, H), 1e300)), ValueError, "U_scaled: controls up to 1e+300"),
    (nl.fly, dict(U_si=U0 + 0j), TypeError, "U_si:"),  # truncated to real
    (nl.fly, dict(U_si=U0.astype(bool)), TypeError, "U_si:"),  # read as 0/1 N
    (nl.fly, dict(U_si=np.full((3, H), np.nan)), ValueError, "U_si:"),  # RuntimeError from CVODES
    (nl.fly, dict(U_si=np.zeros((H, 3))), ValueError, "U_si:"),  # named "U"
    (nl.fly, dict(U_si=U0, integrator="rk5"), ValueError, "integrator:"),
    (nl.fly, dict(U_si=U0, integrator="rk4", substeps=0), ValueError, "substeps:"),  # ZeroDivisionError
    # a start inside the Earth was a CVODES RuntimeError (and RK4 flew through the planet)
    (nl.fly, dict(U_si=U0, x0_si=np.r_[0.0, 0, 0, 6.0e6, 0, 0, 0, 0, 0, 0, 7.5e3, 0]), ValueError,
     "x0_si: the target starts at or below"),
    (nl.fly, dict(U_si=U0, x0_si=np.r_[0.0, 0, 0, 6.0e6, 0, 0, 0, 0, 0, 0, 7.5e3, 0], integrator="rk4"),
     ValueError, "x0_si: the target starts at or below"),
    (nl.summarize, dict(U_scaled=U0, zero_tol=-1.0), ValueError, "zero_tol:"),
    (nl.summarize, dict(U_scaled=U0 + 0j), TypeError, "U_scaled:"),  # named "u"
    (nl.mpc, dict(substeps=0), ValueError, "substeps:"),
    (nl.mpc, dict(replan_every=1.5), TypeError, "replan_every:"),
]


@pytest.mark.parametrize("fn, kwargs, exc, fragment", CASE_ROWS,
                         ids=[f"{c[0].__name__}-{'-'.join(c[1])}-{i}" for i, c in enumerate(CASE_ROWS)])
def test_bad_input_with_a_case_names_the_argument(case, fn, kwargs, exc, fragment):
    with pytest.raises(exc) as info:
        fn(case, **kwargs)
    assert fragment in str(info.value), str(info.value)


def test_case_interval_follows_its_horizon_and_tf(case):
    # Case.dt was TF / N = 60.6 s for every case: fly and summarize of paper_case(horizon=6) flew
    # 6 intervals of 60.6 s instead of 6000 / 6 = 1000 s.
    assert case.dt == pytest.approx(6000.0 / H, rel=1e-15)
    assert nl.paper_case(horizon=H, tf=1200.0).dt == pytest.approx(200.0, rel=1e-15)
    assert nl.paper_case().dt == pytest.approx(6000.0 / 99, rel=1e-15)  # the paper's case
    # The planning model's free drift matches fly on the same model: both use 100 s intervals (with
    # 60.6 s, fly ended 1700 km away from the planned position).
    c = nl.paper_case(horizon=H, tf=600.0)
    X_plan = c.rollout_si(U0)
    X_fly = nl.fly(c, U0, truth_params=nl.model_params(), integrator="rk4", substeps=20)
    assert X_fly.shape == (12, H + 1)
    assert np.max(np.abs(X_fly[3:6, -1] - X_plan[3:6, -1])) < 1e3  # m; measured 450 m (RK3 vs RK4)


@pytest.mark.parametrize("integrator", ["cvodes", "rk4"])
def test_fly_into_the_earth_reports_impact_and_its_time(integrator):
    # Target and chaser slowed to 30 % of their speed fall towards the Earth (two-body truth, no J2 or
    # drag, no control): the flight stops with status "impact" at the chaser's Kepler impact time.
    import satgnc

    c = nl.paper_case()
    x = c.x0_si.copy()
    x[9:12] *= 0.3
    U = np.zeros((3, c.problem.horizon))
    tp = nl.model_params(published=False, j2=False, drag=False)
    with pytest.raises(satgnc.PropagationError) as info:
        nl.fly(c, U, x0_si=x, truth_params=tp, integrator=integrator, substeps=60)
    err = info.value
    assert err.status == "impact" and "impact" in str(err)
    chaser = np.r_[x[3:6] - x[0:3], x[9:12] - x[6:9]] / 1e3  # km, km/s
    with pytest.raises(satgnc.PropagationError) as ref:
        satgnc.propagate(chaser, [0.0, 6000.0], method="kepler", mu=tp.mu / 1e9,
                         surface_radius=tp.j2_radius / 1e3)
    t_hit = ref.value.t_reached  # measured 484.7028 s
    if integrator == "cvodes":
        assert err.t_reached == pytest.approx(t_hit, abs=1e-5)  # root finding; measured 1.4e-7 s
    else:
        assert t_hit <= err.t_reached <= t_hit + c.dt / 60  # the substep in which it was seen
    k = int(t_hit // c.dt)
    assert err.states.shape == (12, k + 1) and np.all(np.isfinite(err.states))


@pytest.mark.parametrize("integrator", ["cvodes", "rk4"])
def test_mpc_into_the_earth_reports_impact(integrator):
    # The same falling pair under MPC: the truth step's impact was a bare RuntimeError.
    import satgnc

    x = nl.paper_case().x0_si.copy()
    x[9:12] *= 0.3
    c = nl.paper_case(horizon=12, x0_si=x, tf=1200.0)
    tp = nl.model_params(published=False, j2=False, drag=False)
    with pytest.raises(satgnc.PropagationError) as info:
        nl.mpc(c, truth_params=tp, planner_params=tp, integrator=integrator, max_iter=3, first_max_iter=50)
    err = info.value
    assert err.status == "impact" and "impact" in str(err)
    assert 450.0 < err.t_reached < 520.0  # measured 486.09 s (CVODES), 490 s (end of the RK4 substep)
    k = int(err.t_reached // c.dt)
    assert err.states.shape == (12, k + 1) and np.all(np.isfinite(err.states))
