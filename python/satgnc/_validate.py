"""Argument checks shared by every satgnc room (private).

Every public function validates its arguments here before calling the engine. The rules:

* arrays are real: complex, boolean, object and string arrays are a ``TypeError`` naming the
  argument (numpy would truncate complex silently and read booleans as 0/1);
* numbers are real and finite unless a function allows infinity; ``bool`` is not a number;
* shapes are checked with the expected shape in the message;
* every message starts with the argument's name, then the rule, then what was given.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = [
    "as_bool",
    "as_int",
    "as_real",
    "as_real_array",
    "one_of",
]

_REAL_KINDS = "fiu"  # float, signed and unsigned integer


def _describe(value: Any) -> str:
    if isinstance(value, np.ndarray):
        return f"array of dtype {value.dtype}"
    return type(value).__name__


def as_real_array(
    value: Any,
    name: str,
    *,
    ndim: int | tuple[int, ...] | None = None,
    shape: tuple[int | None, ...] | None = None,
    finite: bool = True,
    allow_inf: bool = False,
    copy: bool = False,
) -> np.ndarray:
    """Return ``value`` as a float64 array, or raise naming ``name``.

    ``shape`` may hold ``None`` for a free dimension. ``allow_inf`` admits +-inf (bounds) but never
    NaN. Complex, boolean, object and string input is a ``TypeError``."""
    if value is None or isinstance(value, (str, bytes, bool, np.bool_)):
        raise TypeError(f"{name}: must be a real numeric array, got {_describe(value)}")
    if isinstance(value, np.ndarray):
        arr = value
    else:
        try:
            arr = np.asarray(value)
        except (TypeError, ValueError) as e:  # ragged nested sequences
            raise TypeError(f"{name}: must be a real numeric array ({e})") from None
    if arr.dtype.kind not in _REAL_KINDS:
        kind = {"c": "complex", "b": "boolean", "O": "object", "U": "string", "S": "bytes"}.get(
            arr.dtype.kind, str(arr.dtype)
        )
        raise TypeError(f"{name}: must be a real numeric array, got a {kind} array")
    arr = np.array(arr, dtype=np.float64, copy=True) if copy else np.asarray(arr, dtype=np.float64)
    if ndim is not None:
        dims = (ndim,) if isinstance(ndim, int) else tuple(ndim)
        if arr.ndim not in dims:
            want = " or ".join(str(d) for d in dims)
            raise ValueError(f"{name}: must have {want} dimension(s), got shape {arr.shape}")
    if shape is not None:
        ok = arr.ndim == len(shape) and all(s is None or s == a for s, a in zip(shape, arr.shape))
        if not ok:
            dims = ", ".join("n" if s is None else str(s) for s in shape)
            want = f"({dims},)" if len(shape) == 1 else f"({dims})"
            raise ValueError(f"{name}: must have shape {want}, got {arr.shape}")
    if finite:
        bad = np.isnan(arr) if allow_inf else ~np.isfinite(arr)
        if np.any(bad):
            rule = "must not contain NaN" if allow_inf else "must be finite (no NaN or Inf)"
            raise ValueError(f"{name}: {rule}")
    return arr


def as_real(
    value: Any,
    name: str,
    *,
    positive: bool = False,
    nonnegative: bool = False,
    finite: bool = True,
    low: float | None = None,
    high: float | None = None,
) -> float:
    """Return ``value`` as a float, or raise naming ``name``. ``bool`` and complex are TypeErrors."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in _REAL_KINDS:
            value = value.item()
        else:
            raise TypeError(f"{name}: must be a real number, got {_describe(value)}")
    v = float(value)
    if math.isnan(v) or (finite and not math.isfinite(v)):
        raise ValueError(f"{name}: must be finite, got {v}")
    if positive and not v > 0:
        raise ValueError(f"{name}: must be > 0, got {v}")
    if nonnegative and not v >= 0:
        raise ValueError(f"{name}: must be >= 0, got {v}")
    if low is not None and v < low:
        raise ValueError(f"{name}: must be >= {low}, got {v}")
    if high is not None and v > high:
        raise ValueError(f"{name}: must be <= {high}, got {v}")
    return v


def as_int(value: Any, name: str, *, low: int | None = None, high: int | None = None) -> int:
    """Return ``value`` as an int, or raise naming ``name``. Floats (even 2.0) and bools are
    TypeErrors: a count is never rounded silently."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}: must be an integer, got {_describe(value)}")
    v = int(value)
    if low is not None and v < low:
        raise ValueError(f"{name}: must be >= {low}, got {v}")
    if high is not None and v > high:
        raise ValueError(f"{name}: must be <= {high}, got {v}")
    return v


def as_bool(value: Any, name: str) -> bool:
    """Return ``value`` if it is a bool (Python or numpy); strings like "false" are TypeErrors."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise TypeError(f"{name}: must be true or false (a bool), got {_describe(value)}")


def one_of(value: Any, name: str, choices: Sequence[str]) -> str:
    """Return ``value`` if it is one of the strings ``choices``, or raise naming ``name``."""
    if not isinstance(value, str):
        raise TypeError(f"{name}: must be one of {list(choices)}, got {_describe(value)}")
    if value not in choices:
        raise ValueError(f"{name}: must be one of {list(choices)}, got {value!r}")
    return value
