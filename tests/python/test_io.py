"""satgnc.io: CCSDS TDM (KVN + XML), OEM and OPM through the Python API.

Checks: the standards' example files (tests/data/ccsds, provenance in each file's second line) parse
to the printed numbers, compared with an independent regex + float() reading of the same file;
write -> read round trips keep every value bit for bit (tolerance 0: the writer prints the shortest
text that reads back to the same double); every bad-input case raises satgnc.FileFormatError whose
path, line and key name the file, the line and the keyword."""

from __future__ import annotations

import dataclasses
import pathlib
import re

import numpy as np
import pytest
import satgnc
import satgnc.time
from _ccsds import DATA, estimated_oem, leo_metadata, two_way_tdm
from _ccsds import assert_same as _assert_same
from satgnc import io


def _kvn_data_lines(path: pathlib.Path) -> list[tuple[str, str, float]]:
    """Independent reading of a TDM KVN data section: (keyword, epoch, float(value)) of every line
    'KEY = epoch value' between DATA_START and DATA_STOP."""
    out, inside = [], False
    for line in path.read_text().splitlines():
        s = line.strip()
        if s in ("DATA_START", "DATA_STOP"):
            inside = s == "DATA_START"
            continue
        m = re.fullmatch(r"([A-Z0-9_]+)\s*=\s*(\S+)\s+(\S+)", s)
        if inside and m:
            out.append((m.group(1), m.group(2), float(m.group(3))))
    return out


def test_tdm_standard_example_matches_an_independent_reading() -> None:
    path = DATA / "tdm_jaxa.kvn"
    t = io.read_tdm(path)
    seg = t.segments[0]
    expected = _kvn_data_lines(path)
    assert len(expected) == 20
    assert list(zip(seg.keywords, seg.epochs, seg.values.tolist())) == expected  # exact
    m = seg.metadata
    assert (m.time_system, m.participants, m.mode, m.path) == (
        "UTC",
        ("NORTH", "F07R07", "E7"),
        "SEQUENTIAL",
        (1, 2, 3, 2, 1),
    )
    assert (m.range_units, m.angle_type, m.integration_interval) == ("km", "AZEL", 1.0)
    assert ("CORRECTION_RANGE", "2.0") in m.other
    assert seg.units[:5] == ("km", "deg", "deg", "Hz", "Hz")
    epochs, ranges = seg.select("RANGE")
    assert epochs[-1] == "1998-06-10T00:57:44"
    assert ranges.tolist() == [80452.7542, 80452.7368, 80452.7197, 80452.6331]
    assert not seg.values.flags.writeable  # frozen result


def test_tdm_xml_example_equals_the_kvn_example() -> None:
    x = io.read_tdm(DATA / "tdm_jaxa.xml")
    k = io.read_tdm(DATA / "tdm_jaxa.kvn")
    _assert_same(x.segments, k.segments, "segments")
    assert x.header.version == "2.0" and k.header.version == "1.0"


def test_tdm_one_way_example() -> None:
    seg = io.read_tdm(DATA / "tdm_dsn_oneway.kvn").segments[0]
    assert seg.metadata.path == (2, 1)
    assert list(zip(seg.keywords, seg.epochs, seg.values.tolist())) == _kvn_data_lines(
        DATA / "tdm_dsn_oneway.kvn"
    )


@pytest.mark.parametrize("fmt", ["kvn", "xml"])
def test_tdm_round_trip_keeps_every_value(tmp_path: pathlib.Path, fmt: str) -> None:
    for name, t in [("example", io.read_tdm(DATA / "tdm_jaxa.kvn")), ("two_way", two_way_tdm())]:
        path = io.write_tdm(tmp_path / f"{name}.{fmt}", t, format=fmt)
        back = io.read_tdm(path)
        if name == "two_way":  # units are filled in by the reader
            assert back.segments[0].units[:4] == ("km", "km/s", "deg", "deg")
            t = dataclasses.replace(
                t, segments=(dataclasses.replace(t.segments[0], units=back.segments[0].units),)
            )
        _assert_same(back, t, name)


