"""``satgnc od``: orbit determination from a CSV or CCSDS TDM (KVN) observation file.

Examples::

    satgnc od simulate --out obs.csv                 # the paper's pass, synthetic, with noise
    satgnc od solve obs.csv --station-inertial 5463.14996,2139.12637,2493.7785 \
        --guess 5846.89,1265.616,3411.496,0.3146,6.9401,-3.1125 --plots out/
    satgnc od solve obs.tdm --station DSS:23.1667,113.25,0.15 --epoch 1981-03-21T06:00:00 --guess ...

Errors (bad option, bad file, bad data) print one line ``satgnc: error: ...`` and exit with code 2;
``satgnc od solve`` exits with 1 when the solve does not converge (its status is printed).
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
        raise ValueError(f"{name}: expected {n} comma-separated numbers, got {len(vals)} in {text!r}")
    if not all(np.isfinite(vals)):
        raise ValueError(f"{name}: numbers must be finite, got {text!r}")
    return vals


def _stations(args, epoch, names=None):
    """Stations from --station / --station-inertial, in the order of the file's station names when
    the file has names (TDM PARTICIPANT_1): labelled options must then match those names."""
    from . import EARTH_OMEGA, station_geodetic, station_inertial

    out, labels = [], []
    for spec in args.station or []:
        label, _, coords = spec.rpartition(":")
        lat, lon, h = _floats(coords, 3, "--station")
        out.append(station_geodetic(lat, lon, h, epoch, args.ut1_utc, args.ellipsoid))
        labels.append(label)
    for spec in args.station_inertial or []:
        label, _, coords = spec.rpartition(":")
        v = _floats(coords, None, "--station-inertial")
        if len(v) not in (3, 4):
            raise ValueError(f"--station-inertial: expected x,y,z[,omega] (km, rad/s), got {coords!r}")
        r = float(np.linalg.norm(v[:3]))
        if not 6340.0 <= r <= 6400.0:  # a ground station: the Earth's radius is 6357-6378 km
            raise ValueError(f"--station-inertial: |r| = {r:.6g} km is not on the Earth's surface "
                             f"(6340-6400 km; hint: x,y,z in km) in {spec!r}")
        out.append(station_inertial(v[:3], v[3] if len(v) == 4 else EARTH_OMEGA))
        labels.append(label)
    if not out:
        raise ValueError("--station/--station-inertial: give at least one station")
    if len(set(lb for lb in labels if lb)) != len([lb for lb in labels if lb]):
        raise ValueError(f"--station: a station name is given twice in {[lb for lb in labels if lb]}")
    if names:  # TDM participants: the file's names decide the order
        if any(labels):
            unknown = [n for n in names if n not in labels]
            if unknown:
                raise ValueError(
                    f"--station: the file's station {unknown[0]!r} (PARTICIPANT_1) has no --station "
                    f"{unknown[0]}:... or --station-inertial {unknown[0]}:... "
                    f"(given: {[lb for lb in labels if lb]})"
                )
            if not all(labels):
                raise ValueError("--station: name every station (NAME:...) when any is named")
            extra = [lb for lb in labels if lb not in names]
            if extra:
                raise ValueError(
                    f"--station: {extra[0]!r} is not a station of the file (PARTICIPANT_1: {names})"
                )
            out = [out[labels.index(n)] for n in names]
        elif len(names) != len(out):
            raise ValueError(
                f"--station: the file has {len(names)} station(s) {names}, {len(out)} given "
                f"(hint: name them, --station {names[0]}:lat,lon,h)"
            )
        elif len(names) > 1:  # unnamed options, several stations: say how they were matched
            import sys

            given = [*(args.station or []), *(args.station_inertial or [])]
            mapping = ", ".join(f"{n} = {g}" for n, g in zip(names, given))
            print(f"satgnc: warning: the --station options are not named; matched to the file's stations "
                  f"in order: {mapping} (name them, --station {names[0]}:lat,lon,h, to match by name)",
                  file=sys.stderr)
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


def _is_tdm(path: pathlib.Path) -> bool:
    if path.suffix.lower() in (".tdm", ".kvn", ".txt"):
        return True
    try:  # a TDM under another name: sniff the first keyword
        with path.open("rb") as f:
            head = f.read(256).lstrip(b"\xef\xbb\xbf").lstrip()
    except OSError:
        return False  # the reader reports it with the file name
    return head.startswith(b"CCSDS_TDM_VERS")


def _load(args):
    from . import read_csv_names
    from .tdm import read_tdm

    path = pathlib.Path(args.observations)
    if _is_tdm(path):
        sr = 1e-3 if args.sigma_range is None else args.sigma_range
        srr = 1e-6 if args.sigma_range_rate is None else args.sigma_range_rate
        obs, names, epoch = read_tdm(path, sr, srr, args.epoch)
        return obs, names, epoch
    for opt, v in (("--sigma-range", args.sigma_range), ("--sigma-range-rate", args.sigma_range_rate)):
        if v is not None:
            raise ValueError(f"{opt}: only for TDM files; a CSV file gives sigma on every row")
    obs, names = read_csv_names(path)  # names: a station column with names (BOULDER), else None
    return obs, names, args.epoch


def _propagator(args):
    """--propagator / --force-model: the name, or a CVODES propagator on the TOML's force model."""
    if args.force_model is None:
        return "kepler" if args.propagator is None else args.propagator
    if args.propagator == "kepler":
        raise ValueError("--force-model: needs --propagator cvodes (the Kepler propagator is two-body)")
    from ..forcemodel import load_force_model
    from . import make_propagator

    fm = load_force_model(args.force_model)
    return make_propagator("cvodes", mu=fm.mu, force_model=fm)


