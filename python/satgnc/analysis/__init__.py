"""satgnc.analysis: linearization, controllability / observability rank tests, Gramians, loss tables.

Numpy arrays in, report dataclasses (or dicts) out. Every rank test returns a report with the rank,
the relative tolerance used, the margin (how far the smallest accepted singular value is above the
tolerance and above its own rounding noise), the gap, the method and a verdict: ``"full rank"``,
``"rank deficient"`` or ``"not robustly decidable"``. Units: orbits km, km/s, s; CW m, m/s.
Bad input raises ValueError / TypeError naming the argument.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from .. import _satgnc as _s
from .._results import Result, adopt, deprecated, readonly
from .._validate import as_int, as_matrix, as_real, as_real_array, as_scale, check_magnitude, one_of

MU_EARTH = _s.EARTH_MU  # km^3/s^2 (EGM-96), defined once in C++ (core/constants.hpp)
EARTH_RATE_PAPER = 7.27e-5  # rad/s: the rotation rate implied by od_newton_raphson.md Table 3
EARTH_RATE = _s.EARTH_OMEGA  # rad/s: the Earth's rotation rate (IERS), the default of every general function

PolarModel = _s.PolarModel

__all__ = [
    "PolarModel", "RankReport", "StaircaseReport", "PbhReport", "GramianReport", "DistanceReport", "LossRow",
    "Units", "Linearization", "LinearModel", "orbit",
    "polar_model", "polar_linear_model", "cw_model", "polar_units", "cw_units", "nondimensionalize",
    "staircase", "controllability", "observability", "pbh", "kalman_rank", "kalman_matrix",
    "distance_to_uncontrollability", "loss_table", "format_loss_table", "controllability_gramian",
    "observability_gramian", "ltv_observability_gramian", "minimum_energy", "expm", "fd_jacobian",
    "linearize", "od_gramian", "visibility_pass", "od_linear_model",
]


# ----------------------------------------------------------------------------- validation helpers
_MAX_SCALE = 1e100  # rates and lengths: their squares and cubes stay finite (1e300 gave inf matrices)


def _units(units):
    """The C++ units dict of a :class:`Units` (or of a dict with 'time' and 'state'), or None."""
    if units is None:
        return None
    if isinstance(units, Units):
        return {"time": units.time, "state": units.state, "input": units.input, "output": units.output}
    if not isinstance(units, dict) or "time" not in units or "state" not in units:
        raise TypeError("units: must be a dict with 'time' and 'state' (see polar_units / cw_units)")
    return units


# ----------------------------------------------------------------------------- models
def orbit(spec) -> tuple[float, float]:
    """(sigma, omega) of a named or given circular reference orbit.

    Parameters
    ----------
    spec : str or (float, float)
        ``"one"`` (sigma = omega = 1, the paper's case), ``"leo"`` (400 km altitude), ``"geo"``, a
        ``"sigma,omega"`` string or a (sigma, omega) pair (both > 0).

    Returns
    -------
    tuple of float
        (sigma km, omega rad/s).

    Raises
    ------
    ValueError
        An unknown name or a non-positive value.
    TypeError
        Neither a string nor a pair.
    """
    return _orbit(spec, "spec")


def _orbit(spec, name: str) -> tuple[float, float]:
    """orbit() with errors naming the caller's argument (``spec``, or the CLI's ``--orbit``)."""
    if isinstance(spec, str):
        key = spec.strip().lower()
        if key in ("one", "unit", "1"):
            return 1.0, 1.0
        if key == "leo":
            s = 6378.137 + 400.0
            return s, math.sqrt(MU_EARTH / s**3)
        if key == "geo":
            s = 42164.17
            return s, math.sqrt(MU_EARTH / s**3)
        parts = key.split(",")
        if len(parts) != 2:
            raise ValueError(f"{name}: must be leo, geo, one or 'sigma,omega', got {spec!r}")
        try:
            sigma, omega = float(parts[0]), float(parts[1])
        except ValueError:
            raise ValueError(f"{name}: 'sigma,omega' must be two numbers, got {spec!r}") from None
    else:
        try:
            sigma, omega = spec
        except (TypeError, ValueError):
            raise TypeError(f"{name}: must be a string or a (sigma, omega) pair, got {spec!r}") from None
    return as_real(sigma, f"{name} (sigma)", positive=True), as_real(omega, f"{name} (omega)", positive=True)


def polar_model(sigma: float, omega: float) -> PolarModel:
    """Polar model about the circle r = sigma, theta = omega t; k = sigma^3 omega^2.

    Parameters
    ----------
    sigma : float
        Radius of the reference circular orbit (km, > 0).
    omega : float
        Its angular rate (rad/s, > 0).

    Returns
    -------
    PolarModel
        ``A``, ``B`` (scaled or raw coordinates), ``sigma`` (km), ``omega`` (rad/s), ``k`` (km^3/s^2).

    Raises
    ------
    ValueError
        A non-positive or non-finite value.
    """
    return PolarModel(as_scale(sigma, "sigma", "km"), as_scale(omega, "omega", "rad/s"))


def polar_linear_model(sigma: float, omega: float, measured: Sequence[int] = (0, 2),
                       coordinates: str = "scaled") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(A, B, C) of the linearized polar model.

    Parameters
    ----------
    sigma : float
        Radius of the reference circular orbit (km, > 0).
    omega : float
        Its angular rate (rad/s, > 0).
    measured : sequence of int, optional
        State indices measured, the rows of C (default ``(0, 2)``: radius and angle).
    coordinates : {"scaled", "raw"}, optional
        ``"scaled"`` (default) is the paper's x = [r - sigma (km), r' (km/s), sigma (theta - omega t) (km),
        sigma (theta' - omega) (km/s)]; ``"raw"`` drops the sigma factors (angles in rad, rates rad/s).

    Returns
    -------
    A : numpy.ndarray
        (4, 4) (1/s).
    B : numpy.ndarray
        (4, 2), radial and tangential accelerations (km/s^2).
    C : numpy.ndarray
        (len(measured), 4), rows of the identity.

    Raises
    ------
    ValueError
        A non-positive sigma or omega, an unknown coordinates name, or an index outside 0..3.
    """
    m = polar_model(sigma, omega)
    C = np.eye(4)[list(_indices(measured, 4, "measured"))]
    return m.A(coordinates), m.B(coordinates), C


