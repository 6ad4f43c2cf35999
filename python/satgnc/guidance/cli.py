"""``satgnc rendezvous --scenario FILE.toml --model linear|nonlinear --out DIR``: solve the scenario's
cases on the linear CW model (default) or the nonlinear two-satellite model and plot.

Both models read the same file (schema: :mod:`satgnc.scenarios.rendezvous`): its states, bounds,
horizon and weights. A scenario file is checked against the strict schema; any error prints one line
naming the file, the line and the key, and exits with code 2.

``summary.json`` holds one entry per case (``conv_*``: the converged plan). A case of the paper's own
scenario (it carries ``paper_lqr_passes``) adds the published stopping rule's numbers under
``paper_comparison``; a user's case never mentions the paper. Exit code 4 (``satgnc.cli.EXIT_UNREACHABLE``):
a case's target cannot be reached; its entry has ``unreachable: true`` and ``best_miss_m``, the smallest
terminal miss (m) the bounds allow. Exit code 5 (``EXIT_NO_FIGURES``): no matplotlib, numbers written
without figures (``pip install "satgnc[plot]"``)."""

from __future__ import annotations

import argparse
import json
import pathlib


def _run(args: argparse.Namespace) -> int:
    from ..papers import l1_admm_rendezvous_linear as rv
    from ..scenarios import l1_rendezvous as scen

    extra = ("failures", "passive_safety", "min_time", "keep_out", "constrained")
    if any(getattr(args, k, False) for k in extra):
        from ..scenarios import rendezvous

        sc = rendezvous.load(getattr(args, "scenario", None), "scenario")
        cases = getattr(args, "case", None) or [next(iter(sc.cases))]
        for case in cases:
            if case not in sc.cases:
                raise ValueError(f"--case: unknown {case!r}; the scenario has {sorted(sc.cases)}")
        out = pathlib.Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        codes = []
        for case in cases:
            if getattr(args, "failures", False):
                codes.append(run_failures(sc, case, out))
            if getattr(args, "passive_safety", False):
                codes.append(run_passive_safety(sc, case, out))
            if getattr(args, "min_time", False):
                codes.append(run_min_time(sc, case, out))
            if getattr(args, "keep_out", False):
                codes.append(run_keep_out(sc, case, out, getattr(args, "subproblem", "admm"),
                                          passive=getattr(args, "passive_safety", False)))
            if getattr(args, "constrained", False):
                codes.append(run_constrained(sc, case, out))
        return _worst(codes)

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
    _note_state_constraints(args.scenario)
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
    figures = _plot_available()
    cases = args.case or list(sc.cases)
    summary = {}
    unreachable = []
    for case in cases:
        if case not in sc.cases:
            raise ValueError(f"--case: unknown {case!r}; the scenario has {sorted(sc.cases)}")
        # The published settings and stopping rule run only for the paper's cases (they carry
        # paper_lqr_passes); a user's scenario is about its own problem and never mentions the paper.
        paper_case = sc.cases[case].get("paper_lqr_passes") is not None
        run = rv.run_case(sc, case, reference=args.reference, paper_run=paper_case)
        if figures:  # the title and legend say what the plan is: never "converged" for a stopped iterate
            st = run.metrics["conv_status"]
            what = "converged" if st == "solved" else (
                f"target unreachable: {st}, stopped iterate" if st in _UNREACHABLE else st)
            rv.plot_case(sc, run, out / f"{case}.png",
                         f"{case} ({what}; dashed: paper-stop U)" if paper_case else f"{case} ({what})",
                         paper_stop=paper_case, plan_label="converged" if st == "solved" else "plan")
        m = run.metrics
        line = (f"{case}: {m['conv_status']} in {m['conv_iterations']} iterations, "
                f"dv = {m['conv_dv']:.4f} m/s, ")
        if m["conv_status"] in _UNREACHABLE:
            best = best_achievable_miss(sc, case)
            m.update(unreachable=True, best_miss_m=best["miss_m"], best_miss_dv=best["dv"])
            unreachable.append(case)
            line = (f"{case}: target unreachable ({m['conv_status']} after {m['conv_iterations']} "
                    f"iterations): {best['why']}; the best achievable miss is {best['miss_m']:.3f} m "
                    f"(dv = {best['dv']:.4f} m/s, the plan that minimizes the terminal position error alone)")
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
            if figures:
                _plot.flight_figure(pb.dt, [("CW plan, open loop", flight.X)], out / f"{case}_flight.png",
                                    _truth_title(rsc))
            print(f"  flown open loop on the scenario's truth model: miss {flight.miss[0]:.2f} m")
        summary[case] = case_summary(m)
    if "unconstrained" in sc.cases and sc.cases["unconstrained"].get("paper_lqr_passes") is not None:
        # the paper's Fig. 1 (built from its unconstrained case)
        dvq, dvl = rv.plot_fig1(sc, out / "quadratic_vs_l1.png") if figures else rv.fig1_dv(sc)
        summary["paper_comparison"] = {"fig1_dv_m_s": {"quadratic": dvq, "l1": dvl}}
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=str))
    return _finish(out, "summary.json", figures, unreachable)


