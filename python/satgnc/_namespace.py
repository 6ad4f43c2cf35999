"""``dir()`` of a public package lists its API: everything it defines or re-exports, its own
subpackages, and not the third-party or standard-library modules it imports (``np``, ``math``,
``dataclasses``). The names stay importable (``satgnc.od.np`` still works); they are only not offered
to ``dir()``, ``help()`` and tab completion."""

from __future__ import annotations

import sys
import types
from typing import Callable


def public_dir(module_name: str) -> Callable[[], list[str]]:
    """A module-level ``__dir__`` for the module ``module_name``: usage ``__dir__ = public_dir(__name__)``
    at the end of the package's ``__init__``."""

    def __dir__() -> list[str]:
        mod = sys.modules[module_name]
        return sorted(
            n for n, v in vars(mod).items()
            if not (isinstance(v, types.ModuleType) and not v.__name__.startswith(module_name + "."))
        )

    return __dir__
