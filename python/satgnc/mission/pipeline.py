"""The main job as one path (docs/mission.md): tracking -> OD -> relative state -> L1 plan -> flight ->
controllability / observability checks. Each stage takes the previous stages' read-only results and
returns its own (frozen dataclasses, numpy arrays with ``writeable = False``).

Units and frames: orbit stages km, km/s, s in the od room's inertial frame (ECI, GMST Earth
rotation); relative stages m, m/s, N, kg, s in the target's CW frame (y radial, z orbit normal,
x = y cross z, :func:`satgnc._satgnc.cw_relative_state`). One gravitational parameter for every
stage: ``satgnc.EARTH_MU`` (km^3/s^2; times 1e9 in m^3/s^2 for the relative stages).
"""

from __future__ import annotations

import dataclasses
import math
import pathlib
import time

import numpy as np

from .. import _satgnc as _c
from .. import analysis, od
from .._results import Result
from ..guidance import L1Solver, cw_stm
from ..propagation import ExponentialDrag, J2Gravity, propagate
from ..scenarios import l1_rendezvous
from ..scenarios import mission as _scen

__all__ = [
    "Tracking",
    "OrbitEstimate",
    "RelativeState",
    "Plan",
    "Flight",
    "Checks",
    "HandOff",
    "MissionRun",
    "MissionError",
    "track",
    "estimate",
    "relative_state",
    "plan",
    "fly",
    "check",
    "run",
]

_MU_KM = od.EARTH_MU  # km^3/s^2, every stage
_MU_M = _MU_KM * 1e9  # m^3/s^2


class MissionError(ValueError):
    """A stage ended without the result the next one needs (OD not converged, plan not solved)."""


class _Frozen(Result):
    """A stage result: satgnc's one result style (frozen, read-only numpy copies)."""


# ----------------------------------------------------------------------------- stage results
@dataclasses.dataclass(frozen=True)
class Tracking(_Frozen):
    """Stage 1: simulated ground tracking of the target on the truth force model.

    ``t`` (s from the epoch), ``type`` ("range" / "range_rate"), ``value`` (km, km/s), ``sigma``
    (km, km/s), ``station`` (index) per observation; ``truth_times`` (s) and ``truth_states``
    ((n, 6) km, km/s, ECI) of the target; ``forces`` names the truth terms."""

    t: np.ndarray
    type: tuple
    value: np.ndarray
    sigma: np.ndarray
    station: np.ndarray
    stations: tuple  #: od.Station per station
    station_names: tuple
    x0_true: np.ndarray  #: km, km/s, ECI at the epoch
    truth_times: np.ndarray
    truth_states: np.ndarray
    forces: str
    status: str = "success"

    @property
    def observations(self) -> od.Observations:
        """A fresh (mutable) :class:`satgnc.od.Observations` table of the observations."""
        return od.Observations(self.t.copy(), list(self.type), self.value.copy(), self.sigma.copy(),
                               self.station.copy())

    def truth_at(self, t: float) -> np.ndarray:
        """Truth target state (km, km/s) at one of ``truth_times``."""
        k = int(np.flatnonzero(self.truth_times == t)[0])
        return self.truth_states[k]


@dataclasses.dataclass(frozen=True)
class OrbitEstimate(_Frozen):
    """Stage 2: the batch least-squares estimate of the target's state at the epoch.

    ``x0`` (km, km/s, ECI), ``covariance`` (6, 6) (km^2, km^2/s, km^2/s^2), ``error`` = x0 - truth,
    ``sigma`` = sqrt(diag(covariance)); ``normalized`` residuals (-) per observation."""

    status: str
    iterations: int
    x0: np.ndarray
    covariance: np.ndarray
    rank: int
    condition_number: float
    error: np.ndarray
    sigma: np.ndarray
    guess: np.ndarray
    normalized: np.ndarray
    residuals: np.ndarray
    model: str  #: the OD force model ("two-body" or "two-body + J2")


