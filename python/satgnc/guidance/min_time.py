"""Minimum time and the fuel-time trade of a linear rendezvous (issue 16 item 4).

The model: CW (zero-order hold) with a fixed control interval ``dt`` (s) = ``problem.dt``; the horizon
is N intervals (transfer time N dt). Controls: the thrusts of a :class:`ThrusterLayout` (N, in
[0, max_thrust]) or, without a layout, the force per axis in [-u_max, u_max] (``problem.u_max``, N).
Each problem is the certified L1 optimum with the hard terminal state x_N = 0 (L1 weights dt: the
objective is the total impulse, N s); ``solved`` needs the duality gap and terminal tests of the
ADMM, ``primal_infeasible`` comes with a Farkas certificate y (``y' (x_f - x_N(0)) > max over the box
of y' M U``), re-checked here independently from M = [A^(N-1-k) B]_k.

Monotonicity assumption (what makes bisection on N valid): the target x_f = 0 is an equilibrium of
CW and zero thrust is admissible, so a plan that arrives at N steps can wait at the target: reachable
at N implies reachable at N + 1. :func:`minimum_horizon` checks it at the bracket (N_min - 1 certified
unreachable, N_min and N_min + 1 solved).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from .._results import Result
from .._validate import as_int
from . import L1Solver, cw_discretize
from .problem import RendezvousProblem
from .thrusters import ThrusterLayout, thrust_bounds

__all__ = ["TradePoint", "MinimumHorizon", "FuelTimeCurve", "minimum_horizon", "fuel_time_curve",
           "reach", "check_certificate", "trade_figure"]


def _controls(problem: RendezvousProblem, layout: ThrusterLayout | None) -> tuple[np.ndarray, np.ndarray,
                                                                                   np.ndarray, np.ndarray]:
    """(Ad, B, lower, upper) of the linear model with the layout's thrusts or the per-axis box."""
    Ad, Bd = cw_discretize(problem.n, problem.mass, problem.dt, "zoh")
    if layout is not None:
        if not isinstance(layout, ThrusterLayout):
            raise TypeError(f"layout: must be a ThrusterLayout or None, got {type(layout).__name__}")
        lo, hi = thrust_bounds(layout)  # [0, max_thrust]
        return Ad, layout.input_matrix(Bd), lo, hi
    if problem.u_max is None:
        raise ValueError("problem.u_max: required without a thruster layout (the minimum time of an "
                         "unbounded control is 1 interval)")
    return Ad, Bd, -problem.u_max * np.ones(3), problem.u_max * np.ones(3)


def reach(problem: RendezvousProblem, horizon: int, layout: ThrusterLayout | None = None,
          settings: Any = None):
    """The certified L1 problem of ``problem`` at ``horizon`` intervals of ``problem.dt``: returns the
    :class:`satgnc.guidance.L1Result` (``status`` ``solved`` or ``primal_infeasible``, or a limit)."""
    horizon = as_int(horizon, "horizon", low=1, high=10**6)
    Ad, B, lo, hi = _controls(problem, layout)
    # ADMM + polish only: the interior-point endgame certifies nothing on the nonnegative-thrust LPs
    # (mission.failures.REPLAN_SETTINGS says what was measured)
    default = {"method": "admm", "eps_gap": 1e-7, "infeasibility_check_interval": 5}
    st = default if settings is None else settings
    return L1Solver(Ad, B, np.asarray(problem.x0), horizon=horizon,
                    l1_weights=np.full(B.shape[1], problem.dt),
                    u_lower=lo, u_upper=hi, terminal_equality=True, settings=st).solve()


