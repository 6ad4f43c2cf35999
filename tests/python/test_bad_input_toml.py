"""Scenario TOML files against the strict schema: every row is a TOML text written into tmp_path ->
exception type + message fragments (the file, the line, the key and its section)."""

from __future__ import annotations

import re

import numpy as np
import pytest
import satgnc
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as hs
from satgnc.scenarios import l1_rendezvous as scen

GOOD = scen.DEFAULT.read_text()


def _edit(old: str, new: str, text: str = GOOD) -> str:
    """Replace the first line matching regex ``old`` (whole line) by ``new`` (may be '' to delete)."""
    out, n = re.subn(rf"(?m)^{old}$", new, text, count=1)
    assert n == 1, old
    return out


def _line_of(text: str, needle: str) -> int:
    return next(i for i, line in enumerate(text.splitlines(), start=1) if needle in line)


# (id, TOML text, exception type, fragments; "@<needle>" is replaced by ":<line of needle>:")
CASES = [
    # values no scenario can have (fuzz pass): 1e300 reached the CW functions ("dt:", "n:") or overflowed
    (
        "tf-huge",
        _edit(r"tf = .*", "tf = 1e300"),
        ["@tf =", "key 'tf'", "[horizon]", "must be <= 1000000000.0"],
    ),
    (
        "radius-huge",  # OverflowError in radius**3
        _edit(r"radius = .*", "radius = 1e300"),
        ["@radius =", "key 'radius'", "[orbit]", "must be <="],
    ),
    (
        "n-tf-beyond-cw",  # n tf > 1e9 rad with every key in range
        _edit(r"radius = .*", "radius = 1.0"),
        ["@tf =", "key 'tf'", "n tf = ", "exceeds 1e9 rad"],
    ),
    # wrong types
    (
        "bool-as-number",
        _edit(r"mu = .*", "mu = true"),
        ["@mu = true", "key 'mu'", "[orbit]", "expected a number", "boolean true"],
    ),
    (
        "string-as-number",
        _edit(r"mass = .*", 'mass = "4.6"'),
        ["@mass =", "key 'mass'", "[chaser]", "expected a number", "string '4.6'"],
    ),
    (
        "float-as-integer",
        _edit(r"knots = .*", "knots = 2.7"),
        ["@knots =", "key 'knots'", "[horizon]", "expected an integer", "never rounded"],
    ),
    (
        "float-integral-as-integer",
        _edit(r"knots = .*", "knots = 100.0"),
        ["key 'knots'", "expected an integer"],
    ),
    (
        "string-as-bool",
        _edit(r"terminal_equality = false", 'terminal_equality = "false"'),
        [
            '@terminal_equality = "false"',
            "key 'terminal_equality'",
            "[cases.unconstrained]",
            "true or false",
            "without quotes",
        ],
    ),
    (
        "int-as-bool",
        _edit(r"box = false", "box = 0"),
        ["key 'box'", "[cases.unconstrained]", "true or false"],
    ),
    (
        "number-as-string",
        _edit(r'method = "midpoint".*', "method = 1"),
        ["key 'method'", "[discretization]", "expected a string"],
    ),
    (
        "vector-length",
        _edit(r"position = .*", "position = [1.0, 2.0]"),
        ["@position =", "key 'position'", "[initial_state]", "array of 3 numbers", "array of 2"],
    ),
    (
        "vector-of-strings",
        _edit(r"velocity = .*", 'velocity = ["a", 1, 2]'),
        ["key 'velocity'", "array of 3"],
    ),
    ("vector-with-bool", _edit(r"velocity = .*", "velocity = [true, 1, 2]"), ["key 'velocity'"]),
    ("scalar-as-vector", _edit(r"position = .*", "position = 5.0"), ["key 'position'", "float 5.0"]),
    (
        "section-as-key",
        "chaser = 3\n" + _edit(r"\[chaser\]", "", _edit(r"mass = .*", "")),
        ["@chaser = 3", "chaser: must be a table [chaser], got integer 3"],
    ),
    ("date-as-number", _edit(r"tf = .*", "tf = 1979-05-27"), ["key 'tf'", "expected a number"]),
    # values out of range
    ("negative-mu", _edit(r"mu = .*", "mu = -1.0"), ["key 'mu'", "[orbit]", "must be > 0"]),
    ("nan-radius", _edit(r"radius = .*", "radius = nan"), ["key 'radius'", "must be finite"]),
    ("inf-tf", _edit(r"tf = .*", "tf = inf"), ["key 'tf'", "must be finite"]),
    ("knots-one", _edit(r"knots = .*", "knots = 1"), ["key 'knots'", "must be >= 2"]),
    ("zero-position", _edit(r"position = .*", "position = [0, 0, 0]"), ["key 'position'", "all zero"]),
    ("zero-velocity", _edit(r"velocity = .*", "velocity = [0.0, 0.0, 0.0]"), ["key 'velocity'", "all zero"]),
    ("negative-alpha", _edit(r"alpha = .*", "alpha = -1.0"), ["key 'alpha'", "[cost]", ">= 0"]),
    ("zero-u-max", _edit(r"u_max = .*", "u_max = 0.0"), ["key 'u_max'", "> 0"]),
    ("zero-rho", _edit(r"rho = 1.0e-2", "rho = 0.0"), ["key 'rho'", "[cases.unconstrained]", "> 0"]),
    ("negative-passes", _edit(r"paper_lqr_passes = 86", "paper_lqr_passes = -3"), ["key 'paper_lqr_passes'"]),
    (
        "unknown-method",
        _edit(r'method = "midpoint".*', 'method = "zho"'),
        ["key 'method'", "must be one of", "did you mean 'zoh'"],
    ),
    # unknown keys and sections (typos must not be ignored)
    (
        "typo-key",
        _edit(r"mass = .*", "mas = 4.6"),
        ["@mas = 4.6", "unknown key 'mas'", "[chaser]", "did you mean 'mass'"],
    ),
    ("case-key", _edit(r"Qf = .*", "qf = 1000.0"), ["unknown key 'qf'", "[cost]", "did you mean 'Qf'"]),
    (
        "typo-case-key",
        _edit(r"eps = 4.0e-4", "esp = 4.0e-4"),
        ["unknown key 'esp'", "[cases.constrained]", "did you mean 'eps'"],
    ),
    (
        "typo-section",
        _edit(r"\[orbit\]", "[orbt]"),
        ["@[orbt]", "unknown section [orbt]", "did you mean [orbit]"],
    ),
    ("extra-section", GOOD + "\n[solver]\nrho = 1\n", ["unknown section [solver]", "known sections"]),
    (
        "typo-top-key",
        _edit(r"name = .*", 'nmae = "x"'),
        ["@nmae", "unknown key 'nmae'", "did you mean 'name'"],
    ),
    ("unknown-top-key", "verbose = true\n" + GOOD, ["unknown key 'verbose'", "top level"]),
    # missing keys and sections
    ("missing-key", _edit(r"radius = .*", ""), ["missing key 'radius'", "[orbit]", "(m)"]),
    ("missing-case-key", _edit(r"rho = 1.0e-2", ""), ["missing key 'rho'", "[cases.unconstrained]"]),
    (
        "missing-section",
        re.sub(r"(?s)\[chaser\].*?(?=\[initial_state\])", "", GOOD),
        ["missing section [chaser]", "mass"],
    ),
    ("no-cases", GOOD[: GOOD.index("[cases.unconstrained]")], ["missing section [cases.<name>]"]),
    ("empty-file", "", ["missing section [orbit]"]),
    # syntax
    ("syntax-error", _edit(r"mass = .*", "mass = = 4.6"), ["@mass = = 4.6", "TOML syntax"]),
    ("duplicate-key", _edit(r"mass = .*", "mass = 4.6\nmass = 5.0"), ["TOML syntax"]),
    ("latin1", "# caf\xe9\n".encode("latin-1") + GOOD.encode(), [":1:", "not UTF-8"]),
    ("binary", b"\x00\x01\x02", ["binary file"]),
]


