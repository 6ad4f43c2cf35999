"""Reproduction of Gao & Luo, "The Newton-Raphson method in orbit determination" (Tables 1-11, Fig. 2).

Everything here is data plus small functions that the report section and the tests share. The
paper's printed numbers come from ``satgnc/data/paper_tables.json``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._satgnc import EARTH_RADIUS
from ..data import paper_tables
from ..od import (
    EARTH_MU,
    EARTH_OMEGA,
    OdStatus,
    box_guesses,
    gmst,
    implied_rotation_rate,
    make_propagator,
    predict,
    six_point_solver,
    station_inertial,
)
from ..od import ellipsoid as _ellipsoid
from ..od import geodetic_to_ecef as _geodetic_to_ecef
from ..od.sweep import run_chunks, split

SIGMA_RANGE = 1e-3  #: km (1 m) assumed for the paper's conditions
SIGMA_RANGE_RATE = 1e-6  #: km/s (1 mm/s)


def tables() -> dict:
    return paper_tables()["od_newton_raphson"]


def truth() -> np.ndarray:
    """Table 1: the true state at t0 (km, km/s)."""
    return np.array(tables()["table1_true_state"], dtype=float)


def station_state_table3() -> np.ndarray:
    """Table 3: the station's printed inertial state at t0."""
    return np.array(tables()["table3_station_state"], dtype=float)


def times() -> np.ndarray:
    return np.array(tables()["table4_observations"]["t_s"], dtype=float)


def station(omega: float = EARTH_OMEGA):
    """Table 3's position rotating about z at ``omega`` (default the Earth's rate)."""
    return station_inertial(station_state_table3()[:3], omega)


def observe(x0=None, st=None, mu: float = EARTH_MU, t=None) -> tuple[np.ndarray, np.ndarray]:
    """Full-precision two-body ranges (km) and range-rates (km/s) of x0 from station st at t."""
    x0 = truth() if x0 is None else np.asarray(x0, float)
    st = station() if st is None else st
    t = times() if t is None else np.asarray(t, float)
    states, _ = make_propagator("kepler", mu).propagate(x0, list(t))
    rho = np.array([predict("range", x, st.state(tk))[0] for x, tk in zip(states, t)])
    rhodot = np.array([predict("range_rate", x, st.state(tk))[0] for x, tk in zip(states, t)])
    return rho, rhodot


