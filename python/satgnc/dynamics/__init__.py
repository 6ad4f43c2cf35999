"""satgnc.dynamics: force-model terms for orbit propagation.

Units: km, km/s, s; accelerations km/s^2, gradients 1/s^2, potentials km^2/s^2; SRP area m^2, mass kg.
Frames: states in GCRF; a gravity field is evaluated in ITRF through an :class:`EarthRotationModel`
(:class:`UniformRotation` by default: the Earth turning about the inertial z axis).

Precise force models (issue 14): see :mod:`satgnc.dynamics._force_models` and docs/force_models.md.
"""

from __future__ import annotations

from ._force_models import (
    EGM2008_PATH,
    EarthRotationModel,
    GravityCoefficients,
    GravityField,
    SolarRadiationPressure,
    ThirdBodies,
    UniformRotation,
    egm2008,
    force_model,
    load_gfc,
    moon_position,
    sun_position,
)

__all__ = [
    "EGM2008_PATH",
    "EarthRotationModel",
    "GravityCoefficients",
    "GravityField",
    "SolarRadiationPressure",
    "ThirdBodies",
    "UniformRotation",
    "egm2008",
    "force_model",
    "load_gfc",
    "moon_position",
    "sun_position",
]
