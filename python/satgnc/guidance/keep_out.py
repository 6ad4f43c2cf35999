"""Keep-out ellipsoid in sequential convex programming (issue 16 item 1, the nonconvex constraint).

Problem: the linear CW rendezvous of :mod:`satgnc.guidance.min_time` (zero-order hold, interval
``problem.dt``, thrusts of a :class:`ThrusterLayout` or the per-axis box ``problem.u_max``), fuel-optimal
(L1, weights dt: the objective is the total impulse, N s), hard terminal state x_N = ``xf`` (a hold
point outside the zone), and p_k outside the keep-out ellipsoid at the constrained nodes.

Convexification: at iteration j each constrained node's previous position p is scaled radially onto
the (inflated) ellipsoid's surface, q = c + (p - c) / rho(p), and replaced by the supporting half-space
n' (p_k - q) >= 0 with n = (q - c) / a^2 the surface normal there. The half-space lies entirely outside
the ellipsoid (tangent plane of a convex set), so every subproblem plan keeps the nodes out of the zone
exactly; and the previous plan satisfies the new half-spaces (n' (p - q) = rho(p) - 1 >= 0 for p
outside), so from the first feasible iterate on the fuel never rises. A trust region |p_k - p_k^j|_inf
<= ``trust_radius`` (m) on the positions bounds each step. Iterations stop when the positions move
less than ``tol`` (m) or the fuel changes by less than 1e-9 relative.

Between nodes the trajectory is not constrained: the zone is inflated by ``margin`` (relative) for the
planning, and :func:`keep_out_plan` reports the true ellipsoidal radius at every node and between nodes
on the continuous trajectory flown open loop on the truth (J2 + drag two-satellite model, sampled
``per_interval`` times per interval).

Subproblem solvers: ``"admm"`` (satgnc's L1 ADMM with state half-spaces, built once and kept warm across
iterations; the trust rows are added only when the subproblem's minimizer without them leaves the trust
region, which leaves the iterates unchanged: see :class:`_LazyTrustRegion`) or ``"cvxpy"`` (cvxpy +
Clarabel with the trust region always imposed, the independent reference; needs the optional packages).
"""

from __future__ import annotations

import dataclasses
import math
import time
from typing import Any

import numpy as np

from .._results import Result
from .._validate import as_bool, as_int, as_real, as_real_array, one_of
from . import L1Solver
from .min_time import _controls
from .problem import RendezvousProblem
from .safety import KeepOut, cw_positions, sample_flight
from .thrusters import ThrusterLayout

__all__ = ["KeepOutPlan", "keep_out_plan", "plume_inhibited", "supporting_half_spaces"]


