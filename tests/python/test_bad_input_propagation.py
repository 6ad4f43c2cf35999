"""Bad input to the propagation room: every row names the argument that is wrong (issue 11).

Rows: (callable, kwargs, exception type, message fragment). The fragment starts with the argument's
name; categories: complex / boolean / object / string arrays, NaN / Inf, wrong shapes, wrong types
for ints and bools, out-of-range values, physically impossible states, huge sizes.
"""

from __future__ import annotations

import numpy as np
import pytest
import satgnc
from _bad_input import ARGNAMES, case_ids, check_bad_input
from satgnc import _satgnc

X0 = [7000.0, 0.0, 0.0, 0.0, 7.5, 0.0]  # km, km/s
MU = satgnc.EARTH_MU
OBJ = np.array([7000.0, 0, 0, 0, "7.5", 0], dtype=object)


def _prop(**kw):
    args = dict(x0=X0, times=[0.0, 60.0])
    args.update(kw)
    return satgnc.propagate(**args)


def _kepler(**kw):
    args = dict(x0=X0, t0=0.0, times=[60.0], mu=MU)
    args.update(kw)
    return _satgnc.propagate_kepler(**args)


def _kstep(**kw):
    args = dict(x0=X0, dt=60.0, mu=MU)
    args.update(kw)
    return _satgnc.kepler_step(**args)


def _cvodes(**kw):
    args = dict(x0=X0, t0=0.0, times=[60.0])
    args.update(kw)
    return _satgnc.CvodesPropagator(satgnc.ForceModel()).propagate(**args)


def _cvodes_new(**kw):
    return _satgnc.CvodesPropagator(satgnc.ForceModel(), **kw)


def _dop(**kw):
    args = dict(x0=X0, t0=0.0, times=[60.0], force_model=satgnc.ForceModel())
    args.update(kw)
    return _satgnc.propagate_dop853(**args)


