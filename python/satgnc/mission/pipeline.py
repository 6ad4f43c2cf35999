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
from .. import analysis, guidance, od
from .._results import Result
from ..guidance import cw_stm
from ..guidance.planning import transcribe
from ..guidance.problem import RendezvousProblem
from ..propagation import ExponentialDrag, ForceModel, J2Gravity
from ..scenarios import mission as _scen
from ..scenarios import rendezvous as _rv

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
    "fly_closed_loop",
    "check",
    "run",
    "ClosedLoop",
    "problem",
    "flight_truth",
    "truth_force_model",
    "od_force_model",
    "truth_params",
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
    model: str  #: the OD force model ("point mass", "point mass + J2", "point mass + J2 + exponential drag")


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
    x12: np.ndarray  #: the same with the ESTIMATED target: the plan's start (m, m/s, ECI)
    status: str = "success"


@dataclasses.dataclass(frozen=True)
class Plan(_Frozen):
    """Stage 4: :func:`satgnc.guidance.plan` of the rendezvous problem (:func:`problem`) from the plan's
    start (the estimated relative state, or a rendezvous file's start).

    ``U`` (N, 3) N in the target CW frame, piecewise constant over ``dt`` (s); ``X`` (N+1, 6) the
    planned CW states (m, m/s; the nonlinear model's 12-states mapped by ``cw_relative_state``);
    ``Y`` (N, 3) the solver's sparse iterate in its scaled units (control scale ``scales[1]``);
    ``A``, ``B`` the discrete CW model of the plan in those scaled units (``scales`` = (state scale
    (6,) m, m/s; control scale (3,) N; time scale s)); ``delta_v`` = sum ||u_k||_1 dt / mass (m/s);
    ``model`` "linear" (CW, ADMM) or "nonlinear" (two-satellite, SCP); ``problem`` the
    :class:`satgnc.guidance.RendezvousProblem` that was solved."""

    status: str
    iterations: int
    U: np.ndarray
    X: np.ndarray
    Y: np.ndarray
    dt: float
    delta_v: float
    A: np.ndarray
    B: np.ndarray
    scales: tuple
    solve_time: float  #: s, wall
    model: str
    problem: object = dataclasses.field(repr=False, default=None)


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
class ClosedLoop(_Frozen):
    """Stage 5, closed loop: :func:`satgnc.guidance.mpc` on the same truth from the same TRUE start.

    What the MPC sees: the true 12-state of the truth at every re-plan (perfect relative navigation
    after the OD hand-off; the OD error enters only through the open-loop plan, not here). It re-plans
    on the nonlinear two-satellite model with the truth's own terms (J2 and drag) every
    ``replan_every`` intervals. ``X`` (N+1, 12) m, m/s ECI; ``X_cw`` (N+1, 6) CW; ``U`` (N, 3) N;
    ``miss_position`` (m), ``miss_velocity`` (m/s); ``delta_v`` (m/s); ``replans`` and the summed
    re-plan ``solve_time`` (s, thread CPU)."""

    status: str
    X: np.ndarray
    X_cw: np.ndarray
    U: np.ndarray
    miss_position: float
    miss_velocity: float
    delta_v: float
    replans: int
    replan_every: int
    solve_time: float
    tolerance: float


@dataclasses.dataclass(frozen=True)
class Checks(_Frozen):
    """Stage 6: controllability of the plan's discrete CW model and observability of the tracking
    geometry used (rows H_j Phi_j / sigma_j of the OD model at the estimate, state columns scaled by
    |r0| km and |v0| km/s so that they are unit-free)."""

    controllability: str  #: verdict of analysis.controllability
    controllability_rank: int
    controllability_sv: np.ndarray  #: singular values of [B, AB, ..] / the largest
    observability: str  #: verdict of analysis.observability (static map: A = I, C = O); "not run"
    observability_rank: int  #: 0 when the chain has no tracking
    observability_sv: np.ndarray  #: singular values of O / the largest (empty: no tracking)
    gramian_condition: float  #: of analysis.ltv_observability_gramian (scaled state); nan: no tracking
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
    """Every stage result of :func:`run` (None for a stage the chain did not run), the hand-off table
    and the wall time per stage (s)."""

    scenario: _scen.MissionScenario
    tracking: Tracking | None
    estimate: OrbitEstimate | None
    relative: RelativeState | None
    plan: Plan | None
    flight: Flight | None
    checks: Checks | None
    handoff: tuple
    timings: dict
    quick: bool
    closed_loop: ClosedLoop | None = None

    @property
    def statuses(self) -> dict:
        """Stage name -> status string, for the stages that ran."""
        named = {"tracking": self.tracking, "od": self.estimate, "relative": self.relative, "plan": self.plan,
                 "flight": self.flight, "closed_loop": self.closed_loop, "checks": self.checks}
        return {k: v.status for k, v in named.items() if v is not None}

    def handoff_markdown(self) -> str:
        """The hand-off table as Markdown."""
        rows = ["| stage | hands on | value | unit | frame |", "|---|---|---|---|---|"]
        rows += [f"| {h.stage} | {h.quantity} | {h.value} | {h.unit} | {h.frame} |" for h in self.handoff]
        return "\n".join(rows)


