"""``satgnc od``: orbit determination from a CSV or CCSDS TDM (KVN) observation file.

Examples::

    satgnc od simulate --out obs.csv                 # the paper's pass, synthetic, with noise
    satgnc od solve obs.csv --station-inertial 5463.14996,2139.12637,2493.7785 \
        --guess 5846.89,1265.616,3411.496,0.3146,6.9401,-3.1125 --plots out/
    satgnc od solve obs.tdm --station DSS:23.1667,113.25,0.15 --epoch 1981-03-21T06:00:00 --guess ...
"""

from __future__ import annotations

import pathlib
import sys

import numpy as np


def _floats(text: str, n: int | None, name: str) -> list[float]:
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise ValueError(f"{name}: expected comma-separated numbers, got {text!r}") from None
    if n is not None and len(vals) != n:
        raise ValueError(f"{name}: expected {n} numbers, got {len(vals)}")
    return vals


def _stations(args, epoch, names=None):
    from . import station_geodetic, station_inertial

    out, labels = [], []
    for spec in args.station or []:
        label, _, coords = spec.rpartition(":")
        lat, lon, h = _floats(coords, 3, "--station")
        out.append(station_geodetic(lat, lon, h, epoch, args.ut1_utc, args.ellipsoid))
        labels.append(label or f"station{len(out)}")
    for spec in args.station_inertial or []:
        label, _, coords = spec.rpartition(":")
        v = _floats(coords, None, "--station-inertial")
        if len(v) not in (3, 4):
            raise ValueError("--station-inertial: expected x,y,z[,omega]")
        out.append(station_inertial(v[:3], v[3] if len(v) == 4 else 7.292115e-5))
        labels.append(label or f"station{len(out)}")
    if not out:
        raise ValueError("--station/--station-inertial: give at least one station")
    if names:  # TDM participants: order the stations by the file's names when labels match
        if all(n in labels for n in names):
            out = [out[labels.index(n)] for n in names]
        elif len(names) > len(out):
            raise ValueError(f"--station: the file has stations {names}, only {len(out)} given")
    return out