def _indices(idx, n: int, name: str) -> list[int]:
    if isinstance(idx, (str, bytes)) or not hasattr(idx, "__iter__"):
        raise TypeError(f"{name}: must be a sequence of integer indices, got {type(idx).__name__}")
    out = []
    for i in idx:
        if isinstance(i, bool) or not isinstance(i, numbers.Integral):
            raise TypeError(f"{name}: indices must be integers, got {i!r}")
        if not 0 <= int(i) < n:
            raise ValueError(f"{name}: indices must be in [0, {n - 1}], got {i}")
        if int(i) in out:  # a repeated output was accepted silently (a duplicate row of C)
            raise ValueError(f"{name}: index {int(i)} is repeated in {list(idx)}")
        out.append(int(i))
    return out


def cw_model(mean_motion: float, measured: Sequence[int] = (0, 1, 2)):
    """(A, B, C) of Clohessy-Wiltshire in the Hill frame.

    Hill frame: x radial, y along-track, z orbit normal. Guidance uses another CW frame
    (:data:`satgnc.guidance.CW_FRAME`: y radial, x minus along-track); :func:`satgnc.guidance.cw_to_hill`
    and :func:`~satgnc.guidance.hill_to_cw` convert states.

    Parameters
    ----------
    mean_motion : float
        Mean motion n of the reference orbit (rad/s, > 0).
    measured : sequence of int, optional
        State indices measured, the rows of C (default ``(0, 1, 2)``: the position).

    Returns
    -------
    A : numpy.ndarray
        (6, 6), state [x y z vx vy vz] (m, m/s).
    B : numpy.ndarray
        (6, 3), inputs [ax ay az] (m/s^2).
    C : numpy.ndarray
        (len(measured), 6), rows of the identity.

    Raises
    ------
    ValueError
        A non-positive or non-finite mean motion, or an index outside 0..5.
    """
    n = as_scale(mean_motion, "mean_motion", "rad/s")
    return _s._cw_model(n, _indices(measured, 6, "measured"))


def polar_units(sigma: float, omega: float, n_outputs: int = 0) -> Units:
    """Dimensionless units for the polar model: time 1/omega, length sigma."""
    return _make_units(_s._polar_units(as_scale(sigma, "sigma", "km"), as_scale(omega, "omega", "rad/s"),
                           as_int(n_outputs, "n_outputs", low=0, high=10**6)))


def _make_units(d: dict) -> Units:
    return Units(time=d["time"], state=d["state"], input=d["input"], output=d["output"])


def cw_units(mean_motion: float, length: float = 1.0, n_outputs: int = 0) -> Units:
    """Dimensionless units for CW: time 1/n, length ``length`` (m)."""
    return _make_units(_s._cw_units(as_scale(mean_motion, "mean_motion", "rad/s"),
                        as_scale(length, "length", "m"),
                        as_int(n_outputs, "n_outputs", low=0, high=10**6)))


def nondimensionalize(A, B, C, units: Units | dict):
    """(A~, B~, C~) in ``units`` (see :func:`polar_units`)."""
    A = as_matrix(A, "A")
    n = A.shape[0]
    B = as_matrix(B, "B", vector_as="column", allow_empty=True) if np.size(B) else np.zeros((n, 0))
    C = as_matrix(C, "C", vector_as="row", allow_empty=True) if np.size(C) else np.zeros((0, n))
    # A B or C of the wrong size was a bare numpy "cannot reshape array of size 9 into shape (4,newaxis)"
    if B.shape[0] != n:
        raise ValueError(f"B: must have n = {n} rows (A is {n} x {n}), got shape {B.shape}")
    if C.shape[1] != n:
        raise ValueError(f"C: must have n = {n} columns (A is {n} x {n}), got shape {C.shape}")
    return _s._nondimensionalize(A, B, C, _units(units))


# ----------------------------------------------------------------------------- reports
@dataclasses.dataclass(frozen=True)
class RankReport(Result):
    """Result of a rank test (see the module docstring)."""

    property: str
    n: int
    rank: int
    rtol: float
    sigma_r: float
    sigma_next: float
    margin: float
    gap: float
    method: str
    verdict: str
    verdict_text: str
    reason: str

    @property
    def robust(self) -> bool:
        """True unless the verdict is "not robustly decidable" (the rank gap is clear at the tolerance)."""
        return self.verdict != "not robustly decidable"

    @property
    def full(self) -> bool:
        """True when the verdict is "full rank" (controllable / observable)."""
        return self.verdict == "full rank"