def supporting_half_spaces(P: Any, keep_out: KeepOut, inflate: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Rows (a (k, 3), b (k,)) of the half-spaces a' p <= b supporting the ellipsoid (semi-axes times
    1 + ``inflate``) at the radial projections of the positions ``P`` (k, 3) m (module docstring)."""
    P = as_real_array(P, "P", shape=(None, 3))
    c = keep_out.center
    ax = keep_out.semi_axes * (1.0 + inflate)
    d = P - c
    rho = np.linalg.norm(d / ax, axis=1)
    tiny = rho <= 1e-12
    if np.any(tiny):  # a position at the centre: any direction supports; take +x of the frame
        d[tiny] = np.array([ax[0], 0.0, 0.0])
        rho[tiny] = 1.0
    Q = c + d / rho[:, None]
    n = (Q - c) / ax**2
    return -n, -np.sum(n * Q, axis=1)  # -n'p <= -n'q


def plume_inhibited(P: Any, directions: Any, half_angle_deg: float, plume_range: float) -> np.ndarray:
    """Which thrusters would fire their plume at the target (the CW origin) over each interval: (N, m)
    bool for positions ``P`` (N+1, 3) m and unit thrust ``directions`` (m, 3). Thruster i's exhaust
    leaves along -d_i; it impinges when the chaser is within ``plume_range`` m of the target and the
    exhaust points within ``half_angle_deg`` of the target direction -p, i.e. d_i . p / |p| >=
    cos(half_angle), at either end of the interval."""
    P = np.asarray(P, dtype=float)
    D = np.asarray(directions, dtype=float)
    r = np.linalg.norm(P, axis=1)
    c = (P @ D.T) / np.maximum(r, 1e-12)[:, None]
    hit = (r[:, None] <= plume_range) & (c >= math.cos(math.radians(half_angle_deg)))
    return hit[:-1] | hit[1:]


@dataclasses.dataclass(frozen=True)
class KeepOutPlan(Result):
    """:func:`keep_out_plan`'s result. ``U`` (N, nu): the controls (thrusts N, or forces N per axis);
    ``forces`` (N, 3) N, CW frame; ``X`` (N+1, 6): the CW plan (m, m/s); ``status`` of the last
    subproblem, ``converged`` (positions moved < tol), ``iterations``; ``fuel`` (N s) and
    ``fuel_history`` per iteration (the unconstrained plan first); ``node_rho`` (N+1,): the true
    ellipsoidal radius of the plan's nodes; ``flown_rho_nodes`` / ``flown_rho_min`` : the smallest
    radius at the constrained nodes / anywhere between them on the truth flight (sampled);
    ``satisfied_nodes`` (every constrained node of the plan outside the true zone), ``satisfied_flown``
    (the sampled truth flight never inside over the constrained span); ``solve_time`` (s, the
    subproblems) and ``wall_time`` (s, the whole loop without the truth flight)."""

    U: np.ndarray
    forces: np.ndarray
    X: np.ndarray
    status: str
    converged: bool
    iterations: int
    fuel: float
    fuel_history: np.ndarray
    node_rho: np.ndarray
    flown_rho_nodes: float
    flown_rho_min: float
    satisfied_nodes: bool
    satisfied_flown: bool
    solve_time: float
    wall_time: float
    flown_X: np.ndarray | None = dataclasses.field(default=None, repr=False)
    #: engine subproblems whose minimizer without the trust rows left the trust region, so that they
    #: were solved again with them (``solver="admm"``; the others are exact without them)
    trust_region_binding: int = 0
    #: engine SCP subproblems (the plan without the zone not counted) whose plan the engine's
    #: interior-point method returned, certified by the same violation and Fenchel-gap tests as ADMM's
    #: (the others ran ADMM)
    ipm_subproblems: int = 0
    #: passive safety (``drift_time`` given): the largest depth (m, along the surface normal at its
    #: radial projection) of the returned plan's sampled CW drift points inside the inflated zone, i.e.
    #: the violation of their own supporting planes (at convergence the elastic slack; 0: outside);
    #: NaN without ``drift_time``
    drift_slack: float = math.nan
    #: plume cone (``plume`` given): (N, m) bool, the thrusters inhibited at each interval (the union over
    #: the SCP iterations of those whose plume would hit the target); None without ``plume``
    plume_inhibited: Any = dataclasses.field(default=None, repr=False)
    #: firings (thrust > 1e-9 max_thrust) of a thruster whose plume hits the target by the returned
    #: plan's geometry (the CW nodes; with a truth flight, also every flown sample inside the interval);
    #: 0 when the cone holds; -1 without ``plume``
    plume_violations: int = -1
    #: passive safety of the plan flown on the truth (``drift_time`` given and a truth flight): each
    #: drift node's free drift on the truth (:func:`satgnc.guidance.safety.passive_safety`)
    passive: Any = dataclasses.field(default=None, repr=False)


def _rows(idx: list[int], P: np.ndarray, keep_out: KeepOut, margin: float, tr: float
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Half-space rows of one SCP subproblem: per node the supporting plane, then (``tr`` finite) the
    trust region |p_i - P_i| <= tr as six half-spaces (+-e_i); (nodes, a (rows, 6), b (rows,))."""
    a3, b3 = supporting_half_spaces(P, keep_out, margin)
    per = 7 if math.isfinite(tr) else 1
    n = len(idx)
    A = np.zeros((n, per, 6))
    b = np.empty((n, per))
    A[:, 0, :3], b[:, 0] = a3, b3
    if per == 7:
        for i in range(3):
            for j, s in enumerate((1.0, -1.0)):
                A[:, 1 + 2 * i + j, i] = s
                b[:, 1 + 2 * i + j] = s * P[:, i] + tr
    return np.repeat(np.asarray(idx), per), A.reshape(-1, 6), b.reshape(-1)


