"""Report section: the main job as one path (``satgnc mission``, docs/mission.md).

The hand-off table (what each stage passes to the next, with units and frames) and one 4-panel figure:
OD residuals, estimate error against 3 sigma, planned against flown (open and closed loop) trajectory,
and the singular values of the controllability and observability matrices. A partial chain
(``first_stage`` / ``last_stage``) keeps the four panels; a stage that did not run says so in its panel.
"""

from __future__ import annotations

import json
import pathlib

import numpy as np

TITLE = "The main job as one path: tracking, OD, relative state, L1 plan, flight, checks (satgnc mission)"


def figure(run, path) -> pathlib.Path:
    """The 4-panel figure of a :class:`satgnc.mission.MissionRun`, saved as PNG at ``path``."""
    from .. import _plot

    plt = _plot._pyplot()  # satgnc's style: colour-blind-safe palette

    tr, est, pl, fl, ck = run.tracking, run.estimate, run.plan, run.flight, run.checks
    cl = run.closed_loop
    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    for a, stage, title in ((ax[0, 0], est, "1-2 OD residuals"), (ax[0, 1], est, "2 OD estimate error"),
                            (ax[1, 0], pl, "4-5 plan vs flight"), (ax[1, 1], ck, "6 singular values")):
        if stage is None:
            a.text(0.5, 0.5, f"not run (stages {run.scenario.first_stage}..{run.scenario.last_stage})",
                   ha="center", va="center", transform=a.transAxes)
            a.set_xticks([])
            a.set_yticks([])
            a.set_title(title)
    if est is not None:
        _od_panels(ax, tr, est)
    if pl is not None:
        a = ax[1, 0]
        src = "CW model, estimated start" if run.relative is not None else "CW model"
        a.plot(pl.X[:, 0], pl.X[:, 1], "-", label=f"planned ({pl.model}: {src})")
        title = "4 plan"
        if fl is not None:
            a.plot(fl.X_cw[:, 0], fl.X_cw[:, 1], "--", label=f"flown open loop ({fl.truth})")
            title = (f"4-5 plan vs flight, open-loop miss {fl.miss_position:.1f} m "
                     f"(tolerance {fl.tolerance:g} m)")
        if cl is not None:
            a.plot(cl.X_cw[:, 0], cl.X_cw[:, 1], ":",
                   label=f"flown closed loop (MPC), miss {cl.miss_position:.2f} m")
        _plot.mark_start_target(a, pl.X[0, :2])
        a.set_xlabel("x = y cross z, minus along-track (m)")
        a.set_ylabel("y radial (m)")
        a.set_title(title, fontsize=9)
        a.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    if ck is not None:
        a = ax[1, 1]
        a.semilogy(np.arange(1, ck.controllability_sv.size + 1), ck.controllability_sv, "o-",
                   label=f"controllability [B, AB, ..] ({ck.controllability})")
        if ck.observability_sv.size:
            a.semilogy(np.arange(1, ck.observability_sv.size + 1), ck.observability_sv, "s-",
                       label=f"observability O ({ck.observability})")
        a.set_xlabel("index")
        a.set_ylabel("sigma_i / sigma_1")
        a.set_title("6 singular values of the models used")
        a.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=1, frameon=False)
    fig.tight_layout()
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return path


def _od_panels(ax, tr, est) -> None:
    a = ax[0, 0]
    rng = np.array([k == "range" for k in tr.type])
    for mask, label, mk in ((rng, "range", "o"), (~rng, "range-rate", "x")):
        if mask.any():
            a.plot(tr.t[mask], est.normalized[mask], mk, ms=3, label=label)
    a.axhline(3, color="k", lw=0.5, ls="--")
    a.axhline(-3, color="k", lw=0.5, ls="--")
    a.set_xlabel("t from the epoch (s)")
    a.set_ylabel("residual / sigma (-)")
    a.set_title(f"1-2 OD residuals ({tr.t.size} observations, {est.status})")
    a.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)

    a = ax[0, 1]
    names = ["x", "y", "z", "vx", "vy", "vz"]
    idx = np.arange(6)
    a.bar(idx, est.error / est.sigma, color="C0", label="(estimate - truth) / sigma")
    a.axhline(3, color="k", lw=0.8, ls="--", label="+- 3 sigma")
    a.axhline(-3, color="k", lw=0.8, ls="--")
    units = ["m"] * 3 + ["m/s"] * 3
    ticks = [f"{n}\n{1e3 * s:.2g}\n{u}" for n, s, u in zip(names, est.sigma, units)]
    a.set_xticks(idx, ticks, fontsize=8)
    a.set_xlabel("component, its 1 sigma")
    a.set_ylim(-4, 4)
    a.set_ylabel("error / sigma (-)")
    a.set_title("2 OD estimate error vs 3 sigma (ECI, epoch)")
    a.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.3), ncol=2, frameon=False)


