"""Issue 14 bench: one LEO day with EGM2008 20x20 + Sun + Moon + SRP + Harris-Priester drag and the
STM, satgnc DOP853 (C++) against scipy ``solve_ivp(method="DOP853")`` on the same models in numpy.

The numpy models (written here, independent of the C++ code paths except where said):
- gravity: EGM2008 20x20, fully normalized coefficients un-normalized to degree 20, the plain V/W
  (Cunningham) recursion of Montenbruck & Gill 3.2.4 in ITRF, vectorized over a batch of positions;
  ITRF = R3(omega t) GCRF, the same UniformRotation(0, EARTH_OMEGA) as the satgnc field;
- Sun and Moon: point masses with the indirect term; their positions are ``sun_position`` /
  ``moon_position`` (ERFA eraEpv00 / eraMoon98 through satgnc) called inside the RHS at every
  evaluation. satgnc interpolates them (cubic Hermite on 1/8-day nodes); the two ERFA calls cost
  scipy ~37 us of its ~1.5 ms RHS (2.5 %, measured): a slight handicap for scipy, not a deciding one;
- SRP: cannonball, no shadow in both (shadow="none");
- drag: -1/2 Cd A/m rho |w| w, w = v - omega x r, rho = satgnc's HarrisPriester.density (the one
  function shared with satgnc: it is exposed, so both integrate the same atmosphere);
- STM: variational equations Phi' = [[0, I], [da/dr, da/dv]] Phi. da/dr: the central term's
  gradient analytic, the rest (harmonics, Sun, Moon, SRP, drag) by central differences of the numpy
  acceleration (h = 1e-2 km; the truncation is ~(h/r)^2 ~ 2e-12 relative, the 7 positions in one
  batched call); da/dv (drag only): analytic, -k rho (|w| I + w w^T / |w|). Differencing the whole
  acceleration in v too (central term included, h_v = 1e-5 km/s) puts rounding noise (~1e-13 /s,
  estimated) into da/dv that scipy's error estimate on the STM sees as error: measured 25754 RHS
  evaluations for 2 h instead of 1418 (18x).
satgnc's STM uses analytic partials. Both integrators run DOP853 on the 42-vector at the same
rtol / atol (scalar). If scipy's day would be too long, scipy runs SCIPY_HOURS and the table states
the time per simulated hour for both (the default runs the whole day in both).
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np
import satgnc
from satgnc.dynamics import (
    AtmosphereDrag,
    GravityField,
    HarrisPriester,
    SolarRadiationPressure,
    ThirdBodies,
    UniformRotation,
    egm2008,
    force_model,
    moon_position,
    sun_position,
)
from scipy.integrate import solve_ivp

EPOCH = (2460676.5, 0.0)  # 2025-01-01T00:00 TT
DEG = 20
RTOL, ATOL = 1e-12, 1e-12
DAY = 86400.0
SCIPY_HOURS = (
    24.0  # scipy arc (h): the full day (~30 s); lower it on a slow machine, the table scales per hour
)
CD, AREA, MASS, CR, P_SRP = 2.2, 1.0, 100.0, 1.3, 4.56e-6
AU = 149597870.7  # km (IAU 2012), as kAstronomicalUnitKm
OMEGA = satgnc.EARTH_OMEGA


class NumpyModel:
    """The same forces in numpy; ``accel(r, v, t)`` takes batches r, v of shape (B, 3)."""

    def __init__(self) -> None:
        cf = egm2008(DEG)
        self.mu, self.re = cf.mu, cf.radius
        n_max = DEG
        self.C = np.zeros((n_max + 1, n_max + 1))
        self.S = np.zeros((n_max + 1, n_max + 1))
        for n in range(n_max + 1):
            for m in range(n + 1):
                if n == 1 or (n == 0 and m == 0):
                    continue
                norm = math.sqrt((2 - (m == 0)) * (2 * n + 1) * math.factorial(n - m) / math.factorial(n + m))
                self.C[n, m] = norm * cf.cnm(n, m)
                self.S[n, m] = norm * cf.snm(n, m)
        # C00 = 0: the central term is added apart (with its analytic gradient) so that the differenced
        # part is the ~1e-5 km/s^2 perturbation and its rounding stays ~1e-21 km/s^2.
        nn, mm = np.meshgrid(np.arange(n_max + 1), np.arange(n_max + 1), indexing="ij")
        keep = mm <= nn
        self.n, self.m = nn[keep], mm[keep]
        self.cnm, self.snm = self.C[keep], self.S[keep]
        self.fac = np.array(
            [math.factorial(n - m + 2) / math.factorial(n - m) for n, m in zip(self.n, self.m)]
        )
        self.m0 = self.m == 0
        tb = ThirdBodies()
        self.mu_sun, self.mu_moon = tb.mu_sun, tb.mu_moon
        self.hp = HarrisPriester()
        self.k_srp = P_SRP * CR * AREA / MASS * 1e-3 * AU * AU
        self.k_drag = 0.5 * CD * AREA / MASS * 1e3

    def gravity_itrf(self, p: np.ndarray) -> np.ndarray:
        x, y, z = p[:, 0], p[:, 1], p[:, 2]
        r2 = x * x + y * y + z * z
        rr = self.re / r2
        nmax = DEG + 1
        V = np.zeros((nmax + 1, nmax + 1, p.shape[0]))
        W = np.zeros_like(V)
        V[0, 0] = self.re / np.sqrt(r2)
        for m in range(nmax + 1):
            if m > 0:
                V[m, m] = (2 * m - 1) * (x * rr * V[m - 1, m - 1] - y * rr * W[m - 1, m - 1])
                W[m, m] = (2 * m - 1) * (x * rr * W[m - 1, m - 1] + y * rr * V[m - 1, m - 1])
            if m + 1 <= nmax:
                V[m + 1, m] = (2 * m + 1) * z * rr * V[m, m]
                W[m + 1, m] = (2 * m + 1) * z * rr * W[m, m]
            for n in range(m + 2, nmax + 1):
                a, b = (2 * n - 1) / (n - m), (n + m - 1) / (n - m)
                V[n, m] = a * z * rr * V[n - 1, m] - b * self.re * rr * V[n - 2, m]
                W[n, m] = a * z * rr * W[n - 1, m] - b * self.re * rr * W[n - 2, m]
        n, m, c, s = self.n, self.m, self.cnm[:, None], self.snm[:, None]
        vp, wp = V[n + 1, m + 1], W[n + 1, m + 1]
        mm1 = np.maximum(m - 1, 0)
        vm, wm = V[n + 1, mm1], W[n + 1, mm1]
        f = self.fac[:, None]
        ax = np.where(self.m0[:, None], -c * vp, 0.5 * ((-c * vp - s * wp) + f * (c * vm + s * wm)))
        ay = np.where(self.m0[:, None], -c * wp, 0.5 * ((-c * wp + s * vp) + f * (-c * wm + s * vm)))
        v0, w0 = V[n + 1, m], W[n + 1, m]
        az = (n - m + 1)[:, None] * (-c * v0 - s * w0)
        k = self.mu / self.re**2
        return k * np.stack([ax.sum(0), ay.sum(0), az.sum(0)], axis=1)

    def accel(self, r: np.ndarray, v: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Perturbing acceleration (all but -mu r / |r|^3), km/s^2; the drag's rho (kg/m^3), w (km/s)."""
        th = OMEGA * t
        ct, st = math.cos(th), math.sin(th)
        rot = np.array([[ct, st, 0.0], [-st, ct, 0.0], [0.0, 0.0, 1.0]])  # GCRF -> ITRF
        r_itrf = r @ rot.T
        a = self.gravity_itrf(r_itrf) @ rot
        sun = np.asarray(sun_position(EPOCH[0], EPOCH[1] + t / DAY))
        moon = np.asarray(moon_position(EPOCH[0], EPOCH[1] + t / DAY))
        for body, mub in ((sun, self.mu_sun), (moon, self.mu_moon)):
            d = body - r
            a += mub * (d / np.linalg.norm(d, axis=1, keepdims=True) ** 3 - body / np.linalg.norm(body) ** 3)
        d = r - sun
        a += self.k_srp * d / np.linalg.norm(d, axis=1, keepdims=True) ** 3
        w = v - np.cross(np.array([0.0, 0.0, OMEGA]), r)
        sun_itrf = rot @ sun
        rho = np.array([self.hp.density(ri, sun_itrf, t) for ri in r_itrf])
        a -= self.k_drag * (rho * np.linalg.norm(w, axis=1))[:, None] * w
        return a, rho, w


