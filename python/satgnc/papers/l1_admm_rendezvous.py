"""L1 (fuel-optimal) rendezvous guidance on the nonlinear two-satellite model.

The paper's nonlinear cases (Le Cleac'h & Manchester, Table 1, Figs. 4-5) and the tools around them:

* :func:`drift_state` -- the scenario's 1 h uncontrolled drift (RK4, 9999 steps), 12-state SI vector
  ``[r_t - r_c, r_t, v_t - v_c, v_t]`` (m, m/s);
* :func:`paper_case` -- the published implementation's transcription (scaling, RK3 map, weights);
* :func:`solve_paper` -- ADMM with one iLQR iteration per ADMM iteration and the paper's stopping rule;
* :func:`solve_scp` -- sequential convex programming to the optimum of the same transcription;
* :func:`summarize` -- fuel (delta-v), terminal miss, sparsity of a control sequence;
* :func:`fly` -- propagate a plan on a finer "truth" model (J2 and drag switchable);
* :func:`mpc` -- receding-horizon re-planning with warm start.

Units: SI (m, m/s, N, kg, s) at this API; the solvers work in the scaled units of :class:`Case`.
"""

from __future__ import annotations

import dataclasses
import re
import time

import numpy as np

from satgnc import _satgnc as _c
from satgnc._validate import as_bool, as_int, as_real, as_real_array, one_of

MU = 3.99e14  #: m^3/s^2, the scenario's gravitational parameter
R_TARGET = 7231.0e3  #: m, target orbit radius (6731 km + 500 km, the implementation's typo kept)
MASS = 4.6  #: kg, chaser and target
TF = 6000.0  #: s, horizon
N = 99  #: control intervals (100 knot points)
U_MAX = 5e-3  #: N, per-axis bound of the constrained cases
QF_MASK = np.array([1, 1, 1, 0, 0, 0, 1, 1, 1, 0, 0, 0], dtype=float)

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

#: ScpStatus value -> name (docs/guidance_nonlinear.md says what each guarantees).
SCP_STATUS_NAMES = {int(v): k for k, v in _c.ScpStatus.__members__.items()}
#: IlqrAdmmStatus value -> name.
ILQR_ADMM_STATUS_NAMES = {int(v): k for k, v in _c.IlqrAdmmStatus.__members__.items()}
#: The SCP statuses whose plan a caller may fly as converged (the loose one included).
SCP_SUCCESS = (_c.ScpStatus.solved, _c.ScpStatus.solved_inaccurate)


def model_params(published: bool = True, j2: bool = False, drag: bool = True, rho0: float | None = None):
    """TwoSatelliteParams of the scenario. ``published`` selects the implementation's drag sign
    (v + omega x r); otherwise the physical co-rotating atmosphere (v - omega x r)."""
    published, j2, drag = as_bool(published, "published"), as_bool(j2, "j2"), as_bool(drag, "drag")
    p = _c.TwoSatelliteParams()
    p.mu = MU
    p.atmosphere = _c.AtmosphereRotation.published if published else _c.AtmosphereRotation.co_rotating
    p.j2_on = j2  # bool("x") was True
    p.drag_on = drag
    if rho0 is not None:
        p.rho0 = as_real(rho0, "rho0", nonnegative=True)
    return p


def release_state() -> np.ndarray:
    """Scenario release: target on a circular equatorial orbit at [R, 0, 0]; target minus chaser
    [20, 30, 10] m and [0.4, 0.6, -0.1] m/s (ECI)."""
    vc = np.sqrt(MU / R_TARGET)
    return np.array([20.0, 30.0, 10.0, R_TARGET, 0, 0, 0.4, 0.6, -0.1, 0, vc, 0])