# ----------------------------------------------------------------------------- Tables 1-4 checks
def consistency() -> dict:
    """Each inconsistency of Tables 1-4 as a number (see docs/od.md)."""
    tb = tables()
    x = truth()
    r3 = station_state_table3()
    t4 = tb["table4_observations"]
    out: dict = {}
    # Table 3 velocity vs omega x R.
    w = implied_rotation_rate(r3)
    out["omega_implied"] = w
    out["omega_earth"] = EARTH_OMEGA
    out["station_velocity_error_kms"] = float(
        np.linalg.norm(r3[3:] - EARTH_OMEGA * np.array([-r3[1], r3[0], 0.0]))
    )
    # Table 4 vs the two-body prediction of Table 1 from Table 3 (station with the Earth's rate and
    # with the implied rate: the choice does not matter at t = 0).
    rho_e, rr_e = observe(x, station(EARTH_OMEGA))
    rho_w, rr_w = observe(x, station(w))
    rho_p = np.array(t4["range_km"])
    rr_p = np.array(t4["range_rate_km_s"])
    out["range_pred_km"] = rho_e
    out["range_rate_pred_kms"] = rr_e
    out["range_diff_km"] = rho_p - rho_e
    out["range_rate_diff_kms"] = rr_p - rr_e
    out["range_diff_implied_omega_km"] = rho_p - rho_w
    out["range_rate_diff_implied_omega_kms"] = rr_p - rr_w
    # At t = 0 no dynamics are involved: |X1 - R1| straight from Tables 1 and 3.
    out["range_t0_direct_km"] = float(np.linalg.norm(x[:3] - r3[:3]))
    out["range_rate_t0_direct_kms"] = float(
        np.dot(x[:3] - r3[:3], x[3:] - r3[3:]) / np.linalg.norm(x[:3] - r3[:3])
    )
    # Table 3 right ascension vs Table 2 longitude + GMST(1981-03-21 06:00 UTC).
    g = tb["table2_station_geodetic"]
    ra3 = math.degrees(math.atan2(r3[1], r3[0])) % 360.0
    th = math.degrees(gmst(tb["epoch_utc"])) % 360.0
    out["ra_table3_deg"] = ra3
    out["gmst_deg"] = th
    out["ra_from_table2_deg"] = (g["longitude_deg"] + th) % 360.0
    out["ra_diff_deg"] = ((ra3 - out["ra_from_table2_deg"] + 180.0) % 360.0) - 180.0
    out["gmst_needed_deg"] = (ra3 - g["longitude_deg"]) % 360.0
    # Hours of UT1 that would be needed for that GMST on that date.
    out["ut_shift_needed_h"] = (((out["gmst_needed_deg"] - th + 180.0) % 360.0) - 180.0) / (15.0 * 1.0027379)
    # Radius / z against the geodetic position on several ellipsoids.
    rows = []
    for name in ("WGS-84", "IAU-1976", "Krassovsky"):
        e = _geodetic_to_ecef(g["latitude_deg"], g["longitude_deg"], g["height_km"], _ellipsoid(name))
        rows.append(
            {
                "ellipsoid": name,
                "radius_km": float(np.linalg.norm(e)),
                "z_km": float(e[2]),
                "radius_diff_km": float(np.linalg.norm(r3[:3]) - np.linalg.norm(e)),
                "z_diff_km": float(r3[2] - e[2]),
            }
        )
    out["ellipsoids"] = rows
    # The "mirror" 2R - X of eq. (27).
    mirror = 2.0 * r3[:3] - x[:3]
    out["mirror_radius_km"] = float(np.linalg.norm(mirror))
    out["mirror_altitude_km"] = float(np.linalg.norm(mirror) - EARTH_RADIUS)  # km
    return out


# ----------------------------------------------------------------------------- Tables 5-11
@dataclasses.dataclass
class OffsetRun:
    offset_km: float
    status: str
    iterations: int
    x0: np.ndarray
    x1_error_cm: float
    position_error_m: float
    range_residuals_m: np.ndarray  # (iterations+1, 6) predicted - observed, metres
    range_rate_residuals_ms: np.ndarray  # (iterations+1, 6), m/s
    condition_number: float


def _paper_solver(rho, rhodot, method: str = "newton", propagator="kepler", **kw):
    """The six-point Doppler solver of the paper's pass (Table 3 station, Table 4 times; ranges in km,
    range-rates in km/s) with the paper's sigmas (:data:`SIGMA_RANGE`, :data:`SIGMA_RANGE_RATE`)."""
    return six_point_solver(times(), rho, rhodot, station(), "doppler", method, propagator,
                            sigma_range=SIGMA_RANGE, sigma_range_rate=SIGMA_RANGE_RATE, **kw)


def solve_offsets(offsets=None, method: str = "newton", propagator="kepler") -> list[OffsetRun]:
    """Tables 5-11: Doppler conditions from full-precision synthetic data; Newton from x1 + offset."""
    offsets = tables()["table5_initial_x1_offsets_km"] if offsets is None else offsets
    rho, rhodot = observe()
    sv = _paper_solver(rho, rhodot, method, propagator)
    out = []
    for d in offsets:
        g = truth().copy()
        g[0] += d
        r = sv.solve(g)
        out.append(
            OffsetRun(
                float(d),
                r.status.name,
                r.iterations,
                np.asarray(r.x0),
                float((r.x0[0] - truth()[0]) * 1e5),
                float(np.linalg.norm(r.x0[:3] - truth()[:3]) * 1e3),
                np.asarray(r.history_range_residuals) * 1e3,
                np.asarray(r.history_range_rate_residuals) * 1e3,
                r.condition_number,
            )
        )
    return out