CASES = [
    # fuzz pass: x0 = 1e300 was a "force model failed" PropagationError at t0
    (_prop, dict(x0=[1e300, 0, 0, 0, 7.5, 0]), ValueError, "x0: every component must be below 1e100"),
    (_prop, dict(x0=[1e300, 0, 0, 0, 7.5, 0], method="dop853"), ValueError, "x0: every component"),
    (_cvodes, dict(x0=[7000.0, 0, 0, 0, 1e300, 0]), ValueError, "x0: every component"),
    (_dop, dict(x0=[7000.0, 0, 0, 0, 1e300, 0]), ValueError, "x0: every component"),
    # complex / boolean / object / string arrays
    (_prop, dict(x0=np.array(X0, dtype=complex)), TypeError, "x0:"),
    (_prop, dict(x0=np.ones(6, dtype=bool)), TypeError, "x0:"),
    (_prop, dict(x0=OBJ), (TypeError, ValueError), "x0:"),
    (_prop, dict(x0="7000 0 0 0 7.5 0"), TypeError, "x0:"),
    (_prop, dict(times=np.array([0, 60], dtype=complex)), TypeError, "times:"),
    (_prop, dict(times=np.array([False, True])), TypeError, "times:"),
    (_prop, dict(atol=[1e-12j] * 6), TypeError, "atol:"),
    (_kepler, dict(x0=np.array(X0, dtype=complex)), TypeError, "x0:"),
    (_kepler, dict(x0=np.ones(6, dtype=bool)), TypeError, "x0:"),
    (_kepler, dict(times=np.array([60j])), TypeError, "times:"),
    (_kepler, dict(times=["60"]), TypeError, "times:"),
    (_kstep, dict(x0=np.array(X0, dtype=complex)), TypeError, "x0:"),
    (_kstep, dict(x0=OBJ), TypeError, "x0:"),
    (_cvodes, dict(x0=np.array(X0, dtype=complex)), TypeError, "x0:"),
    (_cvodes, dict(times=np.array([True])), TypeError, "times:"),
    (_dop, dict(x0=np.ones(6, dtype=bool)), TypeError, "x0:"),
    # NaN / Inf
    (_prop, dict(x0=[7000.0, 0, 0, 0, np.nan, 0]), ValueError, "x0:"),
    (_prop, dict(times=[0.0, np.inf]), ValueError, "times:"),
    (_prop, dict(t0=np.nan), ValueError, "t0:"),
    (_kstep, dict(dt=np.nan), ValueError, "dt:"),
    (_kstep, dict(x0=[np.inf, 0, 0, 0, 7.5, 0]), ValueError, "x0:"),
    (_kepler, dict(times=[np.nan]), ValueError, "times:"),
    (_cvodes, dict(t0=np.inf), ValueError, "t0:"),
    # wrong shapes
    (_prop, dict(x0=X0[:5]), ValueError, "x0:"),
    (_prop, dict(times=np.zeros((2, 2))), ValueError, "times:"),
    (_prop, dict(atol=[1e-12] * 5), ValueError, "atol:"),
    (_kstep, dict(x0=X0 + [1.0]), ValueError, "x0:"),
    (_kepler, dict(times=[[1.0], [2.0]]), ValueError, "times:"),
    (_cvodes, dict(x0=np.zeros((6, 1))), ValueError, "x0:"),
    # wrong types for numbers, ints and bools
    (_prop, dict(mu=True), TypeError, "mu:"),
    (_prop, dict(mu="earth"), TypeError, "mu:"),
    (_prop, dict(rtol=1j), TypeError, "rtol:"),
    (_prop, dict(max_steps="x"), TypeError, "max_steps:"),
    (_prop, dict(max_steps=2.0), TypeError, "max_steps:"),
    (_prop, dict(with_stm=1), TypeError, "with_stm:"),
    (_prop, dict(method=3), TypeError, "method:"),
    (_prop, dict(surface_radius="6378", method="kepler"), TypeError, "surface_radius:"),
    (_kstep, dict(dt=True), TypeError, "dt:"),
    (_kstep, dict(mu="x"), TypeError, "mu:"),
    (_kepler, dict(with_stm=1), TypeError, "with_stm:"),
    (_kepler, dict(t0="0"), TypeError, "t0:"),
    (_dop, dict(max_steps="x"), TypeError, "max_steps:"),
    (_dop, dict(with_stm="yes"), TypeError, "with_stm:"),
    (_cvodes_new, dict(max_steps="x"), TypeError, "max_steps:"),
    (_cvodes_new, dict(rtol=1j), TypeError, "rtol:"),
    (_cvodes_new, dict(with_stm=1), TypeError, "with_stm:"),
    (_cvodes_new, dict(method=1), TypeError, "method:"),
    (_cvodes_new, dict(atol=[1e-12j] * 6), TypeError, "atol:"),
    (_cvodes_new, dict(atol=True), TypeError, "atol:"),
    (_cvodes_new, dict(atol=[np.nan] * 6), ValueError, "atol:"),
    # out-of-range values
    (_prop, dict(mu=-1.0), ValueError, "mu:"),
    (_prop, dict(rtol=0.0), ValueError, "rtol:"),
    (_prop, dict(max_steps=0), ValueError, "max_steps:"),
    (_prop, dict(method="rk4"), ValueError, "method:"),
    (_prop, dict(times=[0.0, 30.0, 20.0]), ValueError, "times:"),
    (_prop, dict(times=[0.0, 1e300]), ValueError, "times:"),
    (_prop, dict(times=[0.0, 1e300], method="kepler"), ValueError, "times:"),
    (_prop, dict(t0=1e30), ValueError, "t0"),
    (_prop, dict(surface_radius=-1.0, method="kepler"), ValueError, "surface_radius:"),
    (_prop, dict(surface_radius=-1.0, method="dop853"), ValueError, "surface_radius:"),
    (_prop, dict(rtol=1e300), ValueError, "rtol: must be < 1"),  # "succeeded" uncontrolled (fuzz pass)
    (_dop, dict(rtol=2.0), ValueError, "rtol: must be < 1"),
    (_cvodes_new, dict(rtol=1.0), ValueError, "rtol: must be < 1"),
    (_prop, dict(surface_radius=np.nan), ValueError, "surface_radius:"),
    (_prop, dict(surface_radius=True), TypeError, "surface_radius:"),
    (_dop, dict(surface_radius=-1.0), ValueError, "surface_radius:"),
    (_cvodes_new, dict(surface_radius=-1.0), ValueError, "surface_radius:"),
    (_cvodes_new, dict(surface_radius=np.inf), ValueError, "surface_radius:"),
    (_kepler, dict(mu=-1.0), ValueError, "mu:"),
    (_kepler, dict(surface_radius=-5.0), ValueError, "surface_radius:"),
    (_kstep, dict(mu=0.0), ValueError, "mu:"),
    (_dop, dict(rtol=-1.0), ValueError, "rtol:"),
    (_cvodes_new, dict(method="rk4"), ValueError, "method:"),
    # physically impossible states
    (_prop, dict(x0=[0.0, 0, 0, 0, 7.5, 0]), ValueError, "x0:"),
    (_prop, dict(x0=[6000.0, 0, 0, 0, 7.5, 0], method="kepler", surface_radius=6378.0), ValueError, "x0:"),
    (_kstep, dict(x0=[0.0, 0, 0, 1.0, 0, 0]), ValueError, "x0:"),
    (_kstep, dict(x0=[7000.0, 0, 0, -1.0, 0, 0], dt=1e4), ValueError, "x0:"),  # through r = 0
    (_kepler, dict(x0=[6000.0, 0, 0, 0, 7.5, 0], surface_radius=6378.0), ValueError, "x0:"),
    (_cvodes, dict(x0=[0.0, 0, 0, 0, 7.5, 0]), ValueError, "x0:"),
    # below the Earth's surface: every method, the default surface for mu = EARTH_MU (issue 11: it
    # propagated "successfully" with the numerical methods)
    (_prop, dict(x0=[3000.0, 0, 0, 0, 7.5, 0]), ValueError,
     "x0: starts at or below the surface: |r| = 3000 km <= R"),
    (_prop, dict(x0=[3000.0, 0, 0, 0, 7.5, 0], method="bdf"), ValueError, "x0: starts at or below"),
    (_prop, dict(x0=[3000.0, 0, 0, 0, 7.5, 0], method="dop853"), ValueError, "x0: starts at or below"),
    (_prop, dict(x0=[3000.0, 0, 0, 0, 7.5, 0], method="kepler"), ValueError, "x0: starts at or below"),
    (_prop, dict(x0=[6378.1363, 0, 0, 0, 7.5, 0]), ValueError, "x0:"),  # on the surface
    (_prop, dict(x0=[6600.0, 0, 0, 0, 7.5, 0], surface_radius=6600.0, method="dop853"), ValueError, "x0:"),
    (_dop, dict(x0=[6000.0, 0, 0, 0, 7.5, 0], surface_radius=6378.0), ValueError, "x0:"),
    (lambda **kw: _satgnc.CvodesPropagator(satgnc.ForceModel(), surface_radius=6378.0).propagate(**kw),
     dict(x0=[6000.0, 0, 0, 0, 7.5, 0], t0=0.0, times=[60.0]), ValueError, "x0: starts at or below"),
    # huge sizes
    (_dop, dict(max_steps=2**70), ValueError, "max_steps:"),
    (_prop, dict(max_steps=2**70), ValueError, "max_steps:"),
]