@dataclasses.dataclass(frozen=True)
class RelativeState(_Frozen):
    """Stage 3: the chaser relative to the estimated target at the plan epoch ``t`` (s).

    ``x`` (m, m/s, target CW frame) with ``covariance`` (6, 6) (m^2, m^2/s, m^2/s^2) mapped from the
    OD covariance by the orbit STM and the Jacobian (m per km) of the relative state with respect to
    the target state; ``x_true`` the truth relative state; ``target`` (km, km/s, ECI) the estimated
    target at ``t`` and ``radius`` (m), ``mean_motion`` (rad/s) of its CW model."""

    t: float
    x: np.ndarray
    covariance: np.ndarray
    x_true: np.ndarray
    error: np.ndarray
    target: np.ndarray
    target_covariance: np.ndarray
    stm: np.ndarray
    jacobian: np.ndarray
    radius: float
    mean_motion: float
    x12_true: np.ndarray  #: [r_t - r_c, r_t, v_t - v_c, v_t] (m, m/s, ECI) of the truth at t
    status: str = "success"


@dataclasses.dataclass(frozen=True)
class Plan(_Frozen):
    """Stage 4: the L1 plan on the discrete CW model of the estimated orbit.

    ``U`` (N, 3) N in the target CW frame, piecewise constant over ``dt`` (s); ``X`` (N+1, 6) the
    planned states (m, m/s, CW); ``A``, ``B`` the discrete model as solved (scaled units, ``scales``
    = (length m, speed m/s, time s, force N)); ``delta_v`` = sum ||u_k||_1 dt / mass (m/s)."""

    status: str
    iterations: int
    U: np.ndarray
    X: np.ndarray
    dt: float
    delta_v: float
    A: np.ndarray
    B: np.ndarray
    scales: tuple
    solve_time: float


@dataclasses.dataclass(frozen=True)
class Flight(_Frozen):
    """Stage 5: the plan flown open loop on the two-satellite truth (J2 and drag as the scenario says).

    ``X`` (N+1, 12) [r_t - r_c, r_t, v_t - v_c, v_t] (m, m/s, ECI), ``X_cw`` (N+1, 6) the relative
    states in the target CW frame (m, m/s); ``miss_position`` (m) and ``miss_velocity`` (m/s) at the
    final time; ``predicted_3sigma`` (m): 3 sigma of the final position error that the relative-state
    covariance alone explains (CW STM over tf); ``tolerance`` (m) the scenario's."""

    status: str
    X: np.ndarray
    X_cw: np.ndarray
    t: np.ndarray
    miss_position: float
    miss_velocity: float
    predicted_3sigma: float
    tolerance: float
    truth: str


@dataclasses.dataclass(frozen=True)
class Checks(_Frozen):
    """Stage 6: controllability of the plan's discrete CW model and observability of the tracking
    geometry used (rows H_j Phi_j / sigma_j of the OD model at the estimate, state columns scaled by
    |r0| km and |v0| km/s so that they are unit-free)."""

    controllability: str  #: verdict of analysis.controllability
    controllability_rank: int
    controllability_sv: np.ndarray  #: singular values of [B, AB, ..] / the largest
    observability: str  #: verdict of analysis.observability (static map: A = I, C = O)
    observability_rank: int
    observability_sv: np.ndarray  #: singular values of O / the largest
    gramian_condition: float  #: of analysis.ltv_observability_gramian (scaled state)
    od_rank: int
    od_condition: float
    status: str = "success"


@dataclasses.dataclass(frozen=True)
class HandOff(Result):
    """One row of the hand-off table: what ``stage`` passed on, its value, unit and frame."""

    stage: str
    quantity: str
    value: str
    unit: str
    frame: str


