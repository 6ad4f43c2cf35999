"""``satgnc rendezvous --scenario FILE.toml --out DIR``: solve the scenario's linear cases and plot.

A scenario file is checked against a strict schema (see :func:`satgnc.scenarios.l1_rendezvous.load`);
any error prints one line naming the file, the line and the key, and exits with code 2."""

from __future__ import annotations

import argparse
import json
import pathlib


def _run(args: argparse.Namespace) -> int:
    from ..papers import l1_admm_rendezvous_linear as rv
    from ..scenarios import l1_rendezvous as scen

    if getattr(args, "model", "linear") == "nonlinear":
        from . import nonlinear

        for opt in ("--scenario", "--case", "--reference"):
            given = getattr(args, opt[2:], None)
            if given:
                raise ValueError(f"{opt}: only with --model linear (the nonlinear cases are built in)")
        return nonlinear.run_cli(pathlib.Path(args.out), closed_loop=args.closed_loop)
    if getattr(args, "closed_loop", False):
        raise ValueError("--closed-loop: only with --model nonlinear")
    sc = scen._load(args.scenario, "scenario")
    for case in args.case or []:
        if case not in sc.cases:
            raise ValueError(f"--case: unknown {case!r}; the scenario has {sorted(sc.cases)}")
    if args.reference:
        try:
            import cvxpy  # noqa: F401
        except ImportError:
            raise ImportError("--reference: needs the optional package cvxpy (pip install cvxpy clarabel)") \
                from None
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    cases = args.case or list(sc.cases)
    summary = {}
    for case in cases:
        if case not in sc.cases:
            raise ValueError(f"--case: unknown {case!r}; the scenario has {sorted(sc.cases)}")
        run = rv.run_case(sc, case, reference=args.reference)
        rv.plot_case(sc, run, out / f"{case}.png", f"{case} (converged; dashed: paper-stop U)")
        summary[case] = run.metrics
        m = run.metrics
        print(f"{case}: {m['conv_status']} in {m['conv_iterations']} iterations, "
              f"dv = {m['conv_dv']:.4f} m/s, "
              f"miss = {m['conv_miss_m']:.3f} m; paper rule: {m['paper_iterations']} iterations, "
              f"flown miss {m['paper_miss_flown_Y_m'] / 1000:.2f} km")
    if "unconstrained" in sc.cases:  # Fig. 1 is built from the unconstrained case
        dvq, dvl = rv.plot_fig1(sc, out / "quadratic_vs_l1.png")
        summary["quadratic_vs_l1_dv"] = {"quadratic": dvq, "l1": dvl}
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=str))
    print(f"plots and summary.json written to {out}")
    return 0


def register(subparsers) -> None:
    p = subparsers.add_parser("rendezvous",
                              help="fuel-optimal L1 rendezvous guidance (ADMM) for a scenario file")
    p.add_argument("--scenario", default=None, help="scenario TOML (default: the packaged Table 1 scenario)")
    p.add_argument("--out", default="satgnc-rendezvous", help="output directory for plots and summary.json")
    p.add_argument("--case", action="append", help="only this case (repeatable)")
    p.add_argument("--reference", action="store_true",
                   help="also solve with cvxpy + Clarabel and report the gap")
    p.add_argument("--model", choices=["linear", "nonlinear"], default="linear",
                   help="linear CW cases (default) or the nonlinear two-satellite cases (Table 1)")
    p.add_argument("--closed-loop", action="store_true",
                   help="with --model nonlinear: fly the plans on a J2 + drag truth (open loop, MPC)")
    p.set_defaults(func=_run)
