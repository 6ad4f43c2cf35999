"""satgnc: spacecraft guidance, navigation and control.

Orbits are in km, km/s and s; relative motion in m, m/s, N and kg, unless a function says otherwise.
Subpackages mirror the C++ rooms: :mod:`satgnc.od`, :mod:`satgnc.guidance`, :mod:`satgnc.analysis`.
Propagation (state and state transition matrix): :func:`satgnc.propagate`.
"""

from __future__ import annotations

from . import _satgnc
from ._satgnc import EARTH_J2, EARTH_MU, EARTH_OMEGA, EARTH_RADIUS
from ._validate import FileFormatError
from .propagation import (
    ExponentialDrag,
    ForceModel,
    J2Gravity,
    PropagationError,
    Trajectory,
    available_methods,
    propagate,
)

__version__: str = _satgnc.__version__

__all__ = [
    "__version__",
    "propagate",
    "available_methods",
    "Trajectory",
    "ForceModel",
    "J2Gravity",
    "ExponentialDrag",
    "PropagationError",
    "FileFormatError",
    "EARTH_MU",
    "EARTH_RADIUS",
    "EARTH_J2",
    "EARTH_OMEGA",
]
