"""Bad input to the analysis room: rank tests, Gramians, linearization, OD observability.

Rows: (callable, kwargs, exception type, message fragment naming the argument)."""

from __future__ import annotations

import numpy as np
import pytest
from _bad_input import ARGNAMES, case_ids, check_bad_input
from satgnc import analysis as an

A = np.array([[0.0, 1.0], [-1.0, 0.0]])
B = np.array([[0.0], [1.0]])
C = np.array([[1.0, 0.0]])


def _ctrb(**kw):
    args = dict(A=A, B=B)
    args.update(kw)
    return an.controllability(args.pop("A"), args.pop("B"), **args)


def _pbh(**kw):
    args = dict(A=A, BC=B)
    args.update(kw)
    return an.pbh(**args)


def _gram(**kw):
    args = dict(A=A, B=B, T=1.0)
    args.update(kw)
    return an.controllability_gramian(**args)


def _ogram(**kw):
    args = dict(A=A, C=C, T=1.0)
    args.update(kw)
    return an.observability_gramian(**args)


def _fd(**kw):
    return an.fd_jacobian(t=0.0, x=[1.0], u=[0.0], **kw)


def _odg(**kw):
    args = dict(kind="range", times=[0.0, 60.0, 120.0])
    args.update(kw)
    return an.od_gramian(**args)


def _flt(**kw):
    args = dict(rows=an.loss_table(A, B=np.eye(2)), names=["u1", "u2"], n=2)
    args.update(kw)
    return an.format_loss_table(**args)