_RANK_FIELDS = [f.name for f in dataclasses.fields(RankReport)]


@dataclasses.dataclass(frozen=True)
class StaircaseReport(RankReport):
    """Staircase form: stairs, indices, Q (first ``rank`` columns span the controllable / observable
    subspace), the staircase matrices, the uncontrollable (unobservable) block and its modes."""

    stairs: list = dataclasses.field(default_factory=list)
    indices: list = dataclasses.field(default_factory=list)
    Q: np.ndarray | None = None
    A_staircase: np.ndarray | None = None
    B_staircase: np.ndarray | None = None
    A_uncontrollable: np.ndarray | None = None
    uncontrollable_modes: np.ndarray | None = None


@dataclasses.dataclass(frozen=True)
class PbhReport(RankReport):
    """PBH per clustered eigenvalue, with stabilizability (CT: Re >= 0 modes; DT: |lambda| >= 1)."""

    modes: list = dataclasses.field(default_factory=list)
    stabilizable_ct: bool = False
    stabilizable_dt: bool = False
    distance_upper_bound: float = 0.0


@dataclasses.dataclass(frozen=True)
class GramianReport(Result):
    """Symmetric PSD Gramian, ascending eigenvalues, condition number, weakest / strongest directions."""

    W: np.ndarray
    eigenvalues: np.ndarray
    condition: float
    weakest: np.ndarray
    strongest: np.ndarray
    extra: dict = dataclasses.field(default_factory=dict)


@dataclasses.dataclass(frozen=True)
class DistanceReport(Result):
    """Distance to uncontrollability (unobservability): ``upper_bound`` (PBH, at ``lambda_upper``),
    ``refined`` (Nelder-Mead, at ``lambda_refined``), ``relative`` = refined / ||[A B]||_F,
    ``evaluations`` of sigma_min and the ``method`` used. Was a dict (``r["refined"]`` warns)."""

    upper_bound: float
    lambda_upper: complex
    refined: float
    lambda_refined: complex
    relative: float
    evaluations: int
    method: str


@dataclasses.dataclass(frozen=True)
class LossRow(Result):
    """One row of :func:`loss_table`: the kept ``channels``, staircase ``rank``, ``verdict`` (and its
    text), ``margin``, ``kalman_rank`` (numpy tolerance) and ``kalman_ratio`` (smin / smax of the
    Kalman matrix). Was a dict (``row["rank"]`` warns)."""

    channels: list
    rank: int
    verdict: str
    verdict_text: str
    margin: float
    kalman_rank: int
    kalman_ratio: float


@dataclasses.dataclass(frozen=True)
class Units(Result):
    """Dimensionless units (see :func:`polar_units`, :func:`cw_units`): ``time`` (s per unit), and per
    state / input / output component the length or rate that scales it (empty: not scaled). Was a
    dict (``u["time"]`` warns); :func:`nondimensionalize` and the rank tests take both."""

    time: float
    state: np.ndarray
    input: np.ndarray
    output: np.ndarray

    def __setitem__(self, key: str, value: Any) -> None:
        """Deprecated (units were a mutable dict): use ``dataclasses.replace(u, input=...)``. Sets the
        field (arrays stored read-only) so that old code keeps working for now."""
        if key not in ("time", "state", "input", "output"):
            raise KeyError(key)
        deprecated(f"Units[{key!r}] = ... (dict assignment)", f"dataclasses.replace(units, {key}=...)")
        object.__setattr__(self, key, readonly(value))


@dataclasses.dataclass(frozen=True)
class Linearization(Result):
    """:func:`linearize`: analytic ``A``, ``B`` beside the finite-difference ``A_fd``, ``B_fd`` and
    the relative errors ``rel_err_A``, ``rel_err_B`` (max |a - b| / max |a|). Was a dict."""

    A: np.ndarray
    B: np.ndarray
    A_fd: np.ndarray
    B_fd: np.ndarray
    rel_err_A: float
    rel_err_B: float


@dataclasses.dataclass(frozen=True)
class LinearModel(Result):
    """:func:`od_linear_model`: ``times`` (N,) s, ``states`` (N, 6) km, km/s, ``stms`` Phi(t_j, t0)
    (N, 6, 6), ``A`` = A(t_j) (N, 6, 6) and ``transitions`` Phi(t_{j+1}, t_j) (N-1, 6, 6). Was a dict."""

    times: np.ndarray
    states: np.ndarray
    stms: np.ndarray
    A: np.ndarray
    transitions: np.ndarray


def _prop(p: str) -> str:
    if not isinstance(p, str):
        raise TypeError(f"property: must be 'controllability' or 'observability', got {type(p).__name__}")
    if p not in ("controllability", "observability"):
        raise ValueError(f"property: must be 'controllability' or 'observability', got {p!r}")
    return p