def short_arc_run(offset_km: float = 10.0, max_iterations: int = 20):
    """Newton with the paper's short-arc STM of eq. (19) (does not converge)."""
    rho, rhodot = observe()
    prop = make_propagator("kepler")
    from ..od import ShortArcStmPropagator

    sv = _paper_solver(rho, rhodot, "newton", ShortArcStmPropagator(prop), max_iterations=max_iterations)
    g = truth().copy()
    g[0] += offset_km
    return sv.solve(g)


def printed_table4_run(offset_km: float = 10.0, method: str = "newton"):
    """Newton on the printed Table 4 (range and range-rate columns), Table 3 station, guess x1 + 10 km."""
    t4 = tables()["table4_observations"]
    sv = _paper_solver(t4["range_km"], t4["range_rate_km_s"], method, max_iterations=50)
    g = truth().copy()
    g[0] += offset_km
    return sv.solve(g)


def rounding_sensitivity(n: int = 20, seed: int = 1, method: str = "levenberg_marquardt") -> dict:
    """Round-off experiment: full-precision synthetic data rounded to Table 4's digits (0.1 m,
    0.01 m/s), and ``n`` random perturbations within that rounding interval; each solved from the
    truth (LM by default, so the solver does not simply diverge). Returns the distances (km) of the
    solutions from the truth and whether they fit their data."""
    rho, rhodot = observe()
    rng = np.random.default_rng(seed)

    def one(pr, prr):
        sv = _paper_solver(pr, prr, method, max_iterations=300)
        r = sv.solve(truth())
        return r, float(np.linalg.norm(np.asarray(r.x0)[:3] - truth()[:3]))

    errs, fits = [], []
    for _ in range(n):
        r, e = one(rho + rng.uniform(-0.5e-4, 0.5e-4, 6), rhodot + rng.uniform(-0.5e-5, 0.5e-5, 6))
        errs.append(e)
        fits.append(bool(r.fits))
    e = np.array(errs)
    rr, re = one(np.round(rho, 4), np.round(rhodot, 5))
    return {
        "n": n,
        "fits": int(np.sum(fits)),
        "median_km": float(np.median(e)),
        "max_km": float(e.max()),
        "errors_km": e,
        "rounded_status": rr.status.name,
        "rounded_error_km": re,
        "rounded_fits": bool(rr.fits),
        "condition_number": rr.condition_number,
    }


def residual_shapes(runs=None) -> list[dict]:
    """The paper's residual rows (Tables 6-10) against satgnc's initial residual row of the same kind:
    best scale factor k (paper ~ k * initial) and the largest deviation from that proportionality,
    relative to the row's largest entry."""
    runs = solve_offsets() if runs is None else runs
    tb = tables()
    out = []
    for key, kind in (
        ("table6_range_rate_residuals_after_iter2", "rr"),
        ("table7_range_residuals_after_iter3", "r"),
        ("table8_range_rate_residuals_after_iter3", "rr"),
        ("table9_range_residuals_after_iter4", "r"),
        ("table10_range_rate_residuals_after_iter4", "rr"),
    ):
        for r in runs:
            k = f"{r.offset_km:.0f}"
            paper_row = np.array(tb[key][k])
            init = r.range_residuals_m[0] if kind == "r" else r.range_rate_residuals_ms[0]
            scale = float(np.dot(paper_row, init) / np.dot(init, init))
            dev = float(np.max(np.abs(paper_row - scale * init)) / np.max(np.abs(paper_row)))
            out.append({"table": key, "offset": k, "scale": scale, "rel_dev": dev})
    return out


