"""Python bindings of the analytic Kepler propagator (C++ tests hold the numerical checks)."""

import numpy as np
import pytest
from satgnc import _satgnc

MU = 398600.4418
# Vallado, Fundamentals of Astrodynamics and Applications, 4th ed., Example 2-4.
X0 = np.array([1131.340, -2282.343, 6672.423, -5.64305, 4.30333, 2.42879])


def test_kepler_step_vallado_example_2_4():
    x, stm = _satgnc.kepler_step(X0, 2400.0, MU)
    assert x.shape == (6,) and stm.shape == (6, 6)
    # printed to 1e-4 km and 1e-6 km/s: tolerance 2e-4 km, 2e-6 km/s
    np.testing.assert_allclose(x[:3], [-4219.7527, 4363.0292, -3958.7666], atol=2e-4, rtol=0)
    np.testing.assert_allclose(x[3:], [3.689866, -1.916735, -6.112511], atol=2e-6, rtol=0)
    assert abs(np.linalg.det(stm) - 1.0) < 1e-10


def test_kepler_step_stm_matches_finite_differences():
    _, stm = _satgnc.kepler_step(X0, 2400.0, MU)
    fd = np.empty((6, 6))
    for k in range(6):
        h = 1e-6 * (np.linalg.norm(X0[:3]) if k < 3 else np.linalg.norm(X0[3:]))
        e = np.zeros(6)
        e[k] = h
        xp = _satgnc.kepler_step(X0 + e, 2400.0, MU)[0]
        xm = _satgnc.kepler_step(X0 - e, 2400.0, MU)[0]
        fd[:, k] = (xp - xm) / (2 * h)
    for i in (0, 3):
        for j in (0, 3):
            blk, ref = stm[i : i + 3, j : j + 3], fd[i : i + 3, j : j + 3]
            assert np.abs(blk - ref).max() / np.abs(ref).max() < 1e-7


@pytest.mark.parametrize(
    ("x0", "dt", "mu", "name"),
    [
        (np.zeros(6), 10.0, MU, "x0"),
        (np.r_[X0[:5], np.nan], 10.0, MU, "x0"),
        (X0, np.inf, MU, "dt"),
        (X0, 10.0, 0.0, "mu"),
        (X0, 10.0, -1.0, "mu"),
    ],
)
def test_kepler_step_bad_input_names_argument(x0, dt, mu, name):
    with pytest.raises(ValueError, match=f"^{name}:"):
        _satgnc.kepler_step(x0, dt, mu)


def test_kepler_step_wrong_shape_names_the_argument():
    with pytest.raises(ValueError, match=r"^x0: must have shape \(6,\), got \(5,\)"):
        _satgnc.kepler_step(np.zeros(5), 10.0, MU)


def _kepler_states(times, t0=0.0):
    return np.array([_satgnc.kepler_step(X0, t - t0, MU)[0] for t in times])


def test_propagate_kepler_returns_trajectory():
    times = [-600.0, 0.0, 1200.0, 2400.0]
    tr = _satgnc.propagate_kepler(X0, 0.0, times, MU, True)
    assert tr.success and tr.status == "success"
    assert tr.states.shape == (4, 6) and tr.stms.shape == (4, 6, 6)
    np.testing.assert_array_equal(tr.times, times)
    np.testing.assert_allclose(tr.states, _kepler_states(times), rtol=0, atol=1e-12)
    np.testing.assert_array_equal(tr.stms[1], np.eye(6))


def test_propagate_dop853_agrees_with_kepler():
    times = [-1800.0, 600.0, 2400.0]
    tr = _satgnc.propagate_dop853(X0, 0.0, times, _satgnc.ForceModel(), 1e-12, 1e-12, True, 100000)
    assert tr.success, tr.message
    assert tr.stats["steps"] > 0 and tr.stats["rhs_evals"] > 12 * tr.stats["steps"]
    assert np.abs(tr.states[:, :3] - _kepler_states(times)[:, :3]).max() < 1e-6  # km
    _, stm = _satgnc.kepler_step(X0, 2400.0, MU)
    assert np.abs(tr.stms[2] - stm).max() / np.abs(stm).max() < 1e-9


def test_satgnc_propagate_methods_kepler_and_dop853():
    import satgnc

    times = np.array([0.0, 1200.0, 2400.0])
    for method in ("kepler", "dop853"):
        tr = satgnc.propagate(X0, times, method=method, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(tr.states[-1, :3], [-4219.7527, 4363.0292, -3958.7666], atol=2e-4, rtol=0)


def test_propagate_dop853_bad_settings_name_the_argument():
    fm = _satgnc.ForceModel()
    with pytest.raises(ValueError, match="^rtol:"):
        _satgnc.propagate_dop853(X0, 0.0, [60.0], fm, 0.0, 1e-12, True, 1000)
    with pytest.raises(ValueError, match="^rtol:"):
        _satgnc.propagate_dop853(X0, 0.0, [60.0], fm, -1e-9, 1e-12, True, 1000)
    with pytest.raises(ValueError, match="^atol:"):
        _satgnc.propagate_dop853(X0, 0.0, [60.0], fm, 1e-9, -1.0, True, 1000)
    with pytest.raises(ValueError, match="^max_steps:"):
        _satgnc.propagate_dop853(X0, 0.0, [60.0], fm, 1e-9, 1e-12, True, 0)
    with pytest.raises(ValueError, match="^times:"):
        _satgnc.propagate_dop853(X0, 0.0, [60.0, np.nan], fm, 1e-9, 1e-12, True, 1000)
    with pytest.raises(ValueError, match="^x0:"):
        _satgnc.propagate_dop853(np.zeros(6), 0.0, [60.0], fm, 1e-9, 1e-12, True, 1000)
    with pytest.raises(ValueError, match="^mu:"):
        _satgnc.propagate_kepler(X0, 0.0, [60.0], -1.0, True)


def test_propagate_dop853_max_steps_reports_time_reached():
    tr = _satgnc.propagate_dop853(X0, 0.0, [10.0, 86400.0], _satgnc.ForceModel(), 1e-12, 1e-12, False, 5)
    assert not tr.success and tr.status == "too_much_work"
    assert len(tr) == 1 and 10.0 < tr.t_reached < 86400.0
    assert "reached t =" in tr.message and "max_steps" in tr.message
