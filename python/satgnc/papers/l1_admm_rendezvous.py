"""L1 (fuel-optimal) rendezvous on the nonlinear two-satellite model: the paper's nonlinear cases
(Le Cleac'h & Manchester, Table 1, Figs. 4-5) and the tools the reproduction uses.

Every value of the paper's set-up is read from the scenario file ``scenarios/l1_rendezvous.toml`` (the
one source; :mod:`satgnc.scenarios.rendezvous`): :data:`MU`, :data:`R_TARGET`, :data:`MASS`,
:data:`TF`, :data:`N`, :data:`U_MAX` and the release state. The library does the work
(:mod:`satgnc.guidance.planning`, :mod:`satgnc.guidance.flight`, time-major); this module keeps the
reproduction's own API, in the paper's orientation (controls 3 x N, states 12 x (N+1)):

* :func:`drift_state` -- the scenario's 1 h uncontrolled drift (RK4, 9999 steps), 12-state SI vector
  ``[r_t - r_c, r_t, v_t - v_c, v_t]`` (m, m/s);
* :func:`paper_case` -- the published implementation's transcription (scaling, RK3 map, weights);
* :func:`solve_paper` -- ADMM with one iLQR iteration per ADMM iteration and the paper's stopping rule;
* :func:`solve_scp` -- sequential convex programming to the optimum of the same transcription;
* :func:`summarize` -- fuel (delta-v), terminal miss, sparsity of a control sequence;
* :func:`fly`, :func:`mpc`, :func:`linear_cw_plan` -- the library's flight, re-planning and CW plan on a
  :class:`Case` (3 x N / 12 x (N+1));
* :func:`run_cli` -- ``satgnc rendezvous --model nonlinear`` on the paper's scenario.

Units: SI (m, m/s, N, kg, s) at this API; the solvers work in the scaled units of :class:`Case`.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .. import _satgnc as _c
from .._validate import as_bool, as_int, as_real, as_real_array, one_of
from ..guidance import flight as _flight
from ..guidance.planning import (  # noqa: F401  (the reproduction's names for the library's tables)
    ILQR_ADMM_STATUS_NAMES,
    QF_MASK,
    SCP_STATUS_NAMES,
    SCP_SUCCESS,
    check_above_surface,
    make_map,
    rollout,
    solve_ilqr_admm,
    solve_linear_cw,
    transcribe,
)
from ..guidance.planning import solve_scp as _solve_scp
from ..guidance.problem import RendezvousProblem, satellite_params
from ..scenarios import rendezvous as _scenario

#: the paper's scenario (l1_rendezvous.toml), the one source of the values below
SCENARIO = _scenario.load()
_S = SCENARIO.sections
MU = _S["orbit"]["mu"]  #: m^3/s^2, the scenario's gravitational parameter
R_TARGET = _S["orbit"]["radius"]  #: m, target orbit radius (6731 km + 500 km, the implementation's typo kept)
MASS = _S["chaser"]["mass"]  #: kg, chaser and target
TF = _S["horizon"]["tf"]  #: s, horizon
N = _S["horizon"]["knots"] - 1  #: control intervals (100 knot points)
U_MAX = _S["cost"]["u_max"]  #: N, per-axis bound of the constrained cases
ALPHA = _S["cost"]["alpha"]  #: L1 weight (scaled)
QF = _S["cost"]["Qf"]  #: terminal weight (scaled), on the relative position and velocity
DISCRETIZATIONS = ("rk3", "rk4", "dop853")

__all__ = [
    "Case",
    "drift_state",
    "paper_case",
    "solve_paper",
    "solve_scp",
    "summarize",
    "fly",
    "mpc",
    "model_params",
    "make_map",
    "release_state",
    "linear_cw_plan",
    "miss",
    "run_cli",
    "SCP_STATUS_NAMES",
    "ILQR_ADMM_STATUS_NAMES",
    "SCP_SUCCESS",
]


def _case_name(constrained: bool) -> str:
    return "constrained" if constrained else "unconstrained"


def model_params(published: bool = True, j2: bool = False, drag: bool = True, rho0: float | None = None):
    """TwoSatelliteParams of the scenario. ``published`` selects the implementation's drag sign
    (v + omega x r); otherwise the physical co-rotating atmosphere (v - omega x r)."""
    published, j2, drag = as_bool(published, "published"), as_bool(j2, "j2"), as_bool(drag, "drag")
    return satellite_params(
        MU, j2=j2, drag=drag, atmosphere="published" if published else "co_rotating", rho0=rho0, mass=MASS
    )


def release_state() -> np.ndarray:
    """Scenario release: target on a circular equatorial orbit at [R, 0, 0]; target minus chaser
    [20, 30, 10] m and [0.4, 0.6, -0.1] m/s (ECI)."""
    return _scenario.release_state(SCENARIO)


def drift_state(params=None, steps: int | None = None) -> np.ndarray:
    """12-state after 3600 s of uncontrolled RK4 (the implementation: 10000 nodes = 9999 steps)."""
    rel = _S["release"]
    steps = rel["drift_steps"] if steps is None else steps
    steps = as_int(steps, "steps", low=1, high=10**7)  # 2**70 was reported as a bad "scheme"
    model = _c.TwoSatelliteModel(params if params is not None else model_params())
    return np.asarray(model.propagate(4, release_state(), rel["drift_time"], steps))


@dataclasses.dataclass
class Case:
    """One nonlinear case of Table 1 in the implementation's scaled transcription."""

    name: str
    model: object  #: TwoSatelliteModel
    dmap: object  #: TwoSatelliteMap (RK3, scaled)
    problem: object  #: NonlinearL1Problem (scaled)
    scaling: object  #: ReferenceScaling
    x0_si: np.ndarray
    rho: float
    eps: float
    constrained: bool
    discretization: str = "rk3"
    interval: float | None = None  #: s, control interval (None: the paper's TF / N)

    @property
    def dt(self) -> float:
        # paper_case(horizon=..., tf=...) discretizes over tf / horizon: fly, mpc and summarize
        # used TF / N = 60.6 s whatever the case's horizon was.
        return TF / N if self.interval is None else self.interval

    def to_si(self, U: np.ndarray) -> np.ndarray:
        """Scaled controls (3 x N) to newtons."""
        return np.asarray(U) * np.asarray(self.scaling.control_scale)[:, None]

    def from_si(self, U: np.ndarray) -> np.ndarray:
        return np.asarray(U) / np.asarray(self.scaling.control_scale)[:, None]

    def rollout_si(self, U_si: np.ndarray) -> np.ndarray:
        """States (12 x N+1, SI) of the planning model under U_si (newtons, 3 x N)."""
        return rollout(self, np.asarray(U_si).T).T

    def cost(self, U_si: np.ndarray) -> float:
        """True cost (scaled units, as minimized) of U_si on the planning model."""
        X = self.rollout_si(U_si)
        e = X[:, -1] / np.asarray(self.scaling.state_scale) - self.problem.x_target
        u = self.from_si(U_si)
        return 0.5 * e @ np.asarray(self.problem.Qf) @ e + self.problem.stage_weight * np.abs(u).sum()


