"""Reference data shipped with satgnc (see README.md beside this file)."""

from __future__ import annotations

import functools
import json
import pathlib

DATA_DIR = pathlib.Path(__file__).resolve().parent


@functools.cache
def paper_tables() -> dict:
    """The papers' printed tables (``paper_tables.json``), keyed by paper."""
    return json.loads((DATA_DIR / "paper_tables.json").read_text())
