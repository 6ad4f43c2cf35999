"""Report section: the size of each measurement-model effect on a real-looking LEO pass, and what
ignoring it does to a batch orbit determination (issue 13 item 6; docs/od.md "Effect sizes").

Scenario: an ISS-like orbit (420 km circular, 51.64 deg) over the Weilheim station (47.8813 N,
11.0785 E, 0.664 km) on 2016-12-10, Earth orientation IAU 2006/2000A with EOP (the table given, by
default the installed astropy-iers-data; tests and docs use the shipped finals2000A sample), J2
dynamics. The pass is the highest of the day above 5 deg elevation.

Effects (each the largest |difference| over the pass, m and mm/s):

* light time: two-way range / range-rate (light-time equations, mean of the legs) against the
  instantaneous geometry at the tag;
* troposphere: Saastamoinen zenith delay in the standard atmosphere at the station's height mapped
  by Black-Eisner to 5, 10 and 30 deg elevation (m), and its largest rate over the pass (mm/s);
* Shapiro: the Earth's relativistic delay over the pass;
* EOP: the station by the full IAU 2006/2000A chain with EOP against a GMST-only rotation
  (IAU-1982 GMST at UTC, uniform rate, no precession-nutation, polar motion or UT1-UTC);
* polar motion alone: the full chain against the same with xp = yp = 0.

OD: noise-free data of every pass of the day (two-way range 1 m, two-way range-rate 1 mm/s,
az/el 1e-4 rad weights) made with the effect, fitted (batch_estimate) without it; the table gives
the position and velocity error of the fitted epoch state.

Run ``python -m satgnc.report.od_effects`` for the Markdown table.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from .. import _satgnc
from .._results import Result

TITLE = "Orbit determination on tracking data: effect sizes"

STATION = ("WEILHEIM", 47.8813, 11.0785, 0.664)  # name, deg, deg, km (WGS-84)
EPOCH_UTC = "2016-12-10T00:00:00"
_SPAN = 86400.0  # s
_DT = 10.0  # s
_MIN_ELEVATION = 5.0  # deg


@dataclasses.dataclass(frozen=True)
class EffectSizes(Result):
    """Effect sizes (m, mm/s) and OD errors (m, mm/s); rows named by ``effects``."""

    effects: tuple[str, ...]
    range_m: np.ndarray  # largest |range effect| over the pass, m
    range_rate_mm_s: np.ndarray  # largest |range-rate effect| over the pass, mm/s
    od_position_m: np.ndarray  # |position error| of the fit ignoring the effect, m (NaN: not fitted)
    od_velocity_mm_s: np.ndarray  # |velocity error|, mm/s
    troposphere_m: dict[str, float]  # delay at 5, 10, 30 deg elevation, m
    pass_max_elevation_deg: float
    pass_duration_s: float
    od_passes: int
    od_measurements: int


def _orbit() -> np.ndarray:
    a, inc, raan, u = 6378.137 + 420.0, math.radians(51.64), math.radians(35.0), math.radians(20.0)
    v = math.sqrt(float(_satgnc.EARTH_MU) / a)
    ci, si, co, so = math.cos(inc), math.sin(inc), math.cos(raan), math.sin(raan)
    rot = np.array([[co, -so * ci, so * si], [so, co * ci, -co * si], [0.0, si, ci]])
    return np.concatenate(
        [rot @ [a * math.cos(u), a * math.sin(u), 0.0], rot @ [-v * math.sin(u), v * math.cos(u), 0.0]]
    )


def _stations(eop: Any, epoch: Any) -> dict[str, Any]:
    from .. import frames, od
    from ..observation import EarthFixedStationEphemeris

    name, lat, lon, h = STATION
    gs = frames.GroundStation(lat, lon, h, 0.0, name)
    full = EarthFixedStationEphemeris.from_ground_station(
        gs, frames.IauEarthRotation(epoch, eop, -3600.0, _SPAN + 3600.0)
    )
    no_pm_table = frames.EopTable(
        np.asarray(eop.mjd),
        np.zeros(len(eop.mjd)),
        np.zeros(len(eop.mjd)),
        np.asarray(eop.ut1_utc),
        np.asarray(eop.lod),
        np.asarray(eop.dx),
        np.asarray(eop.dy),
    )
    no_pm = EarthFixedStationEphemeris.from_ground_station(
        gs, frames.IauEarthRotation(epoch, no_pm_table, -3600.0, _SPAN + 3600.0)
    )
    theta0 = od.gmst(epoch.to_iso("UTC", 6))
    gmst = EarthFixedStationEphemeris(lat, lon, h, theta0=theta0, omega=float(_satgnc.EARTH_OMEGA))
    return {"full": full, "no_pm": no_pm, "gmst": gmst}


def _passes(el_deg: np.ndarray) -> list[tuple[int, int]]:
    vis = el_deg >= _MIN_ELEVATION
    out, start = [], None
    for i, v in enumerate(vis):
        if v and start is None:
            start = i
        if not v and start is not None:
            out.append((start, i))
            start = None
    if start is not None:
        out.append((start, len(vis)))
    return out


def effect_sizes(eop: Any = None) -> EffectSizes:
    """Compute the table (see the module docstring). ``eop``: a :class:`satgnc.frames.EopTable`
    covering 2016-12-09..12 (default: :func:`satgnc.frames.default_eop`)."""
    from .. import frames, observation, od, propagation
    from ..time import Epoch

    eop = frames.default_eop() if eop is None else eop
    epoch = Epoch.parse(EPOCH_UTC, "UTC")
    st = _stations(eop, epoch)
    x0 = _orbit()
    j2 = _satgnc.J2Gravity()
    t = np.arange(0.0, _SPAN, _DT)
    xs = propagation.propagate(x0, t, forces=j2, with_stm=False).states

    def pred(kind: str, station: Any, ts: np.ndarray, states: np.ndarray, **kw: Any) -> Any:
        return observation.predict(observation.measurement_model(kind, **kw), station, ts, states)

    el = np.degrees(pred("azimuth_elevation", st["full"], t, xs).value[:, 1])
    passes = _passes(el)
    best = max(passes, key=lambda p: el[p[0] : p[1]].max())
    sl = slice(*best)
    tp, xp = t[sl], xs[sl]

    def ranges(station: Any, **kw: Any) -> tuple[np.ndarray, np.ndarray]:
        r = pred("two_way_range", station, tp, xp, **kw).value
        rr = pred("two_way_range_rate", station, tp, xp, **kw).value
        return r, rr

    r_full, rr_full = ranges(st["full"])
    inst_r, inst_rr = np.empty(len(tp)), np.empty(len(tp))
    for i, (ti, xi) in enumerate(zip(tp, xp)):
        rs, vs, _, _ = st["full"].state(float(ti))
        rho = xi[:3] - np.asarray(rs)
        inst_r[i] = np.linalg.norm(rho)
        inst_rr[i] = rho @ (xi[3:] - np.asarray(vs)) / inst_r[i]
    trop = pred("two_way_range", st["full"], tp, xp, troposphere=True).troposphere
    shap = pred("two_way_range", st["full"], tp, xp, shapiro=True).shapiro
    r_gmst, rr_gmst = ranges(st["gmst"])
    r_nopm, rr_nopm = ranges(st["no_pm"])

    def amax(a: np.ndarray) -> float:
        return float(np.max(np.abs(a)))

    effects = ("light time", "troposphere", "Shapiro", "EOP vs GMST-only", "polar motion")
    range_m = (
        np.array(
            [amax(r_full - inst_r), amax(trop), amax(shap), amax(r_full - r_gmst), amax(r_full - r_nopm)]
        )
        * 1e3
    )
    rr_mm = (
        np.array(
            [
                amax(rr_full - inst_rr),
                amax(np.gradient(trop, tp)),
                amax(np.gradient(shap, tp)),
                amax(rr_full - rr_gmst),
                amax(rr_full - rr_nopm),
            ]
        )
        * 1e6
    )
    p, temp, e = observation.standard_atmosphere(STATION[3], 0.5)
    zd = observation.saastamoinen_zenith_delay(p, temp, e, math.radians(STATION[1]), STATION[3])
    tropo = {f"{d} deg": 1e3 * zd * observation.tropo_mapping(math.radians(d)) for d in (5, 10, 30)}

    # OD: every pass of the day, noise-free data with the effect, fitted without it.
    idx = np.concatenate([np.arange(a, b) for a, b in passes])
    td, xd = t[idx], xs[idx]

    def data(station: Any, **kw: Any) -> Any:
        rng = pred("two_way_range", station, td, xd, **kw).value
        rr = pred("two_way_range_rate", station, td, xd).value
        ae = pred("azimuth_elevation", station, td, xd).value
        n = len(td)
        vals = np.zeros((3 * n, 2))
        vals[0::3, 0], vals[1::3, 0], vals[2::3] = rng, rr, ae
        sig = np.tile([[1e-3, 1.0], [1e-6, 1.0], [1e-4, 1e-4]], (n, 1))
        types = ["two_way_range", "two_way_range_rate", "azimuth_elevation"] * n
        return od.tracking_data(np.repeat(td, 3), types, np.zeros(3 * n, dtype=int), vals, sig, epoch=epoch)

    fm = _satgnc.ForceModel(j2=j2)

    def fit(d: Any, station: Any, **kw: Any) -> tuple[float, float]:
        r = od.batch_estimate(d, [station], x0, epoch=epoch, force_model=fm, max_iterations=50, **kw)
        if r.status != "converged":
            return math.nan, math.nan
        return 1e3 * float(np.linalg.norm(r.state[:3] - x0[:3])), 1e6 * float(
            np.linalg.norm(r.state[3:] - x0[3:])
        )

    d_lt = data(st["full"])
    d_trop = data(st["full"], troposphere=True)
    d_shap = data(st["full"], shapiro=True)
    od_err = [
        fit(d_lt, st["full"], light_time=False),
        fit(d_trop, st["full"]),
        fit(d_shap, st["full"]),
        fit(d_lt, st["gmst"]),
        fit(d_lt, st["no_pm"]),
    ]
    return EffectSizes(
        effects=effects,
        range_m=range_m,
        range_rate_mm_s=rr_mm,
        od_position_m=np.array([e[0] for e in od_err]),
        od_velocity_mm_s=np.array([e[1] for e in od_err]),
        troposphere_m=tropo,
        pass_max_elevation_deg=float(el[sl].max()),
        pass_duration_s=float(tp[-1] - tp[0]),
        od_passes=len(passes),
        od_measurements=3 * len(td),
    )


def format_table(s: EffectSizes) -> str:
    """The Markdown table of docs/od.md "Effect sizes" (numbers rounded as printed there)."""
    lines = [
        f"Pass: highest of the day, {s.pass_max_elevation_deg:.1f} deg maximum elevation, "
        f"{s.pass_duration_s:.0f} s above 5 deg. OD: {s.od_passes} passes, {s.od_measurements} measurements.",
        "",
        "| effect | range (m) | range-rate (mm/s) | OD ignoring it: position (m) | velocity (mm/s) |",
        "|---|---|---|---|---|",
    ]
    for i, name in enumerate(s.effects):
        lines.append(
            f"| {name} | {s.range_m[i]:.3f} | {s.range_rate_mm_s[i]:.3f} | {s.od_position_m[i]:.2f} | "
            f"{s.od_velocity_mm_s[i]:.2f} |"
        )
    lines += ["", "| troposphere at elevation | " + " | ".join(s.troposphere_m) + " |", "|---|---|---|---|"]
    lines.append("| delay (m) | " + " | ".join(f"{v:.3f}" for v in s.troposphere_m.values()) + " |")
    return "\n".join(lines)


def build(ctx: Any) -> str:
    """Report section (satgnc.report convention)."""
    return f"## {TITLE}\n\n" + format_table(effect_sizes()) + "\n"


if __name__ == "__main__":
    import sys

    from .. import frames

    table = frames.load_eop(sys.argv[1]) if len(sys.argv) > 1 else None
    print(format_table(effect_sizes(table)))
