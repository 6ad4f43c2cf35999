"""Seeded random-pass orbit determination suite (issue 11): Gauss-Newton and Levenberg-Marquardt on
one-station passes nobody tuned the solvers to, checked against an independent solver.

Each pass: a near-circular orbit (perigee altitude 400-1500 km, e < 0.005, inclination 20-98 deg,
random orientation), one station (rotating with the Earth) under the middle of the pass with a
cross-track offset of up to 2 deg, 600 s of range and range-rate every 10 s (122 rows), Gaussian
noise 5 m / 1 mm/s. Generated here from a seed; nothing is read from disk.

Asserted for every pass, method and start (the truth, and 1 km / 1 m/s off): status ``converged``
and a cost no larger than the cost at the truth (+1e-9 relative: the truth is a feasible point, so a
minimum must fit at least as well). The converged estimate is compared with
scipy.optimize.least_squares on residuals from an independent numpy two-body model (universal
Kepler variables, station rotation written here) with its complex-step Jacobian. The truth comes
from ``satgnc.propagation.elements_to_state`` (elements drawn as before; the degree round trip moves
x0 by <= 4e-12 km).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from satgnc import od
from satgnc.propagation import elements_to_state

MU = od.EARTH_MU
RE = od.EARTH_RADIUS
N_PASSES = 24
SPAN_S = 600.0
STEP_S = 10.0
SIGMA_RANGE = 5e-3  # km
SIGMA_RANGE_RATE = 1e-6  # km/s
OFFSET = np.array([1.0, -1.0, 1.0, 1e-3, -1e-3, 1e-3]) / math.sqrt(3.0)  # |dr| = 1 km, |dv| = 1 m/s


def _rotz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def make_pass(seed: int) -> dict:
    """One seeded pass: truth x0 (km, km/s), station, observations, station r0 (km)."""
    rng = np.random.default_rng(seed)
    alt = rng.uniform(400.0, 1500.0)
    inc = rng.uniform(20.0, 98.0)  # deg
    e = rng.uniform(0.0, 0.005)
    # raan, argp, true anomaly: the same draws as before (radians in [0, 2 pi)), given in degrees
    raan, argp, nu = np.degrees(rng.uniform(0.0, 2 * math.pi, 3))
    x0 = elements_to_state((RE + alt) / (1 - e), e, inc, raan, argp, nu, mu=MU)
    tm = SPAN_S / 2
    xm = _kepler(x0, np.array([tm]))[0]
    up = xm[:3] / np.linalg.norm(xm[:3])
    h = np.cross(x0[:3], x0[3:])
    h /= np.linalg.norm(h)
    off = math.radians(rng.uniform(-2.0, 2.0))
    r0 = _rotz(-od.EARTH_OMEGA * tm) @ (RE * (math.cos(off) * up + math.sin(off) * h))
    st = od.station_inertial(r0)
    t = np.arange(0.0, SPAN_S + 1e-9, STEP_S)
    obs = od.simulate(x0, st, t, sigma_range=SIGMA_RANGE, sigma_range_rate=SIGMA_RANGE_RATE, seed=seed + 1000)
    return {"seed": seed, "x0": x0, "station": st, "r0": r0, "obs": obs, "alt": alt, "inc": inc}


# ----------------------------------------------------------------------------- independent model
# Written with analytic operations only (no abs, norm or real-valued branches on the state), so that
# it also runs on complex inputs: _independent_jacobian differentiates it by the complex step.
def _stumpff(z):
    c = np.empty_like(z)
    s = np.empty_like(z)
    zr = np.real(z)
    pos, neg, zer = zr > 1e-8, zr < -1e-8, np.abs(zr) <= 1e-8
    sp = np.sqrt(z[pos])
    c[pos] = (1 - np.cos(sp)) / z[pos]
    s[pos] = (sp - np.sin(sp)) / sp**3
    sn = np.sqrt(-z[neg])
    c[neg] = (np.cosh(sn) - 1) / -z[neg]
    s[neg] = (np.sinh(sn) - sn) / sn**3
    c[zer] = 0.5 - z[zer] / 24
    s[zer] = 1 / 6 - z[zer] / 120
    return c, s


def _norm_rows(a):
    return np.sqrt(np.sum(a * a, axis=-1))


def _kepler(x0, t):
    """Two-body states at times t (s) by universal variables (Curtis, Algorithm 3.4), numpy only."""
    r0v, v0v = x0[:3], x0[3:]
    r0 = np.sqrt(r0v @ r0v)
    vr0 = r0v @ v0v / r0
    alpha = 2 / r0 - v0v @ v0v / MU
    sq = math.sqrt(MU)
    chi = sq * alpha * np.sign(np.real(alpha)) * t  # |alpha| t sqrt(mu), analytic in the state
    for _ in range(50):
        z = alpha * chi**2
        c, s = _stumpff(z)
        f = r0 * vr0 / sq * chi**2 * c + (1 - alpha * r0) * chi**3 * s + r0 * chi - sq * t
        fp = r0 * vr0 / sq * chi * (1 - z * s) + (1 - alpha * r0) * chi**2 * c + r0
        d = f / fp
        chi = chi - d
        if np.all(np.abs(d) < 1e-13 * (1 + np.abs(chi))):
            break
    z = alpha * chi**2
    c, s = _stumpff(z)
    fl = 1 - chi**2 / r0 * c
    gl = t - chi**3 / sq * s
    r = fl[:, None] * r0v + gl[:, None] * v0v
    rn = _norm_rows(r)
    fd = sq / (rn * r0) * (alpha * chi**3 * s - chi)
    gd = 1 - chi**2 / rn * c
    v = fd[:, None] * r0v + gd[:, None] * v0v
    return np.hstack([r, v])


def _independent_residuals(p):
    obs = p["obs"]
    t = np.asarray(obs.t)
    w = od.EARTH_OMEGA
    R = np.array([_rotz(w * tk) @ p["r0"] for tk in t])
    V = w * np.column_stack([-R[:, 1], R[:, 0], np.zeros(len(t))])
    is_range = np.array([k == "range" for k in obs.type_names()])
    val, sig = np.asarray(obs.value), np.asarray(obs.sigma)

    def fun(x):
        y = _kepler(x, t)
        d, dv = y[:, :3] - R, y[:, 3:] - V
        rho = _norm_rows(d)
        pred = np.where(is_range, rho, np.sum(d * dv, axis=1) / rho)
        return (pred - val) / sig

    return fun


def _independent_jacobian(fun):
    """d fun / dx by the complex step, Im fun(x + i h e_j) / h (Squire & Trapp 1998): exact to
    round-off for any h, no subtraction. A 3-point difference of the same model, with scipy's steps
    (eps^(1/3) |x|: 0.04 km, 5e-5 km/s), is off by up to 1e-3 relative along a pass's weak, strongly
    curved direction, which moved scipy's minimum by 3e-3 formal sigma on pass 15 (measured)."""

    def jac(x):
        h = 1e-20 * max(1.0, float(np.max(np.abs(x))))
        return np.column_stack([np.imag(fun(x + 1j * h * e)) / h for e in np.eye(len(x))])

    return jac