def case_summary(metrics: dict) -> dict:
    """One case's entry of ``summary.json``: the ``conv_*`` numbers (and ``unreachable``,
    ``best_miss_m``, ``truth_miss_*``) at the top; a paper case's published-stopping-rule numbers under
    ``paper_comparison`` (keys without the ``paper_`` prefix). A user's case has no ``paper`` key."""
    entry = {k: v for k, v in metrics.items() if not k.startswith("paper_")}
    paper = {k[len("paper_"):]: v for k, v in metrics.items() if k.startswith("paper_")}
    if paper:
        entry["paper_comparison"] = paper
    return entry


def _worst(codes: list[int]) -> int:
    """The exit code of several runs: EXIT_UNREACHABLE over EXIT_NO_FIGURES over 0."""
    from ..cli import EXIT_NO_FIGURES, EXIT_UNREACHABLE

    for code in (EXIT_UNREACHABLE, EXIT_NO_FIGURES):
        if code in codes:
            return code
    return 0


def _no_figures_code(figures: bool) -> int:
    """0, or (one line printed) EXIT_NO_FIGURES when matplotlib is missing."""
    if figures:
        return 0
    from .._plot import NO_FIGURES
    from ..cli import EXIT_NO_FIGURES

    print(f"satgnc rendezvous: {NO_FIGURES}; exit code {EXIT_NO_FIGURES}")
    return EXIT_NO_FIGURES


def _plot_available() -> bool:
    from .. import _plot

    return _plot.available()


def _finish(out: pathlib.Path, summary_name: str, figures: bool, unreachable: list[str]) -> int:
    """The closing lines of ``satgnc rendezvous`` and its exit code (see :mod:`satgnc.cli`): 0, or
    EXIT_UNREACHABLE when a case's target cannot be reached, else EXIT_NO_FIGURES without matplotlib."""
    from .._plot import NO_FIGURES
    from ..cli import EXIT_NO_FIGURES, EXIT_UNREACHABLE

    print(f"{'plots and ' if figures else ''}{summary_name} written to {out}")
    if not figures:
        print(f"satgnc rendezvous: {NO_FIGURES}; exit code {EXIT_NO_FIGURES}")
    if unreachable:
        print(f"satgnc rendezvous: target unreachable in {', '.join(unreachable)} (best achievable miss in "
              f"{summary_name}); exit code {EXIT_UNREACHABLE}")
        return EXIT_UNREACHABLE
    return 0 if figures else EXIT_NO_FIGURES