CASES = [
    # fuzz pass: overflow blamed on another argument (T, W, x0) or a NaN / Inf result
    (_gram, dict(B=B * 1e300), ValueError, "B: entries must be below 1e+150"),  # blamed T
    (_ogram, dict(C=C * 1e300), ValueError, "C: entries must be below 1e+150"),
    (_gram, dict(T=1e300), ValueError, "T: too long for this A"),  # W = 0 for an oscillator
    (an.ltv_observability_gramian, dict(stms=None, H=[C]), TypeError, "stms: must be a sequence"),
    (an.ltv_observability_gramian, dict(stms=[np.eye(2) * 1e200], H=[C * 1e200]), ValueError,
     "stms, H, weights: the Gramian sum overflows"),  # named "W"
    (an.nondimensionalize, dict(A=np.zeros((4, 4)), B=np.zeros((3, 3)), C=np.zeros((1, 4)),
                                units=an.polar_units(1.0, 1.0, n_outputs=1)), ValueError,
     "B: must have n = 4 rows"),  # "cannot reshape array of size 9"
    (an.od_gramian, dict(kind="range", times=[0.0, 1e300]), ValueError, "times: |t| = 1e+300 s exceeds"),
    (an.od_linear_model, dict(times=[0.0, 60.0], mu=1e300), ValueError, "x0, mu, times: Kepler"),
    (an.visibility_pass, dict(mu=1e300), ValueError, "x0, mu, t_max:"),
    (an.cw_model, dict(mean_motion=1e300), ValueError, "mean_motion: must be in [1e-100, 1e100]"),  # inf in A
    (an.polar_model, dict(sigma=1e300, omega=1.0), ValueError, "sigma: must be in [1e-100, 1e100]"),
    (an.polar_units, dict(sigma=1.0, omega=1e300), ValueError, "omega: must be in"),
    (an.minimum_energy, dict(W=np.eye(2), x_f=[1e300, 0.0]), ValueError, "x_f: entries must be below"),  # inf
    (an.loss_table, dict(A=A, B=np.eye(2) * 1e300), ValueError, "B: entries must be below"),  # NaN ratios
    # orbit said "orbit:" for its argument spec
    (an.orbit, dict(spec="mars"), ValueError, "spec: must be leo, geo, one or 'sigma,omega'"),
    (an.orbit, dict(spec=3), TypeError, "spec: must be a string or a (sigma, omega) pair"),
    (an.orbit, dict(spec=(-1.0, 1.0)), ValueError, "spec (sigma): must be > 0"),
    (an.orbit, dict(spec="1,nan"), ValueError, "spec (omega): must be finite"),
    # format_loss_table had no checks: "ab" printed letters, short names an IndexError, foreign rows a
    # KeyError, n=True printed "rank/True"
    (_flt, dict(names="ab"), TypeError, "names: must be a list of channel names"),
    (_flt, dict(names=["a"]), ValueError, "names: 1 name(s) given, but rows[0] uses channel 1"),
    (_flt, dict(names=["a", 2]), TypeError, "names[1]: must be a string"),
    (_flt, dict(rows=[{"channels": (0,)}]), ValueError, "rows[0]: missing key(s)"),
    (_flt, dict(rows="x"), TypeError, "rows: must be the list of dicts returned by loss_table"),
    (_flt, dict(rows=[3]), TypeError, "rows[0]: must be a dict from loss_table"),
    (_flt, dict(n=True), TypeError, "n: must be an integer"),
    (_flt, dict(n=0), ValueError, "n: must be >= 1"),
    (_flt, dict(title=None), TypeError, "title: must be a string"),
    # complex / boolean / object / string arrays
    (_ctrb, dict(A=A.astype(complex)), TypeError, "A:"),
    (_ctrb, dict(B=B.astype(bool)), TypeError, "B:"),
    (_ctrb, dict(B=np.array([[0], ["1"]], dtype=object)), TypeError, "B:"),
    (_ctrb, dict(A="eye"), TypeError, "A:"),
    (_pbh, dict(A=A + 0j), TypeError, "A:"),
    (_gram, dict(B=B + 1j), TypeError, "B:"),
    (_ogram, dict(C=C.astype(bool)), TypeError, "C:"),
    (lambda **kw: an.expm(**kw), dict(M=np.eye(2, dtype=bool)), TypeError, "M:"),
    (lambda **kw: an.minimum_energy(**kw), dict(W=np.eye(2), x_f=np.array([1j, 0])), TypeError, "x_f:"),
    (lambda **kw: an.kalman_matrix(**kw), dict(A=A, B=B.astype(complex)), TypeError, "B:"),
    (_odg, dict(times=np.array([0, 60j])), TypeError, "times:"),
    (_odg, dict(x0=np.ones(6, dtype=bool)), TypeError, "x0:"),
    (lambda **kw: an.ltv_observability_gramian(**kw), dict(stms=[np.eye(2) + 0j], H=[C]), TypeError, "stms:"),
    (lambda **kw: an.fd_jacobian(lambda t, x, u: x, 0.0, **kw), dict(x=[1j], u=[]), TypeError, "x:"),
    # NaN / Inf
    (_ctrb, dict(A=[[np.nan, 1.0], [0.0, 1.0]]), ValueError, "A:"),
    (_gram, dict(T=np.nan), ValueError, "T:"),
    (_gram, dict(T=np.inf), ValueError, "T:"),
    (_odg, dict(mu=np.nan), ValueError, "mu:"),
    (_pbh, dict(rtol=np.nan), ValueError, "rtol:"),
    # wrong shapes
    (_ctrb, dict(A=np.ones((2, 3))), ValueError, "A:"),
    (_ctrb, dict(B=np.ones((3, 1))), ValueError, "B:"),
    (_gram, dict(A=np.ones(2)), ValueError, "A:"),
    (_ogram, dict(C=np.ones((1, 3))), ValueError, "C:"),
    (lambda **kw: an.minimum_energy(**kw), dict(W=np.eye(2), x_f=np.ones(3)), ValueError, "x_f:"),
    # wrong types for numbers, ints and strings
    (_ctrb, dict(rtol="1e-9"), TypeError, "rtol:"),
    (_ctrb, dict(fuzz=True), TypeError, "fuzz:"),
    (_gram, dict(T="10"), TypeError, "T:"),
    (_gram, dict(T=1j), TypeError, "T:"),
    (lambda **kw: an.polar_units(1.0, 1.0, **kw), dict(n_outputs=1.5), TypeError, "n_outputs:"),
    (lambda **kw: an.cw_units(1e-3, **kw), dict(n_outputs="2"), TypeError, "n_outputs:"),
    (lambda **kw: an.distance_to_uncontrollability(A, B, **kw), dict(max_iter="x"), TypeError, "max_iter:"),
    (lambda **kw: an.distance_to_uncontrollability(A, B, **kw), dict(max_iter=2.0), TypeError, "max_iter:"),
    (lambda **kw: an.cw_model(**kw), dict(mean_motion=True), TypeError, "mean_motion:"),
    (lambda **kw: an.cw_model(1e-3, **kw), dict(measured=[0.5]), TypeError, "measured:"),
    (_odg, dict(rate="fast"), TypeError, "rate:"),
    (_odg, dict(kind=np.array(["range", "both"])), TypeError, "kind:"),
    (_pbh, dict(property=np.ones(2)), TypeError, "property:"),
    (lambda **kw: an.cw_model(1e-3, **kw), dict(measured=1.0), TypeError, "measured:"),
    (lambda **kw: an.polar_linear_model(1.0, 1.0, **kw), dict(measured=True), TypeError, "measured:"),
    # out-of-range values
    (_ctrb, dict(rtol=-1.0), ValueError, "rtol:"),
    (_ctrb, dict(fuzz=0.5), ValueError, "fuzz:"),
    (_gram, dict(T=-1.0), ValueError, "T:"),
    (lambda **kw: an.polar_units(1.0, 1.0, **kw), dict(n_outputs=-1), ValueError, "n_outputs:"),
    (lambda **kw: an.distance_to_uncontrollability(A, B, **kw), dict(max_iter=-1), ValueError, "max_iter:"),
    (lambda **kw: an.polar_model(**kw), dict(sigma=0.0, omega=1.0), ValueError, "sigma:"),
    (_odg, dict(kind="angles"), ValueError, "kind:"),
    (lambda **kw: an.visibility_pass(**kw), dict(dt=-10.0), ValueError, "dt:"),
    (lambda **kw: an.visibility_pass(**kw), dict(dt=1e30), ValueError, "dt:"),  # was blamed on t_max
    # huge horizons: the Gramian overflows or loses positive semidefiniteness -> an error naming T
    (_gram, dict(A=np.diag([1.0, -1.0]), B=np.ones((2, 1)), T=1e3), ValueError, "T:"),
    (_gram, dict(A=np.array([[0.5, 1.0], [0.0, 0.3]]), B=np.array([[0.0], [1.0]]), T=2000.0), ValueError,
     "T:"),
    (_ogram, dict(A=np.diag([1.0, 2.0]), C=np.ones((1, 2)), T=1e4), ValueError, "T:"),
    # huge sizes: 2^m - 1 staircases
    (lambda **kw: an.loss_table(np.eye(2), **kw), dict(B=np.ones((2, 25))), ValueError, "B:"),
    (lambda **kw: an.loss_table(np.eye(2), **kw), dict(C=np.ones((30, 2))), ValueError, "C:"),
    # found by the QA probe (issue 11 verification)
    (lambda **kw: an.expm(**kw), dict(M=1e308 * np.eye(2)), ValueError, "M:"),  # silent NaN matrix
    (lambda **kw: an.visibility_pass(**kw), dict(station_r0=[0.0, 0.0, 0.0]), ValueError,
     "station_r0:"),  # blamed x0 ("not visible")
    (lambda **kw: an.minimum_energy(**kw), dict(W=-np.eye(2), x_f=[1.0, 0.0]), ValueError, "W:"),  # inf
    (lambda **kw: an.minimum_energy(**kw), dict(W=np.array([[1.0, 2.0], [0.0, 1.0]]), x_f=[1.0, 0.0]),
     ValueError, "W:"),  # not symmetric
    (lambda **kw: an.polar_linear_model(1.0, 1.0, **kw), dict(measured=[0, 0]), ValueError,
     "measured:"),  # a repeated output row was accepted
    # f's value: NaN gave a NaN Jacobian, complex was truncated, boolean read as 0/1
    (_fd, dict(f=lambda t, x, u: x * np.nan), ValueError, "f:"),
    (_fd, dict(f=lambda t, x, u: x + 0j), TypeError, "f:"),
    (_fd, dict(f=lambda t, x, u: x > 0), TypeError, "f:"),
]


