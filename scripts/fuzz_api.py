"""Bad-input fuzz pass over satgnc's public Python API (issue 11, point 3).

For every public callable (the ``__all__`` of each public module) a known-good call is mutated one
argument at a time: NaN, +-Inf, complex, boolean, object and string values, None, negative, zero and
huge values, wrong shapes and empty sequences. Each case runs in a worker process with a time limit
and is classified:

* ``clear``     -- TypeError / ValueError (or a file error) whose message names the argument;
* ``unclear``   -- any other exception, a message that does not name the argument, or a raw
                   pybind11 signature dump;
* ``silent``    -- a value no parameter may take (NaN, Inf, complex, bool for a number, object or
                   string arrays, a wrong shape) was accepted without error;
* ``accepted``  -- a negative / zero / huge / None / empty value was accepted (often legitimate:
                   listed for review, not counted as a defect);
* ``hang``      -- no answer within the time limit;  ``crash`` -- the worker process died.

Usage: ``python scripts/fuzz_api.py [--timeout 20] [--only NAME] [--show CLASS ...]``.
Prints the counts per class and the cases of the classes named by --show (default: every defect).
``--cli`` runs the command-line pass instead (every option of ``satgnc od simulate / od solve / rank /
rendezvous`` with NaN, Inf, negative, zero, huge, malformed and empty values).
"""

from __future__ import annotations

import argparse
import collections
import inspect
import multiprocessing as mp
import os
import pathlib
import re
import sys
import tempfile

import numpy as np
import satgnc
from satgnc import analysis as an
from satgnc import guidance as g
from satgnc import od
from satgnc.od import tdm
from satgnc.papers import l1_admm_rendezvous as nl
from satgnc.scenarios import l1_rendezvous as l1s

TMP = pathlib.Path(tempfile.mkdtemp(prefix="satgnc_fuzz_"))
X0 = np.array([7000.0, 0.0, 0.0, 0.0, 7.5, 1.0])
STATION_R0 = np.array([6378.0, 0.0, 0.0])
A2 = np.array([[0.0, 1.0], [-1.0, 0.0]])
B2 = np.array([[0.0], [1.0]])
C2 = np.array([[1.0, 0.0]])
AD, BD = g.cw_discretize(0.0011, 1.0, 60.0)
TIMES = np.linspace(0.0, 300.0, 7)


def _obs():
    st = od.station_inertial(STATION_R0)
    return od.simulate(X0, [st], TIMES, seed=1)


def _csv() -> str:
    p = TMP / "obs.csv"
    if not p.exists():
        o = _obs()
        lines = ["t,type,value,sigma,station"]
        for t, k, v, s, j in zip(o.t, o.type, o.value, o.sigma, o.station):
            lines.append(f"{t},{k if isinstance(k, str) else k.name},{v},{s},{j}")
        p.write_text("\n".join(lines) + "\n")
    return str(p)


def _tdm() -> str:
    p = TMP / "obs.tdm"
    if not p.exists():
        import datetime as dt

        tdm.write_tdm(p, _obs(), dt.datetime(2020, 1, 1), ["ST1"])
    return str(p)


def _case():
    return nl.paper_case(horizon=4)


def _solver():
    o = _obs()
    return od.solver(o, [od.station_inertial(STATION_R0)])


def _loss_rows():
    return an.loss_table(A2, B=np.eye(2))


def _f(t, x, u):
    return np.array([x[1], -x[0] + u[0]])


def _jac(t, x, u):
    return np.array([[0.0, 1.0], [-1.0, 0.0]]), np.array([[0.0], [1.0]])