def plot_residuals(result, observations, outdir) -> list[pathlib.Path]:
    """Residuals per observation per iteration (range in m, range-rate in m/s): the paper's Figs. 3-5."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    outdir = pathlib.Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    hist = np.asarray(result.history_residuals)
    names = observations.type_names()
    paths = []
    for kind, unit in (("range", "m"), ("range_rate", "m/s")):
        sel = np.array([n == kind for n in names])
        if not sel.any():
            continue
        fig, ax = plt.subplots(figsize=(7, 4))
        for k in range(hist.shape[0]):
            ax.plot(observations.t[sel], hist[k, sel] * 1e3, "o-", ms=3, label=f"iteration {k}")
        ax.set(xlabel="t (s)", ylabel=f"{kind} residual ({unit})", title=f"{kind} residuals per iteration")
        ax.set_yscale("symlog", linthresh=1e-3)
        ax.legend(fontsize=7)
        fig.subplots_adjust(left=0.15, bottom=0.12)
        path = outdir / f"residuals_{kind}.png"
        fig.savefig(path, dpi=100)
        plt.close(fig)
        paths.append(path)
    return paths


def summary(result, observations) -> str:
    x = np.asarray(result.x0)
    cov = np.asarray(result.covariance)
    sig = np.sqrt(np.abs(np.diag(cov)))
    lines = [
        f"status      : {result.status.name} ({result.message})",
        f"iterations  : {result.iterations}  (propagations {result.evaluations})",
        f"observations: {len(observations)}",
        "state at t=0: " + " ".join(f"{v:.6f}" for v in x) + "  (km, km/s)",
        "formal sigma: " + " ".join(f"{v:.3e}" for v in sig),
        f"fits        : {result.fits}  (max |residual|/sigma = {result.max_abs_normalized:.3g})",
        f"rank        : {result.rank}  condition number {result.condition_number:.3e}",
    ]
    names = observations.type_names()
    res = np.asarray(result.residuals)
    for kind, scale, unit in (("range", 1e3, "m"), ("range_rate", 1e3, "m/s")):
        sel = np.array([n == kind for n in names])
        if sel.any():
            lines.append(f"rms {kind:10s}: {np.sqrt(np.mean(res[sel] ** 2)) * scale:.4g} {unit}")
    return "\n".join(lines)


def _load(args):
    from . import read_csv
    from .tdm import read_tdm

    path = pathlib.Path(args.observations)
    if path.suffix.lower() in (".tdm", ".kvn", ".txt"):
        obs, names, epoch = read_tdm(path, args.sigma_range, args.sigma_range_rate, args.epoch)
        return obs, names, epoch
    obs = read_csv(path)
    return obs, None, args.epoch


def _solve(args) -> int:
    from . import solve

    obs, names, epoch = _load(args)
    if epoch is None and args.station:
        raise ValueError("--epoch: geodetic stations need the UTC epoch of t = 0")
    st = _stations(args, epoch, names)
    guess = _floats(args.guess, 6, "--guess")
    r = solve(
        obs, st, guess, method=args.method, propagator=args.propagator, max_iterations=args.max_iterations
    )
    print(summary(r, obs))
    if args.plots:
        for p in plot_residuals(r, obs, args.plots):
            print(f"plot        : {p}")
    return 0 if r.status.name == "converged" else 1


def _simulate(args) -> int:
    import datetime as dt

    from . import paper, simulate
    from .tdm import write_tdm

    x0 = paper.truth() if args.state is None else np.array(_floats(args.state, 6, "--state"))
    st = paper.station()
    t = np.arange(0.0, args.duration + 1e-9, args.step)
    obs = simulate(
        x0,
        st,
        t,
        sigma_range=args.sigma_range,
        sigma_range_rate=args.sigma_range_rate,
        seed=None if args.no_noise else args.seed,
    )
    out = pathlib.Path(args.out)
    if out.suffix.lower() == ".tdm":
        write_tdm(out, obs, dt.datetime(1981, 3, 21, 6, 0, 0), ["STATION"])
    else:
        with out.open("w") as f:
            f.write("t,type,value,sigma,station\n")
            for t_, k, v, s, i in zip(obs.t, obs.type_names(), obs.value, obs.sigma, obs.station):
                f.write(f"{t_:.6f},{k},{v:.15e},{s:.6e},{i}\n")
    print(f"wrote {len(obs)} observations to {out}")
    return 0


def register(subparsers) -> None:
    p = subparsers.add_parser("od", help="orbit determination from range / range-rate observations")
    sub = p.add_subparsers(dest="od_command")
    s = sub.add_parser("solve", help="estimate the state at t = 0 from a CSV or TDM file")
    s.add_argument("observations", help="CSV (t,type,value,sigma[,station]) or CCSDS TDM KVN (.tdm)")
    s.add_argument("--guess", required=True, help="x,y,z,vx,vy,vz at t = 0 (km, km/s)")
    s.add_argument("--station", action="append", help="[NAME:]lat_deg,lon_deg,height_km (geodetic)")
    s.add_argument("--station-inertial", action="append", help="[NAME:]x,y,z[,omega] inertial at t = 0 (km)")
    s.add_argument("--epoch", help="UTC epoch of t = 0 (ISO); TDM default: first observation")
    s.add_argument("--ut1-utc", type=float, default=0.0, help="UT1 - UTC, s")
    s.add_argument("--ellipsoid", default="WGS-84")
    s.add_argument(
        "--method",
        default="levenberg_marquardt",
        choices=["levenberg_marquardt", "gauss_newton", "newton", "lm", "gn"],
    )
    s.add_argument("--propagator", default="kepler", choices=["kepler", "cvodes"])
    s.add_argument("--max-iterations", type=int, default=200)
    s.add_argument("--sigma-range", type=float, default=1e-3, help="TDM range sigma, km")
    s.add_argument("--sigma-range-rate", type=float, default=1e-6, help="TDM range-rate sigma, km/s")
    s.add_argument("--plots", help="directory for residual plots")
    s.set_defaults(func=_solve)
    m = sub.add_parser("simulate", help="write synthetic observations of the paper's pass (CSV or .tdm)")
    m.add_argument("--out", required=True)
    m.add_argument("--state", help="x,y,z,vx,vy,vz at t = 0 (default: the paper's Table 1)")
    m.add_argument("--duration", type=float, default=300.0)
    m.add_argument("--step", type=float, default=10.0)
    m.add_argument("--sigma-range", type=float, default=1e-3)
    m.add_argument("--sigma-range-rate", type=float, default=1e-6)
    m.add_argument("--seed", type=int, default=0)
    m.add_argument("--no-noise", action="store_true")
    m.set_defaults(func=_simulate)


if __name__ == "__main__":  # pragma: no cover
    from ..cli import main

    sys.exit(main(["od", *sys.argv[1:]]))