@dataclasses.dataclass(frozen=True)
class MissionRun(Result):
    """Every stage result of :func:`run`, the hand-off table and the wall time per stage (s)."""

    scenario: _scen.MissionScenario
    tracking: Tracking
    estimate: OrbitEstimate
    relative: RelativeState
    plan: Plan
    flight: Flight
    checks: Checks
    handoff: tuple
    timings: dict
    quick: bool

    @property
    def statuses(self) -> dict:
        """Stage name -> status string."""
        return {"tracking": self.tracking.status, "od": self.estimate.status,
                "relative": self.relative.status,
                "plan": self.plan.status, "flight": self.flight.status, "checks": self.checks.status}

    def handoff_markdown(self) -> str:
        """The hand-off table as Markdown."""
        rows = ["| stage | hands on | value | unit | frame |", "|---|---|---|---|---|"]
        rows += [f"| {h.stage} | {h.quantity} | {h.value} | {h.unit} | {h.frame} |" for h in self.handoff]
        return "\n".join(rows)


# ----------------------------------------------------------------------------- models
def _truth_forces(sc: _scen.MissionScenario):
    """(terms for satgnc.propagate, description) of the orbit-level truth: J2 and drag as the file says."""
    terms, names = [], ["point mass"]
    if sc.truth_j2:
        terms.append(J2Gravity(mu=_MU_KM))
        names.append("J2")
    if sc.drag is not None:
        d = sc.drag
        terms.append(ExponentialDrag(rho0=d.rho0, h0=d.h0, scale_height=d.scale_height, cd=d.cd, area=d.area,
                                     mass=d.mass, body_radius=od.EARTH_RADIUS,
                                     omega=np.array([0.0, 0.0, od.EARTH_OMEGA])))
        names.append("exponential drag")
    return terms, " + ".join(names)


def truth_params(sc: _scen.MissionScenario) -> _c.TwoSatelliteParams:
    """The two-satellite truth (SI) with the same mu, J2 and exponential atmosphere as the orbit truth:
    rho0 exp(-(h - h0)/H) = rho0 e^(h0/H) exp(-h/H), h = |r| - Earth radius."""
    j2 = J2Gravity(mu=_MU_KM)
    p = _c.TwoSatelliteParams()
    p.mu = _MU_M
    p.j2_on = bool(sc.truth_j2)
    p.j2 = j2.j2
    p.j2_radius = j2.radius * 1e3
    p.omega = np.array([0.0, 0.0, od.EARTH_OMEGA])
    p.atmosphere = _c.AtmosphereRotation.co_rotating
    p.mass_chaser = sc.mass
    p.drag_on = sc.drag is not None
    if sc.drag is not None:
        d = sc.drag
        if d.h0 / d.scale_height > 700.0:
            raise ValueError(f"truth.drag: h0 / scale_height = {d.h0 / d.scale_height:.3g} overflows the "
                             "two-satellite density rho0 exp(h0 / H) (must be <= 700)")
        p.rho0 = d.rho0 * math.exp(d.h0 / d.scale_height)
        p.density_decay = 1.0 / (d.scale_height * 1e3)
        p.density_radius = od.EARTH_RADIUS * 1e3
        p.mass_target = d.mass
        p.cd_chaser = d.cd
        p.cd_target = d.cd
        p.area_chaser = d.chaser_area
        p.area_target = d.area
    return p


def _od_propagator(sc: _scen.MissionScenario):
    return od.make_propagator(sc.od_propagator, _MU_KM, sc.od_j2 and sc.od_propagator == "cvodes")