# name -> (callable, good keyword arguments). Arguments not listed keep their defaults and are
# fuzzed too when they have a simple default (number, bool, string).
GOOD = {
    "satgnc.propagate": (satgnc.propagate, dict(x0=X0, times=[0.0, 60.0])),
    "satgnc.available_methods": (satgnc.available_methods, {}),
    "satgnc.ForceModel": (satgnc.ForceModel, dict(mu=satgnc.EARTH_MU)),
    "satgnc.J2Gravity": (satgnc.J2Gravity, dict(mu=satgnc.EARTH_MU, j2=1.08e-3, radius=6378.0)),
    "satgnc.ExponentialDrag": (satgnc.ExponentialDrag, dict(rho0=1e-12, h0=400.0, scale_height=60.0)),
    "ForceModel.acceleration": (lambda **k: satgnc.ForceModel().acceleration(**k),
                                dict(t=0.0, r=X0[:3], v=X0[3:])),
    "ExponentialDrag.density": (lambda **k: satgnc.ExponentialDrag(1e-12, 400.0, 60.0).density(**k),
                                dict(radius=6800.0)),
    "od.box_guesses": (od.box_guesses, dict(center=X0, half_width=np.ones(6), n=3)),
    "od.ellipsoid": (od.ellipsoid, dict(name="WGS-84")),
    "od.geodetic_to_ecef": (od.geodetic_to_ecef, dict(lat_deg=10.0, lon_deg=20.0, height_km=0.1)),
    "od.gmst": (od.gmst, dict(epoch="2020-01-01T00:00:00", ut1_minus_utc=0.1)),
    "od.julian_date": (od.julian_date, dict(epoch="2020-01-01T00:00:00")),
    "od.implied_rotation_rate": (od.implied_rotation_rate,
                                 dict(station_state=[6378.0, 10.0, 0.0, -7.3e-4, 0.465, 0.0])),
    "od.make_propagator": (od.make_propagator, dict(kind="kepler", mu=satgnc.EARTH_MU, j2=False)),
    "od.predict": (od.predict, dict(kind="range", x=X0, station_state=[6378.0, 0, 0, 0, 0.465, 0])),
    "od.read_csv": (od.read_csv, dict(path=None)),  # path filled at run time
    "od.settings": (od.settings, dict(method="levenberg_marquardt", max_iterations=20)),
    "od.simulate": (od.simulate, dict(x0=X0, stations=None, times=TIMES, sigma_range=1e-3,
                                      elevation_mask_deg=0.0, seed=1)),
    "od.six_point_conditions": (od.six_point_conditions,
                                dict(t=[0.0, 10, 20, 30, 40, 50], rho=[1000.0, 1001, 1002, 1003, 1004, 1005],
                                     rhodot=[0.1, 0.1, 0.1, 0.1, 0.1, 0.1])),
    "od.solve": (od.solve, dict(observations=None, stations=None, x0_guess=X0 + 0.1)),
    "od.station_geodetic": (od.station_geodetic, dict(lat_deg=10.0, lon_deg=20.0, height_km=0.1,
                                                      epoch="2020-01-01T00:00:00")),
    "od.station_inertial": (od.station_inertial, dict(r0=STATION_R0, omega=7.29e-5)),
    "od.root_search": (od.root_search, dict(solver_=None, guesses=np.array([X0 + 0.1]))),
    "tdm.parse_epoch": (tdm.parse_epoch, dict(text="2020-001T00:00:00")),
    "tdm.read_tdm": (tdm.read_tdm, dict(path=None)),
    "g.cw_discretize": (g.cw_discretize, dict(n=0.0011, mass=1.0, dt=60.0, method="zoh")),
    "g.cw_matrices": (g.cw_matrices, dict(n=0.0011, mass=1.0)),
    "g.cw_stm": (g.cw_stm, dict(n=0.0011, t=60.0)),
    "g.solve_l1": (g.solve_l1, dict(A=AD, B=BD, x0=[1.0, 0, 0, 0, 0, 0], horizon=5, Qf=np.eye(6))),
    "g.L1Solver": (g.L1Solver, dict(A=AD, B=BD, x0=[1.0, 0, 0, 0, 0, 0], horizon=5, Qf=np.eye(6),
                                    group_l2_weight=0.0, u_norm_max=0.0, terminal_equality=False)),
    "nl.drift_state": (nl.drift_state, dict(steps=10)),
    "nl.fly": (nl.fly, dict(case=None, U_si=np.zeros((3, 4)), substeps=2, integrator="rk4")),
    "nl.linear_cw_plan": (nl.linear_cw_plan, dict(case=None, eps=1e-6)),
    "nl.miss": (nl.miss, dict(X=np.zeros((12, 3)))),
    "nl.model_params": (nl.model_params, dict(published=True, j2=False, drag=True, rho0=1e-5)),
    "nl.paper_case": (nl.paper_case, dict(horizon=4, tf=600.0, substeps=1, constrained=False)),
    "nl.summarize": (nl.summarize, dict(case=None, U_scaled=np.zeros((3, 4)), zero_tol=1e-6)),
    "nl.solve_paper": (nl.solve_paper, dict(case=None, max_iter=3, ilqr_iters=1)),
    "an.controllability": (an.controllability, dict(A=A2, B=B2)),
    "an.observability": (an.observability, dict(A=A2, C=C2)),
    "an.controllability_gramian": (an.controllability_gramian, dict(A=A2, B=B2, T=1.0)),
    "an.observability_gramian": (an.observability_gramian, dict(A=A2, C=C2, T=1.0)),
    "an.cw_model": (an.cw_model, dict(mean_motion=0.0011)),
    "an.cw_units": (an.cw_units, dict(mean_motion=0.0011, length=1.0, n_outputs=0)),
    "an.distance_to_uncontrollability": (an.distance_to_uncontrollability, dict(A=A2, BC=B2, max_iter=20)),
    "an.expm": (an.expm, dict(M=A2)),
    "an.fd_jacobian": (an.fd_jacobian, dict(f=_f, t=0.0, x=[1.0, 0.0], u=[0.0])),
    "an.format_loss_table": (an.format_loss_table, dict(rows=None, names=["a", "b"], n=2, title="t")),
    "an.kalman_matrix": (an.kalman_matrix, dict(A=A2, B=B2)),
    "an.kalman_rank": (an.kalman_rank, dict(A=A2, BC=B2, fuzz=100.0)),
    "an.linearize": (an.linearize, dict(f=_f, jac=_jac, t=0.0, x=[1.0, 0.0], u=[0.0])),
    "an.loss_table": (an.loss_table, dict(A=A2, B=np.eye(2), fuzz=100.0)),
    "an.ltv_observability_gramian": (an.ltv_observability_gramian,
                                     dict(stms=np.array([np.eye(2), np.eye(2)]), H=np.array([C2, C2]))),
    "an.minimum_energy": (an.minimum_energy, dict(W=np.eye(2), x_f=[1.0, 1.0])),
    "an.nondimensionalize": (an.nondimensionalize,
                             dict(A=np.zeros((4, 4)), B=np.zeros((4, 2)), C=np.zeros((1, 4)), units=None)),
    "an.od_gramian": (an.od_gramian, dict(kind="range", times=TIMES, rate=7.27e-5)),
    "an.od_linear_model": (an.od_linear_model, dict(times=TIMES)),
    "an.orbit": (an.orbit, dict(spec="leo")),
    "an.pbh": (an.pbh, dict(A=A2, BC=B2, fuzz=100.0)),
    "an.polar_linear_model": (an.polar_linear_model, dict(sigma=1.0, omega=1.0)),
    "an.polar_model": (an.polar_model, dict(sigma=1.0, omega=1.0)),
    "an.polar_units": (an.polar_units, dict(sigma=1.0, omega=1.0, n_outputs=0)),
    "an.staircase": (an.staircase, dict(A=A2, BC=B2, fuzz=100.0)),
    "an.visibility_pass": (an.visibility_pass, dict(t_max=3600.0, dt=10.0, rate=7.27e-5)),
    "l1s.linear_problem": (l1s.linear_problem, dict(sc=None, case="unconstrained")),
    "l1s.paper_settings": (l1s.paper_settings, dict(sc=None, case="unconstrained")),
    "l1s.load": (l1s.load, dict(path=None)),
}

