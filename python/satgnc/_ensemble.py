"""Ensemble propagation: ``satgnc.propagation.propagate_ensemble`` (private module; public names are
re-exported by :mod:`satgnc.propagation`)."""

from __future__ import annotations

import dataclasses
import numbers

import numpy as np

from . import _satgnc
from ._results import Result, adopt
from ._validate import as_float_array, as_real

__all__ = ["EnsembleResult", "propagate_ensemble"]


@dataclasses.dataclass(frozen=True)
class EnsembleResult(Result):
    """K members propagated to n output times (frozen; arrays read-only).

    Attributes
    ----------
    times : numpy.ndarray, shape (n,)
        Output times, s.
    states : numpy.ndarray, shape (K, n, 6)
        ``[r km, v km/s]`` of member k at ``times[i]``; NaN past a failed member's ``outputs[k]``.
    stms : numpy.ndarray, shape (K, n, 6, 6), or None
        ``d x_k(t_i) / d x_k(t0)`` (None with ``stm=False``); NaN where ``states`` is.
    status : tuple of str, length K
        Per member: ``"success"`` or why it stopped (``"impact"``, ``"too_much_work"``,
        ``"rhs_failure"``, ...; the names of :class:`satgnc.PropagationError`).
    success : numpy.ndarray of bool, shape (K,)
        ``status == "success"`` per member.
    messages : tuple of str, length K
        Empty on success, else what stopped the member, where and why.
    outputs : numpy.ndarray of int, shape (K,)
        Outputs delivered per member (n on success).
    t_reached : numpy.ndarray, shape (K,)
        Last time reached per member, s (the impact time on impact).
    steps, rhs_evals, rejected : numpy.ndarray of int, shape (K,)
        Accepted steps, right-hand-side evaluations and rejected steps per member.
    """

    times: np.ndarray
    states: np.ndarray
    stms: np.ndarray | None
    status: tuple[str, ...]
    success: np.ndarray
    messages: tuple[str, ...]
    outputs: np.ndarray
    t_reached: np.ndarray
    steps: np.ndarray
    rhs_evals: np.ndarray
    rejected: np.ndarray

    @property
    def all_success(self) -> bool:
        """True when every member reached the last output time."""
        return bool(np.all(self.success))


def _check_states(states) -> np.ndarray:
    x = as_float_array(states, "states")
    if x.ndim != 2 or x.shape[1] != 6:
        raise ValueError(f"states: must have shape (K, 6) = K states [r km, v km/s], got {x.shape}")
    if x.shape[0] == 0:
        raise ValueError("states: must hold at least one state (K >= 1), got shape (0, 6)")
    bad = ~np.all(np.isfinite(x), axis=1)
    if np.any(bad):
        raise ValueError(f"states: must be finite (no NaN or Inf), row {int(np.argmax(bad))} is not")
    big = np.max(np.abs(x), axis=1) >= 1e100
    if np.any(big):
        raise ValueError(f"states: every component must be below 1e100 (km, km/s), row {int(np.argmax(big))} "
                         "is not (hint: check the units)")
    return np.ascontiguousarray(x)


def _check_times(times) -> np.ndarray:
    """The output times (s) of propagate and propagate_ensemble as a float64 1-D array: a scalar
    becomes one time; not empty, finite, strictly monotone (forward or backward), else ValueError."""
    t = as_float_array(times, "times")
    if t.ndim == 0:
        t = t.reshape(1)
    if t.ndim != 1:
        raise ValueError(f"times: must be one-dimensional, got shape {t.shape}")
    if t.size == 0:
        raise ValueError("times: must not be empty")
    if not np.all(np.isfinite(t)):
        raise ValueError("times: must be finite (no NaN or Inf)")
    d = np.diff(t)
    if d.size and not (np.all(d > 0) or np.all(d < 0)):
        raise ValueError("times: must be strictly monotone (sorted, no duplicates), forward or backward")
    return t


