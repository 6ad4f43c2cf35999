"""The one result style (satgnc._results): frozen dataclasses, read-only arrays, deprecated dict access."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
from satgnc import _results
from satgnc._results import Result, deprecated, deprecated_function, module_getattr


@dataclasses.dataclass(frozen=True)
class _Demo(Result):
    status: str
    iterations: int
    X: np.ndarray
    parts: list = dataclasses.field(default_factory=list)


def _demo() -> tuple[_Demo, np.ndarray]:
    X = np.arange(6.0).reshape(3, 2)
    return _Demo(status="solved", iterations=7, X=X, parts=[np.ones(2), 3]), X


def test_arrays_are_read_only_copies():
    r, X = _demo()
    assert r.X.shape == (3, 2)
    assert r.X.flags.writeable is False
    assert r.X is not X and np.shares_memory(r.X, X) is False
    X[0, 0] = 99.0  # the caller's array stays the caller's
    assert r.X[0, 0] == 0.0
    with pytest.raises(ValueError, match="read-only"):
        r.X[0, 0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        r.parts[0][1] = 5.0
    assert r.parts[1] == 3
    w = r.X.copy()
    w[0, 0] = 2.0
    assert w[0, 0] == 2.0 and r.X[0, 0] == 0.0


def test_attribute_assignment_is_refused():
    r, _ = _demo()
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.status = "max_iterations"  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.X = np.zeros((3, 2))  # type: ignore[misc]
    assert r.status == "solved" and r.iterations == 7


def test_dict_access_warns_and_returns_the_attribute():
    r, _ = _demo()
    msg = r"_Demo\['X'\] \(dict access\) is deprecated; use the attribute _Demo.X"
    with pytest.warns(DeprecationWarning, match=msg):
        x = r["X"]
    assert x is r.X
    with pytest.warns(DeprecationWarning, match="use the attribute _Demo.status"):
        assert r["status"] == "solved"
    with pytest.warns(DeprecationWarning):
        assert r.get("iterations") == 7
    with pytest.warns(DeprecationWarning):
        assert r.get("nothing", 5) == 5
    with pytest.warns(DeprecationWarning):
        assert "X" in r
    with pytest.warns(DeprecationWarning):
        assert list(r.keys()) == ["status", "iterations", "X", "parts"]
    with pytest.warns(DeprecationWarning):
        assert dict(r)["iterations"] == 7  # keys() + __getitem__: **r and dict(r) still work
    with pytest.raises(KeyError, match="nothing"):
        r["nothing"]


def test_attribute_access_does_not_warn():
    r, _ = _demo()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert r.iterations == 7 and r.X.shape == (3, 2)
        assert dataclasses.replace(r, iterations=8).iterations == 8


def test_deprecated_helpers_name_the_new_name():
    with pytest.warns(DeprecationWarning, match=r"^old\.f is deprecated; use new\.g$"):
        deprecated("old.f", "new.g")

    def f(a, b=1):
        return a + b

    g = deprecated_function(f, "m.f", "m.h")
    with pytest.warns(DeprecationWarning, match="m.f is deprecated; use m.h"):
        assert g(1, b=2) == 3
    assert g.__name__ == "f"

    getattr_ = module_getattr("satgnc.old", {"thing": ("satgnc.new.thing", lambda: 42)})
    with pytest.warns(DeprecationWarning, match=r"satgnc\.old\.thing is deprecated; use satgnc\.new\.thing"):
        assert getattr_("thing") == 42
    with pytest.raises(AttributeError, match="has no attribute 'other'"):
        getattr_("other")


def test_pickle_and_copies_stay_read_only():
    import copy
    import pickle

    r, _ = _demo()
    for back in (pickle.loads(pickle.dumps(r)), copy.deepcopy(r), copy.copy(r)):
        assert isinstance(back, _Demo) and back.iterations == 7
        np.testing.assert_array_equal(back.X, r.X)
        assert back.X.flags.writeable is False
        with pytest.raises(dataclasses.FrozenInstanceError):
            back.iterations = 1  # type: ignore[misc]


def test_warning_points_at_the_caller():
    r, _ = _demo()
    with pytest.warns(DeprecationWarning) as rec:
        r["X"]
    assert rec[0].filename == __file__
    assert _results.__name__ == "satgnc._results"


def test_adopt_freezes_fresh_arrays_in_place_and_only_for_its_own_fields():
    """adopt() (for arrays the extension just returned) marks them read-only without a copy; the flag
    does not leak to the next result, which copies again."""
    X = np.arange(6.0).reshape(3, 2)
    parts = [np.ones(2), np.zeros(3)]
    r = _results.adopt(_Demo, status="solved", iterations=1, X=X, parts=parts)
    assert r.X is X and X.flags.writeable is False
    assert r.parts[0] is parts[0] and r.parts[1].flags.writeable is False
    Y = np.ones((2, 2))
    s = _Demo(status="solved", iterations=1, X=Y)
    assert s.X is not Y and Y.flags.writeable is True and s.X.flags.writeable is False


def test_list_of_scalars_is_kept_and_list_of_arrays_frozen():
    r = _Demo(status="solved", iterations=1, X=np.ones(1), parts=[1, 2, 3])
    assert r.parts == [1, 2, 3]
    r2 = _Demo(status="solved", iterations=1, X=np.ones(1), parts=[np.ones(2), np.ones(2)])
    assert all(p.flags.writeable is False for p in r2.parts)


@dataclasses.dataclass(frozen=True)
class _Plain(Result):
    status: str
    iterations: int
    X: np.ndarray
    objective: float = float("nan")
    certificate: np.ndarray | None = None


def test_adopt_direct_path_equals_the_constructor():
    """adopt() fills a dataclass with plain defaults directly (the L1Solver.solve() hot path): the
    result equals cls(**fields) field by field, its arrays are the given ones made read-only, it stays
    frozen, and an unknown or a missing field raises the constructor's own TypeError."""
    from satgnc.guidance import L1Result

    assert _results._direct_layout(_Plain) is not None
    assert _results._direct_layout(L1Result) is not None  # the path L1Solver.solve() takes
    assert _results._direct_layout(_Demo) is None  # default_factory: through the constructor
    X, c = np.arange(6.0).reshape(3, 2), np.ones(2)
    r = _results.adopt(_Plain, status="solved", iterations=3, X=X, certificate=c)
    ref = _Plain(status="solved", iterations=3, X=X.copy(), certificate=c.copy())
    assert r.X is X and r.certificate is c
    assert X.flags.writeable is False and c.flags.writeable is False
    assert repr(r) == repr(ref) and np.isnan(r.objective)
    assert [f.name for f in dataclasses.fields(r)] == list(vars(ref))
    for k in ("X", "certificate"):
        assert np.array_equal(getattr(r, k), getattr(ref, k))
    assert (r.status, r.iterations) == (ref.status, ref.iterations)
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.iterations = 4  # type: ignore[misc]
    with pytest.raises(TypeError, match="unexpected keyword argument 'bogus'"):
        _results.adopt(_Plain, status="solved", iterations=3, X=X, bogus=1)
    with pytest.raises(TypeError, match="missing 1 required positional argument: 'iterations'"):
        _results.adopt(_Plain, status="solved", X=X)


