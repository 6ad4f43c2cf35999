"""Table 1 (linear columns) of l1_admm_rendezvous.md: run a scenario case with the published settings
and to convergence, compare with Clarabel, and draw the paper's figures. Used by the report and CLI."""

from __future__ import annotations

import dataclasses

import numpy as np

from ..guidance import L1Result, L1Solver
from ..scenarios import l1_rendezvous as scen


@dataclasses.dataclass
class CaseRun:
    """Both runs of one case, with SI metrics."""

    case: str
    paper: L1Result | None   # published settings and stopping rule (None: not run, a user's case)
    converged: L1Result      # satgnc defaults (residual stopping, adaptive rho, relaxation)
    reference_objective: float | None
    reference_time: float | None
    metrics: dict


def fuel_dv(sc: scen.Scenario, U_scaled: np.ndarray) -> float:
    """Delta-v (m/s) of a scaled control sequence: sum |u_i| dt / m over all axes and steps."""
    return float(np.abs(U_scaled).sum() * sc.u_ref * sc.dt / sc.mass)


def miss_m(sc: scen.Scenario, X_scaled: np.ndarray) -> float:
    """Terminal position miss (m) of a scaled state history (N+1, 6)."""
    return float(np.linalg.norm(X_scaled[-1, :3]) * sc.l_ref)


def run_case(sc: scen.Scenario, case: str, reference: bool = True, paper_run: bool = True) -> CaseRun:
    """Solve ``case`` to convergence and (``paper_run``) with the published settings and stopping rule;
    ``metrics`` holds the ``conv_*`` numbers and, with ``paper_run``, the ``paper_*`` ones."""
    kw = scen.linear_problem(sc, case)
    paper = L1Solver(**kw, settings=scen.paper_settings(sc, case)).solve() if paper_run else None
    conv = L1Solver(**kw, settings=dict(max_iterations=20000)).solve()
    ref_obj = ref_t = None
    if reference:
        from ..guidance.reference import solve_cvxpy

        ref_obj, _, _, ref_t = solve_cvxpy(**kw)
    nz = lambda Y: int(np.count_nonzero(np.abs(Y) > 1e-9 * max(1.0, np.abs(Y).max())))  # noqa: E731
    m = {} if paper is None else {
        "paper_iterations": paper.iterations,
        "paper_passes_if_unconstrained": 2 * paper.iterations,
        "paper_miss_flown_Y_m": miss_m(sc, paper.X_flown),
        "paper_miss_U_m": miss_m(sc, paper.X),
        "paper_dv_Y": fuel_dv(sc, paper.Y),
        "paper_dv_U": fuel_dv(sc, paper.U),
        "paper_objective_flown_Y": paper.objective,
    }
    m |= {
        "conv_status": conv.status,
        "conv_iterations": conv.iterations,
        "conv_objective": conv.objective,
        "conv_dv": fuel_dv(sc, conv.Y),
        "conv_miss_m": miss_m(sc, conv.X_flown),
        "conv_nonzeros": nz(conv.Y),
        "conv_entries": conv.Y.size,
        "conv_time_s": conv.solve_time,
        "max_abs_u_N": float(np.abs(conv.Y).max() * sc.u_ref),
    }
    if ref_obj is not None:
        m["reference_objective"] = ref_obj
        m["conv_rel_gap"] = (conv.objective - ref_obj) / abs(ref_obj)
        if paper is not None:
            m["paper_rel_gap"] = (paper.objective - ref_obj) / abs(ref_obj)
    return CaseRun(case, paper, conv, ref_obj, ref_t, m)


def quadratic_vs_l1(sc: scen.Scenario):
    """Fig. 1: minimum-energy (sum |u|^2) and minimum-fuel (sum |u|_1) controls with the same initial and
    final state (x_N = 0 exactly). Returns (U_quadratic, U_l1) in N, time-major."""
    kw = scen.linear_problem(sc, "unconstrained")
    kw["terminal_equality"] = True
    quad = L1Solver(**{**kw, "l1_weights": np.zeros(3), "R": np.eye(3)},
                    settings=dict(max_iterations=20000)).solve()
    l1 = L1Solver(**kw, settings=dict(max_iterations=20000)).solve()
    return quad.U * sc.u_ref, l1.Y * sc.u_ref


def plot_case(sc: scen.Scenario, run: CaseRun, path, title: str, paper_stop: bool = True,
              plan_label: str = "converged") -> None:
    """Figs. 2-3 style: positions (m), velocities (m/s), controls (N) of the converged plan, with the
    paper-stop LQR iterate U dashed (``paper_stop``; off for a user's case). satgnc's plotting style:
    one colour per axis, legends outside the data."""
    from .. import _plot

    plt = _plot._pyplot()
    N = sc.horizon
    t = np.arange(N + 1) * sc.dt
    X = sc.to_si(X=run.converged.X_flown)
    U = run.converged.Y * sc.u_ref
    paper_stop = paper_stop and run.paper is not None
    Up = run.paper.U * sc.u_ref if run.paper is not None else None
    fig, ax = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    lab = ["x (minus along-track)", "y (radial)", "z (normal)"]
    for i in range(3):
        col = _plot.AXIS_COLORS[i]
        ax[0].plot(t, X[:, i], color=col, label=lab[i])
        ax[1].plot(t, X[:, 3 + i], color=col, label=f"v{'xyz'[i]}")
        ax[2].step(t[:-1], U[:, i], where="post", color=col, label=f"u{i + 1} {plan_label}")
        if paper_stop:
            ax[2].step(t[:-1], Up[:, i], where="post", ls="--", lw=0.8, color=col,
                       label=f"u{i + 1} paper stop (U)")
    ax[0].set_ylabel("relative position (CW) (m)")
    ax[1].set_ylabel("relative velocity (CW) (m/s)")
    ax[2].set_ylabel("force (N)")
    ax[2].set_xlabel("time (s)")
    for a in ax:
        _plot.legend_outside(a)
    ax[0].set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def fig1_dv(sc: scen.Scenario) -> tuple[float, float]:
    """Fig. 1's numbers without the figure: the delta-v (m/s) of the quadratic and the L1 controls."""
    Uq, Ul = quadratic_vs_l1(sc)
    return _dv(sc, Uq), _dv(sc, Ul)


def _dv(sc: scen.Scenario, U) -> float:
    return float(np.abs(U).sum() * sc.dt / sc.mass)


def plot_fig1(sc: scen.Scenario, path) -> tuple[float, float]:
    """Fig. 1; returns the delta-v (m/s) of the quadratic and the L1 controls."""
    from .. import _plot

    plt = _plot._pyplot()
    Uq, Ul = quadratic_vs_l1(sc)
    t = np.arange(sc.horizon) * sc.dt
    fig, ax = plt.subplots(2, 1, figsize=(8, 5), sharex=True)
    for i in range(3):
        ax[0].step(t, Uq[:, i], where="post", color=_plot.AXIS_COLORS[i], label=f"u{i + 1}")
        ax[1].step(t, Ul[:, i], where="post", color=_plot.AXIS_COLORS[i], label=f"u{i + 1}")
    ax[0].set_title("quadratic control cost (same initial and final state)")
    ax[1].set_title("L1 control cost")
    for a in ax:
        a.set_ylabel("force (N)")
        _plot.legend_outside(a)
    ax[1].set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return _dv(sc, Uq), _dv(sc, Ul)
