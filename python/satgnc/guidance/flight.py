"""Fly a plan on a truth model, open loop (:func:`fly`) or with receding-horizon re-planning (:func:`mpc`).

Time-major arrays, SI units: controls (N, 3) in newtons in the target's CW frame, 12-states
``[r_t - r_c, r_t, v_t - v_c, v_t]`` (m, m/s, ECI) as rows of (N+1, 12). Results are frozen
dataclasses with read-only arrays.
"""

from __future__ import annotations

import dataclasses
import inspect
import re
import time

import numpy as np

from .. import _satgnc as _c
from .._results import Result
from .._validate import as_int, as_real, as_real_array, one_of
from .planning import check_above_surface, make_map, transcribe
from .problem import RendezvousProblem, satellite_params

__all__ = ["Flight", "MpcRun", "fly", "mpc", "INTEGRATORS"]

#: "cvodes": satgnc's CVODES path re-initialised at each interval (rtol 1e-11); "rk4": fixed-step RK4.
INTEGRATORS = ("cvodes", "rk4")


def _norm(v: np.ndarray) -> float:
    """|v| without overflow in the squares (X = 1e300 gave an infinite miss)."""
    m = float(np.max(np.abs(v)))
    return m * float(np.linalg.norm(v / m)) if m > 0 and np.isfinite(m) else float(np.linalg.norm(v))


def terminal_miss(x: np.ndarray) -> tuple[float, float]:
    """Miss (m, m/s) of one 12-state: |r_t - r_c| and |v_t - v_c|."""
    return _norm(x[0:3]), _norm(x[6:9])


@dataclasses.dataclass(frozen=True)
class Flight(Result):
    """An open-loop flight: ``t`` (N+1,) s from the start, ``X`` (N+1, 12) states (m, m/s, ECI),
    ``U`` (N, 3) the flown forces (N, CW frame), ``miss`` (position m, velocity m/s) at the end."""

    t: np.ndarray
    X: np.ndarray
    U: np.ndarray
    miss: tuple


@dataclasses.dataclass(frozen=True)
class MpcRun(Result):
    """A receding-horizon flight: ``X`` (N+1, 12) truth states (m, m/s, ECI), ``U`` (N, 3) flown forces
    (N, CW frame), ``solve_times`` (s, thread CPU time per re-plan), ``iterations`` per re-plan,
    ``first_plan`` (the first solve's info), ``miss`` (m, m/s) at the end."""

    X: np.ndarray
    U: np.ndarray
    solve_times: np.ndarray
    iterations: np.ndarray
    first_plan: object
    miss: tuple

    def __post_init__(self):
        object.__setattr__(self, "iterations", np.array(self.iterations, dtype=np.int64))
        super().__post_init__()


def model_failure(name: str, U, k, err: Exception) -> Exception:
    """The model's failure as an error naming the control argument when its size explains it."""
    big = float(np.max(np.abs(U))) if np.size(U) else 0.0
    where = f" in interval {k}" if k is not None else ""
    if big >= 1e100:
        return ValueError(
            f"{name}: controls up to {big:.3g} make the model's state overflow{where} "
            f"({err}); check the units"
        )
    return RuntimeError(f"{name}: the model failed{where} ({err})")


def _above_surface(x: np.ndarray, params) -> bool:
    """Both bodies of the 12-state x (m) above the sphere of radius params.j2_radius."""
    R2 = float(params.j2_radius) ** 2
    return bool(min(x[3:6] @ x[3:6], (x[3:6] - x[0:3]) @ (x[3:6] - x[0:3])) > R2)


def _impact(message: str, t: float, X_rows, time_major: bool):
    from satgnc.propagation import PropagationError

    err = PropagationError(message, status="impact", t_reached=t)
    X = np.array(X_rows)
    err.states = X if time_major else X.T  # the states reached, SI
    return err