def _note_state_constraints(path) -> None:
    """One line when the file has state-constraint sections, which only ``--constrained`` plans with:
    the cases below are planned without them (never silently)."""
    if path is None:
        return
    from ..scenarios import rendezvous

    secs = rendezvous.load(path, "scenario").sections
    named = [f"[[{k}]]" if k == "half_spaces" else f"[{k}]"
             for k in rendezvous.CONSTRAINT_SECTIONS if secs.get(k)]
    if named:
        print(f"note: the scenario's {', '.join(named)} apply with --constrained; the cases below are "
              "planned without them")


def _truth_title(sc) -> str:
    """The flight figure's title naming the scenario's [truth] model (point mass, J2, drag)."""
    t = sc.sections.get("truth") or {}
    j2, drag, src = t.get("j2", True), t.get("drag", True), ""
    if t.get("force_model") is not None:  # the file's terms, not the [truth] defaults
        from ..scenarios import rendezvous

        tp = rendezvous.truth_params(sc)
        j2, drag, src = tp.j2_on, tp.drag_on, f" from {t['force_model'].name}"
    terms = [name for name, on in (("J2", j2), ("drag", drag)) if on]
    return f"Flying the plans on the truth model ({' + '.join(terms) or 'point mass'}{src}, CVODES)"


#: ADMM statuses that mean the target cannot be met with the case's bounds (or was not met).
_UNREACHABLE = ("primal_infeasible", "terminal_unreachable", "max_iterations")


def best_achievable_miss(sc, case: str) -> dict:
    """The smallest terminal position miss (m) the linear case can reach with its thrust bound: the same
    problem with a free arrival, a terminal cost on the position only (the velocity block of Qf set to
    0: weighting it too traded position for velocity, 443.6 m instead of 301.2 m on the 0.2 mN user
    case) and a negligible fuel weight (1e-9 of the case's), solved to convergence. Equals cvxpy +
    Clarabel's minimum of |r_N| to 1e-6 relative (tests/python/test_user_paths.py). Returns
    ``{"miss_m", "dv" (m/s), "why"}``."""
    import numpy as np

    from ..guidance import L1Solver
    from ..papers import l1_admm_rendezvous_linear as rv
    from ..scenarios import l1_rendezvous as scen

    kw = scen.linear_problem(sc, case)
    kw["terminal_equality"] = False
    kw["l1_weights"] = 1e-9 * np.asarray(kw["l1_weights"])
    qf = np.array(kw["Qf"], dtype=float)
    qf[3:, :] = 0.0
    qf[:, 3:] = 0.0
    kw["Qf"] = qf
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
    figures = _plot_available()
    truth = rendezvous.truth_params(sc)
    summary = {}
    unreachable: list[str] = []
    for case in cases or sc.nonlinear_cases():
        pb = rendezvous.problem(sc, case, "nonlinear")
        nl = sc.cases[case]["nonlinear"]
        key = f"nonlinear_{case}"
        name = f"nonlinear {case}"
        scp = plan(pb, "nonlinear", "scp", eps=1e-7, tol=1e-8)
        s_opt = scp.summary()
        entry = {"horizon": pb.horizon, "scp_status": scp.status, "scp_outer": scp.iterations}
        scp_label = "optimum (SCP)" if scp.status == "solved" else f"SCP stopped ({scp.status})"
        sols = [(scp_label, scp.X, scp.U, "-")]
        line = f"{name}: "
        if nl is not None:
            # iLQR-ADMM with the file's rho and eps and the published stopping rule: named the paper's
            # only on the paper's cases (paper_lqr_passes); a user's case never mentions the paper.
            ilqr = plan(pb, "nonlinear", "ilqr_admm", rho=nl["rho"], eps=nl["eps"], stop="paper")
            numbers = {"iterations": ilqr.iterations, "miss_flown_Y_m": ilqr.miss()[0]}
            if sc.cases[case].get("paper_lqr_passes") is not None:
                entry["paper_comparison"] = numbers
                sols.append(("paper stop, sparse Y", ilqr.X, ilqr.U, ":"))
                line += (f"paper settings stop after {ilqr.iterations} iterations (sparse plan misses by "
                         f"{ilqr.miss()[0] / 1000:.2f} km); ")
            else:
                entry.update({f"ilqr_admm_{k}": v for k, v in numbers.items()})
                sols.append(("iLQR-ADMM (file's rho, eps), sparse Y", ilqr.X, ilqr.U, ":"))
                line += (f"iLQR-ADMM (rho = {nl['rho']:g}, eps = {nl['eps']:g}) stops after "
                         f"{ilqr.iterations} iterations (sparse plan misses by {ilqr.miss()[0]:.2f} m); ")
        entry.update({f"opt_{k}": v for k, v in s_opt.items()})
        summary[key] = entry
        if figures:
            _plot.plan_figure(pb.dt, sols, out / f"{key}.png", name)
        if scp.status == "inner_infeasible":  # the convex subproblem cannot meet the target
            best = _linear_best_miss(sc, case)
            entry.update(unreachable=True, best_miss_m_linear_cw=best)
            unreachable.append(case)
            print(line + f"target unreachable ({scp.status} after {scp.iterations} SCP iterations): the "
                  f"stopped plan misses by {s_opt['miss_position']:.2f} m (dv = {s_opt['delta_v']:.4f} m/s); "
                  f"the best achievable miss on the linear CW model is "
                  + ("n/a" if best is None else f"{best:.3f} m"))
        else:
            print(line + f"{'optimum' if scp.status == 'solved' else 'stopped'} in {scp.iterations} SCP "
                  f"iterations ({scp.status}), dv = {s_opt['delta_v']:.4f} m/s, "
                  f"miss = {s_opt['miss_position']:.2f} m")
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
            if figures:
                _plot.flight_figure(pb.dt, [(label, f.X) for label, f in flights], out / f"{key}_flight.png",
                                    _truth_title(sc))
    (out / "nonlinear_summary.json").write_text(json.dumps(summary, indent=2, default=float))
    return _finish(out, "nonlinear_summary.json", figures, unreachable)


