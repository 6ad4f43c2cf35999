"""One orbit-arc validator (issue 12, I4): the three C++ entry points refuse and accept the inputs they did.

CVODES integrates one arc (times non-empty, on one side of t0, strictly monotone away from it); DOP853
and Kepler integrate two arcs from t0 (times monotone, non-strictly, either side of t0, possibly empty).
Since issue 12 all three call ``validate_orbit_arc_input`` with their rules, and each rule has one
wording. The table below was run against the three former validators (main before the change): the
same rows were refused and accepted; only the texts changed. Non-finite input is refused by the
bindings before C++ is reached (tests/cpp/test_orbit_arc.cpp covers it in C++).
"""

from __future__ import annotations

import numpy as np
import pytest
from satgnc import EARTH_MU, _satgnc

X0 = [7000.0, 0.0, 0.0, 0.0, 7.546, 0.0]
ZERO_R = [0.0, 0.0, 0.0, 0.0, 7.546, 0.0]
HUGE = [1e200, 0.0, 0.0, 0.0, 7.546, 0.0]

MONO_STRICT = "times: must be strictly monotone (sorted, no duplicates) in the direction of propagation"
MONO = "times: must be monotone (sorted increasing or decreasing)"
SIDE = "times: must all lie on one side of t0 (forward or backward)"
ZERO = "x0: position must be non-zero (|r0| = 0) (hint: "
BIG = "x0: every component must be below 1e100 in magnitude"

# (id, x0, t0, times, CVODES outcome, DOP853/Kepler outcome); None = accepted, else the message start.
ROWS = [
    ("forward", X0, 0.0, [10.0, 20.0], None, None),
    ("backward", X0, 0.0, [-10.0, -20.0], None, None),
    ("single", X0, 0.0, [10.0], None, None),
    ("starts-at-t0", X0, 0.0, [0.0, 10.0], None, None),
    ("ends-at-t0-backward", X0, 0.0, [-10.0, 0.0], SIDE, None),
    ("empty", X0, 0.0, [], "times: must not be empty (hint: ", None),
    ("both-sides-up", X0, 0.0, [-10.0, 10.0], SIDE, None),
    ("both-sides-down", X0, 0.0, [10.0, -10.0], SIDE, None),
    ("t0-after-all-up", X0, 30.0, [0.0, 10.0], MONO_STRICT, None),
    ("t0-between", X0, 5.0, [0.0, 10.0], SIDE, None),
    ("unsorted", X0, 0.0, [10.0, 5.0, 20.0], MONO_STRICT, MONO),
    ("duplicate", X0, 0.0, [10.0, 10.0], MONO_STRICT, None),
    ("down-after-t0", X0, 0.0, [20.0, 10.0], MONO_STRICT, None),
    ("up-before-t0", X0, 0.0, [-20.0, -10.0], MONO_STRICT, None),
    ("zero-position", ZERO_R, 0.0, [10.0], ZERO, ZERO),
    ("huge-state", HUGE, 0.0, [10.0], BIG, BIG),
]


def _cvodes(x0, t0, times):
    return _satgnc.CvodesPropagator(_satgnc.ForceModel(), with_stm=False).propagate(x0, t0, times)


def _dop853(x0, t0, times):
    return _satgnc.propagate_dop853(x0, t0, times, _satgnc.ForceModel(), with_stm=False)


def _kepler(x0, t0, times):
    return _satgnc.propagate_kepler(x0, t0, times, EARTH_MU, False)


ENTRY = {"cvodes": (_cvodes, 4), "dop853": (_dop853, 5), "kepler": (_kepler, 5)}


@pytest.mark.parametrize("entry", sorted(ENTRY))
@pytest.mark.parametrize("row", ROWS, ids=[r[0] for r in ROWS])
def test_refused_and_accepted_as_before(entry, row):
    call, col = ENTRY[entry]
    x0, t0, times, expected = row[1], row[2], row[3], row[col]
    if expected is None:
        tr = call(x0, t0, times)
        assert tr.status == "success", tr.message
        assert np.asarray(tr.states).reshape(-1, 6).shape == (len(times), 6)
        np.testing.assert_array_equal(np.asarray(tr.times, dtype=float), np.asarray(times, dtype=float))
    else:
        with pytest.raises(ValueError) as info:
            call(x0, t0, times)
        assert str(info.value).startswith(expected), str(info.value)


def test_one_wording_per_rule_across_entry_points():
    """The |r0| = 0 and 'unsorted' rules read the same from every entry point (bar the caller's hint)."""
    texts = {}
    for name, (call, _) in ENTRY.items():
        with pytest.raises(ValueError) as info:
            call(ZERO_R, 0.0, [10.0])
        texts[name] = str(info.value)
    assert texts["cvodes"] == texts["dop853"] == (
        "x0: position must be non-zero (|r0| = 0) (hint: gravity is singular at the centre of the body)")
    assert texts["kepler"].startswith(ZERO) and "two-body problem" in texts["kepler"]
    with pytest.raises(ValueError) as a:
        _dop853(X0, 0.0, [10.0, 5.0, 20.0])
    with pytest.raises(ValueError) as b:
        _kepler(X0, 0.0, [10.0, 5.0, 20.0])
    assert str(a.value) == str(b.value) == (
        "times: must be monotone (sorted increasing or decreasing), times[0] = 10, times[1] = 5 "
        "(hint: sort the output times; they may lie on either side of t0)")