def _write(tmp_path, content):
    p = tmp_path / "scenario.toml"
    p.write_bytes(content if isinstance(content, bytes) else content.encode())
    return p


@pytest.mark.parametrize("name,text,frags", CASES, ids=[c[0] for c in CASES])
def test_bad_scenario(tmp_path, name, text, frags):
    p = _write(tmp_path, text)
    with pytest.raises(satgnc.FileFormatError) as ei:
        scen.load(p)
    msg = str(ei.value)
    assert isinstance(ei.value, ValueError)
    assert msg.startswith(str(p)), msg
    for f in frags:
        if f.startswith("@"):
            line = _line_of(text, f[1:])
            assert f"{p}:{line}:" in msg, (f, msg)
            assert ei.value.line == line
        else:
            assert f in msg, (f, msg)


def test_missing_and_directory(tmp_path):
    with pytest.raises(FileNotFoundError, match="^path: .*nope.toml does not exist"):  # load's argument
        scen.load(tmp_path / "nope.toml")
    with pytest.raises(IsADirectoryError, match="is a directory"):
        scen.load(tmp_path)
    with pytest.raises(TypeError, match="^path: must be a file path"):
        scen.load(3.5)


def test_packaged_scenario_and_variants_load(tmp_path):
    sc = scen.load()
    assert (
        sc.knots == 100
        and sc.method == "midpoint"
        and sorted(sc.cases) == ["box", "constrained", "unconstrained"]
    )
    assert sc.cases["constrained"] == dict(
        rho=0.1, eps=4e-4, box=True, terminal_equality=True, paper_lqr_passes=404
    )
    assert sc.cases["box"]["terminal_equality"] is False and "paper_lqr_passes" not in sc.cases["box"]
    np.testing.assert_allclose(sc.p0, [-9477.311, -1999.979, -43.046])
    # Integers are numbers; optional keys and the optional section take their defaults; BOM and CRLF.
    text = _edit(r"mu = .*", "mu = 398600441800000")
    text = re.sub(r"(?s)\[discretization\].*?(?=\[cases\.unconstrained\])", "", text)
    text = _edit(r"box = false", "", text)
    sc2 = scen.load(_write(tmp_path, "\ufeff" + text.replace("\n", "\r\n")))
    assert sc2.mu == 398600441800000.0 and isinstance(sc2.mu, float)
    assert sc2.method == "midpoint" and sc2.cases["unconstrained"]["box"] is False


