"""Parameter sensitivity dx/dp alongside the STM (issue 14 item 5), satgnc.propagate_sensitivity:
S against central differences of whole propagations (Cd on LEO with drag, Cr on GEO with SRP), mu
against the analytic dx/dmu of a Kepler orbit (numpy, from the closed-form Kepler STM), the plain STM
bit-for-bit with no parameter, CVODES against DOP853, and bad input."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import satgnc
from satgnc.dynamics import SolarRadiationPressure

LEO = np.array([6778.137, 0.0, 0.0, 0.0, 5.06, 5.77])  # ~400 km near-circular, 48.7 deg
GEO = np.array([42164.17, 0.0, 0.0, 0.0, 3.0746, 0.01])
TIGHT = {"rtol": 1e-13, "atol": 1e-15}  # FD runs: integration noise ~1e-13 |r| per run


def leo_model(cd: float = 2.2) -> satgnc.ForceModel:
    drag = satgnc.ExponentialDrag(rho0=3.725e-12, h0=400.0, scale_height=58.515, cd=cd, area=10.0, mass=500.0)
    return satgnc.ForceModel(j2=satgnc.J2Gravity(), drag=drag)


def geo_model(cr: float = 1.3) -> satgnc.ForceModel:
    return satgnc.dynamics.force_model(srp=SolarRadiationPressure(area=20.0, mass=1000.0, cr=cr))


def central(make, p, h, x0, times):
    """(x(p + h) - x(p - h)) / 2h from two whole DOP853 propagations at rtol 1e-13."""
    plus = satgnc.propagate(x0, times, t0=0.0, forces=make(p + h), with_stm=False, **TIGHT).states
    minus = satgnc.propagate(x0, times, t0=0.0, forces=make(p - h), with_stm=False, **TIGHT).states
    return (plus - minus) / (2 * h)


def rel(a, b):
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


def test_cd_on_leo_matches_central_differences():
    t = np.array([1800.0, 3600.0, 7200.0])
    r = satgnc.propagate_sensitivity(LEO, t, ["cd"], t0=0.0, forces=leo_model(), **TIGHT)
    assert r.sensitivities.shape == (3, 6, 1)
    assert r.stms.shape == (3, 6, 6)
    assert r.parameters == ("cd",)
    # h = 0.2 in Cd: x is nearly linear in Cd (drag is linear in it), so the O(h^2) truncation stays
    # below the integration noise of the two runs divided by 2h. Measured: 3.4e-8 at h = 0.2 (2.5e-7
    # at h = 0.05, noise-dominated); 1e-6 relative keeps a 30x margin.
    fd = central(leo_model, 2.2, 0.2, LEO, t)
    for i in range(3):
        assert rel(r.sensitivities[i, :, 0], fd[i]) < 1e-6
    assert np.linalg.norm(r.sensitivities[-1, :3, 0]) > 1e-2  # ~0.14 km per unit Cd after 2 h


def test_cr_on_geo_matches_central_differences():
    t = np.array([21600.0, 43200.0, 86400.0])
    r = satgnc.propagate_sensitivity(GEO, t, "cr", t0=0.0, forces=geo_model(), **TIGHT)
    # h = 0.5 in Cr: SRP is linear in Cr (x only weakly nonlinear in it); measured 2.1e-8 at h = 0.5
    # (8.4e-7 at h = 0.1, noise-dominated); 1e-6 relative keeps a 50x margin.
    fd = central(geo_model, 1.3, 0.5, GEO, t)
    for i in range(3):
        assert rel(r.sensitivities[i, :, 0], fd[i]) < 1e-6
    assert np.linalg.norm(r.sensitivities[-1, :3, 0]) > 0.1  # ~0.19 km per unit Cr after a day


def kepler_dx_dmu(x0, t, mu):
    """Analytic dx/dmu of a Kepler orbit (numpy). Scaling time by lambda maps solutions to solutions,
    r(t; lambda^2 mu, r0, lambda v0) = r(lambda t; mu, r0, v0), v(...) = lambda v(lambda t; ...); at
    lambda = 1: 2 mu dr/dmu = t v - Phi_rv v0, 2 mu dv/dmu = v + t a - Phi_vv v0 (Phi: Kepler STM)."""
    k = satgnc.propagate(x0, [t], t0=0.0, mu=mu, method="kepler")
    x, phi = k.states[0], k.stms[0]
    r, v = x[:3], x[3:]
    a = -mu * r / np.linalg.norm(r) ** 3
    dr = (t * v - phi[:3, 3:] @ x0[3:]) / (2 * mu)
    dv = (v + t * a - phi[3:, 3:] @ x0[3:]) / (2 * mu)
    return np.concatenate([dr, dv])


@pytest.mark.parametrize("method", ["dop853", "adams"])
def test_mu_on_two_body_matches_the_analytic_kepler_derivative(method):
    x0 = np.array([7000.0, 100.0, -300.0, 0.1, 7.9, 1.0])  # at perigee (7000 km), e ~ 0.12
    t = np.array([600.0, 3000.0, 6000.0, 20000.0])
    mu = satgnc.EARTH_MU
    opts = TIGHT if method == "dop853" else {"rtol": 1e-12, "atol": 1e-14}
    r = satgnc.propagate_sensitivity(x0, t, ["mu"], t0=0.0, method=method, **opts)
    # DOP853 at rtol 1e-13 against an exact identity: 1e-9; CVODES Adams at 1e-12 (5.5 orbits): 1e-6.
    tol = 1e-9 if method == "dop853" else 1e-6
    for i, ti in enumerate(t):
        assert rel(r.sensitivities[i, :, 0], kepler_dx_dmu(x0, ti, mu)) < tol


def test_no_parameter_is_the_plain_stm_bit_for_bit():
    t = np.array([1000.0, 5000.0])
    r = satgnc.propagate_sensitivity(LEO, t, [], t0=0.0, forces=leo_model())
    p = satgnc.propagate(LEO, t, t0=0.0, forces=leo_model())
    assert np.array_equal(r.stms, p.stms)  # exact: the same call
    assert np.array_equal(r.states, p.states)
    assert r.sensitivities.shape == (2, 6, 0)
    ra = satgnc.propagate_sensitivity(LEO, t, [], t0=0.0, forces=leo_model(), method="adams", rtol=1e-10,
                                      atol=1e-12)
    pa = satgnc.propagate(LEO, t, t0=0.0, forces=leo_model(), method="adams", rtol=1e-10, atol=1e-12)
    assert np.array_equal(ra.stms, pa.stms)  # CVODES: the same arithmetic on 42 equations


def test_cvodes_agrees_with_dop853_on_two_parameters():
    t = np.array([3600.0, 7200.0])
    d = satgnc.propagate_sensitivity(LEO, t, ["mu", "cd"], t0=0.0, forces=leo_model(), **TIGHT)
    c = satgnc.propagate_sensitivity(LEO, t, ["mu", "cd"], t0=0.0, forces=leo_model(), method="adams",
                                     rtol=1e-12, atol=1e-14)
    # Two integrators of one system; Adams at 1e-12 over 2 h agrees to ~1e-8: 1e-6.
    assert rel(c.sensitivities, d.sensitivities) < 1e-6
    assert rel(c.stms, d.stms) < 1e-6


def test_result_is_frozen_and_read_only():
    r = satgnc.propagate_sensitivity(LEO, [60.0], ["cd"], t0=0.0, forces=leo_model())
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.parameters = ("mu",)  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        r.sensitivities[0, 0, 0] = 1.0


@pytest.mark.parametrize(
    ("parameters", "forces", "error", "message"),
    [
        (["Cd"], None, ValueError, r"parameters: unknown parameter 'Cd'; use \('mu', 'cd', 'cr'\)"),
        (["mu", "mu"], None, ValueError, "parameters: 'mu' is given twice"),
        ([3], None, TypeError, "parameters: every entry must be a str, got int"),
        (42, None, TypeError, "parameters: must be a name or a list of names"),
        (["cr"], None, ValueError, "parameters: 'cr' needs an srp term in the force model"),
        (["cd"], None, ValueError, "parameters: 'cd' needs a drag or atmosphere_drag term"),
    ],
)
def test_bad_parameters(parameters, forces, error, message):
    with pytest.raises(error, match=message):
        satgnc.propagate_sensitivity(LEO, [60.0], parameters, t0=0.0, forces=forces)


def test_bad_method_and_atol():
    with pytest.raises(ValueError, match="method: unknown 'kepler'"):
        satgnc.propagate_sensitivity(LEO, [60.0], ["mu"], method="kepler")
    with pytest.raises(TypeError, match="atol: must be a real scalar"):
        satgnc.propagate_sensitivity(LEO, [60.0], ["mu"], atol=[1e-12] * 6)
