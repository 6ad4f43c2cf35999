"""Every satgnc command: a user or library error prints ONE line ``satgnc: error: ...`` on stderr and
exits with code 2 (no traceback unless --debug); an internal bug prints one line and exits with 1.
Option values may be negative numbers, with or without ``=``."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from satgnc import cli
from satgnc.papers import od_newton_raphson as paper

GUESS = ",".join(f"{v:.9g}" for v in paper.truth() + np.array([10, 0, 0, 0, 0, 0]))
R0 = ",".join(f"{v:.9g}" for v in paper.station_state_table3()[:3])
NEG_GUESS = "-5846.89,-1265.616,3411.496,-0.3146,6.9401,-3.1125"


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("cli")
    for name in ("obs.csv", "obs.tdm"):
        argv = ["od", "simulate", "--out", str(d / name), "--duration", "300", "--step", "30"]
        assert cli.main(argv) == 0, argv
    (d / "neg.csv").write_text("t,type,value,sigma\n0,range,1000,0.001\n10,range,-5,0.001\n")
    (d / "st1.csv").write_text("t,type,value,sigma,station\n0,range,1000,0.001,1\n")
    text = _scenario_path().read_text()
    (d / "bad.toml").write_text(text.replace("mu = 3.99e14", "mu = true"))
    (d / "typo.toml").write_text(text.replace("[orbit]", "[orbt]"))
    (d / "sub").mkdir()
    return d


def _scenario_path():
    from satgnc.scenarios import l1_rendezvous as scen

    return scen.DEFAULT


SOLVE = ["od", "solve", "{d}/obs.csv", "--station-inertial", f"STATION:{R0}", "--guess"]

# (id, argv with {d} for the files directory, exit code, fragments of the one stderr line)
CASES = [
    # usage errors (argparse), one line
    ("unknown-command", ["fly"], 2, ["invalid choice: 'fly'"]),
    ("od-without-subcommand", ["od"], 2, ["choose a subcommand"]),
    (
        "missing-required",
        ["od", "solve", "{d}/obs.csv"],
        2,
        ["the following arguments are required: --guess"],
    ),
    ("unknown-option", ["od", "simulate", "--out", "{d}/x.csv", "--sed", "3"], 2, ["unrecognized arguments"]),
    ("bad-choice", [*SOLVE, GUESS, "--method", "newtn"], 2, ["argument --method", "invalid choice"]),
    (
        "max-iterations-zero",
        [*SOLVE, GUESS, "--max-iterations", "0"],
        2,
        ["--max-iterations", "must be >= 1"],
    ),
    ("max-iterations-text", [*SOLVE, GUESS, "--max-iterations", "many"], 2, ["--max-iterations", "integer"]),
    (
        "sigma-negative-space",
        [
            "od",
            "solve",
            "{d}/obs.tdm",
            "--station-inertial",
            f"STATION:{R0}",
            "--guess",
            GUESS,
            "--sigma-range",
            "-1e-3",
        ],
        2,
        ["--sigma-range", "must be > 0"],
    ),
    (
        "sigma-nan",
        ["od", "simulate", "--out", "{d}/x.csv", "--sigma-range", "nan"],
        2,
        ["--sigma-range", "finite"],
    ),
    ("duration-zero", ["od", "simulate", "--out", "{d}/x.csv", "--duration", "0"], 2, ["--duration", "> 0"]),
    ("step-inf", ["od", "simulate", "--out", "{d}/x.csv", "--step", "inf"], 2, ["--step", "finite"]),
    (
        "too-many-samples",
        ["od", "simulate", "--out", "{d}/x.csv", "--duration", "1e9", "--step", "1"],
        2,
        ["--duration, --step", "more than 1e6"],  # named only --step
    ),
    (
        "sigma-range-huge",  # the noise made a range negative: named the table's "value"
        ["od", "simulate", "--out", "{d}/x.csv", "--sigma-range", "1e300"],
        2,
        ["--sigma-range: the simulated noise"],
    ),
    (
        "state-huge",  # blamed the propagator's times
        ["od", "simulate", "--out", "{d}/x.csv", "--state", "-1e300,0,0,0,0,0"],
        2,
        ["--state: every component must be below 1e100"],
    ),
    (
        "seed-negative",
        ["od", "simulate", "--out", "{d}/x.csv", "--seed", "-1"],
        2,
        ["--seed", "must be >= 0"],
    ),
    # option values
    ("guess-count", [*SOLVE, "1,2,3"], 2, ["--guess: expected 6"]),
    ("guess-text", [*SOLVE, "1,2,3,4,5,x"], 2, ["--guess: expected comma-separated numbers"]),
    ("guess-nan", [*SOLVE[:-1], "--guess=nan,1,2,3,4,5"], 2, ["--guess: numbers must be finite"]),
    (
        "state-inside-earth",
        ["od", "simulate", "--out", "{d}/x.csv", "--state", "6000,0,0,0,7,0"],
        2,
        ["--state: the satellite is below the Earth's surface"],
    ),
    (
        "station-latitude",
        [
            "od",
            "solve",
            "{d}/obs.csv",
            "--station",
            "95,0,0",
            "--epoch",
            "1981-03-21T06:00:00",
            "--guess",
            GUESS,
        ],
        2,
        ["lat_deg", "[-90, 90]"],
    ),
    (
        "station-inertial-count",
        ["od", "solve", "{d}/obs.csv", "--station-inertial", "1,2", "--guess", GUESS],
        2,
        ["--station-inertial: expected x,y,z[,omega]"],
    ),
    ("no-station", ["od", "solve", "{d}/obs.csv", "--guess", GUESS], 2, ["give at least one station"]),
    (
        "geodetic-needs-epoch",
        ["od", "solve", "{d}/obs.csv", "--station", "23,113,0.1", "--guess", GUESS],
        2,
        ["--epoch"],
    ),
    (
        "epoch-garbage",
        [
            "od",
            "solve",
            "{d}/obs.tdm",
            "--station-inertial",
            f"STATION:{R0}",
            "--guess",
            GUESS,
            "--epoch",
            "tuesday",
        ],
        2,
        ["epoch: not a UTC date-time"],
    ),
    (
        "tdm-station-unknown",
        ["od", "solve", "{d}/obs.tdm", "--station-inertial", f"DSS:{R0}", "--guess", GUESS],
        2,
        ["'STATION'", "PARTICIPANT_1", "DSS"],
    ),
    (
        "station-index",
        ["od", "solve", "{d}/st1.csv", "--station-inertial", R0, "--guess", GUESS],
        2,
        ["st1.csv", "station index 1", "only 1 station"],
    ),
    ("csv-sigma-option", [*SOLVE, GUESS, "--sigma-range", "1e-3"], 2, ["--sigma-range: only for TDM"]),
    (
        "ellipsoid",
        [
            "od",
            "solve",
            "{d}/obs.csv",
            "--station",
            "23,113,0.1",
            "--epoch",
            "1981-03-21T06:00:00",
            "--ellipsoid",
            "flat",
            "--guess",
            GUESS,
        ],
        2,
        ["flat"],
    ),
    # options that would have no effect, and values no ground station or orbit can have
    (
        "ellipsoid-unused",
        [*SOLVE, GUESS, "--ellipsoid", "GRS-80"],
        2,
        ["--ellipsoid: only used with --station"],
    ),
    ("ut1-unused", [*SOLVE, GUESS, "--ut1-utc", "0.1"], 2, ["--ut1-utc: only used with --station"]),
    ("epoch-unused-csv", [*SOLVE, GUESS, "--epoch", "1981-03-21T06:00:00"], 2, ["--epoch: only used with"]),
    (
        "ut1-too-large",
        [
            "od",
            "solve",
            "{d}/obs.csv",
            "--station",
            "23,113,0.1",
            "--epoch",
            "1981-03-21T06:00:00",
            "--ut1-utc",
            "-5",
            "--guess",
            GUESS,
        ],
        2,
        ["--ut1-utc: |UT1 - UTC| must be < 0.9 s"],
    ),
    (
        "ut1-between-0.9-and-1",  # passed the CLI check, then the library named ut1_minus_utc
        [*SOLVE, GUESS, "--station", "23,113,0.1", "--epoch", "1981-03-21T06:00:00", "--ut1-utc", "0.95"],
        2,
        ["--ut1-utc: |UT1 - UTC| must be < 0.9 s"],
    ),
    ("guess-inside-earth", [*SOLVE, "1,2,3,4,5,6"], 2, ["--guess: the position is inside the Earth"]),
    (
        "station-inertial-not-on-earth",
        ["od", "solve", "{d}/obs.csv", "--station-inertial", "-1000,2,3", "--guess", GUESS],
        2,
        ["--station-inertial: |r| = 1000", "Earth's surface"],
    ),
    (
        "tdm-extra-station",
        [
            "od",
            "solve",
            "{d}/obs.tdm",
            "--station-inertial",
            f"STATION:{R0}",
            "--station-inertial",
            f"DSS:{R0}",
            "--guess",
            GUESS,
        ],
        2,
        ["'DSS' is not a station of the file"],
    ),
    (
        "tdm-mixed-labels",
        [
            "od",
            "solve",
            "{d}/obs.tdm",
            "--station-inertial",
            f"STATION:{R0}",
            "--station-inertial",
            R0,
            "--guess",
            GUESS,
        ],
        2,
        ["name every station"],
    ),
    ("plots-empty", [*SOLVE, GUESS, "--plots", ""], 2, ["--plots: must name a directory"]),
    # files
    (
        "missing-file",
        ["od", "solve", "{d}/nope.csv", "--station-inertial", R0, "--guess", GUESS],
        2,
        ["nope.csv", "does not exist"],
    ),
    (
        "directory",
        ["od", "solve", "{d}/sub", "--station-inertial", R0, "--guess", GUESS],
        2,
        ["is a directory"],
    ),
    (
        "bad-csv-line",
        ["od", "solve", "{d}/neg.csv", "--station-inertial", R0, "--guess", GUESS],
        2,
        ["neg.csv:3:", "range must be > 0"],
    ),
    ("out-is-directory", ["od", "simulate", "--out", "{d}/sub"], 2, ["--out", "is a directory"]),
    ("out-no-parent", ["od", "simulate", "--out", "{d}/nodir/x.csv"], 2, ["No such file or directory"]),
    ("plots-is-file", [*SOLVE, GUESS, "--plots", "{d}/obs.tdm"], 2, ["obs.tdm"]),
    # rendezvous
    (
        "scenario-bool",
        ["rendezvous", "--scenario", "{d}/bad.toml", "--out", "{d}/rv"],
        2,
        ["bad.toml:", "key 'mu'", "[orbit]", "boolean true"],
    ),
    (
        "scenario-typo",
        ["rendezvous", "--scenario", "{d}/typo.toml", "--out", "{d}/rv"],
        2,
        ["typo.toml:", "unknown section [orbt]", "did you mean [orbit]"],
    ),
    ("scenario-missing", ["rendezvous", "--scenario", "{d}/nope.toml", "--out", "{d}/rv"], 2, ["nope.toml"]),
    ("case-unknown", ["rendezvous", "--case", "boxx", "--out", "{d}/rv"], 2, ["--case: unknown 'boxx'"]),
    (  # the nonlinear model reads the same scenario file (issue 12), with the same strict schema
        "nonlinear-scenario",
        ["rendezvous", "--model", "nonlinear", "--scenario", "{d}/bad.toml", "--out", "{d}/rv"],
        2,
        ["bad.toml:", "key 'mu'", "[orbit]", "boolean true"],
    ),
    (
        "nonlinear-scenario-typo",
        ["rendezvous", "--model", "nonlinear", "--scenario", "{d}/typo.toml", "--out", "{d}/rv"],
        2,
        ["typo.toml:", "unknown section [orbt]", "did you mean [orbit]"],
    ),
    (
        "nonlinear-case-unknown",
        ["rendezvous", "--model", "nonlinear", "--case", "boxx", "--out", "{d}/rv"],
        2,
        ["--case: unknown 'boxx'"],
    ),
    (
        "nonlinear-reference",
        ["rendezvous", "--model", "nonlinear", "--reference", "--out", "{d}/rv"],
        2,
        ["--reference: only with --model linear"],
    ),
    # rank
    ("orbit-negative-space", ["rank", "--orbit", "-1,2"], 2, ["--orbit (sigma): must be > 0"]),
    ("orbit-negative-equals", ["rank", "--orbit=-1,2"], 2, ["--orbit (sigma): must be > 0"]),
    ("orbit-text", ["rank", "--orbit", "mars"], 2, ["--orbit: must be leo, geo, one"]),
    # reproduce
    (
        "section-unknown",
        ["reproduce", "--section", "nope", "--out", "{d}/rep", "--no-progress"],
        2,
        ["sections: unknown"],
    ),
]


def _argv(argv, d):
    return [a.replace("{d}", str(d)) for a in argv]


@pytest.mark.parametrize("name,argv,code,frags", CASES, ids=[c[0] for c in CASES])
def test_cli_error_is_one_line(files, capsys, name, argv, code, frags):
    rc = cli.main(_argv(argv, files))
    err = capsys.readouterr().err
    assert rc == code, err
    assert err.endswith("\n") and err.count("\n") == 1, err
    assert err.startswith("satgnc: error: "), err
    assert "Traceback" not in err
    for f in frags:
        assert f in err, (f, err)


# Negative numbers as option values, with a space or with "=": parsing succeeds and the command runs.
NEGATIVE_OK = [
    ("guess-space", [*SOLVE, NEG_GUESS, "--max-iterations", "3"]),
    ("guess-equals", [*SOLVE[:-1], f"--guess={NEG_GUESS}", "--max-iterations", "3"]),
    (
        "station-geodetic-space",
        [
            "od",
            "solve",
            "{d}/obs.csv",
            "--station",
            "-33,150,0.1",
            "--epoch",
            "1981-03-21T06:00:00",
            "--guess",
            GUESS,
            "--max-iterations",
            "3",
        ],
    ),
    (
        "station-geodetic-equals",
        [
            "od",
            "solve",
            "{d}/obs.csv",
            "--station=-33,150,0.1",
            "--epoch",
            "1981-03-21T06:00:00",
            "--guess",
            GUESS,
            "--max-iterations",
            "3",
        ],
    ),
    (
        "ut1-negative",
        [
            "od",
            "solve",
            "{d}/obs.csv",
            "--station",
            "-33,150,0.1",
            "--epoch",
            "1981-03-21T06:00:00",
            "--ut1-utc",
            "-0.2",
            "--guess",
            GUESS,
            "--max-iterations",
            "3",
        ],
    ),
]


@pytest.mark.parametrize("name,argv", NEGATIVE_OK, ids=[c[0] for c in NEGATIVE_OK])
def test_negative_option_values_parse(files, capsys, name, argv):
    rc = cli.main(_argv(argv, files))
    out = capsys.readouterr()
    assert rc in (0, 1), out.err  # 1: the solve did not converge in 3 iterations, which is a status
    assert out.err == ""
    assert out.out.startswith("status      :")


def test_negative_state_for_simulate(files, capsys):
    x = paper.truth() * np.array([-1, -1, 1, -1, -1, 1])
    out = files / "neg_state.csv"
    assert (
        cli.main(["od", "simulate", "--out", str(out), "--state", ",".join(map(str, x)), "--no-noise",
                  "--elevation-mask", "-90"]) == 0  # this mirrored state is below the horizon: mask off
    )
    assert "wrote" in capsys.readouterr().out


def test_simulate_masks_at_0_deg_by_default(files, capsys):
    # The mirrored state is below the paper's station's horizon: with the default 0 deg mask nothing is
    # observed, and the error names the option and how to turn the mask off.
    x = paper.truth() * np.array([-1, -1, 1, -1, -1, 1])
    rc = cli.main(["od", "simulate", "--out", str(files / "none.csv"), "--state", ",".join(map(str, x))])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("satgnc: error: --elevation-mask:") and "-90" in err, err


def test_internal_bug_is_one_line_exit_1(monkeypatch, capsys):
    import satgnc.analysis.cli as acli

    def boom(_args):
        raise RuntimeError("invariant broken\nsecond line")

    monkeypatch.setattr(acli, "_rank", boom)
    assert cli.main(["rank"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("satgnc: internal error: RuntimeError: invariant broken")
    assert "--debug" in err
    with pytest.raises(RuntimeError, match="invariant broken"):
        cli.main(["rank", "--debug"])


def test_debug_reraises_user_errors(files):
    with pytest.raises(ValueError, match="--guess: expected 6"):
        cli.main(["--debug", *_argv([*SOLVE, "1,2"], files)])


def test_help_returns_0(capsys):
    assert cli.main(["od", "solve", "--help"]) == 0
    assert "--guess" in capsys.readouterr().out


def test_console_script_one_line_and_debug_traceback(files):
    argv = [
        sys.executable,
        "-m",
        "satgnc.cli",
        "od",
        "solve",
        str(files / "neg.csv"),
        "--station-inertial",
        R0,
        "--guess",
        NEG_GUESS,
    ]
    r = subprocess.run(argv, capture_output=True, text=True)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.count("\n") == 1 and "neg.csv:3:" in r.stderr and "Traceback" not in r.stderr
    r = subprocess.run([sys.executable, "-m", "satgnc.cli", "od"], capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr.startswith("satgnc: error: satgnc od: choose a subcommand")
    r = subprocess.run([*argv, "--debug"], capture_output=True, text=True)
    assert r.returncode == 1 and "Traceback" in r.stderr and "FileFormatError" in r.stderr
