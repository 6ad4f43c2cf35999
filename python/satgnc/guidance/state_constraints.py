"""State constraints of the L1 guidance (issue 16 item 1): the keyword settings of :class:`L1Solver`.

``half_spaces``, ``state_lower`` / ``state_upper`` / ``state_box_nodes``, ``approach_cone`` and
``closing_velocity`` are parsed here into the arguments of the C++ ``StateConstrainedAdmm``
(``satgnc/guidance/state_constraints.hpp``). Nodes are state indices k = 1..N (x_0 is given). Units
are the caller's (the state's units for bounds; the cone's half-angle in degrees here, radians in C++).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .._validate import as_int, as_real, as_real_array

__all__ = ["parse_state_constraints"]

_HS_KEYS = ("nodes", "a", "b")
_CONE_KEYS = ("nodes", "axis", "half_angle_deg", "apex_offset", "position_index")
_CV_KEYS = ("nodes", "axis", "intercept", "slope", "position_index", "velocity_index")


def _keys(value: Any, name: str, allowed: Sequence[str], required: Sequence[str]) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise TypeError(f"{name}: must be a dict with keys {', '.join(allowed)}, got {type(value).__name__}")
    for k in value:
        if k not in allowed:
            raise ValueError(f"{name}: unknown key {k!r} (allowed: {', '.join(allowed)})")
    for k in required:
        if k not in value:
            raise ValueError(f"{name}: missing key {k!r}")
    return value


def _nodes(value: Any, name: str, horizon: int) -> list[int]:
    arr = np.atleast_1d(np.asarray(value))
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"{name}: must be a non-empty 1-D list of node indices")
    out = []
    for v in arr.tolist():
        k = as_int(v, name)
        if not 1 <= k <= horizon:
            raise ValueError(f"{name}: nodes must be in 1..N = {horizon} (x_0 is given), got {k}")
        out.append(k)
    return out


def _index3(value: Any, name: str, nx: int, default: tuple[int, int, int]) -> tuple[int, int, int]:
    if value is None:
        idx = default
    else:
        arr = np.asarray(value)
        if arr.shape != (3,):
            raise ValueError(f"{name}: must hold 3 state indices, got shape {arr.shape}")
        idx = tuple(as_int(v, name) for v in arr.tolist())  # type: ignore[assignment]
    for i in idx:
        if not 0 <= i < nx:
            raise ValueError(f"{name}: state indices must be in 0..{nx - 1}, got {i}")
    return idx


def _axis(value: Any, name: str) -> np.ndarray:
    ax = as_real_array(value, name, ndim=1, shape=(3,))
    if not np.linalg.norm(ax) > 0:
        raise ValueError(f"{name}: must be nonzero")
    return ax


def _as_list(value: Any) -> list[Any]:
    return list(value) if isinstance(value, (list, tuple)) else [value]


def parse_state_constraints(nx: int, horizon: int, *, half_spaces: Any = None, state_lower: Any = None,
                            state_upper: Any = None, state_box_nodes: Any = None, approach_cone: Any = None,
                            closing_velocity: Any = None) -> tuple[list, list, list, list] | None:
    """The C++ argument lists (half_spaces, boxes, cones, closing_velocity), or None without constraints.

    - ``half_spaces``: dict ``nodes`` (M,), ``a`` (M, nx), ``b`` (M,): a_i' x_{nodes_i} <= b_i.
    - ``state_lower`` / ``state_upper``: (nx,) bounds at every node of ``state_box_nodes`` (default
      1..N), or (len(nodes), nx) per node; +-inf for no bound; lower <= upper.
    - ``approach_cone``: dict (or list of dicts) ``nodes``, ``axis`` (3,), ``half_angle_deg`` in
      (0, 90), ``apex_offset`` (position units, default 0), ``position_index`` (default (0, 1, 2)):
      ||p - (a.p) a|| <= tan(half_angle) (a.p - apex_offset), a the unit axis.
    - ``closing_velocity``: dict (or list) ``nodes``, ``axis``, ``intercept`` (velocity units),
      ``slope`` (1/s), one entry per segment, ``position_index``, ``velocity_index`` (default (3, 4, 5)):
      |a.v| <= min_i(intercept_i + slope_i a.p) (a polyhedral set: two half-spaces per segment).
    """
    hs: list = []
    boxes: list = []
    cones: list = []
    cvs: list = []
    if half_spaces is not None:
        d = _keys(half_spaces, "half_spaces", _HS_KEYS, _HS_KEYS)
        nodes = _nodes(d["nodes"], "half_spaces.nodes", horizon)
        M = len(nodes)
        a = as_real_array(d["a"], "half_spaces.a", ndim=(1, 2))
        a = a.reshape(1, -1) if a.ndim == 1 else a
        if a.shape != (M, nx):
            raise ValueError(f"half_spaces.a: must have shape ({M}, {nx}) (one row per node), got {a.shape}")
        if np.any(np.linalg.norm(a, axis=1) == 0):
            raise ValueError("half_spaces.a: a row is zero (no half-space)")
        b = as_real_array(d["b"], "half_spaces.b", ndim=(0, 1)).reshape(-1)
        if b.shape != (M,):
            raise ValueError(f"half_spaces.b: must have {M} entries, got {b.shape}")
        hs = [(k, a[i].copy(), float(b[i])) for i, k in enumerate(nodes)]
    if state_lower is not None or state_upper is not None:
        nodes = list(range(1, horizon + 1)) if state_box_nodes is None else _nodes(
            state_box_nodes, "state_box_nodes", horizon)
        shape_1 = (nx,)
        shape_n = (len(nodes), nx)

        def bound(v: Any, name: str, fill: float) -> np.ndarray:
            if v is None:
                return np.full(shape_n, fill)
            arr = as_real_array(v, name, ndim=(1, 2), finite=False)
            if np.any(np.isnan(arr)):
                raise ValueError(f"{name}: must not be NaN (use +-inf for no bound)")
            if arr.shape == shape_1:
                return np.broadcast_to(arr, shape_n).copy()
            if arr.shape != shape_n:
                raise ValueError(f"{name}: must have shape {shape_1} or {shape_n}, got {arr.shape}")
            return arr

        lo = bound(state_lower, "state_lower", -np.inf)
        hi = bound(state_upper, "state_upper", np.inf)
        bad = np.argwhere(lo > hi)
        if bad.size:
            i, e = bad[0]
            raise ValueError(f"state_lower: must be <= state_upper (node {nodes[i]}, entry {e}: "
                             f"{lo[i, e]} > {hi[i, e]})")
        if np.all(lo == lo[0]) and np.all(hi == hi[0]):
            boxes = [(nodes, lo[0], hi[0])]
        else:
            boxes = [([k], lo[i], hi[i]) for i, k in enumerate(nodes)]
    elif state_box_nodes is not None:
        raise ValueError("state_box_nodes: given without state_lower / state_upper")
    if approach_cone is not None:
        for i, c in enumerate(_as_list(approach_cone)):
            nm = "approach_cone" if not isinstance(approach_cone, (list, tuple)) else f"approach_cone[{i}]"
            d = _keys(c, nm, _CONE_KEYS, ("nodes", "axis", "half_angle_deg"))
            ang = as_real(d["half_angle_deg"], f"{nm}.half_angle_deg")
            if not 0.0 < ang < 90.0:
                raise ValueError(f"{nm}.half_angle_deg: must be in (0, 90) degrees, got {ang}")
            cones.append((_nodes(d["nodes"], f"{nm}.nodes", horizon), _axis(d["axis"], f"{nm}.axis"),
                          float(np.deg2rad(ang)), as_real(d.get("apex_offset", 0.0), f"{nm}.apex_offset"),
                          _index3(d.get("position_index"), f"{nm}.position_index", nx, (0, 1, 2))))
    if closing_velocity is not None:
        for i, c in enumerate(_as_list(closing_velocity)):
            nm = "closing_velocity" if not isinstance(closing_velocity, (list, tuple)) else f"closing_velocity[{i}]"
            d = _keys(c, nm, _CV_KEYS, ("nodes", "axis", "intercept", "slope"))
            ic = np.atleast_1d(as_real_array(d["intercept"], f"{nm}.intercept", ndim=(0, 1))).astype(float)
            sl = np.atleast_1d(as_real_array(d["slope"], f"{nm}.slope", ndim=(0, 1))).astype(float)
            if ic.shape != sl.shape:
                raise ValueError(f"{nm}.intercept: must have one entry per segment, as slope "
                                 f"({ic.shape} vs {sl.shape})")
            cvs.append((_nodes(d["nodes"], f"{nm}.nodes", horizon), _axis(d["axis"], f"{nm}.axis"), ic, sl,
                        _index3(d.get("position_index"), f"{nm}.position_index", nx, (0, 1, 2)),
                        _index3(d.get("velocity_index"), f"{nm}.velocity_index", nx, (3, 4, 5))))
    if not (hs or boxes or cones or cvs):
        return None
    return hs, boxes, cones, cvs