def _with_slack(B: np.ndarray) -> np.ndarray:
    """B (6, nu) with the passive-safety slack's input appended: (7, nu + 1)."""
    return np.block([[B, np.zeros((6, 1))], [np.zeros((1, B.shape[1])), np.ones((1, 1))]])


def _terminal(xf: np.ndarray, N: int, nx: int) -> dict:
    """L1Solver keywords of the hard terminal state x_N = xf (6,); with the passive-safety SCP's
    augmented state (nx = 7, the slack last) the six entries are fixed by a state box at node N and the
    slack left free."""
    if nx == xf.size:
        return {"xf": xf, "terminal_equality": True}
    return {"state_lower": np.r_[xf, -np.inf], "state_upper": np.r_[xf, np.inf], "state_box_nodes": [N]}


class _PassiveRows:
    """Passive safety as SCP rows (module docstring): from node k the free drift's position at time t is
    G(t) x_k, G = the first three rows of the CW state transition matrix (exact for the plan's linear
    model); per node and sampled drift time, the supporting plane of the inflated zone at the radial
    projection q of the previous iterate's drift point, in the elastic form
        n^' (G(t) x_k - q) >= -sigma_k,   n^ the unit normal,
    sigma the slack state (m) appended to the state: sigma_0 = 0, sigma_{k+1} = sigma_k + u_sigma_k,
    u_sigma >= 0 with L1 weight ``penalty`` (N s / m). sigma is nondecreasing, so the cost is
    ``penalty`` x the largest violation of these planes (an exact l-infinity penalty: for a penalty
    above the multipliers' sum the subproblem's minimizer is the constrained one whenever that is
    feasible, and the subproblem is always feasible). ``per_node``: only the rows of the samples nearest
    the zone at the previous iterate, per node (the engine's interior-point step cost jumps between 100
    and 200 rows: 0.1 -> 3.4 ms at N = 20, 2026-12-03); a relaxation, re-selected every iteration, the
    returned plan checked on every sample (``drift_slack``) and on the truth."""

    def __init__(self, problem: RendezvousProblem, keep_out: KeepOut, margin: float, nodes: list[int],
                 drift_time: float, samples: int, penalty: float, per_node: int | None = None):
        from . import cw_discretize

        self.keep_out, self.margin, self.nodes, self.penalty = keep_out, margin, nodes, penalty
        self.per_node = samples if per_node is None else min(per_node, samples)
        self.times = drift_time * np.arange(1, samples + 1) / samples
        self.G = np.array([cw_discretize(problem.n, problem.mass, t, "zoh")[0][:3] for t in self.times])

    def drift(self, X: np.ndarray) -> np.ndarray:
        """Drift positions (nodes, samples, 3) m of the plan X (N+1, >= 6) on the linear model."""
        return np.einsum("sij,kj->ksi", self.G, X[self.nodes, :6])

    def augment(self, rows, X: np.ndarray):
        """The keep-out / trust rows (6 columns) padded with the slack column, then the drift rows."""
        nodes, A, b = rows
        Dn = self.drift(X)  # (nodes, samples, 3)
        k = self.per_node
        # per node the k samples nearest the zone (smallest radius), in time order
        sel = np.sort(np.argsort(self.keep_out.rho(Dn), axis=1, kind="stable")[:, :k], axis=1)
        D = np.take_along_axis(Dn, sel[:, :, None], axis=1).reshape(-1, 3)
        G = self.G[sel.reshape(-1)]  # (nodes * k, 3, 6), node-major as D
        a3, b3 = supporting_half_spaces(D, self.keep_out, self.margin)
        nrm = np.linalg.norm(a3, axis=1)
        a3, b3 = a3 / nrm[:, None], b3 / nrm
        ad = np.hstack([np.einsum("ki,kij->kj", a3, G), -np.ones((a3.shape[0], 1))])
        return (np.r_[nodes, np.repeat(self.nodes, k)],
                np.vstack([np.hstack([A, np.zeros((len(b), 1))]), ad]), np.r_[b, b3])