def _args(A, BC, prop, rtol, fuzz, stair, cluster_rtol, units):
    prop = _prop(prop)
    A = as_matrix(A, "A")
    name = "B" if prop == "controllability" else "C"
    BC = as_matrix(BC, name, allow_empty=True, vector_as="column" if name == "B" else "row")
    if BC.size == 0:
        raise ValueError(f"{name}: empty {'input' if name == 'B' else 'output'} set (needs at least one "
                         f"{'column' if name == 'B' else 'row'})")
    rtol = 0.0 if rtol is None else as_real(rtol, "rtol", nonnegative=True)
    fuzz = as_real(fuzz, "fuzz")
    if fuzz <= 1:
        raise ValueError(f"fuzz: must be > 1, got {fuzz}")
    if stair not in ("svd", "qrcp"):
        raise ValueError(f"stair: must be 'svd' or 'qrcp', got {stair!r}")
    cluster_rtol = as_real(cluster_rtol, "cluster_rtol", nonnegative=True)
    return A, BC, prop, rtol, fuzz, stair, cluster_rtol, _units(units)


def staircase(A, BC, property: str = "controllability", *, rtol: float | None = None, fuzz: float = 100.0,
              stair: str = "svd", cluster_rtol: float = 1e-6,
              units: Units | dict | None = None) -> StaircaseReport:
    """Orthogonal staircase reduction of (A, B), or of (A^T, C^T) for observability (pass C)."""
    d = _s._staircase(*_args(A, BC, property, rtol, fuzz, stair, cluster_rtol, units))
    return adopt(StaircaseReport, **d)


_RANK_DOC = """Staircase {kind} test of (A, {M}){by}.

    Parameters
    ----------
    A : array_like
        (n, n) system matrix (continuous or discrete time, any consistent units).
    {M} : array_like
        {shape} {what} matrix (a vector is one {vector}).
    **kw
        Options of :func:`staircase`: ``rtol``, ``fuzz``, ``stair``, ``cluster_rtol``, ``units``
        (a :class:`Units` to nondimensionalize first).

    Returns
    -------
    StaircaseReport
        ``rank``, ``verdict`` ("full rank", "rank deficient" or "not robustly decidable"), ``margin``,
        the staircase form and the un{kind_adj} modes.

    Raises
    ------
    ValueError
        Non-finite or mis-shaped matrices, naming the argument.
    """
# The two tests and the two Gramians differ only in the second matrix: B (n, m), a vector a column, or
# C (p, n), a vector a row. One docstring template per pair, filled below each function.
_SECOND = {
    "controllability": {"M": "B", "shape": "(n, m)", "what": "input", "vector": "column",
                        "kind_adj": "controllable"},
    "observability": {"M": "C", "shape": "(p, n)", "what": "output", "vector": "row",
                      "kind_adj": "observable"},
}


def controllability(A, B, **kw) -> StaircaseReport:
    return staircase(A, B, "controllability", **kw)


def observability(A, C, **kw) -> StaircaseReport:
    return staircase(A, C, "observability", **kw)


controllability.__doc__ = _RANK_DOC.format(kind="controllability", by="", **_SECOND["controllability"])
observability.__doc__ = _RANK_DOC.format(kind="observability", by=" by duality", **_SECOND["observability"])


def pbh(A, BC, property: str = "controllability", *, rtol: float | None = None, fuzz: float = 100.0,
        cluster_rtol: float = 1e-6, units: Units | dict | None = None) -> PbhReport:
    """PBH test: rank of [A - lambda I, B] per clustered eigenvalue, tolerance rtol ||[A B]||_F."""
    d = _s._pbh(*_args(A, BC, property, rtol, fuzz, "svd", cluster_rtol, units))
    return adopt(PbhReport, **d)


def kalman_rank(A, BC, property: str = "controllability", *, rtol: float | None = None, fuzz: float = 100.0,
                units: Units | dict | None = None) -> RankReport:
    """SVD rank of the Kalman matrix, tolerance rtol * sigma_max (default numpy's). Comparison only."""
    return adopt(RankReport, **_s._kalman_rank(*_args(A, BC, property, rtol, fuzz, "svd", 1e-6, units)))


def kalman_matrix(A, B=None, C=None) -> np.ndarray:
    """[B, AB, ..., A^{n-1} B] (pass B) or [C; CA; ...; C A^{n-1}] (pass C). For display."""
    if (B is None) == (C is None):
        raise ValueError("B, C: pass exactly one of them")
    A = as_matrix(A, "A")
    if B is not None:
        return _s._kalman_controllability_matrix(A, as_matrix(B, "B", vector_as="column"))
    return _s._kalman_observability_matrix(A, as_matrix(C, "C", vector_as="row"))


def distance_to_uncontrollability(A, BC, property: str = "controllability", *, max_iter: int = 200,
                                  cluster_rtol: float = 1e-6) -> DistanceReport:
    """min over complex lambda of sigma_min([A - lambda I, B]): PBH upper bound and Nelder-Mead
    refinement from every eigenvalue cluster (dict: upper_bound, refined, relative, lambda_*)."""
    a = _args(A, BC, property, None, 100.0, "svd", cluster_rtol, None)
    max_iter = as_int(max_iter, "max_iter", low=0, high=10**7)
    return DistanceReport(**_s._distance_to_uncontrollability(*a, max_iter))


