"""Count which room includes which, and prove the room graph has no cycle.

A room is a folder under ``cpp/include/satgnc/`` and ``cpp/src/`` (core, frames, dynamics, propagation,
io, od, guidance, analysis). For every file of a room the script counts the lines
``#include "satgnc/<other room>/...`` and prints the matrix (rows: the including room) as Markdown,
then a topological order of the rooms. The Python package is checked the same way on
``from satgnc.<pkg>`` / ``from ..<pkg>`` imports of ``python/satgnc/<pkg>/`` (library packages only:
report, papers, mission, scenarios are listed but may import the library).

Usage: ``python3 scripts/room_imports.py`` (from the repository root; no build needed).
Exit status 1 when a cycle is found among the C++ rooms or a library package imports report/papers.
"""

from __future__ import annotations

import pathlib
import re
import sys

ROOMS = [
    "core",
    "frames",
    "dynamics",
    "propagation",
    "observation",
    "io",
    "filter",
    "od",
    "guidance",
    "analysis",
]
INCLUDE = re.compile(r'^\s*#\s*include\s+"satgnc/([a-z_]+)/', re.M)


def cpp_matrix(root: pathlib.Path) -> dict[str, dict[str, int]]:
    """{including room: {included room: number of #include lines}} over include/ and src/."""
    m = {r: {s: 0 for s in ROOMS} for r in ROOMS}
    for room in ROOMS:
        for base in (root / "cpp/include/satgnc" / room, root / "cpp/src" / room):
            for f in sorted(base.rglob("*")):
                if f.suffix in (".hpp", ".cpp"):
                    for target in INCLUDE.findall(f.read_text()):
                        if target in m[room]:
                            m[room][target] += 1
    return m


def topological(m: dict[str, dict[str, int]]) -> list[list[str]] | None:
    """Levels of rooms: each room includes only rooms of earlier levels (and itself); None on a cycle."""
    deps = {r: {s for s, n in row.items() if n and s != r} for r, row in m.items()}
    levels: list[list[str]] = []
    while deps:
        ready = sorted((r for r, d in deps.items() if not d), key=ROOMS.index)
        if not ready:
            return None
        levels.append(ready)
        for r in ready:
            del deps[r]
        for d in deps.values():
            d.difference_update(ready)
    return levels


PY_LIBRARY = ["od", "guidance", "analysis", "propagation", "observation", "io"]
PY_IMPORT = re.compile(r"^\s*(?:from|import)\s+(?:satgnc\.|\.\.?)([a-z_]+)", re.M)


def is_shim_or_cli(f: pathlib.Path) -> bool:
    """Deprecated forwarding modules (docstring starts "Deprecated") and the console-script modules
    (cli.py: the application, which runs the papers' commands) are not library code."""
    return f.name == "cli.py" or f.read_text().lstrip().startswith('"""Deprecated')


def python_imports(root: pathlib.Path) -> dict[str, set[str]]:
    """{package or top module: set of satgnc packages/modules its library files import}."""
    pkg_root = root / "python/satgnc"
    out: dict[str, set[str]] = {}
    for f in sorted(pkg_root.rglob("*.py")):
        if is_shim_or_cli(f):
            continue
        rel = f.relative_to(pkg_root)
        name = rel.parts[0] if len(rel.parts) > 1 else rel.stem
        out.setdefault(name, set()).update(t for t in PY_IMPORT.findall(f.read_text()) if t != name)
    return out


def main() -> int:
    root = pathlib.Path(__file__).resolve().parent.parent
    m = cpp_matrix(root)
    print("| includes -> | " + " | ".join(ROOMS) + " |")
    print("|---|" + "---:|" * len(ROOMS))
    for r in ROOMS:
        print(f"| **{r}** | " + " | ".join(str(m[r][s]) if m[r][s] else "." for s in ROOMS) + " |")
    order = topological(m)
    status = 0
    if order is None:
        print("\nC++ rooms: CYCLE")
        status = 1
    else:
        shown = [lv[0] if len(lv) == 1 else "{" + ", ".join(lv) + "}" for lv in order]
        print("\nC++ rooms, no cycle; each includes only rooms to its left: " + " < ".join(shown))
    py = python_imports(root)
    bad = {p: sorted(py.get(p, set()) & {"report", "papers", "mission"}) for p in PY_LIBRARY}
    bad = {p: v for p, v in bad.items() if v}
    found = str(bad) if bad else "none"
    print("\nPython library packages (shims and cli.py aside) importing report/papers/mission: " + found)
    if bad:
        status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