_VALUES = hs.sampled_from(
    [
        "true",
        '"false"',
        "1",
        "0",
        "-1",
        "2.7",
        "nan",
        "inf",
        "[1, 2, 3]",
        "[]",
        "{a = 1}",
        "1979-05-27",
        '"x"',
        "1e3",
    ]
)
_KEYS = [m for m in re.finditer(r"(?m)^(\w+) = (.*?)(\s*#.*)?$", GOOD)]


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    edits=hs.lists(
        hs.tuples(hs.integers(0, len(_KEYS) - 1), _VALUES), min_size=1, max_size=3, unique_by=lambda e: e[0]
    )
)
def test_property_typed_scenario_or_error(tmp_path, edits):
    """Any value in any key gives a Scenario whose fields have their types and ranges, or a
    FileFormatError naming the file; a wrong type is never coerced."""
    text = GOOD
    for k, v in sorted(edits, key=lambda e: -_KEYS[e[0]].start()):
        m = _KEYS[k]
        text = text[: m.start()] + f"{m.group(1)} = {v}" + text[m.end() :]
    p = _write(tmp_path, text)
    try:
        sc = scen.load(p)
    except satgnc.FileFormatError as e:
        assert str(e).startswith(str(p))
        return
    for name in ("mu", "radius", "mass", "tf", "u_max"):
        v = getattr(sc, name)
        assert type(v) is float and v > 0 and np.isfinite(v)
    assert type(sc.knots) is int and sc.knots >= 2
    assert sc.p0.shape == (3,) and sc.v0.shape == (3,) and np.any(sc.p0 != 0) and np.any(sc.v0 != 0)
    for c in sc.cases.values():
        assert type(c["box"]) is bool and type(c["terminal_equality"]) is bool
        assert c["rho"] > 0 and c["eps"] > 0
