"""Two-way light-time range with partials: C++ time per call against a numpy implementation of the
same model (same run, same machine; the ratio is the figure, the absolute times move with the load).

Model (both sides): down leg c tau_d = |r(t - tau_d) - R(t)|, up leg c tau_u = |r_b - R(t_b - tau_u)|
by fixed-point iteration to 1e-14 s, the spacecraft at the bounce by the third-order two-body Taylor
shift, the paper's rotating station, range = c (tau_d + tau_u) / 2 and its analytic gradient with
respect to the state at reception. The C++ loop (``_satgnc._bench_two_way_range``) times predict()
best of 5 blocks; numpy is timed per call with bench/_timing.py. The numpy value and gradient are
checked against the library first (1e-9 km, 1e-9 relative). Goal: <= 2 us per call in C++.
A second C++ row times the same call on a station of the real-data path (WGS-84 in ITRF on
``frames.IauEarthRotation``, the shipped EOP sample; no numpy twin: the ratio row is the first), and
the load average is printed with the numbers.
Usage: python bench/observation.py
"""

from __future__ import annotations

import os
import pathlib

import numpy as np
import satgnc.od as od
from _timing import timeit
from satgnc import _satgnc, frames
from satgnc import observation as obs
from satgnc.time import Epoch

MU = 398600.4418
C = 299792.458


def numpy_two_way_range(x: np.ndarray, t: float, r0: np.ndarray, omega: float) -> tuple[float, np.ndarray]:
    """numpy re-implementation of predict() for the two-way range (value km, gradient (6,))."""
    r, v = x[:3], x[3:]
    r2 = r @ r
    rn = np.sqrt(r2)
    rv = r @ v
    a = -MU / (r2 * rn) * r
    j = -MU / (r2 * rn) * (v - 3.0 * rv / r2 * r)
    eye = np.eye(3)
    A = -MU / (r2 * rn) * (eye - 3.0 / r2 * np.outer(r, r))
    Jr = (3.0 * MU / (r2 * r2 * rn)) * (
        np.outer(v, r) + np.outer(r, v) + rv * eye - 5.0 * rv / r2 * np.outer(r, r)
    )

    def station(tt: float) -> tuple[np.ndarray, np.ndarray]:
        c, s = np.cos(omega * tt), np.sin(omega * tt)
        R = np.array([c * r0[0] - s * r0[1], s * r0[0] + c * r0[1], r0[2]])
        return R, omega * np.array([-R[1], R[0], 0.0])

    R, _ = station(t)
    tau = np.linalg.norm(r - R) / C
    for _ in range(10):
        rb = r - tau * v + 0.5 * tau * tau * a - tau**3 / 6.0 * j
        new = np.linalg.norm(rb - R) / C
        done = abs(new - tau) <= 1e-14
        tau = new
        if done:
            break
    h2, h3 = 0.5 * tau * tau, tau**3 / 6.0
    rb = r - tau * v + h2 * a - h3 * j
    vb = v - tau * a + h2 * j
    Jb_r = np.hstack([eye + h2 * A - h3 * Jr, -tau * eye - h3 * A])  # d r_b / d x at fixed tau
    ud = (rb - R) / np.linalg.norm(rb - R)
    dtd = ud @ Jb_r / (C + ud @ vb)
    Dr = Jb_r - np.outer(vb, dtd)
    tau_u = tau
    for _ in range(10):
        Rt, Vt = station(t - tau - tau_u)
        new = np.linalg.norm(rb - Rt) / C
        done = abs(new - tau_u) <= 1e-14
        tau_u = new
        if done:
            break
    Rt, Vt = station(t - tau - tau_u)
    uu = (rb - Rt) / np.linalg.norm(rb - Rt)
    dtu = (uu @ Dr + (uu @ Vt) * dtd) / (C - uu @ Vt)
    return 0.5 * C * (tau + tau_u), 0.5 * C * (dtd + dtu)


def main() -> None:
    st = od.station_geodetic(40.0, -105.0, 1.6, 2460000.5)
    eph = obs.rotating_station(st)
    up = np.asarray(st.r0) / np.linalg.norm(st.r0)
    axis = np.cross([0.3, -0.2, 1.0], up)
    axis /= np.linalg.norm(axis)
    rhat = up * np.cos(0.1) + np.cross(axis, up) * np.sin(0.1)  # 0.1 rad from the zenith
    x = np.concatenate([7000.0 * rhat, np.sqrt(MU / 7000.0) * np.cross(axis, rhat)])

    model = obs.measurement_model("two_way_range")
    ref = obs.predict(model, eph, 0.5, x)
    val, grad = numpy_two_way_range(x, 0.5, np.asarray(st.r0), float(st.omega))
    err_v = abs(val - ref.value[0])
    err_g = np.max(np.abs(grad - ref.dx[0])) / np.max(np.abs(ref.dx[0]))
    assert err_v < 1e-9 and err_g < 1e-9, (err_v, err_g)

    cpp, _ = _satgnc._bench_two_way_range(eph, x, 200000, 5)
    t_np = timeit(lambda: numpy_two_way_range(x, 0.5, np.asarray(st.r0), float(st.omega)))
    print("two-way light-time range with partials (LEO, rotating station)")
    print(f"  numpy vs C++ agreement: value {err_v:.1e} km, gradient {err_g:.1e} relative")
    print(f"  C++ predict():   {cpp * 1e6:8.3f} us per call (best of 5 x 200000)")
    print(f"  numpy:           {t_np * 1e6:8.1f} us per call (best block)")
    print(f"  ratio numpy / C++: {t_np / cpp:.0f}x;  goal <= 2 us: {'met' if cpp <= 2e-6 else 'NOT met'}")
    eop_file = (
        pathlib.Path(__file__).resolve().parents[1] / "tests" / "data" / "eop" / "finals2000A_2016-12.txt"
    )
    epoch = Epoch.parse("2016-12-10T00:00:00", "UTC")
    rot = frames.IauEarthRotation(epoch, frames.load_eop(eop_file), -3600.0, 3600.0)
    iau = obs.EarthFixedStationEphemeris.from_ground_station(
        frames.GroundStation(40.0, -105.0, 1.6, 0.0, "S"), rot
    )
    r_st = np.asarray(iau.state(0.5)[0], dtype=float)
    up_i = r_st / np.linalg.norm(r_st)
    rh = up_i * np.cos(0.1) + np.cross(axis, up_i) * np.sin(0.1)
    xi = np.concatenate([7000.0 * rh, np.sqrt(MU / 7000.0) * np.cross(axis, rh)])
    cpp_iau, _ = _satgnc._bench_two_way_range(iau, xi, 200000, 5)
    print(f"  C++ predict(), ITRF station on IAU 2006 + EOP: {cpp_iau * 1e6:8.3f} us per call")
    load = " ".join(f"{v:.1f}" for v in os.getloadavg())
    print(f"  load average (1, 5, 15 min): {load} on {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
