"""The one check behind every per-room bad-input table (tests/python/test_bad_input_<room>.py).

Each table row is (callable, kwargs, exception type, message fragment): the call must raise that
type, its message must contain the fragment (the argument's name), and it must not be a raw pybind11
signature dump."""

from __future__ import annotations

import pytest

ARGNAMES = "fn, kwargs, exc, fragment"


def case_ids(cases) -> list[str]:
    return [f"{getattr(c[0], '__name__', 'fn')}-{'-'.join(c[1])}-{i}" for i, c in enumerate(cases)]


def check_bad_input(fn, kwargs, exc, fragment) -> None:
    with pytest.raises(exc) as info:
        fn(**kwargs)
    msg = str(info.value)
    assert fragment in msg, msg
    assert "incompatible function arguments" not in msg and "Invoked with" not in msg, msg
