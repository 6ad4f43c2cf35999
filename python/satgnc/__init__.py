"""satgnc: spacecraft guidance, navigation and control.

Orbits are in km, km/s and s; relative motion in m, m/s, N and kg, unless a function says otherwise.
Subpackages mirror the C++ rooms: :mod:`satgnc.od`, :mod:`satgnc.guidance`, :mod:`satgnc.analysis`.
"""

from __future__ import annotations

from . import _satgnc

__version__: str = _satgnc.__version__

__all__ = ["__version__"]