def loss_table(A, B=None, C=None, *, rtol: float | None = None, fuzz: float = 100.0,
               units: Units | dict | None = None) -> list[LossRow]:
    """Actuator (pass B) or sensor (pass C) loss table.

    Every non-empty subset of the channels, the full set first.

    Parameters
    ----------
    A : array_like
        (n, n) system matrix.
    B : array_like, optional
        (n, m) input matrix: an actuator loss table.
    C : array_like, optional
        (p, n) output matrix: a sensor loss table (pass exactly one of B and C).
    rtol : float, optional
        Relative rank tolerance (default: the staircase's).
    fuzz : float, optional
        Factor around the tolerance inside which the verdict is "not robustly decidable" (default 100).
    units : Units or dict, optional
        Scales to nondimensionalize with first (e.g. :func:`cw_units`).

    Returns
    -------
    list of LossRow
        One row per subset: channels, rank, verdict, margin, kalman_rank (numpy tolerance), kalman_ratio.

    Raises
    ------
    ValueError
        Both or neither of B and C, more than 20 channels, or non-finite matrices.
    """
    if (B is None) == (C is None):
        raise ValueError("B, C: pass exactly one of them")
    prop = "controllability" if B is not None else "observability"
    args = _args(A, B if B is not None else C, prop, rtol, fuzz, "svd", 1e-6, units)
    name, m = ("B", args[1].shape[1]) if B is not None else ("C", args[1].shape[0])
    if m > _MAX_LOSS_CHANNELS:
        raise ValueError(f"{name}: {m} channels make 2^{m} - 1 = {2**m - 1:.3g} subsets (one staircase and "
                         f"one ~1 kB row each, ~{2**m * 1e3 / 1e9:.3g} GB); at most {_MAX_LOSS_CHANNELS} "
                         "channels")
    _squarable(args[1], name)  # B = 1e300 gave NaN Kalman ratios (inf / inf)
    return [LossRow(**row) for row in _s._loss_table(*args)]


_MAX_LOSS_CHANNELS = 20


def format_loss_table(rows: Sequence[LossRow | Mapping], names: Sequence[str], n: int,
                      title: str = "") -> str:
    """Plain-text (Markdown) table of :func:`loss_table` rows with channel ``names`` (one name per
    channel of the B columns / C rows) and state dimension ``n`` (>= 1)."""
    # Checks: names="ab" printed channel letters, a short names list raised a bare IndexError, rows of
    # another function a KeyError, n=True printed "rank/True".
    n = as_int(n, "n", low=1)
    if not isinstance(title, str):
        raise TypeError(f"title: must be a string, got {type(title).__name__}")
    if isinstance(names, (str, bytes)) or not isinstance(names, Sequence):
        raise TypeError(f"names: must be a list of channel names (str), got {type(names).__name__}")
    for i, nm in enumerate(names):
        if not isinstance(nm, str):
            raise TypeError(f"names[{i}]: must be a string, got {type(nm).__name__}")
    if isinstance(rows, (str, bytes, dict)) or not isinstance(rows, Sequence):
        raise TypeError(f"rows: must be the list of dicts returned by loss_table (LossRow rows), "
                        f"got {type(rows).__name__}")
    keys = ("channels", "rank", "verdict_text", "margin", "kalman_rank", "kalman_ratio")
    table = []
    for i, r in enumerate(rows):
        if isinstance(r, LossRow):
            r = {k: getattr(r, k) for k in keys}
        elif not isinstance(r, Mapping):
            raise TypeError(f"rows[{i}]: must be a dict from loss_table (a LossRow), got {type(r).__name__}")
        missing = [k for k in keys if k not in r]
        if missing:
            raise ValueError(f"rows[{i}]: missing key(s) {missing}; pass the rows returned by loss_table")
        table.append(r)
        for c in r["channels"]:
            if isinstance(c, bool) or not isinstance(c, numbers.Integral) or not 0 <= c < len(names):
                raise ValueError(f"names: {len(names)} name(s) given, but rows[{i}] uses channel {c!r} "
                                 "(one name per channel is needed)")
    lines = [title] if title else []
    lines += ["| kept | rank | verdict | margin | Kalman rank (numpy tol) | Kalman smin/smax |",
              "|---|---|---|---|---|---|"]
    for r in table:
        kept = " + ".join(names[i] for i in r["channels"])
        lines.append(f"| {kept} | {r['rank']}/{n} | {r['verdict_text']} | {r['margin']:.3g} | "
                     f"{r['kalman_rank']} | {r['kalman_ratio']:.3g} |")
    return "\n".join(lines)


# ----------------------------------------------------------------------------- Gramians
def _gramian(d: dict) -> GramianReport:
    base = {k: d[k] for k in ("W", "eigenvalues", "condition", "weakest", "strongest")}
    extra = {k: v for k, v in d.items() if k not in base}
    return GramianReport(**base, extra=extra)


_MAX_FACTOR = 1e150  # |B_ij|, |C_ij| below it keep B B^T and C^T C finite


_MAX_PHASE = 1e12  # |A| T: beyond it the doubling of e^{A T / 2^k} keeps no correct digit


def _horizon(A: np.ndarray, T: float) -> float:
    """T, or a ValueError naming it when |A|_1 T > 1e12 or T > 1e100 (T = 1e300 gave W = 0 for an
    oscillator whose Gramian grows like T)."""
    phase = float(np.max(np.sum(np.abs(A), axis=0))) * T if A.size else 0.0
    if phase > _MAX_PHASE or T > _MAX_SCALE:
        raise ValueError(f"T: too long for this A: |A|_1 T = {phase:.3g} (must be <= 1e12) or T = {T:.3g} s "
                         "(must be <= 1e100); the Van Loan doubling keeps no correct digit beyond "
                         "(hint: shorten T, or nondimensionalize the model)")
    return T