# ----------------------------------------------------------------------------- Fig. 2 maps
def _map_chunk(args):
    """Worker: solve the six-point Doppler problem from each guess (picklable, top level)."""
    spec, guesses = args
    from ..od import six_point_solver as _sps
    from ..od import station_inertial as _si

    st = _si(spec["r0"], spec["omega"])
    sv = _sps(
        spec["t"],
        spec["rho"],
        spec["rhodot"],
        st,
        "doppler",
        spec["method"],
        "kepler",
        max_iterations=spec["max_iterations"],
    )
    out = np.zeros((len(guesses), 10))
    for i, g in enumerate(guesses):
        r = sv.solve(g)
        out[i, 0] = int(r.status.value)
        out[i, 1] = 1.0 if (r.status == OdStatus.converged and r.fits) else 0.0
        out[i, 2] = r.iterations
        out[i, 3] = r.max_abs_normalized if np.isfinite(r.max_abs_normalized) else np.inf
        out[i, 4:] = r.x0
    return out


def map_spec(method: str, max_iterations: int | None = None) -> dict:
    rho, rhodot = observe()
    st = station()
    return {
        "r0": np.asarray(st.r0),
        "omega": st.omega,
        "t": times(),
        "rho": rho,
        "rhodot": rhodot,
        "method": method,
        "max_iterations": max_iterations or (50 if method == "newton" else 200),
    }


def run_map(
    guesses: np.ndarray,
    method: str,
    executor: str = "process",
    chunks: int = 8,
    progress: bool = False,
    client=None,
) -> np.ndarray:
    """(n, 10) table per guess: status, fits, iterations, max|normalized residual|, final x0."""
    spec = map_spec(method)
    parts = split(np.asarray(guesses), chunks)
    res = run_chunks(
        _map_chunk,
        [(spec, p) for p in parts],
        executor=executor,
        progress=progress,
        label=f"map {method}",
        client=client,
    )
    return np.vstack(res)


def classify(table: np.ndarray, tol_km: float = 1.0) -> np.ndarray:
    """Per guess: 'truth' (fits, within tol_km of Table 1), 'other root' (fits elsewhere), 'no fit'
    (converged to a non-fitting stationary point or stalled), 'diverged' (left the physical region
    or failed)."""
    out = []
    for row in table:
        status = OdStatus(int(row[0]))
        if row[1] > 0:
            out.append("truth" if np.linalg.norm(row[4:7] - truth()[:3]) < tol_km else "other root")
        elif status in (
            OdStatus.diverged,
            OdStatus.propagation_failed,
            OdStatus.degenerate_geometry,
            OdStatus.singular,
        ):
            out.append("diverged")
        else:
            out.append("no fit")
    return np.array(out)


def box_half_width() -> np.ndarray:
    return np.array([200.0, 200.0, 200.0, 0.2, 0.2, 0.2])


def map_box_guesses(n: int, seed: int = 2024) -> np.ndarray:
    return box_guesses(truth(), box_half_width(), n, seed)


def octant_guesses(n_per: int = 2, seed: int = 7) -> tuple[np.ndarray, np.ndarray]:
    """Guesses X* = R + s * |X - R| * U(0.5, 1.5) per component, for every sign pattern s of the
    six components (64 octant pairs) relative to the station; returns guesses and their relation to
    the truth's octant: 0 same (claim: truth), 6 opposite (claim: mirror), else the number of flips."""
    rng = np.random.default_rng(seed)
    x = truth()
    r = station_state_table3()
    d = np.abs(x - r)
    s_true = np.sign(x - r)
    gs, flips = [], []
    for code in range(64):
        s = np.array([1.0 if (code >> k) & 1 else -1.0 for k in range(6)])
        for _ in range(n_per):
            gs.append(r + s * d * rng.uniform(0.5, 1.5, 6))
            flips.append(int(np.sum(s != s_true)))
    return np.array(gs), np.array(flips)
