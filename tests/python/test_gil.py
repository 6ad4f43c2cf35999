"""Long compiled calls release the GIL (issue 11): another Python thread keeps running meanwhile.

Each test runs one long call in a worker thread and counts how many loop iterations the main thread
makes while the worker is alive. Holding the GIL (as pbh did for its full 2.6 s) leaves the count near
zero; released, the main thread loops hundreds of thousands of times. No timing is asserted."""

from __future__ import annotations

import sys
import threading
import time

import numpy as np
import pytest
import satgnc
from satgnc import analysis as an
from satgnc import guidance as g

MIN_ITERATIONS = 1000


def _progress_during(call) -> tuple[int, object]:
    """Iterations a counter thread makes while ``call()`` runs in this thread.

    The switch interval is raised to 5 s, so the counter only runs when the call gives the GIL up
    itself: a call that holds it leaves the count at 0. The counter is already running (and waiting
    for the GIL) when the call starts, and yields every 1000 iterations so that the call gets the
    GIL back at once when it returns."""
    state = {"phase": 0, "count": 0}
    ready = threading.Event()

    def counter():
        # Spin (yielding) before the call starts, so that this thread is already runnable and
        # waiting for the GIL when the call gives it up: a thread still being woken by the OS on a
        # loaded machine would otherwise miss a short call and count 0.
        ready.set()
        while state["phase"] == 0:
            time.sleep(0)  # gives the GIL back at once, so the main thread can start the call
        c = 0
        while state["phase"] == 1:
            c += 1
            if c % 1000 == 0:
                time.sleep(0)
        state["count"] = c

    old = sys.getswitchinterval()
    sys.setswitchinterval(5.0)  # before the counter first waits for the GIL: no early drop request
    t = threading.Thread(target=counter)
    t.start()
    ready.wait()
    try:
        state["phase"] = 1
        value = call()
    finally:
        state["phase"] = 2
        t.join()
        sys.setswitchinterval(old)
    return state["count"], value


def _big_system(n=90, m=2, seed=1):
    rng = np.random.default_rng(seed)
    return rng.standard_normal((n, n)), rng.standard_normal((n, m))


@pytest.mark.parametrize("name, call", [
    ("pbh", lambda: an.pbh(*_big_system())),
    ("staircase", lambda: an.controllability(*_big_system(160))),
    ("gramian", lambda: an.controllability_gramian(-np.eye(150) + 0.01 * _big_system(150)[0],
                                                  _big_system(150)[1], 1.0)),
    # 60 days (~90 ms): with 5 days (7.5 ms) a counter thread still waiting for a core on a loaded
    # 2-core machine missed the whole call once (count 0, fresh clone at load 4)
    ("propagate", lambda: satgnc.propagate([7000.0, 0, 0, 0, 7.5, 0], np.linspace(0, 86400.0 * 60, 50),
                                           forces=satgnc.J2Gravity(), rtol=1e-12, atol=1e-14)),
    ("propagate_ensemble", lambda: satgnc.propagation.propagate_ensemble(
        np.tile([7000.0, 0, 0, 0, 7.5, 0], (400, 1)), np.linspace(0, 86400.0, 10), satgnc.J2Gravity())),
    ("L1Solver setup", lambda: g.L1Solver(*g.cw_discretize(0.0011, 1.0, 10.0), np.ones(6), horizon=20000,
                                          Qf=np.eye(6))),
])
def test_other_threads_progress_during_long_calls(name, call):
    count, value = _progress_during(call)
    assert value is not None
    assert count > MIN_ITERATIONS, f"{name}: main thread made {count} iterations while the call ran"


def test_the_measure_sees_a_call_that_holds_the_gil():
    # Control: a C loop that never releases the GIL (builtin sum over a range) leaves the count at 0.
    count, value = _progress_during(lambda: sum(range(3 * 10**6)))
    assert value == (3 * 10**6 - 1) * 3 * 10**6 // 2
    assert count < MIN_ITERATIONS