@pytest.mark.parametrize(ARGNAMES, CASES, ids=case_ids(CASES))
def test_bad_input_names_the_argument(fn, kwargs, exc, fragment):
    check_bad_input(fn, kwargs, exc, fragment)


def _radius(x0, dt):
    x, _ = _satgnc.kepler_step(x0, dt, MU)
    return float(np.linalg.norm(x[:3]))


@pytest.mark.parametrize("x0, surface", [
    ([7000.0, 0.0, 0.0, 0.0, 5.0, 0.0], 6378.137),  # apoapsis of an ellipse that dips below the surface
    ([7000.0, 0.0, 0.0, 1.0, 4.0, 0.0], 6378.137),  # ascending first: the descent comes after apoapsis
    ([7000.0, 0.0, 0.0, -11.0, 1.0, 0.0], 6378.137),  # hyperbola falling onto the body
    ([7000.0, 0.0, 0.0, -1.0, 0.0, 0.0], 0.0),  # radial ellipse: a collision orbit through r = 0
])
def test_kepler_impact_status_and_time(x0, surface):
    with pytest.raises(satgnc.PropagationError) as info:
        satgnc.propagate(x0, np.linspace(0.0, 20000.0, 41), method="kepler", surface_radius=surface)
    err = info.value
    assert err.status == "impact"
    t_hit = err.t_reached
    assert 0.0 < t_hit < 20000.0
    assert "impact" in str(err)
    tr = err.trajectory
    assert len(tr.times) == int(np.floor(t_hit / 500.0)) + 1  # every output before the impact, none after
    if surface > 0:
        assert _radius(x0, t_hit) == pytest.approx(surface, rel=1e-9)
        # it is the first crossing: above the surface on a fine grid before it
        grid = np.linspace(0.0, t_hit, 400)[:-1]
        assert min(_radius(x0, s) for s in grid) > surface
    else:
        assert _radius(x0, t_hit * (1 - 1e-9)) < 1e-3 * 7000.0