# ----------------------------------------------------------------------------- models
def _drag_term(sc: _scen.MissionScenario) -> ExponentialDrag:
    d = sc.drag
    return ExponentialDrag(rho0=d.rho0, h0=d.h0, scale_height=d.scale_height, cd=d.cd, area=d.area,
                           mass=d.mass, body_radius=od.EARTH_RADIUS,
                           omega=np.array([0.0, 0.0, od.EARTH_OMEGA]))


def _force_model(j2: bool, drag: bool, sc: _scen.MissionScenario) -> tuple[ForceModel, str]:
    """(satgnc.ForceModel, description): point mass (EARTH_MU, km^3/s^2) + J2 + the file's drag."""
    names = ["point mass"] + (["J2"] if j2 else []) + (["exponential drag"] if drag else [])
    fm = ForceModel(mu=_MU_KM, j2=J2Gravity(mu=_MU_KM) if j2 else None, drag=_drag_term(sc) if drag else None)
    return fm, " + ".join(names)


def truth_force_model(sc: _scen.MissionScenario) -> tuple[ForceModel, str]:
    """The orbit-level truth force model: J2 and drag as the scenario's ``[truth]`` says.

    Parameters
    ----------
    sc : MissionScenario
        The mission scenario (:func:`load`).

    Returns
    -------
    model : satgnc.ForceModel
        Point mass (+ J2, + exponential drag); km, km/s, s.
    description : str
        E.g. "point mass + J2 + exponential drag".

    Raises
    ------
    ValueError
        A scenario whose stage cannot run (the message names the key or the argument).

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()  # the packaged mission_leo.toml
    >>> fm, text = mission.truth_force_model(sc)
    >>> text
    'point mass + J2 + exponential drag'
    """
    return _force_model(sc.truth_j2, sc.drag is not None, sc)


def od_force_model(sc: _scen.MissionScenario) -> tuple[ForceModel, str]:
    """The OD force model: J2 and drag (the truth's atmosphere, known exactly) as ``[od]`` says.

    Parameters
    ----------
    sc : MissionScenario
        The mission scenario (:func:`load`).

    Returns
    -------
    model : satgnc.ForceModel
        km, km/s, s (point mass only with the Kepler propagator).
    description : str
        E.g. "point mass + J2".

    Raises
    ------
    ValueError
        A scenario whose stage cannot run (the message names the key or the argument).

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()  # the packaged mission_leo.toml
    >>> fm, text = mission.od_force_model(sc)
    >>> text.startswith('point mass')
    True
    """
    cvodes = sc.od_propagator == "cvodes"
    return _force_model(sc.od_j2 and cvodes, sc.od_drag and cvodes, sc)


def truth_params(sc: _scen.MissionScenario) -> _c.TwoSatelliteParams:
    """The two-satellite truth (SI) with the same mu, J2 and exponential atmosphere as the orbit truth.

    rho0 exp(-(h - h0)/H) = rho0 e^(h0/H) exp(-h/H), h = |r| - Earth radius.

    Parameters
    ----------
    sc : MissionScenario
        The mission scenario (:func:`load`).

    Returns
    -------
    TwoSatelliteParams
        mu (m^3/s^2), J2, density (kg/m^3) and decay (1/m), masses (kg), areas (m^2), Cd.

    Raises
    ------
    ValueError
        h0 / scale_height > 700 (the density scale overflows).

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()  # the packaged mission_leo.toml
    >>> p = mission.truth_params(sc)
    >>> p.j2_on, p.drag_on
    (True, True)
    """
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
    if sc.od_propagator == "kepler":
        return od.make_propagator("kepler", _MU_KM)
    return od.make_propagator("cvodes", force_model=od_force_model(sc)[0])


def _station(s: _scen.StationSpec, epoch: str | None) -> od.Station:
    if s.frame == "inertial":
        return od.station_inertial(s.position, od.EARTH_OMEGA if s.omega is None else s.omega)
    return od.station_geodetic(s.lat, s.lon, s.height, epoch)


