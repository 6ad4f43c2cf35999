"""Pure-Python references independent of the engine (oracles for the report and the tests).

:func:`kepler_ellipse` is the analytic two-body solution by Kepler's equation and Lagrange's f and g,
written without satgnc's propagators so that it can check them."""

from __future__ import annotations

import math

import numpy as np

from .._satgnc import EARTH_MU

__all__ = ["kepler_ellipse"]


def kepler_ellipse(x0: np.ndarray, dt: float, mu: float = EARTH_MU) -> np.ndarray:
    """State ``[r, v]`` (km, km/s; any consistent units with ``mu``) after ``dt`` s on the ellipse
    through ``x0`` (6,) about a point mass ``mu`` (km^3/s^2, default the Earth's): Kepler's equation
    by Newton from the mean anomaly, then Lagrange's f and g. Elliptic orbits only."""
    r0, v0 = x0[:3], x0[3:]
    rn0 = float(np.linalg.norm(r0))
    a = 1.0 / (2.0 / rn0 - float(v0 @ v0) / mu)
    n = math.sqrt(mu / a**3)
    ecos, esin = 1 - rn0 / a, float(r0 @ v0) / math.sqrt(mu * a)
    e = math.hypot(ecos, esin)
    E0 = math.atan2(esin, ecos)
    M = math.remainder(E0 - esin + n * dt, 2 * math.pi)
    E = M + e * math.sin(M)
    for _ in range(50):
        d = (E - e * math.sin(E) - M) / (1 - e * math.cos(E))
        E -= d
        if abs(d) < 1e-16:
            break
    dE = E - E0
    f = 1 - a / rn0 * (1 - math.cos(dE))
    g = (math.sin(dE) - e * (math.sin(E) - math.sin(E0))) / n
    r = f * r0 + g * v0
    rn = float(np.linalg.norm(r))
    fd = -math.sqrt(mu * a) * math.sin(dE) / (rn * rn0)
    gd = 1 - a / rn * (1 - math.cos(dE))
    return np.concatenate([r, fd * r0 + gd * v0])
