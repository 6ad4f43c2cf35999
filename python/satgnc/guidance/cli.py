"""``satgnc rendezvous --scenario FILE.toml --model linear|nonlinear --out DIR``: solve the scenario's
cases on the linear CW model (default) or the nonlinear two-satellite model and plot.

Both models read the same file (schema: :mod:`satgnc.scenarios.rendezvous`): its states, bounds,
horizon and weights. A scenario file is checked against the strict schema; any error prints one line
naming the file, the line and the key, and exits with code 2."""

from __future__ import annotations

import argparse
import json
import pathlib


def _run(args: argparse.Namespace) -> int:
    from ..papers import l1_admm_rendezvous_linear as rv
    from ..scenarios import l1_rendezvous as scen

    if getattr(args, "model", "linear") == "nonlinear":
        from ..scenarios import rendezvous

        if getattr(args, "reference", False):
            raise ValueError("--reference: only with --model linear (cvxpy solves the convex linear cases)")
        sc = rendezvous.load(getattr(args, "scenario", None), "scenario")
        cases = getattr(args, "case", None)
        for case in cases or []:
            if case not in sc.cases:
                raise ValueError(f"--case: unknown {case!r}; the scenario has {sorted(sc.cases)}")
        closed_loop = getattr(args, "closed_loop", False)
        return run_nonlinear(sc, cases, pathlib.Path(args.out), closed_loop=closed_loop)
    sc = scen._load(args.scenario, "scenario")
    closed_loop = getattr(args, "closed_loop", False)
    if closed_loop:  # the same file's nonlinear start and [truth] model
        from .. import _plot
        from ..scenarios import rendezvous
        from .flight import fly

        rsc = rendezvous.load(args.scenario, "scenario")
        truth = rendezvous.truth_params(rsc)
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
        # The published stopping rule is reported only for the paper's cases (they carry
        # paper_lqr_passes); a user's scenario is about its own problem.
        paper_case = sc.cases[case].get("paper_lqr_passes") is not None
        rv.plot_case(sc, run, out / f"{case}.png",
                     f"{case} (converged; dashed: paper-stop U)" if paper_case else f"{case} (converged)",
                     paper_stop=paper_case)
        summary[case] = run.metrics
        m = run.metrics
        line = (f"{case}: {m['conv_status']} in {m['conv_iterations']} iterations, "
                f"dv = {m['conv_dv']:.4f} m/s, ")
        if m["conv_status"] in _UNREACHABLE:
            best = best_achievable_miss(sc, case)
            m.update(unreachable=True, best_miss_m=best["miss_m"], best_miss_dv=best["dv"])
            line = (f"{case}: target unreachable ({m['conv_status']} after {m['conv_iterations']} "
                    f"iterations): {best['why']}; the best achievable miss is {best['miss_m']:.3f} m "
                    f"(dv = {best['dv']:.4f} m/s, the plan that minimizes the terminal error alone)")
        else:
            line += f"miss = {m['conv_miss_m']:.3f} m"
        if paper_case:
            line += (f"; paper rule: {m['paper_iterations']} iterations, "
                     f"flown miss {m['paper_miss_flown_Y_m'] / 1000:.2f} km")
        print(line)
        if closed_loop:
            pb = rendezvous.problem(rsc, case, "linear")
            flight = fly(truth, pb.state_eci(), run.converged.Y * sc.u_ref, pb.dt)
            m["truth_miss_open_loop_m"] = flight.miss[0]
            _plot.flight_figure(pb.dt, [("CW plan, open loop", flight.X)], out / f"{case}_flight.png",
                                _truth_title(rsc))
            print(f"  flown open loop on the scenario's truth model: miss {flight.miss[0]:.2f} m")
    if "unconstrained" in sc.cases:  # Fig. 1 is built from the unconstrained case
        dvq, dvl = rv.plot_fig1(sc, out / "quadratic_vs_l1.png")
        summary["quadratic_vs_l1_dv"] = {"quadratic": dvq, "l1": dvl}
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=str))
    print(f"plots and summary.json written to {out}")
    return 0


def _truth_title(sc) -> str:
    """The flight figure's title naming the scenario's [truth] model (point mass, J2, drag)."""
    t = sc.sections.get("truth") or {}
    terms = [name for name, on in (("J2", t.get("j2", True)), ("drag", t.get("drag", True))) if on]
    return f"Flying the plans on the truth model ({' + '.join(terms) or 'point mass'}, CVODES)"


#: ADMM statuses that mean the target cannot be met with the case's bounds (or was not met).
_UNREACHABLE = ("primal_infeasible", "terminal_unreachable", "max_iterations")


def best_achievable_miss(sc, case: str) -> dict:
    """The smallest terminal miss (m) the linear case can reach with its thrust bound: the same
    problem with a free arrival (terminal cost only) and a negligible fuel weight (1e-6 of the
    case's), solved to convergence. Returns ``{"miss_m", "dv" (m/s), "why"}``."""
    import numpy as np

    from ..guidance import L1Solver
    from ..papers import l1_admm_rendezvous_linear as rv
    from ..scenarios import l1_rendezvous as scen

    kw = scen.linear_problem(sc, case)
    kw["terminal_equality"] = False
    kw["l1_weights"] = 1e-6 * np.asarray(kw["l1_weights"])
    res = L1Solver(**kw, settings=dict(max_iterations=20000)).solve()
    box = "u_lower" in kw
    why = (f"|u| <= {sc.u_max * 1e3:g} mN per axis over tf = {sc.tf:g} s cannot bring the chaser there"
           if box else f"the horizon tf = {sc.tf:g} s is too short")
    return {"miss_m": rv.miss_m(sc, res.X_flown), "dv": rv.fuel_dv(sc, res.Y), "why": why}


