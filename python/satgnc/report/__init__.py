"""The ``satgnc reproduce`` report: one Markdown section (with PNG figures) per room.

Each section is a module in this package with a ``TITLE`` and a ``build(ctx) -> str`` function that
returns Markdown and saves its figures through ``ctx.figure_path(name)``. ``SECTIONS`` fixes the order.
"""

from __future__ import annotations

import dataclasses
import importlib
import importlib.util
import pathlib
import time

from .._progress import Progress

SECTIONS = ["propagation", "od", "guidance", "guidance_nonlinear", "analysis", "mission"]


@dataclasses.dataclass
class Context:
    """What a section gets: where to write, and whether to run the quick variant."""

    outdir: pathlib.Path
    quick: bool = False
    #: Cross-checks left out because an optional package (the ``test`` extra) is missing: one line each.
    skipped: list[str] = dataclasses.field(default_factory=list)
    #: Whether figures are drawn (matplotlib, the ``plot`` extra, is installed); without it every
    #: section still writes its numbers, and the figures left out are listed in ``figures_skipped``.
    figures: bool = dataclasses.field(default_factory=lambda: _find("matplotlib") is not None)
    figures_skipped: list[str] = dataclasses.field(default_factory=list)

    def have(self, *modules: str, check: str = "") -> bool:
        """True when every module in ``modules`` imports; otherwise record ``check`` as skipped (it needs
        the ``test`` extra: ``pip install "satgnc[test]"``) and return False."""
        missing = [m for m in modules if _find(m) is None]
        if missing and check:
            self.skipped.append(f"{check} (needs {', '.join(missing)})")
        return not missing

    def image(self, name: str, alt: str, draw) -> list[str]:
        """Draw figure ``name`` with ``draw(path)`` and return its Markdown lines (image, blank line);
        without matplotlib draw nothing, record it in ``figures_skipped`` and return []."""
        if not self.figures:
            self.figures_skipped.append(name)
            return []
        path = self.figure_path(name)
        draw(path)
        return [f"![{alt}]({path.parent.name}/{path.name})", ""]

    def figure_path(self, name: str) -> pathlib.Path:
        """Path for a PNG figure ``name`` (without extension) under ``outdir/figures``."""
        d = self.outdir / "figures"
        d.mkdir(parents=True, exist_ok=True)
        return d / f"{name}.png"


def _find(module: str):
    """``importlib.util.find_spec`` that treats a blocked import (sys.modules[name] = None) as absent."""
    try:
        return importlib.util.find_spec(module)
    except (ValueError, ImportError):
        return None


def available_sections() -> list[str]:
    """Sections whose module exists in this build, in report order."""
    out = []
    for name in SECTIONS:
        try:
            importlib.import_module(f"{__name__}.{name}")
        except ModuleNotFoundError as e:
            if e.name != f"{__name__}.{name}":
                raise
            continue
        out.append(name)
    return out


def write_report(outdir: str | pathlib.Path = "satgnc-report", sections: list[str] | None = None,
                 quick: bool = False, progress: bool = True,
                 skipped: list[str] | None = None,
                 figures_skipped: list[str] | None = None) -> pathlib.Path:
    """Run the selected sections (default: all) and write ``outdir/README.md``; return its path.

    Cross-checks that need an optional package that is not installed (cvxpy + Clarabel, from the
    ``test`` extra) are left out of the report and listed in ``skipped`` (when a list is given) and in
    the report itself. Without matplotlib (the ``plot`` extra) every section's numbers are written and
    the figures left out are listed in ``figures_skipped`` (when a list is given) and in the report."""
    outdir = pathlib.Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    names = available_sections() if sections is None else list(sections)
    unknown = [n for n in names if n not in SECTIONS]
    if unknown:
        raise ValueError(f"sections: unknown {unknown}; choose from {SECTIONS}")
    ctx = Context(outdir=outdir, quick=quick)
    bar = Progress(len(names), "satgnc reproduce", enabled=progress)
    parts = ["# satgnc reproduction report", "",
             "Each section reproduces one paper (or the propagation foundation) and states every "
             "discrepancy with the number behind it.", ""]
    for name in names:
        mod = importlib.import_module(f"{__name__}.{name}")
        t0 = time.perf_counter()
        body = mod.build(ctx)
        parts += [f"## {mod.TITLE}", "", body.strip(), "",
                  f"_section generated in {time.perf_counter() - t0:.1f} s_", ""]
        bar.step(name)
    if ctx.skipped:
        parts += ["## Cross-checks not run", "",
                  "These need the test extra (`pip install \"satgnc[test]\"`):",
                  ""] + [f"- {c}" for c in ctx.skipped] + [""]
    if ctx.figures_skipped:
        parts += ["## Figures not drawn", "",
                  f"matplotlib is not installed (`pip install \"satgnc[plot]\"`): "
                  f"{', '.join(ctx.figures_skipped)}.", ""]
    if skipped is not None:
        skipped.extend(ctx.skipped)
    if figures_skipped is not None:
        figures_skipped.extend(ctx.figures_skipped)
    path = outdir / "README.md"
    path.write_text("\n".join(parts))
    return path
