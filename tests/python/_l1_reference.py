"""The independent cvxpy + Clarabel reference of the small L1 tests (test_l1_ipm.py, test_l1_one_sided.py).

min sum |U_kj| (+ 0.5 x_N' (10 I) x_N without a terminal equality) subject to x_0 = x0,
x_{k+1} = Ad x_k + Bd u_k and the bounds that ``bounds(U)`` returns; Clarabel at 1e-10 gap and
feasibility tolerances. Returns the optimal value (the plan's fuel in the units of U).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import cvxpy as cp
import numpy as np


def clarabel_l1_value(Ad: Any, Bd: Any, x0: Any, horizon: int, bounds: Callable[[Any], list],
                      terminal_equality: bool) -> float:
    nu = Bd.shape[1]
    U = cp.Variable((horizon, nu))
    X = cp.Variable((horizon + 1, 6))
    cons = [X[0] == x0] + [X[k + 1] == Ad @ X[k] + Bd @ U[k] for k in range(horizon)] + bounds(U)
    obj = cp.sum(cp.abs(U))
    if terminal_equality:
        cons.append(X[horizon] == 0)
    else:
        obj = obj + 0.5 * cp.quad_form(X[horizon], 10.0 * np.eye(6))
    p = cp.Problem(cp.Minimize(obj), cons)
    p.solve(solver=cp.CLARABEL, tol_gap_abs=1e-10, tol_gap_rel=1e-10, tol_feas=1e-10)
    return float(p.value)
