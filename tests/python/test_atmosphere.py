"""Atmosphere drag (issue 14 item 4): Harris-Priester against an independent numpy re-implementation
of Montenbruck & Gill's model (its Table 3.8 typed here, a numpy geodetic-height iteration), gradients
and drag Jacobians against 4th-order differences, co-rotation, propagation STMs against differences of
whole propagations, and bad input naming the argument."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest
import satgnc
from satgnc.dynamics import AtmosphereDrag, ErfaSun, FixedSun, HarrisPriester, SpaceWeather

# Montenbruck & Gill, "Satellite Orbits" (2000), Table 3.8: height km, min / max density g/km^3.
H = np.array([100, 120, 130, 140, 150, 160, 170, 180, 190, 200, 210, 220, 230, 240, 250, 260, 270, 280,
              290, 300, 320, 340, 360, 380, 400, 420, 440, 460, 480, 500, 520, 540, 560, 580, 600, 620,
              640, 660, 680, 700, 720, 740, 760, 780, 800, 840, 880, 920, 960, 1000], dtype=float)
RHO_MIN = np.array([
    4.974e+05, 2.490e+04, 8.377e+03, 3.899e+03, 2.122e+03, 1.263e+03, 8.008e+02, 5.283e+02, 3.617e+02,
    2.557e+02, 1.839e+02, 1.341e+02, 9.949e+01, 7.488e+01, 5.709e+01, 4.403e+01, 3.430e+01, 2.697e+01,
    2.139e+01, 1.708e+01, 1.099e+01, 7.214e+00, 4.824e+00, 3.274e+00, 2.249e+00, 1.558e+00, 1.091e+00,
    7.701e-01, 5.474e-01, 3.916e-01, 2.819e-01, 2.042e-01, 1.488e-01, 1.092e-01, 8.070e-02, 6.012e-02,
    4.519e-02, 3.430e-02, 2.632e-02, 2.043e-02, 1.607e-02, 1.281e-02, 1.036e-02, 8.496e-03, 7.069e-03,
    4.680e-03, 3.200e-03, 2.210e-03, 1.560e-03, 1.150e-03])
RHO_MAX = np.array([
    4.974e+05, 2.490e+04, 8.710e+03, 4.059e+03, 2.215e+03, 1.344e+03, 8.758e+02, 6.010e+02, 4.297e+02,
    3.162e+02, 2.396e+02, 1.853e+02, 1.455e+02, 1.157e+02, 9.308e+01, 7.555e+01, 6.182e+01, 5.095e+01,
    4.226e+01, 3.526e+01, 2.511e+01, 1.819e+01, 1.337e+01, 9.955e+00, 7.492e+00, 5.684e+00, 4.355e+00,
    3.362e+00, 2.612e+00, 2.042e+00, 1.605e+00, 1.267e+00, 1.005e+00, 7.997e-01, 6.390e-01, 5.123e-01,
    4.121e-01, 3.325e-01, 2.691e-01, 2.185e-01, 1.779e-01, 1.452e-01, 1.190e-01, 9.776e-02, 8.059e-02,
    5.741e-02, 4.210e-02, 3.130e-02, 2.360e-02, 1.810e-02])
LAG = 0.523599
OMEGA = satgnc.EARTH_OMEGA


def geodetic_height(r: np.ndarray) -> float:
    """WGS-84 geodetic height (km) by the classical fixed-point iteration (independent of ERFA)."""
    a, f = 6378.137, 1.0 / 298.257223563
    e2 = f * (2.0 - f)
    p = math.hypot(r[0], r[1])
    lat = math.atan2(r[2], p * (1.0 - e2))
    h = 0.0
    for _ in range(30):
        n = a / math.sqrt(1.0 - e2 * math.sin(lat) ** 2)
        h = p / math.cos(lat) - n
        lat = math.atan2(r[2], p * (1.0 - e2 * n / (n + h)))
    return h


def hp_numpy(r_itrf: np.ndarray, sun_itrf: np.ndarray, n: float = 2.0) -> float:
    """Harris-Priester (M&G 3.5.2) in numpy: exponential interpolation, cos^n(psi/2) bulge."""
    h = geodetic_height(r_itrf)
    if h > 1000.0:
        return 0.0
    i = int(np.clip(np.searchsorted(H, h, side="right") - 1, 0, len(H) - 2))
    def interp(t: np.ndarray) -> float:
        scale = (H[i + 1] - H[i]) / math.log(t[i] / t[i + 1])
        return float(t[i] * math.exp((H[i] - h) / scale))
    s = sun_itrf / np.linalg.norm(sun_itrf)
    apex = np.array([math.cos(LAG) * s[0] - math.sin(LAG) * s[1], math.sin(LAG) * s[0] + math.cos(LAG) * s[1],
                     s[2]])
    cos_psi = float(apex @ r_itrf) / float(np.linalg.norm(r_itrf))
    q = (0.5 + 0.5 * cos_psi) ** (0.5 * n)
    return float((interp(RHO_MIN) + (interp(RHO_MAX) - interp(RHO_MIN)) * q) * 1e-12)


def rot_z(theta: float) -> np.ndarray:
    """GCRF -> ITRF for the uniform rotation by theta about z."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