def _six_point(sc: _scen.MissionScenario, tracking: Tracking) -> od.OdSolver:
    """The OD stage's solver for ``[od] method = "newton_six_point"``: Gao & Luo's Newton-Raphson on
    the six Doppler conditions (eqs. 11-18, the exact STM of the ``[od]`` propagator) of the tracking's
    six times of range (km) and range-rate (km/s) from its one station, weighted by the ``[tracking]``
    sigmas. It is :func:`satgnc.od.six_point_solver`, the solver of the paper's reproduction
    (``satgnc.papers.od_newton_raphson``), built from the mission's tracking.

    Raises ValueError when the tracking is not six times of range and range-rate from one station
    (e.g. the mask hid one)."""
    kinds = np.asarray(tracking.type)
    t = tracking.t[kinds == "range"]
    if len(tracking.stations) != 1 or t.size != 6 or not np.array_equal(t, tracking.t[kinds == "range_rate"]):
        raise ValueError(f"od: method 'newton_six_point' needs six times of range and range-rate from one "
                         f"station; the tracking has {t.size} ranges, "
                         f"{int(np.sum(kinds == 'range_rate'))} range-rates from {len(tracking.stations)} "
                         f"station(s) ({sc.path})")
    return od.six_point_solver(t, tracking.value[kinds == "range"], tracking.value[kinds == "range_rate"],
                               tracking.stations[0], "doppler", "newton", _od_propagator(sc), _MU_KM,
                               sigma_range=sc.sigma_range, sigma_range_rate=sc.sigma_range_rate)



def _residuals(sc: _scen.MissionScenario, tracking: Tracking, x0: np.ndarray) -> np.ndarray:
    """Predicted - observed (km, km/s) per observation of ``tracking`` from x0 on the OD model."""
    times = np.unique(tracking.t)
    states, _ = _od_propagator(sc).propagate(x0, list(times))
    k_of = {float(t): k for k, t in enumerate(times)}
    return np.array([od.predict(kind, states[k_of[float(t)]], tracking.stations[i].state(float(t)))[0] - v
                     for t, kind, v, i in zip(tracking.t, tracking.type, tracking.value, tracking.station)])


# ----------------------------------------------------------------------------- stages
def track(sc: _scen.MissionScenario, quick: bool = False) -> Tracking:
    """Stage 1: simulated tracking of the target by every station on the truth force model.

    :func:`satgnc.od.simulate` (point mass, J2 and drag as ``[truth]`` says; CVODES, rtol 1e-11),
    ordered by time then station.

    Parameters
    ----------
    sc : MissionScenario
        The mission scenario (:func:`load`).
    quick : bool, optional
        Keep every ``quick_thin``-th tracking time (default False).

    Returns
    -------
    Tracking
        t (s), type, value (km, km/s), sigma, station; the stations, the truth states (km, km/s, ECI).

    Raises
    ------
    ValueError
        Fewer than 6 observations above the mask, an orbit below the surface.

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()  # the packaged mission_leo.toml
    >>> tr = mission.track(sc, quick=True)
    >>> tr.t.size >= 6, tr.forces
    (True, 'point mass + J2 + exponential drag')
    """
    times = sc.times[:: sc.quick_thin] if quick else sc.times
    grid = np.union1d(np.r_[0.0, times], [] if sc.start is None else [sc.start])  # + the plan epoch
    fm, forces = truth_force_model(sc)
    stations = tuple(_station(s, sc.epoch) for s in sc.stations)
    kepler = sc.truth_propagator == "kepler"  # the analytic two-body truth (a paper's)
    truth_kw = dict(propagator="kepler", mu=_MU_KM) if kepler else dict(propagator="cvodes", force_model=fm)
    forces = forces + " (Kepler, analytic)" if kepler else forces
    try:
        obs = od.simulate(sc.x0, list(stations), times, types=sc.types, sigma_range=sc.sigma_range,
                          sigma_range_rate=sc.sigma_range_rate, elevation_mask_deg=sc.mask,
                          seed=sc.seed if sc.noise is not False else None, **truth_kw)
    except ValueError as e:
        if not str(e).startswith("elevation_mask_deg"):
            raise
        obs = None
    n = 0 if obs is None else len(obs)
    if n < 6:
        raise ValueError(f"tracking: {n} observations above the {sc.mask} deg mask "
                         f"({sc.path}); the OD needs at least 6 (hint: station positions or the arc)")
    prop = od.make_propagator("kepler", _MU_KM) if kepler else od.make_propagator("cvodes", force_model=fm)
    states, _ = prop.propagate(sc.x0, list(grid))
    order = np.lexsort((obs.station, obs.t))
    kinds = [str(k).split(".")[-1] for k in obs.type]
    return Tracking(
        t=np.asarray(obs.t)[order], type=tuple(kinds[k] for k in order),
        value=np.asarray(obs.value)[order], sigma=np.asarray(obs.sigma)[order],
        station=np.asarray(obs.station, dtype=int)[order], stations=stations,
        station_names=tuple(s.name for s in sc.stations), x0_true=sc.x0, truth_times=grid,
        truth_states=np.asarray(states), forces=forces,
    )


