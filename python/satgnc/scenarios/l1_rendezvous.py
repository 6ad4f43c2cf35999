"""The linear L1 rendezvous scenario (l1_admm_rendezvous.md, Table 1) as data, and the problem builder.

The published implementation scales lengths by |p0|, speeds by |v0|, time by |p0|/|v0| and forces by
mass |p0| / t_ref^2 (l1_scenario.md: 9686.13 m, 3.6215 m/s, 2674.6 s, 6.2286e-3 N), applies
alpha = 1 and Qf = 1000 I to scaled quantities, and multiplies the ADMM penalty terms by dt inside
the LQR step. The last is the same as an unweighted penalty with terminal weight Qf / dt, which is
the problem the implementation's iterates converge to; :func:`linear_problem` builds exactly that.
"""

from __future__ import annotations

import dataclasses
import pathlib

import numpy as np

DEFAULT = pathlib.Path(__file__).with_name("l1_rendezvous.toml")


def _load_toml(path: pathlib.Path) -> dict:
    try:
        import tomllib  # Python >= 3.11
    except ModuleNotFoundError:  # pragma: no cover - Python 3.9/3.10
        try:
            import tomli as tomllib
        except ModuleNotFoundError as e:
            raise ModuleNotFoundError("reading TOML on Python < 3.11 needs the 'tomli' package") from e
    with open(path, "rb") as f:
        return tomllib.load(f)


@dataclasses.dataclass
class Scenario:
    """Physical scenario (SI) and the implementation's scaling units."""

    mu: float
    radius: float
    mass: float
    p0: np.ndarray
    v0: np.ndarray
    tf: float
    knots: int
    alpha: float
    Qf: float
    u_max: float
    method: str
    cases: dict

    @property
    def n(self) -> float:
        """Mean motion (rad/s)."""
        return float(np.sqrt(self.mu / self.radius**3))

    @property
    def horizon(self) -> int:
        return self.knots - 1

    @property
    def dt(self) -> float:
        return self.tf / self.horizon

    @property
    def l_ref(self) -> float:
        return float(np.linalg.norm(self.p0))

    @property
    def v_ref(self) -> float:
        return float(np.linalg.norm(self.v0))

    @property
    def t_ref(self) -> float:
        return self.l_ref / self.v_ref

    @property
    def u_ref(self) -> float:
        return self.l_ref / self.t_ref**2 * self.mass

    def to_si(self, X: np.ndarray | None = None, U: np.ndarray | None = None):
        """Scaled states (.., 6) -> m, m/s; scaled controls -> N."""
        out = []
        if X is not None:
            out.append(np.asarray(X) * np.r_[[self.l_ref] * 3, [self.v_ref] * 3])
        if U is not None:
            out.append(np.asarray(U) * self.u_ref)
        return out[0] if len(out) == 1 else tuple(out)


def load(path: str | pathlib.Path | None = None) -> Scenario:
    """Read a scenario TOML (default: the packaged Table 1 scenario). Raises ValueError on bad data."""
    path = DEFAULT if path is None else pathlib.Path(path)
    if not path.exists():
        raise FileNotFoundError(f"scenario: no such file {path}")
    d = _load_toml(path)
    try:
        sc = Scenario(mu=float(d["orbit"]["mu"]), radius=float(d["orbit"]["radius"]),
                      mass=float(d["chaser"]["mass"]),
                      p0=np.array(d["initial_state"]["position"], float),
                      v0=np.array(d["initial_state"]["velocity"], float),
                      tf=float(d["horizon"]["tf"]), knots=int(d["horizon"]["knots"]),
                      alpha=float(d["cost"]["alpha"]), Qf=float(d["cost"]["Qf"]),
                      u_max=float(d["cost"]["u_max"]),
                      method=str(d.get("discretization", {}).get("method", "midpoint")),
                      cases=dict(d.get("cases", {})))
    except KeyError as e:
        raise ValueError(f"scenario: missing key {e} in {path}") from None
    for name, val in (("orbit.mu", sc.mu), ("orbit.radius", sc.radius), ("chaser.mass", sc.mass),
                      ("horizon.tf", sc.tf), ("cost.u_max", sc.u_max)):
        if not np.isfinite(val) or val <= 0:
            raise ValueError(f"scenario: {name} must be finite and > 0, got {val}")
    if sc.p0.shape != (3,) or sc.v0.shape != (3,):
        raise ValueError("scenario: initial_state position and velocity need 3 entries each")
    if sc.knots < 2:
        raise ValueError("scenario: horizon.knots must be >= 2")
    return sc


def linear_problem(sc: Scenario, case: str = "unconstrained", method: str | None = None,
                   implementation_weights: bool = True) -> dict:
    """Keyword arguments for :class:`satgnc.guidance.L1Solver` in scaled units.

    ``implementation_weights``: terminal weight Qf / dt_scaled (what the published code converges to);
    False gives the paper's eq. (34) weight Qf."""
    from ..guidance import cw_discretize

    if case not in sc.cases:
        raise ValueError(f"case: unknown {case!r}; choose from {sorted(sc.cases)}")
    c = sc.cases[case]
    dt_s = sc.dt / sc.t_ref
    Ad, Bd = cw_discretize(sc.n * sc.t_ref, 1.0, dt_s, method or sc.method)
    x0 = np.r_[sc.p0 / sc.l_ref, sc.v0 / sc.v_ref]
    qf = sc.Qf / dt_s if implementation_weights else sc.Qf
    kw = dict(A=Ad, B=Bd, x0=x0, horizon=sc.horizon, xf=np.zeros(6), Qf=qf * np.eye(6),
              l1_weights=sc.alpha * np.ones(3), terminal_equality=bool(c.get("terminal_equality", False)))
    if c.get("box", False):
        ub = sc.u_max / sc.u_ref
        kw["u_lower"] = -ub * np.ones(3)
        kw["u_upper"] = ub * np.ones(3)
    return kw


def paper_settings(sc: Scenario, case: str) -> dict:
    """The implementation's ADMM settings for a case: fixed rho, no relaxation, its stopping rule
    and multiplier rescaling."""
    c = sc.cases[case]
    return dict(rho=float(c["rho"]), paper_eps=float(c["eps"]), stopping="paper", relaxation=1.0,
                adaptive_rho=False, paper_multiplier_rescale=True, max_iterations=100000)
