"""Thruster layouts: the chaser's thrusters and the allocation B = B_force D (C++
``satgnc/guidance/thruster_layout.hpp``).

Each thruster pushes along a unit ``direction`` with a thrust in ``[0, max_thrust]`` (N); the force on
the chaser is ``D T`` (N), ``D`` = the directions as columns (3, m). A plan whose controls are the
thrusts has a nonnegative control per thruster, so its L1 cost ``sum T dt`` is the fuel (total impulse,
N s; delta-v = impulse / mass). Body frame: for now held aligned with the target's CW frame of the
rendezvous problem (the paper frame: y radial, z orbit normal, x = y cross z, i.e. minus
along-track); ``positions`` (m, from the centre of mass) give the torque arms only.
``min_impulse_bit`` (N s) is the smallest impulse one firing can give: the convex plan does not
impose it (it is not convex); :func:`impulse_bit_violations` counts the firings below it.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .. import _satgnc as _c
from .._results import Result, module_getattr
from .._validate import as_real_array

__all__ = ["ThrusterLayout", "impulse_bit_violations", "cube_layout", "axis_layout", "thrust_bounds"]


def thrust_bounds(layout: ThrusterLayout) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) thrust bounds (N) handed to the L1 solver: (0, max_thrust) per thruster.

    The ADMM handles a bound at the L1 kink (its polish checks the one-sided condition there), so the
    lower bound is exactly 0 (the former -1e-12 max_thrust relaxation, ``LOWER_RELAXATION``, is gone)."""
    return np.zeros_like(np.asarray(layout.max_thrust, dtype=float)), np.array(layout.max_thrust)


# Deprecated: the relaxation the thrust lower bound once carried (-1e-12 max_thrust, a workaround for the
# ADMM's stall at a bound at 0, fixed in a8a4064). Reading it warns; thrust_bounds no longer applies it.
__getattr__ = module_getattr(
    __name__, {"LOWER_RELAXATION": ("thrust_bounds (its lower bound is now exactly 0)", lambda: 1e-12)})


@dataclasses.dataclass(frozen=True)
class ThrusterLayout(Result):
    """A validated layout of m >= 1 thrusters (read-only).

    ``directions`` (m, 3): unit thrust directions (force on the chaser), CW frame; ``max_thrust`` (m,)
    N > 0; ``min_impulse_bit`` (m,) N s >= 0 (default zeros); ``positions`` (m, 3) m (default zeros);
    ``names`` (m,) unique labels (default ``T0, T1, ...``). A direction whose norm differs from 1 by
    more than 1e-9, a thrust <= 0 or a negative impulse bit is a ValueError naming the thruster and
    the field (``thrusters[2].direction: must be a unit vector, got norm 1.41...``)."""

    directions: np.ndarray
    max_thrust: np.ndarray
    min_impulse_bit: np.ndarray | None = None
    positions: np.ndarray | None = None
    names: tuple[str, ...] | None = None

    def __post_init__(self) -> None:
        s = object.__setattr__
        D = as_real_array(self.directions, "directions", shape=(None, 3))
        m = D.shape[0]
        if m == 0:
            raise ValueError("directions: must hold at least one thruster (shape (m, 3), m >= 1)")
        F = as_real_array(self.max_thrust, "max_thrust", shape=(m,))
        mib = np.zeros(m) if self.min_impulse_bit is None else as_real_array(
            self.min_impulse_bit, "min_impulse_bit", shape=(m,))
        P = np.zeros((m, 3)) if self.positions is None else as_real_array(self.positions, "positions",
                                                                             shape=(m, 3))
        if self.names is None:
            names: tuple[str, ...] = tuple(f"T{i}" for i in range(m))
        else:
            if isinstance(self.names, (str, bytes)) or not isinstance(self.names, Sequence):
                raise TypeError(f"names: must be a list of strings, got {type(self.names).__name__}")
            for i, nm in enumerate(self.names):
                if not isinstance(nm, str):
                    raise TypeError(f"names[{i}]: must be a string, got {type(nm).__name__}")
            if len(self.names) != m:
                raise ValueError(f"names: must hold one name per thruster ({m}), got {len(self.names)}")
            names = tuple(self.names)
        cpp = _c.ThrusterLayout(D, P, F, mib, list(names))  # the C++ checks (messages name thrusters[i])
        s(self, "directions", np.asarray(cpp.allocation()).T)  # normalized
        s(self, "max_thrust", F)
        s(self, "min_impulse_bit", mib)
        s(self, "positions", P)
        s(self, "names", tuple(cpp.names()))
        super().__post_init__()
        s(self, "_cpp", cpp)

    @property
    def size(self) -> int:
        """Number of thrusters m."""
        return int(self.directions.shape[0])

    def allocation(self) -> np.ndarray:
        """D (3, m): force (N) per newton of each thrust, CW frame."""
        return np.asarray(self._cpp.allocation())  # type: ignore[attr-defined]

    def torque_allocation(self) -> np.ndarray:
        """r_i x d_i (3, m): torque (N m) per newton of each thrust, body frame."""
        return np.asarray(self._cpp.torque_allocation())  # type: ignore[attr-defined]

    def input_matrix(self, B_force: Any) -> np.ndarray:
        """``B_force @ D`` (nx, m): the input matrix whose controls are the thrusts (N); ``B_force``
        (nx, 3) maps a force (N) to the state derivative (continuous) or increment (discrete)."""
        B = as_real_array(B_force, "B_force", shape=(None, 3))
        return np.asarray(self._cpp.input_matrix(B))  # type: ignore[attr-defined]

    def survivors(self, failed: Sequence[int]) -> list[int]:
        """Indices (ascending) of the thrusters left when those in ``failed`` are lost."""
        return list(self._cpp.survivors(_indices(failed, "failed")))  # type: ignore[attr-defined]

    def without(self, failed: Sequence[int]) -> ThrusterLayout:
        """The layout of the survivors of ``failed`` (names kept)."""
        keep = self.survivors(failed)
        return ThrusterLayout(self.directions[keep], self.max_thrust[keep], self.min_impulse_bit[keep],
                              self.positions[keep], tuple(self.names[i] for i in keep))

    def forces(self, T: Any) -> np.ndarray:
        """Forces (N, 3) (N, CW frame) of thrusts ``T`` (N, m)."""
        T = as_real_array(T, "T", shape=(None, self.size))
        return T @ self.directions

    @classmethod
    def from_table(cls, rows: Sequence[Mapping[str, Any]]) -> ThrusterLayout:
        """A layout from rows ``{"direction": [3], "max_thrust": N, "min_impulse_bit": N s (optional),
        "position": [3] m (optional), "name": str (optional)}`` (the scenario file's [[thrusters]])."""
        if isinstance(rows, (str, bytes, Mapping)) or not isinstance(rows, Sequence):
            raise TypeError(f"rows: must be a list of thruster tables, got {type(rows).__name__}")
        known = {"direction", "max_thrust", "min_impulse_bit", "position", "name"}
        for i, r in enumerate(rows):
            if not isinstance(r, Mapping):
                raise TypeError(f"rows[{i}]: must be a table (dict), got {type(r).__name__}")
            bad = sorted(set(r) - known)
            if bad:
                raise ValueError(f"rows[{i}]: unknown key {bad[0]!r}; known: {sorted(known)}")
            for k in ("direction", "max_thrust"):
                if k not in r:
                    raise ValueError(f"rows[{i}]: missing key {k!r}")
        m = len(rows)
        return cls(np.array([r["direction"] for r in rows], dtype=float).reshape(m, 3),
                   np.array([r["max_thrust"] for r in rows], dtype=float),
                   np.array([r.get("min_impulse_bit", 0.0) for r in rows], dtype=float),
                   np.array([r.get("position", [0.0, 0.0, 0.0]) for r in rows], dtype=float).reshape(m, 3),
                   tuple(r.get("name", f"T{i}") for i, r in enumerate(rows)))