RNG = np.random.default_rng(14)


def random_points(count: int, hmin: float = 110.0, hmax: float = 990.0) -> list[np.ndarray]:
    out = []
    for _ in range(count):
        u = RNG.normal(size=3)
        out.append(u / np.linalg.norm(u) * (6378.137 + RNG.uniform(hmin, hmax)))
    return out


@pytest.mark.parametrize("n", [2.0, 6.0])
def test_harris_priester_matches_numpy_reimplementation(n: float) -> None:
    # 200 random points over 100-1000 km (geodetic height within ~21 km of |r| - a) and random Suns.
    # Relative tolerance 1e-10: both heights converge to 1e-12 km and rho changes by dh / H, H >= 7 km.
    hp = HarrisPriester(n=n)
    for r in random_points(200, 120.0, 975.0):
        sun = RNG.normal(size=3)
        expected = hp_numpy(r, sun, n)
        assert hp.density(r, sun) == pytest.approx(expected, rel=1e-10, abs=0.0)


def test_harris_priester_table_rows_and_limits() -> None:
    # At the table heights on the equator: apex = the max column, antapex = the min column (1e-9).
    hp = HarrisPriester()
    sun = np.array([math.cos(-LAG), math.sin(-LAG), 0.0])  # bulge apex on +x
    for h, lo, hi in zip(H[:-1], RHO_MIN[:-1], RHO_MAX[:-1]):
        assert hp.density([6378.137 + h, 0.0, 0.0], sun) == pytest.approx(hi * 1e-12, rel=1e-9)
        assert hp.density([-(6378.137 + h), 0.0, 0.0], sun) == pytest.approx(lo * 1e-12, rel=1e-9)
    assert hp.density([6378.137 + 1000.5, 0.0, 0.0], sun) == 0.0  # above the table: no atmosphere
    lat, lon, height = HarrisPriester.geodetic([0.0, 0.0, 6356.752314245179 + 300.0])
    assert (lat, lon, height) == pytest.approx((math.pi / 2, 0.0, 300.0), abs=1e-9)


def test_harris_priester_gradient_against_fourth_order_differences() -> None:
    # Step 1e-2 km; 4th-order truncation (h / H)^4 ~ 1e-8; tolerance 1e-6 of the largest component.
    hp = HarrisPriester(n=6.0)
    sun = np.array([0.3, -0.8, 0.45])
    for r in random_points(20, 130.0, 950.0):
        rho, grad = hp.density_gradient(r, sun)
        step = 1e-2
        fd = np.empty(3)
        for k in range(3):
            e = np.zeros(3)
            e[k] = step
            f = [hp.density(r + m * e, sun) for m in (2, 1, -1, -2)]
            fd[k] = (-f[0] + 8 * f[1] - 8 * f[2] + f[3]) / (12 * step)
        assert rho == hp.density(r, sun)
        assert np.max(np.abs(grad - fd)) <= 1e-6 * np.max(np.abs(fd))


EPOCH = 2460000.5  # TT Julian date of t = 0 of make_drag's ErfaSun; a ForceModel must share it (one epoch)


def make_drag(area: float = 12.0) -> AtmosphereDrag:
    return AtmosphereDrag(HarrisPriester(n=6.0), sun=ErfaSun(EPOCH), cd=2.3, area=area, mass=400.0)


R0 = np.array([-4502.0, 3870.0, 3420.0]) / np.linalg.norm([-4502.0, 3870.0, 3420.0]) * (6378.137 + 400.0)
V0 = np.array([-2.1, -5.3, 4.4])