def _linear_best_miss(sc, case: str) -> float | None:
    """:func:`best_achievable_miss` of the same file's case on the linear CW model (m), or None when the
    file has no linear reading (a scenario given as an object, not a path)."""
    from ..scenarios import l1_rendezvous as scen

    path = getattr(sc, "path", None)
    if path is None:
        return None
    return float(best_achievable_miss(scen._load(path, "scenario"), case)["miss_m"])


def _layout(sc, flag: str):
    from ..scenarios import rendezvous

    lay = rendezvous.thruster_layout(sc)
    if lay is None:
        raise ValueError(f"{flag}: the scenario {sc.path} has no [[thrusters]] tables (the thruster layout)")
    return lay


def run_failures(sc, case: str, out: pathlib.Path) -> int:
    """The thruster-loss table of ``case`` (:func:`satgnc.mission.failures.failure_table`) with the
    scenario's ``[[thrusters]]``, ``[failures]`` and ``[truth]``: prints it and writes
    ``failures_<case>.md`` and ``failures_<case>.json``."""
    from ..mission.failures import failure_table
    from ..scenarios import rendezvous

    lay = _layout(sc, "--failures")
    pb = rendezvous.problem(sc, case, "linear")
    t = failure_table(pb, lay, pairs=sc.sections["failures"]["pairs"], truth=rendezvous.truth_params(sc))
    md = t.markdown()
    title = (f"Thruster-loss table, case {case}: {lay.size} thrusters, N = {pb.horizon}, dt = {pb.dt:.4g} s, "
             f"{t.elapsed:.3f} s\n\n")
    (out / f"failures_{case}.md").write_text(title + md + "\n")
    rows = [{k: v for k, v in r.to_dict().items() if k != "thrusts"} for r in t.rows] \
        if hasattr(t.rows[0], "to_dict") else [
            {f: getattr(r, f) for f in ("failed", "survivors", "rank", "verdict", "distance", "sign_ok",
                                        "controllable", "status", "certified", "fuel", "delta_v", "miss",
                                        "impulse_bit_violations", "solve_time")} for r in t.rows]
    (out / f"failures_{case}.json").write_text(json.dumps({"elapsed_s": t.elapsed, "rows": rows}, indent=2,
                                                          default=float))
    print(title + md)
    return 0


