"""The one plotting style of satgnc's figures (matplotlib, Agg backend, imported lazily).

Rules every figure of the report and the gallery follows: the Okabe-Ito colour-blind-safe palette
(:data:`PALETTE`), one colour per axis across figures (:data:`AXIS_COLORS`: x, y, z and u1, u2, u3
share them), a title, axis labels with units ("time (s)"), legends outside the data
(:func:`legend_outside`), start and target marked on tracks (:func:`mark_start_target`).

Rendezvous figures take time-major SI arrays: 12-states ``[r_t - r_c, r_t, v_t - v_c, v_t]`` (N+1, 12;
m, m/s, ECI), shown in the target's CW frame, and forces (N, 3; N, CW frame)."""

from __future__ import annotations

import numpy as np

#: Okabe & Ito (2008) colour-blind-safe palette: black, orange, sky blue, bluish green, yellow, blue,
#: vermillion, reddish purple.
PALETTE = {
    "black": "#000000", "orange": "#E69F00", "sky_blue": "#56B4E9", "green": "#009E73",
    "yellow": "#F0E442", "blue": "#0072B2", "vermillion": "#D55E00", "purple": "#CC79A7",
}
#: One colour per axis (x / u1, y / u2, z / u3) in every figure.
AXIS_COLORS = (PALETTE["blue"], PALETTE["vermillion"], PALETTE["green"])
#: The cycle for series that are not axes (plans, flights, classes).
SERIES_COLORS = (PALETTE["blue"], PALETTE["orange"], PALETTE["green"], PALETTE["purple"], PALETTE["sky_blue"],
                 PALETTE["vermillion"], PALETTE["black"])


#: The one line a command prints when it wrote its numbers but no figures (no matplotlib).
NO_FIGURES = 'figures not drawn: they need matplotlib (pip install "satgnc[plot]")'


def available() -> bool:
    """Whether matplotlib can be imported (the ``plot`` extra); commands write their numbers either way."""
    import importlib.util

    try:
        return importlib.util.find_spec("matplotlib") is not None
    except (ValueError, ImportError):  # sys.modules["matplotlib"] = None: blocked, as if absent
        return False


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from cycler import cycler

    plt.rcParams.update({"axes.prop_cycle": cycler(color=list(SERIES_COLORS)), "axes.grid": True,
                         "grid.alpha": 0.3, "legend.fontsize": 8, "axes.titlesize": 10})
    return plt


def legend_outside(ax, **kw) -> None:
    """The legend of ``ax`` to the right of its data (never over it)."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, frameon=False, **kw)


def mark_start_target(ax, start, target=(0.0, 0.0), label_start: str = "start",
                      label_target: str = "target") -> None:
    """Mark a track's start (open circle) and the target (star) on ``ax`` (data coordinates)."""
    ax.plot(*start, "o", mfc="none", mec=PALETTE["black"], ms=9, label=label_start, zorder=5)
    ax.plot(*target, "*", color=PALETTE["black"], ms=12, label=label_target, zorder=5)


def cw_states(X: np.ndarray) -> np.ndarray:
    """CW relative states (N+1, 6; m, m/s) of 12-states X (N+1, 12) (:func:`satgnc.cw_relative_state`)."""
    from . import _satgnc as _c

    return np.array([_c.cw_relative_state(x) for x in np.asarray(X)])


def plan_figure(dt: float, sols, path, title: str) -> None:
    """Relative position, velocity (CW frame) and forces of plans: ``sols`` = [(label, X (N+1, 12),
    U (N, 3), line style)]; ``dt`` the control interval (s). Written to ``path`` (PNG). Colours are the
    axes (:data:`AXIS_COLORS`), line styles the plans; the legends sit outside the data."""
    plt = _pyplot()
    fig, ax = plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    for label, X, U, ls in sols:
        t = np.arange(np.shape(X)[0]) * dt
        cw = cw_states(X)
        for i, c in enumerate("xyz"):
            col = AXIS_COLORS[i]
            ax[0].plot(t, cw[:, i], ls, label=f"{c}, {label}", color=col)
            ax[1].plot(t, cw[:, 3 + i], ls, color=col, label=f"v{c}, {label}")
            ax[2].step(t[:-1], np.asarray(U)[:, i], ls, where="post", color=col, label=f"u{i + 1}, {label}")
    ax[0].set_ylabel("relative position (CW) (m)")
    ax[1].set_ylabel("relative velocity (CW) (m/s)")
    ax[2].set_ylabel("control force (N)")
    ax[2].set_xlabel("time (s)")
    for a in ax:
        legend_outside(a)
    ax[0].set_title("x = minus along-track, y = radial, z = normal (CW frame)")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def flight_figure(
    dt: float, flights, path, title: str = "Flying the plans on the truth model (J2 + drag, CVODES)"
) -> None:
    """Range to the target (log) and the CW-plane track of flights: ``flights`` = [(label, X (N+1, 12))];
    ``dt`` the control interval (s). Written to ``path`` (PNG); the track marks start and target."""
    plt = _pyplot()
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    start = None
    for label, X in flights:
        X = np.asarray(X)
        t = np.arange(X.shape[0]) * dt
        d = np.linalg.norm(X[:, 0:3], axis=1)
        ax[0].semilogy(t, np.maximum(d, 1e-3), label=label)
        cw = cw_states(X)
        ax[1].plot(cw[:, 0], cw[:, 1], label=label)
        start = cw[0, :2] if start is None else start
    if start is not None:
        mark_start_target(ax[1], start)
    ax[0].set(xlabel="time (s)", ylabel="range to target (m)", title="range to the target")
    ax[1].set(xlabel="x, minus along-track (CW) (m)", ylabel="y, radial (CW) (m)",
              title="track in the orbit plane")
    legend_outside(ax[1])
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