# ----------------------------------------------------------------------------- stages
def track(sc: _scen.MissionScenario, quick: bool = False) -> Tracking:
    """Stage 1: the truth orbit (``satgnc.propagate`` with J2 and drag) observed by every station.

    Same measurement model, noise and mask rule as :func:`satgnc.od.simulate`, which cannot take drag
    today (its propagators carry mu and J2 only): the states come from ``satgnc.propagate``."""
    times = sc.times[:: sc.quick_thin] if quick else sc.times
    grid = np.union1d(np.r_[0.0, times], [sc.start])
    terms, forces = _truth_forces(sc)
    # rtol 1e-12: the truth is more accurate than the OD model's propagator (1e-11) and than the noise
    traj = propagate(sc.x0, grid, t0=0.0, mu=_MU_KM, forces=terms or None, with_stm=False, rtol=1e-12)
    states = np.asarray(traj.states)
    stations = tuple(od.station_geodetic(s.lat, s.lon, s.height, sc.epoch) for s in sc.stations)
    rng = np.random.default_rng(sc.seed)
    rows: dict = {"t": [], "type": [], "value": [], "sigma": [], "station": []}
    sig = {"range": sc.sigma_range, "range_rate": sc.sigma_range_rate}
    index = {float(t): k for k, t in enumerate(grid)}
    for i, st in enumerate(stations):
        for tk in times:
            xk = states[index[float(tk)]]
            R = st.state(float(tk))
            if od.elevation_deg(xk, R) < sc.mask:
                continue
            for kind in sc.types:
                v, _ = od.predict(kind, xk, R)
                rows["t"].append(float(tk))
                rows["type"].append(kind)
                rows["value"].append(v + rng.normal(0.0, sig[kind]))
                rows["sigma"].append(sig[kind])
                rows["station"].append(i)
    if len(rows["t"]) < 6:
        raise ValueError(f"tracking: {len(rows['t'])} observations above the {sc.mask} deg mask "
                         f"({sc.path}); the OD needs at least 6 (hint: station positions or the arc)")
    order = np.lexsort((rows["station"], rows["t"]))
    return Tracking(
        t=np.asarray(rows["t"])[order], type=tuple(rows["type"][k] for k in order),
        value=np.asarray(rows["value"])[order], sigma=np.asarray(rows["sigma"])[order],
        station=np.asarray(rows["station"], dtype=int)[order], stations=stations,
        station_names=tuple(s.name for s in sc.stations), x0_true=sc.x0, truth_times=grid,
        truth_states=states, forces=forces,
    )


def estimate(sc: _scen.MissionScenario, tracking: Tracking) -> OrbitEstimate:
    """Stage 2: :func:`satgnc.od.solve` from the truth plus the file's guess offset."""
    guess = tracking.x0_true + sc.guess_offset
    r = od.solve(tracking.observations, list(tracking.stations), guess, method=sc.od_method,
                 propagator=_od_propagator(sc), mu=_MU_KM)
    x0 = np.asarray(r.x0, dtype=float)
    P = np.asarray(r.covariance, dtype=float)
    model = "two-body + J2" if sc.od_j2 and sc.od_propagator == "cvodes" else "two-body"
    status = r.status if isinstance(r.status, str) else r.status.name  # enum today, a string after B
    return OrbitEstimate(status=status, iterations=int(r.iterations), x0=x0, covariance=P,
                         rank=int(r.rank), condition_number=float(r.condition_number),
                         error=x0 - tracking.x0_true, sigma=np.sqrt(np.diag(P)), guess=guess,
                         normalized=np.asarray(r.normalized, dtype=float).ravel(),
                         residuals=np.asarray(r.residuals, dtype=float).ravel(), model=model)


def _x12(target_km: np.ndarray, chaser_km: np.ndarray) -> np.ndarray:
    """[r_t - r_c, r_t, v_t - v_c, v_t] (m, m/s) from target and chaser ECI states (km, km/s)."""
    t = np.asarray(target_km) * 1e3
    c = np.asarray(chaser_km) * 1e3
    return np.concatenate([t[:3] - c[:3], t[:3], t[3:] - c[3:], t[3:]])


