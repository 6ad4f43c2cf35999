"""Plan a rendezvous on the linear (Clohessy-Wiltshire) or the nonlinear (two-satellite) model.

:func:`plan` takes one :class:`~satgnc.guidance.problem.RendezvousProblem` and returns a
:class:`Plan`, time-major: controls ``U`` (N, 3) in newtons in the target's CW frame, states ``X``
(N+1, nx) in SI (linear: the CW relative state, m and m/s; nonlinear: the 12-state
``[r_t - r_c, r_t, v_t - v_c, v_t]``, m and m/s, ECI). Both models share one transcription of the cost:
states and controls are scaled as :func:`satgnc.published_scaling` does (from the nonlinear start and
the chaser's mass), ``Qf`` weighs the terminal relative position and velocity, ``alpha`` the L1 norm of
the scaled controls times the scaled interval.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .. import _satgnc as _c
from .._results import Result
from .._validate import as_int, as_real, as_real_array, one_of
from .problem import LINEAR_DISCRETIZATIONS, NONLINEAR_DISCRETIZATIONS, RendezvousProblem

__all__ = ["Plan", "plan", "make_map", "MODELS", "METHODS"]

MODELS = ("linear", "nonlinear")
#: methods per model; the first is the default.
METHODS = {"linear": ("admm",), "nonlinear": ("scp", "ilqr_admm")}
#: terminal weight mask of the 12-state: the relative position and velocity (the target's orbit free).
QF_MASK = np.array([1, 1, 1, 0, 0, 0, 1, 1, 1, 0, 0, 0], dtype=float)

#: ScpStatus value -> name (docs/guidance_nonlinear.md says what each guarantees).
SCP_STATUS_NAMES = {int(v): k for k, v in _c.ScpStatus.__members__.items()}
#: IlqrAdmmStatus value -> name.
ILQR_ADMM_STATUS_NAMES = {int(v): k for k, v in _c.IlqrAdmmStatus.__members__.items()}
#: The SCP statuses whose plan a caller may fly as converged (the loose one included).
SCP_SUCCESS = (_c.ScpStatus.solved, _c.ScpStatus.solved_inaccurate)


@dataclasses.dataclass(frozen=True)
class Plan(Result):
    """A planned rendezvous (read-only arrays, time-major).

    ``U`` (N, 3): force (N) per interval in the target's CW frame; ``X`` (N+1, nx): the planning
    model's states under ``U`` (linear: CW relative state, m, m/s; nonlinear: 12-state, m, m/s, ECI);
    ``dt`` (s), ``mass`` (kg); ``status`` (solver status name), ``iterations`` (ADMM iterations, or
    SCP outer iterations), ``objective`` (the minimized cost, scaled units), ``info`` (the solver's
    run record: linear, a read-only :class:`satgnc.guidance.AdmmInfo`, as ``L1Result.info``, whose
    ``raw`` is the extension's result dict this field used to be; nonlinear, the C++ ``ScpInfo`` or
    ``IlqrAdmmInfo``), ``model`` and ``method``. A frozen :class:`satgnc._results.Result`."""

    model: str
    method: str
    U: np.ndarray
    X: np.ndarray
    dt: float
    mass: float
    status: str
    iterations: int
    objective: float
    info: object = dataclasses.field(repr=False, default=None)

    @property
    def horizon(self) -> int:
        """Control intervals N."""
        return int(self.U.shape[0])

    @property
    def x0(self) -> np.ndarray:
        """The plan's initial state (SI), ``X[0]``."""
        return self.X[0]

    def miss(self) -> tuple[float, float]:
        """Terminal miss on the planning model: relative position (m) and velocity (m/s) at the end."""
        x = self.X[-1]
        if self.model == "linear":
            return float(np.linalg.norm(x[0:3])), float(np.linalg.norm(x[3:6]))
        return float(np.linalg.norm(x[0:3])), float(np.linalg.norm(x[6:9]))

    def summary(self, zero_tol: float = 1e-6) -> dict:
        """Fuel (``delta_v`` = sum |u| dt / m, m/s, L1 per axis), terminal miss (``miss_position`` m,
        ``miss_velocity`` m/s), ``sparsity`` (fraction of entries with |u| <= zero_tol max |u|),
        ``nonzero_intervals``, ``objective`` (scaled) and ``u_max`` (N)."""
        zero_tol = as_real(zero_tol, "zero_tol", nonnegative=True)
        U = self.U
        thresh = zero_tol * max(np.abs(U).max(), 1e-30)
        mp, mv = self.miss()
        return {
            "delta_v": float(np.abs(U).sum() * self.dt / self.mass),
            "miss_position": mp,
            "miss_velocity": mv,
            "sparsity": float(np.mean(np.abs(U) <= thresh)),
            "nonzero_intervals": int(np.sum(np.abs(U).max(axis=1) > thresh)),
            "objective": float(self.objective),
            "u_max": float(np.abs(U).max()),
        }