def test_drag_acceleration_matches_numpy() -> None:
    # a = -0.5 Cd A/m rho |w| w (1/m -> 1/km: 1e3) with rho from the numpy model at R(t) r and the
    # ERFA Sun rotated to ITRF, w = v - omega x r. Tolerance 1e-10 (the density's).
    d = make_drag()
    for t in (0.0, 1234.5, 86400.0 * 3.3):
        rot = rot_z(OMEGA * t)
        rho = hp_numpy(rot @ R0, rot @ d.sun.direction(t), 6.0)
        w = V0 - np.cross([0.0, 0.0, OMEGA], R0)
        expected = -0.5 * 2.3 * 12.0 / 400.0 * rho * np.linalg.norm(w) * w * 1e3
        np.testing.assert_allclose(d.acceleration(R0, V0, t), expected, rtol=1e-10, atol=0.0)
        assert d.density(R0, t) == pytest.approx(rho, rel=1e-10)
        # Cd partial: a / Cd (linear in Cd), 1e-15.
        np.testing.assert_allclose(d.cd_partial(R0, V0, t), expected / 2.3, rtol=1e-10)


def test_drag_jacobians_against_fourth_order_differences() -> None:
    d = make_drag()
    t = 3000.0
    a, da_dr, da_dv = d.acceleration_jacobians(R0, V0, t)
    np.testing.assert_allclose(a, d.acceleration(R0, V0, t), rtol=1e-15)

    def fd(f: Callable[[np.ndarray], np.ndarray], x: np.ndarray, h: float) -> np.ndarray:
        out = np.empty((3, 3))
        for k in range(3):
            e = np.zeros(3)
            e[k] = h
            out[:, k] = (-f(x + 2 * e) + 8 * f(x + e) - 8 * f(x - e) + f(x - 2 * e)) / (12 * h)
        return out

    fr = fd(lambda r: d.acceleration(r, V0, t), R0, 1e-2)
    fv = fd(lambda v: d.acceleration(R0, v, t), V0, 1e-5)
    # Tolerances relative to the largest entry: 1e-6 (position: density truncation), 1e-8 (velocity).
    assert np.max(np.abs(da_dr - fr)) <= 1e-6 * np.max(np.abs(fr))
    assert np.max(np.abs(da_dv - fv)) <= 1e-8 * np.max(np.abs(fv))


def test_at_rest_in_itrf_feels_no_drag() -> None:
    d = make_drag()
    v = np.cross([0.0, 0.0, OMEGA], R0)  # co-rotating with the Earth
    assert np.all(d.acceleration(R0, v, 100.0) == 0.0)
    fm = satgnc.ForceModel(atmosphere_drag=d, epoch_jd1=EPOCH)
    np.testing.assert_array_equal(fm.acceleration(R0, v, 100.0), fm.acceleration(R0, v, 100.0))
    a_pm = satgnc.ForceModel().acceleration(R0, v, 100.0)
    np.testing.assert_array_equal(fm.acceleration(R0, v, 100.0), a_pm)  # drag adds exactly 0


def _stm_fd(forces: satgnc.ForceModel, x0: np.ndarray, t: float) -> np.ndarray:
    """Central differences (steps 0.02 km, 2e-5 km/s) of DOP853 runs at rtol 1e-13.

    Harris-Priester's gradient jumps at its table heights make the flow piecewise smooth: the steps
    must be small, and the sample runs keep the STM on, which makes the step control see the jumps
    (state-only runs lose accuracy across them: docs/atmosphere.md)."""
    fd = np.empty((6, 6))
    for k in range(6):
        h = 0.02 if k < 3 else 2e-5
        runs = []
        for m in (1.0, -1.0):
            x = x0.copy()
            x[k] += m * h
            tr = satgnc.propagate(x, [0.0, t], forces=forces, method="dop853", rtol=1e-13, atol=1e-15)
            runs.append(tr.states[-1])
        fd[:, k] = (runs[0] - runs[1]) / (2 * h)
    return fd