def _squarable(M: np.ndarray, name: str) -> np.ndarray:
    """M, or a ValueError naming it when M M^T overflows (B = 1e300 was blamed on T)."""
    return check_magnitude(M, name, _MAX_FACTOR, f"the Gramian's {name}-product overflows double precision "
                           "(hint: nondimensionalize the model)", detail=f"max |{name}_ij| = {{big}}",
                           limit_text=f"{_MAX_FACTOR:.0e}")


_GRAMIAN_DOC = """{formula} by the Van Loan block exponential.

    Parameters
    ----------
    A : array_like
        (n, n) continuous-time system matrix (1/s).
    {M} : array_like
        {shape} {what} matrix.
    T : float
        Horizon (s, > 0).

    Returns
    -------
    GramianReport
        ``W`` (n, n) symmetric PSD, ascending ``eigenvalues``, ``condition``, ``weakest`` / ``strongest``
        directions.

    Raises
    ------
    ValueError
        Non-finite or mis-shaped matrices, or T <= 0.
    """


def _lti_gramian(kind: str, A, M, T: float) -> GramianReport:
    name, vector = _SECOND[kind]["M"], _SECOND[kind]["vector"]
    T = as_real(T, "T", positive=True)
    A = as_matrix(A, "A")
    M = _squarable(as_matrix(M, name, vector_as=vector), name)
    fn = _s._controllability_gramian if kind == "controllability" else _s._observability_gramian
    return _gramian(fn(A, M, _horizon(A, T)))


def controllability_gramian(A, B, T: float) -> GramianReport:
    return _lti_gramian("controllability", A, B, T)


def observability_gramian(A, C, T: float) -> GramianReport:
    return _lti_gramian("observability", A, C, T)


controllability_gramian.__doc__ = _GRAMIAN_DOC.format(
    formula="W_c(T) = int_0^T e^{At} B B^T e^{A^T t} dt", **_SECOND["controllability"])
observability_gramian.__doc__ = _GRAMIAN_DOC.format(
    formula="W_o(T) = int_0^T e^{A^T t} C^T C e^{At} dt", **_SECOND["observability"])


def ltv_observability_gramian(stms, H, weights=None) -> GramianReport:
    """W = sum_j w_j Phi_j^T H_j^T H_j Phi_j of a linear time-varying system.

    Parameters
    ----------
    stms : sequence of array_like
        Transition matrices Phi_j = Phi(t_j, t0), each (n, n).
    H : sequence of array_like
        Measurement partials H_j = d y_j / d x(t_j), each (m_j, n).
    weights : sequence of float, optional
        w_j >= 0, e.g. 1 / sigma_j^2 (1/km^2 for ranges); default 1.

    Returns
    -------
    GramianReport
        ``W`` (n, n) in the units of the products (e.g. 1/km^2 times the state units with weights
        1 / sigma^2), its eigenvalues, condition and weakest / strongest directions.

    Raises
    ------
    TypeError
        ``stms``, ``H`` or ``weights`` not a sequence.
    ValueError
        Mismatched shapes, negative weights, or a sum that overflows double precision.
    """
    for name, value in (("stms", stms), ("H", H), ("weights", weights)):
        if value is not None or name != "weights":  # None was "'NoneType' object is not iterable"
            if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
                raise TypeError(f"{name}: must be a sequence of matrices (one per time), "
                                f"got {type(value).__name__}")
    stms = [as_matrix(p, "stms") for p in stms]
    H = [as_matrix(h, "H") for h in H]
    w = [] if weights is None else [as_real(x, "weights", nonnegative=True) for x in weights]
    try:
        return _gramian(_s._ltv_observability_gramian(stms, H, w))
    except ValueError as e:  # "W: must be finite" named the result, not the inputs that overflowed
        if str(e).startswith("W:"):
            raise ValueError(f"stms, H, weights: the Gramian sum overflows double precision ({e})") from None
        raise


def minimum_energy(W, x_f) -> float:
    """x_f^T W^+ x_f: the minimum control energy to reach ``x_f`` with Gramian ``W``.

    Parameters
    ----------
    W : array_like
        A controllability Gramian (n, n), symmetric positive semidefinite.
    x_f : array_like
        Target state (n,), in the state's units.

    Returns
    -------
    float
        The energy (the input's units squared times s, e.g. (m/s^2)^2 s); inf if x_f leaves the range of W.

    Raises
    ------
    ValueError
        W not symmetric or not positive semidefinite, or mis-shaped arguments.
    """
    W = as_matrix(W, "W")
    if W.shape[0] == W.shape[1]:
        # A non-PSD W (e.g. -I) gave inf ("unreachable") instead of an error.
        scale = float(np.max(np.abs(W)))
        if np.max(np.abs(W - W.T)) > 1e-8 * scale:
            raise ValueError("W: must be symmetric (a Gramian)")
        ev = np.linalg.eigvalsh(0.5 * (W + W.T))
        if ev[0] < -1e-8 * max(scale, float(np.max(np.abs(ev)))):
            raise ValueError(f"W: must be positive semidefinite (a Gramian), smallest eigenvalue {ev[0]:.3g}")
    x_f = _squarable(as_matrix(x_f, "x_f", ndim=1), "x_f")  # 1e300 gave inf, read as "unreachable"
    return _s._minimum_energy(W, x_f)


