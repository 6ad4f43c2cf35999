"""The one plotting style of satgnc's figures (matplotlib, Agg backend, imported lazily).

Rendezvous figures take time-major SI arrays: 12-states ``[r_t - r_c, r_t, v_t - v_c, v_t]`` (N+1, 12;
m, m/s, ECI), shown in the target's CW frame, and forces (N, 3; N, CW frame)."""

from __future__ import annotations

import numpy as np


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def cw_states(X: np.ndarray) -> np.ndarray:
    """CW relative states (N+1, 6; m, m/s) of 12-states X (N+1, 12) (:func:`satgnc.cw_relative_state`)."""
    from . import _satgnc as _c

    return np.array([_c.cw_relative_state(x) for x in np.asarray(X)])


def plan_figure(dt: float, sols, path, title: str) -> None:
    """Relative position, velocity (CW frame) and forces of plans: ``sols`` = [(label, X (N+1, 12),
    U (N, 3), line style)]; ``dt`` the control interval (s). Written to ``path`` (PNG)."""
    plt = _pyplot()
    fig, ax = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    for label, X, U, ls in sols:
        t = np.arange(np.shape(X)[0]) * dt
        cw = cw_states(X)
        for i, c in enumerate("xyz"):
            ax[0].plot(t, cw[:, i], ls, label=f"{c} {label}", color=f"C{i}")
            ax[1].plot(t, cw[:, 3 + i], ls, color=f"C{i}")
            ax[2].step(
                t[:-1], np.asarray(U)[:, i], ls, where="post", color=f"C{i}", label=f"u{i + 1} {label}"
            )
    ax[0].set_ylabel("relative position (CW), m")
    ax[1].set_ylabel("relative velocity (CW), m/s")
    ax[2].set_ylabel("control force, N")
    ax[2].set_xlabel("time, s")
    ax[0].legend(fontsize=7, ncol=2)
    ax[2].legend(fontsize=7, ncol=2)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def flight_figure(
    dt: float, flights, path, title: str = "Flying the plans on the truth model (J2 + drag, CVODES)"
) -> None:
    """Range to the target (log) and the CW-plane track of flights: ``flights`` = [(label, X (N+1, 12))];
    ``dt`` the control interval (s). Written to ``path`` (PNG)."""
    plt = _pyplot()
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    for label, X in flights:
        X = np.asarray(X)
        t = np.arange(X.shape[0]) * dt
        d = np.linalg.norm(X[:, 0:3], axis=1)
        ax[0].semilogy(t, np.maximum(d, 1e-3), label=label)
        cw = cw_states(X)
        ax[1].plot(cw[:, 0], cw[:, 1], label=label)
    ax[0].set_xlabel("time, s")
    ax[0].set_ylabel("range to target, m")
    ax[1].set_xlabel("x (CW, minus along-track), m")
    ax[1].set_ylabel("y (radial), m")
    ax[0].legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
