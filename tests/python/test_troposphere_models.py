"""Troposphere model per run from Python (issue 13): ``troposphere=True`` / ``"saastamoinen"`` (radio)
or ``"mendes_pavlis"`` (laser ranging, IERS Conventions 2010) in ``satgnc.observation.measurement_model``
and ``satgnc.od.batch_estimate``; the published values and the partials are checked in C++
(tests/cpp/test_troposphere_mendes_pavlis.cpp)."""

from __future__ import annotations

import numpy as np
import pytest
from satgnc import observation
from satgnc.observation import EarthFixedStationEphemeris


def _pass() -> tuple[EarthFixedStationEphemeris, np.ndarray]:
    """A station at 40 N, 1.6 km and a LEO state 0.12 rad from its zenith (about 30 deg elevation)."""
    st = EarthFixedStationEphemeris(40.0, -105.0, 1.6, theta0=0.3)
    up = np.asarray(st.state(0.0)[0], dtype=float)
    up /= np.linalg.norm(up)
    side = np.cross(up, [0.0, 0.0, 1.0])
    side /= np.linalg.norm(side)
    pos = 7000.0 * (np.cos(0.12) * up + np.sin(0.12) * side)
    vel = 7.5 * np.cross(side, up)
    return st, np.concatenate([pos, vel])


def test_models_selectable_and_distinct() -> None:
    st, x = _pass()
    out = {}
    for name, kw in (
        ("off", False),
        ("true", True),
        ("saastamoinen", "saastamoinen"),
        ("mendes_pavlis", "mendes_pavlis"),
    ):
        m = observation.measurement_model("two_way_range", troposphere=kw)
        out[name] = observation.predict(m, st, np.array([0.0]), x[None, :])
    assert out["off"].troposphere[0] == 0.0
    assert out["true"].troposphere[0] == out["saastamoinen"].troposphere[0] > 1e-3  # km: metres
    mp, sa = out["mendes_pavlis"].troposphere[0], out["saastamoinen"].troposphere[0]
    assert mp != sa and abs(mp / sa - 1.0) < 0.1  # the optical and radio delays differ by a few %
    m = observation.measurement_model("two_way_range_rate", troposphere="mendes_pavlis", wavelength_um=1.064)
    assert m.troposphere and m.troposphere_model == "mendes_pavlis"
    assert (
        observation.measurement_model("one_way_range", troposphere=True).troposphere_model == "saastamoinen"
    )


def test_bad_troposphere_arguments_name_themselves() -> None:
    with pytest.raises(
        ValueError, match="troposphere: must be a bool, 'saastamoinen', 'mendes_pavlis' or 'marini_murray'"
    ):
        observation.measurement_model("two_way_range", troposphere="hopfield")
    with pytest.raises(ValueError, match=r"wavelength_um: must be in \[0.3, 1.7\]"):
        observation.measurement_model("two_way_range", troposphere="mendes_pavlis", wavelength_um=10.0)
    with pytest.raises(ValueError, match="troposphere: applies to range observables only"):
        observation.measurement_model("azimuth_elevation", troposphere="mendes_pavlis")


def _marini_murray_numpy(p, t, rh, lat, h_km, lam_um, el):
    """Independent numpy re-implementation of the printed formula (IERS Conventions 1996, TN 21 ch. 9):
    delay in m from P (hPa), T (K), relative humidity (0..1), latitude (rad), height (km), wavelength
    (um), elevation (rad)."""
    e0 = rh * 6.11 * 10.0 ** (7.5 * (t - 273.15) / (237.3 + (t - 273.15)))
    k = 1.163 - 0.00968 * np.cos(2 * lat) - 0.00104 * t + 0.00001435 * p
    a = 0.002357 * p + 0.000141 * e0
    b = 1.084e-8 * p * t * k + 4.734e-8 * p * p / t * 2.0 / (3.0 - 1.0 / k)
    f_lam = 0.9650 + 0.0164 / lam_um**2 + 0.000228 / lam_um**4
    f_site = 1.0 - 0.0026 * np.cos(2 * lat) - 0.00031 * h_km
    s = np.sin(el)
    return f_lam / f_site * (a + b) / (s + (b / (a + b)) / (s + 0.01)), e0