def _indices(failed: Any, name: str) -> list[int]:
    if isinstance(failed, (str, bytes)) or not isinstance(failed, (Sequence, np.ndarray)):
        raise TypeError(f"{name}: must be a list of thruster indices, got {type(failed).__name__}")
    out = []
    for j, i in enumerate(failed):
        if isinstance(i, bool) or not isinstance(i, (int, np.integer)):
            raise TypeError(f"{name}[{j}]: must be an integer thruster index, got {type(i).__name__}")
        out.append(int(i))
    return out


def impulse_bit_violations(layout: ThrusterLayout, T: Any, dt: float, *, zero_tol: float = 1e-9) -> int:
    """Firings of the thrust plan ``T`` (N, m) (N held ``dt`` s) with an impulse in
    (zero_tol * max impulse, min_impulse_bit): what the convex plan does not impose."""
    T = as_real_array(T, "T", shape=(None, layout.size))
    imp = np.abs(T) * float(dt)
    floor = zero_tol * max(float(imp.max()) if imp.size else 0.0, 1e-300)
    return int(np.sum((imp > floor) & (imp < layout.min_impulse_bit[None, :])))


def axis_layout(max_thrust: float = 1.0, *, skip: Sequence[str] = ()) -> ThrusterLayout:
    """Six thrusters along +-x, +-y, +-z of the CW frame (names ``+x``, ``-x``, ...), each
    ``max_thrust`` N; ``skip`` leaves some out (e.g. ``["-z"]``: one thruster on the z axis)."""
    axes = {"+x": (1, 0, 0), "-x": (-1, 0, 0), "+y": (0, 1, 0), "-y": (0, -1, 0), "+z": (0, 0, 1),
            "-z": (0, 0, -1)}
    names = [k for k in axes if k not in set(skip)]
    return ThrusterLayout(np.array([axes[k] for k in names], dtype=float), np.full(len(names), max_thrust),
                          names=tuple(names))


def cube_layout(max_thrust: float = 1.0, cant_deg: float = 30.0, half_size: float = 0.5) -> ThrusterLayout:
    """Twelve thrusters, a common RCS pattern: on each of the six faces of a cube of half side
    ``half_size`` m, two thrusters pushing along the face's inward normal, each canted by
    ``cant_deg`` degrees (toward +-the next axis) so that pairs also give torque. ``max_thrust`` N each."""
    c, s = np.cos(np.radians(cant_deg)), np.sin(np.radians(cant_deg))
    dirs, pos, names = [], [], []
    for ax in range(3):
        nxt = (ax + 1) % 3
        for sign in (1.0, -1.0):
            for cant in (1.0, -1.0):
                d = np.zeros(3)
                d[ax] = sign * c
                d[nxt] = cant * s
                p = np.zeros(3)
                p[ax] = -sign * half_size
                p[nxt] = -cant * half_size / 2
                dirs.append(d)
                pos.append(p)
                names.append(f"{'+-'[sign < 0]}{'xyz'[ax]}{'ab'[cant < 0]}")
    return ThrusterLayout(np.array(dirs), np.full(12, max_thrust), None, np.array(pos), tuple(names))