# Arguments that need an object built at run time (not fuzzed with numbers unless listed).
LATE = {
    ("od.read_csv", "path"): _csv,
    ("tdm.read_tdm", "path"): _tdm,
    ("od.simulate", "stations"): lambda: [od.station_inertial(STATION_R0)],
    ("od.solve", "observations"): _obs,
    ("od.solve", "stations"): lambda: [od.station_inertial(STATION_R0)],
    ("od.root_search", "solver_"): _solver,
    ("nl.fly", "case"): _case,
    ("nl.linear_cw_plan", "case"): _case,
    ("nl.summarize", "case"): _case,
    ("nl.solve_paper", "case"): _case,
    ("an.format_loss_table", "rows"): _loss_rows,
    ("an.nondimensionalize", "units"): lambda: an.polar_units(1.0, 1.0, n_outputs=1),
    ("l1s.linear_problem", "sc"): l1s.load,
    ("l1s.paper_settings", "sc"): l1s.load,
    ("l1s.load", "path"): lambda: None,
}

INVALID = ("nan", "inf", "-inf", "complex", "bool", "object", "string", "shape")


def _mutations(good):
    """(label, value) pairs for one argument whose good value is ``good``."""
    if isinstance(good, str):
        return [("unknown-name", "no-such-name"), ("int", 3), ("None", None), ("empty", "")]
    if isinstance(good, (bool, np.bool_)):
        return [("string", "false"), ("int-for-bool", 1), ("None", None), ("complex", 1j)]
    if isinstance(good, (int, np.integer)):
        return [("nan", float("nan")), ("float-for-int", float(good) + 0.5), ("bool", True), ("string", "3"),
                ("neg", -1), ("zero", 0), ("huge", 2**70), ("complex", 1j), ("None", None)]
    if isinstance(good, (float, np.floating)):
        return [("nan", float("nan")), ("inf", float("inf")), ("-inf", -float("inf")), ("complex", 1 + 1j),
                ("bool", True), ("string", "1.0"), ("None", None), ("neg", -abs(good) - 1.0), ("zero", 0.0),
                ("huge", 1e300), ("shape", [good, good])]
    arr = np.asarray(good) if isinstance(good, (list, tuple, np.ndarray)) else None
    if arr is not None and arr.dtype.kind in "fiu" and arr.size:
        bad_nan = arr.astype(float).copy()
        bad_nan.flat[0] = np.nan
        bad_inf = arr.astype(float).copy()
        bad_inf.flat[-1] = np.inf
        obj = arr.astype(object)
        obj.flat[0] = "x"
        return [("nan", bad_nan), ("inf", bad_inf), ("complex", arr.astype(complex) + 1j),
                ("bool", np.ones(arr.shape, dtype=bool)), ("object", obj), ("string", "abc"),
                ("shape", np.zeros(arr.size + 1)), ("empty", []), ("None", None),
                ("huge", arr.astype(float) * 1e300 + 1e300)]
    return [("None", None), ("int", 3), ("string", "abc")]