def expm(M) -> np.ndarray:
    """Matrix exponential (scaling and squaring, Pade)."""
    M = as_matrix(M, "M")
    E = np.asarray(_s._expm(M))
    if not np.all(np.isfinite(E)):  # was a silent NaN matrix for expm(1e308 I)
        raise ValueError(f"M: exp(M) overflows double precision (max |M_ij| = {np.max(np.abs(M)):.3g}; "
                         "hint: scale time or use a shorter interval)")
    return E


# ----------------------------------------------------------------------------- linearization
def fd_jacobian(f: Callable, t: float, x, u, *, rel_step: float = 6.0554544523933395e-06, x_scale=None,
                u_scale=None):
    """Central finite-difference Jacobians (A, B) of f(t, x, u); step rel_step * max(|z_j|, scale_j)."""
    if not callable(f):
        raise TypeError("f: must be callable f(t, x, u) -> array")
    x = as_matrix(x, "x", ndim=1)
    u = as_matrix(u, "u", ndim=1, allow_empty=True)
    xs = np.ones(0) if x_scale is None else as_matrix(x_scale, "x_scale", ndim=1)
    us = np.ones(0) if u_scale is None else as_matrix(u_scale, "u_scale", ndim=1)

    def g(tt, xx, uu):
        # A complex value was truncated, a boolean read as 0/1 and NaN gave a NaN Jacobian silently.
        return as_real_array(f(tt, xx, uu), "f", finite=True)

    return _s._fd_jacobian(g, as_real(t, "t"), x, u, as_real(rel_step, "rel_step", positive=True), xs, us)


def linearize(f: Callable, jac: Callable, t: float, x, u, **fd) -> Linearization:
    """Analytic Jacobians jac(t, x, u) -> (A, B) checked against :func:`fd_jacobian`: dict with A, B,
    A_fd, B_fd, rel_err_A, rel_err_B."""
    if not callable(jac):
        raise TypeError("jac: must be callable jac(t, x, u) -> (A, B)")
    A_fd, B_fd = fd_jacobian(f, t, x, u, **fd)
    A, B = jac(t, np.asarray(x, float), np.asarray(u, float))
    A = as_matrix(A, "jac(A)", allow_empty=True).reshape(A_fd.shape) if np.shape(A) == A_fd.shape else None
    B = np.asarray(B, float)
    if A is None or B.shape != B_fd.shape:
        raise ValueError(f"jac: must return A {A_fd.shape} and B {B_fd.shape}")

    def rel(a, b):
        return float(np.max(np.abs(a - b)) / max(np.max(np.abs(a)), 1e-300)) if a.size else 0.0

    return Linearization(A=A, B=B, A_fd=A_fd, B_fd=B_fd, rel_err_A=rel(A, A_fd), rel_err_B=rel(B, B_fd))


# ----------------------------------------------------------------------------- OD observability
def paper_od_state() -> tuple[np.ndarray, np.ndarray]:
    """(x0 [km, km/s] of Table 1, station position R0 [km] of Table 3) of od_newton_raphson.md."""
    import json
    import pathlib

    path = pathlib.Path(__file__).resolve().parent.parent / "data" / "paper_tables.json"
    od = json.loads(path.read_text())["od_newton_raphson"]
    return np.array(od["table1_true_state"], float), np.array(od["table3_station_state"][:3], float)


_MAX_SPAN = 1e12  # s (~3e4 years), as satgnc.propagate


def _span_checked(times: np.ndarray) -> np.ndarray:
    """times, or a ValueError naming them when an orbit arc cannot span them (1e300 s blamed x0)."""
    if times.size and float(np.max(np.abs(times))) > _MAX_SPAN:
        raise ValueError(f"times: |t| = {float(np.max(np.abs(times))):.3g} s exceeds {_MAX_SPAN:.0e} s (~3e4 "
                         "years) (hint: times are seconds from the epoch of x0)")
    return times


class _kepler_blame:
    """Rewrite the engine's "x0: Kepler propagation ..." so that it names every argument that shapes the
    arc: a huge mu or time span was reported as a bad x0."""

    def __init__(self, span: str):
        self.span = span

    def __enter__(self):
        return self

    def __exit__(self, kind, err, tb):
        if kind is ValueError and str(err).startswith("x0: Kepler propagation"):
            raise ValueError(f"x0, mu, {self.span}: {str(err)[4:]} (hint: check the units: km, km/s, s, "
                             "km^3/s^2)") from None
        return False


