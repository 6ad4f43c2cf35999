"""Parameter sensitivity alongside the STM: :func:`propagate_sensitivity` (issue 14 item 5).

The 6 x k matrix ``S(t) = dx(t)/dp`` for chosen force-model parameters ``p`` (``"mu"``, ``"cd"``,
``"cr"``) is integrated with the state and the STM through ``dS/dt = A S + da/dp``, ``S(t0) = 0``
(DOP853 or CVODES, in C++). Units: x in km, km/s; column j of S per unit of ``p_j`` (per km^3/s^2 for
mu, per unit Cd or Cr). This is what an OD or a filter needs to estimate Cd and Cr.
"""

from __future__ import annotations

import dataclasses
import numbers
from typing import Any

import numpy as np

from . import _satgnc
from ._ensemble import _check_times
from ._results import Result
from ._satgnc import EARTH_MU, EARTH_RADIUS
from ._validate import as_finite_positive, as_float_array, as_real
from .propagation import DEFAULT_ATOL, DEFAULT_RTOL, PropagationError, _force_model

__all__ = ["SENSITIVITY_PARAMETERS", "SensitivityResult", "propagate_sensitivity"]

#: Parameter names :func:`propagate_sensitivity` accepts (C++ ``satgnc::dynamics::ForceParameter``).
SENSITIVITY_PARAMETERS = ("mu", "cd", "cr")

_DEFAULT: Any = object()


@dataclasses.dataclass(frozen=True)
class SensitivityResult(Result):
    """States, STMs and parameter sensitivities at the output times.

    Attributes
    ----------
    times : ndarray (n,)
        Output times, s.
    states : ndarray (n, 6)
        ``[r km, v km/s]`` at each time.
    stms : ndarray (n, 6, 6)
        ``dx(t_i)/dx(t0)``.
    sensitivities : ndarray (n, 6, k)
        ``dx(t_i)/dp``, column j for ``parameters[j]`` (km or km/s per unit of the parameter).
    parameters : tuple of str
        The k parameter names in the columns' order.
    status, message : str
        ``"success"`` and ``""`` (a failure raises :class:`satgnc.PropagationError`).
    stats : dict
        Integrator statistics (steps, rhs_evals, ...).
    """

    times: np.ndarray
    states: np.ndarray
    stms: np.ndarray
    sensitivities: np.ndarray
    parameters: tuple[str, ...]
    status: str
    message: str
    stats: dict[str, Any]


def _check_parameters(parameters: Any) -> list[str]:
    if isinstance(parameters, str):
        parameters = [parameters]
    if not isinstance(parameters, (list, tuple)):
        raise TypeError(f"parameters: must be a name or a list of names from {SENSITIVITY_PARAMETERS}, "
                        f"got {type(parameters).__name__}")
    names: list[str] = []
    for p in parameters:
        if not isinstance(p, str):
            raise TypeError(f"parameters: every entry must be a str, got {type(p).__name__}")
        if p not in SENSITIVITY_PARAMETERS:
            raise ValueError(f"parameters: unknown parameter {p!r}; use {SENSITIVITY_PARAMETERS}")
        if p in names:
            raise ValueError(f"parameters: {p!r} is given twice")
        names.append(p)
    return names


def propagate_sensitivity(
    x0: Any,
    times: Any,
    parameters: Any,
    *,
    t0: float | None = None,
    mu: float = _DEFAULT,
    forces: Any = None,
    method: str = "dop853",
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    max_steps: int = 500_000,
    surface_radius: float | None = None,
) -> SensitivityResult:
    """Propagate ``x0`` (km, km/s) with its STM and ``dx/dp`` for the named parameters.

    Parameters
    ----------
    x0, times, t0, mu, forces, rtol, max_steps, surface_radius
        As in :func:`satgnc.propagate` (``forces`` may be a full :class:`satgnc.ForceModel`, e.g. one
        loaded with :func:`satgnc.load_force_model`).
    parameters : str or sequence of str
        Any subset of ``("mu", "cd", "cr")``, each at most once, in the order of S's columns; ``"cd"``
        needs a drag term, ``"cr"`` an SRP term. ``[]`` returns the plain STM propagation (bit-for-bit
        that of :func:`satgnc.propagate`) with a ``(n, 6, 0)`` sensitivity.
    method : {"dop853", "adams", "bdf"}
        DOP853 (default; two arcs from ``t0`` allowed) or CVODES (times on one side of ``t0``).
    atol : float
        Absolute tolerance (scalar, > 0) for every component (state, STM, S).

    Returns
    -------
    SensitivityResult

    Raises
    ------
    ValueError, TypeError
        Bad input naming the argument (an unknown or repeated parameter, ``"cr"`` without SRP, ...).
    PropagationError
        The integrator stopped early.
    """
    names = _check_parameters(parameters)
    x = as_float_array(x0, "x0")
    if x.shape != (6,):
        raise ValueError(f"x0: must have shape (6,) = [r km, v km/s], got {x.shape}")
    t = _check_times(times)
    t0f = float(t[0]) if t0 is None else as_finite_positive(t0, "t0", positive=False)
    mu_given = mu is not _DEFAULT
    muf = as_finite_positive(EARTH_MU if not mu_given else mu, "mu")
    rtolf = as_finite_positive(rtol, "rtol")
    if not rtolf < 1.0:
        raise ValueError(f"rtol: must be < 1, got {rtol!r}")
    if not isinstance(atol, numbers.Real) or isinstance(atol, bool):
        raise TypeError(f"atol: must be a real scalar, got {type(atol).__name__}")
    atolf = as_finite_positive(atol, "atol")
    if isinstance(max_steps, bool) or not isinstance(max_steps, numbers.Integral):
        raise TypeError(f"max_steps: must be an int, got {type(max_steps).__name__}")
    if not 0 < max_steps <= 2**62:
        raise ValueError(f"max_steps: must be in [1, 2**62], got {max_steps}")
    if not isinstance(method, str):
        raise TypeError(f"method: must be a string, got {type(method).__name__}")
    if method not in ("dop853", "adams", "bdf"):
        raise ValueError(f"method: unknown {method!r}; use 'dop853', 'adams' or 'bdf'")
    if surface_radius is not None:
        surface = as_real(surface_radius, "surface_radius", nonnegative=True)
    else:
        surface = EARTH_RADIUS if muf == EARTH_MU else 0.0
    model = _force_model(forces, muf, mu_given)
    tl = t.tolist()
    if method == "dop853":
        st = _satgnc.propagate_dop853_sensitivity(x, t0f, tl, model, names, rtolf, atolf, int(max_steps),
                                                  surface)
    else:
        st = _satgnc.propagate_cvodes_sensitivity(x, t0f, tl, model, names, method, rtolf, atolf,
                                                  int(max_steps), surface)
    traj = st.trajectory
    if not traj.success:
        raise PropagationError(traj.message, traj)
    return SensitivityResult(times=traj.times, states=traj.states, stms=traj.stms,
                             sensitivities=st.sensitivities, parameters=tuple(st.parameters),
                             status=traj.status, message=traj.message, stats=traj.stats)
