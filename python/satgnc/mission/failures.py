"""Failure-aware replanning: the thruster-loss table of a rendezvous (issue 16 item 3).

For the nominal layout and the loss of every thruster (and, on request, every pair, or the sets
given), one row: the analysis room's controllability verdict of the surviving layout (staircase,
:func:`satgnc.analysis.controllability`) and its distance to uncontrollability
(:func:`satgnc.analysis.distance_to_uncontrollability`), the sign condition that nonnegative thrust
adds, an L1 replan on the survivors (linear CW, zero-order hold, thrusts in [0, max_thrust], hard
terminal state; fuel = total impulse) when the rank test says they still control the state, and the
replan's miss flown open loop on the nonlinear truth (J2 + drag two-satellite model).

Orchestration lives here (``mission`` may import both ``guidance`` and ``analysis``; those two never
import each other).

Units of the controllability numbers: the CW model in its natural units (time 1/n, length L,
force m L n^2), so ``A`` has entries 0, +-1, +-2, 3 and a unit thrust direction gives a column of
``B`` of norm 1: the distance is dimensionless, relative to ``||[A B]||``-sized data of order 1.

Nonnegative thrust: the rank of (A, B) is necessary but not sufficient. Brammer's theorem
(R. F. Brammer, "Controllability in linear autonomous systems with positive controllers", SIAM J.
Control 10 (1972) 339-353): with controls in a cone whose convex hull has an interior (here the
thrusts T >= 0), the system is controllable iff the rank condition holds and no real eigenvector v of
A^T has v' B T <= 0 for every T >= 0. ``sign_condition`` checks the latter: for each real eigenvalue
the left eigenvectors V (n x k) must see V' B positively spanning R^k (NNLS membership of +-e_j in the
cone of the columns). For CW the one real eigenvalue is 0 (the along-track drift): the surviving
thrusters must push both ways along-track.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from .. import _satgnc as _c
from .. import analysis
from .._results import Result
from .._validate import as_bool
from ..guidance import L1Solver, cw_discretize, cw_matrices
from ..guidance.flight import fly
from ..guidance.problem import RendezvousProblem
from ..guidance.thrusters import ThrusterLayout, impulse_bit_violations, thrust_bounds

__all__ = ["FailureRow", "FailureTable", "failure_table", "sign_condition", "nnls", "replan", "TIE_BREAK"]


def nnls(A: np.ndarray, b: np.ndarray, max_iter: int = 0) -> tuple[np.ndarray, float]:
    """Lawson-Hanson non-negative least squares: min ||A x - b||_2 s.t. x >= 0. Returns (x, residual)."""
    A = np.asarray(A, dtype=float)
    b = np.asarray(b, dtype=float)
    m, n = A.shape
    x = np.zeros(n)
    passive = np.zeros(n, dtype=bool)
    w = A.T @ (b - A @ x)
    tol = 10 * np.finfo(float).eps * max(1.0, np.linalg.norm(A, 1)) * max(m, n)
    it, cap = 0, max_iter or 3 * n + 10
    while (~passive).any() and np.max(np.where(passive, -np.inf, w)) > tol and it < cap:
        it += 1
        j = int(np.argmax(np.where(passive, -np.inf, w)))
        passive[j] = True
        while True:
            z = np.zeros(n)
            z[passive] = np.linalg.lstsq(A[:, passive], b, rcond=None)[0]
            if np.all(z[passive] > 0):
                x = z
                break
            neg = passive & (z <= 0)
            alpha = np.min(x[neg] / (x[neg] - z[neg]))
            x = x + alpha * (z - x)
            passive &= x > tol
            x[~passive] = 0.0
        w = A.T @ (b - A @ x)
    return x, float(np.linalg.norm(A @ x - b))


def _positively_spans(W: np.ndarray, rtol: float = 1e-9) -> bool:
    """Whether the columns of W (k x m) positively span R^k: every +-e_j is in their cone."""
    k = W.shape[0]
    if k == 0:
        return True
    scale = max(float(np.abs(W).max()), 1e-300)
    for j in range(k):
        for s in (1.0, -1.0):
            e = np.zeros(k)
            e[j] = s * scale
            if nnls(W, e)[1] > rtol * scale:
                return False
    return True


def sign_condition(A: Any, B: Any, rtol: float = 1e-9) -> bool:
    """Brammer's second condition for controls T >= 0 (module docstring): for every real eigenvalue
    lambda of A, the left eigenvectors V (null space of A' - lambda I, singular values <= rtol ||A||)
    see the columns of V' B positively span R^k."""
    A = np.asarray(A, dtype=float)
    B = np.asarray(B, dtype=float)
    n = A.shape[0]
    na = max(float(np.linalg.norm(A)), 1e-300)
    lam = np.linalg.eigvals(A)
    real = sorted({round(float(v.real) / na, 6) * na for v in lam if abs(v.imag) <= 1e-6 * na})
    for lr in real:
        _, s, Vt = np.linalg.svd(A.T - lr * np.eye(n))
        V = Vt[s <= rtol * na * 1e3].T  # left eigenvectors (a Jordan pair splits at ~sqrt(eps))
        if V.shape[1] and not _positively_spans(V.T @ B, rtol):
            return False
    return True


@dataclasses.dataclass(frozen=True)
class FailureRow(Result):
    """One failure case. ``failed``: names of the lost thrusters (empty: the nominal layout);
    ``survivors``: how many remain; ``rank`` (of 6) and ``verdict`` of the staircase test on the
    surviving (A, B) in CW natural units; ``distance``: distance to uncontrollability (refined,
    dimensionless); ``sign_ok``: Brammer's sign condition for T >= 0; ``controllable``: rank full and
    sign_ok; ``status``: the replan's solver status (``"not_run"`` when the rank test fails);
    ``certified``: status ``solved`` (duality gap <= eps_gap, terminal miss within tolerance);
    ``fuel`` (N s, total impulse), ``delta_v`` (m/s); ``miss`` (m): the replan flown open loop on the
    truth; ``impulse_bit_violations``: firings below their thruster's minimum impulse bit;
    ``thrusts`` (N, m_survivors) N, the plan; ``solve_time`` (s); ``optimality_bound``: the fuel is
    within this relative bound of the optimum (0: the exact LP certified; :data:`TIE_BREAK` (m - 1)
    when the tie-broken replan was needed; NaN without a replan)."""

    failed: tuple[str, ...]
    survivors: int
    rank: int
    verdict: str
    distance: float
    sign_ok: bool
    controllable: bool
    status: str
    certified: bool
    fuel: float
    delta_v: float
    miss: float
    impulse_bit_violations: int
    solve_time: float
    optimality_bound: float = 0.0
    thrusts: np.ndarray | None = dataclasses.field(default=None, repr=False)


@dataclasses.dataclass(frozen=True)
class FailureTable(Result):
    """:func:`failure_table`'s result: ``rows`` (nominal first), the ``layout``, the problem's ``dt``
    (s) and ``mass`` (kg), and ``elapsed`` (s, wall time of the whole table)."""

    rows: tuple[FailureRow, ...]
    layout: ThrusterLayout
    dt: float
    mass: float
    elapsed: float

    def markdown(self) -> str:
        """The table as Markdown: failure, controllable?, margin, fuel, miss."""
        lines = ["| failed | rank | verdict | distance | sign | replan | fuel (N s) | dv (m/s) "
                 "| truth miss (m) |",
                 "|---|---|---|---|---|---|---|---|---|"]
        for r in self.rows:
            name = " + ".join(r.failed) if r.failed else "(none)"
            fuel = "-" if math.isnan(r.fuel) else f"{r.fuel:.4g}"
            dv = "-" if math.isnan(r.delta_v) else f"{r.delta_v:.4g}"
            miss = "-" if math.isnan(r.miss) else f"{r.miss:.3g}"
            lines.append(f"| {name} | {r.rank}/6 | {r.verdict} | {r.distance:.3g} | "
                         f"{'ok' if r.sign_ok else 'one-sided'} | {r.status} | {fuel} | {dv} | {miss} |")
        return "\n".join(lines)


#: Relative tie-break of the thrusters' L1 weights, w_i = dt (1 + TIE_BREAK i), used only when the exact
#: replan ends unsolved: redundant layouts (a canted 12-thruster cube less one thruster) make the LP's
#: optimum non-unique and the ADMM then stalls at max_iterations (gap ~2e-5, measured on the +zb loss of
#: tests/python/test_failure_table.py); with the tie broken it is `solved` in 50 iterations. The plan's
#: true fuel is then within TIE_BREAK (m - 1) (relative) of the optimum (the row's optimality_bound).
TIE_BREAK = 1e-5


#: Default settings of the replans: ADMM with its polish only. On the thruster LPs (nonnegative
#: thrusts, redundant directions) the interior-point endgame (AdmmSettings.method admm_ipm) ran 17-35
#: iterations without a certificate and cost ~25 ms per replan, while the active-set polish certified
#: the optimum in 50-200 ADMM iterations, 1-10 ms (canted 12-thruster cube, measured 2026-12-02).
#: max_iterations 2000: the certified replans took <= 200 iterations; a stalled one (non-unique optimum)
#: is then retried with the tie-broken weights instead of running to 10000.
REPLAN_SETTINGS = {"method": "admm", "eps_gap": 1e-7, "max_iterations": 2000}


def replan(problem: RendezvousProblem, layout: ThrusterLayout, settings: Any = None, tie_break: float = 0.0):
    """L1 replan on ``layout``: linear CW (zero-order hold, ``problem.dt``), controls the thrusts
    (N) in [0, max_thrust] (:func:`satgnc.guidance.thrusters.thrust_bounds`), L1 weights dt (the
    objective is the total impulse, N s), hard terminal
    state x_N = 0. Returns the :class:`satgnc.guidance.L1Result` (Y (N, m) the thrusts)."""
    Ad, Bd = cw_discretize(problem.n, problem.mass, problem.dt, "zoh")
    Bt = layout.input_matrix(Bd)
    st = dict(REPLAN_SETTINGS) if settings is None else settings
    lo, hi = thrust_bounds(layout)
    solver = L1Solver(Ad, Bt, np.asarray(problem.x0), horizon=problem.horizon,
                      l1_weights=problem.dt * (1.0 + tie_break * np.arange(layout.size)),
                      u_lower=lo, u_upper=hi,
                      terminal_equality=True, settings=st)
    return solver.solve()


def _failure_sets(m: int, pairs: bool, failures: Sequence[Sequence[int]] | None) -> list[tuple[int, ...]]:
    if failures is not None:
        if isinstance(failures, (str, bytes)) or not isinstance(failures, Sequence):
            raise TypeError(f"failures: must be a list of lists of thruster indices, got "
                            f"{type(failures).__name__}")
        out = []
        for i, f in enumerate(failures):
            if isinstance(f, (str, bytes)) or not isinstance(f, Sequence):
                raise TypeError(f"failures[{i}]: must be a list of thruster indices, got {type(f).__name__}")
            out.append(tuple(int(j) for j in f))
        return [(), *out]
    sets: list[tuple[int, ...]] = [(), *((i,) for i in range(m))]
    if pairs:
        sets += list(itertools.combinations(range(m), 2))
    return sets


def failure_table(problem: RendezvousProblem, layout: ThrusterLayout, *, pairs: bool = False,
                  failures: Sequence[Sequence[int]] | None = None, truth: Any = None,
                  fly_truth: bool = True, settings: Any = None) -> FailureTable:
    """The thruster-loss table of ``problem`` flown with ``layout`` (module docstring).

    Rows: the nominal layout, then the loss of each thruster, then (``pairs=True``) of each pair; or
    the nominal layout and the index sets in ``failures``.

    Parameters
    ----------
    problem : satgnc.guidance.RendezvousProblem
        The rendezvous (SI: m, m/s, N, kg, s; CW frame).
    layout : satgnc.guidance.thrusters.ThrusterLayout
        Thruster directions (CW frame, unit-free) and max thrust (N).
    pairs : bool, optional
        Also every pair of losses (default False).
    failures : sequence of sequence of int, optional
        Index sets to lose instead of the single (and pair) losses.
    truth : TwoSatelliteParams, optional
        The flight's truth (default: J2 + drag with the problem's mu and mass, co-rotating atmosphere).
    fly_truth : bool, optional
        Fly each replan on the truth (default True; False: miss NaN).
    settings : dict, optional
        The replans' AdmmSettings.

    Returns
    -------
    FailureTable
        One row per layout: rank, verdict, distance to uncontrollability (unit-free, CW natural
        units), sign check, replan status, fuel (N s), delta-v (m/s), truth miss (m).

    Raises
    ------
    ValueError
        An index set naming a thruster that does not exist.
    TypeError
        ``problem``, ``layout`` or ``truth`` of another type.

    Examples
    --------
    >>> from satgnc import guidance, mission
    >>> from satgnc.guidance.thrusters import axis_layout
    >>> pb = guidance.RendezvousProblem(mu=3.986004418e14, radius=6878.137e3, mass=12.0,
    ...                                 x0=[-500.0, 50.0, 10.0, 0.0, 0.0, 0.0], tf=3000.0, horizon=30,
    ...                                 alpha=1.0, Qf=0.0, terminal_equality=True)
    >>> t = mission.failure_table(pb, axis_layout(0.05, skip=["-z"]), fly_truth=False)
    >>> [(r.failed, r.rank) for r in t.rows][:2]
    [((), 6), (('+x',), 6)]
    """
    from ..guidance.problem import satellite_params

    if not isinstance(problem, RendezvousProblem):
        raise TypeError(f"problem: must be a RendezvousProblem, got {type(problem).__name__}")
    if not isinstance(layout, ThrusterLayout):
        raise TypeError(f"layout: must be a ThrusterLayout, got {type(layout).__name__}")
    pairs = as_bool(pairs, "pairs")
    fly_truth = as_bool(fly_truth, "fly_truth")
    sets = _failure_sets(layout.size, pairs, failures)
    for i, f in enumerate(sets[1:]):
        try:
            layout.survivors(list(f))
        except ValueError as e:
            raise ValueError(f"failures[{i}]: {e}") from None
    if truth is None:
        truth = satellite_params(problem.mu, j2=True, drag=True, mass=problem.mass)
    elif not isinstance(truth, _c.TwoSatelliteParams):
        raise TypeError(f"truth: must be TwoSatelliteParams (see satellite_params()), "
                        f"got {type(truth).__name__}")
    A1, B1 = cw_matrices(1.0, 1.0)  # CW natural units (module docstring)
    x0_eci = problem.state_eci() if fly_truth else None
    t_start = time.perf_counter()
    rows = []
    for f in sets:
        surv = layout.without(list(f)) if f else layout
        B = surv.input_matrix(B1)
        st = analysis.controllability(A1, B)
        dist = analysis.distance_to_uncontrollability(A1, B).refined
        sign_ok = sign_condition(A1, B)
        rank_full = st.rank == 6 and st.full
        status, certified, T, ts, nviol = "not_run", False, None, 0.0, 0
        fuel = dv = miss = math.nan
        bound = math.nan
        if rank_full:
            r = replan(problem, surv, settings)
            bound = 0.0
            if r.status != "solved" and surv.size > 1:
                r2 = replan(problem, surv, settings, TIE_BREAK)
                if r2.status == "solved":
                    r, bound = r2, TIE_BREAK * (surv.size - 1)
            status, certified, ts = r.status, r.status == "solved", float(r.solve_time)
            if r.status in ("solved", "solved_inaccurate"):
                T = np.maximum(np.asarray(r.Y), 0.0)  # lower bound 0: clips rounding only
                fuel = float(T.sum() * problem.dt)
                dv = fuel / problem.mass
                nviol = impulse_bit_violations(surv, T, problem.dt)
                if fly_truth:
                    miss = float(fly(truth, x0_eci, surv.forces(T), problem.dt).miss[0])
        rows.append(FailureRow(tuple(layout.names[i] for i in f), surv.size, int(st.rank), st.verdict,
                               float(dist), bool(sign_ok), bool(rank_full and sign_ok), status, certified,
                               fuel, dv, miss, nviol, ts, float(bound), T))
    return FailureTable(tuple(rows), layout, float(problem.dt), float(problem.mass),
                        time.perf_counter() - t_start)


