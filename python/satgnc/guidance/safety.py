"""Keep-out zones and passive safety (issue 16 items 1-2).

A keep-out zone is an ellipsoid in the target's CW frame (the paper frame: y radial, z orbit normal,
x = y cross z), centre ``center`` (m) and semi-axes ``semi_axes`` (m) along the frame's axes (a sphere
when they are equal). Its ellipsoidal radius rho(p) = ||(p - center) / semi_axes||_2 is < 1 inside.

Passive safety (:func:`passive_safety`): from each node of a flown plan (the 12-states on the nonlinear
truth, J2 + drag), the chaser stops burning and drifts for ``drift_time`` s on the same truth; the node
is passively safe when the drift never enters the zone. The drift is sampled at ``samples`` points
(CVODES, rtol 1e-11, re-initialised per sample interval); between samples the check is the sampled
minimum (say ``samples`` so that a sample interval is short against the closest-approach time scale).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from .. import _satgnc as _c
from .._results import Result
from .._validate import as_int, as_real, as_real_array
from .flight import fly

__all__ = ["KeepOut", "PassiveSafety", "passive_safety", "sample_flight", "cw_positions", "safety_figure"]


@dataclasses.dataclass(frozen=True)
class KeepOut(Result):
    """Ellipsoidal keep-out zone (module docstring): ``center`` (3,) m and ``semi_axes`` (3,) m > 0,
    CW frame. ``KeepOut.sphere(radius)`` centred on the target."""

    center: np.ndarray
    semi_axes: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", as_real_array(self.center, "center", shape=(3,)))
        a = as_real_array(self.semi_axes, "semi_axes", shape=(3,))
        if np.any(a <= 0):
            raise ValueError(f"semi_axes: must be > 0 m on every axis, got {a.tolist()}")
        object.__setattr__(self, "semi_axes", a)
        super().__post_init__()

    @classmethod
    def sphere(cls, radius: float, center: Any = (0.0, 0.0, 0.0)) -> KeepOut:
        """A sphere of ``radius`` m (> 0) about ``center`` (m, CW frame)."""
        r = as_real(radius, "radius", positive=True)
        return cls(np.asarray(center, dtype=float), np.full(3, r))

    def rho(self, P: Any) -> np.ndarray:
        """Ellipsoidal radius of positions ``P`` (..., 3) m, CW frame: < 1 inside the zone."""
        P = np.asarray(P, dtype=float)
        return np.linalg.norm((P - self.center) / self.semi_axes, axis=-1)


def cw_positions(X: Any) -> np.ndarray:
    """CW relative positions (k, 3) m of 12-states ``X`` (k, 12) (chaser relative to target)."""
    return np.array([np.asarray(_c.cw_relative_state(x))[:3] for x in np.asarray(X)])


def sample_flight(truth: Any, x0: Any, U: Any, dt: float, per_interval: int = 10) -> np.ndarray:
    """The flight of ``U`` (N, 3; N, CW frame, held ``dt`` s) from the 12-state ``x0`` on ``truth``,
    sampled ``per_interval`` times per control interval: 12-states (N per_interval + 1, 12). The
    continuous trajectory between nodes, for the keep-out check between nodes."""
    U = as_real_array(U, "U", shape=(None, 3))
    per_interval = as_int(per_interval, "per_interval", low=1, high=10**4)
    dt = as_real(dt, "dt", positive=True)
    Uf = np.repeat(U, per_interval, axis=0)
    return np.asarray(fly(truth, x0, Uf, dt / per_interval).X)


@dataclasses.dataclass(frozen=True)
class PassiveSafety(Result):
    """:func:`passive_safety`'s result. ``drift_time`` (s), ``times`` (samples + 1,) s of each drift;
    ``trajectories`` (nodes, samples + 1, 3): CW positions (m) of each node's free drift;
    ``min_rho`` (nodes,): the smallest ellipsoidal radius on each drift (< 1: enters the zone);
    ``t_min`` (nodes,) s: when; ``safe`` (nodes,) bool; ``all_safe``; ``keep_out``."""

    drift_time: float
    times: np.ndarray
    trajectories: np.ndarray
    min_rho: np.ndarray
    t_min: np.ndarray
    safe: np.ndarray
    all_safe: bool
    keep_out: KeepOut

    @property
    def unsafe_nodes(self) -> list[int]:
        """Indices of the nodes whose free drift enters the zone."""
        return [int(i) for i in np.flatnonzero(~self.safe)]


def passive_safety(truth: Any, X: Any, keep_out: KeepOut, drift_time: float, samples: int = 100,
                   nodes: Any = None) -> PassiveSafety:
    """Free drift (no burn) of each node of ``X`` (k, 12; 12-states m, m/s, ECI, e.g. a flight's
    ``X``) for ``drift_time`` s (> 0) on ``truth`` (``TwoSatelliteParams``: J2 + drag for the issue's
    check), sampled at ``samples`` equal steps, checked against ``keep_out``. ``nodes``: the node
    indices to check (default all)."""
    if not isinstance(keep_out, KeepOut):
        raise TypeError(f"keep_out: must be a KeepOut, got {type(keep_out).__name__}")
    X = as_real_array(X, "X", shape=(None, 12))
    drift_time = as_real(drift_time, "drift_time", positive=True)
    samples = as_int(samples, "samples", low=1, high=10**6)
    idx = list(range(X.shape[0])) if nodes is None else [as_int(i, "nodes[]", low=0, high=X.shape[0] - 1)
                                                          for i in nodes]
    h = drift_time / samples
    zero = np.zeros((samples, 3))
    traj = np.empty((len(idx), samples + 1, 3))
    for j, k in enumerate(idx):
        traj[j] = cw_positions(fly(truth, X[k], zero, h).X)
    rho = keep_out.rho(traj)
    imin = np.argmin(rho, axis=1)
    min_rho = rho[np.arange(len(idx)), imin]
    safe = min_rho >= 1.0
    return PassiveSafety(drift_time, np.arange(samples + 1) * h, traj, min_rho, imin * h, safe,
                         bool(np.all(safe)), keep_out)


def safety_figure(ps: PassiveSafety, path: Any, flight_positions: Any = None,
                  title: str = "Passive safety: free drift from each node (J2 + drag truth)",
                  nodes: Any = None) -> None:
    """Two panels: the drift trajectories in the CW x-y plane (along-track-radial) with the keep-out
    ellipse (red: a drift entering the zone), and each node's smallest ellipsoidal radius. PNG.
    ``nodes``: the node index of each drift (default 0, 1, ...)."""
    from .._plot import _pyplot

    plt = _pyplot()
    fig, ax = plt.subplots(1, 2, figsize=(12, 5))
    for j in range(ps.trajectories.shape[0]):
        P = ps.trajectories[j]
        ax[0].plot(P[:, 0], P[:, 1], "-", lw=0.7, color="C3" if not ps.safe[j] else "C0", alpha=0.7)
    if flight_positions is not None:
        F = np.asarray(flight_positions)
        ax[0].plot(F[:, 0], F[:, 1], "k-", lw=1.5, label="plan flown on the truth")
        ax[0].legend(fontsize=8)
    th = np.linspace(0, 2 * np.pi, 200)
    c, a = ps.keep_out.center, ps.keep_out.semi_axes
    ax[0].fill(c[0] + a[0] * np.cos(th), c[1] + a[1] * np.sin(th), color="C1", alpha=0.3)
    ax[0].plot(0, 0, "k+", ms=12)
    ax[0].set_xlabel("x (CW, minus along-track), m")
    ax[0].set_ylabel("y (CW, radial), m")
    ax[0].set_aspect("equal", adjustable="datalim")
    ax[0].set_title(f"free drift {ps.drift_time:.0f} s from each node (red: enters the zone)", fontsize=9)
    k = np.arange(ps.min_rho.size) if nodes is None else np.asarray(nodes)
    ax[1].semilogy(k, ps.min_rho, "o-", ms=3)
    ax[1].axhline(1.0, color="C3", lw=1)
    ax[1].set_xlabel("node")
    ax[1].set_ylabel("min ellipsoidal radius on the drift (< 1: inside)")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
