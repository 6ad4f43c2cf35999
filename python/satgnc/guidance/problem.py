"""The rendezvous problem, one description for both models (linear CW and nonlinear two-satellite).

Units: SI (m, m/s, N, kg, s) except the cost weights ``alpha`` and ``Qf``, which are in the solvers'
scaled units (each model's transcription scales states and controls, see :func:`satgnc.guidance.plan`).
Frames: the relative state ``x0`` is the chaser relative to the target in the target's CW frame
(y radial, z normal, x = y cross z); the 12-state ``x0_eci`` is ``[r_t - r_c, r_t, v_t - v_c, v_t]``
in the inertial frame (ECI). No paper constant lives here: every value comes from the caller or a
scenario file (:func:`satgnc.scenarios.rendezvous.problem`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .. import _satgnc as _c
from .._results import readonly
from .._validate import as_bool, as_int, as_real, as_real_array, one_of

__all__ = [
    "RendezvousProblem",
    "satellite_params",
    "ATMOSPHERES",
    "LINEAR_DISCRETIZATIONS",
    "NONLINEAR_DISCRETIZATIONS",
]

#: drag's atmosphere: "co_rotating" (physical, v - omega x r) or "published" (v + omega x r).
ATMOSPHERES = ("co_rotating", "published")
#: discretizations of the linear CW model (zero-order hold: "zoh", "expm" exact; "midpoint").
LINEAR_DISCRETIZATIONS = ("midpoint", "zoh", "expm")
#: discrete maps of the nonlinear model (Kutta RK3, classic RK4, adaptive DOP853 flow).
NONLINEAR_DISCRETIZATIONS = ("rk3", "rk4", "dop853")


def satellite_params(
    mu: float,
    *,
    j2: bool = False,
    drag: bool = True,
    atmosphere: str = "co_rotating",
    rho0: float | None = None,
    mass: float | None = None,
):
    """``TwoSatelliteParams`` of the nonlinear (two-satellite) model.

    Every field not given keeps the engine's default (the l1 scenario's: target 4.6 kg, 0.01 m^2,
    Cd 1, the density model's 6731 km reference radius).

    Parameters
    ----------
    mu : float
        Gravitational parameter (m^3/s^2, > 0).
    j2 : bool, optional
        The Earth's J2 (default False).
    drag : bool, optional
        Differential drag (default True).
    atmosphere : str, optional
        The drag's atmosphere, one of :data:`ATMOSPHERES` (default "co_rotating").
    rho0 : float, optional
        Density scale (kg/m^3, >= 0).
    mass : float, optional
        The chaser's mass (kg, > 0); it turns the control force (N) into an acceleration.

    Returns
    -------
    TwoSatelliteParams
        The model (SI), for :func:`fly`, :func:`mpc` and ``RendezvousProblem(planner=...)``.

    Raises
    ------
    ValueError
        A non-positive ``mu`` or ``mass``, a negative ``rho0``, an unknown atmosphere.
    TypeError
        A switch that is not a bool.

    Examples
    --------
    >>> from satgnc import guidance
    >>> p = guidance.satellite_params(3.986004418e14, j2=True, drag=False, mass=12.0)
    >>> p.j2_on, p.drag_on, p.mass_chaser
    (True, False, 12.0)
    """
    p = _c.TwoSatelliteParams()
    p.mu = as_real(mu, "mu", positive=True)
    if mass is not None:
        p.mass_chaser = as_real(mass, "mass", positive=True)
    p.j2_on = as_bool(j2, "j2")
    p.drag_on = as_bool(drag, "drag")
    atmosphere = one_of(atmosphere, "atmosphere", ATMOSPHERES)
    p.atmosphere = getattr(_c.AtmosphereRotation, atmosphere)
    if rho0 is not None:
        p.rho0 = as_real(rho0, "rho0", nonnegative=True)
    return p


@dataclasses.dataclass(frozen=True)
class RendezvousProblem:
    """One fuel-optimal (L1) rendezvous: drive the chaser to the target at ``tf``.

    Fields (checked at construction; arrays are stored read-only):

    * ``mu`` (m^3/s^2), ``radius`` (m): the target's circular orbit (mean motion sqrt(mu / radius^3));
    * ``mass`` (kg): the chaser's mass;
    * ``x0`` (6,): initial relative state in the target's CW frame (m, m/s);
    * ``tf`` (s), ``horizon`` (control intervals N, dt = tf / N);
    * ``alpha``: L1 weight, ``Qf``: terminal weight (scaled units of each model's transcription);
    * ``u_max`` (N): per-axis force bound, ``None`` for none;
    * ``terminal_equality``: arrive exactly (hard terminal state) instead of the terminal cost;
    * ``x0_eci`` (12,) or ``None``: the nonlinear model's start ``[r_t - r_c, r_t, v_t - v_c, v_t]``
      (m, m/s, ECI); ``None``: the target at ``[radius, 0, 0]`` on its circular equatorial orbit and the
      chaser at ``x0`` (see :meth:`state_eci`);
    * ``planner``: ``TwoSatelliteParams`` of the nonlinear planning model (``None``: point mass + drag,
      co-rotating atmosphere, with this ``mu`` and ``mass``; see :func:`satellite_params`); its ``mu``
      and ``mass_chaser`` must equal the problem's;
    * ``linear_discretization`` (:data:`LINEAR_DISCRETIZATIONS`), ``nonlinear_discretization``
      (:data:`NONLINEAR_DISCRETIZATIONS`) and ``substeps`` (RK steps per interval of the nonlinear map).
    """

    mu: float
    radius: float
    mass: float
    x0: np.ndarray
    tf: float
    horizon: int
    alpha: float
    Qf: float
    u_max: float | None = None
    terminal_equality: bool = False
    x0_eci: np.ndarray | None = None
    planner: object | None = None
    linear_discretization: str = "zoh"
    nonlinear_discretization: str = "rk3"
    substeps: int = 1

    def __post_init__(self):
        s = object.__setattr__
        s(self, "mu", as_real(self.mu, "mu", positive=True))
        s(self, "radius", as_real(self.radius, "radius", positive=True))
        s(self, "mass", as_real(self.mass, "mass", positive=True))
        s(self, "x0", readonly(as_real_array(self.x0, "x0", shape=(6,))))
        s(self, "tf", as_real(self.tf, "tf", positive=True))
        s(self, "horizon", as_int(self.horizon, "horizon", low=1, high=10**6))
        s(self, "alpha", as_real(self.alpha, "alpha", nonnegative=True))
        s(self, "Qf", as_real(self.Qf, "Qf", nonnegative=True))
        if self.u_max is not None:
            s(self, "u_max", as_real(self.u_max, "u_max", positive=True))
        s(self, "terminal_equality", as_bool(self.terminal_equality, "terminal_equality"))
        if self.x0_eci is not None:
            s(self, "x0_eci", readonly(as_real_array(self.x0_eci, "x0_eci", shape=(12,))))
        if self.planner is None:
            s(self, "planner", satellite_params(self.mu, mass=self.mass))
        elif not isinstance(self.planner, _c.TwoSatelliteParams):
            raise TypeError(
                f"planner: must be TwoSatelliteParams (see satellite_params()), "
                f"got {type(self.planner).__name__}"
            )
        if self.planner.mass_chaser != self.mass or self.planner.mu != self.mu:
            raise ValueError(
                f"planner: mass_chaser = {self.planner.mass_chaser} kg and mu = {self.planner.mu} m^3/s^2 "
                f"must equal the problem's mass = {self.mass} kg and mu = {self.mu} m^3/s^2 "
                "(see satellite_params())"
            )
        one_of(self.linear_discretization, "linear_discretization", LINEAR_DISCRETIZATIONS)
        one_of(self.nonlinear_discretization, "nonlinear_discretization", NONLINEAR_DISCRETIZATIONS)
        s(self, "substeps", as_int(self.substeps, "substeps", low=1, high=10**6))
        if self.n * self.tf > 1e9:
            raise ValueError(
                f"tf: n tf = {self.n * self.tf:.3g} rad exceeds 1e9 rad (n = sqrt(mu / radius^3) "
                f"= {self.n:.3g} rad/s): the CW matrices keep no correct digit"
            )

    @property
    def n(self) -> float:
        """Mean motion of the target's orbit (rad/s)."""
        return math.sqrt(self.mu / self.radius**3)

    @property
    def dt(self) -> float:
        """Control interval (s)."""
        return self.tf / self.horizon

    def state_eci(self) -> np.ndarray:
        """The nonlinear model's 12-state at t = 0 (m, m/s, ECI): ``x0_eci`` when given, else the target
        at ``[radius, 0, 0]`` with velocity ``[0, sqrt(mu / radius), 0]`` and the chaser at ``x0``."""
        if self.x0_eci is not None:
            return np.array(self.x0_eci)
        r_t = np.array([self.radius, 0.0, 0.0])
        v_t = np.array([0.0, math.sqrt(self.mu / self.radius), 0.0])
        return np.asarray(_c.two_satellite_state(r_t, v_t, np.array(self.x0)))
