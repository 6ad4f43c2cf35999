"""Small helpers shared by the Python tests (imported as ``from _helpers import ...``; pytest puts this
folder on sys.path)."""

from __future__ import annotations

import pathlib


def write(tmp_path: pathlib.Path, text: str, name: str = "s.toml") -> pathlib.Path:
    """``text`` written to ``tmp_path / name``; the path."""
    p = tmp_path / name
    p.write_text(text)
    return p
