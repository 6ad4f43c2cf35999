"""Timing helpers shared by the benchmarks (the machine may be shared: the best block is the robust one)."""

from __future__ import annotations

import math
import time


def timeit(fn, min_time: float = 0.3, max_runs: int = 2000, blocks: int = 5) -> float:
    """Fastest block's mean wall time per call of ``fn()``, s.

    One warm-up call, then ``blocks`` blocks of n calls each, n chosen so that all blocks take about
    ``min_time`` seconds (at least 1, at most ``max_runs`` calls per block).
    """
    fn()
    t0 = time.perf_counter()
    fn()
    one = max(time.perf_counter() - t0, 1e-7)
    n = int(max(1, min(max_runs, min_time / blocks / one)))
    return best_per_call(fn, n, blocks)


def best_per_call(fn, calls: int = 1, reps: int = 3) -> float:
    """Best over ``reps`` blocks of the mean wall time per call of ``fn()``, ``calls`` calls a block, s.

    No warm-up call: the first block includes any first-call cost.
    """
    best = math.inf
    for _ in range(reps):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        best = min(best, (time.perf_counter() - t0) / calls)
    return best