def relative_state(sc: _scen.MissionScenario, tracking: Tracking, est: OrbitEstimate) -> RelativeState:
    """Stage 3: the chaser (known in ECI: the file's relative state about the TRUE target) relative to
    the ESTIMATED target at the plan epoch; covariance J Phi P0 Phi^T J^T (m^2, ...)."""
    t = sc.start
    target_true = tracking.truth_at(t)
    x12_true = np.asarray(_c.two_satellite_state(target_true[:3] * 1e3, target_true[3:] * 1e3,
                                                 np.r_[sc.p0, sc.v0]))
    chaser = np.r_[target_true[:3] - x12_true[0:3] / 1e3, target_true[3:] - x12_true[6:9] / 1e3]
    states, stms = _od_propagator(sc).propagate(est.x0, [float(t)])
    target = np.asarray(states[0], dtype=float)
    Phi = np.asarray(stms[0], dtype=float)
    P_target = Phi @ est.covariance @ Phi.T

    def rel(_t, x, _u):
        return np.asarray(_c.cw_relative_state(_x12(x, chaser)))

    J, _ = analysis.fd_jacobian(rel, 0.0, target, np.zeros(0))
    J = np.asarray(J)
    x = rel(0.0, target, None)
    x_true = np.asarray(_c.cw_relative_state(x12_true))
    # The CW model's circular orbit has the estimated target's radius at the plan epoch (the L1
    # scenario's "radius"; the osculating semi-major axis is 2-9 km off in LEO under J2 and flew worse).
    radius = float(np.linalg.norm(target[:3])) * 1e3
    return RelativeState(t=float(t), x=x, covariance=J @ P_target @ J.T, x_true=x_true, error=x - x_true,
                         target=target, target_covariance=P_target, stm=Phi, jacobian=J, radius=radius,
                         mean_motion=math.sqrt(_MU_M / radius**3), x12_true=x12_true)


def plan(sc: _scen.MissionScenario, rel: RelativeState) -> Plan:
    """Stage 4: :class:`satgnc.guidance.L1Solver` on the CW model of the estimated orbit, through the
    L1 scenario's problem builder (its scaling, weights and bounds), from the estimated state.

    One small function so that ``guidance.plan(problem, model)`` can replace its body."""
    cw = l1_rendezvous.Scenario(
        mu=_MU_M, radius=rel.radius, mass=sc.mass, p0=rel.x[:3].copy(), v0=rel.x[3:].copy(), tf=sc.tf,
        knots=sc.knots, alpha=sc.alpha, Qf=sc.Qf, u_max=sc.u_max, method=sc.method,
        cases={"mission": {"rho": sc.rho, "box": sc.box, "terminal_equality": sc.terminal_equality}})
    kw = l1_rendezvous.linear_problem(cw, "mission")
    r = L1Solver(**kw, settings={"rho": sc.rho}).solve()
    U = np.asarray(r.Y) * cw.u_ref
    X = cw.to_si(X=np.asarray(r.X_flown))
    dv = float(np.abs(U).sum() * cw.dt / sc.mass)
    return Plan(status=r.status, iterations=int(r.iterations), U=U, X=X, dt=cw.dt, delta_v=dv, A=kw["A"],
                B=kw["B"], scales=(cw.l_ref, cw.v_ref, cw.t_ref, cw.u_ref), solve_time=float(r.solve_time))


def fly(sc: _scen.MissionScenario, rel: RelativeState, pl: Plan) -> Flight:
    """Stage 5: ``TwoSatelliteTruth.fly`` (CVODES) of the plan from the TRUE 12-state at the plan epoch.

    One small function so that ``guidance.fly(...)`` can replace its body."""
    p = truth_params(sc)
    r = _c.TwoSatelliteTruth(_c.TwoSatelliteModel(p)).fly(rel.x12_true, np.ascontiguousarray(pl.U.T), pl.dt)
    if not r["ok"]:
        raise RuntimeError(f"fly: the two-satellite truth failed: {r['message']}")
    X = np.asarray(r["X"]).T
    X_cw = np.array([np.asarray(_c.cw_relative_state(x)) for x in X])
    Phi = np.asarray(cw_stm(rel.mean_motion, sc.tf))
    Pf = Phi @ rel.covariance @ Phi.T
    pred = 3.0 * math.sqrt(max(float(np.linalg.eigvalsh(Pf[:3, :3])[-1]), 0.0))
    terms = ["point mass"] + (["J2"] if p.j2_on else []) + (["exponential drag"] if p.drag_on else [])
    miss = float(np.linalg.norm(X[-1, 0:3]))
    return Flight(status="success" if miss <= sc.miss_tolerance else "miss_above_tolerance", X=X, X_cw=X_cw,
                  t=np.arange(X.shape[0]) * pl.dt, miss_position=miss,
                  miss_velocity=float(np.linalg.norm(X[-1, 6:9])), predicted_3sigma=pred,
                  tolerance=sc.miss_tolerance, truth=" + ".join(terms))