# ----------------------------------------------------------------------------- the suite
@pytest.fixture(scope="module")
def passes():
    return [make_pass(s) for s in range(N_PASSES)]


def _cost_at(sv, x):
    st, r, _ = sv.evaluate(x)
    assert st == od.OdStatus.converged
    return 0.5 * float(np.sum((np.asarray(r) / np.asarray(sv.row_sigmas)) ** 2))


def _check_result(r, budget):
    assert 0 <= r.iterations <= budget
    assert np.isfinite(r.cost) and r.cost > 0
    hc = np.asarray(r.history_cost)
    assert hc.shape == (r.iterations + 1,)
    assert np.all(np.isfinite(hc)) and np.all(np.isfinite(r.history_x0))
    assert r.cost == pytest.approx(float(hc.min()), rel=1e-12)  # the best iterate is returned


@pytest.mark.parametrize("method", ["gauss_newton", "levenberg_marquardt"])
def test_random_passes_converge_to_a_minimum_that_fits_like_the_truth(passes, method):
    bad = []
    iters = []
    for p in passes:
        sv = od.solver(p["obs"], p["station"], method)
        c_truth = _cost_at(sv, p["x0"])
        for start, g in (("truth", p["x0"]), ("1 km / 1 m/s", p["x0"] + OFFSET)):
            r = sv.solve(g)
            _check_result(r, sv.settings.max_iterations)
            iters.append(r.iterations)
            if r.status != od.OdStatus.converged or r.cost > c_truth * (1 + 1e-9) or r.rank != 6:
                bad.append((p["seed"], start, r.status.name, r.iterations, r.cost, c_truth))
            else:
                P = np.asarray(r.covariance)
                assert np.all(np.isfinite(P)) and np.all(np.linalg.eigvalsh(P) > 0)
                assert r.fits
    assert not bad, f"{len(bad)} of {2 * len(passes)} solves failed: {bad}"
    assert len(iters) == 2 * N_PASSES


