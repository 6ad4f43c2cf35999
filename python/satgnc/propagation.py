"""Orbit propagation with the state transition matrix: ``satgnc.propagate``.

Units: km, km/s, s. A state is ``[x, y, z, vx, vy, vz]`` in an inertial frame. The STM
``Phi(t_i, t0) = d x(t_i) / d x(t0)`` comes from the variational equations (CVODES, Dormand-Prince) or
in closed form (Kepler).
"""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Sequence

import numpy as np

from . import _satgnc
from ._ensemble import EnsembleResult, _check_times, propagate_ensemble
from ._satgnc import (
    EARTH_MU,
    EARTH_RADIUS,
    ExponentialDrag,
    ForceModel,
    J2Gravity,
    Trajectory,
)
from ._validate import as_finite_positive, as_float_array, as_real, check_magnitude

__all__ = [
    "propagate",
    "propagate_ensemble",
    "EnsembleResult",
    "DEFAULT_RTOL",
    "DEFAULT_ATOL",
    "PropagationError",
    "Trajectory",
    "ForceModel",
    "J2Gravity",
    "ExponentialDrag",
    "available_methods",
    "elements_to_state",
]

_CVODES = ("adams", "bdf")

#: Default relative tolerance of :func:`propagate` and :func:`propagate_ensemble` (DOP853), chosen by
#: measurement (bench/propagation_defaults.py): 1 mm per day on LEO orbits (e <= 0.02), with J2, with
#: and without the STM. C++: ``satgnc::propagation::kDefaultOrbitRtol``.
DEFAULT_RTOL = 3e-12
#: Default absolute tolerance, km and km/s (C++ ``kDefaultOrbitAtol``).
DEFAULT_ATOL = 3e-14


class PropagationError(RuntimeError):
    """The integrator stopped before the last requested time.

    ``trajectory`` holds the outputs reached, ``t_reached`` the last time reached (s) and ``status``
    the reason (``"too_much_work"``, ``"too_much_accuracy"``, ``"error_test_failures"``,
    ``"convergence_failures"``, ``"rhs_failure"``, ``"solver_failure"``, or ``"impact"``: the orbit
    reached the surface, ``t_reached`` = the impact time). Raised without a trajectory (``None``) by
    other flights (:func:`satgnc.guidance.nonlinear.fly`), which give ``status`` and ``t_reached``.
    """

    def __init__(self, message: str, trajectory: Trajectory | None = None, *, status: str | None = None,
                 t_reached: float | None = None):
        super().__init__(message)
        self.trajectory = trajectory
        self.t_reached: float = trajectory.t_reached if trajectory is not None else float(t_reached)
        self.status: str = trajectory.status if trajectory is not None else str(status)


def available_methods() -> list[str]:
    """The integration methods this build provides.

    Returns
    -------
    list of str
        ``"adams"`` and ``"bdf"`` (CVODES), and ``"dop853"`` and ``"kepler"`` when the analytic
        bindings are built; any of them is a ``method`` of :func:`propagate` (orbits in km, km/s, s).

    Examples
    --------
    >>> import satgnc
    >>> "dop853" in satgnc.propagation.available_methods()
    True
    """
    out = list(_CVODES)
    if hasattr(_satgnc, "propagate_dop853"):
        out.append("dop853")
    if hasattr(_satgnc, "propagate_kepler"):
        out.append("kepler")
    return out


def _rot_z(t: float) -> np.ndarray:
    return np.array([[math.cos(t), -math.sin(t), 0.0], [math.sin(t), math.cos(t), 0.0], [0.0, 0.0, 1.0]])


def _rot_x(t: float) -> np.ndarray:
    return np.array([[1.0, 0.0, 0.0], [0.0, math.cos(t), -math.sin(t)], [0.0, math.sin(t), math.cos(t)]])