@pytest.mark.parametrize("method", ["adams", "dop853"])
def test_propagation_stm_against_whole_propagations(method: str) -> None:
    # Circular 300 km, A/m = 0.5 m^2/kg, one hour, J2 + Harris-Priester n = 6 with the ERFA Sun: the
    # STM of the variational equations against differences of whole propagations. Error of
    # D^-1 Phi D, D = diag(|r0|, |v0|): tolerance 5e-8 (C++ measures 6e-9 against capped-step runs).
    forces = satgnc.ForceModel(j2=satgnc.J2Gravity(), atmosphere_drag=make_drag(area=200.0), epoch_jd1=EPOCH)
    r = R0 / np.linalg.norm(R0) * (6378.137 + 300.0)  # circular at 300 km, inclined ~50 deg
    u = V0 - (V0 @ r) * r / (r @ r)
    x0 = np.concatenate([r, u / np.linalg.norm(u) * math.sqrt(satgnc.EARTH_MU / np.linalg.norm(r))])
    t = 3600.0
    tr = satgnc.propagate(x0, [0.0, t], forces=forces, method=method, rtol=1e-13, atol=1e-15)
    assert tr.stms is not None
    fd = _stm_fd(forces, x0, t)
    d = np.array([np.linalg.norm(x0[:3])] * 3 + [np.linalg.norm(x0[3:])] * 3)
    a = tr.stms[-1] * d[None, :] / d[:, None]
    b = fd * d[None, :] / d[:, None]
    assert np.max(np.abs(a - b)) <= 5e-8 * np.max(np.abs(b))
    # Drag takes energy away: the specific energy after an hour is lower than without drag.
    no_drag = satgnc.propagate(x0, [0.0, t], forces=satgnc.ForceModel(j2=satgnc.J2Gravity()), method=method,
                               rtol=1e-12, atol=1e-14, with_stm=False)
    e = forces.energy(tr.states[-1][:3], tr.states[-1][3:])
    e0 = forces.energy(no_drag.states[-1][:3], no_drag.states[-1][3:])
    assert e < e0 - 1e-3  # km^2/s^2: measured -1.8e-2 (7.8 km apart after the hour)


def test_bad_input_names_the_argument() -> None:
    with pytest.raises(ValueError, match=r"^n: must be in \[2, 6\]"):
        HarrisPriester(n=1.0)
    with pytest.raises(ValueError, match=r"^lag: must be in \[0, pi\] rad"):
        HarrisPriester(lag=-0.1)
    with pytest.raises(TypeError, match="n"):
        HarrisPriester(n="two")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"^AtmosphereDrag\.mass: must be finite and > 0"):
        AtmosphereDrag(HarrisPriester(), mass=0.0)
    with pytest.raises(ValueError, match=r"^AtmosphereDrag\.area: "):
        AtmosphereDrag(HarrisPriester(), area=-1.0)
    with pytest.raises(ValueError, match=r"^AtmosphereDrag\.cd: must be finite and >= 0"):
        AtmosphereDrag(HarrisPriester(), cd=float("nan"))
    with pytest.raises(ValueError, match=r"^epoch_jd1: must be finite"):
        ErfaSun(float("nan"))
    with pytest.raises(ValueError, match=r"^t_end: must be > t_begin"):
        ErfaSun(2451545.0, t_begin=10.0, t_end=5.0)
    with pytest.raises(ValueError, match=r"^direction: must be non-zero"):
        FixedSun([0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^r_itrf: must be non-zero"):
        HarrisPriester().density([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^sun_itrf: must be finite"):
        HarrisPriester().density([7000.0, 0.0, 0.0], [float("nan"), 0.0, 0.0])
    fm = satgnc.ForceModel(atmosphere_drag=make_drag(), epoch_jd1=EPOCH)
    with pytest.raises(ValueError, match=r"^r: is below the WGS-84 ellipsoid"):
        fm.acceleration([0.0, 0.0, 6300.0], [0.0, 7.5, 0.0])


def test_space_weather_defaults_and_ranges() -> None:
    w = SpaceWeather()
    assert (w.f107, w.f107a, w.ap) == (150.0, 150.0, 4.0)
    assert SpaceWeather(f107=0.0, f107a=400.0, ap=400.0).ap == 400.0  # closed ranges
    with pytest.raises(ValueError, match=r"^SpaceWeather\.f107: must be in \[0, 400\] sfu, got -1$"):
        SpaceWeather(f107=-1.0)
    with pytest.raises(ValueError, match=r"^SpaceWeather\.f107: must be in \[0, 400\] sfu, got 450$"):
        SpaceWeather(f107=450.0)
    with pytest.raises(ValueError, match=r"^SpaceWeather\.f107a: "):
        SpaceWeather(f107a=float("inf"))
    with pytest.raises(ValueError, match=r"^SpaceWeather\.ap: must be in \[0, 400\], got 401$"):
        SpaceWeather(ap=401.0)
    with pytest.raises(TypeError, match="ap"):
        SpaceWeather(ap="high")  # type: ignore[arg-type]
