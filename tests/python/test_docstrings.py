"""Docstrings of the public API (issue 17 items 2 and 3): every public property documented, with its
unit where it has one; numpy-style Parameters / Returns sections on the main public functions; and on
every public function of satgnc.od, satgnc.guidance, satgnc.mission and satgnc.propagation the
Parameters (every argument, with units and, for states, the frame), Returns, Raises and Examples
sections, the examples run here as doctests.

Every assertion is exact (a count, a set of names, a string, doctest failures = 0): docstrings have no
tolerance; the examples' own printed numbers are rounded where the last digits are not the point."""

from __future__ import annotations

import doctest
import importlib
import inspect
import re
from typing import Any

import pytest
import satgnc

# The public namespaces a user imports (od and guidance included: their properties count too).
PUBLIC_MODULES = (
    "satgnc", "satgnc.propagation", "satgnc.frames", "satgnc.time", "satgnc.observation", "satgnc.io",
    "satgnc.analysis", "satgnc.dynamics", "satgnc.od", "satgnc.guidance", "satgnc.filter",
    "satgnc.sensitivity", "satgnc.forcemodel",
)

# Properties allowed without a docstring, by qualified name, each with its reason. Empty: none.
EXCEPTIONS: dict[str, str] = {}


def _public_classes() -> dict[type, str]:
    seen: dict[type, str] = {}
    for m in PUBLIC_MODULES:
        mod = importlib.import_module(m)
        names = getattr(mod, "__all__", None) or [n for n in dir(mod) if not n.startswith("_")]
        for n in names:
            obj = getattr(mod, n, None)
            if inspect.isclass(obj):
                seen.setdefault(obj, f"{m}.{n}")
    return seen


def _public_properties() -> dict[str, Any]:
    out: dict[str, Any] = {}
    for cls, qual in _public_classes().items():
        for k in dir(cls):
            if k.startswith("_"):
                continue
            v = inspect.getattr_static(cls, k)
            if isinstance(v, property):
                out[f"{qual}.{k}"] = v
    return out


def test_every_public_property_has_a_docstring():
    props = _public_properties()
    # PY17 counted 275 public properties (62 undocumented); the walk must see at least that many, or it
    # missed a namespace and the 0 below would be vacuous.
    assert len(props) >= 275, len(props)
    missing = sorted(q for q, p in props.items() if not (p.__doc__ or "").strip() and q not in EXCEPTIONS)
    assert missing == [], f"{len(missing)} public properties without a docstring: {missing}"
    stale = sorted(set(EXCEPTIONS) - set(props))
    assert stale == [], f"EXCEPTIONS names properties that no longer exist: {stale}"


_UNIT = re.compile(r"\b(km|m|s|kg|rad|deg|m\^2|kg/m\^3|km/s|km\^3/s\^2|km\^2|days|sfu|rad/s|N)\b|unit-free")


@pytest.mark.parametrize(
    "cls, name",
    [
        ("AtmosphereDrag", "area"), ("AtmosphereDrag", "mass"), ("AtmosphereDrag", "cd"),
        ("ErfaSun", "epoch_jd1"), ("ForceModelConfig", "radius"), ("GravityField", "degree"),
        ("HarrisPriester", "lag"), ("HarrisPriester", "n"), ("IauEarthRotation", "step"),
        ("IauEarthRotation", "t_begin"), ("IauEarthRotation", "t_end"), ("MeasurementModel", "size"),
        ("SolarRadiationPressure", "cr"), ("ExponentialDrag", "rho0"), ("GroundStation", "height_km"),
    ],
)
def test_dimensioned_property_docstrings_state_the_unit(cls: str, name: str):
    # The properties documented this session that hold a number: the docstring names its unit (or
    # says unit-free).
    doc = getattr(getattr(satgnc._satgnc, cls), name).__doc__
    assert _UNIT.search(doc), f"{cls}.{name}: no unit in {doc!r}"


def test_frame_named_where_a_property_is_a_vector_or_a_rotation():
    c = satgnc._satgnc
    assert "GCRF" in c.AtmosphereDrag.sun.__doc__ and "ITRF" in c.AtmosphereDrag.earth_rotation.__doc__
    assert "ITRF" in c.GravityField.degree.__doc__ and "GCRF" in c.ThirdBodies.sun.__doc__