@pytest.mark.parametrize(ARGNAMES, CASES, ids=case_ids(CASES))
def test_bad_input_names_the_argument(fn, kwargs, exc, fragment):
    check_bad_input(fn, kwargs, exc, fragment)


@pytest.mark.parametrize("T", [1.0, 10.0, 30.0])
def test_gramian_of_unstable_model_over_moderate_horizon_is_psd(T):
    g = an.controllability_gramian(np.diag([0.3, -0.2]), np.ones((2, 1)), T)
    assert g.eigenvalues[0] >= -1e-12 * g.eigenvalues[-1]
    assert np.allclose(g.W, g.W.T)


@pytest.mark.parametrize("seed", range(40))
def test_unstable_gramian_over_long_horizon_is_honest(seed):
    # Issue 11: W_c of an unstable model over a long horizon came back "PSD" with lambda = -5e53.
    # Now a negative eigenvalue beyond the rounding floor (cancellation in Van Loan's product) is an
    # error naming T, and the report carries the floor and whether every eigenvalue is above it.
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 6))
    A, B = rng.standard_normal((n, n)), rng.standard_normal((n, 1))
    for T in (20.0, 50.0, 100.0):
        try:
            g = an.controllability_gramian(A, B, T)
        except ValueError as e:
            assert str(e).startswith("T:")
            continue
        floor = g.extra["rounding_floor"]
        assert floor >= 0 and g.eigenvalues[0] >= -floor
        assert g.extra["resolved"] == bool(g.eigenvalues[0] > floor)
        if g.eigenvalues[0] <= 0:
            assert g.condition == np.inf


def test_list_of_matrices_of_different_shapes_is_valid_input():
    # H_j may have different row counts (p_j x n): the argument checks take each matrix on its own.
    g = an.ltv_observability_gramian([np.eye(6)] * 2, [np.ones((1, 6)), np.ones((2, 6))])
    assert g.W.shape == (6, 6) and g.eigenvalues[-1] == pytest.approx(18.0)
    with pytest.raises(TypeError, match="^H:"):
        an.ltv_observability_gramian([np.eye(2)] * 2, [np.ones((1, 2)), np.ones((2, 2)) + 0j])


def test_pbh_rank_never_negative_for_a_tiny_A():
    # Found by test_properties: A = 1e-22 randn against B = randn made three PBH clusters whose
    # deficiencies added up beyond n (rank -1). Eigenvalues within the rank tolerance are one cluster.
    rng = np.random.default_rng(0)
    A, B = 1e-22 * rng.standard_normal((3, 3)), rng.standard_normal((3, 1))
    p = an.pbh(A, B)
    # [A B] ~ [0 B] to the tolerance: one controllable direction (the staircase, which scales stair by
    # stair, finds 3 for this exact A; the two tests measure different things at this scale)
    assert p.rank == 1 and all(m["deficiency"] <= m["multiplicity"] for m in p.modes)
