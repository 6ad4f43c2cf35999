"""Issue 17: a Python user's paths. The README's quick start runs; the stubs cover every compiled
name; defaults carry no paper constant (0 deg elevation mask, the Earth's rotation rate); the OD
command line takes station names from CSV files and says how unnamed stations were matched; a user's
rendezvous scenario with its own case names never mentions the paper and reports an unreachable
target with the best achievable miss; ``satgnc reproduce`` without the test extra skips the cvxpy
cross-check with one line and exit code 3."""

from __future__ import annotations

import ast
import json
import pathlib
import re
import sys

import numpy as np
import pytest
import satgnc
from satgnc import _satgnc, analysis, cli, od
from satgnc.papers import od_newton_raphson as paper

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _readme_blocks() -> list[str]:
    return re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), flags=re.S)


def test_readme_python_blocks_run():
    blocks = _readme_blocks()
    assert len(blocks) >= 2  # the quick start, then OD + guidance + analysis
    spaces = []
    for code in blocks:
        ns: dict = {}
        exec(compile(code, "README.md", "exec"), ns)  # noqa: S102 - the README's own code
        spaces.append(ns)
    # The quick start's stated shapes (its comment says (5, 6), (5, 6, 6)).
    assert spaces[0]["traj"].states.shape == (5, 6) and spaces[0]["traj"].stms.shape == (5, 6, 6)
    # The second block's comments: a converged fit, a solved plan, an uncontrollable single axis.
    assert spaces[1]["fit"].status.name == "converged"
    assert spaces[1]["plan"].status == "solved"
    assert spaces[1]["analysis"].controllability(spaces[1]["A"], spaces[1]["B"][:, [1]]).rank == 4  # of 6


def test_stub_covers_every_compiled_name():
    stub = ast.parse((ROOT / "python" / "satgnc" / "_satgnc.pyi").read_text())
    declared = set()
    for node in stub.body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            declared.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            declared.add(node.target.id)
        elif isinstance(node, ast.Assign):
            declared.update(t.id for t in node.targets if isinstance(t, ast.Name))
    compiled = {n for n in dir(_satgnc) if not n.startswith("__")}
    missing = sorted(compiled - declared)
    assert missing == [], f"_satgnc.pyi lacks {missing}: run scripts/gen_stub.py"


def test_public_namespaces_hide_module_imports():
    # dir() of a public package lists its API, not the modules it imports (np, math, dataclasses).
    import importlib

    for name in ("od", "analysis", "guidance", "io", "observation", "frames", "dynamics", "propagation"):
        mod = importlib.import_module(f"satgnc.{name}")
        imported = {"np", "math", "dataclasses", "numbers", "os", "pathlib", "functools"}
        leaked = sorted(imported & set(dir(mod)))
        assert leaked == [], f"{mod.__name__}: {leaked}"
        assert set(mod.__all__) <= set(dir(mod)), mod.__name__


def test_simulate_masks_at_0_deg_by_default():
    # The paper's state seen from the antipodal point of its station: below the horizon all the time.
    st = od.station_inertial(-np.asarray(paper.station_state_table3()[:3]))
    t = np.arange(0.0, 301.0, 30.0)
    with pytest.raises(ValueError, match="elevation_mask_deg"):
        od.simulate(paper.truth(), st, t, seed=None)
    through = od.simulate(paper.truth(), st, t, seed=None, elevation_mask_deg=None)  # the old behaviour
    assert len(through) == 2 * t.size  # range and range rate at every time


def test_visibility_pass_defaults_to_the_earth_rate():
    assert analysis.EARTH_RATE == pytest.approx(7.292115e-5, rel=1e-9)
    default = analysis.visibility_pass()
    earth = analysis.visibility_pass(rate=analysis.EARTH_RATE)
    paper_rate = analysis.visibility_pass(rate=analysis.EARTH_RATE_PAPER)
    assert default == earth
    assert default != paper_rate  # the two rates give different passes (to the 10 s search step)


@pytest.fixture(scope="module")
def named_csv(tmp_path_factory):
    d = tmp_path_factory.mktemp("named")
    st = paper.station()
    obs = od.simulate(paper.truth(), st, np.arange(0.0, 301.0, 30.0), seed=None)
    rows = "".join(f"{t},{k},{float(v)!r},{s},BOULDER\n" for t, k, v, s in
                   zip(obs.t, obs.type_names(), obs.value, obs.sigma))
    (d / "named.csv").write_text("t,type,value,sigma,station\n" + rows)
    (d / "mixed.csv").write_text("t,type,value,sigma,station\n0,range,1000,0.001,BOULDER\n"
                                 "10,range,1000,0.001,0\n")
    return d


