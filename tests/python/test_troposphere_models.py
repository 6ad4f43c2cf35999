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
    with pytest.raises(ValueError, match="troposphere: must be a bool, 'saastamoinen' or 'mendes_pavlis'"):
        observation.measurement_model("two_way_range", troposphere="hopfield")
    with pytest.raises(ValueError, match=r"wavelength_um: must be in \[0.3, 1.7\]"):
        observation.measurement_model("two_way_range", troposphere="mendes_pavlis", wavelength_um=10.0)
    with pytest.raises(ValueError, match="troposphere: applies to range observables only"):
        observation.measurement_model("azimuth_elevation", troposphere="mendes_pavlis")