def od_gramian(kind: str, times, x0=None, station_r0=None, rate: float = EARTH_RATE,
               mu: float = MU_EARTH) -> GramianReport:
    """Observability Gramian of single-station tracking along a two-body orbit.

    Parameters
    ----------
    kind : {"range", "range_rate", "both"}
        The observable(s) at each time.
    times : array_like
        Observation times (s from the epoch), (N,).
    x0 : array_like, optional
        Satellite state at the epoch (6,): km, km/s, inertial (default Table 1 of od_newton_raphson.md).
    station_r0 : array_like, optional
        Station position at the epoch (3,), km, inertial (default Table 3).
    rate : float, optional
        Station rotation rate about +z (rad/s; default the Earth's 7.292115e-5; the paper's reproduction
        passes its implied 7.27e-5, :data:`EARTH_RATE_PAPER`).
    mu : float, optional
        Gravitational parameter (km^3/s^2, > 0).

    Returns
    -------
    GramianReport
        ``W`` (6, 6) = sum over the times of Phi^T H^T H Phi, unweighted (entries in the units of
        d observable / d [r km, v km/s] squared), ascending ``eigenvalues``, ``condition``,
        ``weakest`` / ``strongest`` directions; extra: ``jacobi_condition`` (unit-free), ``times`` (s).

    Raises
    ------
    ValueError
        An unknown kind, times not finite or too long for the Kepler solver, or a bad state.
    """
    kind = one_of(kind, "kind", ("range", "range_rate", "both"))
    px, pr = paper_od_state()
    x0 = px if x0 is None else as_matrix(x0, "x0", ndim=1)
    r0 = pr if station_r0 is None else as_matrix(station_r0, "station_r0", ndim=1)
    times = _span_checked(as_matrix(times, "times", ndim=1))
    with _kepler_blame("times"):
        return _gramian(_s._od_observability_gramian(x0, r0, as_real(rate, "rate"), list(times), kind,
                                                     as_real(mu, "mu", positive=True)))


def visibility_pass(x0=None, station_r0=None, rate: float = EARTH_RATE, mu: float = MU_EARTH,
                    t_max: float = 3600.0, dt: float = 10.0) -> tuple[float, float]:
    """(rise, set) times of the pass containing the epoch.

    Elevation above the geocentric horizon of a two-body orbit seen from a station rotating about +z.

    Parameters
    ----------
    x0 : array_like, optional
        Satellite state at the epoch (6,): km, km/s, inertial (default Table 1 of od_newton_raphson.md).
    station_r0 : array_like, optional
        Station position at the epoch (3,), km, inertial (default Table 3).
    rate : float, optional
        Station rotation rate (rad/s; default the Earth's 7.292115e-5, :data:`EARTH_RATE`; the paper's
        reproduction passes :data:`EARTH_RATE_PAPER` = 7.27e-5).
    mu : float, optional
        Gravitational parameter (km^3/s^2, > 0).
    t_max : float, optional
        Search span each way (s, > 0; default 3600).
    dt : float, optional
        Search step (s, 0 < dt <= t_max; default 10).

    Returns
    -------
    tuple of float
        (rise, set) in s from the epoch.

    Raises
    ------
    ValueError
        A station at the centre, a bad step or span, or the satellite not visible at the epoch.
    """
    px, pr = paper_od_state()
    x0 = px if x0 is None else as_matrix(x0, "x0", ndim=1)
    r0 = pr if station_r0 is None else as_matrix(station_r0, "station_r0", ndim=1)
    if not np.linalg.norm(r0) > 0:  # was reported as "x0: the satellite is not visible"
        raise ValueError("station_r0: the station is at the centre of the Earth (|station_r0| = 0)")
    t_max = as_real(t_max, "t_max", positive=True)
    dt = as_real(dt, "dt", positive=True)
    if dt > t_max:
        raise ValueError(f"dt: the search step must be <= t_max = {t_max} s, got {dt}")
    mu = as_real(mu, "mu", positive=True)
    with _kepler_blame("t_max"):
        return tuple(_s._visibility_pass(x0, r0, as_real(rate, "rate"), mu, t_max, dt))


def od_linear_model(times, x0=None, mu: float = MU_EARTH) -> LinearModel:
    """Linear (LTV) model of the OD problem along the two-body orbit of ``x0``.

    Parameters
    ----------
    times : array_like
        Strictly increasing times (s from the epoch), (N,).
    x0 : array_like, optional
        State at the epoch (6,): km, km/s (default Table 1 of od_newton_raphson.md).
    mu : float, optional
        Gravitational parameter (km^3/s^2, > 0).

    Returns
    -------
    LinearModel
        ``states`` (N, 6) km, km/s; ``stms`` Phi(t_j, t0) (N, 6, 6, analytic Kepler STM); ``A`` = A(t_j) =
        [[0, I], [mu/r^3 (3 r r^T/r^2 - I), 0]] (N, 6, 6; 1/s and 1/s^2 blocks); ``transitions``
        Phi(t_{j+1}, t_j) (N-1, 6, 6) for the discrete LTV model.

    Raises
    ------
    ValueError
        Times not strictly increasing, a non-positive mu, or a Kepler propagation that stops early.
    """
    px, _ = paper_od_state()
    x0 = px if x0 is None else as_matrix(x0, "x0", ndim=1)
    times = _span_checked(as_matrix(times, "times", ndim=1))
    if np.any(np.diff(times) <= 0):
        raise ValueError("times: must be strictly increasing")
    mu = as_real(mu, "mu", positive=True)
    tr = _s.propagate_kepler(x0, 0.0, list(times), mu, True)
    states = np.asarray(tr.states)
    stms = np.asarray(tr.stms)
    if len(states) != len(times):
        raise ValueError(f"x0, mu, times: Kepler propagation stopped early ({tr.message})")
    A = np.array([_s._two_body_jacobian(x[:3], mu) for x in states])
    trans = np.array([stms[j + 1] @ np.linalg.inv(stms[j]) for j in range(len(times) - 1)])
    return LinearModel(times=times, states=states, stms=stms, A=A, transitions=trans)


from .._namespace import public_dir as _public_dir  # noqa: E402

__dir__ = _public_dir(__name__)  # dir(): the API, not the imported modules (np, math, ...)