def test_cli_csv_station_names(named_csv, capsys):
    r0 = ",".join(f"{v:.9g}" for v in paper.station_state_table3()[:3])
    guess = ",".join(f"{v:.9g}" for v in paper.truth() + np.array([10.0, 0, 0, 0, 0, 0]))
    rc = cli.main(["od", "solve", str(named_csv / "named.csv"), "--station-inertial", f"BOULDER:{r0},7.27e-5",
                   "--guess", guess])
    out = capsys.readouterr()
    assert rc == 0 and "converged" in out.out, out.err
    rc = cli.main(["od", "solve", str(named_csv / "named.csv"), "--station-inertial", f"PERTH:{r0}",
                   "--guess", guess])
    err = capsys.readouterr().err
    assert rc == 2 and "'BOULDER'" in err and "PERTH" in err, err  # a name mismatch is an error


def test_csv_mixing_names_and_indices_names_the_line(named_csv):
    with pytest.raises(ValueError, match=r"mixed.csv:3: column 'station': an index \('0'\)"):
        od.read_csv(named_csv / "mixed.csv")


def test_cli_unnamed_stations_warn_with_the_mapping(tmp_path, capsys):
    e = "2026-03-20T12:00:00"
    sts = [od.station_geodetic(0.0, 5.0, 0.0, e), od.station_geodetic(-33.0, -70.0, 0.7, e)]
    x0 = np.array([6778.137, 0.0, 0.0, 0.0, 4.7302, 6.0354])
    obs = od.simulate(x0, sts, np.arange(0.0, 6000.0, 60.0), seed=None)
    import datetime as dt

    from satgnc.od import tdm

    tdm.write_tdm(tmp_path / "two.tdm", obs, dt.datetime(2026, 3, 20, 12), ["EQ", "SOUTH"])
    guess = ",".join(f"{v:.9g}" for v in x0 + np.array([5.0, 0, 0, 0, 0, 0]))
    rc = cli.main(["od", "solve", str(tmp_path / "two.tdm"), "--station", "0,5,0", "--station", "-33,-70,0.7",
                   "--epoch", e, "--guess", guess])
    out = capsys.readouterr()
    assert rc == 0, out.err
    assert "warning: the --station options are not named" in out.err
    assert "EQ = 0,5,0, SOUTH = -33,-70,0.7" in out.err  # the mapping, in the file's order


def _user_scenario(tmp_path, u_max: float, mass: float) -> pathlib.Path:
    text = (ROOT / "examples" / "python" / "user_rendezvous.toml").read_text()
    text = text.replace("mass = 12.0", f"mass = {mass}").replace("u_max = 0.02", f"u_max = {u_max}")
    p = tmp_path / "user.toml"
    p.write_text(text)
    return p


def test_user_scenario_any_case_name_no_paper(tmp_path, capsys):
    rc = cli.main(["rendezvous", "--scenario", str(_user_scenario(tmp_path, 0.02, 12.0)), "--out",
                   str(tmp_path / "out")])
    out = capsys.readouterr().out
    assert rc == 0
    assert out.startswith("approach: solved")
    assert "paper" not in out.lower()
    assert (tmp_path / "out" / "approach.png").exists() and (tmp_path / "out" / "summary.json").exists()
    summary = (tmp_path / "out" / "summary.json").read_text()
    assert "paper" not in summary.lower()  # no paper_* key, no paper_comparison section
    assert json.loads(summary)["approach"]["conv_status"] == "solved"