def _check_case(case, needs=("dmap", "problem")) -> None:
    # Duck-typed (solve_scp needs only dmap and problem); None gave an AttributeError on 'dmap'.
    if not all(hasattr(case, a) for a in needs):
        raise TypeError(f"case: must be a Case (see paper_case()), got {type(case).__name__}")


def problem(
    constrained: bool = False,
    x0_si: np.ndarray | None = None,
    params=None,
    horizon: int = N,
    tf: float = TF,
    substeps: int = 1,
    discretization: str = "rk3",
    terminal_equality: bool = False,
) -> RendezvousProblem:
    """The library's :class:`~satgnc.guidance.RendezvousProblem` of a nonlinear case, the published
    implementation's (:func:`paper_case` transcribes it): RK3 over dt = tf/horizon, scaling
    (time 324.48 s, force 0.42318 N), Qf = 1000 diag(1,1,1,0,0,0,1,1,1,0,0,0), alpha = 1, control
    cost weighted by the scaled dt. Constrained: |u_i| <= 5e-3 N (paper: rho 10, eps 5e-6).
    ``discretization``: ``"rk3"`` (published), ``"rk4"`` or ``"dop853"`` (see :func:`make_map`).
    ``terminal_equality``: arrive exactly (x_N = x_f on the chaser's relative position and velocity,
    the target's orbit free) instead of the soft terminal cost; only :func:`solve_scp` solves it
    (its default linear ADMM inner); :func:`solve_paper` (iLQR-ADMM) raises ValueError."""
    constrained = as_bool(constrained, "constrained")
    horizon = as_int(horizon, "horizon", low=1, high=10**6)
    tf = as_real(tf, "tf", positive=True)
    substeps = as_int(substeps, "substeps", low=1, high=10**6)
    discretization = one_of(discretization, "discretization", DISCRETIZATIONS)
    terminal_equality = as_bool(terminal_equality, "terminal_equality")
    if params is not None and not isinstance(params, _c.TwoSatelliteParams):
        raise TypeError(
            f"params: must be TwoSatelliteParams (see model_params()), got {type(params).__name__}"
        )
    p = params if params is not None else model_params()
    x0 = drift_state() if x0_si is None else as_real_array(x0_si, "x0_si", shape=(12,))
    check_above_surface(x0, "x0_si", p)
    return RendezvousProblem(
        mu=MU,
        radius=R_TARGET,
        mass=MASS,
        x0=np.asarray(_c.cw_relative_state(x0)),
        tf=tf,
        horizon=horizon,
        alpha=ALPHA,
        Qf=QF,
        u_max=U_MAX if constrained else None,
        terminal_equality=terminal_equality,
        x0_eci=x0,
        planner=p,
        nonlinear_discretization=discretization,
        substeps=substeps,
    )


