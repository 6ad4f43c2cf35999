"""Fuel-optimal linear CW plan under state constraints (issue 16 item 1; scenario sections
``[approach_cone]``, ``[state_box]``, ``[closing_velocity]``, ``[[half_spaces]]``).

The problem of :mod:`satgnc.guidance.min_time` (zero-order hold, interval ``problem.dt``, thrusts of a
:class:`ThrusterLayout` or the per-axis box ``problem.u_max``, L1 weights dt: the objective is the total
impulse, N s; hard terminal state x_N = ``xf``) plus the state constraints of :class:`L1Solver`
(``StateConstrainedAdmm``). Units: m, m/s, N, s, CW frame. :func:`constraint_violation` re-checks the
plan's nodes in numpy, independently of the engine's own violation figure.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from .._results import Result
from .._validate import as_real_array
from . import L1Solver
from .min_time import _controls
from .problem import RendezvousProblem
from .thrusters import ThrusterLayout

__all__ = ["ConstrainedPlan", "constrained_plan", "constraint_violation"]

_KEYS = ("half_spaces", "state_lower", "state_upper", "state_box_nodes", "approach_cone", "closing_velocity")


def constraint_violation(X: Any, constraints: dict) -> dict:
    """Largest violation (m or m/s; 0 when satisfied) of each state-constraint family by the CW states
    ``X`` (N+1, 6) at its nodes, computed here in numpy from the keyword arguments of
    :class:`L1Solver` (``constraints``): ``{"half_spaces", "state_box", "approach_cone",
    "closing_velocity"}`` (families absent from ``constraints`` are left out). The cone's figure is
    ||p_perp|| - tan(angle) (a.p - apex_offset) (m), the closing velocity's |a.v| - min_i(c_i + s_i a.p)."""
    X = as_real_array(X, "X", shape=(None, 6))
    out: dict = {}
    hs = constraints.get("half_spaces")
    if hs is not None:
        a, b = np.atleast_2d(hs["a"]), np.atleast_1d(hs["b"])
        out["half_spaces"] = max(0.0, float(np.max(np.einsum("ij,ij->i", a, X[list(hs["nodes"])]) - b)))
    if constraints.get("state_lower") is not None or constraints.get("state_upper") is not None:
        nodes = constraints.get("state_box_nodes") or list(range(1, X.shape[0]))
        lo = np.broadcast_to(constraints.get("state_lower", -np.inf), (6,))
        hi = np.broadcast_to(constraints.get("state_upper", np.inf), (6,))
        Xn = X[list(nodes)]
        out["state_box"] = max(0.0, float(np.max(np.maximum(lo - Xn, Xn - hi))))
    cone = constraints.get("approach_cone")
    if cone is not None:
        ax = np.asarray(cone["axis"], float) / np.linalg.norm(cone["axis"])
        P = X[list(cone["nodes"]), :3]
        along = P @ ax
        perp = np.linalg.norm(P - np.outer(along, ax), axis=1)
        t = np.tan(np.deg2rad(cone["half_angle_deg"]))
        out["approach_cone"] = max(0.0, float(np.max(perp - t * (along - cone.get("apex_offset", 0.0)))))
    cv = constraints.get("closing_velocity")
    if cv is not None:
        ax = np.asarray(cv["axis"], float) / np.linalg.norm(cv["axis"])
        Xn = X[list(cv["nodes"])]
        rng, vel = Xn[:, :3] @ ax, Xn[:, 3:] @ ax
        lim = np.min(np.asarray(cv["intercept"])[None, :] + np.outer(rng, np.asarray(cv["slope"])), axis=1)
        out["closing_velocity"] = max(0.0, float(np.max(np.abs(vel) - lim)))
    return out


@dataclasses.dataclass(frozen=True)
class ConstrainedPlan(Result):
    """:func:`constrained_plan`'s result. ``status`` (the engine's: ``solved`` only when violation,
    residuals and duality gap hold, see ``state_constraints.hpp``); ``U`` (N, nu) controls (thrusts N,
    or forces N per axis), ``forces`` (N, 3) N, ``X`` (N+1, 6) the plan flown on the linear model (m,
    m/s); ``fuel`` (N s, the true L1 cost of U); ``violation`` {family: m or m/s} re-checked in numpy;
    ``max_violation`` / ``violation_tolerance`` (the engine's, state units); ``duality_gap``;
    ``iterations``; ``solve_time`` (s); ``truth_miss`` (m, |p_N - xf| of the plan flown open loop on the
    truth, NaN when not flown)."""

    status: str
    U: np.ndarray
    forces: np.ndarray
    X: np.ndarray
    fuel: float
    violation: dict
    max_violation: float
    violation_tolerance: float
    duality_gap: float
    iterations: int
    solve_time: float
    truth_miss: float = float("nan")


def constrained_plan(problem: RendezvousProblem, *, xf: Any = None, layout: ThrusterLayout | None = None,
                     settings: Any = None, truth: Any = False, **constraints: Any) -> ConstrainedPlan:
    """The fuel-optimal plan of ``problem`` (x0 -> ``xf``, default the origin, exactly) under the state
    ``constraints`` (keywords of :class:`L1Solver`: ``half_spaces``, ``state_lower``, ``state_upper``,
    ``state_box_nodes``, ``approach_cone``, ``closing_velocity``; m, m/s, CW frame), thrusts of
    ``layout`` or the per-axis box ``problem.u_max`` (N). ``truth``: ``TwoSatelliteParams`` to fly the
    plan open loop and report its miss |p_N - xf| (m); False: not flown."""
    if not isinstance(problem, RendezvousProblem):
        raise TypeError(f"problem: must be a RendezvousProblem, got {type(problem).__name__}")
    for k in constraints:
        if k not in _KEYS:
            raise TypeError(f"constrained_plan: unknown keyword {k!r} (state constraints: "
                            f"{', '.join(_KEYS)})")
    xf = np.zeros(6) if xf is None else as_real_array(xf, "xf", shape=(6,))
    Ad, B, lo, hi = _controls(problem, layout)
    st = {"method": "admm", "eps_gap": 1e-7, "max_iterations": 20000} if settings is None else settings
    r = L1Solver(Ad, B, np.asarray(problem.x0, float), horizon=problem.horizon, xf=xf,
                 l1_weights=np.full(B.shape[1], problem.dt), u_lower=lo, u_upper=hi, terminal_equality=True,
                 settings=st, **constraints).solve()
    U = np.asarray(r.Y)
    if layout is not None:  # the solver's bound is -1e-12 max_thrust (thrusters.LOWER_RELAXATION)
        U = np.clip(U, 0.0, None)
    forces = U @ layout.directions if layout is not None else U.copy()
    X = np.empty((problem.horizon + 1, 6))
    X[0] = problem.x0
    for k in range(problem.horizon):
        X[k + 1] = Ad @ X[k] + B @ U[k]
    miss = float("nan")
    if truth is not False:
        from .flight import fly
        from .safety import cw_positions

        end = cw_positions(np.asarray(fly(truth, problem.state_eci(), forces, problem.dt).X)[-1:])[0]
        miss = float(np.linalg.norm(end - xf[:3]))
    return ConstrainedPlan(r.status, U, forces, X, float(np.sum(np.abs(U)) * problem.dt),
                           constraint_violation(X, constraints), float(r.max_violation),
                           float(r.violation_tolerance), float(r.duality_gap), int(r.iterations),
                           float(r.solve_time), miss)