def build_cases(only: str | None):
    cases = []
    for name, (fn, good) in GOOD.items():
        if only and only != name:
            continue
        params = dict(good)
        try:
            sig = inspect.signature(fn)
            for p in sig.parameters.values():
                if p.name in params or p.kind in (p.VAR_KEYWORD, p.VAR_POSITIONAL):
                    continue
                if isinstance(p.default, (int, float, str, bool)) and p.default is not None:
                    params[p.name] = p.default
        except (TypeError, ValueError):
            pass
        cases.append((name, None, "good", None))
        for arg, value in params.items():
            if (name, arg) in LATE and value is None:
                muts = [("None-object", None), ("int", 3), ("string", "abc")]
            else:
                muts = _mutations(value)
            for label, bad in muts:
                cases.append((name, arg, label, bad))
    return cases


def _kwargs(name: str) -> dict:
    fn, good = GOOD[name]
    kw = dict(good)
    for (n, arg), make in LATE.items():
        if n == name and kw.get(arg, "missing") is None:
            kw[arg] = make()
    return kw


def _names_arg(msg: str, arg: str) -> bool:
    alias = {"solver_": "solver", "BC": "B"}
    keys = {arg, alias.get(arg, arg)}
    return any(re.search(rf"(^|[\s'\"`(\[,.]){re.escape(k)}(\b|\[|:)", msg) for k in keys)


def run_case(case):
    name, arg, label, bad = case
    fn, _ = GOOD[name]
    kw = _kwargs(name)
    if arg is not None:
        kw[arg] = bad
    try:
        out = fn(**kw)
    except (TypeError, ValueError, FileNotFoundError, IsADirectoryError, satgnc.PropagationError) as e:
        msg = f"{type(e).__name__}: {e}"
        if arg is None:
            return "good-failed", msg
        if "incompatible function arguments" in msg or "Invoked with" in msg:
            return "unclear", msg
        if isinstance(e, satgnc.PropagationError):
            return "unclear", msg
        return ("clear" if _names_arg(str(e), arg) else "unclear"), msg
    except Exception as e:  # noqa: BLE001 - classifying every failure is the point
        return ("good-failed" if arg is None else "unclear"), f"{type(e).__name__}: {e}"
    if arg is None:
        return "good", ""
    if label in INVALID:
        return "silent", f"returned {type(out).__name__}"
    if not _all_finite(out) and _good_is_finite(name):  # NaN / Inf where a good call has none: garbage
        return "silent", f"returned {type(out).__name__} holding NaN or Inf"
    return "accepted", f"returned {type(out).__name__}"


_GOOD_FINITE: dict = {}


def _good_is_finite(name: str) -> bool:
    """Whether the good call's result is free of NaN / Inf (reports may hold inf by design)."""
    if name not in _GOOD_FINITE:
        _GOOD_FINITE[name] = _all_finite(GOOD[name][0](**_kwargs(name)))
    return _GOOD_FINITE[name]