def check_certificate(problem: RendezvousProblem, horizon: int, y: Any, layout: ThrusterLayout | None = None
                      ) -> float:
    """Independent check of a Farkas certificate ``y`` (6,): returns the margin
    ``y' (0 - A^N x0) - max over the box of y' M U`` (> 0: no admissible plan reaches the target).
    The box is the solver's, the physical one: thrusts in [0, max_thrust] (``thrust_bounds``)."""
    Ad, B, lo, hi = _controls(problem, layout)
    y = np.asarray(y, dtype=float)
    x = np.asarray(problem.x0, dtype=float)
    w = y.copy()  # w' = y' A^(N-1-k), walked backwards
    best = 0.0
    for _ in range(horizon):
        g = w @ B
        best += float(np.sum(np.maximum(g * lo, g * hi)))
        w = w @ Ad
    xN0 = np.linalg.matrix_power(Ad, horizon) @ x
    return float(y @ (-xN0) - best)


def _range_residual(problem: RendezvousProblem, horizon: int, layout: ThrusterLayout | None) -> float:
    """||(I - M M^+) A^N x0|| / ||A^N x0||: 0 when some unbounded plan arrives at N."""
    Ad, B, _, _ = _controls(problem, layout)
    cols, P = [], np.eye(Ad.shape[0])
    for _ in range(horizon):
        cols.append(P @ B)
        P = P @ Ad
    M = np.hstack(cols)
    b = -(P @ np.asarray(problem.x0, dtype=float))
    u = np.linalg.lstsq(M, b, rcond=None)[0]
    return float(np.linalg.norm(M @ u - b) / max(np.linalg.norm(b), 1e-300))


@dataclasses.dataclass(frozen=True)
class TradePoint(Result):
    """One horizon: ``horizon`` N, ``transfer_time`` (s), ``status``, ``certified`` (solved; or
    primal_infeasible with an independently verified Farkas certificate; or terminal_unreachable, N
    shorter than the controllability index, verified by the least-squares residual), ``fuel`` (N s;
    NaN when unreachable), ``delta_v`` (m/s), ``duality_gap`` and ``certificate_margin`` (> 0 when
    unreachable: the Farkas margin, or the relative range residual; NaN otherwise)."""

    horizon: int
    transfer_time: float
    status: str
    certified: bool
    fuel: float
    delta_v: float
    duality_gap: float
    certificate_margin: float


def _point(problem: RendezvousProblem, N: int, layout: ThrusterLayout | None, settings: Any) -> TradePoint:
    r = reach(problem, N, layout, settings)
    fuel, margin = math.nan, math.nan
    certified = False
    if r.status == "solved":
        fuel = float(np.sum(np.abs(r.Y)) * problem.dt)
        certified = True
    elif r.status == "primal_infeasible" and r.infeasibility_certificate is not None:
        margin = check_certificate(problem, N, r.infeasibility_certificate, layout)
        certified = margin > 0
    elif r.status == "terminal_unreachable":
        # x_f - A^N x0 outside the range of M = [A^(N-1-k) B] even without bounds (N too short for the
        # controllability index): certified by the least-squares residual, relative to ||A^N x0||
        margin = _range_residual(problem, N, layout)
        certified = margin > 1e-9
    return TradePoint(N, N * problem.dt, r.status, certified, fuel, fuel / problem.mass,
                      float(r.duality_gap), margin)


@dataclasses.dataclass(frozen=True)
class MinimumHorizon(Result):
    """:func:`minimum_horizon`'s result: ``horizon`` N_min (0 when not reachable within ``max_horizon``),
    ``transfer_time`` (s), ``dt`` (s), ``points`` (every horizon solved, in order of solution),
    ``monotone_at_bracket`` (N_min - 1 certified unreachable, N_min and N_min + 1 solved)."""

    horizon: int
    transfer_time: float
    dt: float
    points: tuple[TradePoint, ...]
    monotone_at_bracket: bool


