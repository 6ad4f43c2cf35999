"""Independent exact solutions of the linear L1 guidance problems with cvxpy + Clarabel (tests, bench).

Same arguments and conventions as :class:`satgnc.guidance.L1Solver` (time-major arrays)."""

from __future__ import annotations

import numpy as np


def solve_cvxpy(A, B, x0, *, horizon=None, c=None, xf=None, Qf=None, Q=None, R=None, l1_weights=None,
                group_l2_weight=0.0, u_lower=None, u_upper=None, u_norm_max=0.0, terminal_equality=False,
                tol=1e-10, settings=None):
    """Return (objective, X (N+1, nx), U (N, nu), solve_time) from Clarabel (interior point)."""
    import cvxpy as cp

    A = np.asarray(A, float)
    B = np.asarray(B, float)
    N = horizon if horizon is not None else (A.shape[0] if A.ndim == 3 else B.shape[0])
    nx = A.shape[-1]
    nu = B.shape[-1]
    X = cp.Variable((N + 1, nx))
    U = cp.Variable((N, nu))
    xf = np.zeros(nx) if xf is None else np.asarray(xf, float)
    cons = [X[0] == np.asarray(x0, float)]
    for k in range(N):
        Ak = A[k] if A.ndim == 3 else A
        Bk = B[k] if B.ndim == 3 else B
        ck = 0.0 if c is None else (np.asarray(c)[k] if np.ndim(c) == 2 else np.asarray(c))
        cons.append(X[k + 1] == Ak @ X[k] + Bk @ U[k] + ck)
    obj = 0
    if Qf is not None and not terminal_equality:
        obj += 0.5 * cp.quad_form(X[N] - xf, cp.psd_wrap(np.asarray(Qf, float)))
    if Q is not None:
        for k in range(1, N):
            obj += 0.5 * cp.quad_form(X[k] - xf, cp.psd_wrap(np.asarray(Q, float)))
    if R is not None:
        for k in range(N):
            obj += 0.5 * cp.quad_form(U[k], cp.psd_wrap(np.asarray(R, float)))
    if l1_weights is None:
        w = np.ones(nu) if group_l2_weight == 0 else np.zeros(nu)
    else:
        w = np.asarray(l1_weights)
    if np.any(w > 0):
        obj += cp.sum(cp.abs(U) @ w)
    if group_l2_weight > 0:
        obj += group_l2_weight * cp.sum(cp.norm(U, 2, axis=1))
    if u_lower is not None:
        cons.append(U >= np.asarray(u_lower)[None, :])
    if u_upper is not None:
        cons.append(U <= np.asarray(u_upper)[None, :])
    if u_norm_max > 0:
        cons.append(cp.norm(U, 2, axis=1) <= u_norm_max)
    if terminal_equality:
        cons.append(X[N] == xf)
    prob = cp.Problem(cp.Minimize(obj), cons)
    prob.solve(solver=cp.CLARABEL, tol_gap_abs=tol, tol_gap_rel=tol, tol_feas=tol)
    if prob.status not in ("optimal",):
        raise RuntimeError(f"Clarabel: {prob.status}")
    t = prob.solver_stats.solve_time if prob.solver_stats is not None else float("nan")
    return float(prob.value), np.asarray(X.value), np.asarray(U.value), t