# The main public functions of the rooms this parcel documents (od and guidance: other parcels').
MAIN_FUNCTIONS = {
    "satgnc": ("propagate", "elements_to_state"),
    "satgnc.time": ("parse",),
    "satgnc.frames": ("load_eop", "default_eop", "default_eop_path", "earth_orientation", "gcrs_to_itrs",
                      "itrs_to_gcrs", "gcrs_to_itrs_matrix", "gcrs_to_eme2000", "eme2000_to_gcrs",
                      "gcrs_to_eme2000_matrix"),
    "satgnc.observation": ("measurement_model", "predict", "rotating_station", "shift_state",
                           "standard_atmosphere", "saastamoinen_zenith_delay", "tropo_mapping",
                           "shapiro_delay", "marini_murray_delay"),
    "satgnc.io": tuple(f"{verb}_{kind}" for kind in ("tdm", "oem", "opm")
                       for verb in ("parse", "read", "format", "write")) + ("epoch_seconds", "epochs_at"),
    "satgnc.analysis": ("orbit", "polar_model", "polar_linear_model", "od_gramian", "od_linear_model",
                        "ltv_observability_gramian", "minimum_energy",
                        "cw_model", "controllability", "observability", "controllability_gramian",
                        "observability_gramian", "loss_table", "visibility_pass"),
}
_SECTION = re.compile(r"^\s*(Parameters|Returns|Raises)\n\s*-{3,}\s*$", re.M)
_UNIT_WORD = re.compile(r"\b(km|km/s|s|rad|rad/s|m|m/s|m/s\^2|arcsec|km\^3/s\^2|1/s)\b")


def _main_functions() -> list[tuple[str, Any]]:
    return [(f"{m}.{n}", getattr(importlib.import_module(m), n)) for m, names in MAIN_FUNCTIONS.items()
            for n in names]


@pytest.mark.parametrize("qual, fn", _main_functions(), ids=lambda v: v if isinstance(v, str) else "")
def test_main_functions_have_numpy_sections(qual: str, fn: Any):
    doc = inspect.getdoc(fn) or ""
    sections = set(_SECTION.findall(doc))
    # Every main function documents what it returns; those taking arguments document them.
    assert "Returns" in sections, f"{qual}: no Returns section"
    if inspect.signature(fn).parameters:
        assert "Parameters" in sections, f"{qual}: no Parameters section"
    # Each documented parameter is a real parameter (a renamed argument must not leave a stale entry).
    params = set(inspect.signature(fn).parameters)
    block = ""
    if "Parameters" in sections:
        block = doc.split("Parameters\n----------\n", 1)[-1].split("\n\n", 1)[0]
    heads = [ln.split(" : ")[0] for ln in block.splitlines() if ln and not ln.startswith(" ") and " : " in ln]
    names = {n.strip().lstrip("*") for h in heads for n in h.split(",")}
    assert names <= params | {"kw"}, f"{qual}: documents {sorted(names - params)} not in {sorted(params)}"


def test_main_function_docs_state_units():
    # The functions taking or returning a dimensioned number name its unit in their docstring (io's
    # parse/read/format/write take text and models: the units are in the models' docs).
    no_units = {f"satgnc.io.{v}_{k}" for k in ("tdm", "oem", "opm") for v in ("write", "format")}
    no_units |= {"satgnc.frames.default_eop_path", "satgnc.frames.gcrs_to_eme2000_matrix",
                 "satgnc.frames.gcrs_to_itrs_matrix", "satgnc.analysis.loss_table",
                 "satgnc.analysis.controllability", "satgnc.analysis.observability"}
    missing = [q for q, fn in _main_functions() if q not in no_units and not _UNIT_WORD.search(fn.__doc__)]
    assert missing == []