def elements_to_state(a: float, e: float, i: float, raan: float, argp: float, nu: float,
                      mu: float = EARTH_MU) -> np.ndarray:
    """Inertial state ``[r km, v km/s]`` of the classical orbital elements of an elliptic orbit.

    Parameters
    ----------
    a : float
        Semi-major axis, km (> 0). From the semi-latus rectum ``p``: ``a = p / (1 - e**2)``.
    e : float
        Eccentricity, ``0 <= e < 1`` (circular and elliptic orbits).
    i, raan, argp, nu : float
        Inclination, right ascension of the ascending node, argument of periapsis and true anomaly,
        **degrees** (finite; any value, taken modulo 360).
    mu : float, optional
        Gravitational parameter, km^3/s^2 (> 0; default Earth, ``satgnc.EARTH_MU``).

    Returns
    -------
    numpy.ndarray, shape (6,)
        ``[x, y, z, vx, vy, vz]`` (km, km/s) in the inertial frame the elements refer to (for Earth
        orbits, ECI: x to the vernal equinox, z to the pole): the perifocal position and velocity
        rotated by ``R3(-raan) R1(-i) R3(-argp)`` (Vallado, Algorithm 10 "COE2RV").

    Raises
    ------
    TypeError
        An argument is not a real number.
    ValueError
        ``a`` or ``mu`` not finite and > 0, ``e`` outside ``[0, 1)``, an angle not finite.

    Examples
    --------
    >>> import satgnc
    >>> x = satgnc.elements_to_state(7000.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    >>> x.round(6).tolist()
    [7000.0, 0.0, 0.0, 0.0, 7.546053, 0.0]
    """
    a = as_real(a, "a", positive=True)
    e = as_real(e, "e", nonnegative=True)
    if not e < 1.0:
        raise ValueError(f"e: must be < 1 (an elliptic orbit), got {e}")
    i, raan, argp, nu = (math.radians(as_real(x, n)) for x, n in ((i, "i"), (raan, "raan"), (argp, "argp"),
                                                                   (nu, "nu")))
    mu = as_real(mu, "mu", positive=True)
    p = a * (1.0 - e * e)
    r = p / (1.0 + e * math.cos(nu))
    r_pf = np.array([r * math.cos(nu), r * math.sin(nu), 0.0])
    v_pf = math.sqrt(mu / p) * np.array([-math.sin(nu), e + math.cos(nu), 0.0])
    R = _rot_z(raan) @ _rot_x(i) @ _rot_z(argp)
    return np.concatenate([R @ r_pf, R @ v_pf])


def _force_model(forces, mu: float, mu_given: bool) -> ForceModel:
    if forces is None:
        return ForceModel(mu=mu)
    if isinstance(forces, os.PathLike) or (isinstance(forces, str) and forces.lower().endswith(".toml")):
        # a force-model TOML (satgnc.load_force_model)
        from .forcemodel import load_force_model

        forces = load_force_model(forces)
    if isinstance(forces, ForceModel):
        if mu_given and forces.mu != mu:
            raise ValueError(f"mu: {mu} conflicts with forces.mu = {forces.mu}; give one of them")
        forces.validate()
        return forces
    terms = [forces] if isinstance(forces, (J2Gravity, ExponentialDrag)) else forces
    if not isinstance(terms, Sequence) or isinstance(terms, (str, bytes)):
        raise TypeError("forces: must be None, a ForceModel, a J2Gravity, an ExponentialDrag or a list "
                        f"of those terms, got {type(forces).__name__}")
    j2 = drag = None
    for term in terms:
        if isinstance(term, J2Gravity):
            if j2 is not None:
                raise ValueError("forces: J2Gravity given twice")
            j2 = term
        elif isinstance(term, ExponentialDrag):
            if drag is not None:
                raise ValueError("forces: ExponentialDrag given twice")
            drag = term
        else:
            raise TypeError(f"forces: unknown term {type(term).__name__}; use J2Gravity or ExponentialDrag")
    if j2 is not None and j2.mu != mu:
        if mu_given:
            raise ValueError(f"forces: J2Gravity.mu = {j2.mu} differs from mu = {mu}")
        mu = j2.mu
    return ForceModel(mu=mu, j2=j2, drag=drag)


class _Default:
    """The default of ``propagate(mu=...)``: the force model's mu (EARTH_MU without forces)."""

    def __repr__(self) -> str:
        return "<the forces' mu, else EARTH_MU = 398600.4418 km^3/s^2>"


_DEFAULT = _Default()
_MAX_SPAN = 1e12  # s


