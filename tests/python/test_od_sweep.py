"""Sweep executors (serial, process pool, Dask LocalCluster) and the Monte Carlo of formal covariance."""

from __future__ import annotations

import numpy as np
import pytest
from satgnc.od.sweep import dask_available, run_chunks, split
from satgnc.papers import od_newton_raphson as paper
from satgnc.papers import od_newton_raphson_mc as montecarlo


def _square(xs):
    return [x * x for x in xs]


def test_split_and_serial_and_process_agree():
    chunks = split(list(range(10)), 3)
    assert [len(c) for c in chunks] == [3, 4, 3]
    a = run_chunks(_square, chunks, executor="serial", progress=False)
    b = run_chunks(_square, chunks, executor="process", workers=2, progress=False)
    assert a == b == [[0, 1, 4], [9, 16, 25, 36], [49, 64, 81]]
    with pytest.raises(ValueError, match="executor"):
        run_chunks(_square, chunks, executor="mpi")
    with pytest.raises(ValueError, match="workers"):
        run_chunks(_square, chunks, executor="process", workers=0)


def test_map_same_result_serial_and_process():
    g = paper.map_box_guesses(16, seed=5)
    a = paper.run_map(g, "levenberg_marquardt", executor="serial", chunks=2)
    b = paper.run_map(g, "levenberg_marquardt", executor="process", chunks=2)
    np.testing.assert_array_equal(a[:, :3], b[:, :3])
    np.testing.assert_allclose(a[:, 4:], b[:, 4:], rtol=0, atol=0)


def test_dask_local_cluster():
    # dask[distributed] is a test requirement (requirements-dev.txt): the Dask executor is always tested.
    assert dask_available()
    from dask.distributed import Client, LocalCluster

    g = paper.map_box_guesses(8, seed=6)
    with (
        LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cl,
        Client(cl) as client,
    ):
        d = paper.run_map(g, "levenberg_marquardt", executor="dask", chunks=2, client=client)
    s = paper.run_map(g, "levenberg_marquardt", executor="serial", chunks=2)
    np.testing.assert_allclose(d, s, rtol=0, atol=0)


def test_monte_carlo_pass_vs_six_point():
    mc = montecarlo.run("two_stations", n=24, executor="serial")
    assert mc["converged"] == 24
    assert mc["formal"].shape == (6,)
    # Linear covariance valid: sample scatter / formal sigma near 1 (24 draws: +-30 % sampling error).
    assert np.all((mc["ratio"] > 0.6) & (mc["ratio"] < 1.5))
    mc6 = montecarlo.run("six_point", n=16, executor="serial")
    # The six-point problem: 1 m / 1 mm/s noise scatters the solution by kilometres.
    err = np.linalg.norm(mc6["estimates"][:, :3] - paper.truth()[:3], axis=1)
    assert np.median(err) > 0.1
    with pytest.raises(ValueError, match="case"):
        montecarlo.run("lunar", n=4)