def _all_finite(out, depth: int = 0) -> bool:
    """False when a float, an array, or a container / dataclass / object attribute holds NaN or Inf."""
    if depth > 3:
        return True
    if isinstance(out, (float, np.floating)):
        return bool(np.isfinite(out))
    if isinstance(out, np.ndarray):
        return out.dtype.kind not in "fc" or bool(np.all(np.isfinite(out)))
    if isinstance(out, (list, tuple)):
        return all(_all_finite(v, depth + 1) for v in out)
    if isinstance(out, dict):
        return all(_all_finite(v, depth + 1) for k, v in out.items() if k != "extra")
    if hasattr(out, "__dataclass_fields__"):
        return all(_all_finite(getattr(out, f), depth + 1) for f in out.__dataclass_fields__ if f != "extra")
    return True


def _worker(conn, cases):
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    while True:
        i = conn.recv()
        if i is None:
            return
        try:
            res = run_case(cases[i])
        except BaseException as e:  # noqa: BLE001
            res = ("unclear", f"{type(e).__name__}: {e}")
        conn.send(res)


CLI_VALUES = ["nan", "inf", "-1", "0", "1e300", "x", "", "1,2", "-1e300,0,0,0,0,0", "0,0,0,0,0,0",
              "nan,0,0,0,7,0"]


def cli_pass(timeout: float) -> int:
    """Every option of the CLI subcommands with CLI_VALUES: ``clear`` = exit code 2 with one short
    error line naming the option, ``accepted`` = exit code 0, anything else ``unclear`` / ``hang``."""
    import shutil
    import subprocess

    exe = shutil.which("satgnc") or str(pathlib.Path(sys.executable).with_name("satgnc"))
    obs = _csv()
    out = str(TMP / "cli")
    base = {
        "od simulate": (["od", "simulate", "--out", out + ".csv"],
                        ["--state", "--duration", "--step", "--sigma-range", "--sigma-range-rate", "--seed"]),
        "od solve": (["od", "solve", obs, "--station-inertial", "6378,0,0", "--guess", "7000,0,0,0,7.5,1",
                      "--max-iterations", "5"],
                     ["--guess", "--station", "--station-inertial", "--epoch", "--ut1-utc", "--ellipsoid",
                      "--method", "--propagator", "--max-iterations", "--sigma-range", "--sigma-range-rate"]),
        "rank": (["rank"], ["--model", "--orbit", "--units"]),
        "rendezvous": (["rendezvous", "--out", out], ["--scenario", "--case", "--model"]),
    }
    counts = collections.Counter()
    for name, (args, opts) in base.items():
        for opt in opts:
            for v in CLI_VALUES:
                try:
                    p = subprocess.run([exe, *args, opt, v], capture_output=True, text=True, timeout=timeout)
                except subprocess.TimeoutExpired:
                    cls, msg = "hang", ""
                else:
                    err = p.stderr.strip()
                    if p.returncode == 2 and "Traceback" not in err and len(err.splitlines()) <= 3:
                        cls = "clear" if opt.lstrip("-") in err else "unclear"
                    else:
                        cls = "accepted" if p.returncode in (0, 1) and not err else "unclear"
                    msg = err[-200:] or p.stdout[-120:]
                counts[cls] += 1
                if cls not in ("clear", "accepted"):
                    print(f"[{cls}] satgnc {name} {opt} {v!r}: {msg!r}")
    print(f"CLI: {sum(counts.values())} cases: {dict(counts)}")
    return 0