def test_oem_standard_example_and_round_trip(tmp_path: pathlib.Path) -> None:
    o = io.read_oem(DATA / "oem_mgs.kvn")
    assert len(o.segments) == 2
    s1 = o.segments[1]
    assert s1.states[0].tolist() == [-2432.166, -63.042, 1742.754, 7.33702, -3.495867, -1.041945]
    assert s1.accelerations is None
    cov = s1.covariances[0].matrix
    assert (
        cov[0, 0] == 3.3313494e-04 and cov[5, 5] == 6.2244443e-10 and cov[0, 1] == cov[1, 0] == 4.6189273e-04
    )
    _assert_same(io.read_oem(io.write_oem(tmp_path / "mgs.oem", o)), o, "mgs")
    # An estimated trajectory with accelerations on some lines and a covariance per point.
    est = estimated_oem(seed=5, day="02", n_cov=2, no_acceleration_row=2)
    _assert_same(io.read_oem(io.write_oem(tmp_path / "est.oem", est)), est, "est")


def test_opm_standard_examples_and_round_trip(tmp_path: pathlib.Path) -> None:
    o = io.read_opm(DATA / "opm_eutelsat.kvn")
    assert o.state.tolist() == [6655.9942, -40218.5751, -82.9177, 3.11548208, 0.47042605, -0.00101495]
    assert o.keplerian is not None and o.keplerian.true_anomaly == 41.922339 and o.keplerian.gm == 398600.4415
    assert o.spacecraft is not None and o.spacecraft.mass == 1913.0
    assert [m.ref_frame for m in o.maneuvers] == ["J2000", "RTN"]
    assert o.maneuvers[0].dv == (-0.023257, 0.0168316, -0.00893444)
    c = io.read_opm(DATA / "opm_osprey_cov.kvn")
    assert c.covariance is not None and c.covariance[5, 5] == 6.2244443386355e-10
    for name in ("opm_godzilla.kvn", "opm_eutelsat.kvn", "opm_osprey_cov.kvn"):
        m = io.read_opm(DATA / name)
        _assert_same(io.read_opm(io.write_opm(tmp_path / name, m)), m, name)
    new = dataclasses.replace(
        c,
        state=c.state / 7.0,
        time_system="TT",
        keplerian=io.OpmKeplerian(7000.0, 1e-3, 51.6, 10.0, 20.0, 398600.4418, mean_anomaly=1 / 3),
    )
    _assert_same(io.read_opm(io.write_opm(tmp_path / "new.opm", new)), new, "new")


TDM_BASE = """CCSDS_TDM_VERS = 2.0
CREATION_DATE = 2026-01-01T00:00:00
ORIGINATOR = SATGNC
META_START
TIME_SYSTEM = UTC
PARTICIPANT_1 = STATION
PARTICIPANT_2 = SAT
MODE = SEQUENTIAL
PATH = 1,2,1
RANGE_UNITS = km
ANGLE_TYPE = AZEL
META_STOP
DATA_START
RANGE = 2026-01-01T00:00:00 1000.5
ANGLE_1 = 2026-01-01T00:00:00 10.25
DATA_STOP
"""


def _with_line(n: int, text: str) -> str:
    lines = TDM_BASE.splitlines()
    if text:
        lines[n - 1] = text
    else:
        del lines[n - 1]
    return "\n".join(lines) + "\n"