def _solve(args) -> int:
    from . import EARTH_RADIUS, solve

    guess = _floats(args.guess, 6, "--guess")
    r = float(np.linalg.norm(guess[:3]))
    if r <= EARTH_RADIUS:
        raise ValueError(f"--guess: the position is inside the Earth (|r| = {r:.6g} km <= {EARTH_RADIUS} km; "
                         "hint: x,y,z in km, vx,vy,vz in km/s)")
    # Options that would have no effect are errors: a typo or a misunderstanding must not pass.
    if not args.station:
        for opt, v in (("--ellipsoid", args.ellipsoid), ("--ut1-utc", args.ut1_utc)):
            if v is not None:
                raise ValueError(f"{opt}: only used with --station (geodetic stations)")
    if args.ut1_utc is not None and not abs(args.ut1_utc) < 0.9:  # the library's IERS bound (od.gmst)
        raise ValueError(
            f"--ut1-utc: |UT1 - UTC| must be < 0.9 s (IERS keeps UTC within 0.9 s of UT1), got {args.ut1_utc}"
        )
    if args.plots is not None and not args.plots.strip():
        raise ValueError("--plots: must name a directory")
    if args.epoch is not None and not args.station and not _is_tdm(pathlib.Path(args.observations)):
        raise ValueError("--epoch: only used with --station (geodetic) or a TDM file")
    args.ut1_utc = 0.0 if args.ut1_utc is None else args.ut1_utc
    args.ellipsoid = "WGS-84" if args.ellipsoid is None else args.ellipsoid
    obs, names, epoch = _load(args)
    if epoch is None and args.station:
        raise ValueError("--epoch: geodetic stations need the UTC epoch of t = 0")
    st = _stations(args, epoch, names)
    used = int(np.max(obs.station))
    if used >= len(st):
        raise ValueError(
            f"{args.observations}: observations use station index {used}, only {len(st)} station(s) "
            "given (--station/--station-inertial; indices start at 0)"
        )
    propagator = _propagator(args)
    r = solve(obs, st, guess, method=args.method, propagator=propagator, max_iterations=args.max_iterations)
    print(summary(r, obs))
    if args.plots:
        for p in plot_residuals(r, obs, args.plots):
            print(f"plot        : {p}")
    return 0 if r.status.name == "converged" else 1


def _simulate(args) -> int:
    import datetime as dt

    from ..papers import od_newton_raphson as paper
    from . import simulate
    from .tdm import write_tdm

    x0 = paper.truth() if args.state is None else np.array(_floats(args.state, 6, "--state"))
    if args.duration / args.step > 1e6:
        n = args.duration / args.step
        raise ValueError(f"--duration, --step: {n:.3g} samples, more than 1e6 (hint: a shorter duration or "
                         "a larger step)")
    st = paper.station()
    t = np.arange(0.0, args.duration + 1e-9, args.step)
    try:
        obs = simulate(
            x0,
            st,
            t,
            sigma_range=args.sigma_range,
            sigma_range_rate=args.sigma_range_rate,
            seed=None if args.no_noise else args.seed,
            elevation_mask_deg=args.elevation_mask,
        )
    except ValueError as e:  # the library names its argument x0; the user typed --state
        if str(e).startswith("elevation_mask_deg:"):
            raise ValueError("--elevation-mask" + str(e)[len("elevation_mask_deg"):]
                             + " (hint: --elevation-mask -90 observes every time)") from None
        if str(e).startswith("x0:"):
            raise ValueError("--state" + str(e)[2:]) from None
        if str(e).startswith("sigma_range, bias_range:"):
            raise ValueError("--sigma-range" + str(e)[len("sigma_range, bias_range"):]) from None
        raise
    out = pathlib.Path(args.out)
    if out.is_dir():
        raise IsADirectoryError(f"--out: {out} is a directory (hint: a file name ending in .csv or .tdm)")
    if out.suffix.lower() == ".tdm":
        write_tdm(out, obs, dt.datetime(1981, 3, 21, 6, 0, 0), ["STATION"])
    else:
        with out.open("w") as f:
            f.write("t,type,value,sigma,station\n")
            for t_, k, v, s, i in zip(obs.t, obs.type_names(), obs.value, obs.sigma, obs.station):
                f.write(f"{t_:.6f},{k},{v:.15e},{s:.6e},{i}\n")
    print(f"wrote {len(obs)} observations to {out}")
    return 0