def _file_mutants(text: str):
    """(label, text) variants of a good file: every line dropped or duplicated, every number replaced
    by NaN / Inf / -1 / 0 / 1e300 / a word, every '=' or ',' dropped, truncations, binary bytes."""
    lines = text.splitlines()
    yield "empty", ""
    yield "truncated", text[: len(text) // 2]
    yield "binary", "\x00\xff" + text
    for i in range(len(lines)):
        yield f"drop {i + 1}", "\n".join(lines[:i] + lines[i + 1:]) + "\n"
        yield f"dup {i + 1}", "\n".join(lines[: i + 1] + lines[i:]) + "\n"
        for m in re.finditer(r"-?\d+(\.\d+)?(e[-+]?\d+)?", lines[i]):
            for rep in ("nan", "inf", "-1", "0", "1e300", "x"):
                new = lines[i][: m.start()] + rep + lines[i][m.end():]
                label = f"line {i + 1} number {m.group(0)!r} -> {rep}"
                yield label, "\n".join(lines[:i] + [new] + lines[i + 1:]) + "\n"
            break  # the first number of each line
        for ch in ("=", ","):
            if ch in lines[i]:
                yield f"line {i + 1} without {ch!r}", "\n".join(lines[:i] + [lines[i].replace(ch, " ", 1)]
                                                                 + lines[i + 1:]) + "\n"


def files_pass() -> int:
    """CSV, TDM and scenario-TOML readers on mutants of good files: ``clear`` = a FileFormatError (a
    ValueError) naming the file, ``accepted`` = read without error (review: NaN / Inf in the result is
    counted ``silent``), anything else ``unclear``."""
    from satgnc._validate import FileFormatError

    readers = {
        "csv": (od.read_csv, pathlib.Path(_csv()).read_text()),
        "tdm": (tdm.read_tdm, pathlib.Path(_tdm()).read_text()),
        "toml": (l1s.load, l1s.DEFAULT.read_text() if hasattr(l1s.DEFAULT, "read_text")
                 else pathlib.Path(l1s.DEFAULT).read_text()),
    }
    counts = collections.Counter()
    for kind, (reader, text) in readers.items():
        for label, variant in _file_mutants(text):
            p = TMP / f"mutant.{kind}"
            p.write_bytes(variant.encode("utf-8", "surrogateescape") if "\x00" not in variant
                          else variant.encode("latin-1", "replace"))
            try:
                out = reader(p)
            except FileFormatError as e:
                cls = "clear" if str(p) in str(e) else "unclear"
                msg = str(e)
            except Exception as e:  # noqa: BLE001
                cls, msg = "unclear", f"{type(e).__name__}: {e}"
            else:
                vals = [getattr(out, f, None) for f in ("t", "value", "sigma")]
                finite = all(v is None or np.all(np.isfinite(np.asarray(v, dtype=float))) for v in vals)
                cls, msg = ("accepted", "") if finite else ("silent", "NaN / Inf in the table")
            counts[(kind, cls)] += 1
            if cls in ("unclear", "silent"):
                print(f"[{cls}] {kind} {label}: {msg[:200]}")
    for kind in readers:
        classes = ("clear", "unclear", "silent", "accepted")
        print(f"{kind}: " + ", ".join(f"{c} {counts[(kind, c)]}" for c in classes))
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--timeout", type=float, default=20.0)
    ap.add_argument("--only")
    ap.add_argument("--show", nargs="*", default=["unclear", "silent", "hang", "crash", "good-failed"])
    ap.add_argument("--cli", action="store_true", help="fuzz the command-line interface instead")
    ap.add_argument("--files", action="store_true", help="fuzz the CSV / TDM / TOML readers instead")
    args = ap.parse_args()
    if args.cli:
        return cli_pass(max(args.timeout, 60.0))
    if args.files:
        return files_pass()
    cases = build_cases(args.only)
    ctx = mp.get_context("fork")
    results = []
    proc = conn = None
    for i, case in enumerate(cases):
        if proc is None or not proc.is_alive():
            conn, child = ctx.Pipe()
            proc = ctx.Process(target=_worker, args=(child, cases), daemon=True)
            proc.start()
        conn.send(i)
        if conn.poll(args.timeout):
            try:
                results.append((case, *conn.recv()))
            except EOFError:
                results.append((case, "crash", f"exit code {proc.exitcode}"))
                proc = None
        else:
            alive = proc.is_alive()
            results.append((case, "hang" if alive else "crash", f"exit code {proc.exitcode}"))
            if alive:
                proc.kill()  # the worker this script started
            proc.join()
            proc = None
    if proc is not None and proc.is_alive():
        conn.send(None)
        proc.join(5)
    counts = collections.Counter(r[1] for r in results if r[0][1] is not None)
    goods = collections.Counter(r[1] for r in results if r[0][1] is None)
    print(f"{len(results) - sum(goods.values())} fuzz cases over {sum(goods.values())} callables "
          f"(good calls: {dict(goods)})")
    for k in ("clear", "unclear", "silent", "accepted", "hang", "crash"):
        print(f"  {k:9s} {counts.get(k, 0)}")
    for (name, arg, label, _bad), cls, msg in results:
        if cls in args.show:
            print(f"[{cls}] {name}({arg}={label}): {msg[:240]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
