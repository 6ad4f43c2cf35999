"""``satgnc mission --scenario X.toml [--out DIR] [--quick]``: the main job as one path.

Runs :func:`satgnc.mission.run` and writes ``DIR/mission.md`` (the hand-off table),
``DIR/figures/mission.png`` (the 4-panel figure) and ``DIR/mission_summary.json``. A bad scenario
file prints one line naming the file, the line and the key, and exits with code 2."""

from __future__ import annotations

import argparse
import pathlib


def _run(args: argparse.Namespace) -> int:
    from ..report import mission as report
    from . import run

    result = run(args.scenario, quick=args.quick, closed_loop=True if args.closed_loop else None)
    out = pathlib.Path(args.out)
    path = report.write(result, out)
    total = sum(result.timings.values())
    print(f"{result.scenario.name}: " + "; ".join(_summary(result)) + f"; {total:.1f} s")
    print(f"report written to {path}")
    return _figures_line()


def _figures_line() -> int:
    """0, or (one line printed) the exit code of a run written without figures (no matplotlib)."""
    from .. import _plot
    from ..cli import EXIT_NO_FIGURES

    if _plot.available():
        return 0
    print(f"satgnc mission: {_plot.NO_FIGURES}; exit code {EXIT_NO_FIGURES}")
    return EXIT_NO_FIGURES


def _summary(result) -> list:
    """One clause per stage that ran (a partial chain leaves the others None)."""
    est, pl, fl, cl, ck = result.estimate, result.plan, result.flight, result.closed_loop, result.checks
    out = []
    if est is not None:
        out.append(f"OD {est.status} in {est.iterations} iterations "
                   f"(|dr| = {1e3 * float((est.error[:3] ** 2).sum() ** 0.5):.2f} m)")
    if pl is not None:
        out.append(f"plan {pl.status} in {pl.iterations} iterations, dv = {pl.delta_v:.4f} m/s")
    if fl is not None:
        out.append(f"flown miss {fl.miss_position:.2f} m (open loop; tolerance {fl.tolerance:g} m: "
                   f"{fl.status})")
    if cl is not None:
        out.append(f"closed-loop miss {cl.miss_position:.2f} m ({cl.status})")
    if ck is not None:
        out.append(f"controllability: {ck.controllability}; observability: {ck.observability}")
    return out


def register(subparsers) -> None:
    p = subparsers.add_parser("mission", help="tracking -> OD -> relative state -> L1 plan -> flight -> "
                              "controllability/observability, in one run")
    p.add_argument("--scenario", default=None,
                   help="mission scenario TOML (default: the packaged mission_leo.toml)")
    p.add_argument("--out", default="satgnc-mission", help="output directory (mission.md, figures/)")
    p.add_argument("--quick", action="store_true", help="thin the tracking times (the file's quick_thin)")
    p.add_argument("--closed-loop", action="store_true",
                   help="also fly the plan's problem with guidance.mpc (re-planning from the true state)")
    p.set_defaults(func=_run)
