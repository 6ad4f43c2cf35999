"""Make the example tracking file leo_tracking.tdm (and stations.toml) of ``satgnc od batch``.

Truth: a sun-synchronous orbit at 600 km, GCRF state at 2016-12-10T00:00:00 UTC printed below,
propagated with J2 (satgnc's DOP853). Two stations fixed in ITRF (WGS-84: Kiruna, Weilheim) on IAU
2006/2000A with the EOP of astropy-iers-data. Two-way light-time range (km), range-rate
(DOPPLER_INSTANTANEOUS, km/s) and azimuth / elevation (deg) every 60 s above 10 deg elevation over
24 h, noise 1 m / 1 mm/s / 0.005 deg (seed 7), and a 5 m range bias at Weilheim. Run from the
repository root: ``python examples/data/make_leo_tracking.py``.
"""

from __future__ import annotations

import math
import pathlib

import numpy as np
from satgnc import _satgnc, frames, io, observation, propagation
from satgnc.time import Epoch

HERE = pathlib.Path(__file__).resolve().parent
EPOCH = "2016-12-10T00:00:00"
SITES = {"KIRUNA": (67.8571, 20.9641, 0.402), "WEILHEIM": (47.8813, 11.0785, 0.664)}
RANGE_BIAS = {"KIRUNA": 0.0, "WEILHEIM": 5e-3}  # km
SIG_RANGE, SIG_RR, SIG_ANG_DEG = 1e-3, 1e-6, 0.005  # km, km/s, deg


def truth() -> np.ndarray:
    """The GCRF state at EPOCH, km and km/s."""
    a, inc, raan, u = 6378.137 + 600.0, math.radians(97.8), 1.0, 2.5
    v = math.sqrt(float(_satgnc.EARTH_MU) / a)
    ci, si, co, so = math.cos(inc), math.sin(inc), math.cos(raan), math.sin(raan)
    rot = np.array([[co, -so * ci, so * si], [so, co * ci, -co * si], [0.0, si, ci]])
    return np.concatenate(
        [rot @ [a * math.cos(u), a * math.sin(u), 0.0], rot @ [-v * math.sin(u), v * math.cos(u), 0.0]]
    )


def simulate_tdm(eop, span: float, dt: float, seed: int, *, rounded: bool = True, comments=()):
    """Simulated two-way tracking of :func:`truth` over ``span`` s every ``dt`` s, one TDM segment per
    station in SITES; returns (Tdm, truth). ``eop``: a satgnc EOP table; ``rounded``: values to
    1e-9 km (1e-12 km/s for range-rate), as in the shipped file; tests/python/test_od_batch_cli.py
    calls this with its own span, seed and EOP sample."""
    epoch = Epoch.parse(EPOCH, "UTC")
    rot = frames.IauEarthRotation(epoch, eop, -3600.0, span + 3600.0)
    x0 = truth()
    t = np.arange(0.0, span, dt)
    xs = propagation.propagate(x0, t, forces=_satgnc.J2Gravity(), with_stm=False).states
    rng = np.random.default_rng(seed)
    kinds = ("two_way_range", "two_way_range_rate", "azimuth_elevation")
    models = {k: observation.measurement_model(k) for k in kinds}
    segments = []
    for name, (lat, lon, h) in SITES.items():
        st = observation.EarthFixedStationEphemeris.from_ground_station(
            frames.GroundStation(lat, lon, h, 0.0, name), rot
        )
        ang = observation.predict(models["azimuth_elevation"], st, t, xs).value
        vis = np.degrees(ang[:, 1]) > 10.0
        tv, xv = t[vis], xs[vis]
        rho = observation.predict(models["two_way_range"], st, tv, xv, range_bias=RANGE_BIAS[name]).value
        rr = observation.predict(models["two_way_range_rate"], st, tv, xv).value
        az_el = np.degrees(ang[vis])
        kw, ep, val = [], [], []
        for i, ti in enumerate(tv):
            tag = (epoch + float(ti)).to_iso("UTC", 3)
            for k, v in (
                ("RANGE", rho[i] + SIG_RANGE * rng.normal()),
                ("DOPPLER_INSTANTANEOUS", rr[i] + SIG_RR * rng.normal()),
                ("ANGLE_1", (az_el[i, 0] + SIG_ANG_DEG * rng.normal()) % 360.0),
                ("ANGLE_2", az_el[i, 1] + SIG_ANG_DEG * rng.normal()),
            ):
                kw.append(k)
                ep.append(tag)
                val.append(round(float(v), 9 if k != "DOPPLER_INSTANTANEOUS" else 12) if rounded else v)
        md = io.TdmMetadata(
            time_system="UTC",
            participants=(name, "SAT"),
            mode="SEQUENTIAL",
            path=(1, 2, 1),
            range_units="km",
            angle_type="AZEL",
            comments=tuple(comments),
        )
        segments.append(
            io.TdmSegment(metadata=md, keywords=tuple(kw), epochs=tuple(ep), values=np.array(val))
        )
    header = io.Header(creation_date="2026-12-03T00:00:00", originator="SATGNC")
    return io.Tdm(header=header, segments=tuple(segments)), x0


def stations_toml() -> str:
    """The stations file of SITES (``satgnc od batch --stations``)."""
    lines = ["# Ground stations of leo_tracking.tdm (WGS-84 geodetic; satgnc od batch --stations)"]
    for name, (lat, lon, h) in SITES.items():
        lines += [
            "",
            f"[{name}]",
            f"latitude = {lat}   # deg",
            f"longitude = {lon}  # deg east",
            f"height = {h}       # km above the ellipsoid",
        ]
    return "\n".join(lines) + "\n"


def main() -> None:
    tdm, x0 = simulate_tdm(
        frames.default_eop(),
        24 * 3600.0,
        60.0,
        7,
        comments=(
            "simulated by examples/data/make_leo_tracking.py: two-way, light time, "
            "IAU 2006/2000A + EOP, noise 1 m / 1 mm/s / 0.005 deg",
        ),
    )
    io.write_tdm(HERE / "leo_tracking.tdm", tdm)
    (HERE / "stations.toml").write_text(stations_toml())
    print("truth (GCRF km, km/s):", ",".join(f"{v:.6f}" for v in x0))


if __name__ == "__main__":
    main()
