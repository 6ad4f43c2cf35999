"""The atmosphere drag inside a ForceModel with the precise terms (issue 14, forces merge): the Cd
partial covers it, the drag's Sun is the force model's (one Sun, one epoch), and AtmosphereDrag takes
an ``earth_rotation`` (IauEarthRotation / UniformRotation)."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest
import satgnc
from satgnc import frames
from satgnc.dynamics import (
    AtmosphereDrag,
    ErfaSun,
    FixedSun,
    HarrisPriester,
    ThirdBodies,
    UniformRotation,
    force_model,
    sun_position,
)
from satgnc.time import Epoch

R0 = np.array([-4502.0, 3870.0, 3420.0]) / np.linalg.norm([-4502.0, 3870.0, 3420.0]) * (6378.137 + 400.0)
V0 = np.array([-2.1, -5.3, 4.4])
CD, AREA, MASS = 2.2, 12.0, 400.0
EOP = pathlib.Path(__file__).parent.parent / "data" / "eop" / "finals2000A_2016-12.txt"


def drag_numpy(
    rot: frames.EarthRotationModel, sun_gcrf: np.ndarray, r: np.ndarray, v: np.ndarray, t: float
) -> np.ndarray:
    # a = -0.5 Cd A/m rho |w| w (A/m in m^2/kg, rho kg/m^3: 1e3 turns 1/m into 1/km), w = v - omega x r,
    # rho = Harris-Priester (n = 6) at R(t) r with the Sun at R(t) sun.
    gcrf_to_itrf, omega = rot.rotation(t)
    rho = HarrisPriester(n=6.0).density(gcrf_to_itrf @ r, gcrf_to_itrf @ sun_gcrf, t)
    w = v - np.cross(omega, r)
    return -0.5 * CD * AREA / MASS * 1e3 * rho * np.linalg.norm(w) * w


def test_earth_rotation_argument_with_iau_2006_earth() -> None:
    rot = frames.IauEarthRotation(Epoch.parse("2016-12-10T00:00:00"), frames.load_eop(EOP), 0.0, 86400.0)
    sun = np.array([0.3, -0.9, 0.2])
    d = AtmosphereDrag(
        HarrisPriester(n=6.0), sun=FixedSun(sun), cd=CD, area=AREA, mass=MASS, earth_rotation=rot
    )
    uniform = AtmosphereDrag(HarrisPriester(n=6.0), sun=FixedSun(sun), cd=CD, area=AREA, mass=MASS)
    assert d.earth_rotation is not None and uniform.earth_rotation is None
    for t in (0.0, 3000.0, 40000.0):
        a = d.acceleration(R0, V0, t)
        # Same formula in numpy with the rotation's own matrix and omega: rounding only (1e-13).
        np.testing.assert_allclose(a, drag_numpy(rot, sun, R0, V0, t), rtol=1e-13, atol=0.0)
        # The IAU pole is 0.094 deg from GCRF z in 2016: latitude and co-rotation change the drag by
        # far more than 1e-6 relative (the uniform Earth is another model, not rounding).
        b = uniform.acceleration(R0, V0, t)
        assert np.linalg.norm(a - b) > 1e-6 * np.linalg.norm(b)
        # At rest in the IAU ITRF: no drag (w = 0 up to the rounding of omega x r, |w| < 1e-15 km/s).
        _, omega = rot.rotation(t)
        assert np.linalg.norm(d.acceleration(R0, np.cross(omega, R0), t)) < 1e-20
    # A uniform rotation given explicitly is the default one.
    explicit = AtmosphereDrag(
        HarrisPriester(n=6.0),
        sun=FixedSun(sun),
        cd=CD,
        area=AREA,
        mass=MASS,
        earth_rotation=UniformRotation(0.0),
    )
    np.testing.assert_array_equal(explicit.acceleration(R0, V0, 500.0), uniform.acceleration(R0, V0, 500.0))
    with pytest.raises(TypeError):
        AtmosphereDrag(HarrisPriester(), earth_rotation="iau")  # type: ignore[arg-type]


def test_one_sun_one_epoch() -> None:
    # sun=None: inside a ForceModel the drag's Sun is its cached ERFA Sun at its epoch. Compared with the
    # drag alone with the Sun straight from ERFA at that epoch (FixedSun per t): the 1/8-day Hermite Sun
    # is within 1e-13 rad of ERFA (measured), 1e-9 relative leaves room. The Cd partial times Cd is the
    # drag term alone (the partial covers atmosphere_drag).
    jd1, jd2 = 2460000.5, 0.25
    d = AtmosphereDrag(HarrisPriester(n=6.0), cd=CD, area=AREA, mass=MASS)
    fm = force_model(atmosphere_drag=d, third_body=ThirdBodies(), epoch_jd=(jd1, jd2))
    for t in (0.0, 7000.0, 86400.0 * 2.5):
        alone = AtmosphereDrag(
            HarrisPriester(n=6.0),
            sun=FixedSun(sun_position(jd1, jd2 + t / 86400.0)),
            cd=CD,
            area=AREA,
            mass=MASS,
        )
        expected = alone.acceleration(R0, V0, t)
        np.testing.assert_allclose(
            CD * fm.acceleration_partial("cd", R0, V0, t), expected, rtol=1e-9, atol=0.0
        )
        # Another epoch is another Sun (90 days: ~89 deg): the check above sees the epoch.
        other = AtmosphereDrag(
            HarrisPriester(n=6.0),
            sun=FixedSun(sun_position(jd1, jd2 + 90.0 + t / 86400.0)),
            cd=CD,
            area=AREA,
            mass=MASS,
        ).acceleration(R0, V0, t)
        assert np.linalg.norm(other - expected) > 1e-3 * np.linalg.norm(expected)
    # Alone, sun=None is ERFA at t s after J2000 TT (the ForceModel's default epoch): exact.
    j2000 = AtmosphereDrag(
        HarrisPriester(n=6.0),
        sun=FixedSun(sun_position(2451545.0, 600.0 / 86400.0)),
        cd=CD,
        area=AREA,
        mass=MASS,
    )
    np.testing.assert_allclose(d.acceleration(R0, V0, 600.0), j2000.acceleration(R0, V0, 600.0), rtol=1e-14)
    # One epoch: an ErfaSun at another epoch than the ForceModel's is refused, naming the field.
    with pytest.raises(
        ValueError, match=r"^atmosphere_drag\.sun: ErfaSun epoch must equal the force model's"
    ):
        satgnc.ForceModel(
            atmosphere_drag=AtmosphereDrag(HarrisPriester(), sun=ErfaSun(2451545.0)), epoch_jd1=jd1
        )
    with pytest.raises(ValueError, match=r"^parameter: cd needs a drag or atmosphere_drag term"):
        satgnc.ForceModel().acceleration_partial("cd", R0, V0)