def test_paper_scenario_keeps_its_comparison_in_a_named_section(tmp_path, capsys):
    assert cli.main(["rendezvous", "--out", str(tmp_path), "--case", "unconstrained", "--case", "box"]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert not [k for k in s["unconstrained"] if k.startswith("paper_") and k != "paper_comparison"]
    assert s["unconstrained"]["paper_comparison"]["iterations"] >= 1  # the published stopping rule
    assert "paper_comparison" not in s["box"]  # the packaged file's own case, not in the paper
    assert s["paper_comparison"]["fig1_dv_m_s"]["l1"] < s["paper_comparison"]["fig1_dv_m_s"]["quadratic"]
    assert "unconstrained: solved" in capsys.readouterr().out


def _min_position_miss_cvxpy(path, case: str = "approach") -> float:
    """Independent check: min |r_N| (m) under the case's box with cvxpy + Clarabel."""
    cp = pytest.importorskip("cvxpy")
    from satgnc.scenarios import l1_rendezvous as scen

    sc = scen._load(path, "scenario")
    kw = scen.linear_problem(sc, case)
    A, B, N = kw["A"], kw["B"], kw["horizon"]
    # r_N = (A^N x0)[:3] + sum_k (A^(N-1-k) B)[:3] u_k, as one matrix on the stacked controls
    M = np.hstack([(np.linalg.matrix_power(A, N - 1 - k) @ B)[:3] for k in range(N)])
    u = cp.Variable(3 * N)
    lo, hi = np.tile(kw["u_lower"], N), np.tile(kw["u_upper"], N)
    rN = (np.linalg.matrix_power(A, N) @ kw["x0"])[:3] + M @ u
    prob = cp.Problem(cp.Minimize(cp.sum_squares(rN)), [u <= hi, u >= lo])
    prob.solve(solver="CLARABEL")
    return float(np.sqrt(prob.value) * sc.l_ref)


@pytest.mark.parametrize(("u_max", "mass"), [(2e-4, 12.0), (5e-4, 12.0), (1e-3, 40.0)])
def test_unreachable_target_reports_best_miss(tmp_path, capsys, u_max, mass):
    # 0.2 mN per axis on 12 kg over 3000 s: at most 0.05 m/s of dv per axis, while the chaser starts
    # 1.5 km away drifting at 0.3 m/s: the exact arrival is infeasible (and with the two other bounds).
    path = _user_scenario(tmp_path, u_max, mass)
    rc = cli.main(["rendezvous", "--scenario", str(path), "--out", str(tmp_path / "out")])
    out = capsys.readouterr().out
    assert rc == cli.EXIT_UNREACHABLE == 4  # not 0 (done) and not 2 (bad input)
    m = re.search(r"approach: target unreachable \((\w+) .*best achievable miss is ([0-9.]+) m", out)
    assert m, out
    assert m.group(1) in ("primal_infeasible", "terminal_unreachable", "max_iterations")
    assert out.strip().splitlines()[-1].endswith("exit code 4")
    s = json.loads((tmp_path / "out" / "summary.json").read_text())["approach"]
    assert s["unreachable"] is True and s["best_miss_m"] == pytest.approx(float(m.group(2)), abs=1e-3)
    # The best achievable miss is the minimum position miss: cvxpy + Clarabel agree to 1e-6 relative
    # (measured 7e-10 on the 0.2 mN case: 301.196321 m both; the old full-state weight gave 443.6 m).
    assert s["best_miss_m"] == pytest.approx(_min_position_miss_cvxpy(path), rel=1e-6)
    assert s["best_miss_m"] > 100.0  # the drift alone carries it 900 m; thrust removes at most 150 m
    assert s["best_miss_m"] <= s["conv_miss_m"] * (1 + 1e-9)  # never worse than the stopped iterate
    assert "paper" not in out.lower()


def test_unreachable_target_nonlinear_model(tmp_path, capsys):
    path = _user_scenario(tmp_path, 2e-4, 12.0)
    rc = cli.main(["rendezvous", "--scenario", str(path), "--model", "nonlinear", "--out",
                   str(tmp_path / "nl")])
    out = capsys.readouterr().out
    assert rc == cli.EXIT_UNREACHABLE, out
    assert "nonlinear approach: target unreachable (inner_infeasible" in out and "optimum" not in out
    s = json.loads((tmp_path / "nl" / "nonlinear_summary.json").read_text())["nonlinear_approach"]
    assert s["unreachable"] is True and s["scp_status"] == "inner_infeasible"
    # the linear CW model's best miss (301.196 m); SCP's stopped nonlinear plan misses by 301.46 m: the
    # two models agree to 0.1 % on a 1.5 km approach
    assert s["best_miss_m_linear_cw"] == pytest.approx(_min_position_miss_cvxpy(path), rel=1e-6)
    assert s["opt_miss_position"] == pytest.approx(s["best_miss_m_linear_cw"], rel=1e-2)
    assert "paper" not in out.lower()


def test_rendezvous_without_matplotlib_writes_the_numbers(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # as on an install without [plot]
    rc = cli.main(["rendezvous", "--scenario", str(_user_scenario(tmp_path, 0.02, 12.0)), "--out",
                   str(tmp_path / "out")])
    out = capsys.readouterr().out
    assert rc == cli.EXIT_NO_FIGURES == 5
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["summary.json"]
    assert json.loads((tmp_path / "out" / "summary.json").read_text())["approach"]["conv_status"] == "solved"
    line = [ln for ln in out.splitlines() if "matplotlib" in ln]
    assert len(line) == 1 and 'pip install "satgnc[plot]"' in line[0] and line[0].endswith("exit code 5")
    # unreachable wins over missing figures
    rc = cli.main(["rendezvous", "--scenario", str(_user_scenario(tmp_path, 2e-4, 12.0)), "--out",
                   str(tmp_path / "out2")])
    assert rc == cli.EXIT_UNREACHABLE


def test_mission_without_matplotlib_writes_the_numbers(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    rc = cli.main(["mission", "--quick", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert rc == cli.EXIT_NO_FIGURES
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mission.md", "mission_summary.json"]
    assert "![" not in (tmp_path / "mission.md").read_text()
    js = json.loads((tmp_path / "mission_summary.json").read_text())  # the numbers, without the figure
    assert js["statuses"]["od"] == "converged" and js["statuses"]["plan"] == "solved"
    assert js["observations"] > 0
    assert out.strip().splitlines()[-1].endswith("exit code 5") and "satgnc[plot]" in out


def test_reproduce_without_matplotlib_writes_the_report(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    rc = cli.main(["reproduce", "--section", "propagation", "--section", "guidance", "--quick", "--out",
                   str(tmp_path), "--no-progress"])
    out = capsys.readouterr().out
    assert rc == cli.EXIT_NO_FIGURES == 5
    report = (tmp_path / "README.md").read_text()
    assert "| adams | 1e-10 |" in report and "Fig. 1: same initial state" in report  # the numbers
    assert "## Figures not drawn" in report and "![" not in report
    assert "propagation_accuracy" in report and "guidance_fig1_quadratic_vs_l1" in report
    assert not (tmp_path / "figures").exists()
    line = [ln for ln in out.splitlines() if "matplotlib" in ln]
    assert len(line) == 1 and 'satgnc[plot]' in line[0] and line[0].endswith("exit code 5")


def test_reproduce_without_cvxpy_skips_with_one_line_and_exit_3(tmp_path, capsys, monkeypatch):
    for name in ("cvxpy", "clarabel"):
        monkeypatch.setitem(sys.modules, name, None)  # as on a [plot]-only install
    rc = cli.main(["reproduce", "--section", "guidance", "--out", str(tmp_path), "--no-progress"])
    out = capsys.readouterr().out
    assert rc == cli.EXIT_PARTIAL == 3
    skip = [ln for ln in out.splitlines() if "skipped" in ln]
    assert len(skip) == 1 and 'pip install "satgnc[test]"' in skip[0] and "cvxpy" in skip[0]
    report = (tmp_path / "README.md").read_text()
    assert "## Cross-checks not run" in report and "n/a (no cvxpy)" in report


def test_missing_matplotlib_names_the_extra():
    e = ModuleNotFoundError("No module named 'matplotlib'", name="matplotlib")
    assert cli._message(e).endswith('(install the optional dependency: pip install "satgnc[plot]")')


def test_reprs_summarise_and_properties_have_units():
    obs = od.simulate(paper.truth(), paper.station(), np.arange(0.0, 301.0, 30.0), seed=None)
    r = od.solve(obs, paper.station(), paper.truth() + np.array([1.0, 0, 0, 0, 0, 0]))
    text = repr(r)
    assert text.startswith("OdResult(status=converged, iterations=") and "km/s" in text
    assert " at 0x" not in text
    assert repr(od.solver(obs, paper.station())).startswith("OdSolver(rows=22")
    sig = str(__import__("inspect").signature(satgnc.propagate))
    assert "object at" not in sig and "EARTH_MU" in sig
    units = re.compile(r"\((km|m|s|kg|rad/s|km/s|kg/m\^3|m\^2|km\^3/s\^2|unit-free)[,)/ ^]")
    for cls in (od.OdResult, od.Station, satgnc.Trajectory, satgnc.ExponentialDrag, satgnc.J2Gravity):
        for name, v in vars(cls).items():
            if isinstance(v, property):
                assert (v.__doc__ or "").strip(), f"{cls.__name__}.{name} has no docstring"
    for name in ("rho0", "h0", "scale_height", "area", "mass"):
        doc = getattr(satgnc.ExponentialDrag, name).__doc__
        assert units.search(doc), f"ExponentialDrag.{name}: no unit in {doc!r}"
    assert "kg/m^3" in satgnc.ExponentialDrag.__doc__


def test_cw_frames_convert_by_name():
    # Guidance's CW frame (y radial, x = minus along-track) and analysis's Hill frame (x radial,
    # y along-track) describe the same dynamics: T A_cw T^-1 = A_hill and T B_cw R^T = B_hill (mass 1 kg, so
    # a force of 1 N is an acceleration of 1 m/s^2), with T the state map of cw_to_hill. Exact up to
    # rounding of the n^2 terms (rtol 1e-12).
    from satgnc import guidance

    n = 0.0011
    T = guidance.cw_to_hill(np.eye(6)).T  # columns: images of the unit states
    A_cw, B_cw = guidance.cw_matrices(n, 1.0)
    A_h, B_h, _ = analysis.cw_model(n)
    np.testing.assert_allclose(T @ A_cw @ np.linalg.inv(T), A_h, rtol=1e-12, atol=1e-15)
    R = T[:3, :3]  # the force components rotate like the position: u_hill = R u_cw
    np.testing.assert_allclose(T @ B_cw @ R.T, B_h, rtol=1e-12, atol=1e-15)
    x = np.array([-1500.0, 200.0, 50.0, 0.3, 0.0, -0.05])
    np.testing.assert_array_equal(guidance.cw_to_hill(x), [200.0, 1500.0, 50.0, 0.0, -0.3, -0.05])
    np.testing.assert_array_equal(guidance.hill_to_cw(guidance.cw_to_hill(x)), x)
    assert "minus along-track" in guidance.CW_FRAME and "radial" in guidance.cw_discretize.__doc__


def test_scenario_schema_documented_with_every_key():
    # docs/scenarios.md lists every key of the strict schema (a key added to the schema without its
    # documentation fails here), with its section.
    from satgnc.scenarios import rendezvous as rv

    doc = (ROOT / "docs" / "scenarios.md").read_text()
    rows = [ln for ln in doc.splitlines() if ln.startswith("| `[")]
    for section, keys in rv.SECTIONS.items():
        for key in keys:
            assert any(f"`[{section}]`" in r and f"`{key}`" in r for r in rows), f"[{section}] {key}"
    for key in (*rv.CASE, *rv.CASE_NONLINEAR):
        assert any("`[cases.<name>" in r and f"`{key}`" in r for r in rows), f"[cases.<name>] {key}"


def test_observations_write_csv_round_trip(tmp_path):
    obs = od.simulate(paper.truth(), paper.station(), np.arange(0.0, 301.0, 30.0), seed=4)
    back = od.read_csv(obs.write_csv(tmp_path / "o.csv"))
    # repr of a float is exact: the round trip is bitwise.
    np.testing.assert_array_equal(back.value, obs.value)
    np.testing.assert_array_equal(back.t, obs.t)
    assert back.type_names() == obs.type_names() and back.station.tolist() == obs.station.tolist()
    named, names = od.read_csv_names(obs.write_csv(tmp_path / "n.csv", ["BOULDER"]))
    assert names == ["BOULDER"] and np.array_equal(named.value, obs.value)
    with pytest.raises(ValueError, match="station_names: a name starts with a letter"):
        obs.write_csv(tmp_path / "x.csv", ["1ST"])


def test_plot_style_legend_outside_and_palette():
    from satgnc import plotting

    plt = plotting.pyplot()
    # Okabe-Ito hex codes (Okabe & Ito 2008), one colour per axis.
    assert plotting.AXIS_COLORS == ("#0072B2", "#D55E00", "#009E73")
    fig, ax = plt.subplots()
    for i in range(3):
        ax.plot([0, 1], [i, i + 1], color=plotting.AXIS_COLORS[i], label=f"u{i + 1}")
    plotting.mark_start_target(ax, (0.0, 0.0), (1.0, 3.0))
    plotting.legend_outside(ax)
    fig.canvas.draw()
    leg = ax.get_legend().get_window_extent()
    assert leg.x0 >= ax.get_window_extent().x1  # the legend starts right of the axes: never over data
    assert [t.get_text() for t in ax.get_legend().get_texts()][-2:] == ["start", "target"]
    plt.close(fig)


@pytest.mark.parametrize("page", ["od.md", "analysis.md"])
def test_docs_python_blocks_run(page):
    # The guides' ```python blocks are runnable as written (the gallery holds the longer scripts).
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / page).read_text(), flags=re.S)
    assert blocks, f"docs/{page} has no code example"
    for code in blocks:
        exec(compile(code, f"docs/{page}", "exec"), {})  # noqa: S102 - the docs' own code
