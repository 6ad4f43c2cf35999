"""Report section: L1 guidance on the nonlinear two-satellite model (Table 1 nonlinear columns,
Figs. 4-5, flying the plans, receding-horizon re-planning)."""

from __future__ import annotations

import json
import time

import numpy as np

TITLE = "Guidance on nonlinear dynamics (l1_admm_rendezvous.md, Table 1 nonlinear columns, Figs. 4-5)"


def _fmt(v, d=3):
    return f"{v:.{d}g}" if isinstance(v, float) else str(v)


def _figure(case, sols, path, title):
    """Fig. 4/5 of a case: sols = [(label, U (3 x N, newtons), line style)], rolled out on the case's map."""
    from .. import _plot

    _plot.plan_figure(case.dt, [(label, case.rollout_si(U).T, np.asarray(U).T, ls) for label, U, ls in sols],
                      path, title)


def _flight_figure(case, flights, path):
    """Flights of a case: [(label, X (12 x N+1))]."""
    from .. import _plot

    _plot.flight_figure(case.dt, [(label, np.asarray(X).T) for label, X in flights], path)


def build(ctx) -> str:
    from satgnc.data import __file__ as data_file  # noqa: F401

    from .. import _satgnc as _c
    from ..papers import l1_admm_rendezvous as nl

    out = []
    x = nl.drift_state()
    cw = np.asarray(_c.cw_relative_state_published(x, nl.MU))
    out += [
        "Model: the paper's eq. (33) as the published implementation codes it: 12 states "
        "[r_t - r_c, r_t, v_t - v_c, v_t] (ECI, m, m/s), point-mass gravity (mu = 3.99e14), drag "
        "(Cd = 1, A = 0.01 m^2, 9.201e-5 exp(-5.301e-5 h), h = |r| - 6731 km), control force in the "
        "target's CW frame; analytic Jacobians, RK3 (Kutta) map with its exact Jacobians.",
        "",
        "Drag sign: the paper writes v_rel = pdot + p x omega = v - omega x r (co-rotating atmosphere); "
        "the implementation computes v + omega x r. satgnc defaults to the physical sign and keeps the "
        "published one for reproduction; at 500 km the density is ~3e-16 kg/m^3 and the two differ by "
        "less than 1e-9 m over the drift.",
        "",
        f"1 h drift (RK4, 9999 steps): p = {np.round(cw[:3], 3).tolist()} m, "
        f"v = {np.round(cw[3:], 6).tolist()} m/s (l1_scenario.md: [-9477.311, -1999.979, -43.046] m, "
        "[-3.477486, 1.007149, -0.090170] m/s; equal to the printed digits).",
        "",
    ]
    rows = []
    figs = []
    flights = {}
    summary = {}
    disc_rows = []
    for constrained in (False, True):
        case = nl.paper_case(constrained)
        t0 = time.perf_counter()
        paper = nl.solve_paper(case)
        t_paper = time.perf_counter() - t0
        t0 = time.perf_counter()
        scp = nl.solve_scp(case, eps=1e-7, tol=1e-8)
        t_scp = time.perf_counter() - t0
        lin = nl.linear_cw_plan(case, eps=1e-8)
        s_u = nl.summarize(case, paper.U)
        s_y = nl.summarize(case, paper.Y)
        s_opt = nl.summarize(case, scp.U)
        s_lin = nl.summarize(case, case.from_si(lin["U"]))
        rows.append((case.name, paper.info, t_paper, scp.info, t_scp, s_u, s_y, s_opt, s_lin))
        sols = [("optimum (SCP)", case.to_si(scp.U), "-"), ("paper stop, dense U", case.to_si(paper.U), ":")]
        title = f"Fig. {5 if constrained else 4}: {case.name}"
        figs += ctx.image("fig5_nonlinear_constrained" if constrained else "fig4_nonlinear_unconstrained",
                          title.split(":")[0], lambda p, c=case, s=sols, t=title: _figure(c, s, p, t))
        truth = {}
        for label, U in (("CW plan, open loop", lin["U"]), ("nonlinear plan, open loop", case.to_si(scp.U))):
            X = nl.fly(case, U)
            truth[label] = (X, U)
        if not ctx.quick:
            m = nl.mpc(case)
            truth["MPC (re-plan every 3 intervals)"] = (m["X"], m["U"])
            summary[case.name + " mpc"] = {
                "solve_ms_median": float(np.median(m["solve_times"]) * 1e3),
                "solve_ms_max": float(np.max(m["solve_times"]) * 1e3),
                "replans": int(len(m["solve_times"])),
            }
        flights[case.name] = truth
        # the propagated map (DOP853 on state, STM and control sensitivity) against the RK3 transcription:
        # each optimum flown on the planner's own physics (no J2), so only the discretization differs
        dcase = nl.paper_case(constrained, discretization="dop853")
        sd = nl.solve_scp(dcase, eps=1e-7, tol=1e-8)
        same = nl.model_params()
        disc_rows.append(
            (
                case.name,
                s_opt["miss_position"],
                nl.miss(nl.fly(case, case.to_si(scp.U), truth_params=same))[0],
                nl.summarize(dcase, sd.U)["miss_position"],
                nl.miss(nl.fly(dcase, dcase.to_si(sd.U), truth_params=same))[0],
                sd.info.objective,
            )
        )

    out += [
        "### Table 1, nonlinear columns",
        "",
        "| | paper | satgnc, paper settings | converged optimum (SCP) | linear CW optimum, flown |",
        "|---|---|---|---|---|",
    ]
    for name, pi, tp, si, ts, s_u, s_y, s_opt, s_lin in rows:
        paper_passes = 206 if "constrained" == name.split()[-1] else 120
        out.append(
            f"| **{name}** | {paper_passes} LQR passes | {pi.iterations} ADMM iterations, "
            f"{pi.lqr_passes} passes ({tp * 1e3:.0f} ms) | {si.outer_iterations} outer, "
            f"{si.inner_iterations} inner ADMM iterations ({ts * 1e3:.0f} ms) | |"
        )
        out.append(
            f"| objective | | dense U {s_u['objective']:.5f}; sparse Y {s_y['objective']:.4g} | "
            f"{s_opt['objective']:.6f} | {s_lin['objective']:.5f} |"
        )
        out.append(
            f"| delta-v, m/s | | U {s_u['delta_v']:.4f}; Y {s_y['delta_v']:.4f} | {s_opt['delta_v']:.4f} | "
            f"{s_lin['delta_v']:.4f} |"
        )
        out.append(
            f"| terminal miss, m | | U {s_u['miss_position']:.2f}; Y {s_y['miss_position']:.1f} | "
            f"{s_opt['miss_position']:.2f} | {s_lin['miss_position']:.1f} |"
        )
        out.append(
            f"| zero control entries | | U {s_u['sparsity']:.0%}; Y {s_y['sparsity']:.0%} | "
            f"{s_opt['sparsity']:.0%} ({s_opt['nonzero_intervals']} intervals firing) | "
            f"{s_lin['sparsity']:.0%} |"
        )
    out += [
        "",
        "Unconstrained: with rho = 0.1, eps = 6e-5 (on ||U - Y||_2 / 297), the multiplier row rescaling "
        "after iteration 1 and one Gauss-Newton iLQR iteration per ADMM iteration, satgnc stops after "
        "exactly 60 ADMM iterations = the paper's 120 passes (the implementation counts the rollout "
        "as a pass). At that point the sparse iterate Y misses the target by ~9 km when flown; the "
        "figure shows the dense U, which is nowhere zero. SCP reaches the optimum of the same "
        "transcription in 3-4 re-linearizations; the paper's scheme run on needs tens of thousands "
        "of iterations (measured: 30000 iterations reach 1e-4 to 1e-7 relative depending on rho).",
        "",
        "Constrained: the paper's 206 'passes' count iterations of TrajectoryOptimization.jl's "
        "augmented-Lagrangian iLQR (box constraints inside the inner solve) and are not ADMM "
        "iterations; satgnc puts the box in the prox (exact prox of L1 + box), so its iteration "
        "count at the paper's rho = 10, eps = 5e-6 is not comparable and is reported as measured.",
        "",
    ]
    out += figs

    out += [
        "### RK3 transcription against the propagated map",
        "",
        "The published RK3 over 60.6 s intervals against satgnc's propagated map (adaptive DOP853 on the "
        "state, its STM and control sensitivity: the flow itself, rtol 1e-10). Each optimum is flown on the "
        "planner's own physics (no J2, CVODES), so the difference is the transcription error alone.",
        "",
        "| case | RK3 plan: planned miss, m | RK3 plan flown, m | DOP853 plan: planned miss, m | "
        "DOP853 plan flown, m | DOP853 objective |",
        "|---|---|---|---|---|---|",
    ]
    for name, p3, f3, pd, fd, jd in disc_rows:
        out.append(f"| {name} | {p3:.3f} | {f3:.3f} | {pd:.3f} | {fd:.3f} | {jd:.7f} |")
    out += [
        "",
        "### Flying the plan",
        "",
        "Truth: the same two-satellite model with J2 and co-rotating drag on, integrated by satgnc's CVODES "
        "path (Adams + Newton, rtol 1e-11, re-initialised at every control interval; the plans use RK3 at "
        "60.6 s without J2). Terminal miss |r_t - r_c| at t = 6000 s.",
        "",
        "| case | plan | miss, m | miss, m/s | delta-v, m/s | max |u|, N |",
        "|---|---|---|---|---|---|",
    ]
    for name, tr in flights.items():
        for label, (X, U) in tr.items():
            mp, mv = nl.miss(X)
            out.append(
                f"| {name} | {label} | {mp:.2f} | {mv:.4f} | {np.abs(U).sum() * nl.TF / nl.N / nl.MASS:.4f} "
                f"| {np.abs(U).max():.4f} |"
            )
    out.append("")
    for k, v in summary.items():
        out.append(
            f"- {k}: {v['replans']} re-plans, CPU time per re-plan median {v['solve_ms_median']:.2f} ms, "
            f"max {v['solve_ms_max']:.2f} ms (warm-started iLQR-ADMM, 10 N / remaining iterations capped at "
            "120, Qf x 1e4, planner with J2)."
        )
    name0 = next(iter(flights))
    out += ["", *ctx.image("nonlinear_flight", "flight", lambda p: _flight_figure(
        nl.paper_case(False), [(k, v[0]) for k, v in flights[name0].items()], p))]
    (ctx.outdir / "guidance_nonlinear.json").write_text(json.dumps(summary, indent=1))
    return "\n".join(out)
