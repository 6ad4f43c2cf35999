"""Bad observation files (CSV, CCSDS TDM KVN) and bad ``od.simulate`` arguments: every row is an
input written by the test into tmp_path -> exception type + message fragment. File errors name the
file and the line (``<name>:<line>:``), and the column or keyword."""

from __future__ import annotations

import datetime as dt

import numpy as np
import pytest
import satgnc
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as hs
from satgnc import od
from satgnc.od.tdm import read_tdm, write_tdm
from satgnc.papers import od_newton_raphson as paper

HEADER = "t,type,value,sigma,station"
ROW = "0,range,1321.1,0.001,0"
ROW2 = "10,range_rate,-2.5,1e-6,0"

# (id, file bytes or text, exception type, fragments that must all appear in str(err))
CSV_CASES = [
    ("empty", "", satgnc.FileFormatError, ["empty file"]),
    ("blank-lines-only", "\n\n  \n", satgnc.FileFormatError, ["empty file"]),
    ("comments-only", "# nothing\n", satgnc.FileFormatError, ["empty file"]),
    ("header-only", HEADER + "\n", satgnc.FileFormatError, ["no observations after the header"]),
    (
        "missing-column",
        "t,type,value\n0,range,1\n",
        satgnc.FileFormatError,
        [":1:", "missing column", "sigma"],
    ),
    (
        "duplicate-column",
        "t,type,value,sigma,value\n",
        satgnc.FileFormatError,
        [":1:", "'value' appears twice"],
    ),
    (
        "unknown-column-typo",
        "t,type,value,sigma,staton\n",
        satgnc.FileFormatError,
        [":1:", "unknown column 'staton'", "did you mean 'station'"],
    ),
    ("empty-header-cell", "t,type,,value,sigma\n", satgnc.FileFormatError, [":1:", "column 3 has no name"]),
    (
        "too-few-cells",
        f"{HEADER}\n0,range,1321.1,0.001\n",
        satgnc.FileFormatError,
        [":2:", "expected 5 cells", "got 4"],
    ),
    ("too-many-cells", f"{HEADER}\n{ROW},7\n", satgnc.FileFormatError, [":2:", "expected 5 cells", "got 6"]),
    (
        "non-numeric-t",
        f"{HEADER}\nabc,range,1,0.001,0\n",
        satgnc.FileFormatError,
        [":2:", "column 't'", "'abc'"],
    ),
    (
        "non-numeric-value",
        f"{HEADER}\n{ROW}\n5,range,x1,0.001,0\n",
        satgnc.FileFormatError,
        [":3:", "column 'value'", "not a number"],
    ),
    (
        "nan-value",
        f"{HEADER}\n0,range,nan,0.001,0\n",
        satgnc.FileFormatError,
        [":2:", "column 'value'", "finite"],
    ),
    ("inf-t", f"{HEADER}\ninf,range,1,0.001,0\n", satgnc.FileFormatError, [":2:", "column 't'", "finite"]),
    (
        "inf-sigma",
        f"{HEADER}\n0,range,1,-inf,0\n",
        satgnc.FileFormatError,
        [":2:", "column 'sigma'", "finite"],
    ),
    (
        "negative-range",
        f"{HEADER}\n{ROW}\n5,range,-1321.1,0.001,0\n",
        satgnc.FileFormatError,
        [":3:", "range must be > 0"],
    ),
    ("zero-range", f"{HEADER}\n5,range,0,0.001,0\n", satgnc.FileFormatError, [":2:", "range must be > 0"]),
    ("zero-sigma", f"{HEADER}\n5,range,1,0,0\n", satgnc.FileFormatError, [":2:", "column 'sigma'", "> 0"]),
    ("negative-sigma", f"{HEADER}\n5,range,1,-1e-3,0\n", satgnc.FileFormatError, [":2:", "column 'sigma'"]),
    ("unknown-type", f"{HEADER}\n0,angle,1,0.001,0\n", satgnc.FileFormatError, [":2:", "column 'type'"]),
    (
        "negative-station",
        f"{HEADER}\n0,range,1,0.001,-1\n",
        satgnc.FileFormatError,
        [":2:", "column 'station'", "[0, 2^31 - 1)"],
    ),
    (
        "float-station",
        f"{HEADER}\n0,range,1,0.001,1.5\n",
        satgnc.FileFormatError,
        [":2:", "column 'station'", "integer"],
    ),
    (
        "station-overflow",
        f"{HEADER}\n0,range,1,0.001,9999999999999999999\n",
        satgnc.FileFormatError,
        [":2:", "column 'station'", "2^31"],
    ),
    ("station-empty-cell", f"{HEADER}\n0,range,1,0.001,\n", satgnc.FileFormatError, [":2:", "empty cell"]),
    ("underscore-number", f"{HEADER}\n0,range,1_000,0.001,0\n", satgnc.FileFormatError, [":2:", "'1_000'"]),
    ("sigma-underflow", f"{HEADER}\n0,range,1,1e-320,0\n", satgnc.FileFormatError, [":2:", "too small"]),
    (
        "duplicate-row",
        f"{HEADER}\n{ROW}\n{ROW2}\n{ROW}\n",
        satgnc.FileFormatError,
        [":4:", "duplicate observation", "line 2"],
    ),
    (
        "duplicate-row-spelled-differently",
        f"{HEADER}\n{ROW}\n0.0,range,1400,0.001,0\n",
        satgnc.FileFormatError,
        [":3:", "duplicate", "line 2"],
    ),
    (
        "line-numbers-count-comments",
        f"# a comment\n\n{HEADER}\n# another\n{ROW}\n5,range,oops,1,0\n",
        satgnc.FileFormatError,
        [":6:", "column 'value'"],
    ),
    (
        "crlf-line-numbers",
        f"{HEADER}\r\n{ROW}\r\n5,range,-2,0.001,0\r\n",
        satgnc.FileFormatError,
        [":3:", "range"],
    ),
    (
        "latin1-bytes",
        (HEADER + "\n# caf\xe9\n" + ROW + "\n").encode("latin-1"),
        satgnc.FileFormatError,
        [":2:", "not UTF-8", "0xe9"],
    ),
    ("binary", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", satgnc.FileFormatError, ["binary file"]),
]


def _write(tmp_path, name, content):
    p = tmp_path / name
    if isinstance(content, bytes):
        p.write_bytes(content)
    else:
        p.write_bytes(content.encode("utf-8"))
    return p


@pytest.mark.parametrize("name,content,exc,frags", CSV_CASES, ids=[c[0] for c in CSV_CASES])
def test_csv_bad_content(tmp_path, name, content, exc, frags):
    p = _write(tmp_path, "obs.csv", content)
    with pytest.raises(exc) as ei:
        od.read_csv(p)
    msg = str(ei.value)
    assert isinstance(ei.value, ValueError)  # FileFormatError is a ValueError
    assert str(p) in msg
    for f in frags:
        assert f in msg, (f, msg)
    assert ei.value.path == p
    if frags[0].startswith(":"):
        assert ei.value.line == int(frags[0].strip(":"))


# Accepted variants: BOM, CRLF, any column order, comments, blank lines, unsorted times, UTF-16.
CSV_OK = [
    ("bom", "\ufeff" + f"{HEADER}\n{ROW}\n{ROW2}\n", 2),
    ("crlf", f"{HEADER}\r\n{ROW}\r\n{ROW2}\r\n", 2),
    ("column-order-and-no-station", "sigma,value,type,t\n0.001,1321.1,range,0\n", 1),
    ("upper-case-header-spaces", " T , Type , VALUE , sigma \n0,range,1321.1,0.001\n", 1),
    ("unsorted-times", f"{HEADER}\n{ROW2}\n{ROW}\n", 2),
    ("same-time-other-type", f"{HEADER}\n{ROW}\n0,range_rate,1,1e-6,0\n", 2),
    ("same-time-other-station", f"{HEADER}\n{ROW}\n0,range,1400,0.001,1\n", 2),
]


@pytest.mark.parametrize("name,content,n", CSV_OK, ids=[c[0] for c in CSV_OK])
def test_csv_accepted_variants(tmp_path, name, content, n):
    obs = od.read_csv(_write(tmp_path, "ok.csv", content))
    assert len(obs) == n
    assert np.all(obs.value[np.array(obs.type_names()) == "range"] > 0)


def test_csv_utf16_with_bom(tmp_path):
    p = tmp_path / "u16.csv"
    p.write_bytes(f"{HEADER}\n{ROW}\n".encode("utf-16"))
    assert len(od.read_csv(p)) == 1


TDM_GOOD = [
    "CCSDS_TDM_VERS = 2.0",
    "CREATION_DATE = 2026-01-01T00:00:00",
    "ORIGINATOR = TEST",
    "META_START",
    "TIME_SYSTEM = UTC",
    "PARTICIPANT_1 = GZ",
    "PARTICIPANT_2 = SAT",
    "RANGE_UNITS = km",
    "META_STOP",
    "DATA_START",
    "RANGE = 1981-080T06:00:00 1321.104",
    "DOPPLER_INSTANTANEOUS = 1981-080T06:00:00 -2.5",
    "RANGE = 1981-080T06:00:10 1300.0",
    "DATA_STOP",
]


def _tdm(replace: dict[int, str | None] | None = None, insert: dict[int, str] | None = None) -> str:
    """TDM_GOOD with 1-based line ``k`` replaced (None deletes) or a line inserted before ``k``."""
    lines = list(TDM_GOOD)
    for k, v in sorted((insert or {}).items(), reverse=True):
        lines.insert(k - 1, v)
    for k, v in (replace or {}).items():
        lines[k - 1] = v
    return "\n".join(x for x in lines if x is not None) + "\n"


TDM_CASES = [
    ("empty", "", ["incomplete file", "no META_START"]),
    ("header-only", "CCSDS_TDM_VERS = 2.0\n", ["incomplete file", "no META_START"]),
    ("version-not-first", _tdm({1: "ORIGINATOR = X", 3: "CCSDS_TDM_VERS = 2.0"}), [":1:", "must come first"]),
    ("bad-version", _tdm({1: "CCSDS_TDM_VERS = abc"}), [":1:", "CCSDS_TDM_VERS", "unsupported version"]),
    ("unknown-header-keyword", _tdm({3: "ORIGINATR = X"}), [":3:", "ORIGINATR", "did you mean ORIGINATOR"]),
    ("malformed-line", _tdm({11: "RANGE 1981-080T06:00:00 1321.104"}), [":11:", "malformed line"]),
    ("missing-value", _tdm({11: "RANGE = 1981-080T06:00:00"}), [":11:", "RANGE", "'<epoch> <value>'"]),
    (
        "unsupported-data",
        _tdm({11: "ANGLE_1 = 1981-080T06:00:00 12.0"}),
        [":11:", "ANGLE_1", "not supported"],
    ),
    ("bad-epoch", _tdm({11: "RANGE = 1981-13-80T06:00:00 1.0"}), [":11:", "bad epoch"]),
    ("non-numeric-value", _tdm({11: "RANGE = 1981-080T06:00:00 12,5"}), [":11:", "not a number", "'12,5'"]),
    ("day-366-common-year", _tdm({11: "RANGE = 1981-366T00:00:00 1.0"}), [":11:", "1981 has no day 366"]),
    ("leap-second", _tdm({11: "RANGE = 1981-080T23:59:60 1.0"}), [":11:", "leap second"]),
    ("lower-case-keyword", _tdm({11: "range = 1981-080T06:00:00 1.0"}), [":11:", "must be upper case"]),
    ("repeated-header", _tdm({2: "CCSDS_TDM_VERS = 2.0"}), [":2:", "repeated in the header", "line 1"]),
    ("nan-value", _tdm({12: "DOPPLER_INSTANTANEOUS = 1981-080T06:00:00 NaN"}), [":12:", "finite"]),
    ("negative-range", _tdm({13: "RANGE = 1981-080T06:00:10 -1300.0"}), [":13:", "RANGE", "> 0 km"]),
    ("zero-range", _tdm({13: "RANGE = 1981-080T06:00:10 0"}), [":13:", "> 0 km"]),
    (
        "duplicate-observation",
        _tdm({13: "RANGE = 1981-080T06:00:00 1321.2"}),
        [":13:", "duplicate RANGE", "line 11"],
    ),
    ("time-system", _tdm({5: "TIME_SYSTEM = TAI"}), [":5:", "TIME_SYSTEM TAI", "UTC"]),
    ("range-units", _tdm({8: "RANGE_UNITS = RU"}), [":8:", "RANGE_UNITS RU"]),
    ("no-time-system", _tdm({5: None}), [":8:", "without TIME_SYSTEM"]),
    ("no-participant", _tdm({6: None}), [":8:", "without PARTICIPANT_1"]),
    ("empty-participant", _tdm({6: "PARTICIPANT_1 ="}), [":6:", "PARTICIPANT_1 must name"]),
    (
        "unknown-meta-keyword",
        _tdm({7: "PARTICIPANT2 = SAT"}),
        [":7:", "PARTICIPANT2", "did you mean PARTICIPANT_2"],
    ),
    ("repeated-meta-keyword", _tdm(insert={8: "TIME_SYSTEM = UTC"}), [":8:", "repeated", "line 5"]),
    (
        "range-correction",
        _tdm(insert={9: "CORRECTION_RANGE = 0.012"}),
        [":9:", "CORRECTION_RANGE", "not supported"],
    ),
    ("receive-delay", _tdm(insert={9: "RECEIVE_DELAY_1 = 1e-6"}), [":9:", "RECEIVE_DELAY_1"]),
    ("non-numeric-delay", _tdm(insert={9: "TRANSMIT_DELAY_1 = soon"}), [":9:", "not a number"]),
    ("corrections-applied-value", _tdm(insert={9: "CORRECTIONS_APPLIED = MAYBE"}), [":9:", "YES or NO"]),
    ("keyword-outside-section", _tdm(insert={10: "RANGE = 1981-080T06:00:00 1.0"}), [":10:", "outside"]),
    ("unexpected-data-start", _tdm({9: "DATA_START"}), [":9:", "unexpected DATA_START"]),
    ("no-data-stop", _tdm({14: None}), [":13:", "no DATA_STOP"]),
    ("no-data", _tdm({11: None, 12: None, 13: None}), ["no RANGE or DOPPLER_INSTANTANEOUS data"]),
    ("latin1", _tdm({3: "ORIGINATOR = CAF\xc9"}).encode("latin-1"), [":3:", "not UTF-8"]),
    ("binary", b"CCSDS_TDM_VERS = 2.0\n\x00\x01\x02", [":2:", "binary file"]),
]


@pytest.mark.parametrize("name,content,frags", TDM_CASES, ids=[c[0] for c in TDM_CASES])
def test_tdm_bad_content(tmp_path, name, content, frags):
    p = _write(tmp_path, "obs.tdm", content)
    with pytest.raises(satgnc.FileFormatError) as ei:
        read_tdm(p)
    msg = str(ei.value)
    assert str(p) in msg
    for f in frags:
        assert f in msg, (f, msg)


TDM_OK = [
    ("bom-crlf", "\ufeff" + _tdm().replace("\n", "\r\n"), 3),
    ("comments-and-blank-lines", _tdm(insert={4: "COMMENT pass 1", 11: ""}), 3),
    ("corrections-applied", _tdm(insert={9: "CORRECTION_RANGE = 0.012\nCORRECTIONS_APPLIED = YES"}), 3),
    ("zero-delay", _tdm(insert={9: "TRANSMIT_DELAY_1 = 0.0"}), 3),
    (
        "unsorted-epochs",
        _tdm({11: "RANGE = 1981-080T06:00:10 1300.0", 13: "RANGE = 1981-080T06:00:00 1321.104"}),
        3,
    ),
]


@pytest.mark.parametrize("name,content,n", TDM_OK, ids=[c[0] for c in TDM_OK])
def test_tdm_accepted_variants(tmp_path, name, content, n):
    obs, names, epoch = read_tdm(_write(tmp_path, "ok.tdm", content))
    assert len(obs) == n and names == ["GZ"]
    assert epoch == dt.datetime(1981, 3, 21, 6)
    assert sorted(obs.t) == [0.0, 0.0, 10.0]


# Arguments of the readers (not the file content) name the argument.
ARG_CASES = [
    ("missing-csv", lambda d: od.read_csv(d / "nope.csv"), FileNotFoundError, ["nope.csv", "does not exist"]),
    ("missing-tdm", lambda d: read_tdm(d / "nope.tdm"), FileNotFoundError, ["nope.tdm", "does not exist"]),
    ("directory-csv", lambda d: od.read_csv(d), IsADirectoryError, ["is a directory"]),
    ("directory-tdm", lambda d: read_tdm(d), IsADirectoryError, ["is a directory"]),
    ("path-type", lambda d: od.read_csv(3), TypeError, ["path: must be a file path"]),
    ("path-empty", lambda d: od.read_csv(""), ValueError, ["path: must not be empty"]),
    (
        "sigma-zero",
        lambda d: read_tdm(d / "ok.tdm", sigma_range=0.0),
        ValueError,
        ["sigma_range: must be > 0"],
    ),
    (
        "sigma-bool",
        lambda d: read_tdm(d / "ok.tdm", sigma_range=True),
        TypeError,
        ["sigma_range: must be a real"],
    ),
    (
        "sigma-nan",
        lambda d: read_tdm(d / "ok.tdm", sigma_range_rate=float("nan")),
        ValueError,
        ["sigma_range_rate: must be finite"],
    ),
    ("epoch-garbage", lambda d: read_tdm(d / "ok.tdm", epoch="yesterday"), ValueError, ["epoch: not a UTC"]),
    ("epoch-number", lambda d: read_tdm(d / "ok.tdm", epoch=2444684.75), TypeError, ["epoch: must be None"]),
]


@pytest.mark.parametrize("name,call,exc,frags", ARG_CASES, ids=[c[0] for c in ARG_CASES])
def test_reader_arguments(tmp_path, name, call, exc, frags):
    _write(tmp_path, "ok.tdm", _tdm())
    with pytest.raises(exc) as ei:
        call(tmp_path)
    for f in frags:
        assert f in str(ei.value), (f, str(ei.value))


def test_tdm_epoch_forms(tmp_path):
    p = _write(tmp_path, "ok.tdm", _tdm())
    for epoch in (
        "1981-03-21T05:59:50",
        "1981-080T05:59:50",
        dt.datetime(1981, 3, 21, 5, 59, 50),
        dt.datetime(1981, 3, 21, 7, 59, 50, tzinfo=dt.timezone(dt.timedelta(hours=2))),
    ):
        obs, _, e = read_tdm(p, epoch=epoch)
        assert e == dt.datetime(1981, 3, 21, 5, 59, 50)
        assert sorted(obs.t) == [10.0, 10.0, 20.0]


def test_file_format_error_attributes(tmp_path):
    p = _write(tmp_path, "a.csv", f"{HEADER}\n5,range,-1,0.001,0\n")
    with pytest.raises(satgnc.FileFormatError) as ei:
        od.read_csv(p)
    e = ei.value
    assert (e.path, e.line, e.key) == (p, 2, "value")
    assert str(e) == f"{p}:2: {e.reason}"
    import pickle

    assert str(pickle.loads(pickle.dumps(e))) == str(e)


_OBS2 = od.Observations([0.0, 10.0], "range", [1000.0, 1001.0], 1e-3, [0, 1])
_EP = dt.datetime(1981, 3, 21, 6)
WRITE_CASES = [
    ("names-too-few", dict(station_names=["A"]), ValueError, ["station_names", "index 1", "only 1 name"]),
    ("names-duplicate", dict(station_names=["A", "A"]), ValueError, ["station_names: names must be unique"]),
    ("name-empty", dict(station_names=["A", " "]), ValueError, ["not a valid PARTICIPANT_1"]),
    ("name-newline", dict(station_names=["A", "B\nDATA_STOP"]), ValueError, ["not a valid PARTICIPANT_1"]),
    ("names-string", dict(station_names="AB"), TypeError, ["station_names: must be a list"]),
    ("epoch-string", dict(epoch="1981-03-21"), TypeError, ["epoch: must be a datetime"]),
    ("observations-list", dict(observations=[1, 2]), TypeError, ["observations: must be an Observations"]),
    ("originator-empty", dict(originator=""), ValueError, ["originator"]),
]


@pytest.mark.parametrize("name,kw,exc,frags", WRITE_CASES, ids=[c[0] for c in WRITE_CASES])
def test_write_tdm_arguments(tmp_path, name, kw, exc, frags):
    args = dict(path=tmp_path / "w.tdm", observations=_OBS2, epoch=_EP, station_names=["A", "B"])
    args.update(kw)
    with pytest.raises(exc) as ei:
        write_tdm(**args)
    for f in frags:
        assert f in str(ei.value), (f, str(ei.value))
    assert not (tmp_path / "w.tdm").exists()  # nothing half-written


def test_write_tdm_two_stations_round_trip(tmp_path):
    obs, names, _ = read_tdm(write_tdm(tmp_path / "w.tdm", _OBS2, _EP, ["A", "B"]))
    assert names == ["A", "B"] and list(obs.station) == [0, 1]
    np.testing.assert_array_equal(obs.value, [1000.0, 1001.0])


def test_round_trips_still_hold(tmp_path):
    obs = od.simulate(paper.truth(), paper.station(), np.arange(0, 301, 20.0), seed=None)
    back, names, _ = read_tdm(write_tdm(tmp_path / "a.tdm", obs, dt.datetime(1981, 3, 21, 6), ["GZ"]))
    np.testing.assert_allclose(back.value, obs.value, rtol=1e-12)
    assert names == ["GZ"]


# od.simulate: every bad argument names itself.
X0 = paper.truth()
ST = paper.station()
T = np.arange(0.0, 301.0, 30.0)
SIM_CASES = [
    (
        "inside-earth",
        dict(x0=np.r_[6000.0, 0, 0, 0, 7.0, 0]),
        ValueError,
        ["x0:", "below the Earth's surface"],
    ),
    ("at-centre", dict(x0=np.zeros(6)), ValueError, ["x0:", "below the Earth's surface"]),
    (
        "dips-below-surface",
        dict(x0=np.r_[6500.0, 0, 0, 0, 2.0, 0], times=np.arange(0.0, 3000.0, 100.0)),
        ValueError,
        ["x0:", "goes below the Earth's surface", "t = "],
    ),
    ("mask-nan", dict(elevation_mask_deg=float("nan")), ValueError, ["elevation_mask_deg", "finite"]),
    ("mask-above-90", dict(elevation_mask_deg=95.0), ValueError, ["elevation_mask_deg", "<= 90"]),
    ("mask-bool", dict(elevation_mask_deg=True), TypeError, ["elevation_mask_deg"]),
    ("mask-drops-all", dict(elevation_mask_deg=89.9), ValueError, ["elevation_mask_deg", "no observation"]),
    ("types-empty", dict(types=[]), ValueError, ["types: must name at least one"]),
    ("types-unknown", dict(types=["range", "angle"]), ValueError, ["types[1]"]),
    ("types-repeated", dict(types=["range", "range"]), ValueError, ["types: a measurement type is repeated"]),
    ("types-number", dict(types=[3]), TypeError, ["types[0]"]),
    ("bias-nan", dict(bias_range=float("nan")), ValueError, ["bias_range: must be finite"]),
    ("bias-complex", dict(bias_range_rate=1j), TypeError, ["bias_range_rate"]),
    ("seed-negative", dict(seed=-1), ValueError, ["seed: must be >= 0"]),
    ("seed-float", dict(seed=1.5), TypeError, ["seed: must be an integer"]),
    ("sigma-zero", dict(sigma_range=0.0), ValueError, ["sigma_range: must be > 0"]),
    ("x0-complex", dict(x0=X0 + 0j), TypeError, ["x0: must be a real numeric array"]),
    ("x0-shape", dict(x0=X0[:5]), ValueError, ["x0: must have shape (6,)"]),
    ("times-bool", dict(times=np.ones(3, bool)), TypeError, ["times"]),
    ("times-empty", dict(times=[]), ValueError, ["times: must not be empty"]),
    ("times-unsorted", dict(times=[0.0, 20.0, 10.0]), ValueError, ["times: must be strictly increasing"]),
    ("times-nan", dict(times=[0.0, float("nan")]), ValueError, ["times: must be finite"]),
    ("mu-negative", dict(mu=-1.0), ValueError, ["mu: must be > 0"]),
]


@pytest.mark.parametrize("name,kw,exc,frags", SIM_CASES, ids=[c[0] for c in SIM_CASES])
def test_simulate_bad_arguments(name, kw, exc, frags):
    args = dict(x0=X0, stations=ST, times=T)
    args.update(kw)
    with pytest.raises(exc) as ei:
        od.simulate(**args)
    for f in frags:
        assert f in str(ei.value), (f, str(ei.value))


def test_simulate_accepts_single_type_string_and_mask():
    obs = od.simulate(X0, ST, T, types="range", elevation_mask_deg=0.0, seed=None)
    assert obs.type_names() == ["range"] * len(T)


# ----------------------------------------------------------------------------- properties

_CELLS = hs.sampled_from(
    [
        "0",
        "1.5",
        "-2",
        "1e3",
        "nan",
        "inf",
        "",
        " ",
        "abc",
        "range",
        "range_rate",
        "doppler",
        "0.001",
        "-0",
        "7",
        '"1"',
        "1_0",
        "1e400",
        "\u00e9",
    ]
)
_HEADERS = hs.sampled_from(
    [HEADER, "t,type,value,sigma", "sigma,value,type,t,station", "t,type,value", "t,t"]
)
_LINES = hs.one_of(
    hs.lists(_CELLS, min_size=0, max_size=7).map(",".join), hs.sampled_from(["# c", "", ROW, ROW2])
)
_PROPS = settings(
    max_examples=200, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


@_PROPS
@given(header=_HEADERS, lines=hs.lists(_LINES, max_size=6), crlf=hs.booleans())
def test_csv_property_valid_table_or_file_error(tmp_path, header, lines, crlf):
    """Any CSV text gives either a valid table (finite, ranges > 0, sigmas > 0, stations >= 0) or a
    FileFormatError naming the file; nothing else escapes."""
    p = tmp_path / "prop.csv"
    p.write_text(("\r\n" if crlf else "\n").join([header, *lines]))
    try:
        obs = od.read_csv(p)
    except satgnc.FileFormatError as e:
        assert str(e).startswith(str(p))
        return
    assert np.all(np.isfinite(obs.t)) and np.all(np.isfinite(obs.value))
    assert np.all(obs.sigma > 0) and np.all(obs.station >= 0)
    assert np.all(obs.value[np.array(obs.type_names()) == "range"] > 0)


_TDM_SUBS = hs.sampled_from(
    [
        "",
        "META_START",
        "META_STOP",
        "DATA_START",
        "DATA_STOP",
        "RANGE = 1981-080T06:00:05 1.0",
        "RANGE = 1981-080T06:00:05 -1.0",
        "DOPPLER_INSTANTANEOUS = 1981-080T06:00:05 nan",
        "TIME_SYSTEM = UTC",
        "PARTICIPANT_1 = B",
        "FOO = 1",
        "x",
        "COMMENT hi",
        "RANGE = 1981-366T06:00:05 1.0",
        "CORRECTION_RANGE = 1",
    ]
)


@_PROPS
@given(edits=hs.lists(hs.tuples(hs.integers(0, len(TDM_GOOD)), _TDM_SUBS, hs.booleans()), max_size=4))
def test_tdm_property_valid_or_file_error(tmp_path, edits):
    """Any line-level edit of a good TDM gives either valid observations or a FileFormatError with
    the file name."""
    lines = list(TDM_GOOD)
    for k, text, insert in edits:
        if insert or k >= len(lines):
            lines.insert(min(k, len(lines)), text)
        else:
            lines[k] = text
    p = tmp_path / "prop.tdm"
    p.write_text("\n".join(lines))
    try:
        obs, names, _ = read_tdm(p)
    except satgnc.FileFormatError as e:
        assert str(e).startswith(str(p))
        return
    assert len(obs) >= 1 and names
    assert np.all(np.isfinite(obs.value))
    assert np.all(obs.value[np.array(obs.type_names()) == "range"] > 0)


@_PROPS
@given(
    rows=hs.lists(
        hs.tuples(
            hs.floats(-1e6, 1e6, allow_nan=False),
            hs.booleans(),
            hs.floats(1e-3, 1e5),
            hs.floats(1e-9, 1.0),
            hs.integers(0, 3),
        ),
        min_size=1,
        max_size=20,
        unique_by=lambda r: (r[0], r[1], r[4]),
    )
)
def test_csv_property_round_trip(tmp_path, rows):
    """Rows written with full precision read back bit for bit, in file order."""
    p = tmp_path / "rt.csv"
    text = [HEADER] + [
        f"{t!r},{'range' if rng else 'range_rate'},{v!r},{s!r},{st}" for t, rng, v, s, st in rows
    ]
    p.write_text("\n".join(text) + "\n")
    obs = od.read_csv(p)
    np.testing.assert_array_equal(obs.t, [r[0] for r in rows])
    np.testing.assert_array_equal(obs.value, [r[2] for r in rows])
    np.testing.assert_array_equal(obs.sigma, [r[3] for r in rows])
    np.testing.assert_array_equal(obs.station, [r[4] for r in rows])
    assert obs.type_names() == ["range" if r[1] else "range_rate" for r in rows]
