"""The generic filter engine through the bindings (issue 15, parcel KF15A): independent numpy
re-implementations (batch least squares in information form, a Newton solve of the MAP cost) and
scipy's chi-square quantiles check the C++ results. Tolerances are stated beside each assertion."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.stats
from satgnc import filter as sf


def linear_case(n: int, epochs: int, seed: int):
    """Near-orthogonal Phi, H by type (1..3 rows), 1-2 records per epoch, sigma in [0.5, 2]."""
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    phi = q @ np.diag(0.98 + 0.04 * (np.arange(n) + 0.5) / n)
    hs = [rng.standard_normal((m, n)) for m in (1, 2, 3)]
    p0 = np.diag(np.linspace(1.0, 10.0, n))
    xt = 10.0 * rng.standard_normal(n)
    x0 = xt + np.sqrt(np.diag(p0)) * rng.standard_normal(n)
    t, types, vals, sigs, steps = [], [], [], [], []
    x = xt.copy()
    for k in range(1, epochs + 1):
        x = phi @ x
        for _ in range(1 + k % 2):
            ty = int(rng.integers(0, 3))
            m = ty + 1
            sig = np.full(3, np.nan)
            val = np.full(3, np.nan)
            sig[:m] = rng.uniform(0.5, 2.0, m)
            val[:m] = hs[ty] @ x + sig[:m] * rng.standard_normal(m)
            t.append(float(k))
            types.append(ty)
            vals.append(val)
            sigs.append(sig)
            steps.append(k)
    vals_a = np.nan_to_num(np.array(vals), nan=0.0)
    sigs_a = np.nan_to_num(np.array(sigs), nan=1.0)
    case = dict(phi=phi, h=hs, x0=x0, p0=p0, t=np.array(t), type=np.array(types), value=vals_a, sigma=sigs_a)
    return case, steps


def batch(case: dict, steps: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """Batch least squares at t0 in information form (numpy, independent of the engine)."""
    phi, p0 = case["phi"], case["p0"]
    lam = np.linalg.inv(p0)
    b = lam @ case["x0"]
    for i, k in enumerate(steps):
        m = case["type"][i] + 1
        a = case["h"][case["type"][i]] @ np.linalg.matrix_power(phi, k)
        w = 1.0 / case["sigma"][i, :m] ** 2
        lam = lam + a.T @ (w[:, None] * a)
        b = b + a.T @ (w * case["value"][i, :m])
    cov = np.linalg.inv(lam)
    return cov @ b, cov


def rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


@pytest.mark.parametrize("n", [6, 9])
@pytest.mark.parametrize("form", ["joseph", "ud"])
def test_zero_noise_kf_equals_numpy_batch_and_smoother_at_t0(n: int, form: str) -> None:
    case, steps = linear_case(n, 40, 100 + n)
    run = sf.run_filter(qd=np.zeros((n, n)), gating=False, form=form, smooth=True, **case)
    assert run.status == "success"
    assert run.states.shape == (len(steps), n) and run.covariances.shape == (len(steps), n, n)
    xb, pb = batch(case, steps)
    pk = np.linalg.matrix_power(case["phi"], steps[-1])
    # filter at the last record = Phi^K batch: 1e-10 relative (both exact; ~60 updates of rounding)
    assert rel(run.states[-1], pk @ xb) < 1e-10
    assert rel(run.covariances[-1], pk @ pb @ pk.T) < 1e-10
    # RTS smoother at t0 = batch: 1e-6 relative (the bound)
    assert run.smoother_status == "success"
    assert rel(run.smoothed_initial_state, xb) < 1e-6
    assert rel(run.smoothed_initial_covariance, pb) < 1e-6


def test_ukf_equals_kf_on_linear_system() -> None:
    # alpha = 1: the unscented transform is exact for a linear model; 1e-10 relative
    n = 6
    case, _ = linear_case(n, 30, 7)
    qd = 0.01 * np.eye(n)
    kf = sf.run_filter(qd=qd, gating=False, sequential=False, **case)
    uk = sf.run_filter(qd=qd, gating=False, algorithm="ukf", ukf_alpha=1.0, **case)
    assert rel(uk.states, kf.states) < 1e-10
    assert rel(uk.covariances, kf.covariances) < 1e-10
    assert np.allclose(uk.nis, kf.nis, rtol=1e-10, atol=0)


def test_iterated_ekf_converges_to_the_map_of_a_numpy_newton_solve() -> None:
    # One range to a beacon at the origin from a vague anisotropic prior: x_bar = (3, 1),
    # P = diag(4, 0.25), z = 5 with sigma 0.05 (nonlinear: the prior spans +-2 around a range of
    # 3.2; an isotropic P would move the state along the ray, where the range is linear). The MAP minimizes
    # J(x) = (x - x_bar)' P^-1 (x - x_bar) + (z - |x|)^2 / r; numpy's Newton with the exact Hessian
    # finds it to |grad| < 1e-14. The IEKF's fixed point is grad J = 0, so it agrees to 1e-8
    # (iteration tolerance 1e-12 relative; the last Gauss-Newton step ~ contraction x tolerance).
    xbar = np.array([3.0, 1.0])
    p = np.diag([4.0, 0.25])
    z, sig = 5.0, 0.05
    r = sig**2
    pinv = np.linalg.inv(p)
    x = xbar.copy()
    for _ in range(100):
        rho = np.linalg.norm(x)
        u = x / rho
        grad = 2 * pinv @ (x - xbar) - 2 * (z - rho) / r * u
        hess = 2 * pinv + 2 / r * (np.outer(u, u) - (z - rho) * (np.eye(2) - np.outer(u, u)) / rho)
        step = np.linalg.solve(hess, grad)
        x = x - step
        if np.linalg.norm(step) < 1e-15:
            break
    x_map = x
    common = dict(phi=np.eye(2), qd=np.zeros((2, 2)), x0=xbar, p0=p, t=[0.0], value=[z], sigma=[sig],
                  beacons=np.zeros((2, 1)), gating=False)
    it = sf.run_filter(iterated=True, iteration_tolerance=1e-12, **common)
    ekf = sf.run_filter(**common)
    assert it.status == "success" and it.iterations[0] > 2
    assert np.max(np.abs(it.states[0] - x_map)) < 1e-8
    # the single-step EKF is off the MAP by far more (measured 0.03 here): > 1e-2
    assert np.max(np.abs(ekf.states[0] - x_map)) > 1e-2
    # post-fit residual of the MAP: z - |x_map|
    assert abs(it.postfit[0, 0] - (z - np.linalg.norm(x_map))) < 1e-8


@pytest.mark.parametrize("dof", [1, 2, 3])
@pytest.mark.parametrize("p", [0.95, 0.99, 0.999])
def test_gate_quantiles_against_scipy(dof: int, p: float) -> None:
    # scipy.stats.chi2.ppf as the independent reference: 1e-12 relative
    assert abs(sf.chi_square_quantile(dof, p) / scipy.stats.chi2.ppf(p, dof) - 1.0) < 1e-12


def test_outlier_rejected_and_listed() -> None:
    case, _ = linear_case(6, 40, 3)
    case["value"] = case["value"].copy()
    case["value"][25, 0] += 50.0 * case["sigma"][25, 0]
    run = sf.run_filter(qd=np.zeros((6, 6)), **case)
    assert run.status == "success" and run.rejected == 1
    assert list(run.rejected_records) == [25]
    assert abs(run.normalized[25, 0]) > 40.0  # +50 sigma of noise on ~1-3 sigma of innovation
    assert run.step_status[25] == int(sf.FilterStatus.rejected)
    assert np.array_equal(run.states[25], run.predicted_states[25])


def test_bad_inputs_name_the_argument_and_rule() -> None:
    case, _ = linear_case(3, 5, 1)
    z = np.zeros((3, 3))
    with pytest.raises(ValueError, match=r"settings.gate_probability: must be in \(0, 1\), got 1.000000"):
        sf.run_filter(qd=z, gate_probability=1.0, **case)
    bad = dict(case, p0=np.diag([1.0, -1.0, 1.0]))
    with pytest.raises(ValueError, match=r"problem.p0: must be positive definite"):
        sf.run_filter(qd=z, **bad)
    with pytest.raises(ValueError, match=r"qd: must be positive semidefinite \(negative process noise"):
        sf.run_filter(qd=np.diag([0.0, -1e-3, 0.0]), **case)
    typ = case["type"].copy()
    typ[2] = 5
    with pytest.raises(ValueError, match=r"problem.records\[2\].type: type 5 is not set up"):
        sf.run_filter(qd=z, **dict(case, type=typ))
    t = case["t"][::-1].copy()
    with pytest.raises(ValueError, match=r"records must be sorted by time"):
        sf.run_filter(qd=z, **dict(case, t=t))
    with pytest.raises(ValueError, match=r"probability: must be in \(0, 1\)"):
        sf.chi_square_quantile(1, 0.0)
    with pytest.raises(ValueError, match=r"form: must be one of"):
        sf.run_filter(qd=z, form="sqrt", **case)


def test_status_tables() -> None:
    assert int(sf.FilterStatus.success) == 0 and int(sf.FilterStatus.rejected) == 1
    assert sf.FilterStatus.covariance_not_pd.message.startswith("the covariance lost positive definiteness")
    assert int(sf.FilterEditFlag.warm_up) == 2


def numpy_rts(run: sf.FilterRun, case: dict, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Textbook RTS (numpy inverse, independent of the engine) over a run's filtered / predicted
    moments; Phi = I and Qd = 0 between records at one time (one step per distinct time)."""
    n = case["phi"].shape[0]
    xs, ps = run.states.copy(), run.covariances.copy()
    t = np.r_[0.0, case["t"]]
    for k in range(len(xs) - 2, -1, -1):
        moved = t[k + 2] > t[k + 1]
        phi = case["phi"] if moved else np.eye(n)
        c = ps[k] @ phi.T @ np.linalg.inv(run.predicted_covariances[k + 1])
        xs[k] = run.states[k] + c @ (xs[k + 1] - run.predicted_states[k + 1])
        ps[k] = run.covariances[k] + c @ (ps[k + 1] - run.predicted_covariances[k + 1]) @ c.T
    return xs, ps


@pytest.mark.parametrize("seed", range(6))
def test_ud_run_is_smoothed_on_its_factors_equal_to_numpy_rts(seed: int) -> None:
    """form="ud" with smooth=True runs the factored RTS (smoother_factored); seeded problems with a full
    random Qd and two records at some times: every smoothed step equals a numpy RTS to 1e-10 relative
    (measured ~1e-14 / ~1e-13)."""
    n = 6 + seed % 4
    case, _ = linear_case(n, 30, 500 + seed)
    a = np.random.default_rng(seed).standard_normal((n, n))
    qd = 0.01 * (a @ a.T / n + 0.1 * np.eye(n))
    run = sf.run_filter(qd=qd, gating=False, form="ud", smooth=True, **case)
    assert run.status == "success" and run.smoother_status == "success"
    assert run.smoother_factored is True
    assert run.smoothed_states is not None and run.smoothed_covariances is not None
    xs, ps = numpy_rts(run, case, qd)
    assert rel(run.smoothed_states, xs) < 1e-10
    assert rel(run.smoothed_covariances, ps) < 1e-10
    joseph = sf.run_filter(qd=qd, gating=False, form="joseph", smooth=True, **case)
    assert joseph.smoother_factored is False
