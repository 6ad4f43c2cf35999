"""Benchmark: accuracy and cost of each method over one LEO day, to choose satgnc.propagate's defaults.

Two problems, each with the 6x6 STM (satgnc.propagate's default) and 25 hourly outputs:
- two-body: error against the analytic Kepler solution (satgnc kepler, universal variables);
- J2: error against a tight DOP853 run (rtol 1e-13, atol 1e-15), itself checked against CVODES
  Adams at rtol 1e-13 (their difference is printed: it bounds the reference's own error).

Every method (CVODES Adams, CVODES BDF, DOP853) runs over a sweep of rtol with atol = rtol / 100
(the ratio of the old default 1e-10 / 1e-12). Error = the largest position error over the 25 outputs
(km); cost = the fastest block's mean time of one call of the compiled propagator (the workspace
reused for CVODES), best of 5 blocks. Prints a Markdown table (docs/propagation.md, "Defaults") and
the cheapest setting of each method that meets 1 mm per day on both problems.

    .venv/bin/python bench/propagation_defaults.py [--quick]
"""

from __future__ import annotations

import argparse
import os
import platform

import numpy as np
import satgnc
from _timing import timeit
from satgnc import _satgnc
from satgnc.propagation import DEFAULT_ATOL, DEFAULT_RTOL

DEFAULT_METHOD = "dop853"

MU = satgnc.EARTH_MU
DAY = 86400.0
TIMES = [3600.0 * k for k in range(25)]
# LEO: 400 km altitude, e = 0.001, i = 51.6 deg (the bench/propagation.py orbit).
X0 = np.array([6778.137, 0.0, 0.0, 0.0, 4.7302, 6.0354])
TARGET = 1e-6  # km: 1 mm per day


def run(method: str, model, rtol: float, atol: float, stm: bool = True):
    if method == "dop853":
        def fn():
            return _satgnc.propagate_dop853(X0, 0.0, TIMES, model, rtol, atol, stm, 10_000_000)
    else:
        prop = _satgnc.CvodesPropagator(model, method=method, rtol=rtol, atol=atol, max_steps=10_000_000,
                                        with_stm=stm)

        def fn():
            return prop.propagate(X0, 0.0, TIMES)
    return fn


