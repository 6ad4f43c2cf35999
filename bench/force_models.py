"""Precise force models (issue 14): the effect of each force on a LEO and a GEO day (km), and the cost
of one DOP853 day with the STM per model. C++ per-evaluation costs: bench/cpp/bench_force_models.cpp.

Effect of a force = |r_with - r_without| after 24 h, both arcs from the same state with DOP853 at
rtol 1e-12 (the integration error, < 1e-6 km, is far below every number printed). The reference model
is the point mass; each line adds one term alone, except "EGM2008 20x20 vs J2": the full field against
the paper's J2."""

from __future__ import annotations

import sys
import time
from functools import partial

import numpy as np
import satgnc
from _timing import best_per_call
from satgnc.dynamics import (
    GravityField,
    SolarRadiationPressure,
    ThirdBodies,
    UniformRotation,
    egm2008,
    force_model,
)

EPOCH = (2460676.5, 0.0)  # 2025-01-01T00:00 TT
MU = egm2008(2).mu


def _models():
    rot = UniformRotation(0.0, satgnc.EARTH_OMEGA)
    f20 = GravityField(egm2008(20), 20, rotation=rot)
    srp = SolarRadiationPressure(area=1.0, mass=100.0)
    return {
        "point mass": force_model(mu=MU),
        "J2 (paper)": satgnc.ForceModel(mu=MU, j2=satgnc.J2Gravity(mu=MU)),
        "EGM2008 20x20": force_model(gravity=f20),
        "Sun + Moon": force_model(mu=MU, third_body=ThirdBodies(), epoch_jd=EPOCH),
        "SRP (A/m 0.01 m^2/kg, Cr 1.3, conical)": force_model(mu=MU, srp=srp, epoch_jd=EPOCH),
        "all (20x20 + Sun + Moon + SRP)": force_model(
            gravity=f20, third_body=ThirdBodies(), srp=srp, epoch_jd=EPOCH
        ),
    }


def _final(x0, fm, with_stm=False):
    tr = satgnc.propagate(x0, [0.0, 86400.0], forces=fm, method="dop853", rtol=1e-12, atol=1e-14,
                          with_stm=with_stm)
    return np.asarray(tr.states)[-1]


def main() -> int:
    orbits = {
        "LEO 400 km 51.6 deg": satgnc.elements_to_state(6778.0, 0.001, 51.6, 30.0, 40.0, 0.0, mu=MU),
        "GEO": satgnc.elements_to_state(42164.0, 0.0002, 0.05, 0.0, 0.0, 0.0, mu=MU),
    }
    models = _models()
    print("effect of each force after 24 h (km), against the point mass (J2 row: the field against J2)")
    print(f"{'force':42s}" + "".join(f"{k:>22s}" for k in orbits))
    ref = {k: _final(x, models["point mass"]) for k, x in orbits.items()}
    j2 = {k: _final(x, models["J2 (paper)"]) for k, x in orbits.items()}
    for name, fm in models.items():
        if name == "point mass":
            continue
        row = []
        for k, x in orbits.items():
            row.append(np.linalg.norm(_final(x, fm)[:3] - ref[k][:3]))
        print(f"{name:42s}" + "".join(f"{v:22.4f}" for v in row))
    row = [np.linalg.norm(_final(x, models["EGM2008 20x20"])[:3] - j2[k][:3]) for k, x in orbits.items()]
    print(f"{'EGM2008 20x20 vs J2':42s}" + "".join(f"{v:22.4f}" for v in row))
    print("\ncost of one LEO day, DOP853 rtol 1e-12 with the STM (best of 3, wall s; machine shared)")
    for name in ("point mass", "J2 (paper)", "EGM2008 20x20", "Sun + Moon", "all (20x20 + Sun + Moon + SRP)"):
        best = best_per_call(partial(_final, orbits["LEO 400 km 51.6 deg"], models[name], with_stm=True))
        print(f"{name:42s}{best:10.4f}")
    _nrlmsise00_rows(orbits["LEO 400 km 51.6 deg"])
    return 0


def _nrlmsise00_rows(x0) -> None:
    """NRLMSISE-00 against Harris-Priester: one density evaluation (Python call, best of 3 x 20000
    calls, the same call overhead in both) and a LEO day of drag (A/m 0.01 m^2/kg, Cd 2.2) with each,
    all else equal (point mass + J2 about ITRF z is not needed: drag alone on the point mass)."""
    from satgnc.dynamics import AtmosphereDrag, HarrisPriester, Nrlmsise00, SpaceWeather

    rot = UniformRotation(0.0, satgnc.EARTH_OMEGA)
    atmos = {
        "Harris-Priester (n=2)": HarrisPriester(),
        "NRLMSISE-00 (F10.7 150, Ap 4)": Nrlmsise00(epoch_jd1=EPOCH[0], epoch_jd2=EPOCH[1],
                                                    space_weather=SpaceWeather()),
    }
    print("\nNRLMSISE-00 vs Harris-Priester")
    r = np.array([6778.0, 100.0, 200.0])
    sun = np.array([0.3, 0.9, 0.1])
    for name, a in atmos.items():
        best = best_per_call(partial(a.density, r, sun, 0.0), 20000)
        best_g = best_per_call(partial(a.density_gradient, r, sun, 0.0), 2000)
        print(f"{name:42s} density {best * 1e6:8.2f} us/call, with gradient {best_g * 1e6:8.2f} us/call "
              f"(Python call included)")
    finals = {}
    for name, a in atmos.items():
        drag = AtmosphereDrag(atmosphere=a, earth_rotation=rot, cd=2.2, area=1.0, mass=100.0)
        fm = force_model(mu=MU, atmosphere_drag=drag, epoch_jd=EPOCH)
        t0 = time.perf_counter()
        finals[name] = _final(x0, fm)
        print(f"{name:42s} LEO day with drag: {time.perf_counter() - t0:8.3f} s wall")
    names = list(finals)
    ref = _final(x0, force_model(mu=MU))
    for name in names:
        print(f"{name:42s} drag effect after 24 h: {np.linalg.norm(finals[name][:3] - ref[:3]):10.4f} km")
    d = np.linalg.norm(finals[names[0]][:3] - finals[names[1]][:3])
    print(f"{'NRLMSISE-00 vs Harris-Priester after 24 h':42s} {d:10.4f} km")


if __name__ == "__main__":
    sys.exit(main())
