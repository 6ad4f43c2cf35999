"""satgnc.guidance: fuel-optimal (L1) guidance by ADMM with a Riccati step.

Everything is in the caller's units (the rendezvous scenario uses m, m/s, N, kg, s or the published
implementation's scaled units, see :mod:`satgnc.scenarios.l1_rendezvous`). The C++ solver is
``satgnc/guidance/admm.hpp``; this module validates numpy input and returns numpy results.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from .. import _satgnc
from .. import _validate as _v
from .._results import Result, adopt_dict, deprecated
from .._validate import as_bool, as_real, as_real_array, check_magnitude, one_of

__all__ = [
    "AdmmInfo",
    "AdmmSettings",
    "L1Result",
    "L1Solver",
    "STATUS_NAMES",
    "CW_FRAME",
    "cw_discretize",
    "cw_matrices",
    "cw_stm",
    "cw_to_hill",
    "hill_to_cw",
    "solve_l1",
]

AdmmSettings = _satgnc.AdmmSettings
# Read from the C++ status table (satgnc/core/status.hpp), never re-typed: value -> name.
STATUS_NAMES = {int(v): k for k, v in _satgnc.AdmmStatus.__members__.items()}


_OVERFLOW = "the solver's products overflow double precision (hint: scale the problem)"


def _array(value: Any, name: str, ndim: int | tuple[int, ...], shape: tuple[int, ...] | None = None,
           *, finite: bool = True) -> np.ndarray:
    # finite: no NaN / Inf, and |entries| < 1e100 (A = 1e300 gave a numerical_error with a NaN
    # objective, x0 = 1e300 an infinite one)
    arr = as_real_array(value, name, ndim=ndim, shape=shape, finite=finite)
    return check_magnitude(arr, name, 1e100, _OVERFLOW) if finite else arr


def cw_matrices(n: float, mass: float) -> tuple[np.ndarray, np.ndarray]:
    """Continuous Clohessy-Wiltshire matrices in guidance's CW frame.

    The frame is :data:`CW_FRAME` (y radial, z orbit normal, x = y cross z = minus along-track);
    :func:`cw_to_hill` / :func:`hill_to_cw` convert to and from the Hill frame of
    :func:`satgnc.analysis.cw_model` (x radial, y along-track).

    Parameters
    ----------
    n : float
        Mean motion of the target's circular orbit (rad/s, > 0).
    mass : float
        Chaser mass (kg, > 0); the input u is a force (N).

    Returns
    -------
    A : numpy.ndarray
        (6, 6), state [x y z vx vy vz] (m, m/s).
    B : numpy.ndarray
        (6, 3), (m/s^2) per N.

    Raises
    ------
    ValueError
        ``n`` or ``mass`` not finite and > 0.

    Examples
    --------
    >>> from satgnc import guidance
    >>> A, B = guidance.cw_matrices(0.0011, 12.0)
    >>> A.shape, B.shape, round(float(B[3, 0]), 6)
    ((6, 6), (6, 3), 0.083333)
    """
    return _satgnc.cw_matrices(as_real(n, "n", positive=True), as_real(mass, "mass", positive=True))


def cw_stm(n: float, t: float) -> np.ndarray:
    """Analytic CW state transition matrix in guidance's CW frame (:data:`CW_FRAME`).

    Parameters
    ----------
    n : float
        Mean motion (rad/s, > 0).
    t : float
        Elapsed time (s; finite, any sign).

    Returns
    -------
    numpy.ndarray
        (6, 6) map of the state [x y z vx vy vz] (m, m/s) over ``t``.

    Raises
    ------
    ValueError
        ``n`` not finite and > 0, or ``t`` not finite.

    Examples
    --------
    A whole orbit brings a radial offset back (x is minus along-track, y radial):

    >>> import math
    >>> import numpy as np
    >>> from satgnc import guidance
    >>> n = 0.0011
    >>> Phi = guidance.cw_stm(n, 2 * math.pi / n)
    >>> bool(np.allclose(Phi @ [0, 0, 0, 0, 0, 1.0], [0, 0, 0, 0, 0, 1.0], atol=1e-9))
    True
    """
    return _satgnc.cw_stm(as_real(n, "n", positive=True), as_real(t, "t"))


def cw_discretize(n: float, mass: float, dt: float, method: str = "zoh") -> tuple[np.ndarray, np.ndarray]:
    """Discrete CW pair in guidance's CW frame (:data:`CW_FRAME`: y radial, z normal, x = minus
    along-track).

    Parameters
    ----------
    n : float
        Mean motion (rad/s, > 0).
    mass : float
        Chaser mass (kg, > 0).
    dt : float
        Interval (s, > 0); the input is a force (N) held over each interval.
    method : {"zoh", "expm", "midpoint"}, optional
        "zoh" (analytic STM and input integral, default), "expm" (Van Loan matrix exponential) or
        "midpoint" (the published implementation's).

    Returns
    -------
    Ad : numpy.ndarray
        (6, 6), state [x y z vx vy vz] (m, m/s).
    Bd : numpy.ndarray
        (6, 3), per N.

    Raises
    ------
    ValueError
        Non-positive or non-finite ``n``, ``mass``, ``dt``; an unknown method.

    Examples
    --------
    >>> import numpy as np
    >>> from satgnc import guidance
    >>> Ad, Bd = guidance.cw_discretize(0.0011, 12.0, 50.0)
    >>> Ad2, Bd2 = guidance.cw_discretize(0.0011, 12.0, 50.0, "expm")
    >>> bool(np.allclose(Bd, Bd2, rtol=1e-10, atol=1e-14))
    True
    """
    method = one_of(method, "method", ("zoh", "expm", "midpoint"))
    return _satgnc.cw_discretize(as_real(n, "n", positive=True), as_real(mass, "mass", positive=True),
                                 as_real(dt, "dt", positive=True), method)


#: Guidance's CW frame: y radial (out), z orbit normal, x = y cross z (minus along-track). The Hill
#: frame of :func:`satgnc.analysis.cw_model` is x radial, y along-track, z normal.
CW_FRAME = "y radial, z orbit normal, x = y cross z (minus along-track)"
_TO_HILL = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # Hill = _TO_HILL @ CW


def _rotate_states(x: Any, rt: np.ndarray) -> np.ndarray:
    """Position and velocity of the 6-state(s) x (last axis) each times rt (a rotation transposed)."""
    a = as_real_array(x, "x")
    if a.shape[-1:] != (6,):
        raise ValueError(f"x: must have 6 components in its last axis, got shape {a.shape}")
    out = np.empty_like(a, dtype=float)
    out[..., 0:3] = a[..., 0:3] @ rt
    out[..., 3:6] = a[..., 3:6] @ rt
    return out


def cw_to_hill(x: Any) -> np.ndarray:
    """A state from guidance's CW frame (:data:`CW_FRAME`) to the Hill frame of
    :func:`satgnc.analysis.cw_model` (x radial, y along-track, z normal).

    Parameters
    ----------
    x : array_like
        State(s) [x y z vx vy vz] (m, m/s), shape (6,) or (..., 6), CW frame.

    Returns
    -------
    numpy.ndarray
        The same shape, Hill frame: radial = y, along-track = -x, normal = z.

    Raises
    ------
    ValueError
        A last axis that is not 6, non-finite values.

    Examples
    --------
    >>> from satgnc import guidance
    >>> guidance.cw_to_hill([-1500.0, 200.0, 50.0, 0.3, 0.0, -0.05]).tolist()
    [200.0, 1500.0, 50.0, 0.0, -0.3, -0.05]
    """
    return _rotate_states(x, _TO_HILL.T)


def hill_to_cw(x: Any) -> np.ndarray:
    """The inverse of :func:`cw_to_hill`: Hill frame to guidance's CW frame (:data:`CW_FRAME`).

    Parameters
    ----------
    x : array_like
        Hill-frame state(s) (x radial, y along-track, z normal; m, m/s), shape (6,) or (..., 6).

    Returns
    -------
    numpy.ndarray
        The same shape, CW frame (y radial, x = minus along-track).

    Raises
    ------
    ValueError
        A last axis that is not 6, non-finite values.

    Examples
    --------
    >>> from satgnc import guidance
    >>> guidance.hill_to_cw([200.0, 1500.0, 50.0, 0.0, -0.3, -0.05]).tolist()
    [-1500.0, 200.0, 50.0, 0.3, 0.0, -0.05]
    """
    return _rotate_states(x, _TO_HILL)


#: The fields of AdmmInfo, in order; each is also an L1Result attribute of the same name and value.
_INFO_FIELDS = (
    "status", "message", "iterations", "primal_residual", "dual_residual", "solve_time", "eps_primal",
    "eps_dual", "paper_criterion", "objective", "objective_u", "terminal_miss", "rho", "factorizations",
    "rho_updates", "polished", "polish_attempts", "condensed", "primal_objective", "dual_objective",
    "duality_gap", "certified", "ipm_iterations", "ipm_solved", "dual_recoveries",
)


@dataclasses.dataclass(frozen=True)
class AdmmInfo(Result):
    """Run record of one ADMM solve, read-only: the C++ ``AdmmInfo`` (``core::InfoBase`` of the solver
    contract) as ``L1Result.info`` and, for linear plans, ``guidance.Plan.info``.

    ``status`` is a name of :data:`STATUS_NAMES` (``"solved"``, ...), ``message`` its text,
    ``iterations`` the ADMM iterations, ``primal_residual`` / ``dual_residual`` the residuals at the
    returned iterate and ``eps_primal`` / ``eps_dual`` their tolerances (the problem's units),
    ``solve_time`` the wall time of the solve (s); then the ADMM extras (``rho``, ``factorizations``,
    ``polished``, the objectives and ``duality_gap``, ...) and the interior-point fields
    ``ipm_iterations`` (0: the IPM did not run), ``ipm_solved`` and ``dual_recoveries``."""

    status: str
    message: str
    iterations: int
    primal_residual: float
    dual_residual: float
    solve_time: float
    eps_primal: float
    eps_dual: float
    paper_criterion: float
    objective: float
    objective_u: float
    terminal_miss: float
    rho: float
    factorizations: int
    rho_updates: int
    polished: bool
    polish_attempts: int
    condensed: bool
    primal_objective: float
    dual_objective: float
    duality_gap: float
    certified: bool
    ipm_iterations: int
    ipm_solved: bool
    #: state constraints: least-squares multiplier recoveries on the IPM's converged plan (0: none)
    dual_recoveries: int = 0
    #: linear guidance.Plan only: the extension's result dict (scaled units, arrays nu x N), what
    #: ``Plan.info`` was before it became this object; None otherwise
    raw: Mapping[str, Any] | None = dataclasses.field(default=None, repr=False, compare=False)

    @property
    def converged(self) -> bool:
        """True when ``status`` is ``"solved"`` (residuals and duality gap within their tolerances)."""
        return self.status == "solved"

    def __getitem__(self, key: str) -> Any:
        # Plan.info was the result dict: its keys still answer, unchanged, with a warning
        if self.raw is not None and isinstance(key, str) and key in self.raw:
            deprecated(f"Plan.info[{key!r}] (the ADMM result dict)",
                       f"Plan.info.{key}" if key in _INFO_FIELDS[2:] else f"Plan.info.raw[{key!r}]",
                       stacklevel=2)
            return self.raw[key]
        return super().__getitem__(key)


def _admm_info(d: Mapping[str, Any], *, keep_raw: bool = False) -> AdmmInfo:
    """AdmmInfo from the extension's result dict ``d`` (AdmmSolver.solve()); ``keep_raw``: d as ``raw``."""
    vals = {k: d[k] for k in _INFO_FIELDS[2:]}
    return AdmmInfo(status=STATUS_NAMES[d["status"]], message=d["status_name"], **vals,
                    raw=d if keep_raw else None)


#: the extension's nu x N / nx x (N+1) arrays that L1Result holds time-major (transposed views)
_TIME_MAJOR = ("X", "U", "Y", "Lambda", "X_flown")
#: L1Result's fields that can hold an array (adopt_dict freezes them)
_L1_ARRAYS = (*_TIME_MAJOR, "terminal_multiplier", "infeasibility_certificate", "state_multipliers")


@dataclasses.dataclass(frozen=True)
class L1Result(Result):
    """Solution of :func:`solve_l1`, read-only. Arrays are time-major: X (N+1, nx), U/Y/Lambda (N, nu).

    ``Y`` is the sparse plan to fly; ``X_flown`` its rollout; ``U``/``X`` the LQR iterate. ``status``
    is one of :data:`STATUS_NAMES` (``"solved"``, ...), ``message`` its text, ``iterations`` the ADMM
    iterations. Arrays are read-only copies (``r.Y.copy()`` gives a writeable one)."""

    status: str
    message: str
    iterations: int
    X: np.ndarray
    U: np.ndarray
    Y: np.ndarray
    Lambda: np.ndarray
    X_flown: np.ndarray
    terminal_multiplier: np.ndarray
    objective: float
    objective_u: float
    terminal_miss: float
    primal_residual: float
    dual_residual: float
    eps_primal: float
    eps_dual: float
    paper_criterion: float
    rho: float
    factorizations: int
    rho_updates: int
    polished: bool
    polish_attempts: int
    solve_time: float
    condensed: bool = False  # the condensed x/u step was used (AdmmSettings.condensed)
    #: objective of Y (= objective) and the Fenchel dual bound D <= optimum (objective units)
    primal_objective: float = float("nan")
    dual_objective: float = float("nan")
    #: relative duality gap (P - D) / max(|P|, |D|); "solved" requires |gap| <= settings.eps_gap
    duality_gap: float = float("nan")
    #: the active-set polish certificate holds (the result is the exact optimum up to rounding)
    certified: bool = False
    #: "primal_infeasible": unit y (nx,) with y'(xf - x_N(0)) > max over the box of y' dx_N/dU U
    infeasibility_certificate: np.ndarray | None = None
    #: interior-point iterations of this solve (0: the IPM did not run; settings.method)
    ipm_iterations: int = 0
    #: the plan is the interior-point method's, "solved" by the same gap test as ADMM's
    ipm_solved: bool = False
    #: state constraints: least-squares multiplier recoveries tried on the IPM's converged plan (its
    #: active set), each checked by the same Fenchel bound; 0 when the IPM's own multipliers sufficed
    dual_recoveries: int = 0
    #: state constraints only (issue 16): largest violation of a constraint row by X_flown (state
    #: units; cones: distance to the surface) and its tolerance eps_abs + eps_rel ||X_flown||_inf
    max_violation: float = float("nan")
    violation_tolerance: float = float("nan")
    #: state constraints only: multipliers of the constraint rows (unit-norm rows; see docs/guidance.md)
    state_multipliers: np.ndarray | None = None
    #: state constraints, method admm_ipm, neither method certified: True when the returned plan is the
    #: interior-point method's last one (the better plan by the honest rule), False when it is ADMM's
    ipm_plan: bool = False

    @property
    def converged(self) -> bool:
        """True when ``status`` is ``"solved"`` (residuals and duality gap within their tolerances)."""
        return self.status == "solved"

    @property
    def info(self) -> AdmmInfo:
        """The run record (status, iterations, residuals, solve time, ADMM and IPM fields) as one
        read-only :class:`AdmmInfo`; each of its fields equals the attribute of the same name here."""
        return AdmmInfo(**{k: getattr(self, k) for k in _INFO_FIELDS})


def _settings(settings: Any) -> Any:
    if settings is None:
        return AdmmSettings()
    if isinstance(settings, AdmmSettings):
        return settings
    if isinstance(settings, dict):
        st = AdmmSettings()
        for key, val in settings.items():
            if not hasattr(st, key):
                raise ValueError(f"settings: unknown key {key!r}")
            if key == "stopping" and isinstance(val, str):
                if val not in ("residuals", "paper"):
                    raise ValueError("settings: stopping must be 'residuals' or 'paper'")
                val = getattr(_satgnc.StoppingRule, val)
            elif key == "method" and not isinstance(val, _satgnc.AdmmMethod):
                val = getattr(_satgnc.AdmmMethod, one_of(val, "settings.method", ("admm", "admm_ipm", "ipm")))
            else:
                # the type of the current value decides the check (no pybind11 signature dumps)
                cur = getattr(st, key)
                if isinstance(cur, bool):
                    val = _v.as_bool(val, f"settings.{key}")
                elif isinstance(cur, int) and not isinstance(cur, (_satgnc.StoppingRule, _satgnc.AdmmMethod)):
                    val = _v.as_int(val, f"settings.{key}", low=-(2**31), high=2**31 - 1)
                elif isinstance(cur, float):
                    val = _v.as_real(val, f"settings.{key}", finite=False)
            setattr(st, key, val)
        return st
    raise TypeError(f"settings: must be None, a dict or AdmmSettings, got {type(settings).__name__}")


class L1Solver:
    """Set up once (validation, allocation, Riccati factorization), solve many times.

    Parameters (nx states, nu controls, N = horizon intervals):
      A: (nx, nx) or (N, nx, nx); B: (nx, nu) or (N, nx, nu); c: None, (nx,) or (N, nx) drift;
      x0: (nx,); xf: (nx,) target (default 0); Qf: (nx, nx) terminal weight (PSD);
      Q: stage weight on x_k - xf (k = 1..N-1); R: stage weight on u_k;
      l1_weights: (nu,) per-axis fuel weights (default ones if no group weight);
      group_l2_weight: weight of ||u_k||_2 (one gimballed engine);
      u_lower/u_upper: (nu,) per-axis bounds; u_norm_max: ||u_k||_2 bound (group-L2 only);
      terminal_equality: enforce x_N = xf exactly; settings: dict or AdmmSettings.
    State constraints (issue 16; see :func:`satgnc.guidance.state_constraints.parse_state_constraints`):
      half_spaces: dict nodes (M,), a (M, nx), b (M,): a_i' x_{node_i} <= b_i;
      state_lower/state_upper: (nx,) or (len(nodes), nx) bounds at state_box_nodes (default 1..N);
      approach_cone: dict nodes, axis (3,), half_angle_deg in (0, 90), apex_offset, position_index;
      closing_velocity: dict nodes, axis, intercept, slope (|a.v| <= min_i(intercept_i + slope_i a.p)).
      With any of them the state-constrained ADMM runs (C++ StateConstrainedAdmm; diagonal R, no
      group-L2 / ball, residual rule; the IPM endgame and the polish do not apply).
    """

    def __init__(self, A, B, x0, *, horizon: int | None = None, c=None, xf=None, Qf=None, Q=None, R=None,
                 l1_weights=None, group_l2_weight: float = 0.0, u_lower=None, u_upper=None,
                 u_norm_max: float = 0.0, terminal_equality: bool = False, settings=None,
                 half_spaces=None, state_lower=None, state_upper=None, state_box_nodes=None,
                 approach_cone=None, closing_velocity=None):
        A = _array(A, "A", (2, 3))
        B = _array(B, "B", (2, 3))
        if A.ndim == 3 and horizon is None:
            horizon = A.shape[0]
        if B.ndim == 3 and horizon is None:
            horizon = B.shape[0]
        if horizon is None:
            raise ValueError("horizon: required when A and B are time-invariant (2-D)")
        if isinstance(horizon, bool) or not isinstance(horizon, (int, np.integer)) or horizon < 1:
            raise ValueError(f"horizon: must be an integer >= 1, got {horizon!r}")
        horizon = int(horizon)
        if horizon > 2**31 - 1:
            raise ValueError(f"horizon: must be < 2**31, got {horizon} (the workspace would need about "
                             f"{horizon * 3.6e3 / 1e9:.3g} GB for nx = 6, nu = 3; see "
                             "AdmmSettings.max_workspace_bytes)")
        As = [A] if A.ndim == 2 else list(A)
        Bs = [B] if B.ndim == 2 else list(B)
        for name, seq in (("A", As), ("B", Bs)):
            if len(seq) not in (1, horizon):
                raise ValueError(f"{name}: must hold 1 or horizon = {horizon} matrices, got {len(seq)}")
        nx = As[0].shape[0]
        if As[0].shape != (nx, nx):
            raise ValueError(f"A: must be square (nx, nx), got {As[0].shape}")
        if Bs[0].shape[0] != nx:
            raise ValueError(f"B: must have nx = {nx} rows, got shape {Bs[0].shape}")
        nu = Bs[0].shape[1]
        if c is None:
            cs = []
        else:
            c = _array(c, "c", (1, 2))
            cs = [c] if c.ndim == 1 else list(c)
            if cs[0].shape != (nx,):
                raise ValueError(f"c: must have nx = {nx} entries per step, got {cs[0].shape}")
        x0 = _array(x0, "x0", 1, (nx,))
        xf = np.zeros(nx) if xf is None else _array(xf, "xf", 1, (nx,))
        Qf = np.zeros((nx, nx)) if Qf is None else _array(Qf, "Qf", 2, (nx, nx))
        Q = np.zeros((0, 0)) if Q is None else _array(Q, "Q", 2, (nx, nx))
        R = np.zeros((0, 0)) if R is None else _array(R, "R", 2, (nu, nu))
        if l1_weights is None:
            w = np.ones(nu) if group_l2_weight == 0 else np.zeros(0)
        else:
            w = _array(l1_weights, "l1_weights", 1, (nu,))
            if np.any(w < 0):
                raise ValueError("l1_weights: must be >= 0 (a fuel weight cannot be negative)")
        lo = np.zeros(0) if u_lower is None else _array(u_lower, "u_lower", 1, (nu,), finite=False)
        hi = np.zeros(0) if u_upper is None else _array(u_upper, "u_upper", 1, (nu,), finite=False)
        if np.any(np.isnan(lo)) or np.any(np.isnan(hi)):
            raise ValueError("u_lower/u_upper: must not be NaN")
        if lo.size and hi.size and np.any(lo > hi):
            raise ValueError(f"u_lower: must be <= u_upper on every axis (got {lo} > {hi})")
        group_l2_weight = as_real(group_l2_weight, "group_l2_weight", nonnegative=True)
        u_norm_max = as_real(u_norm_max, "u_norm_max", nonnegative=True)
        terminal_equality = as_bool(terminal_equality, "terminal_equality")  # bool("false") is True
        st = _settings(settings)
        if not (np.isfinite(st.rho) and st.rho > 0):
            raise ValueError(f"settings.rho: must be finite and > 0, got {st.rho}")
        self.nx, self.nu, self.horizon = nx, nu, horizon
        self._counts = (len(As), len(Bs), len(cs))
        from .state_constraints import parse_state_constraints
        sc = parse_state_constraints(nx, horizon, half_spaces=half_spaces, state_lower=state_lower,
                                     state_upper=state_upper, state_box_nodes=state_box_nodes,
                                     approach_cone=approach_cone, closing_velocity=closing_velocity)
        self._state_constrained = sc is not None
        if sc is not None:
            if st.stopping != _satgnc.StoppingRule.residuals:
                raise ValueError("settings.stopping: state constraints need the residual rule")
            if R.size and np.any(R != np.diag(np.diag(R))):
                raise ValueError("R: must be diagonal with state constraints (closed-form prox)")
            if group_l2_weight != 0 or u_norm_max != 0:
                raise ValueError("group_l2_weight/u_norm_max: not supported with state constraints")
            prob = _satgnc.LtvProblem(A=As, B=Bs, c=cs, horizon=horizon, x0=x0, xf=xf, Qf=Qf, Q=Q, R=R,
                                      l1_weights=w, u_lower=lo, u_upper=hi,
                                      terminal_equality=bool(terminal_equality))
            self._solver = _satgnc.StateConstrainedAdmm(prob, *sc, st)
            return
        try:
            self._solver = _satgnc.AdmmSolver(As, Bs, cs, horizon, x0, xf, Qf, Q, R, w,
                                              float(group_l2_weight), lo, hi, float(u_norm_max),
                                              bool(terminal_equality), st)
        except ValueError as e:
            # Qf = 1e300 I overflowed the Riccati recursion and the error blamed "rho".
            if str(e).startswith("rho: Riccati factorization failed"):
                for name, v in (("Qf", Qf), ("Q", Q), ("R", R), ("group_l2_weight", group_l2_weight)):
                    big = float(np.max(np.abs(v))) if np.size(v) else 0.0
                    if big >= 1e150:
                        raise ValueError(f"{name}: entries up to {big:.3g} overflow the Riccati recursion "
                                         "(hint: scale the cost; weights must be below 1e150)") from None
            raise

    def solve(self) -> L1Result:
        """Run ADMM (never raises for solver outcomes: check ``result.status``)."""
        d = self._solver.solve()  # a fresh dict of fresh arrays: adopted, not copied
        d["status"] = STATUS_NAMES[d["status"]]
        d["message"] = d.pop("status_name")
        del d["workspace_bytes"]
        d.pop("state_consensus", None)
        for k in _TIME_MAJOR:
            d[k] = d[k].T
        return adopt_dict(L1Result, d, _L1_ARRAYS)

    def set_half_space(self, i: int, node: int, a, b: float) -> None:
        """Replace half-space ``i`` (its row in ``half_spaces``) by a' x_node <= b, without allocation
        (sequential convex programming); the next solve starts warm from the last iterate."""
        if not self._state_constrained:
            raise ValueError("half_spaces: the solver was built without half_spaces")
        a = _array(a, "a", 1, (self.nx,))
        if not self._solver.set_half_space(_v.as_int(i, "i"), _v.as_int(node, "node"), a, as_real(b, "b")):
            raise ValueError(f"i/node/a: half-space {i} at node {node} rejected (index beyond half_spaces, "
                             f"node outside 1..{self.horizon} or a = 0)")

    def warm_start(self, Y, Lambda) -> None:
        """Start the next solve from Y, Lambda (N, nu) each, e.g. a shifted previous solution."""
        if self._state_constrained:
            raise ValueError("warm_start: with state constraints the solver restarts from its last iterate")
        Y = _array(Y, "Y", 2, (self.horizon, self.nu))
        L = _array(Lambda, "Lambda", 2, (self.horizon, self.nu))
        self._solver.warm_start(np.ascontiguousarray(Y.T), np.ascontiguousarray(L.T))

    def set_x0(self, x0) -> None:
        """New initial state (receding horizon); the Riccati gains are reused."""
        self._solver.set_x0(_array(x0, "x0", 1, (self.nx,)))

    def update_settings(self, settings) -> None:
        self._solver.update_settings(_settings(settings))

    def update_dynamics(self, A, B, c=None) -> None:
        """Replace the dynamics in place (re-linearization, sequential convex programming, LTV MPC).

        A (N, nx, nx), B (N, nx, nu) and c (N, nx) with the counts given at construction: the solver
        must have been built time-varying (N matrices each), and c is required exactly when c was
        given then. The cached factorization is refreshed without allocation; the warm start is kept.
        """
        if self._state_constrained:
            raise ValueError("update_dynamics: not supported with state constraints yet")
        na, nb, nc = self._counts
        N, nx, nu = self.horizon, self.nx, self.nu
        if na != N or nb != N or nc not in (0, N):
            raise ValueError(f"A, B: update_dynamics needs a solver built with horizon = {N} matrices of A "
                             f"and of B (and of c if any); this one holds {na} / {nb} / {nc}")
        A = _array(A, "A", 3, (N, nx, nx))
        B = _array(B, "B", 3, (N, nx, nu))
        if nc == 0 and c is not None:
            raise ValueError("c: the solver was built without c; pass c=None")
        if nc == N and c is None:
            raise ValueError(f"c: required, shape ({N}, {nx}) (the solver was built with c)")
        cs = [] if c is None else list(_array(c, "c", 2, (N, nx)))
        if not self._solver.update_dynamics(list(A), list(B), cs):
            raise ValueError("A, B: the updated problem cannot be factored at the current rho "
                             "(R + rho I must stay positive definite)")

    def objective_of(self, U) -> float:
        """Objective of flying U (N, nu) from x0."""
        U = _array(U, "U", 2, (self.horizon, self.nu))
        return self._solver.objective_of(np.ascontiguousarray(U.T))


def solve_l1(A, B, x0, **kwargs) -> L1Result:
    """One-shot :class:`L1Solver` set-up and solve: min alpha sum |u_k|_1 (+ terminal cost) subject to
    x_{k+1} = A x_k + B u_k (+ c_k).

    Parameters
    ----------
    A : array_like
        (nx, nx) or (N, nx, nx) per step (units of the user's state, e.g. m, m/s).
    B : array_like
        (nx, nu) or (N, nx, nu) (state units per input unit, e.g. per N).
    x0 : array_like
        (nx,) initial state, in the frame of A and B (for rendezvous, guidance's CW frame
        :data:`CW_FRAME`, m and m/s).
    **kwargs
        The keywords of :class:`L1Solver`: ``horizon`` N, ``xf``, ``Qf``, ``Q``, ``R``,
        ``l1_weights``, ``u_lower`` / ``u_upper`` (input units, e.g. N), ``terminal_equality``,
        ``settings`` (:class:`AdmmSettings`), state constraints, ...

    Returns
    -------
    L1Result
        ``status`` (``"solved"`` only when the residual tests and the duality gap hold), ``U`` (N, nu),
        ``X`` (N+1, nx) time-major, objective, residuals and certificates.

    Raises
    ------
    ValueError
        Naming the argument: wrong shapes, non-finite entries, a negative weight, lower > upper.
    TypeError
        Unknown keywords or non-numeric arrays.

    Examples
    --------
    A double integrator (m, m/s; u in m/s^2) brought to rest at the origin in 20 steps:

    >>> import numpy as np
    >>> from satgnc import guidance
    >>> A = np.array([[1.0, 1.0], [0.0, 1.0]])
    >>> B = np.array([[0.5], [1.0]])
    >>> r = guidance.solve_l1(A, B, [10.0, 0.0], horizon=20, terminal_equality=True,
    ...                       u_lower=[-1.0], u_upper=[1.0])
    >>> r.status, r.U.shape, bool(np.linalg.norm(r.X[-1]) < 1e-4)
    ('solved', (20, 1), True)
    """
    return L1Solver(A, B, x0, **kwargs).solve()


# Issue 12: the rendezvous library (explicit problem and model parameters, time-major read-only results);
# guidance.nonlinear is its deprecated paper-bound form. ``plan`` is the function; its module is
# satgnc.guidance.planning.
from .flight import Flight, MpcRun, fly, mpc  # noqa: E402
from .planning import Plan, plan  # noqa: E402
from .problem import RendezvousProblem, satellite_params  # noqa: E402

__all__ += ["Flight", "MpcRun", "Plan", "RendezvousProblem", "fly", "mpc", "plan", "satellite_params"]


from .._namespace import public_dir as _public_dir  # noqa: E402

__dir__ = _public_dir(__name__)  # dir(): the API, not the imported modules (np, math, ...)