def _singular(M: np.ndarray) -> np.ndarray:
    s = np.linalg.svd(M, compute_uv=False)
    return s / s[0]


def check(sc: _scen.MissionScenario, tracking: Tracking, est: OrbitEstimate, pl: Plan) -> Checks:
    """Stage 6: the staircase controllability test of the plan's (A, B), and the observability of the
    tracking geometry: the whitened, scaled sensitivity O = [H_j Phi_j D / sigma_j] of the OD model at
    the estimate, tested as the static pair (I, O) (rank O = 6 <=> observable) and as the LTV Gramian."""
    ctrl = analysis.controllability(pl.A, pl.B)
    K = analysis.kalman_matrix(pl.A, B=pl.B)
    times = np.unique(tracking.t)
    states, stms = _od_propagator(sc).propagate(est.x0, list(times))
    k_of = {float(t): k for k, t in enumerate(times)}
    D = np.diag([np.linalg.norm(est.x0[:3])] * 3 + [np.linalg.norm(est.x0[3:])] * 3)
    rows, Phis, Hs, ws = [], [], [], []
    for t, kind, s, i in zip(tracking.t, tracking.type, tracking.sigma, tracking.station):
        k = k_of[float(t)]
        _, H = od.predict(kind, states[k], tracking.stations[i].state(float(t)))
        PhiD = np.asarray(stms[k]) @ D
        rows.append(H @ PhiD / s)
        Phis.append(PhiD)
        Hs.append(H[None, :])
        ws.append(1.0 / s**2)
    O = np.array(rows)
    obs = analysis.observability(np.eye(6), O)
    gram = analysis.ltv_observability_gramian(Phis, Hs, ws)
    return Checks(controllability=ctrl.verdict, controllability_rank=int(ctrl.rank),
                  controllability_sv=_singular(K), observability=obs.verdict,
                  observability_rank=int(obs.rank),
                  observability_sv=_singular(O), gramian_condition=float(gram.condition), od_rank=est.rank,
                  od_condition=est.condition_number)