def max_pos_err(states: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.linalg.norm(states[:, :3] - ref[:, :3], axis=1)))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer tolerances, shorter timing")
    args = ap.parse_args()
    min_time = 0.1 if args.quick else 0.3
    two_body = satgnc.ForceModel()
    j2 = satgnc.ForceModel(j2=satgnc.J2Gravity())
    ref_2b = _satgnc.propagate_kepler(X0, 0.0, TIMES, MU, True).states
    ref_j2 = run("dop853", j2, 1e-13, 1e-15)().states
    check_j2 = run("adams", j2, 1e-13, 1e-15)().states
    ref_gap = max_pos_err(check_j2, ref_j2)

    rtols = [1e-8, 1e-9, 1e-10, 3e-11, 1e-11, 3e-12, 1e-12, 1e-13]
    if args.quick:
        rtols = [1e-9, 1e-10, 3e-11, 1e-11, 3e-12, 1e-12]
    ref_err_2b = max_pos_err(run("dop853", two_body, 1e-13, 1e-15)().states, ref_2b)
    rows = []  # method, rtol, errors (2b, J2, 2b no STM, J2 no STM), ms (2b, J2), steps J2
    for method in ("adams", "bdf", "dop853"):
        for rtol in rtols:
            if method == "bdf" and rtol < 1e-11:
                continue  # 10-20x the steps of Adams; it never gets near 1 mm (see the rows above)
            errs, secs, steps = [], [], 0
            for model, ref in ((two_body, ref_2b), (j2, ref_j2)):
                fn = run(method, model, rtol, rtol / 100)
                tr = fn()
                errs.append(max_pos_err(tr.states, ref))
                secs.append(timeit(fn, min_time))
                steps = tr.stats["steps"]
            for model, ref in ((two_body, ref_2b), (j2, ref_j2)):
                errs.append(max_pos_err(run(method, model, rtol, rtol / 100, False)().states, ref))
            rows.append((method, rtol, errs, secs, steps))

    load = os.getloadavg()[0]
    print("\nOne LEO day (400 km, e = 0.001, i = 51.6 deg), 25 hourly outputs; atol = rtol / 100; error = "
          "the largest position error over the outputs, km.")
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores shared with other jobs, load average "
          f"{load:.1f} at the end of the run; times: one call with the STM, fastest of 5 blocks.")
    print(f"References: two-body = analytic Kepler; J2 = DOP853 rtol 1e-13 (its two-body error: "
          f"{ref_err_2b:.1e} km; CVODES Adams at rtol 1e-13 differs from it by {ref_gap:.1e} km).\n")
    print("| method | rtol | two-body | J2 | two-body, no STM | J2, no STM | ms two-body | ms J2 | "
          "J2 steps |")
    print("|---|---|---|---|---|---|---|---|---|")
    for m, rtol, e, t, st in rows:
        ok = " **ok**" if max(e) <= TARGET else ""
        print(f"| {m} | {rtol:.0e} | {e[0]:.1e} | {e[1]:.1e} | {e[2]:.1e} | {e[3]:.1e}{ok} | "
              f"{t[0] * 1e3:.2f} | {t[1] * 1e3:.2f} | {st} |")
    print("\n**ok**: <= 1 mm per day in all four columns. Cheapest setting of each method that is ok "
          "(cost = two-body + J2 with the STM):")
    best = {}
    for m, rtol, e, t, _ in rows:
        if max(e) <= TARGET and (m not in best or sum(t) < best[m][2]):
            best[m] = (rtol, max(e), sum(t))
    fastest = min(v[2] for v in best.values()) if best else float("nan")
    for m, (rtol, err, cost) in sorted(best.items(), key=lambda kv: kv[1][2]):
        print(f"- {m}: rtol {rtol:.0e}, largest error {err:.1e} km, {cost * 1e3:.2f} ms "
              f"({cost / fastest:.1f}x the cheapest)")
    for m in ("adams", "bdf", "dop853"):
        if m not in best:
            print(f"- {m}: no tolerance in the sweep meets 1 mm per day")

    # The chosen default on other LEO orbits (satgnc.propagate with nothing but the state and times),
    # beside the cheapest tolerance that is ok on the orbit above (1e-11): it is not ok on all of them.
    print(f"\nDOP853 (satgnc.propagate's method {DEFAULT_METHOD!r}) on LEO orbits at rtol 1e-11 and at the "
          f"default rtol {DEFAULT_RTOL:g} (atol = rtol / 100), largest position error over one day, km:\n")
    print("| a (km) | e | i (deg) | rtol | two-body | two-body, no STM | J2 | J2, no STM |")
    print("|---|---|---|---|---|---|---|---|")
    worst = {1e-11: 0.0, DEFAULT_RTOL: 0.0}
    for a, e, inc in ((6578.137, 0.001, 28.5), (6678.137, 0.0, 98.0), (6778.137, 0.001, 51.6),
                      (6978.0, 0.01, 51.6), (7178.0, 0.02, 98.7)):
        x = satgnc.elements_to_state(a, e, inc, 10.0, 20.0, 30.0)
        kep = _satgnc.propagate_kepler(x, 0.0, TIMES, MU, False).states
        tight = satgnc.propagate(x, TIMES, forces=satgnc.J2Gravity(), rtol=1e-13, atol=1e-15,
                                 with_stm=False).states
        for rtol in (1e-11, DEFAULT_RTOL):
            atol = DEFAULT_ATOL if rtol == DEFAULT_RTOL else rtol / 100
            errs = []
            for forces, ref in ((None, kep), (satgnc.J2Gravity(), tight)):
                for stm in (True, False):
                    tr = satgnc.propagate(x, TIMES, forces=forces, with_stm=stm, rtol=rtol, atol=atol)
                    errs.append(max_pos_err(tr.states, ref))
            worst[rtol] = max(worst[rtol], *errs)
            cells = " | ".join(f"{v:.1e}" for v in errs)
            print(f"| {a:.1f} | {e:g} | {inc:g} | {rtol:.0e} | {cells} |")
    for rtol, w in worst.items():
        print(f"- rtol {rtol:.0e}: worst {w:.1e} km ({'meets' if w <= TARGET else 'misses'} 1 mm per day)")

if __name__ == "__main__":
    main()