# ----------------------------------------------------------------------------------------------------
# Issue 17 item 2: every public function (``__all__``) of the packages a user starts from, plus the
# TDM functions of satgnc.od.tdm that the API reference lists.
FUNCTION_PACKAGES = ("satgnc.od", "satgnc.guidance", "satgnc.mission", "satgnc.propagation")
EXTRA_FUNCTIONS = {"satgnc.od.tdm": ("read_tdm", "write_tdm", "parse_epoch")}
_ALL_SECTIONS = re.compile(r"^\s*(Parameters|Returns|Raises|Examples)\n\s*-{3,}\s*$", re.M)
# A unit (or "unit-free") in the docstring: orbits km, km/s, s; relative motion m, m/s, N, kg.
_ANY_UNIT = re.compile(r"\b(km|km/s|s|m|m/s|m/s\^2|N|kg|rad|rad/s|deg|km\^2|km\^3/s\^2|m\^3/s\^2|"
                       r"kg/m\^3|km/s\^2|N s|days)\b|unit-free")
# Arguments that hold a state or a position: the docstring must name the frame it is in.
_STATE_ARGS = {"x", "x0", "x0_guess", "station_state", "r0", "states", "parameters", "center"}
_FRAME = re.compile(r"inertial|GCRF|ECI|CW frame|CW_FRAME|Hill|Earth-fixed|ITRF")


def _package_functions() -> dict[str, Any]:
    out: dict[str, Any] = {}
    seen: set[int] = set()
    listed = [(m, tuple(importlib.import_module(m).__all__)) for m in FUNCTION_PACKAGES]
    for m, names in [*listed, *EXTRA_FUNCTIONS.items()]:
        mod = importlib.import_module(m)
        for n in names:
            obj = getattr(mod, n)
            if inspect.isfunction(obj) and id(obj) not in seen:
                seen.add(id(obj))
                out[f"{m}.{n}"] = obj
    return out


_FUNCTIONS = _package_functions()


def _documented_parameters(doc: str) -> set[str]:
    block = doc.split("Parameters\n----------\n", 1)[-1].split("\n\n", 1)[0]
    heads = [ln.split(" : ")[0] for ln in block.splitlines() if ln and not ln.startswith(" ")]
    return {n.strip().lstrip("*") for h in heads for n in h.split(",")}


def test_the_function_walk_sees_every_package():
    # 56 functions when this test was written (od 24 + tdm 3, guidance 10, mission 15, propagation 4):
    # fewer means a package or its __all__ was missed and the checks below would pass vacuously.
    packages = (*FUNCTION_PACKAGES, *EXTRA_FUNCTIONS)
    per = {m: sum(q.rsplit(".", 1)[0] == m for q in _FUNCTIONS) for m in packages}
    assert len(_FUNCTIONS) >= 56, per
    assert min(per.values()) >= 3, per


@pytest.mark.parametrize("qual", sorted(_FUNCTIONS))
def test_public_function_has_numpy_sections(qual: str):
    fn = _FUNCTIONS[qual]
    doc = inspect.getdoc(fn) or ""
    sections = set(_ALL_SECTIONS.findall(doc))
    params = {n for n in inspect.signature(fn).parameters if not n.startswith("_")}
    need = {"Returns", "Examples"} | ({"Parameters", "Raises"} if params else set())
    assert need <= sections, f"{qual}: missing section(s) {sorted(need - sections)}"
    if params:
        # every argument documented, and nothing documented that is not an argument
        assert _documented_parameters(doc) == params, (
            f"{qual}: documents {sorted(_documented_parameters(doc))}, signature {sorted(params)}")
    assert _ANY_UNIT.search(doc), f"{qual}: no unit named"
    if params & _STATE_ARGS:
        assert _FRAME.search(doc), f"{qual}: takes {sorted(params & _STATE_ARGS)} but names no frame"


@pytest.mark.parametrize("qual", sorted(_FUNCTIONS))
def test_public_function_examples_run(qual: str, tmp_path, monkeypatch):
    # The Examples section as a doctest, in a scratch directory (some examples write files).
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    test = doctest.DocTestParser().get_doctest(_FUNCTIONS[qual].__doc__ or "", {}, qual, None, 0)
    assert len(test.examples) >= 2, f"{qual}: the Examples section has no runnable example"
    lines: list[str] = []
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    result = runner.run(test, out=lines.append)
    assert result.failed == 0, "".join(lines)