def drift_state(params=None, steps: int = 9999) -> np.ndarray:
    """12-state after 3600 s of uncontrolled RK4 (the implementation: 10000 nodes = 9999 steps)."""
    steps = as_int(steps, "steps", low=1, high=10**7)  # 2**70 was reported as a bad "scheme"
    model = _c.TwoSatelliteModel(params if params is not None else model_params())
    return np.asarray(model.propagate(4, release_state(), 3600.0, steps))


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
        """States (12 x N+1, SI) of the planning model under U_si (newtons)."""
        x = self.problem.x0.copy()
        X = [x]
        U = self.from_si(U_si)
        for k in range(U.shape[1]):
            x, _, _ = self.dmap.step(k, x, U[:, k])
            X.append(x)
        return np.array(X).T * np.asarray(self.scaling.state_scale)[:, None]

    def cost(self, U_si: np.ndarray) -> float:
        """True cost (scaled units, as minimized) of U_si on the planning model."""
        X = self.rollout_si(U_si)
        e = X[:, -1] / np.asarray(self.scaling.state_scale) - self.problem.x_target
        u = self.from_si(U_si)
        return 0.5 * e @ np.asarray(self.problem.Qf) @ e + self.problem.stage_weight * np.abs(u).sum()


DISCRETIZATIONS = ("rk3", "rk4", "dop853")


def _check_case(case, needs=("dmap", "problem")) -> None:
    # Duck-typed (solve_scp needs only dmap and problem); None gave an AttributeError on 'dmap'.
    if not all(hasattr(case, a) for a in needs):
        raise TypeError(f"case: must be a Case (see paper_case()), got {type(case).__name__}")


def make_map(model, dt: float, scaling, discretization: str = "rk3", substeps: int = 1, rtol: float = 1e-10):
    """Discrete map of ``model`` over intervals of ``dt`` s with the case's scaling:
    ``"rk3"`` (the published implementation's Kutta RK3, ``substeps`` per interval), ``"rk4"``
    (classic RK4), or ``"dop853"`` (the flow itself: adaptive DOP853 on the state, STM and control
    sensitivity, tolerance ``rtol`` on the scaled variables)."""
    discretization = one_of(discretization, "discretization", DISCRETIZATIONS)
    dt = as_real(dt, "dt", positive=True)
    substeps = as_int(substeps, "substeps", low=1, high=10**6)
    rtol = as_real(rtol, "rtol", positive=True)
    if discretization == "dop853":
        ps = _c.PropagatedMapSettings()
        ps.dt = dt
        ps.rtol = rtol
        ps.atol = rtol
        ps.state_scale = scaling.state_scale
        ps.control_scale = scaling.control_scale
        return _c.PropagatedTwoSatelliteMap(model, ps)
    ms = _c.TwoSatelliteMapSettings()
    ms.dt = dt
    ms.scheme = 3 if discretization == "rk3" else 4
    ms.substeps = substeps
    ms.state_scale = scaling.state_scale
    ms.control_scale = scaling.control_scale
    return _c.TwoSatelliteMap(model, ms)


