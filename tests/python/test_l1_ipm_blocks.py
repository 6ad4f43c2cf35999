"""The interior-point endgame's Riccati factor on the decoupled Clohessy-Wiltshire blocks.

With A, B, Qf (Q, R) exactly split into the in-plane (x, y, vx, vy; ux, uy) and out-of-plane (z, vz;
uz) parts, admm_ipm.cpp factors the 4 x 4 and 2 x 2 blocks alone (ipm_riccati_factor_cw). A coupling
entry of 1e-300 in A (A[2, 0]: z from x) turns that path off and the full 6 x 3 factor runs on a
problem that differs from the first only below rounding. Asserted on 40 problems of the seeded random
suite (soft and hard terminal states, boxes, R > 0, stage Q, km / mm units): the same status, ADMM and
IPM iteration counts, and objectives / plans within 1e-10 relative.
"""

from __future__ import annotations

import importlib.util
import pathlib
import sys

import numpy as np
import pytest
from satgnc.guidance import L1Solver


def _suite_module():
    path = pathlib.Path(__file__).with_name("test_l1_random.py")
    spec = importlib.util.spec_from_file_location("l1_random_blocks", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


CASES = list(_suite_module().suite(seed=23, counts={"l1": 24, "qp": 4, "stage_q": 4, "units_km": 4,
                                                     "units_mm": 4}))


@pytest.mark.parametrize("i", range(len(CASES)))
@pytest.mark.parametrize("method", ["admm_ipm", "ipm"])
def test_block_factor_matches_full_factor(i, method):
    kw = CASES[i].kw
    coupled = dict(kw, A=kw["A"].copy())
    coupled["A"][2, 0] = 1e-300  # not exactly decoupled: the 6 x 3 factor
    a = L1Solver(**kw, settings={"method": method}).solve()
    b = L1Solver(**coupled, settings={"method": method}).solve()
    assert a.status == b.status
    assert (a.iterations, a.ipm_iterations, a.ipm_solved) == (b.iterations, b.ipm_iterations, b.ipm_solved)
    assert abs(a.objective - b.objective) <= 1e-10 * abs(b.objective) + 1e-300
    scale = max(np.abs(b.Y).max(), 1e-300)
    assert np.abs(a.Y - b.Y).max() <= 1e-10 * scale


def test_suite_uses_both_terminal_kinds():
    # the block path covers the hard terminal state (sensitivity W on the blocks) as well
    kinds = {bool(c.kw.get("terminal_equality")) for c in CASES}
    assert kinds == {False, True}