def estimate(sc: _scen.MissionScenario, tracking: Tracking) -> OrbitEstimate:
    """Stage 2: the orbit estimate, :func:`satgnc.od.solve` from the truth plus the file's guess offset.

    Parameters
    ----------
    sc : MissionScenario
        The mission scenario (:func:`load`).
    tracking : Tracking
        Stage 1's result.

    Returns
    -------
    OrbitEstimate
        status, x0 (km, km/s, ECI at the epoch), covariance, sigma, error vs the truth, residuals.

    Raises
    ------
    ValueError
        Bad tracking or settings (naming the argument).

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()  # the packaged mission_leo.toml
    >>> tr = mission.track(sc, quick=True)
    >>> est = mission.estimate(sc, tr)
    >>> est.status
    'converged'
    """
    guess = tracking.x0_true + sc.guess_offset
    if sc.od_method == "newton_six_point":
        r = _six_point(sc, tracking).solve(guess)
    else:
        r = od.solve(tracking.observations, list(tracking.stations), guess, method=sc.od_method,
                     propagator=_od_propagator(sc), mu=_MU_KM)
    x0 = np.asarray(r.x0, dtype=float)
    P = np.asarray(r.covariance, dtype=float)
    model = od_force_model(sc)[1]
    if sc.od_method == "newton_six_point":  # r's residuals are the six conditions': per observation here
        residuals = _residuals(sc, tracking, x0)
        normalized = residuals / tracking.sigma
    else:
        residuals = np.asarray(r.residuals, dtype=float).ravel()
        normalized = np.asarray(r.normalized, dtype=float).ravel()
    status = r.status if isinstance(r.status, str) else r.status.name  # enum today, a string after B
    return OrbitEstimate(status=status, iterations=int(r.iterations), x0=x0, covariance=P,
                         rank=int(r.rank), condition_number=float(r.condition_number),
                         error=x0 - tracking.x0_true, sigma=np.sqrt(np.diag(P)), guess=guess,
                         normalized=normalized, residuals=residuals, model=model)


def _x12(target_km: np.ndarray, chaser_km: np.ndarray) -> np.ndarray:
    """[r_t - r_c, r_t, v_t - v_c, v_t] (m, m/s) from target and chaser ECI states (km, km/s)."""
    t = np.asarray(target_km) * 1e3
    c = np.asarray(chaser_km) * 1e3
    return np.concatenate([t[:3] - c[:3], t[:3], t[3:] - c[3:], t[3:]])


def relative_state(sc: _scen.MissionScenario, tracking: Tracking, est: OrbitEstimate) -> RelativeState:
    """Stage 3: the chaser relative to the ESTIMATED target at the plan epoch.

    The chaser is known in ECI (the file's relative state about the TRUE target); the covariance is
    J Phi P0 Phi^T J^T (m^2, ...).

    Parameters
    ----------
    sc : MissionScenario
        The mission scenario (:func:`load`).
    tracking : Tracking
        Stage 1's result.
    est : OrbitEstimate
        Stage 2's result.

    Returns
    -------
    RelativeState
        x (6,) m, m/s in the target's CW frame (y radial, z normal), its covariance and error,
        the CW orbit radius (m) and mean motion (rad/s).

    Raises
    ------
    ValueError
        A propagation that fails.

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()  # the packaged mission_leo.toml
    >>> tr = mission.track(sc, quick=True)
    >>> est = mission.estimate(sc, tr)
    >>> rel = mission.relative_state(sc, tr, est)
    >>> rel.x.shape, rel.covariance.shape
    ((6,), (6, 6))
    """
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
                         mean_motion=math.sqrt(_MU_M / radius**3), x12_true=x12_true,
                         x12=_x12(target, chaser))


def flight_truth(sc: _scen.MissionScenario) -> _c.TwoSatelliteParams:
    """The flight's truth (SI): :func:`truth_params` of the mission file, or the ``[truth]`` of its
    rendezvous scenario file (``[rendezvous] scenario``).

    Parameters
    ----------
    sc : MissionScenario
        The mission scenario (:func:`load`).

    Returns
    -------
    TwoSatelliteParams
        SI (m, m/s, kg, m^2).

    Raises
    ------
    ValueError
        As :func:`truth_params`.

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()  # the packaged mission_leo.toml
    >>> mission.flight_truth(sc).j2_on
    True
    """
    return truth_params(sc) if sc.rendezvous is None else _rv.truth_params(sc.rendezvous)


