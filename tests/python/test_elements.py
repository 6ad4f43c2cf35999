"""satgnc.elements_to_state: Vallado's worked example, invariants along a propagated orbit, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
import satgnc
from satgnc.propagation import elements_to_state


def test_vallado_example_2_6():
    # Vallado, Fundamentals of Astrodynamics and Applications, Example 2-6 (COE2RV): p = 11067.790 km,
    # so a = p / (1 - e^2). The printed answer is the state of Example 2-5, whose elements are printed
    # rounded (e to 5 digits, angles to 0.01 / 0.001 deg): that rounding alone moves the state by up
    # to 1.5 km and 8e-4 km/s (first order, half a unit in each last printed digit). Measured here:
    # 0.024 km and 1.6e-5 km/s; the tolerances below are 1.25 times that, 60x inside the rounding.
    p, e = 11067.790, 0.83285
    x = elements_to_state(p / (1 - e * e), e, 87.87, 227.89, 53.38, 92.335, mu=398600.4418)
    assert x.shape == (6,) and x.dtype == np.float64
    np.testing.assert_allclose(x[:3], [6525.344, 6861.535, 6449.125], rtol=0, atol=0.03)
    np.testing.assert_allclose(x[3:], [4.902276, 5.533124, -1.975709], rtol=0, atol=2e-5)
    # the orbit's size and shape are exact functions of p, e, nu: |r| = p / (1 + e cos nu)
    assert np.linalg.norm(x[:3]) == pytest.approx(p / (1 + e * math.cos(math.radians(92.335))), rel=1e-14)


def test_default_mu_is_earth_and_top_level_name():
    assert satgnc.elements_to_state is elements_to_state
    x = elements_to_state(7000.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    # circular equatorial orbit at nu = 0: r on +x, v = sqrt(mu / a) on +y
    np.testing.assert_allclose(x, [7000.0, 0, 0, 0, math.sqrt(satgnc.EARTH_MU / 7000.0), 0], atol=1e-12)


@pytest.mark.parametrize("elements", [(7000.0, 0.01, 51.6, 30.0, 40.0, 10.0),
                                      (26560.0, 0.7, 63.4, 270.0, 280.0, 200.0),
                                      (42164.0, 0.0, 0.0, 0.0, 0.0, 0.0)])
def test_energy_and_angular_momentum_along_the_orbit(elements):
    a, e, i, raan, argp, nu = elements
    mu = satgnc.EARTH_MU
    x0 = elements_to_state(*elements)
    tr = satgnc.propagate(x0, [0.0, 1000.0, 5000.0], method="adams", rtol=1e-12, atol=1e-12, with_stm=False)
    for x in tr.states:
        r, v = x[:3], x[3:]
        energy = 0.5 * v @ v - mu / np.linalg.norm(r)
        assert energy == pytest.approx(-mu / (2 * a), rel=1e-9)  # vis-viva
        h = np.cross(r, v)
        assert np.linalg.norm(h) == pytest.approx(math.sqrt(mu * a * (1 - e * e)), rel=1e-9)
        ir = math.radians(i)
        # h direction: [sin i sin raan, -sin i cos raan, cos i]
        hr = math.radians(raan)
        np.testing.assert_allclose(h / np.linalg.norm(h),
                                   [math.sin(ir) * math.sin(hr), -math.sin(ir) * math.cos(hr), math.cos(ir)],
                                   atol=1e-9)


@pytest.mark.parametrize("kwargs, exc, text", [
    ({"a": -7000.0}, ValueError, "a: must be > 0"),
    ({"a": float("nan")}, ValueError, "a: must be finite"),
    ({"e": 1.0}, ValueError, "e: must be < 1 (an elliptic orbit), got 1.0"),
    ({"e": -0.1}, ValueError, "e: must be >= 0"),
    ({"i": float("inf")}, ValueError, "i: must be finite"),
    ({"nu": "10"}, TypeError, "nu: must be a real number"),
    ({"raan": True}, TypeError, "raan: must be a real number"),
    ({"mu": 0.0}, ValueError, "mu: must be > 0"),
])
def test_bad_input_names_the_argument(kwargs, exc, text):
    args = {"a": 7000.0, "e": 0.01, "i": 51.6, "raan": 30.0, "argp": 40.0, "nu": 10.0} | kwargs
    with pytest.raises(exc, match=text.replace("(", r"\(").replace(")", r"\)")):
        elements_to_state(**args)
