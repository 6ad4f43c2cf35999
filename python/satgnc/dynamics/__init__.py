"""satgnc.dynamics: force-model terms for orbit propagation.

Units: km, km/s, s; accelerations km/s^2, gradients 1/s^2, potentials km^2/s^2; densities kg/m^3;
SRP and drag area m^2, mass kg.
Frames: states in GCRF; a gravity field and an atmosphere are evaluated in ITRF through an
:class:`EarthRotationModel` (:class:`UniformRotation` by default: the Earth turning about the
inertial z axis).

Precise force models (issue 14): see :mod:`satgnc.dynamics._force_models` and docs/force_models.md;
atmosphere drag (issue 14 item 4): :mod:`satgnc.dynamics.atmosphere` and docs/atmosphere.md.
"""

from __future__ import annotations

from ._force_models import (
    EGM2008_PATH,
    EarthRotationModel,
    GravityCoefficients,
    GravityField,
    SolarRadiationPressure,
    SpkEphemeris,
    ThirdBodies,
    UniformRotation,
    egm2008,
    force_model,
    load_gfc,
    load_spk,
    moon_position,
    sun_position,
)
from .atmosphere import (
    AtmosphereDrag,
    AtmosphereModel,
    ErfaSun,
    FixedSun,
    HarrisPriester,
    SpaceWeather,
    SunDirectionModel,
)
from .nrlmsise00 import Nrlmsise00, Nrlmsise00Result, nrlmsise00

__all__ = [
    "EGM2008_PATH",
    "AtmosphereDrag",
    "AtmosphereModel",
    "EarthRotationModel",
    "ErfaSun",
    "FixedSun",
    "GravityCoefficients",
    "GravityField",
    "HarrisPriester",
    "Nrlmsise00",
    "Nrlmsise00Result",
    "SolarRadiationPressure",
    "SpaceWeather",
    "SpkEphemeris",
    "SunDirectionModel",
    "ThirdBodies",
    "UniformRotation",
    "egm2008",
    "force_model",
    "load_gfc",
    "load_spk",
    "moon_position",
    "nrlmsise00",
    "sun_position",
]


from .._namespace import public_dir as _public_dir  # noqa: E402

__dir__ = _public_dir(__name__)  # dir(): the API, not the imported modules (np, math, ...)
