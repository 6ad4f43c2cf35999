"""The ``satgnc`` console script. Each room adds a subcommand through ``register(subparsers)``.

Errors: a user or library error (bad option, bad file, bad data: ValueError, TypeError, OSError,
KeyError, ImportError of an optional dependency, MemoryError, a failed propagation) prints one line
``satgnc: error: <message>`` to stderr and exits with code 2. Anything else is an internal bug: one
line ``satgnc: internal error: ...`` and exit code 1. ``--debug`` (anywhere on the command line)
shows the full traceback instead. Option values may be negative numbers (``--guess -3026.7,...``).

Exit codes: 0 done; 1 internal error (or ``od solve`` did not converge: its status is printed);
2 usage or input error; 3 (:data:`EXIT_PARTIAL`) ``reproduce``
wrote its report without the cross-checks that need the ``test`` extra; 4 (:data:`EXIT_UNREACHABLE`)
``rendezvous`` wrote its summary but a case's target cannot be reached (the best achievable miss is in
``summary.json``); 5 (:data:`EXIT_NO_FIGURES`) the numbers were written but no figures, since
matplotlib (the ``plot`` extra) is missing. When several apply: 4, then 5, then 3. 130: interrupted.
"""

from __future__ import annotations

import argparse
import importlib
import re
import sys

# Modules that provide ``register(subparsers)``; a missing one simply contributes no subcommand.
_COMMAND_MODULES = ["satgnc.od.cli", "satgnc.guidance.cli", "satgnc.analysis.cli", "satgnc.mission.cli"]

# A token that is a negative number or a list of numbers (-3026.7,1265 / -.5 / -1e3 / -inf / -nan).
_NEGATIVE = re.compile(r"^-(\d|\.\d|inf|nan)", re.IGNORECASE)


class CliError(ValueError):
    """A command-line usage error raised by a subcommand (printed as one line, exit code 2)."""


class ArgumentParser(argparse.ArgumentParser):
    """argparse with one-line errors (exit code 2) and negative-number option values."""

    def error(self, message: str):  # one line, not usage + message
        self.exit(2, f"satgnc: error: {self.prog}: {message} (see '{self.prog} --help')\n")

    def parse_known_args(self, args=None, namespace=None):
        if args is not None:
            args = self._join_negative_values(list(args))
        return super().parse_known_args(args, namespace)

    def _join_negative_values(self, args: list[str]) -> list[str]:
        """``--opt -3,1`` -> ``--opt=-3,1`` for options of this parser that take one value: argparse
        would read ``-3,1`` as an unknown option and report "expected one argument"."""
        out: list[str] = []
        i = 0
        while i < len(args):
            a = args[i]
            action = self._option_string_actions.get(a)
            takes_value = action is not None and action.nargs in (None, 1) and action.option_strings
            if takes_value and i + 1 < len(args) and _NEGATIVE.match(args[i + 1]):
                out.append(f"{a}={args[i + 1]}")
                i += 2
                continue
            if a == "--":
                out.extend(args[i:])
                break
            out.append(a)
            i += 1
        return out


# argparse ``type=`` converters: a bad value is reported as "argument --x: <rule>, got '<text>'".
def _number(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if v != v or v in (float("inf"), float("-inf")):
        raise argparse.ArgumentTypeError(f"must be finite, got {text!r}")
    return v


def finite_float(text: str) -> float:
    """argparse type: a finite number."""
    return _number(text)


def positive_float(text: str) -> float:
    """argparse type: a finite number > 0."""
    v = _number(text)
    if not v > 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text!r}")
    return v