def make_map(model, dt: float, scaling, discretization: str = "rk3", substeps: int = 1, rtol: float = 1e-10):
    """Discrete map of ``model`` over intervals of ``dt`` s with the case's scaling:
    ``"rk3"`` (the published implementation's Kutta RK3, ``substeps`` per interval), ``"rk4"``
    (classic RK4), or ``"dop853"`` (the flow itself: adaptive DOP853 on the state, STM and control
    sensitivity, tolerance ``rtol`` on the scaled variables)."""
    discretization = one_of(discretization, "discretization", NONLINEAR_DISCRETIZATIONS)
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


# ------------------------------------------------------------------------------------------- transcription
@dataclasses.dataclass
class Transcription:
    """The scaled nonlinear transcription of a problem (what the solvers see): ``model``
    (TwoSatelliteModel), ``dmap`` (scaled discrete map), ``problem`` (NonlinearL1Problem, scaled),
    ``scaling`` (ReferenceScaling), ``x0_si`` (12-state, m, m/s), ``constrained``, ``discretization``
    and ``dt`` (s). Controls in newtons are (N, 3) here."""

    model: object
    dmap: object
    problem: object
    scaling: object
    x0_si: np.ndarray
    constrained: bool
    discretization: str
    dt: float


def check_above_surface(x: np.ndarray, name: str, params) -> None:
    """ValueError naming ``name`` when the target or the chaser of the 12-state x (m) is at or below
    the Earth's surface, the sphere of radius ``params.j2_radius`` (m); a start inside the Earth was a
    CVODES RuntimeError (or, with RK4, a silent flight through the planet)."""
    R = float(params.j2_radius)
    rt = float(np.linalg.norm(x[3:6]))
    rc = float(np.linalg.norm(x[3:6] - x[0:3]))
    for body, r in (("target |r_t|", rt), ("chaser |r_t - d|", rc)):
        if not r > R:
            raise ValueError(
                f"{name}: the {body.split()[0]} starts at or below the Earth's surface: "
                f"{body} = {r:.6g} m <= R = {R:.6g} m (j2_radius); "
                "x = [d, r_t, w, v_t] in m, m/s"
            )


def transcribe(problem: RendezvousProblem, x0_name: str = "x0_eci") -> Transcription:
    """The nonlinear transcription of ``problem``: the planner model, its map over dt = tf / N with
    :func:`satgnc.published_scaling` of the start, terminal weight ``Qf`` on the relative position and
    velocity, L1 weight ``alpha`` times the scaled interval, the box ``u_max`` when given."""
    if not isinstance(problem, RendezvousProblem):
        raise TypeError(f"problem: must be a RendezvousProblem, got {type(problem).__name__}")
    model = _c.TwoSatelliteModel(problem.planner)
    x0 = problem.state_eci()
    check_above_surface(x0, x0_name, problem.planner)
    sc = _c.published_scaling(x0, problem.mu, problem.mass)
    dt = problem.tf / problem.horizon
    dmap = make_map(model, dt, sc, problem.nonlinear_discretization, problem.substeps)
    pr = _c.NonlinearL1Problem()
    pr.horizon = problem.horizon
    pr.x0 = x0 / np.asarray(sc.state_scale)
    pr.x_target = np.zeros(12)
    pr.Qf = problem.Qf * np.diag(QF_MASK)
    pr.alpha = problem.alpha * np.ones(3)
    pr.stage_weight = dt / sc.time_scale
    pr.terminal_equality = problem.terminal_equality
    constrained = problem.u_max is not None
    if constrained:
        pr.cost = _c.ControlCost.l1_box
        ub = problem.u_max / np.asarray(sc.control_scale)
        pr.u_min = -ub
        pr.u_max = ub
    return Transcription(model, dmap, pr, sc, x0, constrained, problem.nonlinear_discretization, dt)