def problem(sc: _scen.MissionScenario, rel: RelativeState | None) -> RendezvousProblem:
    """The :class:`satgnc.guidance.RendezvousProblem` of stage 4.

    From the mission file: the CW orbit of the ESTIMATED target (radius |r| at the plan epoch), the
    estimated relative state ``rel.x`` and its 12-state ``rel.x12`` (the nonlinear model's start), the
    flight truth as the nonlinear planner. From ``[rendezvous] scenario``:
    :func:`satgnc.scenarios.rendezvous.problem` of the file's case and the mission's ``model``, with the
    mission's ``method`` (linear discretization) when it gives one.

    Parameters
    ----------
    sc : MissionScenario
        The mission scenario (:func:`load`).
    rel : RelativeState or None
        Stage 3's result (None with ``[rendezvous] scenario``).

    Returns
    -------
    RendezvousProblem
        SI: m, m/s, N, kg, s.

    Raises
    ------
    ValueError
        ``rel`` None without ``[rendezvous] scenario``.

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()  # the packaged mission_leo.toml
    >>> tr = mission.track(sc, quick=True)
    >>> est = mission.estimate(sc, tr)
    >>> rel = mission.relative_state(sc, tr, est)
    >>> pb = mission.problem(sc, rel)
    >>> pb.mass > 0
    True
    """
    if sc.rendezvous is not None:
        pb = _rv.problem(sc.rendezvous, sc.case, sc.model)
        if pb.linear_discretization != sc.method:
            pb = dataclasses.replace(pb, linear_discretization=sc.method)
        return pb
    if rel is None:
        raise ValueError("rel: the plan needs the relative state of stage 3 (or [rendezvous] scenario)")
    return RendezvousProblem(
        mu=_MU_M, radius=rel.radius, mass=sc.mass, x0=rel.x, tf=sc.tf, horizon=sc.knots - 1, alpha=sc.alpha,
        Qf=sc.Qf, u_max=sc.u_max if sc.box else None, terminal_equality=sc.terminal_equality, x0_eci=rel.x12,
        planner=truth_params(sc), linear_discretization=sc.method)


def plan(sc: _scen.MissionScenario, rel: RelativeState | None) -> Plan:
    """Stage 4: :func:`satgnc.guidance.plan` of :func:`problem` on the file's ``model``.

    "linear": the CW optimum by ADMM; "nonlinear": SCP on the two-satellite model; in the library's
    transcription (its scaling of states and controls, the weights ``alpha`` and ``Qf`` in those units).

    Parameters
    ----------
    sc : MissionScenario
        The mission scenario (:func:`load`).
    rel : RelativeState or None
        Stage 3's result (None with ``[rendezvous] scenario``).

    Returns
    -------
    Plan
        status, U (N, 3) forces (N), X (N+1, 6) CW states (m, m/s), dt (s), delta_v (m/s), the
        scaled discrete (A, B).

    Raises
    ------
    ValueError
        As :func:`problem`.

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()  # the packaged mission_leo.toml
    >>> tr = mission.track(sc, quick=True)
    >>> est = mission.estimate(sc, tr)
    >>> rel = mission.relative_state(sc, tr, est)
    >>> pl = mission.plan(sc, rel)
    >>> pl.status
    'solved'
    """
    pb = problem(sc, rel)
    t0 = time.perf_counter()
    r = guidance.plan(pb, sc.model)
    wall = time.perf_counter() - t0
    tr = transcribe(pb)
    ss = np.asarray(tr.scaling.state_scale)
    s6 = np.r_[ss[0:3], ss[6:9]]
    su = np.asarray(tr.scaling.control_scale)
    # the discrete CW pair of the plan in the solver's scaled units (guidance.planning.solve_linear_cw's)
    n = math.sqrt(pb.mu / float(np.linalg.norm(tr.x0_si[3:6])) ** 3)
    Ad, Bd = _c.cw_discretize(n, pb.mass, tr.dt, pb.linear_discretization)
    A = np.asarray(Ad) * s6[None, :] / s6[:, None]
    B = np.asarray(Bd) * su[None, :] / s6[:, None]
    if r.model == "linear":
        X = np.asarray(r.X)
        Y = np.asarray(r.info.raw["Y"]).T  # guidance.AdmmInfo: the solver's scaled plan, nu x N
    else:
        X = _cw_states(r.X)
        Y = np.asarray(r.U) / su[None, :]
    dv = float(np.abs(r.U).sum() * r.dt / pb.mass)
    return Plan(status=r.status, iterations=int(r.iterations), U=np.asarray(r.U), X=X, Y=Y, dt=r.dt,
                delta_v=dv,
                A=A, B=B, scales=(s6, su, float(tr.scaling.time_scale)), solve_time=wall, model=r.model,
                problem=pb)


def _cw_states(X) -> np.ndarray:
    """The CW relative states (N+1, 6; m, m/s, target frame) of 12-states X (N+1, 12)."""
    return np.array([np.asarray(_c.cw_relative_state(x)) for x in X])


def _miss_status(sc: _scen.MissionScenario, miss: float) -> str:
    """A flight's status: ``"success"`` when the terminal miss (m) is within the scenario's tolerance."""
    return "success" if miss <= sc.miss_tolerance else "miss_above_tolerance"


def _truth_name(p) -> str:
    terms = ["point mass"] + (["J2"] if p.j2_on else []) + (["exponential drag"] if p.drag_on else [])
    return " + ".join(terms)


def _start_true(rel: RelativeState | None, pl: Plan) -> np.ndarray:
    """The flight's TRUE 12-state (m, m/s, ECI): the truth at the plan epoch, or the rendezvous file's
    start (no OD: the plan's start is the truth)."""
    return np.asarray(rel.x12_true) if rel is not None else pl.problem.state_eci()