def paper_case(*args, **options) -> Case:
    """The published implementation's nonlinear case: :func:`problem` (the same arguments, positional or
    by keyword, and defaults) in the implementation's scaled transcription (:class:`Case`)."""
    # Checked here: complex / boolean x0_si was truncated or read as 0/1, horizon = 0 divided by zero,
    # and a bad horizon or tf was reported as a bad "dt".
    pb = problem(*args, **options)
    tr = transcribe(pb, "x0_si")
    nl = SCENARIO.cases[_case_name(pb.u_max is not None)]["nonlinear"]
    name = "nonlinear constrained" if tr.constrained else "nonlinear unconstrained"
    return Case(
        name,
        tr.model,
        tr.dmap,
        tr.problem,
        tr.scaling,
        tr.x0_si,
        nl["rho"],
        nl["eps"],
        tr.constrained,
        tr.discretization,
        tr.dt,
    )


def solve_paper(
    case: Case, max_iter: int = 300, rho: float | None = None, eps: float | None = None, ilqr_iters: int = 1
):
    """ADMM + iLQR with the published settings (paper stopping rule, multiplier row rescaling after
    iteration 1). Returns the solver (``.U``, ``.Y``, ``.X``, ``.info``; scaled units)."""
    _check_case(case)
    return solve_ilqr_admm(
        case,
        case.rho if rho is None else rho,
        case.eps if eps is None else eps,
        max_iter=max_iter,
        ilqr_iters=ilqr_iters,
        stop="paper",
        multiplier_rescale=True,
    )


def solve_scp(case: Case, *args, **options):
    """:func:`satgnc.guidance.planning.solve_scp` on the case's transcription: sequential convex
    programming to the optimum (options ``U0``, ``tol`` = 1e-10, ``eps`` = 1e-8, ``max_outer`` = 30,
    ``inner``, ``max_inner``, ``globalization``, ``time_limit``: positional or by keyword, defaults and
    statuses as documented there). Returns the solver (``.U``, ``.X``, ``.info``; scaled units)."""
    _check_case(case)
    return _solve_scp(case, *args, **options)


def summarize(case: Case, U_scaled: np.ndarray, zero_tol: float = 1e-6) -> dict:
    """Fuel (delta-v = sum |u| dt / m, m/s, L1 per axis), terminal miss on the planning model (m and
    m/s), sparsity (fraction of control entries with |u| <= zero_tol * u_max), objective."""
    _check_case(case)
    zero_tol = as_real(zero_tol, "zero_tol", nonnegative=True)
    U = case.to_si(as_real_array(U_scaled, "U_scaled", shape=(3, case.problem.horizon)))
    try:
        X = case.rollout_si(U)
    except RuntimeError as e:  # "step: the model failed on interval 0" named no argument
        raise _flight.model_failure("U_scaled", U_scaled, None, e) from None
    dv = float(np.abs(U).sum() * case.dt / MASS)
    thresh = zero_tol * max(np.abs(U).max(), 1e-30)
    return {
        "delta_v": dv,
        "miss_position": float(np.linalg.norm(X[0:3, -1])),
        "miss_velocity": float(np.linalg.norm(X[6:9, -1])),
        "sparsity": float(np.mean(np.abs(U) <= thresh)),
        "nonzero_intervals": int(np.sum(np.abs(U).max(axis=0) > thresh)),
        "objective": case.cost(U),
        "u_max": float(np.abs(U).max()),
    }


def _truth_default():
    return model_params(published=False, j2=True, drag=True)