class _EngineSubproblem:
    """The state-constrained ADMM built once (``L1Solver(..., half_spaces=...)``); each SCP iteration
    replaces the rows that changed in place (``set_half_space``, no allocation) and solves warm from the
    previous subproblem's primal and dual iterate (the engine keeps them)."""

    def __init__(self, Ad, B, x0, xf, N, w, lo, hi, rows, settings):
        nodes, A, b = rows
        self.s = L1Solver(Ad, B, x0, horizon=N, l1_weights=w, u_lower=lo, u_upper=hi, settings=settings,
                          half_spaces={"nodes": nodes, "a": A, "b": b}, **_terminal(xf, N, Ad.shape[0]))
        self.A, self.b = A.copy(), b.copy()
        self.ipm_solved = False  # the last solve's plan is the interior-point method's, certified

    def solve(self, rows):
        nodes, A, b = rows
        # only the rows that moved (the rows were validated when built: the same shapes and nodes)
        # (the extension's call directly: the public wrapper's re-validation doubled its ~13 us)
        for i in np.flatnonzero(np.any(A != self.A, axis=1) | (b != self.b)):
            if not self.s._solver.set_half_space(int(i), int(nodes[i]), A[i], float(b[i])):
                raise ValueError(f"half-space {i} at node {nodes[i]}: rejected (a zero or non-finite row)")
        self.A[:], self.b[:] = A, b
        r = self.s.solve()
        self.ipm_solved = bool(r.ipm_solved)
        return r.status, np.asarray(r.Y), np.asarray(r.X_flown), float(r.solve_time)


class _LazyTrustRegion:
    """The SCP subproblem with the trust region added only when it binds. The subproblem without the
    trust rows (one supporting plane per node) is a relaxation of the one with them; when its
    minimizer lies inside the trust region it is feasible for, hence a minimizer of, the trust-region
    subproblem: the same iterate at a seventh of the rows. Otherwise the subproblem is solved again
    with the trust rows (a second engine, built on first need and then kept warm)."""

    def __init__(self, Ad, B, x0, xf, N, w, lo, hi, settings, idx, keep_out, margin, tr, passive=None):
        self.args = (Ad, B, x0, xf, N, w, lo, hi)
        self.st, self.idx, self.keep_out, self.margin, self.tr = settings, idx, keep_out, margin, tr
        self.passive: _PassiveRows | None = passive
        self.plain: _EngineSubproblem | None = None
        self.trust: _EngineSubproblem | None = None
        self.with_trust = 0  # subproblems that needed the trust rows
        self.ipm_certified = 0  # SCP subproblems whose plan the interior-point method certified

    def _engine(self, which: str, rows):
        e = getattr(self, which)
        if e is None:
            try:
                e = _EngineSubproblem(*self.args, rows, self.st)
            except TypeError as err:
                if "half_spaces" in str(err):
                    raise NotImplementedError("solver: 'admm' needs the ADMM state constraints (half_spaces; "
                                              "parcel GUID16A); use solver='cvxpy'") from None
                raise
            setattr(self, which, e)
        return e

    def set_input(self, B: np.ndarray) -> None:
        """New input matrices (the plume inhibitions changed): the engines are rebuilt on next need."""
        self.args = self.args[:1] + (B,) + self.args[2:]
        self.plain = self.trust = None

    def _all_rows(self, X: np.ndarray, tr: float):
        rows = _rows(self.idx, X[self.idx, :3], self.keep_out, self.margin, tr)
        return rows if self.passive is None else self.passive.augment(rows, X)

    def initial(self, X: np.ndarray):
        """The plan without the zone, solved on the SCP's own engine with its rows relaxed (the
        supporting planes at the positions of ``X`` (N+1, nx) moved out by ``_RELAX`` times the
        problem's length scale, never active): the interior-point method solves and certifies it in ~10
        steps, where the L1 ADMM without rows needed ~600 iterations and a failed IPM attempt (5.4 ms of
        the 15-19 ms plan, 2026-12-03). Falls back to the L1 solver without rows if that does not end
        ``solved``."""
        Ad, B, x0, xf, N, w, lo, hi = self.args
        nodes, A, b = self._all_rows(X, math.inf)
        scale = max(float(np.max(np.abs(x0[:3]))), float(np.max(np.abs(xf[:3]))),
                    float(np.max(self.keep_out.semi_axes)), 1.0)
        relaxed = (nodes, A, b + _RELAX * scale * np.linalg.norm(A, axis=1))
        status, U, X, t = self._engine("plain", relaxed).solve(relaxed)
        if status == "solved":
            return status, U, X, t
        r = L1Solver(Ad, B, x0, horizon=N, l1_weights=w, u_lower=lo, u_upper=hi, settings=self.st,
                     **_terminal(xf, N, Ad.shape[0])).solve()
        return r.status, np.asarray(r.Y), np.asarray(r.X_flown), t + float(r.solve_time)

    def solve(self, Xp: np.ndarray):
        P = Xp[self.idx, :3]
        rows = self._all_rows(Xp, math.inf)
        status, U, X, t = self._engine("plain", rows).solve(rows)
        if not math.isfinite(self.tr) or (
                X is not None and float(np.max(np.abs(X[self.idx, :3] - P))) <= self.tr):
            self.ipm_certified += self._engine("plain", rows).ipm_solved
            return status, U, X, t
        self.with_trust += 1
        rows = self._all_rows(Xp, self.tr)
        status, U, X, t2 = self._engine("trust", rows).solve(rows)
        self.ipm_certified += self._engine("trust", rows).ipm_solved
        return status, U, X, t + t2