def rollout(tr, U_si: np.ndarray) -> np.ndarray:
    """States (N+1, 12; m, m/s) of the planning map of ``tr`` under U_si (N, 3; newtons)."""
    x = tr.problem.x0.copy()
    X = [x]
    U = np.asarray(U_si) / np.asarray(tr.scaling.control_scale)[None, :]
    for k in range(U.shape[0]):
        x, _, _ = tr.dmap.step(k, x, U[k])
        X.append(x)
    return np.array(X) * np.asarray(tr.scaling.state_scale)[None, :]


# ------------------------------------------------------------------------------------------- solvers
def solve_ilqr_admm(
    tr,
    rho: float,
    eps: float,
    max_iter: int = 300,
    ilqr_iters: int = 1,
    stop: str = "paper",
    multiplier_rescale: bool = True,
    U0=None,
):
    """iLQR-ADMM (one Gauss-Newton iLQR iteration per ADMM iteration by default) on the transcription
    ``tr``; ``stop="paper"`` is the published rule on ||U - Y|| <= ``eps``, ``"residual"`` the primal /
    dual residual rule (eps_abs = eps_rel = ``eps``). Returns the solver (``.U``, ``.Y``, ``.X``,
    ``.info``; scaled units, nu x N)."""
    stop = one_of(stop, "stop", ("paper", "residual"))
    st = _c.IlqrAdmmSettings()
    st.rho = rho
    if stop == "paper":
        st.stop = _c.StopRule.paper
        st.eps_paper = eps
    else:
        st.eps_abs = eps
        st.eps_rel = eps
    st.paper_multiplier_rescale = multiplier_rescale
    st.max_iter = max_iter
    st.ilqr_iters = ilqr_iters
    sol = _c.IlqrAdmmSolver(tr.dmap, tr.problem, st)
    sol.set_initial_controls(np.zeros((3, tr.problem.horizon)) if U0 is None else U0)
    sol.solve()
    return sol


def solve_scp(
    tr,
    U0=None,
    tol: float = 1e-10,
    eps: float = 1e-8,
    max_outer: int = 30,
    inner: str = "linear_admm",
    max_inner: int = 20000,
    globalization: str = "trust_region",
    time_limit: float = 0.0,
):
    """Sequential convex programming on the transcription ``tr`` (a Case of the papers, or
    :func:`transcribe`'s): re-linearize (exact map Jacobians), solve the convex L1
    subproblem (``inner="ilqr_admm"``: satgnc's iLQR-ADMM on the affine model, which is exact
    LQR-ADMM there, allocation-free, with the trust region as per-stage bounds; ``"linear_admm"``:
    the linear guidance AdmmSolver, the step scaled into the trust region), and accept steps by a
    trust-region ratio test (``globalization="trust_region"``) or an Armijo line search
    (``"line_search"``) on the true cost. ``time_limit``: seconds (0 = none). Returns the solver
    (``.U``, ``.X``, ``.info``; scaled units); ``info.status`` is ``solved`` only when the convex
    model predicts a decrease <= ``tol`` max(1, J) on a solved subproblem (table in
    docs/guidance_nonlinear.md). With ``tr.problem.terminal_equality`` (hard terminal state; the
    linear_admm inner only, ``inner="ilqr_admm"`` raises ValueError) ``solved`` also needs
    ``info.terminal_constraint_miss <= 1e-6 info.terminal_reference``, and an unreachable target ends
    ``inner_infeasible`` with ``info.infeasibility_certificate`` and ``info.infeasibility_margin > 0``;
    ``time_limit`` also bounds each subproblem (the inner gets the remaining time)."""
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
    sol = _c.ScpSolver(tr.dmap, tr.problem, st)
    if U0 is not None:
        sol.set_initial_controls(U0)
    sol.solve()
    return sol


