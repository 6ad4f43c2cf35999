"""
Read a CCSDS tracking data message (TDM)
========================================

Write simulated two-way range and range-rate of two named stations to a KVN TDM, read it back (the
station names come from PARTICIPANT_1, the times are seconds after the first observation) and fit
the orbit from it. Units: km, km/s, s.
"""

import datetime as dt
import pathlib
import tempfile

import numpy as np
from satgnc import od
from satgnc.od import tdm

epoch = dt.datetime(2026, 3, 20, 12, 0, 0)
truth = np.array([6778.137, 0.0, 0.0, 0.0, 4.7302, 6.0354])  # km, km/s
names = ["EQUATOR", "SOUTH"]
stations = [od.station_geodetic(0.0, 5.0, 0.0, epoch.isoformat()),
            od.station_geodetic(-33.0, -70.0, 0.7, epoch.isoformat())]
obs = od.simulate(truth, stations, np.arange(0.0, 6000.0, 20.0), seed=2)

with tempfile.TemporaryDirectory() as d:
    path = tdm.write_tdm(pathlib.Path(d) / "pass.tdm", obs, epoch, names)
    print("".join(path.read_text().splitlines(keepends=True)[:14]), "...")
    read, read_names, read_epoch = tdm.read_tdm(path, epoch=epoch)  # times: s after our epoch

print(f"read {len(read)} observations of stations {read_names} from {read_epoch} UTC")
# The station list must follow the file's names (read_names), not the order we wrote them in.
by_name = dict(zip(names, stations))
fit = od.solve(read, [by_name[n] for n in read_names], truth + np.array([10.0, 10.0, -10.0, 0.0, 0.0, 0.0]))
err_m = 1e3 * float(np.linalg.norm(fit.x0[:3] - truth[:3]))
print(f"fit: {fit.status.name} in {fit.iterations} iterations, position error {err_m:.2f} m")