def int_at_least(low: int):
    """argparse type: an integer >= ``low``."""

    def convert(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be an integer, got {text!r}") from None
        if v < low:
            raise argparse.ArgumentTypeError(f"must be >= {low}, got {text!r}")
        return v

    convert.__name__ = f"integer >= {low}"
    return convert


#: Exit code of ``satgnc reproduce`` when the report is written but cross-checks that need the ``test``
#: extra (cvxpy, Clarabel) were skipped; 0 means everything ran.
EXIT_PARTIAL = 3
#: Exit code of ``satgnc rendezvous`` when a case's target cannot be reached with its bounds and
#: horizon: ``summary.json`` is written with ``unreachable`` and the best achievable miss (m).
EXIT_UNREACHABLE = 4
#: Exit code of a command that wrote its numbers (JSON, Markdown tables) but no figures because
#: matplotlib (the ``plot`` extra) is not installed; EXIT_UNREACHABLE takes precedence over it, and it
#: over EXIT_PARTIAL.
EXIT_NO_FIGURES = 5


def _reproduce(args: argparse.Namespace) -> int:
    from ._plot import NO_FIGURES
    from .report import write_report

    sections = args.section or None
    skipped: list[str] = []
    no_figures: list[str] = []
    path = write_report(args.out, sections=sections, quick=args.quick, progress=not args.no_progress,
                        skipped=skipped, figures_skipped=no_figures)
    print(f"report written to {path}")
    code = 0
    if skipped:
        code = EXIT_PARTIAL
        print(f"satgnc reproduce: skipped {len(skipped)} cross-check(s) that need the test extra "
              f"(pip install \"satgnc[test]\"): {'; '.join(skipped)}; exit code {code}")
    if no_figures:
        code = EXIT_NO_FIGURES
        print(f"satgnc reproduce: {len(no_figures)} {NO_FIGURES}; exit code {code}")
    return code


def build_parser() -> argparse.ArgumentParser:
    p = ArgumentParser(prog="satgnc", description="satgnc: spacecraft GNC toolkit",
                       epilog="Errors print one line and exit with code 2; --debug (anywhere) shows the "
                       f"traceback. Other exit codes: {EXIT_PARTIAL} cross-checks skipped (reproduce), "
                       f"{EXIT_UNREACHABLE} a target unreachable (rendezvous), {EXIT_NO_FIGURES} numbers "
                       "written without figures (no matplotlib).")
    p.add_argument("--version", action="store_true", help="print the version and exit")
    p.add_argument("--debug", action="store_true", help="show the Python traceback of an error")
    sub = p.add_subparsers(dest="command")
    r = sub.add_parser("reproduce", help="reproduce the papers' tables and write a Markdown report",
                       epilog=f"Exit code 0: every section, cross-check and figure ran; {EXIT_PARTIAL}: the "
                       "report is written but the cross-checks that need the test extra (cvxpy, Clarabel; "
                       "pip install \"satgnc[test]\") were skipped (listed on one line and in the report); "
                       f"{EXIT_NO_FIGURES}: the report's numbers are written but no figures (no matplotlib: "
                       "pip install \"satgnc[plot]\"; takes precedence over 3); 2: a usage or input error.")
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


# Optional imports and the extra that provides each (pyproject.toml [project.optional-dependencies]).
_EXTRAS = {"matplotlib": "plot", "cvxpy": "test", "clarabel": "test", "scipy": "test", "control": "test"}


def _message(e: BaseException) -> str:
    if isinstance(e, KeyError):  # str(KeyError) is the bare quoted key
        return f"missing key {e}"
    if isinstance(e, MemoryError):
        return f"out of memory{': ' + str(e) if str(e) else ''} (hint: a smaller problem)"
    if isinstance(e, ImportError) and e.name in _EXTRAS:
        return f"{e} (install the optional dependency: pip install \"satgnc[{_EXTRAS[e.name]}]\")"
    if isinstance(e, ImportError) and not str(e):
        return f"cannot import {e.name}"
    text = str(e) or type(e).__name__
    return " ".join(text.split())  # one line: no embedded newlines


def _user_errors() -> tuple[type[BaseException], ...]:
    from .propagation import PropagationError

    return (ValueError, TypeError, OSError, KeyError, ImportError, MemoryError, PropagationError, CliError)


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv[: argv.index("--")] if "--" in argv else "--debug" in argv
    if debug:
        argv = [a for a in argv if a != "--debug"]
    try:
        parser = build_parser()
        try:
            args = parser.parse_args(argv)
        except SystemExit as e:  # --help (0) or a usage error (2, already printed on one line)
            return int(e.code or 0) if not isinstance(e.code, str) else 2
        if args.version:
            from . import __version__

            print(__version__)
            return 0
        if not getattr(args, "func", None):
            parser.print_help()
            return 2
        return int(args.func(args) or 0)
    except BrokenPipeError:  # `satgnc ... | head`: the reader left; not an error worth a message
        try:
            import os

            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError, AttributeError):
            pass
        return 1
    except KeyboardInterrupt:
        if debug:
            raise
        print("satgnc: interrupted", file=sys.stderr)
        return 130
    except Exception as e:
        if debug:
            raise
        if isinstance(e, _user_errors()):
            print(f"satgnc: error: {_message(e)}", file=sys.stderr)
            return 2
        print(f"satgnc: internal error: {type(e).__name__}: {_message(e)} (a bug: rerun with --debug "
              "and report the traceback)", file=sys.stderr)
        return 1


if __name__ == "__main__":  # python -m satgnc.cli: run the package module, not a second copy of it
    from satgnc.cli import main as _main

    sys.exit(_main())
