"""satgnc.dynamics: force-model terms for orbit propagation.

Units: km, km/s, s; densities kg/m^3; drag area m^2, mass kg. States in GCRF.

Atmosphere drag (issue 14 item 4): :mod:`satgnc.dynamics.atmosphere` and docs/atmosphere.md.
"""

from __future__ import annotations

from .atmosphere import (
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