SAME_MINIMUM = 1e-4  # formal sigma: scipy's own stopping points from two starts differ by up to 6e-5


def _formal_sigma(sv, x, d):
    """|J_n(x) d|: the length of d in formal sigmas at x, from the row-normalized Jacobian (the
    covariance's condition number reaches 5e17 on these passes: solving with it is round-off)."""
    _, _, J = sv.evaluate(x)
    return float(np.linalg.norm((np.asarray(J) / np.asarray(sv.row_sigmas)[:, None]) @ d))


def test_converged_estimates_match_independent_scipy_least_squares(passes):
    from scipy.optimize import least_squares

    worst_sigma, worst_cost, worst_default, two_minima = 0.0, 0.0, 0.0, []
    for p in passes:
        fun = _independent_residuals(p)
        # scipy's dogbox on the independent model with its complex-step Jacobian, from the same start.
        opts = dict(jac=_independent_jacobian(fun), method="dogbox", x_scale="jac", xtol=1e-15, ftol=1e-15,
                    gtol=1e-15, max_nfev=3000)
        ref = least_squares(fun, p["x0"] + OFFSET, **opts)
        assert ref.status > 0
        # Default settings: converged, and the cost within the documented cost test (1e-6 relative).
        r = od.solver(p["obs"], p["station"], "levenberg_marquardt").solve(p["x0"] + OFFSET)
        assert r.status == od.OdStatus.converged
        worst_default = max(worst_default, (r.cost - ref.cost) / ref.cost)
        # The independent model reproduces satgnc's residuals at the same point (to 1e-6 sigma).
        np.testing.assert_allclose(fun(np.asarray(r.x0)), np.asarray(r.normalized), atol=1e-6, rtol=0)
        # To the round-off floor (cost_tol 1e-12 cannot hold in floating point: converged or stalled
        # there), both solvers reach the same minimum: within SAME_MINIMUM formal sigma, costs to 1e-9.
        sv = od.solver(p["obs"], p["station"], "levenberg_marquardt", cost_tol=1e-12)
        r = sv.solve(p["x0"] + OFFSET)
        assert r.status in (od.OdStatus.converged, od.OdStatus.stalled)
        x = np.asarray(r.x0)
        sigma = _formal_sigma(sv, x, x - ref.x)
        if sigma > SAME_MINIMUM:
            # A pass with two local minima (pass 15: 2.4e-3 formal sigma apart, costs equal to 3e-10
            # relative, a 1.4e-7 cost barrier between them; a full Newton step with the
            # finite-difference Hessian stays at each). satgnc's estimate must then be the other
            # one: scipy started there stays there.
            back = least_squares(fun, x, **opts)
            assert back.status > 0
            # Either distinct minima, or scipy's own first stop was the loose one: on an AMD EPYC
            # (2026-12-03, another BLAS kernel) scipy from the offset start stopped in pass 15's flat
            # valley 1.39e-4 sigma from satgnc's estimate at a cost 1.9e-10 relative higher; restarted
            # at satgnc's estimate it stays there (0 sigma) and its first stop is 1.6e-4 sigma off.
            loose_ref = _formal_sigma(sv, ref.x, ref.x - back.x) > SAME_MINIMUM and r.cost <= ref.cost
            assert sigma > 10 * SAME_MINIMUM or loose_ref, (p["seed"], sigma)
            sigma = _formal_sigma(sv, x, x - back.x)
            two_minima.append(p["seed"])
        worst_sigma = max(worst_sigma, sigma)
        worst_cost = max(worst_cost, abs(r.cost - ref.cost) / ref.cost)
    assert worst_default < 1e-6  # measured 5.5e-8
    # Measured 5.7e-5 (pass 11; 17 of 24 passes under 1e-6). With scipy's 3-point differences instead
    # of the complex step this was 2.9e-3 (pass 15, scipy in the other minimum and off it by its
    # Jacobian's error) and moved to 3.03e-3 when make_pass changed x0 by 4e-12 km.
    assert worst_sigma < SAME_MINIMUM
    assert len(two_minima) <= 1, two_minima  # measured [15]
    assert worst_cost < 1e-9  # measured 4.8e-10


