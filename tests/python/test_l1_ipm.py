"""The interior-point method alone (AdmmSettings.method = "ipm") on the L1 + box problem (issue 11).

Found last session: pure IPM stopped after ~17-26 iterations without a certificate on two-sided 3-axis boxes
with a hard terminal state, whatever ipm_max_iterations was (ipm_tolerance 1e-5 solved them). Cause: on
these degenerate LPs complementarity falls to ~1e-13 |P| while the terminal sensitivity dx_N/dnu loses rank;
the last steps wreck the terminal error (3e-6 -> 2-13 m) and the factorization fails. The run now certifies
its best iterate (checkpoint) through the same independent gap / terminal test. Reference: cvxpy + Clarabel.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest
from _l1_reference import clarabel_l1_value
from satgnc.guidance import L1Solver, cw_discretize
from test_l1_random import clarabel, draw

N = 40
UMAX = 0.5


def _box_case(seed):
    rng = np.random.default_rng(seed)
    n = rng.uniform(0.0008, 0.0012)
    Ad, Bd = cw_discretize(n, 10.0, 30.0)
    x0 = np.concatenate([rng.uniform(-100.0, 100.0, 3), rng.uniform(-0.1, 0.1, 3)])
    return Ad, Bd, x0


def _clarabel_box(Ad, Bd, x0, terminal_equality):
    return clarabel_l1_value(Ad, Bd, x0, N, lambda U: [cp.abs(U) <= UMAX], terminal_equality)


@pytest.mark.parametrize("max_it", [60, 200])
@pytest.mark.parametrize("terminal_equality", [True, False])
@pytest.mark.parametrize("seed", range(6))
def test_pure_ipm_two_sided_box(seed, terminal_equality, max_it):
    Ad, Bd, x0 = _box_case(seed)
    kw = dict(horizon=N, l1_weights=np.ones(3), u_lower=np.full(3, -UMAX), u_upper=np.full(3, UMAX))
    if terminal_equality:
        kw["terminal_equality"] = True
    else:
        kw["Qf"] = 10.0 * np.eye(6)
    r = L1Solver(Ad, Bd, x0, **kw, settings={"method": "ipm", "ipm_max_iterations": max_it}).solve()
    ref = _clarabel_box(Ad, Bd, x0, terminal_equality)
    # before the fix: max_iterations after 17-26 IPM iterations on 5 of the 6 hard-terminal cases
    assert r.info.status == "solved", (r.info.status, r.info.ipm_iterations, r.info.duality_gap)
    assert r.info.ipm_solved and r.info.ipm_iterations <= 40
    assert abs(r.info.duality_gap) <= 1e-5  # default eps_gap
    # Clarabel at 1e-10; default eps_gap 1e-5 bounds the relative gap: the objective within 1e-5
    assert abs(r.info.objective - ref) <= 1e-5 * abs(ref), (r.info.objective, ref)
    assert float(np.max(np.abs(r.Y))) <= UMAX * (1 + 1e-12)


def _random_box_cases(count=16, seed=23):
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        case = draw(rng)
        if "u_lower" in case.kw:
            out.append(case)
    return out


@pytest.mark.parametrize("i", range(16))
def test_pure_ipm_random_box_problems_vs_clarabel(i):
    """Seeded box-bounded problems of the random suite's mix (a quarter with a hard terminal state)."""
    case = _random_box_cases()[i]
    r = L1Solver(**case.kw, settings={"method": "ipm"}).solve()
    ref, st = clarabel(case.kw)
    if st != "optimal":
        # the IPM alone has no infeasibility test: never "solved" on a problem Clarabel calls infeasible
        assert r.info.status != "solved", (st, r.info.status)
        return
    assert r.info.status == "solved", (r.info.status, r.info.ipm_iterations, r.info.duality_gap)
    assert abs(r.info.duality_gap) <= 1e-5
    # the suite's 1e-4 relative optimality check (default eps_gap 1e-5 plus Clarabel's reference error)
    assert r.info.objective - ref[0] <= 1e-4 * max(abs(ref[0]), 1e-300), (r.info.objective, ref[0])
