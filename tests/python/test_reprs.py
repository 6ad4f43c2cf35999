"""Issue 17: every public result prints as a one-line summary, never an array's entries or an address.

The dataclass results (every subclass of ``satgnc._results.Result``) are checked on instances whose
array fields hold 50 x 6 arrays; the compiled result / info classes and ``Observations`` on real
solves."""

from __future__ import annotations

import dataclasses
import importlib
import pkgutil
import re

import numpy as np
import pytest
import satgnc
from satgnc import _results, _satgnc, guidance, od
from satgnc.papers import od_newton_raphson as paper

# A printed array (numpy's "[0. 0. ..." / "array([") or an object address.
_BAD = re.compile(r"array\(\[|\[\s*-?\d+\.\d*\s+-?\d|\[\s*\[| at 0x")


def _check(text: str, limit: int = 1500) -> None:
    assert "\n" not in text, text
    assert not _BAD.search(text), text
    assert len(text) <= limit, (len(text), text[:200])


def _result_classes() -> list[type]:
    for m in pkgutil.walk_packages(satgnc.__path__, "satgnc."):
        if "cli" not in m.name and not m.name.startswith("satgnc.report"):
            importlib.import_module(m.name)

    def subs(c: type):
        for s in c.__subclasses__():
            yield s
            yield from subs(s)

    return sorted({c for c in subs(_results.Result) if not c.__name__.startswith("_")},
                  key=lambda c: c.__module__ + c.__name__)


def test_every_result_class_has_the_summary_repr():
    classes = _result_classes()
    assert len(classes) >= 40  # 59 on 2026-12-03: the test sees them all
    big = np.arange(300.0).reshape(50, 6)
    for cls in classes:
        obj = object.__new__(cls)
        for f in dataclasses.fields(cls):
            obj.__dict__[f.name] = big
        text = repr(obj)
        assert text.startswith(f"{cls.__name__}("), text
        assert "<float64 array 50x6>" in text, text  # shape, not entries
        _check(text)


def test_summary_of_field_kinds():
    s = _results._summary
    assert s(np.zeros((3, 4))) == "<float64 array 3x4>"
    assert s([np.zeros(3)] * 7) == "<list of 7>"
    assert s(1.23456789) == "1.23457" and s(7) == "7" and s(None) == "None" and s(True) == "True"
    assert s("x" * 100).endswith("...'") and len(s("x" * 100)) == 62
    assert s({"a": 1, "b": 2}) == "<dict of 2>"
    assert s(_satgnc.OdStatus.converged) == "converged"


def test_observations_repr_counts_types_stations_and_span():
    sts = [od.station_geodetic(40.0, -105.0, 1.6, "2026-03-20T12:00:00"),
           od.station_geodetic(-33.0, 150.0, 0.1, "2026-03-20T12:00:00")]
    obs = od.Observations(np.arange(10.0) * 60.0, ["range"] * 6 + ["range_rate"] * 4, np.full(10, 7000.0),
                          1e-3, np.array([0, 1] * 5))
    assert repr(obs) == "Observations(n=10, types={range: 6, range_rate: 4}, stations=[0, 1], t=0 .. 540 s)"
    assert repr(obs.select(np.zeros(10, bool))) == "Observations(n=0)"
    x0 = np.array([6778.137, 0.0, 0.0, 0.0, 4.7302, 6.0354])
    big = od.simulate(x0, sts, np.arange(0.0, 86400.0, 30.0), seed=1)
    assert len(big) > 100
    _check(repr(big), limit=200)


def test_real_results_summarise():
    obs = od.simulate(paper.truth(), paper.station(), np.arange(0.0, 601.0, 30.0), seed=None)
    r = od.solve(obs, paper.station(), paper.truth() + np.array([1.0, 0, 0, 0, 0, 0]))
    tr = satgnc.propagate(paper.truth(), np.linspace(0.0, 3000.0, 50))
    A, B = guidance.cw_discretize(0.0011, 12.0, 10.0)
    l1 = guidance.solve_l1(A, B, np.array([100.0, 0, 0, 0, 0, 0]), horizon=30,
                           terminal_equality=True)
    for obj, start in ((obs, "Observations(n="), (r, "OdResult(status=converged"),
                       (r.info, "OdInfo(status=converged"), (tr, "Trajectory(n=50"),
                       (obs.measurements()[0], "Measurement(t=0, type=range"), (l1, "L1Result(")):
        text = repr(obj)
        assert text.startswith(start), text
        _check(text)
    assert "X=<float64 array 31x6>" in repr(l1)


@pytest.mark.parametrize("name", ["IlqrAdmmInfo", "LookAngles", "Measurement", "OdInfo", "PropagatedMapInfo",
                                  "PropagationStats", "Root", "RootSearchResult", "ScpInfo",
                                  "SensitivityTrajectory", "TrackingData"])
def test_compiled_result_classes_have_a_repr(name):
    cls = getattr(_satgnc, name)
    assert cls.__repr__ is not object.__repr__ and "_summary_repr" in cls.__repr__.__qualname__
