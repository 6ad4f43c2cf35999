"""The run record of every solver result as one read-only ``info`` (issue 12, solver contract):
``L1Result.info`` and a linear ``guidance.Plan.info`` are a :class:`satgnc.guidance.AdmmInfo`,
``OdResult.info`` the C++ ``OdInfo``. Every former attribute stays, with the same value."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
from satgnc import _satgnc as _c
from satgnc import guidance as g
from satgnc import od
from satgnc.guidance import AdmmInfo, plan
from satgnc.papers import od_newton_raphson as paper
from satgnc.scenarios import l1_rendezvous as scen
from satgnc.scenarios import rendezvous as rv

SC = scen.load()


@pytest.fixture(scope="module")
def l1():
    kw = scen.linear_problem(SC, "unconstrained")
    return g.L1Solver(**kw, settings=scen.paper_settings(SC, "unconstrained")).solve()


def test_l1_result_info_is_a_read_only_record_equal_to_the_attributes(l1):
    info = l1.info
    assert isinstance(info, AdmmInfo)
    assert info.status == l1.status == "solved_paper_rule"
    assert info.iterations == l1.iterations == 43  # test_guidance: Table 1
    for f in dataclasses.fields(AdmmInfo):
        if f.name != "raw":
            assert getattr(info, f.name) == getattr(l1, f.name), f.name
    assert info.raw is None
    assert info.solve_time > 0.0
    assert info.ipm_iterations == 0 and info.ipm_solved is False
    with pytest.raises(dataclasses.FrozenInstanceError):
        info.status = "x"  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        l1.info = info  # type: ignore[misc]


def test_ipm_fields_reach_the_info():
    st = scen.paper_settings(SC, "constrained")
    st.update(method="ipm", stopping="residuals")
    r = g.L1Solver(**scen.linear_problem(SC, "constrained"), settings=st).solve()
    assert r.info.ipm_iterations == r.ipm_iterations > 0
    assert r.info.ipm_solved == r.ipm_solved
    assert r.info.status == r.status


def test_linear_plan_info_is_the_admm_info_and_the_old_dict_still_answers():
    pb = rv.problem(rv.load(), "unconstrained", "nonlinear")
    p = plan(pb, "linear", discretization="zoh")
    assert isinstance(p.info, AdmmInfo)
    assert p.info.status == p.status and p.info.iterations == p.iterations
    assert p.info.objective == p.objective
    assert isinstance(p.info.raw, dict) and np.asarray(p.info.raw["Y"]).shape == (3, pb.horizon)
    with pytest.warns(DeprecationWarning, match=r"Plan.info\['Y'\].*use Plan.info.raw\['Y'\]"):
        Y = p.info["Y"]
    assert Y is p.info.raw["Y"]  # the old value, unchanged (nu x N)
    with pytest.warns(DeprecationWarning, match=r"use Plan.info.iterations"):
        assert p.info["iterations"] == p.iterations
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert isinstance(p.info.raw["status"], int)  # no warning on the new path


def test_nonlinear_plan_info_is_the_solver_info():
    pb = rv.problem(rv.load(), "unconstrained", "nonlinear")
    p = plan(pb, "nonlinear", "ilqr_admm", rho=0.1, eps=6e-5, stop="paper")
    assert isinstance(p.info, _c.IlqrAdmmInfo)
    assert p.info.iterations == p.iterations == 60


def test_od_result_info_mirrors_status_and_iterations():
    st = [paper.station(), od.station_inertial([5200.0, 3000.0, 1900.0])]
    obs = od.simulate(paper.truth(), st, np.arange(0, 301, 10.0), seed=3)
    r = od.solve(obs, st, paper.truth() + np.array([30, -20, 10, 0.01, -0.01, 0.02]))
    assert isinstance(r.info, _c.OdInfo)
    assert r.info.status == r.status == od.OdStatus.converged
    assert r.info.iterations == r.iterations > 0
    assert r.info.message == r.message
    n = len(np.asarray(r.normalized))
    assert r.info.primal_residual == pytest.approx(np.sqrt(2.0 * r.cost / n), rel=1e-12)
    assert r.info.dual_residual >= 0.0 and r.info.solve_time > 0.0
    with pytest.raises(AttributeError):
        r.info.iterations = 0