def fly(sc: _scen.MissionScenario, rel: RelativeState | None, pl: Plan) -> Flight:
    """Stage 5: :func:`satgnc.guidance.fly` (CVODES) of the plan, open loop, from the TRUE 12-state.

    Parameters
    ----------
    sc : MissionScenario
        The mission scenario (:func:`load`).
    rel : RelativeState or None
        Stage 3's result (None: the rendezvous file's start is the truth).
    pl : Plan
        Stage 4's result.

    Returns
    -------
    Flight
        status ("success" when the miss is within the tolerance), X (N+1, 12) m, m/s ECI, the
        miss (m, m/s) and the OD's predicted 3-sigma miss (m).

    Raises
    ------
    satgnc.PropagationError
        A body reaching the Earth's surface.

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()  # the packaged mission_leo.toml
    >>> tr = mission.track(sc, quick=True)
    >>> est = mission.estimate(sc, tr)
    >>> rel = mission.relative_state(sc, tr, est)
    >>> pl = mission.plan(sc, rel)
    >>> fl = mission.fly(sc, rel, pl)
    >>> fl.X.shape[1], fl.miss_position >= 0.0
    (12, True)
    """
    p = flight_truth(sc)
    f = guidance.fly(p, _start_true(rel, pl), pl.U, pl.dt)
    X = np.asarray(f.X)
    X_cw = _cw_states(X)
    pred = 0.0
    if rel is not None:
        Phi = np.asarray(cw_stm(rel.mean_motion, sc.tf))
        Pf = Phi @ rel.covariance @ Phi.T
        pred = 3.0 * math.sqrt(max(float(np.linalg.eigvalsh(Pf[:3, :3])[-1]), 0.0))
    miss, vmiss = f.miss
    return Flight(status=_miss_status(sc, miss), X=X, X_cw=X_cw,
                  t=np.asarray(f.t), miss_position=float(miss), miss_velocity=float(vmiss),
                  predicted_3sigma=pred, tolerance=sc.miss_tolerance, truth=_truth_name(p))


def fly_closed_loop(sc: _scen.MissionScenario, rel: RelativeState | None, pl: Plan,
                    replan_every: int = 3) -> ClosedLoop:
    """Stage 5, closed loop: :func:`satgnc.guidance.mpc` of the plan's problem from the TRUE 12-state.

    Re-plans every ``replan_every`` intervals from the true state (what the MPC sees, see
    :class:`ClosedLoop`) on the nonlinear model with the truth's terms (J2 and drag).

    Parameters
    ----------
    sc : MissionScenario
        The mission scenario (:func:`load`).
    rel : RelativeState or None
        Stage 3's result.
    pl : Plan
        Stage 4's result.
    replan_every : int, optional
        Intervals between re-plans (default 3).

    Returns
    -------
    ClosedLoop
        X (N+1, 12) m, m/s ECI, U (N, 3) N, the miss (m, m/s), delta_v (m/s), replans, solve_time (s).

    Raises
    ------
    ValueError
        A bad ``replan_every``.
    satgnc.PropagationError
        A body reaching the Earth's surface.

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()  # the packaged mission_leo.toml
    >>> tr = mission.track(sc, quick=True)
    >>> est = mission.estimate(sc, tr)
    >>> rel = mission.relative_state(sc, tr, est)
    >>> pl = mission.plan(sc, rel)
    >>> cl = mission.fly_closed_loop(sc, rel, pl, replan_every=10)
    >>> cl.U.shape == pl.U.shape
    True
    """
    p = flight_truth(sc)
    pb = dataclasses.replace(pl.problem, x0_eci=_start_true(rel, pl), planner=p)
    m = guidance.mpc(pb, truth=p, replan_every=replan_every)
    X = np.asarray(m.X)
    X_cw = _cw_states(X)
    miss, vmiss = m.miss
    return ClosedLoop(status=_miss_status(sc, miss), X=X,
                      X_cw=X_cw, U=np.asarray(m.U), miss_position=float(miss), miss_velocity=float(vmiss),
                      delta_v=float(np.abs(m.U).sum() * pl.dt / pb.mass), replans=int(len(m.iterations)) + 1,
                      replan_every=replan_every, solve_time=float(np.sum(m.solve_times)),
                      tolerance=sc.miss_tolerance)


def _singular(M: np.ndarray) -> np.ndarray:
    s = np.linalg.svd(M, compute_uv=False)
    return s / s[0]


