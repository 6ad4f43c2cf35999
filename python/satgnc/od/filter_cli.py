"""``satgnc od filter``: sequential orbit determination over a CCSDS TDM, writing an OEM with covariance.

Example (the shipped example of ``od batch``, examples/data/)::

    satgnc od filter --tdm examples/data/leo_tracking.tdm --stations examples/data/stations.toml \
        --guess=-2540,-5015,4135,-3.14,-3.36,-6.0 --epoch 2016-12-10T00:00:00 \
        --estimate-range-bias --smooth --out est.oem

The TDM (KVN or XML) is read as ``od batch`` reads it (:func:`satgnc.od.read_tracking_tdm`): RANGE
(km), DOPPLER_INSTANTANEOUS / DOPPLER_INTEGRATED (km/s), ANGLE_1 + ANGLE_2 (AZEL or RADEC, deg) of the
receiving participants; PATH 1,2,1 (or none) two-way, 2,1 one-way, with light time. Stations come
from ``--stations FILE`` / ``--station NAME:lat,lon,h`` and are built by the same code as ``od batch``
(``od/_cli_stations.py``): by default WGS-84 geodetic stations fixed in the ITRF, carried to GCRF by IAU
2006/2000A with EOP (``--eop`` FILE; default astropy-iers-data); ``--station-model paper`` gives the
paper's GMST-rotating station (for data simulated with it, e.g. tests/data/filter/two_station.tdm).
t = 0 is ``--epoch`` (UTC, default: the first observation, or the ``[epoch]`` of ``--force-model``).
``--force-model FILE`` reads the force-model TOML (docs/force_models.md: gravity field, drag, SRP,
third bodies) the filter propagates with between measurements (default: point mass + J2). The OEM
holds, per measurement epoch (one line per distinct tag), the filtered (or with ``--smooth`` the
smoothed) GCRF state and its 6 x 6 covariance.

Errors print one line ``satgnc: error: ...`` and exit with code 2.
"""

from __future__ import annotations

import datetime as _dt
import math
import pathlib
from typing import Any

import numpy as np

from . import _cli_stations as _st

_KEYWORDS = {"RANGE": "range", "DOPPLER_INSTANTANEOUS": "range_rate"}


def _floats(text: str, n: int, name: str) -> list[float]:
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise ValueError(f"{name}: expected {n} comma-separated numbers, got {text!r}") from None
    if len(vals) != n or not all(np.isfinite(vals)):
        raise ValueError(f"{name}: expected {n} finite comma-separated numbers, got {text!r}")
    return vals


def _utc(text: str, name: str) -> _dt.datetime:
    try:
        return _dt.datetime.fromisoformat(text.strip().rstrip("Z"))
    except ValueError:
        raise ValueError(f"{name}: not an ISO-8601 UTC date-time: {text!r}") from None


def load_tdm(
    path: str, epoch: str | None, epoch_name: str = "--epoch"
) -> tuple[dict[str, Any], list[str], _dt.datetime]:
    """Measurements of a TDM as arrays (t s from the epoch, station index, observable name, value) and
    the station names in order of first appearance; ``epoch_name`` names the epoch's source in errors."""
    from .. import io as _io

    tdm = _io.read_tdm(path)
    rows: list[tuple[_dt.datetime, str, str, float]] = []
    for i, seg in enumerate(tdm.segments):
        md = seg.metadata
        if md.time_system != "UTC":
            raise ValueError(
                f"{path}: segment {i + 1}: TIME_SYSTEM {md.time_system} (the filter CLI reads UTC)"
            )
        path_idx = tuple(md.path) if md.path else ()
        if path_idx in ((), (1, 2, 1)):
            way = "two_way"
        elif path_idx == (2, 1):
            way = "one_way"
        else:
            raise ValueError(f"{path}: segment {i + 1}: PATH {md.path} not supported (hint: 1,2,1 or 2,1)")
        station = md.participants[0]
        for kw, ep, val in zip(seg.keywords, seg.epochs, np.asarray(seg.values)):
            if kw not in _KEYWORDS:
                raise ValueError(
                    f"{path}: segment {i + 1}: keyword {kw} not used by the filter "
                    f"(hint: RANGE, DOPPLER_INSTANTANEOUS)"
                )
            rows.append((_utc(ep, path), station, f"{way}_{_KEYWORDS[kw]}", float(val)))
    if not rows:
        raise ValueError(f"{path}: no RANGE or DOPPLER_INSTANTANEOUS observation")
    rows.sort(key=lambda r: r[0])
    t_epoch = rows[0][0] if epoch is None else _utc(epoch, epoch_name)
    names: list[str] = []
    for r in rows:
        if r[1] not in names:
            names.append(r[1])
    t = np.array([(r[0] - t_epoch).total_seconds() for r in rows])
    if t[0] < 0:
        raise ValueError(
            f"{epoch_name}: {t_epoch.isoformat()} is after the first observation ({rows[0][0].isoformat()})"
        )
    return (
        {
            "t": t,
            "station": np.array([names.index(r[1]) for r in rows]),
            "observable": [r[2] for r in rows],
            "value": np.array([r[3] for r in rows]),
        },
        names,
        t_epoch,
    )


