"""Bad input to the dynamics room (force models, Earth constants' classes, the polar model).

Rows: (callable, kwargs, exception type, message fragment naming the argument)."""

from __future__ import annotations

import numpy as np
import pytest
import satgnc
from _bad_input import ARGNAMES, case_ids, check_bad_input
from satgnc import analysis

R = np.array([7000.0, 0.0, 0.0])  # km
V = np.array([0.0, 7.5, 0.0])  # km/s
DRAG = dict(rho0=1e-12, h0=500.0, scale_height=60.0)


def _acc(**kw):
    args = dict(r=R, v=V)
    args.update(kw)
    return satgnc.ForceModel().acceleration(**args)


def _acc_drag(**kw):
    args = dict(r=R, v=V)
    args.update(kw)
    return satgnc.ForceModel(drag=satgnc.ExponentialDrag(**DRAG)).acceleration(**args)


def _jac(**kw):
    args = dict(r=R, v=V)
    args.update(kw)
    return satgnc.ForceModel(j2=satgnc.J2Gravity()).acceleration_jacobians(**args)


def _pot(**kw):
    return satgnc.ForceModel(j2=satgnc.J2Gravity()).potential(**kw)


def _energy(**kw):
    args = dict(r=R, v=V)
    args.update(kw)
    return satgnc.ForceModel().energy(**args)


def _density(**kw):
    return satgnc.ExponentialDrag(**DRAG).density(**kw)


def _setattr(obj, **kw):
    for k, v in kw.items():
        setattr(obj, k, v)


def _set_j2(**kw):
    _setattr(satgnc.J2Gravity(), **kw)


def _set_drag(**kw):
    _setattr(satgnc.ExponentialDrag(**DRAG), **kw)


def _set_fm(**kw):
    _setattr(satgnc.ForceModel(), **kw)


def _polar_rhs(**kw):
    args = dict(t=0.0, s=[1.0, 0.0, 0.0, 1.0], u=[0.0, 0.0])
    args.update(kw)
    return analysis.PolarModel(1.0, 1.0).rhs(**args)