def solve_linear_cw(tr, mu: float, mass: float, eps: float = 1e-9, discretization: str = "zoh"):
    """The linear-model (Clohessy-Wiltshire) optimum of the cost of ``tr`` from the same initial relative
    state (exact CW frame of the target, :func:`satgnc.cw_relative_state`), with the transcription's
    scaling so that Qf and alpha mean the same thing: satgnc's linear ADMM solver. ``mu`` (m^3/s^2) and
    ``mass`` (kg) give the CW model. Returns ``(U (N, 3) newtons, result dict (scaled, nu x N), x0_cw,
    state scale s (6,))``."""
    eps = as_real(eps, "eps", positive=True)  # errors named the solver field "eps_abs"
    sc = tr.scaling
    x0 = np.asarray(_c.cw_relative_state(tr.x0_si))
    n = np.sqrt(mu / np.linalg.norm(tr.x0_si[3:6]) ** 3)
    Ad, Bd = _c.cw_discretize(n, mass, tr.dt, discretization)
    s = np.concatenate([np.asarray(sc.state_scale)[0:3], np.asarray(sc.state_scale)[6:9]])
    su = np.asarray(sc.control_scale)
    As = Ad * s[None, :] / s[:, None]
    Bs = Bd * su[None, :] / s[:, None]
    st = _c.AdmmSettings()
    st.eps_abs = eps
    st.eps_rel = eps
    st.max_iterations = 100000
    w = tr.problem.stage_weight
    lo = np.asarray(tr.problem.u_min) if tr.constrained else np.zeros(0)
    hi = np.asarray(tr.problem.u_max) if tr.constrained else np.zeros(0)
    qf = float(np.asarray(tr.problem.Qf)[0, 0])
    alpha = np.asarray(tr.problem.alpha)
    solver = _c.AdmmSolver(
        [As],
        [Bs],
        [],
        tr.problem.horizon,
        x0 / s,
        np.zeros(6),
        qf * np.eye(6),
        np.zeros((0, 0)),
        np.zeros((0, 0)),
        w * alpha,
        0.0,
        lo,
        hi,
        0.0,
        bool(tr.problem.terminal_equality),
        st,
    )
    r = solver.solve()
    U = (np.asarray(r["Y"]) * su[:, None]).T
    return U, r, x0, s


