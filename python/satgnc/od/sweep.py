"""One small executor interface for sweeps (convergence maps, Monte Carlo).

``run_chunks(fn, chunks, executor=...)`` applies a picklable top-level function to each chunk and
returns the results in order. Executors:

- ``"serial"``: in this process;
- ``"process"`` (default): a local :class:`concurrent.futures.ProcessPoolExecutor` with a progress bar;
- ``"dask"``: a ``dask.distributed`` cluster (``client=`` an existing Client or a scheduler address;
  without one a LocalCluster is started). Requires ``dask[distributed]``.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence

from .._progress import Progress

EXECUTORS = ("serial", "process", "dask")


def dask_available() -> bool:
    """True when ``dask.distributed`` can be imported."""
    try:
        import dask.distributed  # noqa: F401
    except ImportError:
        return False
    return True


def run_chunks(
    fn: Callable,
    chunks: Sequence,
    executor: str = "process",
    workers: int | None = None,
    progress: bool = True,
    label: str = "sweep",
    client=None,
) -> list:
    """Apply ``fn`` to every chunk; results in chunk order. ``workers`` defaults to the CPU count."""
    if executor not in EXECUTORS:
        raise ValueError(f"executor: unknown {executor!r} (hint: one of {EXECUTORS})")
    chunks = list(chunks)
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise ValueError(f"workers: must be an integer >= 1, got {workers!r}")
    bar = Progress(len(chunks), label, enabled=progress)
    if executor == "serial" or len(chunks) <= 1:
        out = []
        for c in chunks:
            out.append(fn(c))
            bar.step()
        return out
    if executor == "process":
        import concurrent.futures as cf
        import multiprocessing as mp

        n = workers or min(len(chunks), os.cpu_count() or 1)
        out = [None] * len(chunks)
        ctx = mp.get_context("spawn")  # no fork of a threaded parent
        with cf.ProcessPoolExecutor(max_workers=n, mp_context=ctx) as pool:
            futs = {pool.submit(fn, c): i for i, c in enumerate(chunks)}
            for f in cf.as_completed(futs):
                out[futs[f]] = f.result()
                bar.step()
        return out
    if not dask_available():
        raise ValueError("executor: 'dask' needs dask.distributed (hint: pip install 'dask[distributed]')")
    from dask.distributed import Client, LocalCluster, as_completed

    own = None
    if client is None:
        own = LocalCluster(
            n_workers=workers or 2, threads_per_worker=1, processes=True, dashboard_address=None
        )
        client = Client(own)
    elif isinstance(client, str):
        client = Client(client)
    try:
        futs = client.map(fn, chunks, pure=False)
        index = {f.key: i for i, f in enumerate(futs)}
        out = [None] * len(chunks)
        for f in as_completed(futs):
            out[index[f.key]] = f.result()
            bar.step()
        return out
    finally:
        if own is not None:
            client.close()
            own.close()


def split(items: Sequence, n_chunks: int) -> list:
    """Split a sequence (or array) into at most n_chunks contiguous pieces."""
    n = len(items)
    n_chunks = max(1, min(n_chunks, n))
    edges = [round(i * n / n_chunks) for i in range(n_chunks + 1)]
    return [items[edges[i] : edges[i + 1]] for i in range(n_chunks)]