def test_marini_murray_matches_an_independent_numpy_implementation() -> None:
    """200 seeded random inputs over the model's range (10-90 deg, 700-1050 hPa, 250-310 K): the bound
    function equals the numpy formula to 1e-13 relative; its elevation derivative equals a central
    difference to 1e-7. One of PATRIUS's published Scilab values (CNES, MariniMurrayModelTest: 500 nm,
    30 deg, -30 deg, sea level, 800 hPa, 288 K, 40 %: 3.89365646599918 m) to 1e-12 m."""
    rng = np.random.default_rng(13)
    worst = 0.0
    for _ in range(200):
        p, t, rh = rng.uniform(700, 1050), rng.uniform(250, 310), rng.uniform(0, 1)
        lat, h, lam = rng.uniform(-1.5, 1.5), rng.uniform(0, 4), rng.uniform(0.35, 1.1)
        el = np.radians(rng.uniform(10, 90))
        ref, e0 = _marini_murray_numpy(p, t, rh, lat, h, lam, el)
        d, dd = observation.marini_murray_delay(p, t, e0, lat, h, lam, el)
        worst = max(worst, abs(1e3 * d / ref - 1.0))
        step = 1e-6
        fd = (
            observation.marini_murray_delay(p, t, e0, lat, h, lam, el + step)[0]
            - observation.marini_murray_delay(p, t, e0, lat, h, lam, el - step)[0]
        ) / (2 * step)
        assert abs(dd - fd) <= 1e-7 * abs(fd)
    print(f"worst relative difference to numpy: {worst:.2e}")
    assert worst < 1e-13
    _, e0 = _marini_murray_numpy(800.0, 288.0, 0.4, 0.0, 0.0, 0.5, 0.0)
    d, _ = observation.marini_murray_delay(800.0, 288.0, e0, np.radians(-30.0), 0.0, 0.5, np.radians(30.0))
    assert abs(1e3 * d - 3.89365646599918) < 1e-12


def test_marini_murray_per_run() -> None:
    """``troposphere="marini_murray"`` in a measurement model: the delay equals the closed form at the
    down-leg elevation with the station's standard atmosphere and the IERS e0 (1e-12 km), the range-rate
    carries its rate, and it differs from Mendes-Pavlis by a few % on the same pass."""
    st, x = _pass()
    pred = {}
    for name in ("marini_murray", "mendes_pavlis"):
        m = observation.measurement_model("two_way_range", troposphere=name)
        assert m.troposphere_model == name
        pred[name] = observation.predict(m, st, np.array([0.0]), x[None, :]).troposphere[0]
    el = observation.predict(observation.measurement_model("azimuth_elevation"), st, np.array([0.0]),
                             x[None, :]).value[0, 1]
    p, t, _ = observation.standard_atmosphere(st.height, 0.5)
    ref, _ = _marini_murray_numpy(p, t, 0.5, st.latitude, st.height, 0.532, el)
    print(f"elevation {np.degrees(el):.2f} deg: Marini-Murray {1e3 * pred['marini_murray']:.4f} m, "
          f"Mendes-Pavlis {1e3 * pred['mendes_pavlis']:.4f} m")
    assert abs(pred["marini_murray"] - 1e-3 * ref) < 1e-12
    assert pred["marini_murray"] != pred["mendes_pavlis"]
    assert abs(pred["marini_murray"] / pred["mendes_pavlis"] - 1.0) < 0.1
    rr = observation.measurement_model("two_way_range_rate", troposphere="marini_murray")
    assert observation.predict(rr, st, np.array([0.0]), x[None, :]).troposphere[0] != 0.0
    with pytest.raises(ValueError, match="wavelength_um"):
        observation.marini_murray_delay(1013.25, 288.15, 10.0, 0.7, 0.0, 5.0, 0.5)


def test_filter_takes_the_troposphere_per_run() -> None:
    """``satgnc.od.filter(troposphere=...)``: data simulated with Marini-Murray are fitted at the noise
    level with that model (mean NIS < 2) and not without it (the metres of delay against 5 m noise
    on a low pass show in the NIS)."""
    from satgnc import od
    from satgnc.od.filter_sim import simulate_tracking, two_station_scenario

    sc = two_station_scenario()
    tags = np.arange(60.0, 6 * 3600.0, 20.0)
    m = simulate_tracking(sc.x0, sc.stations, tags, force_model=sc.force_model, seed=3,
                          observables=("two_way_range",), sigma=0.001, min_elevation_deg=10.0)
    # Add the Marini-Murray delay of each measurement (the simulator has no troposphere).
    mm = observation.measurement_model("two_way_range", troposphere="marini_murray")
    value = np.array(m["value"], dtype=float)
    for k in range(len(value)):
        st = sc.stations[int(m["station"][k])]
        tk, xk = np.array([m["t"][k]]), m["truth"][k][None, :]
        value[k, 0] += observation.predict(mm, st, tk, xk).troposphere[0]
    p0 = np.diag([1.0, 1.0, 1.0, 1e-3, 1e-3, 1e-3]) ** 2
    kw = dict(stations=list(sc.stations), x0=sc.x0, P0=p0, force_model=sc.force_model,
              observables=("two_way_range",), sigma=(0.001,), gating=False)
    with_mm = od.filter(m["t"], m["station"], m["observable"], value, troposphere="marini_murray", **kw)
    without = od.filter(m["t"], m["station"], m["observable"], value, **kw)
    nis_with, nis_without = float(np.mean(with_mm.nis[20:])), float(np.mean(without.nis[20:]))
    print(f"{len(value)} ranges: mean NIS with Marini-Murray {nis_with:.2f}, without {nis_without:.2f}")
    assert with_mm.status == "completed" and nis_with < 2.0
    assert nis_without > 3.0 * nis_with