# ----------------------------------------------------------------------------- honest failures
def _rank_deficient_cases():
    """Rank 2 (one station listed three times, range and range-rate at t = 0: rows [u, 0] and
    [w, u] only) and rank 3 (six ranges at one instant from six stations: velocity unobservable)."""
    from satgnc.papers import od_newton_raphson as paper

    x, st = paper.truth(), paper.station()
    vals, kinds, idx = [], [], []
    for i in range(3):
        for k in ("range", "range_rate"):
            vals.append(od.predict(k, x, st.state(0.0))[0])
            kinds.append(k)
            idx.append(i)
    sig = [1e-3 if k == "range" else 1e-6 for k in kinds]
    rank2 = (od.Observations([0.0] * 6, kinds, vals, sig, idx), [st, st, st], 2)
    sts = [od.station_inertial(np.asarray(st.r0) + [100.0 * i, -50.0 * i * i, 30.0 * i]) for i in range(6)]
    vals = [od.predict("range", x, s.state(0.0))[0] for s in sts]
    rank3 = (od.Observations([0.0] * 6, "range", vals, 1e-3, list(range(6))), sts, 3)
    return [rank2, rank3]


@pytest.mark.parametrize("method", ["newton", "gauss_newton", "levenberg_marquardt"])
@pytest.mark.parametrize("case", [0, 1])
def test_rank_deficient_data_is_singular_never_converged(method, case):
    from satgnc.papers import od_newton_raphson as paper

    obs, sts, rank = _rank_deficient_cases()[case]
    r = od.solve(obs, sts, paper.truth() + np.r_[1.0, 1.0, 1.0, 1e-3, 1e-3, 1e-3], method=method)
    assert r.status == od.OdStatus.singular
    assert r.rank == rank
    assert r.condition_number > 1e13  # rank 2: ~1e32, beyond rank_tol = 1e-13
    assert np.all(np.isinf(np.diag(r.covariance)))
    assert np.isfinite(r.cost)


def test_gao_luo_pass_gauss_newton_from_the_truth_never_reports_garbage():
    # Issue 11: on the 300 s Gao-Luo pass with 1 m / 1 mm/s noise, undamped GN from the truth went
    # from cost 2.98e1 to 2.2e10 in one step, then reported cost 0, a NaN covariance and a NaN row.
    from satgnc.papers import od_newton_raphson as paper

    for seed in range(1, 6):
        obs = od.simulate(paper.truth(), paper.station(), np.arange(0, 301, 10.0), seed=seed)
        r = od.solve(obs, paper.station(), paper.truth(), method="gauss_newton")
        assert r.status in (od.OdStatus.converged, od.OdStatus.max_iterations)
        hc = np.asarray(r.history_cost)
        assert np.all(np.diff(hc) <= 0)  # the line search never raises the cost
        assert 0 < r.cost <= hc[0]
        assert np.all(np.isfinite(r.history_x0)) and np.all(np.isfinite(r.covariance))
        _check_result(r, 100)


def _predicted_decrease(sv, x):
    """0.5 |Q1^T r_n|^2 at x (the Gauss-Newton decrement) and the cost, by numpy's QR of satgnc's
    row-normalized Jacobian: the convergence test recomputed outside the solver."""
    st, r, J = sv.evaluate(x)
    assert st == od.OdStatus.converged
    sig = np.asarray(sv.row_sigmas)
    rn = np.asarray(r) / sig
    q, _ = np.linalg.qr(np.asarray(J) / sig[:, None])
    c = q.T @ rn
    return 0.5 * float(c @ c), 0.5 * float(rn @ rn)


