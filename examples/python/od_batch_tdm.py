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

try:
    DATA = pathlib.Path(__file__).resolve().parents[1] / "data"
except NameError:  # run without a file (interactive): from the repository root
    DATA = pathlib.Path("examples") / "data"
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
    oem = io.read_oem(out)

state = oem.segments[0].states[0]
sigma_m = 1e3 * np.sqrt(np.diag(oem.segments[0].covariances[0].matrix)[:3])
print(
    f"exit code {rc}; position error {1e3 * np.linalg.norm(state[:3] - truth[:3]):.2f} m "
    f"(formal 1-sigma per axis {np.array2string(sigma_m, precision=2)} m)"
)
