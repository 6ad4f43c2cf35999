"""Public API stability (issue 12, compatibility): every public name of today stays importable, and the
result attributes and status strings users read keep their names and values.

The list is tests/python/data/public_names.txt (``module:name`` per line), a copy kept in the repository.
A name that moved may answer through a deprecated alias: importing it may warn (DeprecationWarning naming
the new name), but it must resolve."""

from __future__ import annotations

import dataclasses
import importlib
import pathlib
import warnings

import numpy as np
import pytest

NAMES_FILE = pathlib.Path(__file__).parent / "data" / "public_names.txt"


def _names() -> list[tuple[str, str]]:
    rows = []
    for line in NAMES_FILE.read_text().splitlines():
        line = line.strip()
        if line and not line.startswith("#"):
            module, _, name = line.partition(":")
            rows.append((module, name))
    return rows


def test_names_file_is_complete():
    rows = _names()
    assert len(rows) == 117  # today's public surface (12 satgnc, 31 analysis, 35 od, 14 nonlinear, ...)
    modules = {m for m, _ in rows}
    assert {"satgnc", "satgnc.od", "satgnc.guidance", "satgnc.analysis", "satgnc.propagation"} <= modules


@pytest.mark.parametrize("module, name", _names(), ids=[f"{m}:{n}" for m, n in _names()])
def test_public_name_resolves(module, name):
    mod = importlib.import_module(module)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # a moved name may warn; it must still resolve
        obj = getattr(mod, name)
    assert obj is not None, f"{module}:{name}"


def _l1():
    from satgnc import guidance as g

    Ad, Bd = g.cw_discretize(0.0011, 1.0, 60.0)
    return g.solve_l1(Ad, Bd, [100.0, 50.0, 0.0, 0.0, 0.0, 0.0], horizon=20, Qf=np.eye(6) * 1e4)


def test_l1_result_attributes_and_status_strings():
    from satgnc import guidance as g

    r = _l1()
    assert isinstance(r.status, str) and r.status in g.STATUS_NAMES.values()
    assert r.status == "solved" and r.converged is True
    assert isinstance(r.iterations, int) and r.iterations > 0
    assert r.Y.shape == (20, 3) and r.U.shape == (20, 3) and r.X.shape == (21, 6)
    assert r.X[0].tolist() == [100.0, 50.0, 0.0, 0.0, 0.0, 0.0]
    assert isinstance(r.message, str) and r.message
    # the status names users compare against keep their spelling
    assert {"solved", "max_iterations", "unsolved", "time_limit"} <= set(g.STATUS_NAMES.values())
    # read-only result: arrays and attributes
    with pytest.raises(ValueError, match="read-only"):
        r.Y[0, 0] = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.status = "x"


def test_od_result_attributes_and_status_strings():
    from satgnc import analysis as an
    from satgnc import od

    x0, r0 = an.paper_od_state()
    st = od.station_inertial(r0)
    obs = od.simulate(x0, st, np.arange(0.0, 301.0, 30.0), seed=None)
    r = od.solve(obs, st, x0 + np.array([1.0, -1.0, 0.5, 1e-3, -1e-3, 0.0]))
    assert r.status.name == "converged" and r.status == od.OdStatus.converged
    assert isinstance(r.iterations, int) and r.iterations >= 1
    assert np.asarray(r.x0).shape == (6,)
    np.testing.assert_allclose(np.asarray(r.x0), x0, rtol=0, atol=1e-6)


def test_propagation_status_string():
    import satgnc

    tr = satgnc.propagate([7000.0, 0.0, 0.0, 0.0, 7.5, 0.0], [0.0, 60.0])
    assert tr.status == "success"
    assert tr.states.shape == (2, 6)


def test_analysis_reports_keep_their_attributes():
    from satgnc import analysis as an

    A, B, C = an.cw_model(1.1e-3)
    rep = an.controllability(A, B)
    assert (rep.rank, rep.verdict, rep.full, rep.robust) == (6, "full rank", True, True)
    rows = an.loss_table(A, B=B)
    assert len(rows) == 7 and rows[0].channels == [0, 1, 2] and rows[0].rank == 6
    with pytest.warns(DeprecationWarning, match=r"LossRow\['rank'\] \(dict access\) is deprecated"):
        assert rows[0]["rank"] == 6  # the old dict access still answers
