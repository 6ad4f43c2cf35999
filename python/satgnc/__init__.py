"""satgnc: spacecraft guidance, navigation and control.

Orbits are in km, km/s and s; relative motion in m, m/s, N and kg, unless a function says otherwise.
Subpackages mirror the C++ rooms: :mod:`satgnc.od`, :mod:`satgnc.guidance`, :mod:`satgnc.analysis`.
Propagation (state and state transition matrix): :func:`satgnc.propagate`.
Time scales and Earth orientation (IAU 2006/2000A with EOP, ground stations): :mod:`satgnc.time`,
:mod:`satgnc.frames`.
"""

from __future__ import annotations

from . import _satgnc
from ._validate import harden_module as _harden_module

_harden_module(_satgnc)  # before any room imports a compiled name: type checks on every entry point

from ._docs import attach as _attach_docs  # noqa: E402

_attach_docs()  # property docstrings with units and summarising reprs on the compiled classes

from ._satgnc import EARTH_J2, EARTH_MU, EARTH_OMEGA, EARTH_RADIUS  # noqa: E402
from ._validate import FileFormatError  # noqa: E402
from .forcemodel import load_force_model  # noqa: E402
from .propagation import (  # noqa: E402
    ExponentialDrag,
    ForceModel,
    J2Gravity,
    PropagationError,
    Trajectory,
    available_methods,
    elements_to_state,
    propagate,
)
from .sensitivity import SensitivityResult, propagate_sensitivity  # noqa: E402

__version__: str = _satgnc.__version__

__all__ = [
    "__version__",
    "propagate",
    "propagate_sensitivity",
    "SensitivityResult",
    "load_force_model",
    "available_methods",
    "elements_to_state",
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