def check(sc: _scen.MissionScenario, tracking: Tracking | None, est: OrbitEstimate | None,
          pl: Plan) -> Checks:
    """Stage 6: controllability of the plan's (A, B) and observability of the tracking geometry.

    The staircase test of the plan's scaled (A, B); the whitened, scaled sensitivity
    O = [H_j Phi_j D / sigma_j] of the OD model at the estimate, tested as the static pair (I, O)
    (rank O = 6 <=> observable) and as the LTV Gramian.

    Parameters
    ----------
    sc : MissionScenario
        The mission scenario (:func:`load`).
    tracking : Tracking or None
        Stage 1's result (None: observability not run).
    est : OrbitEstimate or None
        Stage 2's result.
    pl : Plan
        Stage 4's result.

    Returns
    -------
    Checks
        Verdicts, ranks and normalized singular values (unit-free), the Gramian condition number.

    Raises
    ------
    ValueError
        A propagation that fails.

    Examples
    --------
    >>> from satgnc import mission
    >>> sc = mission.load()  # the packaged mission_leo.toml
    >>> tr = mission.track(sc, quick=True)
    >>> est = mission.estimate(sc, tr)
    >>> rel = mission.relative_state(sc, tr, est)
    >>> pl = mission.plan(sc, rel)
    >>> ck = mission.check(sc, tr, est, pl)
    >>> ck.controllability_rank, ck.observability_rank
    (6, 6)
    """
    ctrl = analysis.controllability(pl.A, pl.B)
    K = analysis.kalman_matrix(pl.A, B=pl.B)
    if tracking is None or est is None:  # a chain that starts at the plan has no tracking to check
        return Checks(controllability=ctrl.verdict, controllability_rank=int(ctrl.rank),
                      controllability_sv=_singular(K), observability="not run", observability_rank=0,
                      observability_sv=np.zeros(0), gramian_condition=float("nan"), od_rank=0,
                      od_condition=float("nan"))
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


def _handoff(sc, tr: Tracking | None, est: OrbitEstimate | None, rel: RelativeState | None, pl: Plan | None,
             fl: Flight | None, cl: ClosedLoop | None, ck: Checks | None) -> tuple:
    def v(a, fmt=".4g"):
        return "[" + ", ".join(format(float(x), fmt) for x in a) + "]"

    rows = []
    if tr is not None:
        n_st = len(set(tr.station.tolist()))
        rows += [
            HandOff("1 tracking", f"{tr.t.size} observations ({', '.join(sc.types)}) from {n_st} stations, "
                    f"t in [{tr.t[0]:.0f}, {tr.t[-1]:.0f}]",
                    f"sigma {sc.sigma_range:g} / {sc.sigma_range_rate:g}",
                    "km / km/s", "station to target (topocentric line of sight)"),
            HandOff("1 tracking", "truth force model of the observations", tr.forces, "-", "ECI"),
        ]
    if est is not None:
        rows += [
            HandOff("2 OD", f"x0 estimate ({est.status}, {est.iterations} iterations, rank {est.rank}, "
                    f"cond {est.condition_number:.3g})", v(est.x0, ".6f"), "km, km/s", "ECI at the epoch"),
            HandOff("2 OD", "OD force model", est.model, "-", "ECI"),
            HandOff("2 OD", "1-sigma of x0 (sqrt diag P0)", v(est.sigma, ".3g"), "km, km/s",
                    "ECI at the epoch"),
            HandOff("2 OD", "x0 error vs truth, in sigmas", v(est.error / est.sigma, ".2f"), "-",
                    "ECI at the epoch"),
        ]
    if rel is not None:
        sr = np.sqrt(np.linalg.eigvalsh(rel.covariance[:3, :3])[-1])
        sv = np.sqrt(np.linalg.eigvalsh(rel.covariance[3:, 3:])[-1])
        rows += [
            HandOff("3 relative", f"chaser relative state at t = {rel.t:.0f} s", v(rel.x, ".4f"), "m, m/s",
                    "target CW (y radial, z normal)"),
            HandOff("3 relative", "1-sigma (largest axis) of position / velocity", f"{sr:.3g} / {sv:.3g}",
                    "m / m/s", "target CW"),
            HandOff("3 relative", "CW model: orbit radius, mean motion",
                    f"{rel.radius:.1f}, {rel.mean_motion:.6e}",
                    "m, rad/s", "estimated target orbit"),
        ]
    if pl is not None:
        src = (f"{sc.rendezvous.path.name} case {sc.case}" if sc.rendezvous is not None
               else "the estimated relative state")
        rows += [
            HandOff("4 plan", f"plan start ({src})", v(pl.X[0], ".4f"), "m, m/s", "target CW"),
            HandOff("4 plan", f"U ({pl.U.shape[0]} x 3) over dt = {pl.dt:.3f} s (guidance.plan, {pl.model}, "
                    f"{pl.status}, {pl.iterations} iterations)",
                    f"delta-v {pl.delta_v:.4f}, max abs(u) {np.max(np.abs(pl.U)):.3e}", "m/s, N",
                    "target CW"),
        ]
    if fl is not None:
        rows.append(HandOff("5 flight", f"open-loop miss at tf = {sc.tf:g} s on {fl.truth}",
                            f"{fl.miss_position:.2f} m, {fl.miss_velocity:.4f} m/s (tolerance "
                            f"{fl.tolerance:g} m, OD 3-sigma {fl.predicted_3sigma:.2f} m)", "m, m/s",
                            "ECI relative (d = r_t - r_c)"))
    if cl is not None:
        rows.append(HandOff("5 flight", f"closed-loop miss (guidance.mpc, re-plan every {cl.replan_every} "
                            "intervals from the true state)",
                            f"{cl.miss_position:.2f} m, {cl.miss_velocity:.4f} m/s, delta-v "
                            f"{cl.delta_v:.4f} m/s",
                            "m, m/s", "ECI relative (d = r_t - r_c)"))
    if ck is not None:
        rows.append(HandOff("6 checks", "controllability of the plan's discrete CW (A, B)",
                            f"{ck.controllability} (rank {ck.controllability_rank})", "-", "scaled CW"))
        if ck.observability != "not run":
            rows.append(HandOff("6 checks", "observability of the tracking geometry (OD model)",
                                f"{ck.observability} (rank {ck.observability_rank}, Gramian cond "
                                f"{ck.gramian_condition:.3g})", "-",
                                "ECI, state scaled by norm(r0), norm(v0)"))
    return tuple(rows)