# ------------------------------------------------------------------------------------------- plan
def plan(problem: RendezvousProblem, model: str = "linear", method: str | None = None, **options) -> Plan:
    """Plan a fuel-optimal rendezvous on the linear (CW) or the nonlinear (two-satellite) model.

    Parameters
    ----------
    problem : RendezvousProblem
        The rendezvous (SI: m, m/s, N, kg, s; target's CW frame, :data:`satgnc.guidance.CW_FRAME`).
    model : {"linear", "nonlinear"}, optional
        "linear": CW (default); "nonlinear": the two-satellite model (``problem.planner``).
    method : str, optional
        See :data:`METHODS` (default the first of the model): linear "admm"; nonlinear "scp"
        (sequential convex programming to the optimum of the transcription) or "ilqr_admm".
    **options
        "admm": ``eps`` (1e-9) and ``discretization`` (default ``problem.linear_discretization``);
        "scp": the options of :func:`solve_scp` (``tol``, ``eps``, ``max_outer``, ``inner``,
        ``max_inner``, ``globalization``, ``time_limit`` s, ``U0`` (N, 3) N); "ilqr_admm": ``rho``
        (1.0), ``eps`` (1e-6), ``stop`` ("residual" or "paper"), ``max_iter`` (300), ``ilqr_iters`` (1).

    Returns
    -------
    Plan
        ``U`` (N, 3) forces (N, CW frame), ``X`` (N+1, 6 or 12; m, m/s), ``status``, ``iterations``,
        ``objective``. The linear plan starts from the CW state of the nonlinear start
        (``problem.x0`` unless ``problem.x0_eci`` is given).

    Raises
    ------
    ValueError
        An unknown model, method or discretization.
    TypeError
        ``problem`` of another type, an option the method does not take.

    Examples
    --------
    >>> from satgnc import guidance
    >>> pb = guidance.RendezvousProblem(mu=3.986004418e14, radius=6878.137e3, mass=12.0,
    ...                                 x0=[-1500.0, 200.0, 50.0, 0.3, 0.0, -0.05], tf=3000.0,
    ...                                 horizon=30, alpha=1.0, Qf=1000.0, u_max=0.02,
    ...                                 terminal_equality=True)
    >>> p = guidance.plan(pb)
    >>> p.status, p.U.shape, bool(abs(p.U).max() <= 0.02 + 1e-9)
    ('solved', (30, 3), True)
    """
    if not isinstance(problem, RendezvousProblem):
        raise TypeError(f"problem: must be a RendezvousProblem, got {type(problem).__name__}")
    model = one_of(model, "model", MODELS)
    method = METHODS[model][0] if method is None else one_of(method, "method", METHODS[model])
    allowed = {
        "admm": ("eps", "discretization"),
        "scp": ("tol", "eps", "max_outer", "inner", "max_inner", "globalization", "time_limit", "U0"),
        "ilqr_admm": ("rho", "eps", "stop", "max_iter", "ilqr_iters"),
    }[method]
    for k in options:
        if k not in allowed:
            raise TypeError(f"{k}: not an option of method {method!r} (options: {', '.join(allowed)})")
    tr = transcribe(problem)
    cs = np.asarray(tr.scaling.control_scale)
    if model == "linear":
        disc = one_of(
            options.get("discretization", problem.linear_discretization),
            "discretization",
            LINEAR_DISCRETIZATIONS,
        )
        U, r, x0, s = solve_linear_cw(tr, problem.mu, problem.mass, options.get("eps", 1e-9), disc)
        from . import STATUS_NAMES, _admm_info

        X = np.asarray(r["X_flown"]).T * s[None, :]
        return Plan(
            "linear",
            method,
            U,
            X,
            tr.dt,
            problem.mass,
            STATUS_NAMES.get(int(r["status"]), str(r["status"])),
            int(r["iterations"]),
            float(r["objective"]),
            _admm_info(r, keep_raw=True),
        )
    if method == "scp":
        opts = dict(options)
        if opts.get("U0") is not None:
            U0 = as_real_array(opts["U0"], "U0", shape=(problem.horizon, 3))
            opts["U0"] = (U0 / cs[None, :]).T
        sol = solve_scp(tr, **opts)
        status = SCP_STATUS_NAMES[int(sol.info.status)]
        iterations = int(sol.info.outer_iterations)
        U_scaled = np.asarray(sol.U)
    else:
        sol = solve_ilqr_admm(
            tr,
            rho=as_real(options.get("rho", 1.0), "rho", positive=True),
            eps=as_real(options.get("eps", 1e-6), "eps", positive=True),
            max_iter=as_int(options.get("max_iter", 300), "max_iter", low=1),
            ilqr_iters=as_int(options.get("ilqr_iters", 1), "ilqr_iters", low=1),
            stop=options.get("stop", "residual"),
            multiplier_rescale=options.get("stop", "residual") == "paper",
        )
        status = ILQR_ADMM_STATUS_NAMES[int(sol.info.status)]
        iterations = int(sol.info.iterations)
        U_scaled = np.asarray(sol.Y)  # the sparse iterate, inside the bounds by construction of the prox
    U = (U_scaled * cs[:, None]).T
    X = rollout(tr, U)
    return Plan("nonlinear", method, U, X, tr.dt, problem.mass, status, iterations, _cost(tr, X, U), sol.info)


def _cost(tr, X: np.ndarray, U: np.ndarray) -> float:
    """The transcription's cost (scaled units) of U (N, 3; N) with its rollout X (N+1, 12; SI)."""
    e = X[-1] / np.asarray(tr.scaling.state_scale) - tr.problem.x_target
    u = U / np.asarray(tr.scaling.control_scale)[None, :]
    return float(0.5 * e @ np.asarray(tr.problem.Qf) @ e + tr.problem.stage_weight * np.abs(u).sum())