def markdown(run, figure_rel: str | None = None) -> str:
    """The section body: scenario line, hand-off table, stage times and (optionally) the figure link."""
    sc = run.scenario
    parts = [f"Scenario `{sc.path.name}` ({sc.name}), stages {', '.join(sc.stages)}"]
    if run.tracking is not None:
        parts.append(f"epoch {sc.epoch} UTC, {len(sc.stations)} stations, tracking {sc.times[0]:g}.."
                     f"{sc.times[-1]:g} s every {sc.times[1] - sc.times[0]:g} s"
                     f"{f' (quick: 1 time in {sc.quick_thin})' if run.quick else ''}")
    if run.plan is not None:
        src = f" ({sc.rendezvous.path.name}, case {sc.case})" if sc.rendezvous is not None else ""
        parts.append(f"plan{src} from t = {sc.start:g} s over {sc.tf:g} s ({sc.knots} knots)")
    lines = [
        "; ".join(parts) + ". Orbit stages: km, km/s, ECI; relative stages: m, m/s, N, target CW frame "
        "(y radial, z orbit normal, x = y cross z).",
        "",
        run.handoff_markdown(),
        "",
        "Stage wall times: " + ", ".join(f"{k} {v:.2f} s" for k, v in run.timings.items())
        + f" (total {sum(run.timings.values()):.2f} s).",
    ]
    if figure_rel:
        lines += ["", f"![mission]({figure_rel})"]
    return "\n".join(lines)


def summary(run) -> dict:
    """Numbers of the run for JSON (statuses, errors, miss, verdicts, times); the stages that ran."""
    out: dict = {"scenario": str(run.scenario.path), "stages": list(run.scenario.stages),
                 "statuses": run.statuses}
    tr, est, rel, pl, fl, cl, ck = (run.tracking, run.estimate, run.relative, run.plan, run.flight,
                                    run.closed_loop, run.checks)
    if tr is not None:
        out["observations"] = int(tr.t.size)
    if est is not None:
        out.update(od_iterations=est.iterations, od_model=est.model,
                   od_error_sigmas=(est.error / est.sigma).tolist())
    if rel is not None:
        out.update(relative_state_m=rel.x.tolist(), relative_error_m=rel.error.tolist())
    if pl is not None:
        out.update(plan_model=pl.model, plan_iterations=pl.iterations, delta_v_m_s=pl.delta_v)
    if fl is not None:
        out.update(miss_position_m=fl.miss_position, miss_velocity_m_s=fl.miss_velocity,
                   miss_tolerance_m=fl.tolerance, od_3sigma_at_tf_m=fl.predicted_3sigma)
    if cl is not None:
        out.update(closed_loop_miss_position_m=cl.miss_position,
                   closed_loop_miss_velocity_m_s=cl.miss_velocity,
                   closed_loop_delta_v_m_s=cl.delta_v, closed_loop_replans=cl.replans)
    if ck is not None:
        out.update(controllability=ck.controllability, observability=ck.observability)
    out["timings_s"] = run.timings
    return out


def write(run, outdir, figures: bool | None = None) -> pathlib.Path:
    """Write ``outdir/mission.md``, ``outdir/figures/mission.png`` and ``outdir/mission_summary.json``;
    return the Markdown's path. ``figures`` (default: whether matplotlib, the ``plot`` extra, is
    installed) False writes the Markdown and the JSON without the figure."""
    from .. import _plot

    out = pathlib.Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    if figures is None:
        figures = _plot.available()
    if figures:
        figure(run, out / "figures" / "mission.png")
    path = out / "mission.md"
    path.write_text(f"# {TITLE}\n\n" + markdown(run, "figures/mission.png" if figures else None) + "\n")
    (out / "mission_summary.json").write_text(json.dumps(summary(run), indent=2))
    return path


def build(ctx) -> str:
    from ..mission import run as run_mission

    run = run_mission(None, quick=ctx.quick, closed_loop=True)
    if not ctx.figures:
        ctx.figures_skipped.append("mission")
        return markdown(run, None)
    path = ctx.figure_path("mission")
    figure(run, path)
    return markdown(run, f"figures/{path.name}")