def _force_model(path: str | None) -> tuple[Any, str | None]:
    """--force-model: the TOML's ForceModel (None: point mass + J2) and its [epoch] as UTC ISO text
    (None when the file has no [epoch]). The model's time origin is that epoch, so it must be the
    filter's t = 0: it is the default of --epoch, and a different --epoch is an error."""
    if path is None:
        return None, None
    from ..forcemodel import load_force_model_config

    cfg = load_force_model_config(path)
    ep = None if cfg.epoch is None else cfg.epoch.to_iso("UTC", 3)
    return cfg.model, ep


def _iso(epoch: Any) -> str:
    """UTC ISO text of an Epoch without trailing zero fractions (as the user typed it)."""
    return _dt.datetime.fromisoformat(epoch.to_iso("UTC", 6)).isoformat()


def _run(args: Any) -> int:
    from .. import io as _io
    from ..time import Epoch
    from . import filtering
    from .batch import OBSERVABLES, read_tracking_tdm
    from .batch_cli import estimate_oem

    tdm_path = str(args.tdm)
    if not pathlib.Path(tdm_path).is_file():
        raise FileNotFoundError(f"--tdm: no such file: {tdm_path}")
    fm, toml_epoch = _force_model(args.force_model)
    names = _st.receivers(tdm_path)  # the same stations, files and models as od batch
    sites = _st.site_coordinates(args.stations, args.station, names)
    td = read_tracking_tdm(
        tdm_path,
        names,
        sigma_range=args.sigma_range,
        sigma_range_rate=args.sigma_range_rate,
        sigma_angle=math.radians(args.sigma_angle),
    )
    if len(td) == 0:
        raise ValueError(f"--tdm: {tdm_path}: no RANGE, DOPPLER_* or ANGLE_1/2 measurement")
    ref = Epoch.parse("2000-01-01T00:00:00", "TAI")
    first = ref + float(np.min(np.asarray(td.arrays(ref)["t"])))
    epoch_name = "--epoch"
    if args.epoch is not None:
        text = args.epoch
    elif toml_epoch is not None:
        text, epoch_name = toml_epoch, f"--force-model: {args.force_model}: [epoch]"
    else:
        text = first.to_iso("UTC", 6)
    try:
        epoch = Epoch.parse(text.strip().rstrip("Z"), "UTC")
    except ValueError:
        raise ValueError(f"{epoch_name}: not an ISO-8601 UTC date-time: {text!r}") from None
    if toml_epoch is not None and abs(epoch - Epoch.parse(toml_epoch, "UTC")) > 1e-3:
        raise ValueError(
            f"--force-model: {args.force_model}: [epoch] {toml_epoch} UTC is not the filter's t = 0 "
            f"({_iso(epoch)}) (hint: the same instant in --epoch and the TOML, or drop one)"
        )
    arr = td.arrays(epoch)
    t = np.asarray(arr["t"], dtype=float)
    if t.min() < 0:
        raise ValueError(f"{epoch_name}: {_iso(epoch)} is after the first observation ({_iso(first)})")
    stations = _st.station_ephemerides(
        args.station_model, sites, names, epoch, float(t.min()), float(t.max()), args.eop
    )
    guess = _st.floats(args.guess, 6, "--guess")
    if np.linalg.norm(guess[:3]) <= 6378.0:
        raise ValueError(
            "--guess: the position is inside the Earth (hint: x,y,z km, vx,vy,vz km/s, GCRF at t = 0)"
        )
    codes = np.asarray(arr["types"], dtype=int)
    obs_names = [OBSERVABLES[c] for c in sorted(set(codes.tolist()))]
    unit_sigma = (args.sigma_range, args.sigma_range_rate, math.radians(args.sigma_angle))
    sig = [unit_sigma[min(OBSERVABLES.index(o) // 2, 2)] for o in obs_names]
    p0 = np.diag([args.sigma_position**2] * 3 + [args.sigma_velocity**2] * 3)
    run = filtering.smooth if args.smooth else filtering.filter
    r = run(
        t,
        np.asarray(arr["stations"], dtype=int),
        np.array([OBSERVABLES[c] for c in codes], dtype=object),
        np.asarray(arr["values"], dtype=float),
        stations=stations,
        x0=np.array(guess),
        P0=p0,
        observables=obs_names,
        sigma=sig,
        snc_psd_ric=args.snc_psd,
        method=args.method,
        force_model=fm,
        estimate_range_bias=args.estimate_range_bias,
        troposphere=False if args.troposphere == "none" else args.troposphere,
        wavelength_um=args.wavelength,
    )
    states = r.smoothed_state if args.smooth else r.state
    covs = r.smoothed_covariance if args.smooth else r.covariance
    keep = np.r_[np.diff(r.t) > 0, True]  # one OEM line per distinct tag: the last step at it
    eps = [(epoch + float(tk)).to_iso("UTC", 3) for tk in r.t[keep]]
    comment = (
        "satgnc od filter: "
        + ("RTS smoother" if args.smooth else f"{args.method.upper()}")
        + f" over {args.tdm}; stations {args.station_model}; {r.message}"
    )
    oem = estimate_oem(eps, states[keep, :6], covs[keep], comment)
    out = pathlib.Path(args.out)
    if out.is_dir():
        raise ValueError(f"--out: {out} is a directory (hint: a file name ending in .oem)")
    _io.write_oem(out, oem)
    print(f"{r.message}; status {r.status}")
    print(
        f"final 1-sigma position {np.sqrt(np.trace(covs[-1][:3, :3])) * 1e3:.3f} m; "
        f"wrote {len(eps)} states to {out}"
    )
    if args.estimate_range_bias:
        k = [i for i, n in enumerate(r.state_names) if n.startswith("range_bias_")]
        for j, i in enumerate(k):
            print(
                f"station {names[j]:10s}: range bias {1e3 * states[-1, i]:.3f} "
                f"+- {1e3 * np.sqrt(covs[-1][i, i]):.3f} m"
            )
    return 0 if r.status == "completed" else 1


def register(sub: Any) -> None:
    """Add ``filter`` to the ``satgnc od`` subcommands."""
    from ..cli import finite_float, positive_float
    from .batch_cli import add_troposphere_arguments

    f = sub.add_parser(
        "filter", help="sequential OD (EKF/UKF, optional RTS smoother) over a TDM; writes an OEM"
    )
    f.add_argument("--tdm", required=True, help="CCSDS TDM (KVN or XML): RANGE, DOPPLER_*, ANGLE_1/2")
    f.add_argument("--out", required=True, help="OEM file to write (KVN, with covariance)")
    f.add_argument("--guess", required=True, help="x,y,z,vx,vy,vz at t = 0 (GCRF km, km/s)")
    f.add_argument(
        "--stations", help="stations file: TOML ([NAME] latitude, longitude deg, height km) or CSV"
    )
    f.add_argument("--station", action="append", help="NAME:lat_deg,lon_deg,height_km (WGS-84); repeatable")
    f.add_argument(
        "--station-model",
        default="itrf",
        choices=list(_st.STATION_MODELS),
        help="itrf: WGS-84 in ITRF on IAU 2006 + EOP, as od batch (default); paper: the paper's "
        "GMST-rotating station",
    )
    f.add_argument(
        "--eop", metavar="FILE", help="EOP file, finals2000A or EOP 20 C04 (default: astropy-iers-data)"
    )
    f.add_argument("--epoch", help="UTC epoch of t = 0 (ISO); default: the first observation")
    f.add_argument("--smooth", action="store_true", help="write the RTS-smoothed states")
    f.add_argument("--method", default="ekf", choices=["ekf", "ukf"])
    f.add_argument("--sigma-range", type=positive_float, default=0.005, help="km (default 0.005)")
    f.add_argument("--sigma-range-rate", type=positive_float, default=1e-6, help="km/s (default 1e-6)")
    f.add_argument("--sigma-angle", type=positive_float, default=0.005, help="deg (default 0.005)")
    f.add_argument("--estimate-range-bias", action="store_true", help="one range-bias state per station (km)")
    add_troposphere_arguments(f)
    f.add_argument("--sigma-position", type=positive_float, default=1.0, help="a priori, km (default 1)")
    f.add_argument(
        "--sigma-velocity", type=positive_float, default=1e-3, help="a priori, km/s (default 1e-3)"
    )
    f.add_argument(
        "--force-model",
        metavar="FILE",
        help="force-model TOML (docs/force_models.md) between measurements; default point mass + J2",
    )
    f.add_argument("--snc-psd", type=finite_float, default=1e-15, help="SNC PSD, km^2/s^3 (default 1e-15)")
    f.set_defaults(func=_run)
