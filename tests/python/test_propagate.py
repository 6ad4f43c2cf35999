"""satgnc.propagate: accuracy, STM checks, conservation, N_Vector identity and bad input."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import satgnc
from satgnc import _satgnc
from satgnc.papers.reference import kepler_ellipse  # the pure-Python oracle (was a local copy)

MU = satgnc.EARTH_MU


X0 = satgnc.elements_to_state(7000.0, 0.01, 51.6, 30.0, 40.0, 10.0)
PERIOD = 2 * math.pi * math.sqrt(7000.0**3 / MU)


def energy(model, x):
    return model.energy(x[:3], x[3:])


# ------------------------------------------------------------------ API shape


def test_trajectory_shapes_and_t0_default():
    tr = satgnc.propagate(X0, [100.0, 1000.0, 7300.0], forces=satgnc.J2Gravity())
    assert isinstance(tr, satgnc.Trajectory)
    assert tr.times.shape == (3,)
    assert tr.states.shape == (3, 6)
    assert tr.stms.shape == (3, 6, 6)
    assert tr.status == "success" and tr.success
    # t0 defaults to times[0]: the first output is x0 itself with the identity STM.
    np.testing.assert_array_equal(tr.states[0], X0)
    np.testing.assert_array_equal(tr.stms[0], np.eye(6))
    assert set(tr.stats) >= {"steps", "rhs_evals", "error_test_fails", "nonlin_iters"}
    assert tr.stats["steps"] > 50 and tr.stats["rhs_evals"] >= tr.stats["steps"]
    assert tr.t_reached == 7300.0
    # Explicit t0 shifts the epoch: same arc as above.
    tr2 = satgnc.propagate(X0, [900.0, 7200.0], t0=0.0, forces=satgnc.J2Gravity())
    np.testing.assert_allclose(tr2.states[1], tr.states[2], rtol=0, atol=1e-6)


def test_without_stm_returns_none():
    tr = satgnc.propagate(X0, [0.0, 600.0], with_stm=False)
    assert tr.stms is None
    assert tr.states.shape == (2, 6)


def test_available_methods_lists_cvodes_and_kepler():
    m = satgnc.available_methods()
    assert m[:2] == ["adams", "bdf"]
    assert "kepler" in m


def test_kepler_method_matches_cvodes_one_day():
    times = np.arange(0, 25) * 3600.0
    an = satgnc.propagate(X0, times, method="kepler")
    nu = satgnc.propagate(X0, times, rtol=1e-14, atol=1e-12)
    assert an.stms.shape == (25, 6, 6)
    assert np.max(np.linalg.norm(an.states[:, :3] - nu.states[:, :3], axis=1)) < 1e-6
    assert np.max(np.linalg.norm(an.states[:, 3:] - nu.states[:, 3:], axis=1)) < 1e-9
    ref = np.array([kepler_ellipse(X0, t) for t in times])
    assert np.max(np.abs(an.states - ref)) < 1e-7


def test_dop853_method_matches_cvodes_with_j2():
    assert "dop853" in satgnc.available_methods()
    times = [0.0, 3600.0, 7200.0]
    a = satgnc.propagate(X0, times, method="dop853", forces=satgnc.J2Gravity(), rtol=1e-13, atol=1e-15)
    b = satgnc.propagate(X0, times, method="adams", forces=satgnc.J2Gravity(), rtol=1e-13, atol=1e-15)
    assert a.states.shape == (3, 6) and a.stms.shape == (3, 6, 6)
    assert np.max(np.linalg.norm(a.states[:, :3] - b.states[:, :3], axis=1)) < 1e-6
    assert nondim_stm_error(a.stms[2], b.stms[2], X0) < 1e-8
    assert a.stats["steps"] > 0


def test_dop853_failure_raises_propagation_error():
    with pytest.raises(satgnc.PropagationError) as info:
        satgnc.propagate(X0, [0.0, 86400.0], method="dop853", max_steps=5)
    assert info.value.t_reached < 86400.0
    assert info.value.status != "success"


def test_kepler_method_rejects_perturbations():
    with pytest.raises(ValueError, match="forces: method 'kepler' is the analytic two-body solution"):
        satgnc.propagate(X0, [0.0, 10.0], method="kepler", forces=satgnc.J2Gravity())


# ------------------------------------------------------------------ accuracy


def test_one_day_against_analytic_below_millimetre():
    times = np.arange(1, 25) * 3600.0
    tr = satgnc.propagate(X0, times, t0=0.0, rtol=1e-14, atol=1e-12, with_stm=False)
    ref = np.array([kepler_ellipse(X0, t) for t in times])
    assert np.max(np.linalg.norm(tr.states[:, :3] - ref[:, :3], axis=1)) < 1e-6  # 1 mm
    assert np.max(np.linalg.norm(tr.states[:, 3:] - ref[:, 3:], axis=1)) < 1e-9  # 1 um/s


def test_vallado_example_2_4():
    # Vallado, Fundamentals of Astrodynamics and Applications, 4th ed. (2013), Example 2-4 (KEPLER).
    x0 = np.array([1131.340, -2282.343, 6672.423, -5.64305, 4.30333, 2.42879])
    tr = satgnc.propagate(x0, [0.0, 2400.0], rtol=1e-13, atol=1e-13)
    # Printed to 0.1 m and 1 mm/s: half a unit of the last printed digit.
    np.testing.assert_allclose(tr.states[1, :3], [-4219.7527, 4363.0292, -3958.7666], rtol=0, atol=0.5e-4)
    np.testing.assert_allclose(tr.states[1, 3:], [3.689866, -1.916735, -6.112511], rtol=0, atol=0.5e-6)


def test_curtis_example_3_7():
    # Curtis, Orbital Mechanics for Engineering Students, 3rd ed. (2014), Example 3.7 (mu = 398600):
    # printed r = -3297.8 i + 7413.4 j km, v = -8.2977 i - 0.96309 j km/s. Curtis rounds chi, f, g to
    # 5 digits, so the printed v_y carries a 7e-4 km/s rounding error (exact: -0.963717).
    x0 = np.array([7000.0, -12124.0, 0.0, 2.6679, 4.6210, 0.0])
    tr = satgnc.propagate(x0, [0.0, 3600.0], mu=398600.0, rtol=1e-13, atol=1e-13)
    x = tr.states[1]
    assert abs(x[0] - -3297.8) < 0.5 and abs(x[1] - 7413.4) < 0.2
    assert abs(x[3] - -8.2977) < 5e-4 and abs(x[4] - -0.96309) < 1e-3


def test_backward_returns_to_start():
    fwd = satgnc.propagate(X0, [0.0, 7200.0], rtol=1e-13, atol=1e-13, forces=satgnc.J2Gravity())
    bwd = satgnc.propagate(fwd.states[1], [7200.0, 0.0], rtol=1e-13, atol=1e-13, forces=satgnc.J2Gravity())
    assert np.linalg.norm(bwd.states[1, :3] - X0[:3]) < 1e-7
    assert np.linalg.norm(bwd.states[1, 3:] - X0[3:]) < 1e-10
    assert np.max(np.abs(bwd.stms[1] @ fwd.stms[1] - np.eye(6))) < 1e-6


# ------------------------------------------------------------------ STM


def nondim_stm_error(phi, ref, x0):
    """Relative error of D^-1 Phi D, D = diag(|r0| I3, |v0| I3) (entries weighted by physical scale)."""
    d = np.r_[[np.linalg.norm(x0[:3])] * 3, [np.linalg.norm(x0[3:])] * 3]
    a, b = phi * d[None, :] / d[:, None], ref * d[None, :] / d[:, None]
    return np.abs(a - b).max() / np.abs(b).max()


def test_stm_matches_central_differences():
    forces = [satgnc.J2Gravity(), satgnc.ExponentialDrag(rho0=2.789e-13, h0=600.0, scale_height=71.835,
                                                         area=20.0, mass=100.0)]
    x0 = satgnc.elements_to_state(6378.1363 + 450.0, 0.001, 97.0, *np.degrees([0.3, 0.2, 0.1]))
    phi = satgnc.propagate(x0, [0.0, 7200.0], forces=forces, rtol=1e-13, atol=1e-13).stms[1]

    def f(x):  # rtol 1e-14: the integrator error enters the differences as noise ~ err / h
        return satgnc.propagate(x, [0.0, 7200.0], forces=forces, rtol=1e-14, atol=1e-13,
                                with_stm=False).states[1]

    fd = np.empty((6, 6))
    for j in range(6):  # 4th-order central differences
        h = 0.5 if j < 3 else 5e-4
        e = np.zeros(6)
        e[j] = h
        fd[:, j] = (8 * (f(x0 + e) - f(x0 - e)) - (f(x0 + 2 * e) - f(x0 - 2 * e))) / (12 * h)
    assert nondim_stm_error(phi, fd, x0) < 1e-7


def test_stm_composition_det_and_symplectic():
    j2 = satgnc.J2Gravity()
    kw = dict(forces=j2, rtol=1e-13, atol=1e-13)
    a = satgnc.propagate(X0, [0.0, 2000.0, 5000.0], **kw)
    b = satgnc.propagate(a.states[1], [2000.0, 5000.0], **kw)
    np.testing.assert_allclose(b.stms[1] @ a.stms[1], a.stms[2], rtol=0, atol=1e-9 * np.abs(a.stms[2]).max())
    phi = a.stms[2]
    assert abs(np.linalg.det(phi) - 1) < 1e-8
    J = np.block([[np.zeros((3, 3)), np.eye(3)], [-np.eye(3), np.zeros((3, 3))]])
    assert np.max(np.abs(phi.T @ J @ phi - J)) < 1e-9 * np.sum(phi**2)


def test_energy_and_hz_conserved_ten_orbits_j2():
    model = satgnc.ForceModel(j2=satgnc.J2Gravity())
    times = np.linspace(0, 10 * PERIOD, 101)
    tr = satgnc.propagate(X0, times, forces=model, rtol=1e-12, atol=1e-14)
    e = np.array([energy(model, x) for x in tr.states])
    hz = np.cross(tr.states[:, :3], tr.states[:, 3:])[:, 2]
    assert np.max(np.abs(e / e[0] - 1)) < 1e-11
    assert np.max(np.abs(hz / hz[0] - 1)) < 1e-11


def test_satgnc_nvector_identical_to_sundials_serial():
    model = satgnc.ForceModel(j2=satgnc.J2Gravity())
    times = [600.0 * k for k in range(1, 13)]
    a = _satgnc.CvodesPropagator(model, vector="satgnc").propagate(X0, 0.0, times)
    b = _satgnc.CvodesPropagator(model, vector="sundials_serial").propagate(X0, 0.0, times)
    assert a.stats == b.stats
    assert np.array_equal(a.states, b.states) and np.array_equal(a.stms, b.stms)


def test_force_model_jacobians_match_finite_differences():
    m = satgnc.ForceModel(j2=satgnc.J2Gravity(), drag=satgnc.ExponentialDrag(
        rho0=1e-12, h0=500.0, scale_height=60.0, area=10.0, mass=100.0))
    r, v = np.array([-4502.0, 3870.0, 3420.0]), np.array([-2.1, -5.3, 4.4])
    a, gr, gv = m.acceleration_jacobians(r, v)
    fd = np.empty((3, 3))
    for k in range(3):
        e = np.zeros(3)
        e[k] = 1e-2
        fd[:, k] = (m.acceleration(r + e, v) - m.acceleration(r - e, v)) / 2e-2
    assert np.max(np.abs(gr - fd)) / np.max(np.abs(fd)) < 1e-7
    np.testing.assert_allclose(a, m.acceleration(r, v), rtol=1e-15)
    assert gv.shape == (3, 3) and np.all(np.isfinite(gv)) and np.abs(gv).max() > 0


# ------------------------------------------------------------------ bad input


@pytest.mark.parametrize("x0, exc, text", [
    ([7000.0, 0, 0, 0, 7.5, float("nan")], ValueError, "x0: must be finite"),
    ([7000.0, 0, 0, 0, float("inf"), 0], ValueError, "x0: must be finite"),
    ([0.0, 0, 0, 0, 7.5, 0], ValueError, "x0: position must be non-zero"),
    ([7000.0, 0, 0, 0, 7.5], ValueError, "x0: must have shape (6,)"),
    (np.zeros((6, 1)) + 7000.0, ValueError, "x0: must have shape (6,)"),
    (np.array([7000, 0, 0, 0, 7.5, 0], dtype=complex), TypeError, "x0: must be real"),
    (["a", "b", "c", "d", "e", "f"], TypeError, "x0: must be an array of real numbers"),
    ("7000 0 0 0 7.5 0", TypeError, "x0: must be an array of real numbers"),
    ([[7000.0, 0], [1]], ValueError, "x0:"),
])
def test_bad_state(x0, exc, text):
    with pytest.raises(exc, match=None) as info:
        satgnc.propagate(x0, [0.0, 10.0])
    assert text in str(info.value)


@pytest.mark.parametrize("times, text", [
    ([0.0, 20.0, 10.0], "times: must be strictly monotone"),
    ([0.0, 10.0, 10.0], "times: must be strictly monotone"),
    ([0.0, float("nan")], "times: must be finite"),
    ([0.0, float("inf")], "times: must be finite"),
    ([], "times: must not be empty"),
    (np.zeros((2, 2)), "times: must be one-dimensional"),
])
def test_bad_times(times, text):
    with pytest.raises(ValueError) as info:
        satgnc.propagate(X0, times)
    assert text in str(info.value)


def test_times_on_both_sides_of_t0_rejected():
    with pytest.raises(ValueError, match="times: must all lie on one side of t0"):
        # CVODES's one-sided rule (the default, DOP853, integrates both sides of t0)
        satgnc.propagate(X0, [-10.0, 10.0], t0=0.0, method="adams")


def test_bad_times_dtype():
    with pytest.raises(TypeError, match="times: must be real"):
        satgnc.propagate(X0, np.array([0, 10], dtype=complex))
    with pytest.raises(TypeError, match="times"):
        satgnc.propagate(X0, ["0", "10"])


@pytest.mark.parametrize("kw, exc, text", [
    (dict(mu=0.0), ValueError, "mu: must be finite and > 0"),
    (dict(mu=-398600.0), ValueError, "mu: must be finite and > 0"),
    (dict(mu=float("nan")), ValueError, "mu: must be finite and > 0"),
    (dict(mu="earth"), TypeError, "mu: must be a real number"),
    (dict(rtol=0.0), ValueError, "rtol: must be finite and > 0"),
    (dict(rtol=-1e-10), ValueError, "rtol: must be finite and > 0"),
    (dict(atol=0.0), ValueError, "atol: must be finite and > 0"),
    (dict(atol=[1e-12] * 5), ValueError, "atol: must be a scalar or have 6 or 42 entries"),
    (dict(atol=[1e-12, 1e-12, 1e-12, -1, 1e-12, 1e-12]), ValueError, "atol: every entry"),
    (dict(rtol=1j), TypeError, "rtol: must be a real number"),
    (dict(max_steps=0), ValueError, "max_steps: must be > 0"),
    (dict(max_steps=1.5), TypeError, "max_steps: must be an int"),
    (dict(max_steps=True), TypeError, "max_steps: must be an int"),
    (dict(method="rk4"), ValueError, "method: unknown 'rk4'; available in this build"),
    (dict(method=3), TypeError, "method: must be a string"),
    (dict(t0=float("nan")), ValueError, "t0: must be finite"),
    (dict(forces="j2"), TypeError, "forces: must be None, a ForceModel"),
    (dict(forces=[satgnc.J2Gravity(), 3]), TypeError, "forces: unknown term int"),
    (dict(forces=satgnc.J2Gravity(mu=1.0), mu=398600.0), ValueError, "forces: J2Gravity.mu"),
    (dict(with_stm="yes"), TypeError, "with_stm: must be a bool"),
])
def test_bad_arguments(kw, exc, text):
    with pytest.raises(exc) as info:
        satgnc.propagate(X0, [0.0, 10.0], **kw)
    assert text in str(info.value)


def test_bad_force_model_parameters():
    # The term's constructor names its own argument (it used to wait for the propagation: "drag.mass");
    # a field set to a bad value afterwards is still caught at setup, named from the model.
    with pytest.raises(ValueError, match="^mass: must be finite and > 0"):
        satgnc.ExponentialDrag(rho0=1e-12, h0=500, scale_height=60, mass=0.0)
    drag = satgnc.ExponentialDrag(rho0=1e-12, h0=500, scale_height=60)
    drag.mass = 0.0
    with pytest.raises(ValueError, match="drag.mass: must be finite and > 0"):
        satgnc.propagate(X0, [0.0, 10.0], forces=drag)
    with pytest.raises(ValueError, match="mu: must be finite and > 0"):
        satgnc.ForceModel(mu=-1.0)


def test_too_much_work_raises_with_time_reached_and_partial_trajectory():
    with pytest.raises(satgnc.PropagationError) as info:
        satgnc.propagate(X0, [0.0, 10.0, 86400.0], max_steps=30, method="adams")  # CVODES's message
    err = info.value
    assert isinstance(err, RuntimeError)
    assert err.status == "too_much_work"
    assert 10.0 < err.t_reached < 86400.0
    msg = str(err)
    m = re.search(r"stopped at t = ([-+0-9.e]+) s", msg)
    assert m is not None and float(m.group(1)) == err.t_reached
    assert "too much work" in msg and "max_steps = 30" in msg
    assert len(err.trajectory) == 2
    assert np.all(np.isfinite(err.trajectory.states))
    assert err.trajectory.stms.shape == (2, 6, 6)


def _radial_fall_time(r0: float, r: float, mu: float = satgnc.EARTH_MU) -> float:
    """Time (s) of a radial free fall from rest at r0 down to r (analytic)."""
    x = r / r0
    return math.sqrt(r0**3 / (2 * mu)) * (math.sqrt(x * (1 - x)) + math.acos(math.sqrt(x)))


@pytest.mark.parametrize("method", satgnc.available_methods())
def test_collision_course_raises(method):
    x0 = np.array([7000.0, 0, 0, 0, 0, 0])  # radial free fall reaches r = 0 at ~1.5e3 s
    # Without a surface, the numerical methods fail near r = 0 (never NaN), Kepler reports "impact".
    with pytest.raises(satgnc.PropagationError) as info:
        satgnc.propagate(x0, [0.0, 4000.0], method=method, surface_radius=0.0)
    assert info.value.t_reached < 4000.0
    assert np.all(np.isfinite(info.value.trajectory.states))
    if method != "kepler":
        assert "stopped at t = " in str(info.value) or "step size" in str(info.value)
    # With the Earth's surface (the default for mu = EARTH_MU): "impact" at the analytic fall time.
    with pytest.raises(satgnc.PropagationError) as info:
        satgnc.propagate(x0, [0.0, 100.0, 4000.0], method=method)
    err = info.value
    assert err.status == "impact" and "impact at t = " in str(err)
    assert err.t_reached == pytest.approx(_radial_fall_time(7000.0, satgnc.EARTH_RADIUS), rel=1e-7)
    assert len(err.trajectory) == 2  # the outputs before the impact


# An inclined LEO orbit whose perigee lies 200 km below the surface: every method sees the same impact.
_DIVE = [6600.0, 0, 0, -3.0, 5.0, 1.0]


def _dive_impact_time() -> float:
    """Impact time of _DIVE from Kepler's equation: r(E) = a (1 - e cos E) = R, E before perigee."""
    mu, R = satgnc.EARTH_MU, satgnc.EARTH_RADIUS
    r, v = np.array(_DIVE[:3]), np.array(_DIVE[3:])
    rn = np.linalg.norm(r)
    a = 1.0 / (2.0 / rn - v @ v / mu)
    ecosE0, esinE0 = 1.0 - rn / a, (r @ v) / math.sqrt(mu * a)
    e = math.hypot(ecosE0, esinE0)
    E0 = math.atan2(esinE0, ecosE0)
    E1 = -math.acos((1.0 - R / a) / e)  # descending branch (E < 0 before perigee), E0 < E1
    assert E0 < E1 < 0.0
    n = math.sqrt(mu / a**3)
    return ((E1 - e * math.sin(E1)) - (E0 - e * math.sin(E0))) / n


