"""``satgnc od batch``: batch least-squares OD on a CCSDS tracking data message, end to end.

Example (the shipped example, examples/data/)::

    satgnc od batch --tdm examples/data/leo_tracking.tdm --stations examples/data/stations.toml \
        --guess=-2540,-5015,4135,-3.14,-3.36,-6.0 --epoch 2016-12-10T00:00:00 \
        --estimate-range-bias WEILHEIM --out fit.json

Runs :func:`satgnc.od.batch_estimate` (``BatchEstimator`` in C++) on the TDM's RANGE (km),
DOPPLER_INSTANTANEOUS / DOPPLER_INTEGRATED (km/s) and ANGLE_1 + ANGLE_2 (AZEL or RADEC, deg) with the
light-time models of :mod:`satgnc.observation` (PATH 1,2,1: two-way; 2,1: one-way), stations fixed in
ITRF (WGS-84 geodetic) carried to GCRF by IAU 2006/2000A with EOP (``--eop``: a finals2000A or EOP 20
C04 file; default the astropy-iers-data table; ``--station-model paper``: the paper's GMST-rotating
station instead, for reproductions; the same station code as ``od filter``, ``od/_cli_stations.py``),
DOP853 with the STM on the force model of ``--force-model`` (TOML, docs/force_models.md; default point
mass + J2), its epoch set to the run's.

Stations: ``--stations FILE`` (TOML: one table per participant name with ``latitude`` deg,
``longitude`` deg east, ``height`` km; or CSV with the header ``name,latitude_deg,longitude_deg,
height_km``) and/or ``--station NAME:lat,lon,h``. Every receiving participant of the TDM needs one.

Output: a summary on stdout; ``--out FILE``: ``.json`` (state, covariance, biases, statistics, the
residuals per measurement), ``.oem`` (OEM KVN: the state at the epoch with its covariance) or ``.xml``
(the same OEM in XML). Exit 0 when converged, 1 otherwise (the status is printed); errors print one line
``satgnc: error: ...`` and exit 2 (``--debug`` shows the traceback).
"""

from __future__ import annotations

import datetime as _dt
import json
import math
import pathlib
from typing import Any

import numpy as np

from . import _cli_stations as _st
from ._cli_stations import read_stations  # noqa: F401 (kept importable from here)


def _finite(a: Any) -> Any:
    """Nested lists of an array with non-finite entries (a singular covariance) as None: strict JSON."""
    return [_finite(v) for v in a] if isinstance(a, list) else (a if math.isfinite(a) else None)


def _result_json(r: Any, epoch: Any, names: list[str], args: Any) -> dict[str, Any]:
    return {
        "tdm": str(args.tdm),
        "epoch_utc": epoch.to_iso("UTC", 6),
        "frame": "GCRF",
        "status": r.status,
        "message": r.message,
        "iterations": r.iterations,
        "evaluations": r.evaluations,
        "state_km_kms": r.state.tolist(),
        "parameter_names": list(r.parameter_names),
        "parameters": _finite(r.parameters.tolist()),
        "sigma": _finite(r.sigma.tolist()),
        "covariance": _finite(r.covariance.tolist()),
        "stations": names,
        "range_bias_km": r.range_bias.tolist(),
        "time_bias_s": r.time_bias.tolist(),
        "rms_normalized": _finite(r.rms),
        "cost": _finite(r.cost),
        "rank": r.rank,
        "condition_number": _finite(r.condition_number),
        "step_sigma": r.step_sigma,
        "residuals": _finite(r.residuals.tolist()),
        "troposphere": args.troposphere,
        "light_time": not args.no_light_time,
        "shapiro": args.shapiro,
    }


def estimate_oem(epochs: Any, states: Any, covariances: Any, comment: str) -> Any:
    """The OEM (object SAT, GCRF, UTC) of estimated states (K, 6) in km, km/s at the ISO ``epochs`` with
    their symmetrized 6 x 6 covariances; ``od batch`` and ``od filter`` write it."""
    from .. import io as _io

    md = _io.OemMetadata(
        object_name="SAT",
        object_id="UNKNOWN",
        center_name="EARTH",
        ref_frame="GCRF",
        time_system="UTC",
        start_time=epochs[0],
        stop_time=epochs[-1],
        comments=(comment,),
    )
    cv = tuple(
        _io.OemCovariance(epoch=e, matrix=0.5 * (c[:6, :6] + c[:6, :6].T))
        for e, c in zip(epochs, covariances)
    )
    seg = _io.OemSegment(metadata=md, epochs=tuple(epochs), states=states, covariances=cv)
    now = _dt.datetime.now(_dt.timezone.utc).replace(tzinfo=None).isoformat(timespec="seconds")
    return _io.Oem(header=_io.Header(creation_date=now, originator="SATGNC"), segments=(seg,))


