"""Bad input to the guidance API: CW models, L1Solver arguments, settings fields of every solver.

Rows: (callable, kwargs, exception type, message fragment naming the argument or field)."""

from __future__ import annotations

import numpy as np
import pytest
from _bad_input import ARGNAMES, case_ids, check_bad_input
from satgnc import _satgnc
from satgnc import guidance as g

N_MEAN = 0.0011  # rad/s
AD, BD = g.cw_discretize(N_MEAN, 1.0, 60.0)


def _l1(**kw):
    args = dict(A=AD, B=BD, x0=[100.0, 50.0, 0.0, 0.0, 0.0, 0.0], horizon=5, Qf=np.eye(6))
    args.update(kw)
    return g.L1Solver(**args)


def _set(cls):
    def setter(**kw):
        obj = cls()
        for k, v in kw.items():
            setattr(obj, k, v)
    setter.__name__ = f"set_{cls.__name__}"
    return setter


ADMM, ILQR, SCP = _set(g.AdmmSettings), _set(_satgnc.IlqrAdmmSettings), _set(_satgnc.ScpSettings)
MAPSET, PMAPSET = _set(_satgnc.TwoSatelliteMapSettings), _set(_satgnc.PropagatedMapSettings)
PARAMS, PROBLEM = _set(_satgnc.TwoSatelliteParams), _set(_satgnc.NonlinearL1Problem)