def fly_core(
    p, x: np.ndarray, U: np.ndarray, dt: float, substeps: int, integrator: str, u_name: str, time_major: bool
) -> np.ndarray:
    """Checked inputs -> states (N+1, 12). ``U`` (N, 3) newtons; errors name ``u_name``; an impact's
    ``states`` are time-major or 12 x k as ``time_major`` says."""
    if integrator == "cvodes":
        truth = _c.TwoSatelliteModel(p)
        r = _c.TwoSatelliteTruth(truth).fly(x, np.ascontiguousarray(U.T), dt)
        if r["impact"]:
            k = int(r["failed_interval"])
            raise _impact(
                f"fly: impact at t = {r['t_reached']:.6f} s: {r['message']}",
                float(r["t_reached"]),
                np.asarray(r["X"])[:, : k + 1].T,
                time_major,
            )
        if not r["ok"]:
            raise RuntimeError(f"fly: CVODES truth failed: {r['message']}")
        return np.asarray(r["X"]).T
    truth = _c.TwoSatelliteModel(p)
    h = dt / substeps
    R2 = float(p.j2_radius) ** 2
    X = [x.copy()]
    for k in range(U.shape[0]):
        for j in range(substeps):
            try:
                x = np.asarray(truth.rk_step(4, h, x, U[k]))
            except RuntimeError as e:  # "rk_step: model evaluation failed" named no argument
                raise model_failure(u_name, U, k, e) from None
            if min(x[3:6] @ x[3:6], (x[3:6] - x[0:3]) @ (x[3:6] - x[0:3])) <= R2:
                t = k * dt + (j + 1) * h
                raise _impact(
                    f"fly: impact: a body reached the Earth's surface (radius j2_radius = "
                    f"{p.j2_radius:.6g} m) in interval {k}, within the RK4 substep ending at t = "
                    f"{t:.6f} s",
                    t,
                    X,
                    time_major,
                )
        X.append(x.copy())
    return np.array(X)


def fly(params, x0, U, dt: float, substeps: int = 60, integrator: str = "cvodes") -> Flight:
    """Fly piecewise-constant forces open loop on the two-satellite truth model.

    Parameters
    ----------
    params : TwoSatelliteParams
        The truth model (see :func:`satellite_params`; SI).
    x0 : array_like
        The 12-state ``[r_t - r_c, r_t, v_t - v_c, v_t]`` (m, m/s, ECI).
    U : array_like
        (N, 3) forces (N, target's CW frame), each held ``dt``.
    dt : float
        Interval (s, > 0).
    substeps : int, optional
        RK4 steps per interval (default 60; ``integrator="rk4"`` only).
    integrator : {"cvodes", "rk4"}, optional
        "cvodes" (re-initialised at each interval, rtol 1e-11; default) or "rk4".

    Returns
    -------
    Flight
        ``t`` (N+1,) s, ``X`` (N+1, 12) m, m/s ECI, ``U``, ``miss`` (position m, velocity m/s).

    Raises
    ------
    ValueError
        Wrong shapes, a start at or below the Earth's surface (radius ``params.j2_radius``) naming
        ``x0``.
    TypeError
        ``params`` of another type.
    satgnc.PropagationError
        Reaching the surface: ``status == "impact"``, ``t_reached`` (s) and ``states`` (k, 12).

    Examples
    --------
    >>> from satgnc import guidance
    >>> pb = guidance.RendezvousProblem(mu=3.986004418e14, radius=6878.137e3, mass=12.0,
    ...                                 x0=[-1500.0, 200.0, 50.0, 0.3, 0.0, -0.05], tf=3000.0,
    ...                                 horizon=30, alpha=1.0, Qf=1000.0, u_max=0.02,
    ...                                 terminal_equality=True)
    >>> p = guidance.plan(pb)  # on the CW model
    >>> two_body = guidance.satellite_params(pb.mu, j2=False, drag=False, mass=pb.mass)
    >>> f = guidance.fly(two_body, pb.state_eci(), p.U, p.dt)  # the CW plan on the nonlinear truth
    >>> f.X.shape, bool(f.miss[0] < 10.0)
    ((31, 12), True)
    """
    if not isinstance(params, _c.TwoSatelliteParams):
        raise TypeError(
            f"params: must be TwoSatelliteParams (see satellite_params()), got {type(params).__name__}"
        )
    x = as_real_array(x0, "x0", shape=(12,), copy=True)
    U = as_real_array(U, "U", shape=(None, 3))
    dt = as_real(dt, "dt", positive=True)
    substeps = as_int(substeps, "substeps", low=1, high=10**6)
    integrator = one_of(integrator, "integrator", INTEGRATORS)
    check_above_surface(x, "x0", params)
    X = fly_core(params, x, U, dt, substeps, integrator, "U", True)
    return Flight(np.arange(U.shape[0] + 1) * dt, X, U, terminal_miss(X[-1]))