def _write_oem(path: pathlib.Path, r: Any, epoch: Any, args: Any, xml: bool) -> None:
    from .. import io as _io

    ep = epoch.to_iso("UTC", 6)
    comment = f"satgnc od batch over {args.tdm}: {r.status}, {r.iterations} iterations, RMS {r.rms:.4g}"
    oem = estimate_oem((ep,), r.state.reshape(1, 6), (r.covariance,), comment)
    (_io.write_oem_xml if xml else _io.write_oem)(path, oem)


def _summary(r: Any, td: Any, epoch: Any, names: list[str]) -> str:
    from .batch import OBSERVABLES

    lines = [
        f"status      : {r.status} ({r.message})",
        f"iterations  : {r.iterations} ({r.evaluations} evaluations), RMS normalized {r.rms:.4f}, "
        f"step {r.step_sigma:.3g} sigma",
        f"epoch (UTC) : {epoch.to_iso('UTC', 6)}",
        "state GCRF  : "
        + " ".join(f"{v:.6f}" for v in r.state[:3])
        + " km  "
        + " ".join(f"{v:.9f}" for v in r.state[3:])
        + " km/s",
        f"1-sigma RSS : {1e3 * np.linalg.norm(r.sigma[:3]):.3f} m, "
        f"{1e6 * np.linalg.norm(r.sigma[3:6]):.3f} mm/s",
    ]
    for k, n in enumerate(names):
        lines.append(
            f"station {n:10s}: range bias {1e3 * r.range_bias[k]:.3f} m, "
            f"time bias {1e3 * r.time_bias[k]:.4f} ms"
        )
    arr = td.arrays(epoch)
    types = np.asarray(arr["types"])
    units = {
        0: (1e3, "m"),
        1: (1e3, "m"),
        2: (1e6, "mm/s"),
        3: (1e6, "mm/s"),
        4: (206264.806, "arcsec"),
        5: (206264.806, "arcsec"),
    }
    for code in sorted(set(types.tolist())):
        sel = types == code
        res = r.residuals[sel]
        res = res[np.isfinite(res)]
        scale, unit = units[int(code)]
        lines.append(
            f"rms {OBSERVABLES[int(code)]:26s}: {np.sqrt(np.mean(res**2)) * scale:.4g} {unit} ({sel.sum()})"
        )
    return "\n".join(lines)


def _run(args: Any) -> int:
    from .. import _satgnc
    from ..forcemodel import load_force_model_config
    from ..time import Epoch
    from .batch import batch_estimate, read_tracking_tdm

    tdm_path = str(args.tdm)
    if not pathlib.Path(tdm_path).is_file():
        raise FileNotFoundError(f"--tdm: no such file: {tdm_path}")
    receivers = _st.receivers(tdm_path)
    sites = _st.site_coordinates(args.stations, args.station, receivers)
    names = receivers  # only the stations that measured: an unused station would make biases singular
    for opt, chosen in (
        ("--estimate-range-bias", args.estimate_range_bias),
        ("--estimate-time-bias", args.estimate_time_bias),
    ):
        for n in chosen or []:
            if n not in names:
                raise ValueError(f"{opt}: {n!r} is not a receiving station of the TDM ({names})")
    sig = {
        "sigma_range": args.sigma_range,
        "sigma_range_rate": args.sigma_range_rate,
        "sigma_angle": math.radians(args.sigma_angle),
    }
    td = read_tracking_tdm(tdm_path, names, **sig)
    if len(td) == 0:
        raise ValueError(f"--tdm: {tdm_path}: no RANGE, DOPPLER_* or ANGLE_1/2 measurement")
    ref = Epoch.parse("2000-01-01T00:00:00", "TAI")
    t_ref = np.asarray(td.arrays(ref)["t"])
    if args.epoch is None:
        epoch = ref + float(t_ref[0])
    else:
        try:
            epoch = Epoch.parse(args.epoch, "UTC")
        except ValueError as e:
            raise ValueError(f"--epoch: {e}") from None
    t = t_ref - (epoch - ref)
    stations = _st.station_ephemerides(
        args.station_model, sites, names, epoch, float(t.min()), float(t.max()), args.eop
    )
    if args.force_model is None:
        fm = _satgnc.ForceModel(j2=_satgnc.J2Gravity())
    else:
        fm = load_force_model_config(args.force_model).model
    fm.set_epoch(epoch)
    guess = np.array(_st.floats(args.guess, 6, "--guess"))
    if np.linalg.norm(guess[:3]) <= 6378.0:
        raise ValueError(
            "--guess: the position is inside the Earth (hint: x,y,z km, vx,vy,vz km/s, GCRF at the epoch)"
        )
    out = None
    if args.out is not None:
        out = pathlib.Path(args.out)
        if out.suffix.lower() not in (".json", ".oem", ".xml"):
            raise ValueError(f"--out: {out}: unknown kind (hint: .json, .oem (OEM KVN) or .xml (OEM XML))")
        if out.is_dir():
            raise ValueError(f"--out: {out} is a directory")
    r = batch_estimate(
        td,
        stations,
        guess,
        epoch=epoch,
        force_model=fm,
        station_names=names,
        estimate_range_bias=list(args.estimate_range_bias or []),
        estimate_time_bias=list(args.estimate_time_bias or []),
        light_time=not args.no_light_time,
        troposphere=False if args.troposphere == "none" else args.troposphere,
        shapiro=args.shapiro,
        max_iterations=args.max_iterations,
        method={"gn": "gauss_newton", "lm": "levenberg_marquardt"}.get(args.method, args.method),
        wavelength_um=args.wavelength,
    )
    print(_summary(r, td, epoch, names))
    if out is not None:
        if out.suffix.lower() == ".json":
            text = json.dumps(_result_json(r, epoch, names, args), indent=1, allow_nan=False)
            out.write_text(text + "\n")
        else:
            _write_oem(out, r, epoch, args, xml=out.suffix.lower() == ".xml")
        print(f"wrote       : {out}")
    return 0 if r.converged else 1


