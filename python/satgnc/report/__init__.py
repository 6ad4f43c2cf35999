"""The ``satgnc reproduce`` report: one Markdown section (with PNG figures) per room.

Each section is a module in this package with a ``TITLE`` and a ``build(ctx) -> str`` function that
returns Markdown and saves its figures through ``ctx.figure_path(name)``. ``SECTIONS`` fixes the order.
"""

from __future__ import annotations

import dataclasses
import importlib
import pathlib
import time

from .._progress import Progress

SECTIONS = ["propagation", "od", "guidance", "guidance_nonlinear", "analysis", "mission"]


@dataclasses.dataclass
class Context:
    """What a section gets: where to write, and whether to run the quick variant."""

    outdir: pathlib.Path
    quick: bool = False

    def figure_path(self, name: str) -> pathlib.Path:
        """Path for a PNG figure ``name`` (without extension) under ``outdir/figures``."""
        d = self.outdir / "figures"
        d.mkdir(parents=True, exist_ok=True)
        return d / f"{name}.png"


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
                 quick: bool = False, progress: bool = True) -> pathlib.Path:
    """Run the selected sections (default: all) and write ``outdir/README.md``; return its path."""
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
    path = outdir / "README.md"
    path.write_text("\n".join(parts))
    return path