def run_passive_safety(sc, case: str, out: pathlib.Path) -> int:
    """Passive safety of ``case``'s linear plan flown open loop on the ``[truth]``: each node's free drift
    for ``[passive_safety] drift_time`` s against ``[keep_out]``; writes ``passive_safety_<case>.png``."""
    from ..scenarios import rendezvous
    from .flight import fly
    from .planning import plan
    from .safety import cw_positions, passive_safety, safety_figure

    ps_cfg, ko = sc.sections["passive_safety"], rendezvous.keep_out(sc)
    if ps_cfg is None or ko is None:
        raise ValueError(f"--passive-safety: the scenario {sc.path} needs [passive_safety] and [keep_out]")
    truth = rendezvous.truth_params(sc)
    pb = rendezvous.problem(sc, case, "linear")
    p = plan(pb, "linear", discretization="zoh")
    fl = fly(truth, pb.state_eci(), p.U, pb.dt)
    ps = passive_safety(truth, fl.X, ko, ps_cfg["drift_time"], ps_cfg["samples"])
    path = out / f"passive_safety_{case}.png"
    figures = _plot_available()
    if figures:
        safety_figure(ps, path, cw_positions(fl.X))
    print(f"{case}: passive safety over {ps.drift_time:.0f} s: {int(ps.safe.sum())}/{ps.safe.size} "
          "nodes safe, "
          f"smallest ellipsoidal radius {float(ps.min_rho.min()):.3g}; "
          f"figure {path if figures else 'not drawn'}")
    return _no_figures_code(figures)


def run_min_time(sc, case: str, out: pathlib.Path) -> int:
    """Minimum horizon (bisection on N at the scenario's dt, up to its knots - 1) and the fuel-time
    curve of ``case`` with the ``[[thrusters]]`` layout (or the case's box); writes
    ``fuel_time_<case>.md`` and ``.png``."""
    import numpy as np

    from ..scenarios import rendezvous
    from .min_time import fuel_time_curve, minimum_horizon, trade_figure

    pb = rendezvous.problem(sc, case, "linear")
    lay = rendezvous.thruster_layout(sc)
    m = minimum_horizon(pb, lay)
    if m.horizon == 0:
        from ..cli import EXIT_UNREACHABLE

        print(f"{case}: the target is not reachable within N = {pb.horizon} (certified); exit code "
              f"{EXIT_UNREACHABLE}")
        return EXIT_UNREACHABLE
    Ns = np.unique(np.linspace(max(m.horizon - 1, 1), pb.horizon, 12).astype(int))
    c = fuel_time_curve(pb, Ns, lay)
    figures = _plot_available()
    if figures:
        trade_figure(c, out / f"fuel_time_{case}.png", m)
    md = (f"Minimum time {m.transfer_time:.1f} s (N = {m.horizon}, dt = {m.dt:.4g} s; monotone at the "
          f"bracket: {m.monotone_at_bracket})\n\n" + c.markdown())
    (out / f"fuel_time_{case}.md").write_text(md + "\n")
    print(md)
    return _no_figures_code(figures)