def propagate(
    x0,
    times,
    *,
    t0: float | None = None,
    mu: float = _DEFAULT,  # type: ignore[assignment]
    forces=None,
    method: str = "dop853",
    rtol: float = DEFAULT_RTOL,
    atol=DEFAULT_ATOL,
    with_stm: bool = True,
    max_steps: int = 500_000,
    surface_radius: float | None = None,
) -> Trajectory:
    """Propagate the state ``x0`` (km, km/s) given at ``t0`` to every time in ``times`` (s).

    Parameters
    ----------
    x0 : array_like, shape (6,)
        Initial state ``[r km, v km/s]`` at ``t0`` in an inertial frame (e.g. GCRF; the outputs are
        in the same frame); finite, ``|r| > 0``.
    times : array_like, shape (n,)
        Output times (s), strictly monotone in one direction (forward or backward) and on one side of
        ``t0``. A time equal to ``t0`` returns ``x0`` and the identity STM.
    t0 : float, optional
        Epoch of ``x0`` (s). Default: ``times[0]`` (so the first output is ``x0`` itself).
    mu : float, optional
        Central-body gravitational parameter, km^3/s^2 (default Earth, EGM-96 398600.4418).
    forces : None, ForceModel, J2Gravity, ExponentialDrag, a list of J2Gravity/ExponentialDrag, or a path
        Perturbations on top of point-mass gravity. ``None``: two-body. A path (an os.PathLike, or a
        str ending in ``.toml``) is a force-model TOML read with :func:`satgnc.load_force_model`
        (docs/force_models.md).
    method : {"dop853", "adams", "bdf", "kepler"}
        The fixed-size Dormand-Prince 8(5,3) integrator (default), CVODES Adams-Moulton, CVODES BDF
        (stiff cases, e.g. re-entry drag), or the analytic two-body solution (point mass only). See
        :func:`available_methods`. Measured on a LEO day with and without J2 (docs/propagation.md,
        "Defaults"): DOP853 is 5-8x faster than Adams at every accuracy, and its default tolerances
        meet 1 mm per day, which Adams meets at no tolerance down to 1e-12.
    rtol, atol : float
        Relative and absolute tolerances (> 0). Defaults ``DEFAULT_RTOL = 3e-12`` and
        ``DEFAULT_ATOL = 3e-14`` (km, km/s), chosen by measurement to meet 1 mm per day on LEO orbits.
        For the CVODES methods ``atol`` may also be 6 values (state) or, with the STM, 42 values
        (state, then the STM column by column); DOP853 takes a scalar.
    with_stm : bool
        Also return the 6x6 STMs.
    max_steps : int
        Step budget of the whole call (> 0). Exhausting it raises :class:`PropagationError`.
    surface_radius : float, optional
        Radius of the central body's surface (km, >= 0), for every method. Default: ``EARTH_RADIUS``
        (6378.1363 km) when the body is the Earth (``mu`` not given or equal to ``EARTH_MU``), else 0.
        ``x0`` at or below it is a ValueError naming ``x0``; an arc that reaches it before a requested
        time raises :class:`PropagationError` with ``status == "impact"`` and ``t_reached`` = the impact
        time (s), holding the outputs before it (CVODES root finding, a bisection on DOP853's dense
        output, Kepler's time to radius). 0 turns the surface off: then the numerical methods fail
        near r = 0 with a PropagationError (never NaN states), and Kepler stops with ``"impact"`` on a
        collision orbit through the centre, which the analytic solution would otherwise pass straight
        through.

    Returns
    -------
    Trajectory
        ``.times`` (n,), ``.states`` (n, 6), ``.stms`` (n, 6, 6) or None without the STM, ``.stats``
        (dict: steps, rhs_evals, ...), ``.status`` ("success").

    Raises
    ------
    ValueError, TypeError
        Bad input, naming the argument (non-finite state, ``|r| = 0``, ``mu <= 0``, unsorted or
        non-finite times, non-positive tolerances, wrong shapes or dtypes).
    PropagationError
        The integrator stopped early (or the orbit hit the surface: ``status == "impact"``); the
        message says the time reached and why, and ``err.trajectory`` holds the outputs reached.

    Examples
    --------
    One revolution of a circular orbit with J2 and the STM:

    >>> import math
    >>> import numpy as np
    >>> import satgnc
    >>> x0 = satgnc.elements_to_state(7000.0, 0.001, 51.6, 0.0, 0.0, 0.0)
    >>> period = 2 * math.pi * math.sqrt(7000.0**3 / satgnc.EARTH_MU)
    >>> tr = satgnc.propagate(x0, [0.0, period], forces=satgnc.J2Gravity())
    >>> tr.states.shape, tr.stms.shape, tr.status
    ((2, 6), (2, 6, 6), 'success')
    """
    x = as_float_array(x0, "x0")
    if x.shape != (6,):
        raise ValueError(f"x0: must have shape (6,) = [r km, v km/s], got {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("x0: must be finite (no NaN or Inf)")
    if not np.any(x[:3] != 0.0):
        raise ValueError("x0: position must be non-zero (|r0| = 0)")
    # x0 = 1e300 was a "force model failed" PropagationError at t0
    check_magnitude(x, "x0", 1e100, "|r|^3 overflows double precision in the force model "
                    "(hint: check the units)", subject="every component", detail="km, km/s")
    t = _check_times(times)
    t0f = float(t[0]) if t0 is None else as_finite_positive(t0, "t0", positive=False)
    # A span no orbit integration can cover (1e300 s) is the times' fault, not the force model's.
    span = float(np.max(np.abs(t - t0f)))
    if span > _MAX_SPAN:
        name = "times" if t0 is None else "times, t0"
        raise ValueError(f"{name}: span |t - t0| = {span:.3g} s exceeds {_MAX_SPAN:.0e} s (~3e4 years); "
                         "check the units (s) and t0")
    mu_given = mu is not _DEFAULT
    muf = as_finite_positive(EARTH_MU if not mu_given else mu, "mu")
    rtolf = as_finite_positive(rtol, "rtol")
    if not rtolf < 1.0:  # rtol = 1e300 "succeeded" with a trajectory no tolerance controlled
        raise ValueError(f"rtol: must be < 1 (a relative tolerance of 100 % controls nothing), got {rtol!r}")
    if isinstance(atol, numbers.Real) and not isinstance(atol, bool):
        atolv: float | list[float] = as_finite_positive(atol, "atol")
    else:
        a = as_float_array(atol, "atol")
        if a.ndim != 1 or a.size not in (6, 42):
            raise ValueError(f"atol: must be a scalar or have 6 or 42 entries, got shape {a.shape}")
        if not np.all(np.isfinite(a) & (a > 0)):
            raise ValueError("atol: every entry must be finite and > 0")
        atolv = a.tolist()
    if not isinstance(with_stm, (bool, np.bool_)):
        raise TypeError(f"with_stm: must be a bool, got {type(with_stm).__name__}")
    if isinstance(max_steps, bool) or not isinstance(max_steps, numbers.Integral):
        raise TypeError(f"max_steps: must be an int, got {type(max_steps).__name__}")
    if max_steps <= 0:
        raise ValueError(f"max_steps: must be > 0, got {max_steps}")
    if max_steps > 2**62:
        raise ValueError(f"max_steps: must be <= 2**62, got {max_steps}")
    if not isinstance(method, str):
        raise TypeError(f"method: must be a string, got {type(method).__name__}")
    methods = available_methods()
    if method not in methods:
        raise ValueError(f"method: unknown {method!r}; available in this build: {methods}")

    if surface_radius is not None:
        surface = as_real(surface_radius, "surface_radius", nonnegative=True)
        what = "surface_radius"
    else:  # a state inside the Earth propagated "successfully" with every numerical method
        surface = EARTH_RADIUS if muf == EARTH_MU else 0.0
        what = "the Earth's radius (the default surface_radius; pass surface_radius=0 to turn it off)"
    r0 = float(np.linalg.norm(x[:3]))
    if surface > 0.0 and not r0 > surface:
        raise ValueError(f"x0: starts at or below the surface: |r| = {r0:.6g} km <= R = {surface:.6g} km, "
                         f"{what}; x0 = [r km, v km/s]")

    tl = t.tolist()
    if method == "kepler":
        if forces is not None:
            raise ValueError("forces: method 'kepler' is the analytic two-body solution; use forces=None")
        traj = _satgnc.propagate_kepler(x, t0f, tl, muf, bool(with_stm), surface)
    else:
        model = _force_model(forces, muf, mu_given)
        if method == "dop853":
            if not isinstance(atolv, float):
                raise ValueError("atol: method 'dop853' (the default) takes a scalar atol; per-component "
                                 "atol needs method='adams' or 'bdf'")
            traj = _satgnc.propagate_dop853(x, t0f, tl, model, rtolf, atolv, bool(with_stm), int(max_steps),
                                            surface)
        else:
            if isinstance(atolv, list) and len(atolv) == 42 and not with_stm:
                raise ValueError("atol: 42 entries need with_stm=True (6 without the STM)")
            prop = _satgnc.CvodesPropagator(model, method=method, rtol=rtolf, atol=atolv,
                                            with_stm=bool(with_stm), max_steps=int(max_steps),
                                            surface_radius=surface)
            traj = prop.propagate(x, t0f, tl)
    if not traj.success:
        raise PropagationError(traj.message, traj)
    return traj


from ._namespace import public_dir as _public_dir  # noqa: E402

__dir__ = _public_dir(__name__)  # dir(): the API, not the imported modules (np, math, ...)