#: distance (in units of the problem's length scale) by which :meth:`_LazyTrustRegion.initial` moves
#: the rows out, so that none is active on the plan without the zone
_RELAX = 100.0


def _solve_cvxpy(Ad, B, x0, xf, N, w, lo, hi, hs, box, settings):
    import cvxpy as cp

    nx, nu = B.shape[-2:]
    X = cp.Variable((N + 1, nx))
    U = cp.Variable((N, nu))
    cons = [X[0] == x0, U >= lo[None, :], U <= hi[None, :], X[N, :xf.size] == xf]  # (a slack state free)
    cons += [X[k + 1] == Ad @ X[k] + (B[k] if B.ndim == 3 else B) @ U[k] for k in range(N)]
    if hs is not None:
        nodes, a, b = hs
        cons += [a[i] @ X[k] <= b[i] for i, k in enumerate(nodes)]
    if box is not None:
        nodes, L, H = box
        for i, k in enumerate(nodes):
            fin = np.isfinite(L[i])
            cons += [X[k][np.flatnonzero(fin)] >= L[i][fin], X[k][np.flatnonzero(fin)] <= H[i][fin]]
    prob = cp.Problem(cp.Minimize(cp.sum(cp.multiply(np.tile(w, (N, 1)), cp.abs(U)))), cons)
    t0 = time.perf_counter()
    prob.solve(solver=cp.CLARABEL)
    t = time.perf_counter() - t0
    if prob.status not in ("optimal", "optimal_inaccurate"):
        return ("primal_infeasible" if "infeasible" in prob.status else prob.status), None, None, t
    return ("solved" if prob.status == "optimal" else "solved_inaccurate"), np.asarray(U.value), \
        np.asarray(X.value), t