def fly(
    case: Case,
    U_si: np.ndarray,
    truth_params=None,
    substeps: int = 60,
    x0_si=None,
    integrator: str = "cvodes",
) -> np.ndarray:
    """Propagate the 12-state under the piecewise-constant plan U_si (3 x N, N, in the target's CW
    frame) on a truth model (default: J2 and drag on, co-rotating atmosphere). ``integrator``:
    ``"cvodes"`` (satgnc's CVODES path, re-initialised at each interval boundary, rtol 1e-11) or
    ``"rk4"`` (fixed step dt/substeps). Returns states 12 x (N+1), SI; raises RuntimeError naming
    the interval when the propagation fails. A start with either body at or below the Earth's surface
    (radius ``j2_radius`` of the truth parameters) is a ValueError naming ``x0_si``; reaching it is a
    :class:`satgnc.PropagationError` with ``status == "impact"``, ``t_reached`` the impact time (s
    from the start; CVODES root finding, or the end of the RK4 substep where it was first seen) and
    ``states`` the states reached (12 x k). The library's time-major form is
    :func:`satgnc.guidance.fly`."""
    _check_case(case)
    integrator = one_of(integrator, "integrator", _flight.INTEGRATORS)
    substeps = as_int(substeps, "substeps", low=1, high=10**6)
    p = truth_params if truth_params is not None else _truth_default()
    x = case.x0_si.copy() if x0_si is None else as_real_array(x0_si, "x0_si", shape=(12,), copy=True)
    # complex U_si was truncated with a ComplexWarning and boolean read as 0/1 newtons
    U_si = as_real_array(U_si, "U_si", shape=(3, None))
    check_above_surface(x, "x0_si" if x0_si is not None else "case.x0_si", p)
    return _flight.fly_core(p, x, U_si.T, case.dt, substeps, integrator, "U_si", False).T


def mpc(case: Case, truth_params=None, planner_params=None, *args, **options) -> dict:
    """Receding-horizon flight of a case: :func:`satgnc.guidance.mpc` on the case's transcription, with
    its options after ``planner`` (``replan_every`` = 3, ``substeps`` = 20, ``max_iter`` = 10, ...,
    positional or by keyword, the same defaults). Planner default: J2 on, drag, co-rotating
    atmosphere; truth: the same. Returns a dict: states ``X`` (12 x N+1, SI), controls ``U`` (3 x N,
    N), re-plan ``solve_times`` (s, thread CPU time), ``iterations`` and ``first_plan`` (the first
    solve's info). A body reaching the Earth's surface raises :class:`satgnc.PropagationError` with
    ``status == "impact"``, ``t_reached`` and ``states`` (12 x k)."""
    _check_case(case)
    tp = truth_params if truth_params is not None else _truth_default()
    pp = planner_params if planner_params is not None else _truth_default()
    X, U, times, iters, first = _flight.mpc_on(case, tp, pp, *args, time_major=False, **options)
    return {"X": X.T, "U": U.T, "solve_times": times, "iterations": iters, "first_plan": first}


def linear_cw_plan(case: Case, eps: float = 1e-9) -> dict:
    """The linear-model (Clohessy-Wiltshire, exact zero-order hold) optimum of the same cost, from the
    same initial relative state (exact CW frame of the target): satgnc's linear ADMM solver, with
    the nonlinear case's scaling so that Qf and alpha mean the same thing. Returns the plan in newtons
    (3 x N, target CW frame) and the solver's result dict."""
    _check_case(case)
    U, r, x0, _ = solve_linear_cw(case, MU, MASS, eps, "zoh")
    return {"U": U.T, "result": r, "x0_cw": x0}


def miss(X: np.ndarray) -> tuple[float, float]:
    """Terminal miss (m, m/s) of a 12-state trajectory: |r_t - r_c| and |v_t - v_c| at the end."""
    X = as_real_array(X, "X", shape=(12, None))  # a complex X gave (0, 0), a 1-D X an IndexError
    if X.shape[1] == 0:
        raise ValueError("X: needs at least one column (state)")
    return _flight.terminal_miss(X[:, -1])


def run_cli(out, closed_loop: bool = False) -> int:
    """``satgnc rendezvous --model nonlinear [--closed-loop]`` on the paper's scenario: solve both
    nonlinear cases (paper settings and converged SCP), plot, and with ``closed_loop`` fly them (open
    loop and MPC) on the J2 + drag truth; writes PNGs and nonlinear_summary.json to ``out``."""
    from ..guidance.cli import run_nonlinear

    closed_loop = as_bool(closed_loop, "closed_loop")  # "x" was True
    return run_nonlinear(SCENARIO, None, out, closed_loop)