@pytest.mark.parametrize("method", satgnc.available_methods())
@pytest.mark.parametrize("with_stm", [True, False])
def test_impact_time_agrees_across_methods(method, with_stm):
    ref = satgnc.propagate(_DIVE, [0.0, 60.0], method="kepler")  # before the impact
    with pytest.raises(satgnc.PropagationError) as info:
        satgnc.propagate(_DIVE, [0.0, 60.0, 3000.0], method=method, with_stm=with_stm)
    err = info.value
    assert err.status == "impact"
    t_hit = _dive_impact_time()
    assert err.t_reached == pytest.approx(t_hit, abs=1e-6)
    np.testing.assert_allclose(err.trajectory.states, ref.states, rtol=1e-8, atol=1e-8)
    # a larger body (surface_radius 6500 km) is reached earlier
    with pytest.raises(satgnc.PropagationError) as info:
        satgnc.propagate(_DIVE, [0.0, 3000.0], method=method, surface_radius=6500.0, with_stm=with_stm)
    assert info.value.status == "impact" and 0.0 < info.value.t_reached < t_hit


@pytest.mark.parametrize("method", satgnc.available_methods())
def test_backward_impact(method):
    # backward in time from a point on the way down: the arc rises, so no impact; forward it falls.
    traj = satgnc.propagate(_DIVE, [0.0, -600.0], method=method)
    assert traj.success and np.linalg.norm(traj.states[-1, :3]) > satgnc.EARTH_RADIUS