def paper_case(
    constrained: bool = False,
    x0_si: np.ndarray | None = None,
    params=None,
    horizon: int = N,
    tf: float = TF,
    substeps: int = 1,
    discretization: str = "rk3",
    terminal_equality: bool = False,
) -> Case:
    """The published implementation's nonlinear case: RK3 over dt = tf/horizon, scaling
    (time 324.48 s, force 0.42318 N), Qf = 1000 diag(1,1,1,0,0,0,1,1,1,0,0,0), alpha = 1, control
    cost weighted by the scaled dt. Constrained: |u_i| <= 5e-3 N (paper: rho 10, eps 5e-6).
    ``discretization``: ``"rk3"`` (published), ``"rk4"`` or ``"dop853"`` (see :func:`make_map`).
    ``terminal_equality``: arrive exactly (x_N = x_f on the chaser's relative position and velocity,
    the target's orbit free) instead of the soft terminal cost; only :func:`solve_scp` solves it
    (its default linear ADMM inner); :func:`solve_paper` (iLQR-ADMM) raises ValueError."""
    # Checked here: complex / boolean x0_si was truncated or read as 0/1, horizon = 0 divided by zero,
    # and a bad horizon or tf was reported as a bad "dt".
    constrained = as_bool(constrained, "constrained")
    horizon = as_int(horizon, "horizon", low=1, high=10**6)
    tf = as_real(tf, "tf", positive=True)
    substeps = as_int(substeps, "substeps", low=1, high=10**6)
    discretization = one_of(discretization, "discretization", DISCRETIZATIONS)
    terminal_equality = as_bool(terminal_equality, "terminal_equality")
    if params is not None and not isinstance(params, _c.TwoSatelliteParams):
        raise TypeError(f"params: must be TwoSatelliteParams (see model_params()), "
                        f"got {type(params).__name__}")
    model = _c.TwoSatelliteModel(params if params is not None else model_params())
    x0 = drift_state() if x0_si is None else as_real_array(x0_si, "x0_si", shape=(12,))
    _check_above_surface(x0, "x0_si", params if params is not None else model_params())
    sc = _c.published_scaling(x0, MU, MASS)
    dmap = make_map(model, tf / horizon, sc, discretization, substeps)
    pr = _c.NonlinearL1Problem()
    pr.horizon = horizon
    pr.x0 = x0 / np.asarray(sc.state_scale)
    pr.x_target = np.zeros(12)
    pr.Qf = 1000.0 * np.diag(QF_MASK)
    pr.alpha = np.ones(3)
    pr.stage_weight = tf / horizon / sc.time_scale
    pr.terminal_equality = terminal_equality
    if constrained:
        pr.cost = _c.ControlCost.l1_box
        ub = U_MAX / np.asarray(sc.control_scale)
        pr.u_min = -ub
        pr.u_max = ub
    name = "nonlinear constrained" if constrained else "nonlinear unconstrained"
    return Case(
        name,
        model,
        dmap,
        pr,
        sc,
        x0,
        10.0 if constrained else 0.1,
        5e-6 if constrained else 6e-5,
        constrained,
        discretization,
        tf / horizon,
    )


def solve_paper(
    case: Case, max_iter: int = 300, rho: float | None = None, eps: float | None = None, ilqr_iters: int = 1
):
    """ADMM + iLQR with the published settings (paper stopping rule, multiplier row rescaling after
    iteration 1). Returns the solver (``.U``, ``.Y``, ``.X``, ``.info``; scaled units)."""
    _check_case(case)
    st = _c.IlqrAdmmSettings()
    st.rho = case.rho if rho is None else rho
    st.stop = _c.StopRule.paper
    st.eps_paper = case.eps if eps is None else eps
    st.paper_multiplier_rescale = True
    st.max_iter = max_iter
    st.ilqr_iters = ilqr_iters
    sol = _c.IlqrAdmmSolver(case.dmap, case.problem, st)
    sol.set_initial_controls(np.zeros((3, case.problem.horizon)))
    sol.solve()
    return sol


