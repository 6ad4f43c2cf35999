"""Passive safety (satgnc.guidance.safety, issue 16 item 2): each node's free drift on the J2 + drag
truth against a keep-out zone, checked against the analytic CW drift, and the figure."""

from __future__ import annotations

import numpy as np
import pytest
from satgnc import _satgnc as _c
from satgnc.guidance import RendezvousProblem, cw_stm, satellite_params
from satgnc.guidance.flight import fly
from satgnc.guidance.safety import KeepOut, cw_positions, passive_safety, safety_figure, sample_flight

MU, R = 3.986004418e14, 7231.0e3  # the l1 scenario's orbit (its drag density is referenced to 6731 km)
N_MEAN = np.sqrt(MU / R**3)


def eci(cw):
    r_t = np.array([R, 0.0, 0.0])
    v_t = np.array([0.0, np.sqrt(MU / R), 0.0])
    return np.asarray(_c.two_satellite_state(r_t, v_t, np.asarray(cw, dtype=float)))


def truth():
    return satellite_params(MU, j2=True, drag=True, mass=100.0)


def test_drift_matches_cw_and_classifies_nodes(tmp_path):
    # node 0: V-bar hold 200 m away (CW equilibrium) -> stays away; node 1: closing at 0.3 m/s along x
    # from 80 m -> passes through the 50 m sphere; node 2: 30 m radial offset, at rest (drifts
    # along-track, 6 n y per unit time on average).
    nodes = [[200.0, 0, 0, 0, 0, 0], [80.0, 0, 0, -0.3, 0, 0], [120.0, 30.0, 0, 0, 0, 0]]
    X = np.array([eci(c) for c in nodes])
    ko = KeepOut.sphere(50.0)
    T = 1200.0
    ps = passive_safety(truth(), X, ko, T, samples=120)
    assert ps.trajectories.shape == (3, 121, 3)
    # independent check: the analytic CW flow from the same relative state, at every sample. Over
    # 1200 s and <= 300 m the CW linearization and J2 / differential drag differ by well under 1 m.
    ref_rho = []
    for j, c in enumerate(nodes):
        ref = np.array([cw_stm(N_MEAN, t) @ np.asarray(c) for t in ps.times])[:, :3]
        assert np.max(np.linalg.norm(ps.trajectories[j] - ref, axis=1)) < 1.0
        ref_rho.append(float(np.min(np.linalg.norm(ref, axis=1)) / 50.0))
    # the truth's smallest radius matches the CW one to 1 m / 50 m = 0.02, and so does the verdict
    np.testing.assert_allclose(ps.min_rho, ref_rho, atol=0.02)
    assert ps.safe.tolist() == [True, False, ref_rho[2] >= 1.0]
    assert ps.min_rho[0] == pytest.approx(4.0, abs=0.02)  # 200 m / 50 m, held (CW equilibrium)
    assert ps.min_rho[1] < 0.5  # within 25 m of the target (Coriolis bends the straight line: CW says 20.7 m)
    assert not ps.all_safe and ps.unsafe_nodes[0] == 1
    safety_figure(ps, tmp_path / "drift.png", flight_positions=cw_positions(X))
    assert (tmp_path / "drift.png").stat().st_size > 10_000


def test_sample_flight_matches_the_coarse_flight_at_the_nodes():
    pb = RendezvousProblem(mu=MU, radius=R, mass=100.0, x0=np.array([200.0, 0, 0, 0, 0, 0]), tf=600.0,
                           horizon=6, alpha=1.0, Qf=0.0)
    U = np.zeros((6, 3))
    U[0, 0] = -0.02
    U[4, 0] = 0.02
    coarse = fly(truth(), pb.state_eci(), U, pb.dt).X
    fine = sample_flight(truth(), pb.state_eci(), U, pb.dt, per_interval=5)
    assert fine.shape == (31, 12)
    # the same flight sampled 5x finer: the nodes agree to the integrator's tolerance (mm)
    np.testing.assert_allclose(cw_positions(fine[::5]), cw_positions(coarse), atol=1e-3)


def test_bad_input():
    with pytest.raises(ValueError) as e:
        KeepOut([0, 0, 0], [10.0, -1.0, 5.0])
    assert str(e.value) == "semi_axes: must be > 0 m on every axis, got [10.0, -1.0, 5.0]"
    with pytest.raises(ValueError) as e:
        KeepOut.sphere(0.0)
    assert str(e.value).startswith("radius: must be")
    X = np.array([eci([200.0, 0, 0, 0, 0, 0])])
    with pytest.raises(ValueError) as e:
        passive_safety(truth(), X, KeepOut.sphere(10.0), -5.0)
    assert str(e.value).startswith("drift_time: must be")
    with pytest.raises(TypeError) as e:
        passive_safety(truth(), X, 10.0, 100.0)
    assert str(e.value) == "keep_out: must be a KeepOut, got float"
    ko = KeepOut([0, 0, 0], [100.0, 50.0, 25.0])
    assert ko.rho([[100.0, 0, 0], [0, 25.0, 0]]).tolist() == [1.0, 0.5]  # exact quotients
