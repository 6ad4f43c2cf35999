"""Module shims for code that moved: the old module forwards every attribute to the new one with a
``DeprecationWarning`` naming the new module (PEP 562 module ``__getattr__``)."""

from __future__ import annotations

import importlib

from .._results import deprecated


def forward(old: str, new: str, renamed: dict[str, str] | None = None, hints: dict[str, str] | None = None):
    """``(__getattr__, __dir__)`` for the shim module ``old``: attribute ``x`` is ``new.x`` (or the
    target named in ``renamed[x]``, ``"module:attr"``), fetched on access with a DeprecationWarning
    ``"old.x is deprecated; use new.x"`` (+ ``hints[x]``). The values are the new module's own objects
    (same behaviour)."""
    renamed = dict(renamed or {})
    hints = dict(hints or {})

    def __getattr__(name: str):
        if name.startswith("__"):
            raise AttributeError(f"module {old!r} has no attribute {name!r}")
        target = renamed.get(name, f"{new}:{name}")
        mod_name, _, attr = target.partition(":")
        mod = importlib.import_module(mod_name)
        try:
            value = getattr(mod, attr)
        except AttributeError:
            raise AttributeError(f"module {old!r} has no attribute {name!r} (it moved to {new!r})") from None
        deprecated(f"{old}.{name}", f"{mod_name}.{attr}{hints.get(name, '')}", stacklevel=2)
        return value

    def __dir__():
        mod = importlib.import_module(new)
        return sorted(set(dir(mod)) | set(renamed))

    return __getattr__, __dir__
