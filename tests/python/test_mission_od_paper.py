"""mission_od_paper.toml: Gao & Luo's OD case as an instance of the mission chain (stages 1-2).

The mission's tracking stage observes the paper's pass ([tracking] times of Table 4, the Table 3
station as an inertial station, noise-free, Kepler truth) and its OD stage runs the paper's
Newton-Raphson ([od] method = "newton_six_point"). The reproduction test
(test_od_paper.py::test_tables_5_to_11_newton_converges_for_all_offsets) asserts, per offset of Table 5:
status converged, at most 5 iterations, |x1 error| < 10 cm. The same assertions hold here, with the
same tolerances, and the estimate is the reproduction's bit for bit (measured: equal, 0.0 difference;
iterations 4, 4, 5, 5)."""

import dataclasses
import json

import numpy as np
import pytest
import satgnc
from satgnc import mission
from satgnc.cli import main
from satgnc.papers import od_newton_raphson as paper
from satgnc.scenarios import mission as scen

OD_PAPER = scen.DEFAULT.with_name("mission_od_paper.toml")


@pytest.fixture(scope="module")
def run():
    return mission.run(OD_PAPER)


def test_od_paper_file_is_the_papers_set_up(run):
    sc = run.scenario
    assert sc.stages == ("track", "estimate")
    np.testing.assert_array_equal(sc.x0, paper.truth())  # Table 1
    np.testing.assert_array_equal(sc.times, paper.times())  # Table 4
    assert sc.stations[0].frame == "inertial" and sc.stations[0].omega is None  # the Earth's rate
    np.testing.assert_array_equal(sc.stations[0].position, paper.station_state_table3()[:3])  # Table 3
    assert (sc.sigma_range, sc.sigma_range_rate) == (paper.SIGMA_RANGE, paper.SIGMA_RANGE_RATE)
    assert sc.noise is False and sc.od_method == "newton_six_point" and sc.truth_propagator == "kepler"


def test_tracking_stage_is_the_reproductions_synthetic_data(run):
    tr = run.tracking
    rho, rhodot = paper.observe()
    kinds = np.asarray(tr.type)
    assert tr.t.size == 12 and tr.forces == "point mass (Kepler, analytic)"
    np.testing.assert_array_equal(tr.value[kinds == "range"], rho)  # bit for bit (km)
    np.testing.assert_array_equal(tr.value[kinds == "range_rate"], rhodot)  # km/s


def test_tables_5_to_11_through_the_mission_chain(run):
    """Each Table 5 offset as the file's guess_offset: the reproduction's assertions, same tolerances."""
    assert run.statuses == {"tracking": "success", "od": "converged"}
    ref = paper.solve_offsets()
    offsets = paper.tables()["table5_initial_x1_offsets_km"]
    assert [r.offset_km for r in ref] == offsets
    for d, pr in zip(offsets, ref):
        sc = dataclasses.replace(run.scenario, guess_offset=np.array([d, 0.0, 0.0, 0.0, 0.0, 0.0]))
        est = mission.run(sc).estimate
        assert est.status == "converged"
        assert est.iterations <= 5  # issue goal; measured 4, 4, 5, 5 (as the reproduction)
        x1_error_cm = (est.x0[0] - paper.truth()[0]) * 1e5
        assert abs(x1_error_cm) < 10.0  # issue goal (paper Table 11: 1-6 cm); measured < 0.2 cm
        # the reproduction's run itself, not a close one
        assert est.iterations == pr.iterations
        np.testing.assert_array_equal(est.x0, pr.x0)
        assert x1_error_cm == pr.x1_error_cm
    assert run.estimate.iterations == ref[0].iterations == 4  # the file's own guess: Table 5's 10 km


def test_od_stage_residuals_per_observation(run):
    est = run.estimate
    assert est.residuals.shape == (12,) and est.normalized.shape == (12,)
    # noise-free data: the converged fit leaves < 1e-3 sigma (measured ~1e-7 m in range)
    assert np.max(np.abs(est.normalized)) < 1e-3
    assert est.rank == 6 and est.model == "point mass"
    assert [h.stage for h in run.handoff] == ["1 tracking", "1 tracking", "2 OD", "2 OD", "2 OD", "2 OD"]


def test_cli_runs_the_od_paper_file(tmp_path, capsys):
    assert main(["mission", "--scenario", str(OD_PAPER), "--out", str(tmp_path / "m")]) == 0
    out = capsys.readouterr().out
    assert out.startswith("mission_od_paper: OD converged in 4 iterations")
    js = json.loads((tmp_path / "m" / "mission_summary.json").read_text())
    assert js["stages"] == ["track", "estimate"] and js["od_iterations"] == 4
    assert (tmp_path / "m" / "figures" / "mission.png").stat().st_size > 10_000


def _bad(tmp_path, old, new):
    text = OD_PAPER.read_text()
    assert old in text
    p = tmp_path / "bad.toml"
    p.write_text(text.replace(old, new))
    return p


@pytest.mark.parametrize(("old", "new", "message"), [
    ("times = [0.0, 60.0, 120.0, 180.0, 240.0, 300.0]", "times = [0.0, 60.0, 120.0, 180.0, 240.0]",
     r"key 'method' in section \[od\]: 'newton_six_point' .*exactly 6 tracking times, \[tracking\] gives 5"),
    ('types = "both"', 'types = "range"', r"'newton_six_point' .*types = 'both'"),
    ("times = [0.0, 60.0, 120.0, 180.0, 240.0, 300.0]", "times = [0.0, 60.0, 60.0, 180.0, 240.0, 300.0]",
     r"key 'times' in section \[tracking\] .*strictly increasing"),
    ("times = [0.0", "start = 0.0\ntimes = [0.0",
     r"key 'start' in section \[tracking\]: give either times or"),
    ("noise = false", "noise = true", r"missing key 'seed' in section \[tracking\]"),
    ('frame = "inertial"', 'frame = "geodetic"', r"key 'position' .*not a key of frame = 'geodetic'"),
    ('frame = "inertial"', 'frame = "inertal"',
     r"key 'frame' .*must be one of \['geodetic', 'inertial'\]"),
    ("position = [5463.14996", "lat = 1.0\nposition = [5463.14996",
     r"key 'lat' .*not a key of frame = 'inertial'"),
    ('[truth]\nj2 = false', '[truth]\nj2 = true',
     r"key 'propagator' in section \[truth\]: 'kepler' .*j2 = false"),
])
def test_bad_od_paper_files(tmp_path, old, new, message):
    with pytest.raises(satgnc.FileFormatError, match=message):
        mission.load(_bad(tmp_path, old, new))


def test_inertial_station_without_position(tmp_path):
    p = _bad(tmp_path, "position = [5463.14996, 2139.12637, 2493.7785]", "")
    with pytest.raises(satgnc.FileFormatError,
                       match=r"missing key 'position' .*frame = 'inertial' needs position"):
        mission.load(p)
