"""Report section: l1_admm_rendezvous.md, Table 1 linear columns and Figs. 1-3."""

from __future__ import annotations

import json

TITLE = "L1 rendezvous guidance by ADMM (l1_admm_rendezvous.md, Table 1, linear columns)"


def _num(m: dict, key: str, fmt: str) -> str:
    """``m[key]`` formatted, or "n/a (no cvxpy)" when the cross-check did not run."""
    return format(m[key], fmt) if key in m else "n/a (no cvxpy)"


def build(ctx) -> str:
    from importlib import resources

    from ..papers import l1_admm_rendezvous_linear as rv
    from ..scenarios import l1_rendezvous as scen

    tables = json.loads(resources.files("satgnc.data").joinpath("paper_tables.json").read_text())
    t1 = tables["l1_admm_rendezvous"]["table1"]
    sc = scen.load()
    ref = ctx.have("cvxpy", "clarabel", check="guidance: converged plans against Clarabel (cvxpy)")
    runs = {c: rv.run_case(sc, c, reference=ref) for c in ("unconstrained", "constrained", "box")}
    lines = [
        "Scenario (data/l1_scenario.md): drifted relative state p = [-9477.3, -2000.0, -43.0] m, "
        "v = [-3.4775, 1.0071, -0.0902] m/s (9.7 km, not the paper's 50 m), n = "
        f"{sc.n:.6e} rad/s, m = {sc.mass} kg, tf = {sc.tf:.0f} s, {sc.knots} knots, dt = {sc.dt:.4f} s, "
        "explicit-midpoint CW, the implementation's scaling (length "
        f"{sc.l_ref:.2f} m, speed {sc.v_ref:.4f} m/s, time {sc.t_ref:.1f} s, force {sc.u_ref:.4e} N), "
        "alpha = 1, Qf = 1000 I scaled (the implementation multiplies the ADMM penalty by dt inside "
        "the LQR, i.e. it converges to the problem with terminal weight Qf/dt = "
        f"{sc.Qf / (sc.dt / sc.t_ref):.0f} I; that is the problem solved and checked here).",
        "",
        "### Table 1 with the published settings",
        "",
        "| case | rho | eps | paper LQR passes | satgnc ADMM iterations | passes (2 per iteration) | "
        "miss flying sparse Y | miss of LQR iterate U | dv of Y | dv of U |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for col, case in ((0, "unconstrained"), (1, "constrained")):
        m = runs[case].metrics
        passes = m["paper_passes_if_unconstrained"] if case == "unconstrained" else "n/a (see below)"
        lines.append(
            f"| linear {case} | {t1['rho'][col]:g} | {t1['eps'][col]:g} | {t1['lqr_passes'][col]} | "
            f"{m['paper_iterations']} | {passes} | "
            f"{m['paper_miss_flown_Y_m'] / 1000:.2f} km | {m['paper_miss_U_m']:.1f} m | "
            f"{m['paper_dv_Y']:.3f} m/s | {m['paper_dv_U']:.3f} m/s |")
    lines += [
        "",
        "- Unconstrained: the paper's rule ||U - Y||_2 / 297 <= 4.5e-3 with rho = 1e-2 and the "
        "implementation's multiplier rescaling stops after exactly 43 ADMM iterations = 86 logged LQR "
        "passes (one extra pass per iteration for the rollout), as in Table 1 (test: "
        "`test_paper_unconstrained_43_iterations`). Without the rescaling the same rule needs "
        f"{_no_rescale_iterations(sc)} iterations.",
        "- Constrained: the paper's 404 'passes' are not ADMM iterations: each ADMM iteration ran an "
        "augmented-Lagrangian trajectory optimizer (box and x_N = 0 inside the LQR step) and the count "
        "sums its inner iLQR iterations. satgnc puts the box into the closed-form prox (soft threshold "
        "then clip, the exact prox of L1 + box) and x_N = 0 into the Riccati step (terminal multiplier), "
        "so with the paper's rho = 0.1 and eps = 4e-4 it stops after "
        f"{runs['constrained'].metrics['paper_iterations']} "
        "ADMM iterations, one Riccati sweep each.",
        "- At the paper's stopping point the sparse iterate Y is far from converged: flown open loop it "
        "misses the target by kilometres (column 'miss flying sparse Y'); the paper's figures show the "
        "dense LQR iterate U.",
        "",
        "### Converged solutions against Clarabel (cvxpy), same problem",
        "",
        "| case | status | iterations | objective | Clarabel objective | rel. gap | dv (m/s) | "
        "terminal miss (m) | nonzeros of Y | max force (N) | satgnc time | Clarabel time |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for case in ("unconstrained", "box", "constrained"):
        r = runs[case]
        m = r.metrics
        lines.append(
            f"| {case} | {m['conv_status']} | {m['conv_iterations']} | {m['conv_objective']:.6f} | "
            f"{_num(m, 'reference_objective', '.6f')} | {_num(m, 'conv_rel_gap', '.1e')} | "
            f"{m['conv_dv']:.4f} | "
            f"{m['conv_miss_m']:.3f} | {m['conv_nonzeros']}/{m['conv_entries']} | {m['max_abs_u_N']:.4g} | "
            f"{m['conv_time_s'] * 1e3:.1f} ms | "
            f"{'n/a' if r.reference_time is None else f'{r.reference_time * 1e3:.1f} ms'} |")
    lines += ["", "(box: per-axis |u| <= 5 mN with the terminal cost only; not a paper column.)", ""]
    if ctx.figures:
        p1 = ctx.figure_path("guidance_fig1_quadratic_vs_l1")
        dvq, dvl = rv.plot_fig1(sc, p1)
        lines += [f"![Fig. 1]({p1.parent.name}/{p1.name})", ""]
    else:
        ctx.figures_skipped.append("guidance_fig1_quadratic_vs_l1")
        dvq, dvl = rv.fig1_dv(sc)
    lines += [f"Fig. 1: same initial state and x_N = 0; quadratic cost dv = {dvq:.3f} m/s (smooth, "
              f"non-zero throughout), L1 cost dv = {dvl:.3f} m/s (impulsive).", ""]
    for case, fig in (("unconstrained", 2), ("constrained", 3)):
        title = f"Fig. {fig}: linear {case} (converged; dashed: paper-stop U)"
        lines += ctx.image(f"guidance_fig{fig}_{case}", f"Fig. {fig}",
                           lambda p, c=case, t=title: rv.plot_case(sc, runs[c], p, t))
    return "\n".join(lines)


def _no_rescale_iterations(sc) -> int:
    from ..guidance import L1Solver
    from ..scenarios import l1_rendezvous as scen

    st = scen.paper_settings(sc, "unconstrained")
    st["paper_multiplier_rescale"] = False
    return L1Solver(**scen.linear_problem(sc, "unconstrained"), settings=st).solve().iterations
