"""
Batch OD on a tracking data file from the command line
=======================================================

``satgnc od batch`` on the shipped CCSDS TDM ``examples/data/leo_tracking.tdm``: 8 h of two-way
light-time range, range-rate and azimuth / elevation of Kiruna and Weilheim (stations in
``examples/data/stations.toml``), simulated from a known orbit by ``examples/data/make_leo_tracking.py``
with a 5 m range bias at Weilheim. The command estimates the GCRF state at the epoch and that bias
(stations on IAU 2006/2000A with the EOP of astropy-iers-data, point mass + J2) and writes an OEM with
the covariance. Units: km, km/s, s.
"""

import pathlib
import tempfile

import numpy as np
from satgnc import io
from satgnc.cli import main


def _data_dir() -> pathlib.Path:
    """examples/data, found from this file or the working directory (the gallery runs in docs/)."""
    start = pathlib.Path(str(globals().get("__file__", pathlib.Path.cwd() / "_"))).resolve().parent
    for d in (start, *start.parents, pathlib.Path.cwd(), *pathlib.Path.cwd().parents):
        for cand in (d / "data", d / "examples" / "data"):
            if (cand / "leo_tracking.tdm").is_file():
                return cand
    raise FileNotFoundError("examples/data/leo_tracking.tdm not found: run from the satgnc repository")


DATA = _data_dir()
truth = np.array([-2543.62720, -5010.46660, 4137.58155, -3.13535812, -3.36212493, -5.99891423])  # km, km/s

with tempfile.TemporaryDirectory() as d:
    out = pathlib.Path(d) / "fit.oem"
    rc = main(
        [
            "od",
            "batch",
            "--tdm",
            str(DATA / "leo_tracking.tdm"),
            "--stations",
            str(DATA / "stations.toml"),
            "--guess=-2540,-5015,4135,-3.14,-3.36,-6.0",  # a few km and m/s off
            "--epoch",
            "2016-12-10T00:00:00",
            "--estimate-range-bias",
            "WEILHEIM",
            "--out",
            str(out),
        ]
    )
    if rc != 0:
        raise SystemExit(f"satgnc od batch exited with {rc}")
    oem = io.read_oem(out)

state = oem.segments[0].states[0]
sigma_m = 1e3 * np.sqrt(np.diag(oem.segments[0].covariances[0].matrix)[:3])
print(
    f"exit code {rc}; position error {1e3 * np.linalg.norm(state[:3] - truth[:3]):.2f} m "
    f"(formal 1-sigma per axis {np.array2string(sigma_m, precision=2)} m)"
)