def rhs_factory(model: NumpyModel):
    hr = 1e-2
    dr = np.zeros((7, 3))
    for i in range(3):
        dr[1 + 2 * i, i], dr[2 + 2 * i, i] = hr, -hr
    eye = np.eye(3)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        r, v = y[:3], y[3:6]
        a, rho, w = model.accel(r + dr, np.broadcast_to(v, (7, 3)), t)
        jac = np.empty((3, 6))
        for i in range(3):  # perturbing forces: central differences in r
            jac[:, i] = (a[1 + 2 * i] - a[2 + 2 * i]) / (2 * hr)
        rn = np.linalg.norm(r)
        u = r / rn
        a0 = a[0] - model.mu * u / rn**2  # central term and its gradient: analytic
        jac[:, :3] += model.mu / rn**3 * (3.0 * np.outer(u, u) - eye)
        wn = np.linalg.norm(w[0])  # only the drag depends on v: d(-k rho |w| w)/dv, analytic
        jac[:, 3:] = -model.k_drag * rho[0] * (wn * eye + np.outer(w[0], w[0]) / wn)
        phi = y[6:].reshape(6, 6)
        dphi = np.vstack([phi[3:], jac @ phi])
        return np.concatenate([v, a0, dphi.ravel()])

    return rhs


def main() -> int:
    x0 = satgnc.elements_to_state(6778.0, 0.001, 51.6, 30.0, 40.0, 0.0, mu=egm2008(2).mu)
    rot = UniformRotation(0.0, OMEGA)
    fm = force_model(
        gravity=GravityField(egm2008(DEG), DEG, rotation=rot),
        third_body=ThirdBodies(),
        srp=SolarRadiationPressure(area=AREA, mass=MASS, cr=CR, shadow="none", pressure=P_SRP),
        atmosphere_drag=AtmosphereDrag(HarrisPriester(), cd=CD, area=AREA, mass=MASS, earth_rotation=rot),
        epoch_jd=EPOCH,
    )
    model = NumpyModel()
    rhs = rhs_factory(model)
    # Same acceleration and Jacobian at x0 and at t = 6 h (the models agree before integrating).
    err_a = err_j = 0.0
    for t in (0.0, 21600.0):
        a_sg, dadr, dadv = (np.asarray(z) for z in fm.acceleration_jacobians(x0[:3], x0[3:], t))
        d = rhs(t, np.concatenate([x0, np.eye(6).ravel()]))
        jac_np = d[6:].reshape(6, 6)[3:]
        err_a = max(err_a, np.linalg.norm(d[3:6] - a_sg) / np.linalg.norm(a_sg))
        err_j = max(err_j, np.abs(jac_np - np.hstack([dadr, dadv])).max() / np.abs(dadr).max())
    y0 = np.concatenate([x0, np.eye(6).ravel()])
    t_sc = SCIPY_HOURS * 3600.0

    def run_satgnc(t_end: float):
        tr = satgnc.propagate(
            x0, [0.0, t_end], forces=fm, method="dop853", rtol=RTOL, atol=ATOL, with_stm=True
        )
        return np.asarray(tr.states)[-1], np.asarray(tr.stms)[-1], int(tr.stats["rhs_evals"])

    best_day = math.inf
    for _ in range(3):
        t0 = time.perf_counter()
        run_satgnc(DAY)
        best_day = min(best_day, time.perf_counter() - t0)
    best_arc = math.inf
    for _ in range(3):
        t0 = time.perf_counter()
        xs, phis, nfev_sg = run_satgnc(t_sc)
        best_arc = min(best_arc, time.perf_counter() - t0)
    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, t_sc), y0, method="DOP853", rtol=RTOL, atol=ATOL)
    wall_sc = time.perf_counter() - t0
    xsc, phisc = sol.y[:6, -1], sol.y[6:, -1].reshape(6, 6)

    print("LEO 400 km 51.6 deg, EGM2008 20x20 + Sun + Moon + SRP (no shadow) + Harris-Priester drag, STM;")
    print(f"DOP853 rtol {RTOL:g} atol {ATOL:g} on the 42-vector; satgnc best of 3, scipy one run (wall s)")
    print(
        f"at x0 (t = 0, 6 h): |a_numpy - a_satgnc| / |a| = {err_a:.2e}, "
        f"max |J_fd - J_satgnc| / max |da/dr| = {err_j:.2e}"
    )
    print(f"{'':34s}{'satgnc':>12s}{'scipy':>12s}{'ratio':>10s}")
    arc = f"wall, {SCIPY_HOURS:g} h arc (s)"
    print(f"{arc:34s}{best_arc:12.4f}{wall_sc:12.2f}{wall_sc / best_arc:10.0f}")
    if SCIPY_HOURS != 24.0:
        print(f"{'wall, 24 h arc (s)':34s}{best_day:12.4f}{'':>12s}")
    per_h_sg, per_h_sc = best_arc / SCIPY_HOURS, wall_sc / SCIPY_HOURS  # the same arc for both
    print(f"{'wall per simulated hour (s)':34s}{per_h_sg:12.4f}{per_h_sc:12.2f}{per_h_sc / per_h_sg:10.0f}")
    print(f"{'RHS evaluations, arc':34s}{nfev_sg:12d}{sol.nfev:12d}")
    us_sg, us_sc = best_arc / nfev_sg * 1e6, wall_sc / sol.nfev * 1e6
    print(f"{'wall per RHS evaluation (us)':34s}{us_sg:12.2f}{us_sc:12.0f}{us_sc / us_sg:10.0f}")
    print(f"final |r_satgnc - r_scipy| after {SCIPY_HOURS:g} h: {np.linalg.norm(xs[:3] - xsc[:3]):.3e} km")
    print(f"final |v_satgnc - v_scipy| after {SCIPY_HOURS:g} h: {np.linalg.norm(xs[3:] - xsc[3:]):.3e} km/s")
    rel = np.abs(phis - phisc).max() / np.abs(phis).max()
    print(f"max |Phi_satgnc - Phi_scipy| / max |Phi|: {rel:.3e}")
    return 0 if sol.success else 1


if __name__ == "__main__":
    sys.exit(main())