def _hessian_eigenvalues(sv, x):
    """Eigenvalues of the full Hessian of the cost (J^T J + sum r_i H_i) at x, by central
    differences of the gradient J^T r_n along the formal 1-sigma directions (1 = J^T J alone)."""
    sig = np.asarray(sv.row_sigmas)

    def grad(y):
        _, r, J = sv.evaluate(y)
        return (np.asarray(J) / sig[:, None]).T @ (np.asarray(r) / sig)

    _, _, J = sv.evaluate(x)
    _, s, vt = np.linalg.svd(np.asarray(J) / sig[:, None], full_matrices=False)
    B = vt.T / s
    H = np.column_stack([B.T @ (grad(x + 1e-3 * b) - grad(x - 1e-3 * b)) / 2e-3 for b in B.T])
    return np.linalg.eigvalsh(0.5 * (H + H.T))


@pytest.mark.parametrize("method", ["gauss_newton", "levenberg_marquardt"])
def test_gao_luo_pass_from_the_truth_converges_for_every_noise_seed(method):
    # Issue 11, the first OD item: the 300 s Gao-Luo pass, one station, 1 m / 1 mm/s noise, from the
    # truth. The minimum lies 4-16 km away along a curved valley (formal sigmas 35 km / 0.25 km /
    # 0.13 m, condition 3e8). Before the valley corrector and the extrapolation, GN converged for
    # 4 of these 10 seeds and LM for 6 within 100 iterations; now 10 / 10 each (GN 2-8 iterations,
    # LM 12-18, measured).
    from satgnc.papers import od_newton_raphson as paper

    T, st = paper.truth(), paper.station()
    converged, iters = 0, []
    for seed in range(1, 11):
        obs = od.simulate(T, st, np.arange(0, 301, 10.0), seed=seed)
        sv = od.solver(obs, st, method)
        c_truth = _cost_at(sv, T)
        r = sv.solve(T)
        _check_result(r, 100)
        iters.append(r.iterations)
        if r.status != od.OdStatus.converged:
            continue
        converged += 1
        # Every converged solve fits at least as well as the truth, and the stated test holds.
        assert r.cost <= c_truth
        assert r.rank == 6 and r.fits
        dec, cost = _predicted_decrease(sv, np.asarray(r.x0))
        assert dec <= sv.settings.cost_tol * cost * 1.01
        assert np.all(np.linalg.eigvalsh(np.asarray(r.covariance)) > 0)
    assert converged == 10
    assert max(iters) <= 25  # measured GN 8, LM 18


def test_gao_luo_pass_gauss_newton_and_lm_reach_the_same_minimum():
    # Two different globalizations end at the same point. With the default cost_tol = 1e-6 they
    # agree in cost to 3.5e-5 (a chi-square difference of 7e-5) but may lie up to 0.9 km apart
    # along the flat valley (0.025 of its 35 km formal sigma); cost_tol = 1e-10 brings them to
    # <= 18 m (0.018 formal sigma), measured.
    from satgnc.papers import od_newton_raphson as paper

    T, st = paper.truth(), paper.station()
    for seed in range(1, 11):
        obs = od.simulate(T, st, np.arange(0, 301, 10.0), seed=seed)
        a = od.solve(obs, st, T, method="gauss_newton")
        b = od.solve(obs, st, T, method="levenberg_marquardt")
        assert abs(a.cost - b.cost) <= 1e-4
        a = od.solve(obs, st, T, method="gauss_newton", cost_tol=1e-10)
        b = od.solve(obs, st, T, method="levenberg_marquardt", cost_tol=1e-10)
        # Near the round-off floor a trial may no longer lower the cost: converged or stalled there.
        assert a.status in (od.OdStatus.converged, od.OdStatus.stalled)
        assert b.status in (od.OdStatus.converged, od.OdStatus.stalled)
        d = np.asarray(a.x0) - np.asarray(b.x0)
        assert math.sqrt(d @ np.linalg.solve(np.asarray(a.covariance), d)) < 0.05
        assert np.linalg.norm(d[:3]) < 0.05  # km
        assert abs(a.cost - b.cost) <= 1e-7


# Passes 100-199 (not the 24 of the suite above) from 10 km / 10 m/s off. Measured: GN 96 / 100,
# LM 100 / 100 (before the valley corrector: GN 61, LM 98).
FAR_SEEDS = range(100, 200)
FAR_FLOOR = {"gauss_newton": 96, "levenberg_marquardt": 100}


@pytest.fixture(scope="module")
def far_passes():
    return [make_pass(s) for s in FAR_SEEDS]