CASES = [
    # fuzz pass (issue 11): the force terms' constructors accepted NaN / Inf until a propagation
    (satgnc.J2Gravity, dict(mu=np.nan), ValueError, "mu: must be finite and > 0"),
    (satgnc.J2Gravity, dict(j2=np.inf), ValueError, "j2: must be finite"),
    (satgnc.J2Gravity, dict(radius=-np.inf), ValueError, "radius: must be finite and > 0"),
    (satgnc.ExponentialDrag, dict(DRAG, rho0=np.inf), ValueError, "rho0: must be finite and >= 0"),
    (satgnc.ExponentialDrag, dict(DRAG, h0=np.nan), ValueError, "h0: must be finite"),
    (satgnc.ExponentialDrag, dict(DRAG, scale_height=-np.inf), ValueError,
     "scale_height: must be finite and > 0"),
    (satgnc.ExponentialDrag, dict(DRAG, body_radius=0.0), ValueError, "body_radius: must be finite and > 0"),
    (satgnc.ExponentialDrag, dict(DRAG, omega=[0.0, 0.0, np.nan]), ValueError, "omega: must be finite"),
    # complex / boolean / object / string arrays
    (_acc, dict(r=R.astype(complex)), TypeError, "r:"),
    (_acc, dict(r=np.ones(3, dtype=bool)), TypeError, "r:"),
    (_acc, dict(v=np.array([0, "7.5", 0], dtype=object)), TypeError, "v:"),
    (_acc, dict(v="0 7.5 0"), TypeError, "v:"),
    (_jac, dict(r=R + 0j), TypeError, "r:"),
    (_jac, dict(v=[True, False, True]), TypeError, "v:"),
    (_pot, dict(r=R.astype(complex)), TypeError, "r:"),
    (_energy, dict(v=np.array([1j, 0, 0])), TypeError, "v:"),
    (_polar_rhs, dict(s=np.ones(4, dtype=complex)), TypeError, "s:"),
    (_polar_rhs, dict(u=np.zeros(2, dtype=bool)), TypeError, "u:"),
    # NaN / Inf
    (_acc, dict(r=[np.nan, 0.0, 0.0]), ValueError, "r:"),
    (_acc, dict(v=[0.0, np.inf, 0.0]), ValueError, "v:"),
    (_acc, dict(t=np.nan), ValueError, "t:"),
    (_density, dict(radius=np.nan), ValueError, "radius:"),
    (_set_drag, dict(mass=np.nan), ValueError, "mass:"),
    (_polar_rhs, dict(t=np.inf), ValueError, "t:"),
    # wrong shapes
    (_acc, dict(r=np.ones(4)), ValueError, "r:"),
    (_acc, dict(v=np.ones((3, 1))), ValueError, "v:"),
    (_jac, dict(r=[1.0, 2.0]), ValueError, "r:"),
    (_polar_rhs, dict(s=[1.0, 0.0, 0.0]), ValueError, "s:"),
    # wrong types for numbers and bools
    (_acc, dict(t="0"), TypeError, "t:"),
    (_acc, dict(t=True), TypeError, "t:"),
    (_density, dict(radius=1j), TypeError, "radius:"),
    (_density, dict(radius=True), TypeError, "radius:"),
    (lambda **kw: satgnc.ForceModel(**kw), dict(mu="earth"), TypeError, "mu:"),
    (lambda **kw: satgnc.ForceModel(**kw), dict(mu=True), TypeError, "mu:"),
    (lambda **kw: satgnc.J2Gravity(**kw), dict(j2=1j), TypeError, "j2:"),
    (lambda **kw: satgnc.ExponentialDrag(**kw), dict(DRAG, cd="2.2"), TypeError, "cd:"),
    (lambda **kw: satgnc.ForceModel(**kw), dict(j2="yes"), TypeError, "j2:"),
    (_set_j2, dict(radius="6378"), TypeError, "radius:"),
    (_set_j2, dict(mu=True), TypeError, "mu:"),
    (_set_fm, dict(mu=1j), TypeError, "mu:"),
    (_set_drag, dict(omega=[1j, 0, 0]), TypeError, "omega:"),
    (lambda **kw: analysis.PolarModel(**kw), dict(sigma=1j, omega=1.0), TypeError, "sigma:"),
    # out-of-range values
    (lambda **kw: satgnc.ForceModel(**kw), dict(mu=-1.0), ValueError, "mu:"),
    (lambda **kw: analysis.PolarModel(**kw), dict(sigma=-1.0, omega=1.0), ValueError, "sigma:"),
    # physically impossible states: the centre of the body, below the surface
    (_acc, dict(r=[0.0, 0.0, 0.0]), ValueError, "r:"),
    (_jac, dict(r=[0.0, 0.0, 0.0]), ValueError, "r:"),
    (_pot, dict(r=[0.0, 0.0, 0.0]), ValueError, "r:"),
    (_energy, dict(r=[0.0, 0.0, 0.0]), ValueError, "r:"),
    (_acc_drag, dict(r=[6000.0, 0.0, 0.0]), ValueError, "r:"),
    (_density, dict(radius=-1.0), ValueError, "radius:"),
    (_density, dict(radius=100.0), ValueError, "radius:"),
]


@pytest.mark.parametrize(ARGNAMES, CASES, ids=case_ids(CASES))
def test_bad_input_names_the_argument(fn, kwargs, exc, fragment):
    check_bad_input(fn, kwargs, exc, fragment)


def test_good_input_still_works_and_is_finite():
    fm = satgnc.ForceModel(j2=satgnc.J2Gravity(), drag=satgnc.ExponentialDrag(**DRAG))
    a = fm.acceleration(R, V)
    assert a.shape == (3,) and np.all(np.isfinite(a))
    assert a[0] == pytest.approx(-satgnc.EARTH_MU / 7000.0**2, rel=2e-3)
    a2, gr, gv = fm.acceleration_jacobians([7000, 0, 0], (0, 7.5, 0), 10)  # ints and tuples are real input
    assert np.allclose(a, a2) and gr.shape == (3, 3) and gv.shape == (3, 3)
    rho = satgnc.ExponentialDrag(**DRAG).density(satgnc.EARTH_RADIUS + 500.0)
    assert rho == pytest.approx(1e-12, rel=1e-9)
    assert satgnc.ExponentialDrag(**DRAG).density(np.float64(6378.1363)) > 0  # at the surface: allowed