# (id, line replaced, replacement, line named, keyword named, rule fragment)
BAD_TDM = [
    ("unknown-time-system", 5, "TIME_SYSTEM = XYZ", 5, "TIME_SYSTEM", "unknown time system 'XYZ'"),
    ("missing-time-system", 5, "", 11, "TIME_SYSTEM", "missing mandatory keyword"),
    ("unknown-data-keyword", 14, "RANGEX = 2026-01-01T00:00:00 1.0", 14, "RANGEX", "unknown data keyword"),
    ("unknown-meta-keyword", 10, "RANGE_UNIT = km", 10, "RANGE_UNIT", "unknown metadata keyword"),
    ("path-vs-participants", 9, "PATH = 1,3,1", 9, "PATH", "names participant 3"),
    ("unsupported-range-units", 10, "RANGE_UNITS = s", 10, "RANGE_UNITS", "unsupported range unit 's'"),
    ("unsupported-angle-type", 11, "ANGLE_TYPE = XSYE", 11, "ANGLE_TYPE", "unsupported angle type"),
    ("non-numeric", 14, "RANGE = 2026-01-01T00:00:00 1O00.5", 14, "RANGE", "not a number: '1O00.5'"),
    ("bad-epoch", 15, "ANGLE_1 = 2026-02-30T00:00:00 1", 15, "ANGLE_1", "day out of range"),
]


@pytest.mark.parametrize(
    ("case", "n", "text", "line", "key", "fragment"), BAD_TDM, ids=[c[0] for c in BAD_TDM]
)
def test_bad_tdm_names_file_line_keyword(
    tmp_path: pathlib.Path, case: str, n: int, text: str, line: int, key: str, fragment: str
) -> None:
    path = tmp_path / f"{case}.tdm"
    path.write_text(_with_line(n, text))
    with pytest.raises(satgnc.FileFormatError) as e:
        io.read_tdm(path)
    assert (e.value.path, e.value.line, e.value.key) == (path, line, key)
    assert str(e.value).startswith(f"{path}:{line}: {key}: ")
    assert fragment in str(e.value)
    assert isinstance(e.value, ValueError)


def test_bad_tdm_xml_names_the_line(tmp_path: pathlib.Path) -> None:
    xml = io.format_tdm(io.parse_tdm(TDM_BASE), format="xml").replace(
        "<PATH>1,2,1</PATH>", "<PATH>2,5</PATH>"
    )
    path = tmp_path / "bad.xml"
    path.write_text(xml)
    line = 1 + xml[: xml.index("<PATH>")].count("\n")
    with pytest.raises(satgnc.FileFormatError, match=r"PATH: path '2,5' names participant 5") as e:
        io.read_tdm(path)
    assert (e.value.line, e.value.key) == (line, "PATH")


def test_bad_oem_and_opm_name_file_line_keyword(tmp_path: pathlib.Path) -> None:
    text = (DATA / "oem_mgs.kvn").read_text().replace("-336.859", "-336.8x9")
    path = tmp_path / "bad.oem"
    path.write_text(text)
    with pytest.raises(satgnc.FileFormatError, match=r"EPHEMERIS: not a number: '-336.8x9'") as e:
        io.read_oem(path)
    assert e.value.line == 1 + text[: text.index("-336.8x9")].count("\n")
    text = (DATA / "opm_godzilla.kvn").read_text().replace("TIME_SYSTEM    = UTC", "TIME_SYSTEM    = SCLK")
    path = tmp_path / "bad.opm"
    path.write_text(text)
    with pytest.raises(
        satgnc.FileFormatError, match=r"bad.opm:11: TIME_SYSTEM: unsupported time system 'SCLK'"
    ):
        io.read_opm(path)