def run_keep_out(sc, case: str, out: pathlib.Path, subproblem: str = "admm", passive: bool = False) -> int:
    """The keep-out plan of ``case`` (:func:`satgnc.guidance.keep_out.keep_out_plan`) to the
    ``[keep_out] hold_point`` with the ``[[thrusters]]`` layout (or the case's box), its check on the
    ``[truth]`` at the nodes and between them; writes ``keep_out_<case>.json``. ``passive`` (with
    ``--passive-safety``): passive safety over ``[passive_safety] drift_time`` imposed in the SCP, its
    check on the truth in the json and ``keep_out_passive_<case>.png``."""
    import numpy as np

    from ..scenarios import rendezvous
    from .keep_out import keep_out_plan

    ko, k = rendezvous.keep_out(sc), sc.sections["keep_out"]
    if ko is None or k["hold_point"] is None:
        raise ValueError(f"--keep-out: the scenario {sc.path} needs [keep_out] with hold_point")
    pb = rendezvous.problem(sc, case, "linear")
    ps_cfg = sc.sections["passive_safety"] if passive else None
    if passive and ps_cfg is None:
        raise ValueError(f"--passive-safety: the scenario {sc.path} needs [passive_safety]")
    drift = {} if ps_cfg is None else {"drift_time": ps_cfg["drift_time"],
                                       "drift_check_samples": ps_cfg["samples"]}
    plume = rendezvous.plume(sc)
    r = keep_out_plan(pb, ko, xf=np.r_[k["hold_point"], 0.0, 0.0, 0.0], layout=rendezvous.thruster_layout(sc),
                      margin=k["margin"], solver=subproblem, truth=rendezvous.truth_params(sc), plume=plume,
                      **drift)
    d = {"status": r.status, "converged": r.converged, "iterations": r.iterations, "fuel_Ns": r.fuel,
         "fuel_history": r.fuel_history.tolist(), "min_node_rho": float(r.node_rho[1:].min()),
         "flown_rho_nodes": r.flown_rho_nodes, "flown_rho_min": r.flown_rho_min,
         "satisfied_nodes": r.satisfied_nodes, "satisfied_flown": r.satisfied_flown,
         "wall_time_s": r.wall_time}
    if plume is not None:
        d.update(plume_half_angle_deg=plume["half_angle_deg"], plume_range_m=plume["range"],
                 plume_inhibited=int(r.plume_inhibited.sum()), plume_violations=r.plume_violations)
    if r.passive is not None:
        from .safety import cw_positions, safety_figure

        d.update(passive_drift_time_s=r.passive.drift_time, passive_nodes_safe=int(r.passive.safe.sum()),
                 passive_nodes=int(r.passive.safe.size), passive_min_rho=float(r.passive.min_rho.min()),
                 drift_slack_m=r.drift_slack)
        if _plot_available():
            safety_figure(r.passive, out / f"keep_out_passive_{case}.png", cw_positions(r.flown_X),
                          title="Keep-out plan with passive safety imposed: free drift from each node "
                                "(truth)",
                          nodes=np.arange(1, r.passive.safe.size + 1))  # the default drift nodes 1..N-1
    (out / f"keep_out_{case}.json").write_text(json.dumps(d, indent=2, default=float))
    print(f"{case}: keep-out plan {r.status} after {r.iterations} SCP iterations (converged: {r.converged}), "
          f"fuel {r.fuel:.4g} N s; outside the zone at every node: {r.satisfied_nodes}; on the truth "
          f"between nodes: {r.satisfied_flown} (smallest radius {r.flown_rho_min:.3f})")
    if plume is not None:
        print(f"{case}: plume cone {plume['half_angle_deg']:g} deg within {plume['range']:g} m: "
              f"{int(r.plume_inhibited.sum())} thruster-intervals inhibited, {r.plume_violations} impinging "
              "firings on the returned plan")
    if r.passive is not None:
        print(f"{case}: passive safety imposed over {r.passive.drift_time:.0f} s: "
              f"{int(r.passive.safe.sum())}/{r.passive.safe.size} drift nodes safe on the truth, smallest "
              f"radius {float(r.passive.min_rho.min()):.3f}; remaining violation on CW {r.drift_slack:.3g} m")
        return _no_figures_code(_plot_available())
    return 0


