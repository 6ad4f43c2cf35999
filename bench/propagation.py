"""Benchmark: one 2 h LEO arc with J2 and the 6x6 STM, satgnc against scipy and heyoka.py.

Every method is run over a sweep of tolerances; its accuracy (final position and nondimensional STM
error) is measured against a tight reference, and at each accuracy target the cheapest tolerance of
each method that meets it is timed. Ratios are against scipy's solve_ivp(DOP853) with the 42-dim
variational system vectorised in numpy, measured in the same run.

    .venv/bin/python bench/propagation.py [--quick]

heyoka.py (~240 MB with its LLVM) is installed by ``make bench`` (requirements-bench.txt); run directly
without it, its rows are skipped with a note.
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np
import satgnc
from _heyoka import j2_variational_system
from _timing import timeit
from satgnc import _satgnc

MU = satgnc.EARTH_MU
RE = satgnc.EARTH_RADIUS
J2 = satgnc.EARTH_J2
T_ARC = 7200.0
# 400 km, e = 0.001, i = 51.6 deg.
X0 = np.array([6778.137, 0.0, 0.0, 0.0, 4.7302, 6.0354])
TARGETS = (1e-3, 1e-6)  # final position error, km (1 m, 1 mm)


def nondim(phi: np.ndarray) -> np.ndarray:
    d = np.r_[[np.linalg.norm(X0[:3])] * 3, [np.linalg.norm(X0[3:])] * 3]
    return phi * d[None, :] / d[:, None]


# ---------------------------------------------------------------- scipy: numpy-vectorised 42-dim system
_C = np.array([1.0, 1.0, 3.0])
_EYE3 = np.eye(3)


def scipy_rhs(t, y):
    r = y[:3]
    z = r[2]
    r2 = r @ r
    rn = math.sqrt(r2)
    k = MU / (r2 * rn)
    kj = -1.5 * J2 * MU * RE * RE / (r2 * r2 * rn)
    s = 5.0 * z * z / r2
    f = _C - s
    ds = (-2.0 * s / r2) * r
    ds[2] += 10.0 * z / r2
    # G = da/dr: point mass + J2 (same closed form as satgnc's, written with numpy outer products).
    G = np.outer((3.0 * k / r2) * r - (5.0 * kj / r2) * r * f, r) - np.outer(kj * r, ds)
    G[np.diag_indices(3)] += kj * f - k
    out = np.empty(42)
    out[:3] = y[3:6]
    out[3:6] = (kj * f - k) * r
    phi = y[6:].reshape(6, 6)
    d = out[6:].reshape(6, 6)
    d[:3] = phi[3:]
    d[3:] = G @ phi[:3]
    return out


def run_scipy(rtol):
    from scipy.integrate import solve_ivp

    y0 = np.concatenate([X0, np.eye(6).ravel()])
    sol = solve_ivp(scipy_rhs, (0.0, T_ARC), y0, method="DOP853", rtol=rtol, atol=rtol * 1e-3)
    return sol.y[:6, -1], sol.y[6:, -1].reshape(6, 6)


# ---------------------------------------------------------------- heyoka: hand-built 42-dim system
def make_heyoka(tol):
    import heyoka as hy

    sys = j2_variational_system()
    ic = np.concatenate([X0, np.eye(6).ravel()])
    ta = hy.taylor_adaptive(sys, ic, tol=tol, compact_mode=False)

    def run():
        ta.time = 0.0
        ta.state[:] = ic
        ta.propagate_until(T_ARC)
        return ta.state[:6].copy(), ta.state[6:].reshape(6, 6).copy()

    return run


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer tolerances, shorter timing")
    args = ap.parse_args()
    min_time = 0.1 if args.quick else 0.3
    try:
        import heyoka  # noqa: F401

        have_heyoka = True
    except ImportError:
        have_heyoka = False
        print("note: heyoka.py not installed (pip install heyoka): its rows are skipped")

    # Reference: heyoka's Taylor integrator at tol 1e-16 if present, else CVODES Adams at rtol 1e-14
    # (cross-checked against scipy DOP853 at its tightest rtol below).
    if have_heyoka:
        ref_x, ref_phi = make_heyoka(1e-16)()
        ref_name = "heyoka.py Taylor, tol 1e-16"
    else:
        p = _satgnc.CvodesPropagator(satgnc.ForceModel(j2=satgnc.J2Gravity()), rtol=1e-14, atol=1e-15)
        tr = p.propagate(X0, 0.0, [T_ARC])
        ref_x, ref_phi = tr.states[0], tr.stms[0]
        ref_name = "satgnc CVODES Adams, rtol 1e-14"

    def errors(xf, phi):
        return (float(np.linalg.norm(xf[:3] - ref_x[:3])),
                float(np.abs(nondim(phi) - nondim(ref_phi)).max() / np.abs(nondim(ref_phi)).max()))

    model = satgnc.ForceModel(j2=satgnc.J2Gravity())
    tols = [1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14]
    if args.quick:
        tols = [1e-9, 1e-11, 1e-13]
    rows = []  # (method, tol, pos_err, stm_err, seconds, note)

    methods = ["adams", "bdf"] + (["dop853"] if "dop853" in satgnc.available_methods() else [])
    for method in methods:
        for tol in tols:
            if method in ("adams", "bdf"):
                prop = _satgnc.CvodesPropagator(model, method=method, rtol=tol, atol=tol * 1e-2,
                                                max_steps=5_000_000)

                def fn(prop=prop):
                    return prop.propagate(X0, 0.0, [T_ARC])
            else:
                def fn(tol=tol):
                    return _satgnc.propagate_dop853(X0, 0.0, [T_ARC], model, tol, tol * 1e-2, True, 5_000_000)
            tr = fn()
            pe, se = errors(tr.states[0], tr.stms[0])
            rows.append((f"satgnc {method}", tol, pe, se, timeit(fn, min_time), f"{tr.stats['steps']} steps"))
    # Python-API overhead for the default call.
    t_api = timeit(lambda: satgnc.propagate(X0, [0.0, T_ARC], forces=satgnc.J2Gravity()), min_time)

    for tol in tols:
        if tol < 2.3e-14:
            continue
        xf, phi = run_scipy(tol)
        pe, se = errors(xf, phi)
        sec = timeit(lambda tol=tol: run_scipy(tol), min_time, 50, 3)
        rows.append(("scipy DOP853", tol, pe, se, sec, ""))

    heyoka_compile = None
    if have_heyoka:
        for tol in ([1e-9, 1e-12, 1e-15] if not args.quick else [1e-9, 1e-13]):
            t0 = time.perf_counter()
            run = make_heyoka(tol)
            heyoka_compile = time.perf_counter() - t0
            xf, phi = run()
            pe, se = errors(xf, phi)
            sec = timeit(run, min_time)
            rows.append(("heyoka.py taylor", tol, pe, se, sec, f"JIT {heyoka_compile:.2f} s"))

    print(f"\n2 h LEO arc (400 km, i = 51.6 deg) with J2 and the STM; reference: {ref_name}")
    print(f"satgnc.propagate() call incl. Python checks and workspace set-up (adams, rtol 1e-10): "
          f"{t_api * 1e3:.3f} ms\n")
    print(f"{'method':<18}{'tol':>8}{'pos err km':>12}{'STM err':>10}{'ms/arc':>10}  note")
    for m, tol, pe, se, sec, note in rows:
        print(f"{m:<18}{tol:>8.0e}{pe:>12.2e}{se:>10.1e}{sec * 1e3:>10.3f}  {note}")

    print("\nAt equal measured accuracy (cheapest tolerance of each method meeting the target):")
    for target in TARGETS:
        best = {}
        for m, tol, pe, _se, sec, _ in rows:
            if pe <= target and (m not in best or sec < best[m][2]):
                best[m] = (tol, pe, sec)
        base = best.get("scipy DOP853")
        print(f"  final position error <= {target:g} km:")
        for m, (tol, pe, sec) in sorted(best.items(), key=lambda kv: kv[1][2]):
            ratio = f"  scipy/this = {base[2] / sec:6.1f}x" if base else ""
            print(f"    {m:<18} tol {tol:.0e}  err {pe:.1e} km  {sec * 1e3:8.3f} ms{ratio}")
        if "heyoka.py taylor" in best:
            for m in ("satgnc adams", "satgnc dop853"):
                if m in best:
                    print(f"    heyoka/{m} = {best['heyoka.py taylor'][2] / best[m][2]:.2f}")

    # Analytic two-body: satgnc kepler (point mass) if this build has it.
    if "kepler" in satgnc.available_methods():
        fn = lambda: _satgnc.propagate_kepler(X0, 0.0, [T_ARC], MU, True)  # noqa: E731
        ms = timeit(fn, min_time) * 1e3
        print(f"\nsatgnc kepler (analytic, point mass, with STM): {ms:.4f} ms per arc")
    scipy_ms = statistics.median([r[4] for r in rows if r[0] == "scipy DOP853"]) * 1e3
    print(f"\nmedian of scipy runs: {scipy_ms:.1f} ms")


if __name__ == "__main__":
    main()