def _handoff(sc, tr: Tracking, est: OrbitEstimate, rel: RelativeState, pl: Plan, fl: Flight,
             ck: Checks) -> tuple:
    def v(a, fmt=".4g"):
        return "[" + ", ".join(format(float(x), fmt) for x in a) + "]"

    n_st = len(set(tr.station.tolist()))
    sr = np.sqrt(np.linalg.eigvalsh(rel.covariance[:3, :3])[-1])
    sv = np.sqrt(np.linalg.eigvalsh(rel.covariance[3:, 3:])[-1])
    return (
        HandOff("1 tracking", f"{tr.t.size} observations ({', '.join(sc.types)}) from {n_st} stations, "
                f"t in [{tr.t[0]:.0f}, {tr.t[-1]:.0f}]",
                f"sigma {sc.sigma_range:g} / {sc.sigma_range_rate:g}",
                "km / km/s", "station to target (topocentric line of sight)"),
        HandOff("1 tracking", "truth force model of the observations", tr.forces, "-", "ECI"),
        HandOff("2 OD", f"x0 estimate ({est.status}, {est.iterations} iterations, rank {est.rank}, "
                f"cond {est.condition_number:.3g})", v(est.x0, ".6f"), "km, km/s", "ECI at the epoch"),
        HandOff("2 OD", "1-sigma of x0 (sqrt diag P0)", v(est.sigma, ".3g"), "km, km/s", "ECI at the epoch"),
        HandOff("2 OD", "x0 error vs truth, in sigmas", v(est.error / est.sigma, ".2f"), "-",
                "ECI at the epoch"),
        HandOff("3 relative", f"chaser relative state at t = {rel.t:.0f} s", v(rel.x, ".4f"), "m, m/s",
                "target CW (y radial, z normal)"),
        HandOff("3 relative", "1-sigma (largest axis) of position / velocity", f"{sr:.3g} / {sv:.3g}",
                "m / m/s",
                "target CW"),
        HandOff("3 relative", "CW model: orbit radius, mean motion",
                f"{rel.radius:.1f}, {rel.mean_motion:.6e}",
                "m, rad/s", "estimated target orbit"),
        HandOff("4 plan", f"U ({pl.U.shape[0]} x 3) over dt = {pl.dt:.3f} s ({pl.status}, {pl.iterations} "
                "iterations)", f"delta-v {pl.delta_v:.4f}, max abs(u) {np.max(np.abs(pl.U)):.3e}", "m/s, N",
                "target CW"),
        HandOff("5 flight", f"miss at tf = {sc.tf:g} s on {fl.truth}",
                f"{fl.miss_position:.2f} m, {fl.miss_velocity:.4f} m/s (tolerance {fl.tolerance:g} m, "
                f"OD 3-sigma "
                f"{fl.predicted_3sigma:.2f} m)", "m, m/s", "ECI relative (d = r_t - r_c)"),
        HandOff("6 checks", "controllability of the plan's discrete CW (A, B)",
                f"{ck.controllability} (rank {ck.controllability_rank})", "-", "scaled CW"),
        HandOff("6 checks", "observability of the tracking geometry (OD model)",
                f"{ck.observability} (rank {ck.observability_rank}, Gramian cond {ck.gramian_condition:.3g})",
                "-", "ECI, state scaled by norm(r0), norm(v0)"),
    )


def run(scenario=None, quick: bool = False) -> MissionRun:
    """Run the six stages on a scenario (a path, a loaded :class:`MissionScenario`, or None for the
    packaged ``mission_leo.toml``). ``quick`` keeps every ``quick_thin``-th tracking time."""
    if isinstance(scenario, _scen.MissionScenario):
        sc = scenario
    elif scenario is None or isinstance(scenario, (str, pathlib.Path)):
        sc = _scen.load(scenario, "scenario")
    else:
        raise TypeError(f"scenario: must be a path, a MissionScenario or None, got {type(scenario).__name__}")
    if not isinstance(quick, bool):
        raise TypeError(f"quick: must be true or false (a bool), got {type(quick).__name__}")
    timings = {}
    t0 = time.perf_counter()
    tr = track(sc, quick)
    timings["tracking"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    est = estimate(sc, tr)
    timings["od"] = time.perf_counter() - t0
    if est.status != "converged":
        raise MissionError(f"od: the estimate did not converge (status {est.status}); the mission stops")
    t0 = time.perf_counter()
    rel = relative_state(sc, tr, est)
    timings["relative"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    pl = plan(sc, rel)
    timings["plan"] = time.perf_counter() - t0
    if pl.status != "solved":
        raise MissionError(f"plan: the L1 plan is not solved (status {pl.status}); the mission stops")
    t0 = time.perf_counter()
    fl = fly(sc, rel, pl)
    timings["flight"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    ck = check(sc, tr, est, pl)
    timings["checks"] = time.perf_counter() - t0
    return MissionRun(scenario=sc, tracking=tr, estimate=est, relative=rel, plan=pl, flight=fl, checks=ck,
                      handoff=_handoff(sc, tr, est, rel, pl, fl, ck), timings=timings, quick=quick)