def add_troposphere_arguments(p: Any) -> None:
    """``--troposphere`` and ``--wavelength``, the same in ``od batch`` and ``od filter``."""
    from ..cli import positive_float

    p.add_argument(
        "--troposphere",
        default="none",
        choices=["none", "saastamoinen", "mendes_pavlis", "marini_murray"],
        help="troposphere model (default none: data already corrected)",
    )
    p.add_argument(
        "--wavelength",
        type=positive_float,
        default=0.532,
        help="laser wavelength, um (mendes_pavlis, marini_murray)",
    )


def register(sub: Any) -> None:
    """Add ``batch`` to the ``satgnc od`` subcommands."""
    from ..cli import int_at_least, positive_float

    b = sub.add_parser(
        "batch",
        help="batch least squares on a CCSDS TDM (light time, IAU 2006 + EOP, biases); JSON or OEM out",
    )
    b.add_argument("--tdm", required=True, help="CCSDS TDM (KVN or XML): RANGE, DOPPLER_*, ANGLE_1/2")
    b.add_argument(
        "--stations", help="stations file: TOML ([NAME] latitude, longitude deg, height km) or CSV"
    )
    b.add_argument("--station", action="append", help="NAME:lat_deg,lon_deg,height_km (WGS-84); repeatable")
    b.add_argument("--guess", required=True, help="x,y,z,vx,vy,vz at the epoch (GCRF km, km/s)")
    b.add_argument("--epoch", help="UTC epoch of the estimated state (ISO); default: the first measurement")
    b.add_argument("--force-model", metavar="FILE", help="force-model TOML (default: point mass + J2)")
    b.add_argument(
        "--station-model",
        default="itrf",
        choices=list(_st.STATION_MODELS),
        help="itrf: WGS-84 in ITRF on IAU 2006 + EOP (default); paper: the paper's GMST-rotating station",
    )
    b.add_argument(
        "--eop", metavar="FILE", help="EOP file, finals2000A or EOP 20 C04 (default: astropy-iers-data)"
    )
    b.add_argument(
        "--estimate-range-bias", action="append", metavar="NAME", help="station whose range bias is estimated"
    )
    b.add_argument(
        "--estimate-time-bias", action="append", metavar="NAME", help="station whose time bias is estimated"
    )
    add_troposphere_arguments(b)
    b.add_argument("--shapiro", action="store_true", help="add the Shapiro delay")
    b.add_argument(
        "--no-light-time", action="store_true", help="instantaneous geometry (for comparison only)"
    )
    b.add_argument("--method", default="lm", choices=["lm", "gn", "levenberg_marquardt", "gauss_newton"])
    b.add_argument("--max-iterations", type=int_at_least(1), default=50)
    b.add_argument("--sigma-range", type=positive_float, default=1e-3, help="km (default 1e-3)")
    b.add_argument("--sigma-range-rate", type=positive_float, default=1e-6, help="km/s (default 1e-6)")
    b.add_argument("--sigma-angle", type=positive_float, default=0.005, help="deg (default 0.005)")
    b.add_argument("--out", help="result file: .json, .oem (OEM KVN) or .xml (OEM XML)")
    b.set_defaults(func=_run)
