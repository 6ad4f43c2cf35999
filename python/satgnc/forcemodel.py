"""The force-model TOML (issue 14 item 8): one file for propagation, OD and the guidance truth.

The file is read by the C++ core (``satgnc::dynamics::load_force_model_config``, toml++), so a C++
program and Python build the same :class:`satgnc.ForceModel` from it. Schema, units and defaults:
docs/force_models.md "The force-model TOML"; a complete example: examples/force_model.toml.
A file that breaks the schema raises :class:`satgnc.FileFormatError` naming the file, the line, the
``[section] key`` and the rule.
"""

from __future__ import annotations

import os
import pathlib
from typing import Any

from . import _satgnc
from ._satgnc import ForceModel
from .dynamics._force_models import EGM2008_PATH

__all__ = ["ForceModelConfig", "load_force_model", "load_force_model_config", "two_satellite_params"]

ForceModelConfig = _satgnc.ForceModelConfig


def _path(path: Any, name: str = "path") -> str:
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"{name}: must be a path (str or os.PathLike) to a force-model TOML, "
                        f"got {type(path).__name__}")
    p = pathlib.Path(path)
    if not p.is_file():
        raise FileNotFoundError(f"{name}: no force-model TOML at {p}")
    return str(p)


def load_force_model_config(path: str | os.PathLike[str]) -> Any:
    """Read a force-model TOML: ``.model`` (the :class:`satgnc.ForceModel`), ``.epoch`` (a
    :class:`satgnc.time.Epoch` or None), ``.space_weather``, ``.gravity_model``, ``.gravity_file``,
    ``.atmosphere``, ``.earth_orientation``, ``.eop_file``, ``.ephemeris_file`` (the JPL DE .bsp of
    ``[third_body] ephemeris``, or empty), ``.radius`` (km), ``.source``.
    ``[gravity] model = "egm2008"`` reads the shipped coefficients (``satgnc.dynamics.EGM2008_PATH``)."""
    return _satgnc.load_force_model_config(_path(path), str(EGM2008_PATH))


def load_force_model(path: str | os.PathLike[str]) -> ForceModel:
    """The :class:`satgnc.ForceModel` a force-model TOML describes (see :func:`load_force_model_config`);
    ``satgnc.propagate(x0, t, forces=path)`` and ``satgnc propagate``-style callers accept the path."""
    model: ForceModel = load_force_model_config(path).model
    return model


def two_satellite_params(path: str | os.PathLike[str], base: Any = None) -> Any:
    """``TwoSatelliteParams`` (SI) of the guidance two-satellite truth from the same TOML: mu, J2,
    radius and exponential drag (cd, area, mass for both bodies); the rest from ``base`` (default
    ``TwoSatelliteParams()``). A file with a gravity field, Sun/Moon, SRP or Harris-Priester raises
    :class:`satgnc.FileFormatError` naming the section (the two-satellite model has no such term)."""
    cfg = load_force_model_config(path)
    if base is None:
        return _satgnc.two_satellite_params_from_config(cfg)
    return _satgnc.two_satellite_params_from_config(cfg, base)
