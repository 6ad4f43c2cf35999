"""JPL DE ephemeris (issue 14 item 2): one evaluation of DE421's geocentric Moon and Sun, satgnc's SPK
reader against jplephem on the same file (skyfield-data's de421.bsp), in one run.

Rows: a batch of 10000 seeded epochs evaluated in one call (satgnc: a C++ loop; jplephem: its numpy
vectorized Chebyshev), per evaluation in ns; and one epoch per Python call (both pay the interpreter).
The geocentric Moon is EMB->Moon - EMB->Earth (2 segments), the Sun SSB->Sun - SSB->EMB - EMB->Earth
(3 segments), chained the same way on both sides. Wall time, best block (bench/_timing.py); the
machine load is printed with the numbers."""

from __future__ import annotations

import os
import pathlib
import sys

import numpy as np
import skyfield_data
from _timing import timeit
from jplephem.spk import SPK
from satgnc.dynamics import load_spk

DE421 = pathlib.Path(skyfield_data.__file__).resolve().parent / "data" / "de421.bsp"
T0 = 2451545.0


def main() -> int:
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    de = load_spk(DE421)
    k = SPK.open(str(DE421))
    rng = np.random.default_rng(1)
    days = rng.integers(-36000, 18000, 10000) + rng.integers(0, 1024, 10000) / 1024.0
    et = days * 86400.0
    emb_moon, emb_earth, ssb_sun, ssb_emb = k[3, 301], k[3, 399], k[0, 10], k[0, 3]

    def jm_moon(d):
        return emb_moon.compute(T0, d) - emb_earth.compute(T0, d)

    def jm_sun(d):
        return ssb_sun.compute(T0, d) - ssb_emb.compute(T0, d) - emb_earth.compute(T0, d)

    # Same numbers first (1e-9 km for the Moon, 1e-7 km for the Sun: tests/python/test_ephemeris_spk.py).
    assert np.abs(de.positions(301, 399, et[:100]) - jm_moon(days[:100]).T).max() < 1e-9
    n = len(et)
    print(f"{'one evaluation, ns':44s}{'satgnc':>10s}{'jplephem':>10s}{'ratio':>8s}")
    for name, target, ref in (("Moon from Earth", 301, jm_moon), ("Sun from Earth", 10, jm_sun)):
        ours = timeit(lambda t=target: de.positions(t, 399, et)) / n * 1e9
        theirs = timeit(lambda r=ref: r(days)) / n * 1e9
        print(f"{name + ', batch of 10000':44s}{ours:10.1f}{theirs:10.1f}{theirs / ours:8.1f}")
        ours1 = timeit(lambda t=target: de.position(t, 399, et[0])) * 1e9
        theirs1 = timeit(lambda r=ref: r(days[0])) * 1e9
        print(f"{name + ', one Python call':44s}{ours1:10.1f}{theirs1:10.1f}{theirs1 / ours1:8.1f}")
    k.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
