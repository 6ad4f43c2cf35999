"""The ``satgnc`` console script. Each room adds a subcommand through ``register(subparsers)``."""

from __future__ import annotations

import argparse
import importlib
import sys

# Modules that provide ``register(subparsers)``; a missing one simply contributes no subcommand.
_COMMAND_MODULES = ["satgnc.od.cli", "satgnc.guidance.cli", "satgnc.analysis.cli"]


def _reproduce(args: argparse.Namespace) -> int:
    from .report import write_report

    sections = args.section or None
    path = write_report(args.out, sections=sections, quick=args.quick, progress=not args.no_progress)
    print(f"report written to {path}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="satgnc", description="satgnc: spacecraft GNC toolkit")
    p.add_argument("--version", action="store_true", help="print the version and exit")
    sub = p.add_subparsers(dest="command")
    r = sub.add_parser("reproduce", help="reproduce the papers' tables and write a Markdown report")
    r.add_argument("--out", default="satgnc-report", help="output directory (default ./satgnc-report)")
    r.add_argument("--section", action="append", help="only this section (repeatable)")
    r.add_argument("--quick", action="store_true", help="smaller sweeps, for smoke tests")
    r.add_argument("--no-progress", action="store_true", help="do not draw the progress bar")
    r.set_defaults(func=_reproduce)
    for name in _COMMAND_MODULES:
        try:
            mod = importlib.import_module(name)
        except ModuleNotFoundError as e:
            if e.name is not None and name.startswith(e.name):
                continue
            raise
        mod.register(sub)
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.version:
        from . import __version__

        print(__version__)
        return 0
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except (ValueError, TypeError, FileNotFoundError) as e:
        print(f"satgnc: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