def test_writers_and_models_refuse_invalid_input(tmp_path: pathlib.Path) -> None:
    t = io.parse_tdm(TDM_BASE)
    bad = dataclasses.replace(
        t,
        segments=(
            dataclasses.replace(
                t.segments[0], metadata=dataclasses.replace(t.segments[0].metadata, path=(1, 3, 1))
            ),
        ),
    )
    with pytest.raises(ValueError, match=r"tdm: not a valid TDM: PATH: path '1,3,1' names participant 3"):
        io.write_tdm(tmp_path / "x.tdm", bad)
    with pytest.raises(ValueError, match=r"time_system: must be one of"):
        dataclasses.replace(t.segments[0].metadata, time_system="UT1")
    with pytest.raises(ValueError, match=r"format: must be one of \['kvn', 'xml'\]"):
        io.format_tdm(t, format="json")
    with pytest.raises(ValueError, match=r"keywords, epochs, values: must have the same length"):
        dataclasses.replace(t.segments[0], values=np.zeros(3))
    with pytest.raises(ValueError, match=r"matrix: must be symmetric"):
        io.OemCovariance(epoch="2026-01-01T00:00:00", matrix=np.triu(np.ones((6, 6))))
    with pytest.raises(ValueError, match=r"epochs: epochs must not be empty strings"):
        dataclasses.replace(t.segments[0], epochs=("", "2026-01-01T00:00:00"))
    with pytest.raises(TypeError, match=r"tdm: must be a satgnc.io.Tdm"):
        io.format_tdm("not a tdm")  # type: ignore[arg-type]
    with pytest.raises(FileNotFoundError, match=r"path: .* does not exist"):
        io.read_tdm(tmp_path / "missing.tdm")
    with pytest.raises(TypeError, match=r"path: must be a file path"):
        io.read_oem(42)  # type: ignore[arg-type]


def test_epoch_seconds_and_epochs_at_count_leap_seconds() -> None:
    # 2016-12-31 had a leap second: 23:59:59 -> 00:00:00 is 2 s (exact); TAI has none.
    assert io.epoch_seconds(["2017-01-01T00:00:00"], "2016-12-31T23:59:59").tolist() == [2.0]
    assert io.epoch_seconds(["2017-01-01T00:00:00"], "2016-12-31T23:59:59", "TAI").tolist() == [1.0]
    assert io.epochs_at("2016-12-31T23:59:59", [1.0, 1.5, 2.0]) == (
        "2016-12-31T23:59:60",
        "2016-12-31T23:59:60.5",
        "2017-01-01T00:00:00",
    )
    seg = io.read_tdm(DATA / "tdm_jaxa.kvn").segments[0]
    np.testing.assert_array_equal(seg.seconds_since("1998-06-10T00:57:37")[::5], [0.0, 1.0, 2.0, 7.0])
    times = seg.times()  # satgnc.time.Epoch instants (the time parcel's Python Epoch)
    assert times[19] - times[0] == 7.0
    assert times[0] == satgnc.time.parse("1998-06-10T00:57:37", "UTC")
    with pytest.raises(ValueError, match=r"epochs\[1\]: .*2026-06-30T23:59:60"):
        io.epoch_seconds(["2026-06-30T23:59:59", "2026-06-30T23:59:60"], "2026-06-30T00:00:00")
    with pytest.raises(ValueError, match=r"time_system: must be one of"):
        io.epochs_at("2026-01-01T00:00:00", [0.0], "UT1")


def test_propagated_trajectory_written_as_oem(tmp_path: pathlib.Path) -> None:
    """A Kepler arc from satgnc.propagate, with its times turned into epochs across the 2016 leap
    second, written and read back: states bit-identical, times recovered exactly."""
    x0 = np.array([6778.137, 0.0, 0.0, 0.0, 7.6686, 0.1])
    times = np.arange(0.0, 600.0, 60.0)
    traj = satgnc.propagate(x0, times, method="kepler", with_stm=False)
    origin = "2016-12-31T23:55:00.125"
    epochs = io.epochs_at(origin, times)
    assert epochs[5] == "2016-12-31T23:59:60.125"  # 300 s later, inside the leap second
    meta = leo_metadata(epochs[0], epochs[-1])
    seg = io.OemSegment(metadata=meta, epochs=epochs, states=traj.states)
    oem = io.Oem(header=io.Header(creation_date="2026-12-02T00:00:00", originator="SATGNC"), segments=(seg,))
    back = io.read_oem(io.write_oem(tmp_path / "traj.oem", oem))
    np.testing.assert_array_equal(back.segments[0].states, traj.states)  # exact (shortest round-trip text)
    np.testing.assert_array_equal(io.epoch_seconds(back.segments[0].epochs, origin), times)  # exact
    t = back.segments[0].times()
    assert [ti - t[0] for ti in t] == times.tolist()