def run(scenario=None, quick: bool = False, closed_loop: bool | None = None) -> MissionRun:
    """Run the scenario's stages (``first_stage`` .. ``last_stage``, all six by default).

    Parameters
    ----------
    scenario : str, pathlib.Path, MissionScenario or None, optional
        A path, a loaded :class:`MissionScenario`, or None for the packaged ``mission_leo.toml``.
    quick : bool, optional
        Keep every ``quick_thin``-th tracking time (default False).
    closed_loop : bool or None, optional
        Also fly :func:`fly_closed_loop` after the open-loop flight (default: the file's
        ``[rendezvous] closed_loop``).

    Returns
    -------
    MissionRun
        Every stage's result (None for stages not run), the hand-off table (units and frames per
        row) and the wall time per stage (s).

    Raises
    ------
    MissionError
        (a ValueError) the OD does not converge or the plan is not solved: the mission stops.
    satgnc.FileFormatError
        A bad scenario file (file, line and key named).
    TypeError
        ``scenario``, ``quick`` or ``closed_loop`` of another type.

    Examples
    --------
    >>> from satgnc import mission
    >>> r = mission.run(quick=True, closed_loop=False)
    >>> r.estimate.status, r.plan.status
    ('converged', 'solved')
    """
    if isinstance(scenario, _scen.MissionScenario):
        sc = scenario
    elif scenario is None or isinstance(scenario, (str, pathlib.Path)):
        sc = _scen.load(scenario, "scenario")
    else:
        raise TypeError(f"scenario: must be a path, a MissionScenario or None, got {type(scenario).__name__}")
    if not isinstance(quick, bool):
        raise TypeError(f"quick: must be true or false (a bool), got {type(quick).__name__}")
    if closed_loop is not None and not isinstance(closed_loop, bool):
        raise TypeError(f"closed_loop: must be None, true or false (a bool), got "
                        f"{type(closed_loop).__name__}")
    closed = bool(sc.closed_loop) if closed_loop is None else closed_loop
    stages = sc.stages
    timings: dict = {}
    out: dict = dict.fromkeys(("tr", "est", "rel", "pl", "fl", "cl", "ck"))

    def timed(name, f, *args):
        t0 = time.perf_counter()
        r = f(*args)
        timings[name] = time.perf_counter() - t0
        return r

    if "track" in stages:
        out["tr"] = timed("tracking", track, sc, quick)
    if "estimate" in stages:
        out["est"] = est = timed("od", estimate, sc, out["tr"])
        if est.status != "converged":
            raise MissionError(f"od: the estimate did not converge (status {est.status}); the mission stops")
    if "relative_state" in stages:
        out["rel"] = timed("relative", relative_state, sc, out["tr"], out["est"])
    if "plan" in stages:
        out["pl"] = pl = timed("plan", plan, sc, out["rel"])
        if pl.status != "solved":
            raise MissionError(f"plan: the L1 plan is not solved (status {pl.status}); the mission stops")
    if "fly" in stages:
        out["fl"] = timed("flight", fly, sc, out["rel"], out["pl"])
        if closed:
            out["cl"] = timed("closed_loop", fly_closed_loop, sc, out["rel"], out["pl"])
    if "check" in stages:
        out["ck"] = timed("checks", check, sc, out["tr"], out["est"], out["pl"])
    o = out
    return MissionRun(scenario=sc, tracking=o["tr"], estimate=o["est"], relative=o["rel"], plan=o["pl"],
                      flight=o["fl"], checks=o["ck"], closed_loop=o["cl"],
                      handoff=_handoff(sc, o["tr"], o["est"], o["rel"], o["pl"], o["fl"], o["cl"], o["ck"]),
                      timings=timings, quick=quick)