def keep_out_plan(problem: RendezvousProblem, keep_out: KeepOut, *, xf: Any = None,
                  layout: ThrusterLayout | None = None, nodes: Any = None, margin: float = 0.05,
                  trust_radius: float | None = None, max_iterations: int = 20, tol: float = 1e-3,
                  solver: str = "admm", truth: Any = None, per_interval: int = 20,
                  settings: Any = None, drift_time: float | None = None, drift_nodes: Any = None,
                  drift_samples: int = 20, drift_penalty: float = 100.0, impose_drift: bool = True,
                  drift_check_samples: int = 100, drift_rows: int | None = 4,
                  plume: Any = None) -> KeepOutPlan:
    """Fuel-optimal plan from ``problem.x0`` to the hold point ``xf`` (6,) m, m/s (default: zeros, which
    is inside a zone centred on the target: then pass ``nodes`` to exempt the final approach) that stays
    out of ``keep_out`` at ``nodes`` (default 1..N), by SCP (module docstring). ``trust_radius`` (m,
    default: 2 x the largest semi-axis; ``math.inf``: none, the fuel still never rises); ``truth``:
    ``TwoSatelliteParams`` of the check flight (default
    J2 + drag, the problem's mu and mass; ``False`` skips the flight).

    Passive safety (``drift_time`` s > 0; None: not considered): the free drift from each of
    ``drift_nodes`` (default 1..N-1; x_0 and the hold point are given) over ``drift_time``, sampled at
    ``drift_samples`` equal steps on the plan's CW model, is kept outside the inflated zone by the
    elastic supporting planes of :class:`_PassiveRows` (slack penalty ``drift_penalty`` N s per m;
    ``impose_drift=False``: only checked; ``drift_rows``: per node only the rows of that many samples
    nearest the zone at the previous iterate, None: all). The result's ``drift_slack`` (m) is the
    largest depth of a drift sample (all of them) inside the inflated zone, behind its own supporting
    plane (0: outside), and ``passive`` the check on ``truth``: each drift node's state on the flight,
    drifting on the truth, sampled ``drift_check_samples`` times.

    Plume cone (``plume``: dict ``half_angle_deg`` in (0, 90], ``range`` m > 0; needs ``layout``): a
    thruster whose exhaust would point within the half-angle of the target while the chaser is within
    the range (:func:`plume_inhibited`, on the previous iterate's positions) is inhibited over that
    interval (its column of B zeroed, so the L1 optimum does not fire it); the inhibitions accumulate over
    the iterations (the set only grows, so it settles), and convergence needs an iteration that added
    none. The result's ``plume_violations`` counts firings that still impinge on the returned plan."""
    from .problem import satellite_params
    from .safety import PassiveSafety, passive_safety

    if not isinstance(problem, RendezvousProblem):
        raise TypeError(f"problem: must be a RendezvousProblem, got {type(problem).__name__}")
    if not isinstance(keep_out, KeepOut):
        raise TypeError(f"keep_out: must be a KeepOut, got {type(keep_out).__name__}")
    solver = one_of(solver, "solver", ("admm", "cvxpy"))
    N = problem.horizon
    xf = np.zeros(6) if xf is None else as_real_array(xf, "xf", shape=(6,))
    idx = list(range(1, N + 1)) if nodes is None else sorted(
        {as_int(k, "nodes[]", low=1, high=N) for k in nodes})
    if not idx:
        raise ValueError("nodes: must hold at least one node in 1..N")
    margin = as_real(margin, "margin", nonnegative=True)
    if N in idx and keep_out.rho(xf[:3]) < 1.0 + margin:
        raise ValueError(f"xf: the hold point {xf[:3].tolist()} m lies inside the (inflated) keep-out zone; "
                         "move it out or leave node N out of `nodes` (the final approach)")
    if float(keep_out.rho(np.asarray(problem.x0)[:3])) < 1.0:
        raise ValueError("problem.x0: the start lies inside the keep-out zone")
    tr = (2.0 * float(keep_out.semi_axes.max()) if trust_radius is None
          else as_real(trust_radius, "trust_radius", positive=True, finite=False))
    max_iterations = as_int(max_iterations, "max_iterations", low=1, high=10**4)
    tol = as_real(tol, "tol", positive=True)
    Ad, B, lo, hi = _controls(problem, layout)
    nu = B.shape[1]
    inh = None
    if plume is not None:
        if layout is None:
            raise ValueError("plume: needs a thruster layout (the per-axis box has no thruster to inhibit)")
        if not isinstance(plume, dict) or set(plume) - {"half_angle_deg", "range"} or len(plume) != 2:
            raise ValueError("plume: must be a dict with exactly the keys half_angle_deg and range")
        p_ang = as_real(plume["half_angle_deg"], "plume.half_angle_deg", positive=True)
        if p_ang > 90.0:
            raise ValueError(f"plume.half_angle_deg: must be in (0, 90] degrees, got {p_ang}")
        p_rng = as_real(plume["range"], "plume.range", positive=True)
        inh = np.zeros((N, nu), dtype=bool)
    B6 = B
    w = np.full(nu, problem.dt)
    x0 = np.asarray(problem.x0, dtype=float)
    passive = None
    dnodes: list[int] = []
    if drift_time is not None:
        drift_time = as_real(drift_time, "drift_time", positive=True)
        dnodes = list(range(1, N)) if drift_nodes is None else sorted(
            {as_int(k, "drift_nodes[]", low=1, high=N) for k in drift_nodes})
        if not dnodes:
            raise ValueError("drift_nodes: must hold at least one node in 1..N")
        drift_samples = as_int(drift_samples, "drift_samples", low=1, high=10**4)
        drift_check_samples = as_int(drift_check_samples, "drift_check_samples", low=1, high=10**6)
        drift_penalty = as_real(drift_penalty, "drift_penalty", positive=True)
        if as_bool(impose_drift, "impose_drift"):
            # x_N = xf is given: the plan cannot move its drift (and the engine's IPM and ADMM both
            # failed on elastic rows at the fixed terminal node, 2026-12-03)
            if N in dnodes:
                raise ValueError(f"drift_nodes: node N = {N} is the hold point xf, fixed; its drift cannot "
                                 "be changed by the plan (check it with impose_drift=False)")
            drift_rows = None if drift_rows is None else as_int(drift_rows, "drift_rows", low=1, high=10**4)
            passive = _PassiveRows(problem, keep_out, margin, dnodes, drift_time, drift_samples,
                                   drift_penalty, drift_rows)
            # the slack state sigma (m) and its control u_sigma in [0, bound] with weight drift_penalty
            scale = max(float(np.max(np.abs(x0[:3]))), float(np.max(np.abs(xf[:3]))), 1.0)
            Ad = np.block([[Ad, np.zeros((6, 1))], [np.zeros((1, 6)), np.ones((1, 1))]])
            B = _with_slack(B)
            x0 = np.r_[x0, 0.0]
            lo, hi, w = np.r_[lo, 0.0], np.r_[hi, 10.0 * scale], np.r_[w, drift_penalty]
    nx = Ad.shape[0]
    # method "admm_ipm" (the default): the engine's Riccati interior-point method first, its plan
    # accepted only by the violation and Fenchel-gap tests (eps_gap); ADMM if it is not
    st = {"eps_gap": 1e-7} if settings is None else settings
    t_wall = time.perf_counter()
    engine = None
    if solver == "admm":
        engine = _LazyTrustRegion(Ad, B, x0, xf, N, w, lo, hi, st, idx, keep_out, margin, tr, passive)
        # rows at the straight line x0 -> xf at rest (any supporting planes will do: they are relaxed)
        line = np.zeros((N + 1, nx))
        line[:, :3] = np.linspace(x0[:3], xf[:3], N + 1)
        status, U, X, t_solve = engine.initial(line)
    else:
        status, U, X, t_solve = _solve_cvxpy(Ad, B, x0, xf, N, w, lo, hi, None, None, st)
    if U is None or status not in ("solved", "solved_inaccurate"):
        raise ValueError(f"problem: the plan without the keep-out zone ended {status!r} (hint: a longer "
                           "horizon or larger thrust bounds)")

    def merit(U: np.ndarray, X: np.ndarray) -> tuple[float, float]:  # (fuel N s, slack m)
        sl = float(X[N, 6]) if nx == 7 else 0.0
        return float(np.sum(np.abs(U[:, :nu])) * problem.dt), sl

    fuel_hist = [merit(U, X)[0]]
    cost = fuel_hist[0]
    converged, it = False, 0
    while it < max_iterations:
        it += 1
        P = X[idx, :3]
        added = False
        if inh is not None:
            new = inh | plume_inhibited(X[:, :3], layout.directions, p_ang, p_rng)
            added = bool(np.any(new != inh))
            if added:
                inh = new
                Bk = np.repeat(B6[None], N, axis=0)
                Bk[inh[:, None, :].repeat(6, axis=1)] = 0.0
                if passive is not None:
                    Bk = np.array([_with_slack(b) for b in Bk])
                B = Bk
                if engine is not None:
                    engine.set_input(B)
        if engine is not None:  # the same rows as half-spaces, the solver kept warm
            status, Un, Xn, ts = engine.solve(X)
        else:
            nodes_r, a, b = _rows(idx, P, keep_out, margin, math.inf)
            if passive is not None:
                nodes_r, a, b = passive.augment((nodes_r, a, b), X)
            L = np.full((len(idx), nx), -np.inf)
            H = np.full((len(idx), nx), np.inf)
            L[:, :3] = P - tr
            H[:, :3] = P + tr
            status, Un, Xn, ts = _solve_cvxpy(Ad, B, x0, xf, N, w, lo, hi, (nodes_r, a, b), (idx, L, H), st)
        t_solve += ts
        if Un is None or status not in ("solved", "solved_inaccurate"):
            break
        step = float(np.max(np.abs(Xn[:, :3] - X[:, :3])))
        U, X = Un, Xn
        f, sl = merit(U, X)
        fuel_hist.append(f)
        cost, prev = f + (drift_penalty * sl if passive is not None else 0.0), cost
        if not added and (step < tol or abs(cost - prev) <= 1e-9 * abs(prev)):
            converged = True
            break
    wall = time.perf_counter() - t_wall
    U, X = U[:, :nu], X[:, :6]
    slack = math.nan
    if drift_time is not None:  # of the plan returned (also when the last subproblem failed), not sigma
        D = _PassiveRows(problem, keep_out, margin, dnodes, drift_time, drift_samples, 1.0).drift(X)
        a3, b3 = supporting_half_spaces(D.reshape(-1, 3), keep_out, margin)
        depth = (np.sum(a3 * D.reshape(-1, 3), axis=1) - b3) / np.linalg.norm(a3, axis=1)
        slack = float(max(0.0, np.max(depth)))
    forces = U @ layout.directions if layout is not None else U.copy()
    node_rho = keep_out.rho(X[:, :3])
    sat_nodes = bool(np.all(node_rho[idx] >= 1.0))
    flown_nodes = flown_min = math.nan
    sat_flown = False
    Xf = None
    ps: PassiveSafety | None = None
    if truth is not False:
        tp = satellite_params(problem.mu, j2=True, drag=True, mass=problem.mass) if truth is None else truth
        Xf = sample_flight(tp, problem.state_eci(), forces, problem.dt, per_interval)
        rho_f = keep_out.rho(cw_positions(Xf))
        span = slice(idx[0] * per_interval, idx[-1] * per_interval + 1)
        flown_nodes = float(np.min(rho_f[[k * per_interval for k in idx]]))
        flown_min = float(np.min(rho_f[span]))
        sat_flown = flown_min >= 1.0
        if drift_time is not None:
            ps = passive_safety(tp, Xf[[k * per_interval for k in dnodes]], keep_out, drift_time,
                                drift_check_samples)
    pviol = -1
    if inh is not None:
        fire = U > 1e-9 * layout.max_thrust[None, :]
        hit = plume_inhibited(X[:, :3], layout.directions, p_ang, p_rng)
        if Xf is not None:  # every flown sample of interval k (both ends included)
            Pf = cw_positions(Xf)
            for k in range(N):
                seg = Pf[k * per_interval:(k + 1) * per_interval + 1]
                hit[k] |= np.any(plume_inhibited(seg, layout.directions, p_ang, p_rng), axis=0)
        pviol = int(np.sum(fire & hit))
    return KeepOutPlan(U, forces, X, status, converged, it, fuel_hist[-1], np.array(fuel_hist), node_rho,
                       flown_nodes, flown_min, sat_nodes, sat_flown, t_solve, wall, Xf,
                       engine.with_trust if engine is not None else 0,
                       engine.ipm_certified if engine is not None else 0, slack, inh, pviol, ps)
