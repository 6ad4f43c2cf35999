"""Atmosphere density models and drag with a co-rotating atmosphere (issue 14 item 4).

Units: positions km, velocities km/s, times s, densities kg/m^3, density gradients kg/m^3 per km,
accelerations km/s^2; ``area`` m^2, ``mass`` kg. Frames: the drag term works in GCRF (the inertial
frame of the propagation); density models take ITRF positions. docs/atmosphere.md has the details.

- :class:`HarrisPriester`: Montenbruck & Gill (2000) section 3.5.2, Table 3.8 (100-1000 km).
- :class:`ErfaSun` / :class:`FixedSun`: the Sun direction of the diurnal bulge.
- :class:`SpaceWeather`: F10.7, F10.7a (sfu) and Ap inputs, range-checked (for NRLMSISE-00-type models).
- :class:`AtmosphereDrag`: ``-0.5 Cd (A/m) rho |v_rel| v_rel``, ``v_rel = v - omega x r``; pass it to
  ``satgnc.ForceModel(atmosphere_drag=...)`` to propagate with it (CVODES and DOP853, STM included).
"""

from __future__ import annotations

from .._satgnc import (
    AtmosphereDrag,
    AtmosphereModel,
    ErfaSun,
    FixedSun,
    HarrisPriester,
    SpaceWeather,
    SunDirectionModel,
)

__all__ = [
    "AtmosphereDrag",
    "AtmosphereModel",
    "ErfaSun",
    "FixedSun",
    "HarrisPriester",
    "SpaceWeather",
    "SunDirectionModel",
]