def mpc_core(
    case,
    tp,
    pp,
    replan_every,
    substeps,
    max_iter,
    min_horizon,
    qf_scale,
    rho,
    first_max_iter,
    integrator,
    discretization,
    endgame,
    scale_iterations,
    max_iter_cap,
    time_major,
):
    """Receding-horizon flight of the transcription ``case`` (checked arguments, see :func:`mpc`).
    Returns ``(X (N+1, 12), U (N, 3), solve_times, iterations, first_info)``."""
    truth = _c.TwoSatelliteModel(tp)
    cv_truth = _c.TwoSatelliteTruth(truth) if integrator == "cvodes" else None
    planner = _c.TwoSatelliteModel(pp)
    dmap = make_map(planner, case.dt, case.scaling, discretization or case.discretization)
    x = np.array(case.x0_si, dtype=float)
    Nh = case.problem.horizon
    h = case.dt / substeps
    sc = np.asarray(case.scaling.state_scale)
    cs = np.asarray(case.scaling.control_scale)
    U_all = np.zeros((3, Nh))
    X = [x.copy()]
    times, iters = [], []
    prev = None  # (U, Y, Lambda) not yet executed, scaled
    k = 0
    first = None
    while k < Nh:
        rem = Nh - k
        if prev is None or rem >= min_horizon:
            pr = _c.NonlinearL1Problem()
            pr.horizon = rem
            pr.x0 = x / sc
            pr.x_target = np.zeros(12)
            pr.Qf = qf_scale * np.asarray(case.problem.Qf)
            pr.alpha = case.problem.alpha
            pr.stage_weight = case.problem.stage_weight
            pr.cost = case.problem.cost
            if case.constrained:
                pr.u_min = case.problem.u_min
                pr.u_max = case.problem.u_max
            st = _c.IlqrAdmmSettings()
            st.rho = rho
            st.eps_abs = 1e-9
            st.eps_rel = 1e-9
            st.return_best = False
            sol = None
            if prev is None:
                st.max_iter = first_max_iter
                st.adaptive_rho = True
                sol = _c.IlqrAdmmSolver(dmap, pr, st)
                sol.set_initial_controls(np.zeros((3, rem)))
                sol.solve()
                first = sol.info
                rho_run = sol.info.rho
            else:
                st.max_iter = min(max_iter_cap, -(-max_iter * Nh // rem)) if scale_iterations else max_iter
                st.rho = rho_run
                sol = _c.IlqrAdmmSolver(dmap, pr, st)
                sol.warm_start(*prev)
                t0 = time.thread_time()
                sol.solve()
                times.append(time.thread_time() - t0)
                iters.append(sol.info.iterations)
            prev = (np.asarray(sol.U), np.asarray(sol.Y), np.asarray(sol.Lambda))
        nexec = min(1 if rem <= endgame else replan_every, rem)
        for j in range(nexec):
            u = (prev[1][:, j : j + 1] * cs[:, None])[:, 0]
            U_all[:, k + j] = u
            t_start = (k + j) * case.dt
            if cv_truth is not None:
                try:
                    x = np.asarray(cv_truth.step(x, u, case.dt))
                except RuntimeError as e:  # an impact was a bare RuntimeError of the truth's step
                    m = re.search(r"impact at t = ([-+0-9.eE]+)", str(e))
                    if m is None:
                        raise
                    t_hit = t_start + float(m.group(1))
                    raise _impact(f"mpc: impact at t = {t_hit:.6f} s: {e}", t_hit, X, time_major) from None
            else:
                for i in range(substeps):
                    x = np.asarray(truth.rk_step(4, h, x, u))
                    if not _above_surface(x, tp):
                        t_hit = t_start + (i + 1) * h
                        raise _impact(
                            f"mpc: impact: a body reached the Earth's surface within the RK4 "
                            f"substep ending at t = {t_hit:.6f} s",
                            t_hit,
                            X,
                            time_major,
                        )
            X.append(x.copy())
        prev = tuple(a[:, nexec:] for a in prev)
        k += nexec
    return np.array(X), U_all.T, np.array(times), np.array(iters), first


def mpc(
    problem: RendezvousProblem,
    truth=None,
    planner=None,
    replan_every: int = 3,
    substeps: int = 20,
    max_iter: int = 10,
    min_horizon: int = 1,
    qf_scale: float = 1e4,
    rho: float = 1.0,
    first_max_iter: int = 2000,
    integrator: str = "cvodes",
    discretization: str | None = None,
    endgame: int = 0,
    scale_iterations: bool = True,
    max_iter_cap: int = 120,
) -> MpcRun:
    """Receding-horizon flight of ``problem`` (shrinking horizon to the fixed final time ``tf``).

    The first plan is solved to convergence (iLQR-ADMM, residual rule, adaptive rho; not timed). Then
    every ``replan_every`` intervals -- every interval once at most ``endgame`` remain -- the remaining
    horizon is re-planned from the measured truth state with warm-started iLQR-ADMM iterations, and the
    sparse plan is flown on the truth.

    Parameters
    ----------
    problem : RendezvousProblem
        The rendezvous (SI: m, m/s, N, kg, s; CW frame :data:`satgnc.guidance.CW_FRAME`).
    truth : TwoSatelliteParams, optional
        Default: J2 and drag on, co-rotating atmosphere, the problem's ``mu`` and ``mass``.
    planner : TwoSatelliteParams, optional
        The planning model (default: the truth's).
    replan_every : int, optional
        Intervals between re-plans (default 3).
    substeps : int, optional
        RK4 steps per interval of the truth (``integrator="rk4"``; default 20).
    max_iter : int, optional
        iLQR-ADMM iterations per re-plan (default 10; scaled by N / remaining with
        ``scale_iterations``, capped at ``max_iter_cap``).
    min_horizon : int, optional
        Shortest re-planned horizon (intervals; default 1).
    qf_scale : float, optional
        Terminal weight = ``qf_scale`` times the problem's (default 1e4).
    rho : float, optional
        ADMM penalty (scaled units; default 1).
    first_max_iter : int, optional
        Iterations of the first plan (default 2000).
    integrator : {"cvodes", "rk4"}, optional
        The truth's integrator (default "cvodes").
    discretization : str, optional
        The planner's map (default: the problem's nonlinear one).
    endgame : int, optional
        Re-plan every interval once at most this many remain (default 0).
    scale_iterations : bool, optional
        Scale ``max_iter`` by N / remaining (default True).
    max_iter_cap : int, optional
        Cap of the scaled iterations (default 120).

    Returns
    -------
    MpcRun
        ``X`` (N+1, 12) truth states (m, m/s, ECI), ``U`` (N, 3) forces (N), ``solve_times`` (s),
        ``iterations`` per re-plan, ``miss`` (m, m/s).

    Raises
    ------
    ValueError
        Bad settings, naming the argument.
    TypeError
        ``truth`` or ``planner`` of another type.
    satgnc.PropagationError
        A body reaching the Earth's surface (``status == "impact"``, ``t_reached``, ``states``).

    Examples
    --------
    >>> from satgnc import guidance
    >>> pb = guidance.RendezvousProblem(mu=3.986004418e14, radius=6878.137e3, mass=12.0,
    ...                                 x0=[-1500.0, 200.0, 50.0, 0.3, 0.0, -0.05], tf=3000.0,
    ...                                 horizon=30, alpha=1.0, Qf=1000.0, u_max=0.02,
    ...                                 terminal_equality=True)
    >>> run = guidance.mpc(pb, truth=guidance.satellite_params(pb.mu, j2=True, drag=False, mass=12.0),
    ...                    replan_every=5)
    >>> run.U.shape, bool(run.miss[0] < 5.0)
    ((30, 3), True)
    """
    tr = transcribe(problem)
    default = satellite_params(problem.mu, j2=True, drag=True, atmosphere="co_rotating", mass=problem.mass)
    for name, p in (("truth", truth), ("planner", planner)):
        if p is not None and not isinstance(p, _c.TwoSatelliteParams):
            raise TypeError(
                f"{name}: must be TwoSatelliteParams (see satellite_params()), got {type(p).__name__}"
            )
    truth = default if truth is None else truth
    X, U, times, iters, first = mpc_on(
        tr, truth, truth if planner is None else planner, replan_every, substeps, max_iter, min_horizon,
        qf_scale, rho, first_max_iter, integrator, discretization, endgame, scale_iterations, max_iter_cap)
    return MpcRun(X, U, times, iters, first, terminal_miss(X[-1]))


def mpc_on(tr, truth, planner, *args, time_major: bool = True, **options):
    """:func:`mpc` on the transcription ``tr`` with ``truth`` and ``planner`` (TwoSatelliteParams):
    the options after ``planner`` (positional or by keyword) and their defaults are :func:`mpc`'s, read
    from its signature (one place). ``time_major``: orientation of the states of a PropagationError.
    Returns ``(X (N+1, 12), U (N, 3), solve_times, iterations, first_info)``."""
    bound = inspect.signature(mpc).bind(None, truth, planner, *args, **options)
    bound.apply_defaults()
    a = bound.arguments
    replan_every, substeps, integrator = check_mpc_args(a["replan_every"], a["substeps"], a["integrator"])
    return mpc_core(tr, truth, planner, replan_every, substeps, a["max_iter"], a["min_horizon"],
                    a["qf_scale"], a["rho"], a["first_max_iter"], integrator, a["discretization"],
                    a["endgame"], a["scale_iterations"], a["max_iter_cap"], time_major)


def check_mpc_args(replan_every, substeps, integrator):
    """(replan_every, substeps, integrator) checked, in the order the old API checked them."""
    integrator = one_of(integrator, "integrator", INTEGRATORS)
    replan_every = as_int(replan_every, "replan_every", low=1)
    substeps = as_int(substeps, "substeps", low=1, high=10**6)  # substeps=0 divided by zero
    return replan_every, substeps, integrator