def run_constrained(sc, case: str, out: pathlib.Path) -> int:
    """The fuel-optimal plan of ``case`` under the scenario's state constraints (``[approach_cone]``,
    ``[state_box]``, ``[closing_velocity]``, ``[[half_spaces]]``; :func:`satgnc.guidance.constrained.
    constrained_plan`) with the ``[[thrusters]]`` layout or the case's box, to the target exactly; the
    violation re-checked at the nodes, the plan flown open loop on the ``[truth]``; writes
    ``constrained_<case>.json``."""
    from ..scenarios import rendezvous
    from .constrained import constrained_plan

    kw = rendezvous.state_constraints(sc)
    if not kw:
        raise ValueError(f"--constrained: the scenario {sc.path} has no [approach_cone], [state_box], "
                         "[closing_velocity] or [[half_spaces]]")
    pb = rendezvous.problem(sc, case, "linear")
    r = constrained_plan(pb, layout=rendezvous.thruster_layout(sc), truth=rendezvous.truth_params(sc), **kw)
    d = {"status": r.status, "iterations": r.iterations, "fuel_Ns": r.fuel, "dv_mps": r.fuel / pb.mass,
         "violation": r.violation, "max_violation": r.max_violation,
         "violation_tolerance": r.violation_tolerance, "duality_gap": r.duality_gap,
         "truth_miss_m": r.truth_miss, "solve_time_s": r.solve_time}
    (out / f"constrained_{case}.json").write_text(json.dumps(d, indent=2, default=float))
    worst = max(r.violation.values())
    print(f"{case}: constrained plan ({', '.join(r.violation)}) {r.status} in {r.iterations} iterations, "
          f"fuel {r.fuel:.4g} N s (dv {r.fuel / pb.mass:.4g} m/s); largest violation at the nodes "
          f"{worst:.3g} (tolerance {r.violation_tolerance:.3g}); miss on the truth {r.truth_miss:.3g} m")
    return 0


def register(subparsers) -> None:
    p = subparsers.add_parser("rendezvous",
                              help="fuel-optimal L1 rendezvous guidance (ADMM) for a scenario file",
                              epilog="Exit code 0: every case solved, figures drawn; 4: a case's target is "
                                     "unreachable (summary.json has unreachable and best_miss_m, the best "
                                     "achievable miss in m); 5: numbers written without figures (no "
                                     "matplotlib: pip install \"satgnc[plot]\"); 2: a usage or input error.")
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
    p.add_argument("--failures", action="store_true",
                   help="the thruster-loss table of the scenario's [[thrusters]] layout: controllability and "
                        "margin of the survivors, L1 replan, fuel and miss on the [truth] (issue 16)")
    p.add_argument("--passive-safety", action="store_true",
                   help="free drift from each node of the flown plan against [keep_out] ([passive_safety]); "
                        "with --keep-out also imposed in that plan's SCP")
    p.add_argument("--min-time", action="store_true",
                   help="minimum horizon by bisection on N and the fuel-versus-transfer-time curve")
    p.add_argument("--keep-out", action="store_true",
                   help="fuel-optimal plan to [keep_out] hold_point outside the keep-out zone (SCP with "
                        "supporting half-spaces), checked at the nodes and between them on the [truth]")
    p.add_argument("--constrained", action="store_true",
                   help="fuel-optimal plan under the scenario's [approach_cone], [state_box], "
                        "[closing_velocity] and [[half_spaces]] (state-constrained ADMM), re-checked at the "
                        "nodes and flown on the [truth]")
    p.add_argument("--subproblem", choices=["admm", "cvxpy"], default="admm",
                   help="--keep-out's convex subproblem solver (cvxpy: cvxpy + Clarabel, the reference)")
    p.set_defaults(func=_run)