def propagate_ensemble(
    states,
    times,
    force_model=None,
    *,
    t0: float | None = None,
    stm: bool = True,
    threads: int = 1,
    simd: bool = True,
    simd_portable: bool = False,
    rtol: float | None = None,
    atol: float | None = None,
    max_steps: int = 100_000,
    surface_radius: float | None = None,
) -> EnsembleResult:
    """Propagate K initial states in one call (DOP853, optionally with the STMs), in parallel.

    Every member has its own step-size control and its own status: a member that fails (impact, step
    budget, ``|r0| = 0``, a start below the surface) does not stop or change the others, and its
    ``status`` / ``messages`` entry says why. Each member gets the result of
    ``satgnc.propagate(x0_k, times, method="dop853", ...)``: bitwise with ``simd=False``, to rounding
    with the default SIMD lanes, whatever ``threads`` is. The GIL is released while the threads run.

    Parameters
    ----------
    states : array_like, shape (K, 6)
        Initial states ``[r km, v km/s]`` at ``t0`` in the force model's inertial frame; finite.
    times : array_like, shape (n,)
        Output times (s), strictly monotone, all on one side of ``t0`` (forward or backward).
    force_model : None, ForceModel, J2Gravity, ExponentialDrag or a list of terms
        As ``forces`` of :func:`satgnc.propagate` (None: two-body with the Earth's mu).
    t0 : float, optional
        Epoch of the states, s. Default ``times[0]``.
    stm : bool
        Also return the 6x6 STMs (default True).
    threads : int
        Threads to use, including the calling one: 1..256 (a fixed pool started for this call).
    simd : bool
        Integrate 8 members at once, one per SIMD lane (AVX-512 when the CPU has it), each lane with
        its own step-size control (default). Results then agree with the single-arc calls to
        rounding (~1e-12 relative: sums in another order, fused multiply-adds), not bitwise. ``False``:
        one member at a time, bitwise equal to ``satgnc.propagate(..., method="dop853")``.
    simd_portable : bool
        With ``simd``: use the baseline (SSE2) build of the lane integrator even where the CPU has
        AVX-512 (whose fused multiply-adds change the last bits): results then do not depend on the
        x86-64 machine. Default False (the fastest build the CPU runs).
    rtol, atol : float, optional
        DOP853 tolerances (atol in km, km/s). Default :data:`satgnc.propagation.DEFAULT_RTOL` /
        ``DEFAULT_ATOL`` (1 mm per LEO day, as :func:`satgnc.propagate`).
    max_steps : int
        Step budget of each member (> 0).
    surface_radius : float, optional
        Surface radius, km (>= 0). Default the Earth's radius for the Earth's mu, else 0. A member
        starting at or below it, or reaching it, gets the status ``"impact"``.

    Returns
    -------
    EnsembleResult
        ``states`` (K, n, 6), ``stms`` (K, n, 6, 6) or None, ``status`` (K), ``success`` (K), ...

    Raises
    ------
    ValueError, TypeError
        Naming the argument: ``states`` not of shape (K, 6), K = 0, non-finite rows; bad ``times``;
        ``threads`` not an int in 1..256; non-positive tolerances; an invalid force model.

    Examples
    --------
    Three LEO states, 10 min ahead, two threads:

    >>> import numpy as np
    >>> import satgnc
    >>> X = np.array([satgnc.elements_to_state(a, 0.001, 51.6, 0.0, 0.0, 0.0)
    ...               for a in (6800.0, 7000.0, 7200.0)])
    >>> r = satgnc.propagation.propagate_ensemble(X, [0.0, 600.0], threads=2)
    >>> r.states.shape, bool(r.success.all())
    ((3, 2, 6), True)
    """
    from .propagation import DEFAULT_ATOL, DEFAULT_RTOL, _force_model  # circular at import time

    x = _check_states(states)
    t = _check_times(times)
    t0f = float(t[0]) if t0 is None else as_real(t0, "t0")
    if isinstance(threads, bool) or not isinstance(threads, numbers.Integral):
        raise TypeError(f"threads: must be an int, got {type(threads).__name__}")
    if not 1 <= threads <= 256:
        raise ValueError(f"threads: must lie in [1, 256] (threads used, including the caller's), "
                         f"got {threads}")
    if not isinstance(stm, (bool, np.bool_)):
        raise TypeError(f"stm: must be a bool, got {type(stm).__name__}")
    if not isinstance(simd, (bool, np.bool_)):
        raise TypeError(f"simd: must be a bool, got {type(simd).__name__}")
    if not isinstance(simd_portable, (bool, np.bool_)):
        raise TypeError(f"simd_portable: must be a bool, got {type(simd_portable).__name__}")
    if isinstance(max_steps, bool) or not isinstance(max_steps, numbers.Integral):
        raise TypeError(f"max_steps: must be an int, got {type(max_steps).__name__}")
    if not 0 < max_steps <= 2**62:
        raise ValueError(f"max_steps: must lie in [1, 2**62], got {max_steps}")
    rtolf = as_real(DEFAULT_RTOL if rtol is None else rtol, "rtol", positive=True)
    if not rtolf < 1.0:
        raise ValueError(f"rtol: must be < 1 (a relative tolerance of 100 % controls nothing), got {rtol!r}")
    atolf = as_real(DEFAULT_ATOL if atol is None else atol, "atol", positive=True)
    try:
        model = _force_model(force_model, _satgnc.EARTH_MU, False)
    except (TypeError, ValueError) as e:  # name this function's argument, not propagate's "forces"
        msg = str(e)
        raise type(e)("force_model" + msg[len("forces"):] if msg.startswith("forces") else msg) from None
    if surface_radius is not None:
        surface = as_real(surface_radius, "surface_radius", nonnegative=True)
    else:
        surface = _satgnc.EARTH_RADIUS if model.mu == _satgnc.EARTH_MU else 0.0
    prop = _satgnc.EnsemblePropagator(model, rtol=rtolf, atol=atolf, with_stm=bool(stm),
                                      max_steps=int(max_steps), surface_radius=surface, threads=int(threads),
                                      simd=bool(simd), simd_portable=bool(simd_portable))
    d = prop.propagate(x, t0f, t)
    status = tuple(d["status"])
    return adopt(
        EnsembleResult,
        times=d["times"],
        states=d["states"],
        stms=d["stms"],
        status=status,
        success=np.array([s == "success" for s in status], dtype=bool),
        messages=tuple(d["messages"]),
        outputs=d["outputs"],
        t_reached=d["t_reached"],
        steps=d["steps"],
        rhs_evals=d["rhs_evals"],
        rejected=d["rejected"],
    )