def solve_scp(
    case: Case,
    U0: np.ndarray | None = None,
    tol: float = 1e-10,
    eps: float = 1e-8,
    max_outer: int = 30,
    inner: str = "linear_admm",
    max_inner: int = 20000,
    globalization: str = "trust_region",
    time_limit: float = 0.0,
):
    """Sequential convex programming: re-linearize (exact map Jacobians), solve the convex L1
    subproblem (``inner="ilqr_admm"``: satgnc's iLQR-ADMM on the affine model, which is exact
    LQR-ADMM there, allocation-free, with the trust region as per-stage bounds; ``"linear_admm"``:
    the linear guidance AdmmSolver, the step scaled into the trust region), and accept steps by a
    trust-region ratio test (``globalization="trust_region"``) or an Armijo line search
    (``"line_search"``) on the true cost. ``time_limit``: seconds (0 = none). Returns the solver
    (``.U``, ``.X``, ``.info``; scaled units); ``info.status`` is ``solved`` only when the convex
    model predicts a decrease <= ``tol`` max(1, J) on a solved subproblem (table in
    docs/guidance_nonlinear.md). With ``case.problem.terminal_equality`` (hard terminal state; the
    linear_admm inner only, ``inner="ilqr_admm"`` raises ValueError) ``solved`` also needs
    ``info.terminal_constraint_miss <= 1e-6 info.terminal_reference``, and an unreachable target ends
    ``inner_infeasible`` with ``info.infeasibility_certificate`` and ``info.infeasibility_margin > 0``;
    ``time_limit`` also bounds each subproblem (the inner gets the remaining time)."""
    _check_case(case)
    inner = one_of(inner, "inner", ("ilqr_admm", "linear_admm"))
    globalization = one_of(globalization, "globalization", ("trust_region", "line_search"))
    st = _c.ScpSettings()
    st.tol = as_real(tol, "tol", nonnegative=True)
    st.max_outer = as_int(max_outer, "max_outer", low=1)
    st.time_limit = as_real(time_limit, "time_limit", nonnegative=True)
    st.tol_inaccurate = max(st.tol_inaccurate, st.tol)
    st.globalization = getattr(_c.ScpGlobalization, globalization)
    eps = as_real(eps, "eps", nonnegative=True)
    max_inner = as_int(max_inner, "max_inner", low=1)
    if inner == "ilqr_admm":
        st.inner_solver = _c.ScpInner.ilqr_admm
        ii = st.inner_ilqr
        ii.eps_abs = eps
        ii.eps_rel = eps
        ii.max_iter = max_inner
        st.inner_ilqr = ii
    else:
        st.inner_solver = _c.ScpInner.linear_admm
        ia = _c.ScpSettings().inner  # the SCP defaults (terminal_tolerance 1e-10)
        ia.eps_abs = eps
        ia.eps_rel = eps
        if st.tol > 0:  # hard terminal state: the subproblem reaches x_f finer than the outer test
            ia.terminal_tolerance = min(ia.terminal_tolerance, 0.1 * st.tol)
        ia.max_iterations = max_inner
        st.inner = ia
    sol = _c.ScpSolver(case.dmap, case.problem, st)
    if U0 is not None:
        sol.set_initial_controls(U0)
    sol.solve()
    return sol


def summarize(case: Case, U_scaled: np.ndarray, zero_tol: float = 1e-6) -> dict:
    """Fuel (delta-v = sum |u| dt / m, m/s, L1 per axis), terminal miss on the planning model (m and
    m/s), sparsity (fraction of control entries with |u| <= zero_tol * u_max), objective."""
    _check_case(case)
    zero_tol = as_real(zero_tol, "zero_tol", nonnegative=True)
    U = case.to_si(as_real_array(U_scaled, "U_scaled", shape=(3, case.problem.horizon)))
    try:
        X = case.rollout_si(U)
    except RuntimeError as e:  # "step: the model failed on interval 0" named no argument
        raise _model_failure("U_scaled", U_scaled, None, e) from None
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


def _check_above_surface(x: np.ndarray, name: str, params) -> None:
    """ValueError naming ``name`` when the target or the chaser of the 12-state x (m) is at or below
    the Earth's surface, the sphere of radius ``params.j2_radius`` (m); a start inside the Earth was a
    CVODES RuntimeError (or, with RK4, a silent flight through the planet)."""
    R = float(params.j2_radius)
    rt = float(np.linalg.norm(x[3:6]))
    rc = float(np.linalg.norm(x[3:6] - x[0:3]))
    for body, r in (("target |r_t|", rt), ("chaser |r_t - d|", rc)):
        if not r > R:
            raise ValueError(f"{name}: the {body.split()[0]} starts at or below the Earth's surface: "
                             f"{body} = {r:.6g} m <= R = {R:.6g} m (j2_radius); "
                             "x = [d, r_t, w, v_t] in m, m/s")


def _model_failure(name: str, U, k, err: Exception) -> Exception:
    """The model's failure as an error naming the control argument when its size explains it."""
    big = float(np.max(np.abs(U))) if np.size(U) else 0.0
    where = f" in interval {k}" if k is not None else ""
    if big >= 1e100:
        return ValueError(f"{name}: controls up to {big:.3g} make the model's state overflow{where} "
                          f"({err}); check the units")
    return RuntimeError(f"{name}: the model failed{where} ({err})")