def _need_subcommand(parser):
    def run(args) -> int:
        from ..cli import CliError

        raise CliError(
            f"{parser.prog}: choose a subcommand: solve, simulate, filter or batch "
            f"(see '{parser.prog} --help')"
        )

    return run


def register(subparsers) -> None:
    from ..cli import finite_float, int_at_least, positive_float

    p = subparsers.add_parser("od", help="orbit determination from range / range-rate observations")
    p.set_defaults(func=_need_subcommand(p))
    sub = p.add_subparsers(dest="od_command")
    s = sub.add_parser("solve", help="estimate the state at t = 0 from a CSV or TDM file")
    s.add_argument("observations", help="CSV (t,type,value,sigma[,station]) or CCSDS TDM KVN (.tdm)")
    s.add_argument("--guess", required=True, help="x,y,z,vx,vy,vz at t = 0 (km, km/s)")
    s.add_argument("--station", action="append", help="[NAME:]lat_deg,lon_deg,height_km (geodetic)")
    s.add_argument("--station-inertial", action="append", help="[NAME:]x,y,z[,omega] inertial at t = 0 (km)")
    s.add_argument("--epoch", help="UTC epoch of t = 0 (ISO); TDM default: first observation")
    s.add_argument("--ut1-utc", type=finite_float, default=None, help="UT1 - UTC, s (default 0)")
    s.add_argument("--ellipsoid", default=None, help="geodetic stations' ellipsoid (default WGS-84)")
    s.add_argument(
        "--method",
        default="levenberg_marquardt",
        choices=["levenberg_marquardt", "gauss_newton", "newton", "lm", "gn"],
    )
    s.add_argument("--propagator", default=None, choices=["kepler", "cvodes"],
                   help="STM propagator (default kepler; cvodes with --force-model)")
    s.add_argument("--force-model", default=None, metavar="FILE",
                   help="force-model TOML (docs/force_models.md) for the cvodes propagator")
    s.add_argument("--max-iterations", type=int_at_least(1), default=200)
    s.add_argument("--sigma-range", type=positive_float, default=None,
                   help="TDM range sigma, km (default 1e-3)")
    s.add_argument("--sigma-range-rate", type=positive_float, default=None,
                   help="TDM range-rate sigma, km/s (default 1e-6)")
    s.add_argument("--plots", help="directory for residual plots")
    s.set_defaults(func=_solve)
    m = sub.add_parser("simulate", help="write synthetic observations of the paper's pass (CSV or .tdm)")
    m.add_argument("--out", required=True)
    m.add_argument("--state", help="x,y,z,vx,vy,vz at t = 0 (default: the paper's Table 1)")
    m.add_argument("--duration", type=positive_float, default=300.0, help="s")
    m.add_argument("--step", type=positive_float, default=10.0, help="s")
    m.add_argument("--sigma-range", type=positive_float, default=1e-3, help="km")
    m.add_argument("--sigma-range-rate", type=positive_float, default=1e-6, help="km/s")
    m.add_argument("--seed", type=int_at_least(0), default=0)
    m.add_argument("--no-noise", action="store_true")
    m.add_argument("--elevation-mask", type=finite_float, default=0.0,
                   help="deg above the station's geocentric horizon (default 0: nothing through the Earth; "
                        "-90 observes every time)")
    m.set_defaults(func=_simulate)
    from .filter_cli import register as _register_filter  # issue 15: satgnc od filter

    _register_filter(sub)
    from .batch_cli import register as _register_batch  # issue 13: satgnc od batch (tracking data)

    _register_batch(sub)


if __name__ == "__main__":  # pragma: no cover
    from ..cli import main

    sys.exit(main(["od", *sys.argv[1:]]))
