"""Generic sequential filter engine (issue 15; private-ish: the users' orbit filter is ``satgnc.od``).

The C++ room ``filter`` (``satgnc/filter/*.hpp``) holds the mathematics, knowing nothing of orbits:
EKF (Joseph form, UD / Bierman-Thornton form, iterated option, scalar-sequential processing), UKF
(Wan / van der Merwe scaled sigma points, alpha = 1e-3, beta = 2, kappa = 0 by default),
Schmidt-Kalman consider parameters, a chi-square gate per record with a warm-up, and a
fixed-interval RTS smoother. This package runs it on the generic models the engine ships (a linear
discrete process x1 = Phi x0 + w, Qd = cov(w), per interval; linear measurements z = H_type x or a
range to fixed beacons), which is what the engine's own tests need. docs/filter.md has the
equations and what each covariance form guarantees. Units are the caller's; times in s.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from .. import _satgnc
from .._results import Result
from .._validate import as_bool, as_int, as_matrix, as_real, one_of

FilterStatus = _satgnc.FilterStatus
FilterEditFlag = _satgnc.FilterEditFlag

__all__ = ["FilterEditFlag", "FilterRun", "FilterStatus", "chi_square_quantile", "run_filter"]


def chi_square_quantile(dof: float, probability: float) -> float:
    """The chi-square quantile x with P(chi2_dof <= x) = probability (no scipy: regularized incomplete
    gamma inverted by Wilson-Hilferty + Halley; |P(x) - p| <= 1e-14). ``probability`` in (0, 1)."""
    dof = as_real(dof, "dof")
    probability = as_real(probability, "probability")
    if not 0.0 < probability < 1.0:
        raise ValueError(f"probability: must be in (0, 1), got {probability!r}")
    if not dof > 0.0:
        raise ValueError(f"dof: must be > 0, got {dof!r}")
    return float(_satgnc._chi_square_quantile(dof, probability))


@dataclasses.dataclass(frozen=True)
class FilterRun(Result):
    """One filter run, time-major (N records, n states, entries past a record's dimension NaN).

    ``states`` (N, n) and ``covariances`` (N, n, n) after each record's update (the prediction when
    the record was rejected or failed); ``predicted_*`` before it; ``prefit`` / ``postfit`` (N, 3)
    residuals (observed - predicted); ``normalized`` (N, 3) prefit / sqrt(S_ii); ``nis`` (N)
    y' S^-1 y; ``gate`` (N) the threshold used (0: not gated); ``flag`` (N) FilterEditFlag values;
    ``step_status`` (N) FilterStatus values; ``status`` the run's FilterStatus name; ``smoothed_*``
    from the RTS smoother when asked (else None); ``smoother_factored`` True when the run was smoothed
    on its UD factors (form "ud")."""

    times: np.ndarray
    states: np.ndarray
    covariances: np.ndarray
    predicted_states: np.ndarray
    predicted_covariances: np.ndarray
    prefit: np.ndarray
    postfit: np.ndarray
    innovation_sigma: np.ndarray
    normalized: np.ndarray
    nis: np.ndarray
    gate: np.ndarray
    flag: np.ndarray
    step_status: np.ndarray
    iterations: np.ndarray
    status: str
    accepted: int
    rejected: int
    failed: int
    smoothed_initial_state: np.ndarray | None = None
    smoothed_initial_covariance: np.ndarray | None = None
    smoothed_states: np.ndarray | None = None
    smoothed_covariances: np.ndarray | None = None
    smoother_status: str | None = None
    smoother_factored: bool | None = None

    @property
    def rejected_records(self) -> np.ndarray:
        """Indices of the records the gate rejected (never dropped silently)."""
        return np.flatnonzero(self.flag == int(FilterEditFlag.rejected))


_NAMES = {int(v): k for k, v in FilterStatus.__members__.items()}


def run_filter(
    *,
    phi: Any,
    qd: Any,
    x0: Any,
    p0: Any,
    t: Any,
    value: Any,
    sigma: Any,
    type: Any = None,  # noqa: A002 - the record field's name
    station: Any = None,
    h: Any = None,
    beacons: Any = None,
    t0: float = 0.0,
    algorithm: str = "ekf",
    form: str = "joseph",
    sequential: bool = True,
    iterated: bool = False,
    max_iterations: int = 20,
    iteration_tolerance: float = 1e-10,
    ukf_alpha: float = 1e-3,
    ukf_beta: float = 2.0,
    ukf_kappa: float = 0.0,
    consider_count: int = 0,
    gating: bool = True,
    gate_probability: float = 0.999,
    warm_up: float = 0.0,
    smooth: bool = False,
) -> FilterRun:
    """Run the engine over records (t, type, station, value, sigma) sorted by t.

    Process: x1 = phi x0 with discrete noise qd per interval (one step per distinct record time).
    Measurements: ``h`` a list of (m, n) matrices by type id (linear), or ``beacons`` (d, B) for a
    range to beacon ``station`` (type 0). ``value`` and ``sigma`` are (N,) or (N, m). Setup errors
    are ValueError naming the argument and the rule."""
    phi_a = as_matrix(phi, "phi")
    n = phi_a.shape[0]
    qd_a = as_matrix(qd, "qd")
    x0_a = np.ascontiguousarray(np.asarray(x0, dtype=float).reshape(-1))
    p0_a = as_matrix(p0, "p0")
    t_a = np.ascontiguousarray(np.asarray(t, dtype=float).reshape(-1))
    N = t_a.size
    val = np.asarray(value, dtype=float).reshape(N, -1)
    sig = np.asarray(sigma, dtype=float).reshape(N, -1)
    if val.shape[1] > 3 or sig.shape != val.shape:
        raise ValueError(f"value, sigma: must be (N,) or (N, m) with m <= 3 and the same shape, got "
                         f"{val.shape} and {sig.shape}")
    type_a = np.zeros(N, dtype=np.int32) if type is None else np.asarray(type, dtype=np.int32).reshape(N)
    st_a = np.zeros(N, dtype=np.int32) if station is None else np.asarray(station, dtype=np.int32).reshape(N)
    if (h is None) == (beacons is None):
        raise ValueError("h, beacons: give exactly one (linear measurements by type, or beacon ranges)")
    kind = "linear" if h is not None else "beacon"
    hs = [as_matrix(m, f"h[{i}]") for i, m in enumerate(h)] if h is not None else []
    bc = as_matrix(beacons, "beacons") if beacons is not None else np.zeros((2, 1))
    settings = {
        "algorithm": one_of(algorithm, "algorithm", ["ekf", "ukf"]),
        "form": one_of(form, "form", ["joseph", "ud", "conventional"]),
        "sequential": as_bool(sequential, "sequential"),
        "iterated": as_bool(iterated, "iterated"),
        "max_iterations": as_int(max_iterations, "max_iterations", low=1),
        "iteration_tolerance": as_real(iteration_tolerance, "iteration_tolerance"),
        "ukf_alpha": as_real(ukf_alpha, "ukf_alpha"),
        "ukf_beta": as_real(ukf_beta, "ukf_beta"),
        "ukf_kappa": as_real(ukf_kappa, "ukf_kappa"),
        "consider_count": as_int(consider_count, "consider_count", low=0),
        "gating": as_bool(gating, "gating"),
        "gate_probability": as_real(gate_probability, "gate_probability"),
        "warm_up": as_real(warm_up, "warm_up"),
    }
    if qd_a.shape != (n, n):
        raise ValueError(f"qd: must be ({n}, {n}) like phi, got {qd_a.shape}")
    d = _satgnc._filter_run(phi_a, qd_a, kind, hs, bc, x0_a, p0_a, float(t0), t_a, type_a, st_a, val, sig,
                            settings, bool(smooth))
    smoothed: dict[str, Any] = {}
    if smooth:
        smoothed = {
            "smoothed_initial_state": np.asarray(d["smoothed_initial_state"]),
            "smoothed_initial_covariance": np.asarray(d["smoothed_initial_covariance"]),
            "smoothed_states": np.asarray(d["smoothed_states"]),
            "smoothed_covariances": np.asarray(d["smoothed_covariances"]),
            "smoother_status": _NAMES[int(d["smoother_status"])],
            "smoother_factored": bool(d["smoother_factored"]),
        }
    return FilterRun(
        times=np.asarray(d["times"]), states=np.asarray(d["states"]),
        covariances=np.asarray(d["covariances"]),
        predicted_states=np.asarray(d["predicted_states"]),
        predicted_covariances=np.asarray(d["predicted_covariances"]), prefit=np.asarray(d["prefit"]),
        postfit=np.asarray(d["postfit"]), innovation_sigma=np.asarray(d["innovation_sigma"]),
        normalized=np.asarray(d["normalized"]), nis=np.asarray(d["nis"]), gate=np.asarray(d["gate"]),
        flag=np.asarray(d["flag"]), step_status=np.asarray(d["step_status"]),
        iterations=np.asarray(d["iterations"]), status=_NAMES[int(d["status"])], accepted=int(d["accepted"]),
        rejected=int(d["rejected"]), failed=int(d["failed"]), **smoothed)