def _above_surface(x: np.ndarray, params) -> bool:
    """Both bodies of the 12-state x (m) above the sphere of radius params.j2_radius."""
    R2 = float(params.j2_radius) ** 2
    return bool(min(x[3:6] @ x[3:6], (x[3:6] - x[0:3]) @ (x[3:6] - x[0:3])) > R2)


def _impact(message: str, t: float, X: np.ndarray):
    from satgnc.propagation import PropagationError

    err = PropagationError(message, status="impact", t_reached=t)
    err.states = X  # the states reached, 12 x (k + 1), SI
    return err


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
    ``states`` the states reached (12 x k)."""
    _check_case(case)
    integrator = one_of(integrator, "integrator", ("cvodes", "rk4"))
    substeps = as_int(substeps, "substeps", low=1, high=10**6)
    p = truth_params if truth_params is not None else model_params(published=False, j2=True, drag=True)
    truth = _c.TwoSatelliteModel(p)
    x = case.x0_si.copy() if x0_si is None else as_real_array(x0_si, "x0_si", shape=(12,), copy=True)
    # complex U_si was truncated with a ComplexWarning and boolean read as 0/1 newtons
    U_si = as_real_array(U_si, "U_si", shape=(3, None))
    _check_above_surface(x, "x0_si" if x0_si is not None else "case.x0_si", p)
    if integrator == "cvodes":
        r = _c.TwoSatelliteTruth(truth).fly(x, U_si, case.dt)
        if r["impact"]:
            k = int(r["failed_interval"])
            raise _impact(f"fly: impact at t = {r['t_reached']:.6f} s: {r['message']}", float(r["t_reached"]),
                          np.asarray(r["X"])[:, : k + 1])
        if not r["ok"]:
            raise RuntimeError(f"fly: CVODES truth failed: {r['message']}")
        return np.asarray(r["X"])
    h = case.dt / substeps
    R2 = float(p.j2_radius) ** 2
    X = [x.copy()]
    for k in range(U_si.shape[1]):
        for j in range(substeps):
            try:
                x = np.asarray(truth.rk_step(4, h, x, U_si[:, k]))
            except RuntimeError as e:  # "rk_step: model evaluation failed" named no argument
                raise _model_failure("U_si", U_si, k, e) from None
            if min(x[3:6] @ x[3:6], (x[3:6] - x[0:3]) @ (x[3:6] - x[0:3])) <= R2:
                t = k * case.dt + (j + 1) * h
                raise _impact(f"fly: impact: a body reached the Earth's surface (radius j2_radius = "
                              f"{p.j2_radius:.6g} m) in interval {k}, within the RK4 substep ending at t = "
                              f"{t:.6f} s", t, np.array(X).T)
        X.append(x.copy())
    return np.array(X).T


def mpc(
    case: Case,
    truth_params=None,
    planner_params=None,
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
) -> dict:
    """Receding-horizon flight (shrinking horizon to the fixed final time).

    The first plan is solved to convergence (iLQR-ADMM, residual rule, adaptive rho; not timed as a
    re-plan). Then every ``replan_every`` intervals -- every interval once at most ``endgame``
    intervals remain -- the remaining horizon is re-planned from the measured truth state with at
    most ``max_iter`` warm-started iLQR-ADMM iterations (U, Y, Lambda shifted; one Gauss-Newton step
    per iteration), and the sparse plan Y -- inside the bounds by construction of the prox -- is flown
    on the truth model. The terminal weight is ``qf_scale`` times the case's (a soft terminal
    constraint stiff enough for sub-metre misses). With ``scale_iterations`` the iteration budget
    grows as the horizon shrinks, ``max_iter * N / remaining`` (capped at ``max_iter_cap``), so every
    re-plan costs about the same as the first full-horizon one (the cost of an iteration is
    proportional to the horizon); with a fixed budget the short end-game re-plans stop short of
    convergence and the terminal miss has a ~1 m floor (docs/guidance_nonlinear.md).
    Planner: ``discretization`` (default: the case's) on ``planner_params`` (default: J2 on, drag);
    truth: J2 and drag on, co-rotating atmosphere, integrated by ``integrator`` (``"cvodes"``:
    satgnc's CVODES path re-initialised at each interval; ``"rk4"``: RK4 at dt/substeps). Returns
    states (12 x N+1, SI), controls (3 x N, N), re-plan solve times (s, thread CPU time) and
    iterations. A body reaching the Earth's surface (``j2_radius`` of the truth) raises
    :class:`satgnc.PropagationError` with ``status == "impact"``, ``t_reached`` and ``states``, as
    :func:`fly` does."""
    _check_case(case)
    integrator = one_of(integrator, "integrator", ("cvodes", "rk4"))
    replan_every = as_int(replan_every, "replan_every", low=1)
    substeps = as_int(substeps, "substeps", low=1, high=10**6)  # substeps=0 divided by zero
    tp = truth_params if truth_params is not None else model_params(published=False, j2=True, drag=True)
    pp = planner_params if planner_params is not None else model_params(published=False, j2=True, drag=True)
    truth = _c.TwoSatelliteModel(tp)
    cv_truth = _c.TwoSatelliteTruth(truth) if integrator == "cvodes" else None
    planner = _c.TwoSatelliteModel(pp)
    dmap = make_map(planner, case.dt, case.scaling, discretization or case.discretization)
    x = np.array(case.x0_si, dtype=float)
    Nh = case.problem.horizon
    h = case.dt / substeps
    sc = np.asarray(case.scaling.state_scale)
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
            u = case.to_si(prev[1][:, j : j + 1])[:, 0]
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
                    raise _impact(f"mpc: impact at t = {t_hit:.6f} s: {e}", t_hit, np.array(X).T) from None
            else:
                for i in range(substeps):
                    x = np.asarray(truth.rk_step(4, h, x, u))
                    if not _above_surface(x, tp):
                        t_hit = t_start + (i + 1) * h
                        raise _impact(f"mpc: impact: a body reached the Earth's surface within the RK4 "
                                      f"substep ending at t = {t_hit:.6f} s", t_hit, np.array(X).T)
            X.append(x.copy())
        prev = tuple(a[:, nexec:] for a in prev)
        k += nexec
    return {
        "X": np.array(X).T,
        "U": U_all,
        "solve_times": np.array(times),
        "iterations": np.array(iters),
        "first_plan": first,
    }


def linear_cw_plan(case: Case, eps: float = 1e-9) -> dict:
    """The linear-model (Clohessy-Wiltshire, exact zero-order hold) optimum of the same cost, from the
    same initial relative state (exact CW frame of the target): satgnc's linear ADMM solver, with
    the nonlinear case's scaling so that Qf and alpha mean the same thing. Returns the plan in newtons
    (3 x N, target CW frame) and the solver's result dict."""
    _check_case(case)
    eps = as_real(eps, "eps", positive=True)  # errors named the solver field "eps_abs"
    sc = case.scaling
    x0 = np.asarray(_c.cw_relative_state(case.x0_si))
    n = np.sqrt(MU / np.linalg.norm(case.x0_si[3:6]) ** 3)
    Ad, Bd = _c.cw_discretize(n, MASS, case.dt, "zoh")
    s = np.concatenate([np.asarray(sc.state_scale)[0:3], np.asarray(sc.state_scale)[6:9]])
    su = np.asarray(sc.control_scale)
    As = Ad * s[None, :] / s[:, None]
    Bs = Bd * su[None, :] / s[:, None]
    st = _c.AdmmSettings()
    st.eps_abs = eps
    st.eps_rel = eps
    st.max_iterations = 100000
    w = case.problem.stage_weight
    lo = np.asarray(case.problem.u_min) if case.constrained else np.zeros(0)
    hi = np.asarray(case.problem.u_max) if case.constrained else np.zeros(0)
    solver = _c.AdmmSolver(
        [As],
        [Bs],
        [],
        case.problem.horizon,
        x0 / s,
        np.zeros(6),
        1000.0 * np.eye(6),
        np.zeros((0, 0)),
        np.zeros((0, 0)),
        w * np.ones(3),
        0.0,
        lo,
        hi,
        0.0,
        False,
        st,
    )
    r = solver.solve()
    return {"U": case.to_si(r["Y"]), "result": r, "x0_cw": x0}


def miss(X: np.ndarray) -> tuple[float, float]:
    """Terminal miss (m, m/s) of a 12-state trajectory: |r_t - r_c| and |v_t - v_c| at the end."""
    X = as_real_array(X, "X", shape=(12, None))  # a complex X gave (0, 0), a 1-D X an IndexError
    if X.shape[1] == 0:
        raise ValueError("X: needs at least one column (state)")
    return _norm(X[0:3, -1]), _norm(X[6:9, -1])


def _norm(v: np.ndarray) -> float:
    """|v| without overflow in the squares (X = 1e300 gave an infinite miss)."""
    m = float(np.max(np.abs(v)))
    return m * float(np.linalg.norm(v / m)) if m > 0 and np.isfinite(m) else float(np.linalg.norm(v))


def run_cli(out, closed_loop: bool = False) -> int:
    """``satgnc rendezvous --model nonlinear [--closed-loop]``: solve both nonlinear cases (paper
    settings and converged SCP), plot, and with ``closed_loop`` fly them (open loop and MPC) on the
    J2 + drag truth; writes PNGs and nonlinear_summary.json to ``out``."""
    import json
    import pathlib

    from ..report.guidance_nonlinear import _figure, _flight_figure

    closed_loop = as_bool(closed_loop, "closed_loop")  # "x" was True

    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    summary = {}
    for constrained in (False, True):
        case = paper_case(constrained)
        paper = solve_paper(case)
        scp = solve_scp(case, eps=1e-7, tol=1e-8)
        key = case.name.replace(" ", "_")
        s_opt = summarize(case, scp.U)
        summary[key] = {
            "paper_iterations": paper.info.iterations,
            "paper_miss_flown_Y_m": summarize(case, paper.Y)["miss_position"],
            "scp_outer": scp.info.outer_iterations,
            **{f"opt_{k}": v for k, v in s_opt.items()},
        }
        _figure(
            case,
            [("optimum (SCP)", case.to_si(scp.U), "-"), ("paper stop, dense U", case.to_si(paper.U), ":")],
            out / f"{key}.png",
            case.name,
        )
        print(
            f"{case.name}: paper settings stop after {paper.info.iterations} iterations "
            f"(sparse plan misses by {summary[key]['paper_miss_flown_Y_m'] / 1000:.2f} km); optimum in "
            f"{scp.info.outer_iterations} SCP iterations, dv = {s_opt['delta_v']:.4f} m/s, "
            f"miss = {s_opt['miss_position']:.2f} m"
        )
        if closed_loop:
            lin = linear_cw_plan(case)
            flights = [
                ("CW plan, open loop", fly(case, lin["U"])),
                ("nonlinear plan, open loop", fly(case, case.to_si(scp.U))),
            ]
            m = mpc(case)
            flights.append(("MPC", m["X"]))
            for label, X in flights:
                summary[key][f"truth_miss_{label}"] = miss(X)[0]
                print(f"  {label}: truth miss {miss(X)[0]:.2f} m")
            summary[key]["mpc_replan_ms_max"] = float(np.max(m["solve_times"]) * 1e3)
            _flight_figure(case, flights, out / f"{key}_flight.png")
    (out / "nonlinear_summary.json").write_text(json.dumps(summary, indent=2, default=float))
    print(f"plots and nonlinear_summary.json written to {out}")
    return 0