CASES = [
    # fuzz pass: 1e300 entries gave a NaN objective (A) or an infinite one (x0); Qf = 1e300 blamed "rho"
    (_l1, dict(A=AD * 1e300), ValueError, "A: entries must be below 1e100"),
    (_l1, dict(x0=np.full(6, 1e300)), ValueError, "x0: entries must be below 1e100"),
    (_l1, dict(Qf=np.eye(6) * 1e300), ValueError, "Qf: entries must be below 1e100"),
    # huge times: cw_stm(t=1e300) returned a matrix of 1e300 entries with no correct digit (|n t| <= 1e9 rad)
    (g.cw_stm, dict(n=N_MEAN, t=1e300), ValueError, "t: |n t| = 1.1e+297 rad exceeds 1e9 rad"),
    (g.cw_stm, dict(n=N_MEAN, t=-1e13), ValueError, "t: |n t|"),
    (g.cw_stm, dict(n=1e300, t=1.0), ValueError, "n: must be in [1e-100, 1e100] rad/s"),  # n^2 = inf
    (g.cw_matrices, dict(n=1e300, mass=1.0), ValueError, "n: must be in [1e-100, 1e100]"),  # inf in A
    (g.cw_stm, dict(n=1e90, t=1e20), ValueError, "t: |n t|"),
    (_satgnc.cw_stm, dict(n=N_MEAN, t=1e300), ValueError, "t: |n t|"),
    (g.cw_discretize, dict(n=N_MEAN, mass=1.0, dt=1e13), ValueError, "dt: |n dt|"),
    (g.cw_discretize, dict(n=N_MEAN, mass=1.0, dt=1e13, method="expm"), ValueError, "dt: |n dt|"),
    (g.cw_discretize, dict(n=N_MEAN, mass=1.0, dt=1e13, method="midpoint"), ValueError, "dt: |n dt|"),
    # CW: complex / bool / string numbers, NaN, out of range
    (g.cw_stm, dict(n=N_MEAN, t=np.nan), ValueError, "t:"),
    (g.cw_stm, dict(n=N_MEAN, t=np.inf), ValueError, "t:"),
    (g.cw_stm, dict(n=1j, t=1.0), TypeError, "n:"),
    (g.cw_stm, dict(n=N_MEAN, t=True), TypeError, "t:"),
    (g.cw_stm, dict(n=-1.0, t=1.0), ValueError, "n:"),
    (_satgnc.cw_stm, dict(n=N_MEAN, t=np.nan), ValueError, "t:"),
    (_satgnc.cw_stm, dict(n=N_MEAN, t=1j), TypeError, "t:"),
    (g.cw_discretize, dict(n=N_MEAN, mass=1.0, dt=-60.0), ValueError, "dt:"),
    (g.cw_discretize, dict(n=N_MEAN, mass=1.0, dt="60"), TypeError, "dt:"),
    (g.cw_discretize, dict(n=N_MEAN, mass=np.nan, dt=60.0), ValueError, "mass:"),
    (g.cw_discretize, dict(n=N_MEAN, mass=1.0, dt=60.0, method=3), TypeError, "method:"),
    (g.cw_discretize, dict(n=N_MEAN, mass=1.0, dt=60.0, method="rk4"), ValueError, "method:"),
    (g.cw_matrices, dict(n=N_MEAN, mass=0.0), ValueError, "mass:"),
    (g.cw_matrices, dict(n=[N_MEAN], mass=1.0), TypeError, "n:"),
    # L1Solver arrays: complex / boolean / object / string, NaN, shapes
    (_l1, dict(A=AD.astype(complex)), TypeError, "A:"),
    (_l1, dict(B=BD.astype(bool)), TypeError, "B:"),
    (_l1, dict(x0=np.array([1, 0, 0, 0, 0, "0"], dtype=object)), TypeError, "x0:"),
    (_l1, dict(x0=np.ones(6, dtype=bool)), TypeError, "x0:"),
    (_l1, dict(Qf=np.eye(6) + 0j), TypeError, "Qf:"),
    (_l1, dict(l1_weights=[1j, 1, 1]), TypeError, "l1_weights:"),
    (_l1, dict(u_lower=np.array([True, True, True])), TypeError, "u_lower:"),
    (_l1, dict(xf="origin"), TypeError, "xf:"),
    (_l1, dict(x0=[np.nan, 0, 0, 0, 0, 0]), ValueError, "x0:"),
    (_l1, dict(x0=np.zeros(5)), ValueError, "x0:"),
    (_l1, dict(l1_weights=[1.0, -1.0, 1.0]), ValueError, "l1_weights:"),
    # settings fields: wrong types, NaN, values beyond the engine's integers (no signature dumps)
    (ADMM, dict(max_iterations="x"), TypeError, "max_iterations:"),
    (ADMM, dict(max_iterations=2.0), TypeError, "max_iterations:"),
    (ADMM, dict(max_iterations=True), TypeError, "max_iterations:"),
    (ADMM, dict(max_iterations=2**40), ValueError, "max_iterations:"),
    (ADMM, dict(rho="0.1"), TypeError, "rho:"),
    (ADMM, dict(rho=np.nan), ValueError, "rho:"),
    (ADMM, dict(rho=1j), TypeError, "rho:"),
    (ADMM, dict(polish=1), TypeError, "polish:"),
    (ADMM, dict(polish="false"), TypeError, "polish:"),
    (ADMM, dict(stopping=3), TypeError, "stopping:"),
    (ADMM, dict(stopping="never"), ValueError, "stopping:"),
    (ADMM, dict(max_iterations=0), ValueError, "max_iterations:"),  # out of range: at assignment
    (ADMM, dict(relaxation=3.0), ValueError, "relaxation:"),
    (ADMM, dict(rho=-1.0), ValueError, "rho:"),
    (ILQR, dict(rho=-1.0), ValueError, "rho:"),
    (ILQR, dict(max_iter=0), ValueError, "max_iter:"),
    (SCP, dict(armijo=1.5), ValueError, "armijo:"),
    (ILQR, dict(max_iter="x"), TypeError, "max_iter:"),
    (ILQR, dict(rho=True), TypeError, "rho:"),
    (ILQR, dict(adaptive_rho="yes"), TypeError, "adaptive_rho:"),
    (ILQR, dict(ilqr_iters=2**31), ValueError, "ilqr_iters:"),
    (SCP, dict(max_outer="x"), TypeError, "max_outer:"),
    (SCP, dict(armijo=1j), TypeError, "armijo:"),
    (MAPSET, dict(dt="60"), TypeError, "dt:"),
    (MAPSET, dict(substeps=1.5), TypeError, "substeps:"),
    (PMAPSET, dict(rtol=np.nan), ValueError, "rtol:"),
    (PMAPSET, dict(max_steps=-(2**70)), ValueError, "max_steps:"),
    (PARAMS, dict(mu="earth"), TypeError, "mu:"),
    (PARAMS, dict(j2_on=1), TypeError, "j2_on:"),
    (PROBLEM, dict(horizon="x"), TypeError, "horizon:"),
    (PROBLEM, dict(horizon=2**31), ValueError, "horizon:"),
    (PROBLEM, dict(x0=np.ones(6, dtype=complex)), TypeError, "x0:"),
    (PROBLEM, dict(alpha="1"), TypeError, "alpha:"),
    # compiled constructors: wrong argument types name the argument
    (lambda **kw: _satgnc.LinearDiscreteModel(**kw), dict(A=[np.eye(2) + 0j], B=[np.ones((2, 1))], c=[]),
     TypeError, "A:"),
    (lambda **kw: _satgnc.TwoSatelliteMap(**kw), dict(model="cw", settings=_satgnc.TwoSatelliteMapSettings()),
     TypeError, "model:"),
]


@pytest.mark.parametrize(ARGNAMES, CASES, ids=case_ids(CASES))
def test_bad_input_names_the_argument(fn, kwargs, exc, fragment):
    check_bad_input(fn, kwargs, exc, fragment)


def test_a_refused_setting_keeps_the_old_value():
    s = g.AdmmSettings()
    before = s.max_iterations
    with pytest.raises(TypeError):
        s.max_iterations = "x"
    assert s.max_iterations == before
    s.max_iterations = np.int64(123)  # numpy integers are integers
    assert s.max_iterations == 123
    s.stopping = "paper"  # enum members by name
    assert s.stopping == _satgnc.StoppingRule.paper
    with pytest.raises(ValueError, match="^relaxation:"):
        s.relaxation = 2.5
    assert s.relaxation == g.AdmmSettings().relaxation