def test_kepler_impact_backward_in_time():
    x0 = [7000.0, 0.0, 0.0, 1.0, 4.0, 0.0]
    with pytest.raises(satgnc.PropagationError) as info:
        satgnc.propagate(x0, [0.0, -20000.0], method="kepler", surface_radius=6378.137)
    assert info.value.status == "impact" and -20000.0 < info.value.t_reached < 0.0
    assert _radius(x0, info.value.t_reached) == pytest.approx(6378.137, rel=1e-9)


def test_kepler_without_surface_keeps_orbits_above_it():
    tr = satgnc.propagate(X0, np.linspace(0.0, 86400.0, 11), method="kepler", surface_radius=6378.137)
    assert tr.status == "success" and len(tr.times) == 11


@pytest.mark.parametrize("method", ["adams", "bdf", "dop853"])
def test_numerical_impact_status_and_time(method):
    # The first Kepler case above on the numerical methods: the same impact, to the tolerances.
    x0 = [7000.0, 0.0, 0.0, 0.0, 5.0, 0.0]
    times = np.linspace(0.0, 20000.0, 41)
    with pytest.raises(satgnc.PropagationError) as ref:
        satgnc.propagate(x0, times, method="kepler", surface_radius=6378.137)
    with pytest.raises(satgnc.PropagationError) as info:
        satgnc.propagate(x0, times, method=method, surface_radius=6378.137)
    err = info.value
    assert err.status == "impact" and "impact at t = " in str(err)
    assert err.t_reached == pytest.approx(ref.value.t_reached, abs=1e-5)
    assert len(err.trajectory) == len(ref.value.trajectory)
    assert np.all(np.isfinite(err.trajectory.states)) and np.all(np.isfinite(err.trajectory.stms))


def test_status_message_knows_impact():
    assert "surface" in _satgnc.status_message("impact")


def test_kepler_overflow_message_names_the_conic():
    # A nearly radial ellipse: whatever fails must not be called a hyperbola.
    try:
        satgnc.propagate([7000.0, 0, 0, 0, 1e-12, 0], [0.0, 1e7], method="kepler")
    except satgnc.PropagationError as e:
        assert "hyperbola" not in str(e)