def test_adopt_dict_equals_adopt_and_freezes_the_named_arrays():
    """adopt_dict() (L1Solver.solve()'s path) takes the dict itself: same result as adopt() field by
    field, the named arrays read-only without a copy, and adopt()'s errors for a bad field set."""
    X, c = np.arange(6.0).reshape(3, 2), np.ones(2)
    r = _results.adopt_dict(_Plain, {"status": "solved", "iterations": 3, "X": X.T, "certificate": c},
                            ("X", "certificate"))
    ref = _Plain(status="solved", iterations=3, X=X.T.copy(), certificate=c.copy())
    assert repr(r) == repr(ref) and np.isnan(r.objective)
    assert np.shares_memory(r.X, X) and r.certificate is c
    assert r.X.flags.writeable is False and c.flags.writeable is False
    with pytest.raises(TypeError, match="unexpected keyword argument 'bogus'"):
        _results.adopt_dict(_Plain, {"status": "solved", "iterations": 3, "X": X, "bogus": 1}, ("X",))
    with pytest.raises(TypeError, match="missing 1 required positional argument: 'iterations'"):
        _results.adopt_dict(_Plain, {"status": "solved", "X": X}, ("X",))


def test_l1_solve_result_is_read_only_time_major_and_drops_engine_only_keys():
    from satgnc import guidance as g

    A, B = g.cw_discretize(0.0011, 1.0, 10.0, "zoh")
    s = g.L1Solver(A, B, np.array([100.0, 20.0, -5.0, -0.05, 0.0, 0.01]), horizon=10, Qf=np.eye(6),
                   l1_weights=np.ones(3), u_lower=-0.01 * np.ones(3), u_upper=0.01 * np.ones(3))
    r = s.solve()
    assert r.X.shape == (11, 6) and r.U.shape == r.Y.shape == r.Lambda.shape == (10, 3)
    assert all(not getattr(r, k).flags.writeable for k in ("X", "U", "Y", "Lambda", "X_flown",
                                                           "terminal_multiplier",
                                                           "infeasibility_certificate"))
    assert r.status == "solved" and r.message and not r.infeasibility_certificate.any()
    assert not hasattr(r, "workspace_bytes")