@pytest.mark.parametrize("method", ["gauss_newton", "levenberg_marquardt"])
def test_ten_km_starts_reach_a_minimum_that_fits_like_the_truth(far_passes, method):
    good, other = 0, []
    for p in far_passes:
        sv = od.solver(p["obs"], p["station"], method)
        c_truth = _cost_at(sv, p["x0"])
        r = sv.solve(p["x0"] + 10 * OFFSET)
        _check_result(r, 100)
        if r.status == od.OdStatus.converged and r.cost <= c_truth * (1 + 1e-9):
            good += 1
            continue
        other.append((p["seed"], r.status.name, r.iterations, round(r.cost, 1), round(c_truth, 1)))
        if r.status == od.OdStatus.converged:
            # Honest: a converged solve that fits worse than the truth is a strict local minimum of
            # the cost (the full Hessian, not only J^T J, is positive definite), not a false stop.
            dec, cost = _predicted_decrease(sv, np.asarray(r.x0))
            assert dec <= sv.settings.cost_tol * cost * 1.01
            assert _hessian_eigenvalues(sv, np.asarray(r.x0)).min() > 0.5
        else:
            assert r.status in (od.OdStatus.max_iterations, od.OdStatus.stalled)
    assert good >= FAR_FLOOR[method], other


@pytest.mark.parametrize("source", ["conditions", "observations"])
def test_exact_six_point_problem_lm_reaches_the_truth_in_the_default_budget(source):
    # Issue 11: LM's default of 30 iterations stopped 39 m off; the default budget is now 100 and
    # the geodesic LM needed 12-41 iterations from these guesses, 11-15 with the valley corrector
    # (measured).
    from satgnc.papers import od_newton_raphson as paper

    rho, rhodot = paper.observe()
    T = paper.truth()
    if source == "conditions":
        sv = od.six_point_solver(paper.times(), rho, rhodot, paper.station(), method="levenberg_marquardt")
    else:
        obs = od.simulate(T, paper.station(), paper.times(), types=("range_rate",), seed=None)
        sv = od.solver(obs, paper.station(), "levenberg_marquardt")
    assert sv.settings.max_iterations == 100
    for g in (T + [10.0, 0, 0, 0, 0, 0], T + [40.0, 0, 0, 0, 0, 0], T + OFFSET, T + 10 * OFFSET):
        r = sv.solve(g)
        assert r.status == od.OdStatus.converged
        assert np.linalg.norm(np.asarray(r.x0)[:3] - T[:3]) < 1e-3  # < 1 m


def test_hopeless_starts_report_the_best_iterate_with_finite_cost_and_history():
    from satgnc.papers import od_newton_raphson as paper

    p = make_pass(3)
    far = p["x0"] + np.r_[800.0, -600.0, 500.0, 0.5, -0.4, 0.3]
    for method in ("gauss_newton", "levenberg_marquardt"):
        r = od.solver(p["obs"], p["station"], method, max_iterations=3).solve(far)
        assert r.status in (od.OdStatus.max_iterations, od.OdStatus.stalled)
        _check_result(r, 3)
        assert np.all(np.isfinite(r.covariance))
    # The paper's undamped Newton from 200 km off on the printed Table 4 leaves the physical region:
    # diverged, with the lowest-cost iterate (finite) returned and no NaN history row.
    rho, rhodot = paper.observe()
    g = paper.truth() + np.r_[200.0, -200.0, 200.0, 0.2, -0.2, 0.2]
    r = od.solve_six_point(paper.times(), rho, rhodot, paper.station(), g, max_iterations=50)
    assert r.status != od.OdStatus.converged
    assert np.isfinite(r.cost) and np.all(np.isfinite(r.history_cost))
    assert r.cost == pytest.approx(float(np.min(r.history_cost)), rel=1e-12)
    # A guess inside the Earth cannot be evaluated at all: diverged, cost +inf (never 0).
    inside = p["x0"].copy()
    inside[:3] *= 0.5
    for method in ("gauss_newton", "levenberg_marquardt"):
        r = od.solver(p["obs"], p["station"], method).solve(inside)
        assert r.status == od.OdStatus.diverged
        assert r.iterations == 0 and math.isinf(r.cost) and not r.fits
        np.testing.assert_array_equal(r.history_x0, inside[None, :])