def run_nonlinear(sc, cases, out, closed_loop: bool = False) -> int:
    """Plan ``cases`` (default: the scenario's nonlinear cases, see
    :meth:`~satgnc.scenarios.rendezvous.RendezvousScenario.nonlinear_cases`) of the scenario ``sc`` on
    the nonlinear model: the converged optimum (SCP) and, for a case with a ``[cases.<name>.nonlinear]``
    table, iLQR-ADMM with its rho and eps and the paper's stopping rule; plot; with ``closed_loop`` fly
    the exact-CW (zero-order hold) plan and the nonlinear plan open loop, and MPC, on the scenario's
    ``[truth]``. Writes PNGs and nonlinear_summary.json to ``out``."""
    import numpy as np

    from .. import _plot
    from ..scenarios import rendezvous
    from .flight import fly, mpc
    from .planning import plan

    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    truth = rendezvous.truth_params(sc)
    summary = {}
    for case in cases or sc.nonlinear_cases():
        pb = rendezvous.problem(sc, case, "nonlinear")
        nl = sc.cases[case]["nonlinear"]
        key = f"nonlinear_{case}"
        name = f"nonlinear {case}"
        scp = plan(pb, "nonlinear", "scp", eps=1e-7, tol=1e-8)
        s_opt = scp.summary()
        entry = {"horizon": pb.horizon, "scp_status": scp.status, "scp_outer": scp.iterations}
        sols = [("optimum (SCP)", scp.X, scp.U, "-")]
        line = f"{name}: "
        if nl is not None:
            paper = plan(pb, "nonlinear", "ilqr_admm", rho=nl["rho"], eps=nl["eps"], stop="paper")
            entry["paper_iterations"] = paper.iterations
            entry["paper_miss_flown_Y_m"] = paper.miss()[0]
            sols.append(("paper stop, sparse Y", paper.X, paper.U, ":"))
            line += (f"paper settings stop after {paper.iterations} iterations (sparse plan misses by "
                     f"{paper.miss()[0] / 1000:.2f} km); ")
        entry.update({f"opt_{k}": v for k, v in s_opt.items()})
        summary[key] = entry
        _plot.plan_figure(pb.dt, sols, out / f"{key}.png", name)
        print(line + f"optimum in {scp.iterations} SCP iterations ({scp.status}), "
              f"dv = {s_opt['delta_v']:.4f} m/s, miss = {s_opt['miss_position']:.2f} m")
        if closed_loop:
            lin = plan(pb, "linear", discretization="zoh")
            x0 = pb.state_eci()
            m = mpc(pb, truth=truth, planner=truth)
            flights = [
                ("CW plan, open loop", fly(truth, x0, lin.U, pb.dt)),
                ("nonlinear plan, open loop", fly(truth, x0, scp.U, pb.dt)),
                ("MPC", m),
            ]
            for label, f in flights:
                summary[key][f"truth_miss_{label}"] = f.miss[0]
                print(f"  {label}: truth miss {f.miss[0]:.2f} m")
            replan_ms = float(np.max(m.solve_times) * 1e3) if m.solve_times.size else 0.0
            summary[key]["mpc_replan_ms_max"] = replan_ms
            _plot.flight_figure(pb.dt, [(label, f.X) for label, f in flights], out / f"{key}_flight.png",
                                _truth_title(sc))
    (out / "nonlinear_summary.json").write_text(json.dumps(summary, indent=2, default=float))
    print(f"plots and nonlinear_summary.json written to {out}")
    return 0


def register(subparsers) -> None:
    p = subparsers.add_parser("rendezvous",
                              help="fuel-optimal L1 rendezvous guidance (ADMM) for a scenario file")
    p.add_argument("--scenario", default=None, help="scenario TOML (default: the packaged Table 1 scenario)")
    p.add_argument("--out", default="satgnc-rendezvous", help="output directory for plots and summary.json")
    p.add_argument("--case", action="append",
                   help="only this case (repeatable; default: every case, with --model nonlinear the cases "
                        "with a [cases.<name>.nonlinear] table)")
    p.add_argument("--reference", action="store_true",
                   help="also solve with cvxpy + Clarabel and report the gap")
    p.add_argument("--model", choices=["linear", "nonlinear"], default="linear",
                   help="plan the scenario's cases on the linear CW model (default) or the nonlinear "
                        "two-satellite model (the same file's states, bounds, horizon and weights)")
    p.add_argument("--closed-loop", action="store_true",
                   help="fly the plans on the scenario's [truth] model (linear: the converged plan open "
                        "loop; nonlinear: the CW and nonlinear plans open loop, and MPC)")
    p.set_defaults(func=_run)