def minimum_horizon(problem: RendezvousProblem, layout: ThrusterLayout | None = None, *,
                    max_horizon: int | None = None, settings: Any = None) -> MinimumHorizon:
    """Shortest N (intervals of ``problem.dt``) at which the target is reachable, by bisection on N
    between a certified-unreachable and a solved horizon (module docstring). ``max_horizon`` (default
    ``problem.horizon``) must be reachable, else ``horizon`` is 0. A solve that ends neither solved
    nor certified infeasible stops the search with a RuntimeError naming the horizon."""
    if not isinstance(problem, RendezvousProblem):
        raise TypeError(f"problem: must be a RendezvousProblem, got {type(problem).__name__}")
    hi = problem.horizon if max_horizon is None else as_int(max_horizon, "max_horizon", low=1, high=10**6)
    pts: list[TradePoint] = []

    def feasible(N: int) -> bool:
        p = _point(problem, N, layout, settings)
        pts.append(p)
        if not p.certified:
            raise RuntimeError(f"horizon: the solve at N = {N} ended {p.status!r}, neither solved nor "
                               "certified infeasible (hint: raise settings max_iterations)")
        return p.status == "solved"

    if not feasible(hi):
        return MinimumHorizon(0, math.nan, problem.dt, tuple(pts), False)
    lo = 0  # N = 0: x0 != 0 is not the target
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if feasible(mid):
            hi = mid
        else:
            lo = mid
    done = {p.horizon: p for p in pts}
    after = done.get(hi + 1) or _point(problem, hi + 1, layout, settings)
    if hi + 1 not in done:
        pts.append(after)
    before_ok = lo == 0 or (done[lo].status != "solved" and done[lo].certified)
    mono = before_ok and done[hi].status == "solved" and after.status == "solved"
    return MinimumHorizon(hi, hi * problem.dt, problem.dt, tuple(pts), bool(mono))


@dataclasses.dataclass(frozen=True)
class FuelTimeCurve(Result):
    """:func:`fuel_time_curve`'s result: ``points`` (one :class:`TradePoint` per horizon, ascending)."""

    points: tuple[TradePoint, ...]
    dt: float

    def markdown(self) -> str:
        rows = ["| N | transfer time (s) | status | fuel (N s) | dv (m/s) | duality gap |",
                "|---|---|---|---|---|---|"]
        for p in self.points:
            fuel = "-" if math.isnan(p.fuel) else f"{p.fuel:.6g}"
            dv = "-" if math.isnan(p.delta_v) else f"{p.delta_v:.6g}"
            rows.append(f"| {p.horizon} | {p.transfer_time:.1f} | {p.status} | {fuel} | {dv} | "
                        f"{p.duality_gap:.2g} |")
        return "\n".join(rows)


def fuel_time_curve(problem: RendezvousProblem, horizons: Any, layout: ThrusterLayout | None = None, *,
                    settings: Any = None) -> FuelTimeCurve:
    """The certified L1 optimum at each horizon N of ``horizons`` (intervals of ``problem.dt``)."""
    if not isinstance(problem, RendezvousProblem):
        raise TypeError(f"problem: must be a RendezvousProblem, got {type(problem).__name__}")
    Ns = sorted({as_int(N, "horizons[]", low=1, high=10**6) for N in horizons})
    if not Ns:
        raise ValueError("horizons: must hold at least one horizon")
    return FuelTimeCurve(tuple(_point(problem, N, layout, settings) for N in Ns), problem.dt)


def trade_figure(curve: FuelTimeCurve, path: Any, minimum: MinimumHorizon | None = None,
                 title: str = "Fuel versus transfer time (certified L1 optima)") -> None:
    """Delta-v (m/s) against the transfer time (s); unreachable horizons marked; PNG at ``path``."""
    from .._plot import _pyplot

    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ok = [p for p in curve.points if p.status == "solved"]
    bad = [p for p in curve.points if p.status != "solved"]
    ax.plot([p.transfer_time for p in ok], [p.delta_v for p in ok], "o-", ms=4, label="certified L1 optimum")
    if bad:
        y0 = min((p.delta_v for p in ok), default=1.0)
        ax.plot([p.transfer_time for p in bad], [y0] * len(bad), "x", color="C3",
                label="certified unreachable")
    if minimum is not None and minimum.horizon:
        ax.axvline(minimum.transfer_time, color="C3", ls="--", lw=1,
                   label=f"minimum time {minimum.transfer_time:.0f} s (N = {minimum.horizon})")
    ax.set_xlabel("transfer time, s")
    ax.set_ylabel("delta-v, m/s")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
