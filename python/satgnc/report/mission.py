"""Report section: the main job as one path (``satgnc mission``, docs/mission.md).

The hand-off table (what each stage passes to the next, with units and frames) and one 4-panel figure:
OD residuals, estimate error against 3 sigma, planned against flown trajectory, and the singular values
of the controllability and observability matrices.
"""

from __future__ import annotations

import json
import pathlib

import numpy as np

TITLE = "The main job as one path: tracking, OD, relative state, L1 plan, flight, checks (satgnc mission)"


def figure(run, path) -> pathlib.Path:
    """The 4-panel figure of a :class:`satgnc.mission.MissionRun`, saved as PNG at ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tr, est, pl, fl, ck = run.tracking, run.estimate, run.plan, run.flight, run.checks
    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
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
    a.legend(fontsize=8)

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
    a.legend(fontsize=8)

    a = ax[1, 0]
    a.plot(pl.X[:, 0], pl.X[:, 1], "-", label="planned (CW model, estimated start)")
    a.plot(fl.X_cw[:, 0], fl.X_cw[:, 1], "--", label=f"flown ({fl.truth})")
    a.plot([0], [0], "k+", ms=12)
    a.set_xlabel("x = y cross z (m)")
    a.set_ylabel("y radial (m)")
    a.set_title(f"4-5 plan vs flight, miss {fl.miss_position:.1f} m (tolerance {fl.tolerance:g} m)")
    a.legend(fontsize=8)

    a = ax[1, 1]
    a.semilogy(np.arange(1, ck.controllability_sv.size + 1), ck.controllability_sv, "o-",
               label=f"controllability [B, AB, ..] ({ck.controllability})")
    a.semilogy(np.arange(1, ck.observability_sv.size + 1), ck.observability_sv, "s-",
               label=f"observability O ({ck.observability})")
    a.set_xlabel("index")
    a.set_ylabel("sigma_i / sigma_1")
    a.set_title("6 singular values of the models used")
    a.legend(fontsize=8)
    fig.tight_layout()
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def markdown(run, figure_rel: str | None = None) -> str:
    """The section body: scenario line, hand-off table, stage times and (optionally) the figure link."""
    sc = run.scenario
    lines = [
        f"Scenario `{sc.path.name}` ({sc.name}), epoch {sc.epoch} UTC, {len(sc.stations)} stations, "
        f"tracking {sc.times[0]:g}..{sc.times[-1]:g} s every {sc.times[1] - sc.times[0]:g} s"
        f"{f' (quick: 1 time in {sc.quick_thin})' if run.quick else ''}; plan from "
        f"t = {sc.start:g} s over {sc.tf:g} s ({sc.knots} knots). Orbit stages: km, km/s, ECI; relative "
        "stages: m, m/s, N, target CW frame (y radial, z orbit normal, x = y cross z).",
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
    """Numbers of the run for JSON (statuses, errors, miss, verdicts, times)."""
    return {
        "scenario": str(run.scenario.path),
        "statuses": run.statuses,
        "observations": int(run.tracking.t.size),
        "od_iterations": run.estimate.iterations,
        "od_error_sigmas": (run.estimate.error / run.estimate.sigma).tolist(),
        "relative_state_m": run.relative.x.tolist(),
        "relative_error_m": run.relative.error.tolist(),
        "plan_iterations": run.plan.iterations,
        "delta_v_m_s": run.plan.delta_v,
        "miss_position_m": run.flight.miss_position,
        "miss_velocity_m_s": run.flight.miss_velocity,
        "miss_tolerance_m": run.flight.tolerance,
        "od_3sigma_at_tf_m": run.flight.predicted_3sigma,
        "controllability": run.checks.controllability,
        "observability": run.checks.observability,
        "timings_s": run.timings,
    }


def write(run, outdir) -> pathlib.Path:
    """Write ``outdir/mission.md``, ``outdir/figures/mission.png`` and ``outdir/mission_summary.json``;
    return the Markdown's path."""
    out = pathlib.Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    figure(run, out / "figures" / "mission.png")
    path = out / "mission.md"
    path.write_text(f"# {TITLE}\n\n" + markdown(run, "figures/mission.png") + "\n")
    (out / "mission_summary.json").write_text(json.dumps(summary(run), indent=2))
    return path


def build(ctx) -> str:
    from ..mission import run as run_mission

    run = run_mission(None, quick=ctx.quick)
    path = ctx.figure_path("mission")
    figure(run, path)
    return markdown(run, f"figures/{path.name}")
