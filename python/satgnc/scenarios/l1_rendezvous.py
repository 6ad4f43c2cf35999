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

from .._validate import as_bool
from . import rendezvous as _rv

DEFAULT = _rv.DEFAULT


# The strict schema is the one rendezvous schema (scenarios/rendezvous.py), read by both models; this
# module reads the linear model's part of it.
_TOP = _rv._TOP
_SECTIONS = _rv.SECTIONS
_OPTIONAL_SECTIONS = _rv.OPTIONAL_SECTIONS
_CASE = _rv.CASE


def _read(path: pathlib.Path, name: str = "path"):
    """(path, top, checked sections, cases) of a scenario file; FileFormatError on any bad entry.
    ``name`` is the caller's argument in errors about the path itself (``path``, the CLI's scenario).
    The cases hold the linear model's keys (their ``[cases.<name>.nonlinear]`` tables are checked and
    left out)."""
    p, _, top, secs, cases = _rv.read(path, name)
    cases = {n: {k: v for k, v in c.items() if k != "nonlinear"} for n, c in cases.items()}
    return p, top, secs, cases


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
    """Read a scenario TOML (default: the packaged Table 1 scenario).

    The file is checked against the strict rendezvous schema (:mod:`satgnc.scenarios.rendezvous`:
    sections [orbit], [chaser], [initial_state], [horizon], [cost], optional [discretization],
    [release], [planner], [truth], and one or more [cases.<name>] with optional
    [cases.<name>.nonlinear]): a missing, unknown or mistyped key is a :class:`satgnc.FileFormatError`
    (a ``ValueError``) naming the file, the line, the key and its section. A missing file is
    ``FileNotFoundError``. The returned :class:`Scenario` holds the linear model's part."""
    return _load(path, "path")


def _load(path, name: str) -> Scenario:
    p, _, s, cases = _read(DEFAULT if path is None else path, name)
    # Cases keep only the keys the file gave, plus the defaults of box and terminal_equality.
    cases = {n: {k: v for k, v in c.items() if v is not None} for n, c in cases.items()}
    return Scenario(
        mu=s["orbit"]["mu"], radius=s["orbit"]["radius"], mass=s["chaser"]["mass"],
        p0=np.array(s["initial_state"]["position"]), v0=np.array(s["initial_state"]["velocity"]),
        tf=s["horizon"]["tf"], knots=s["horizon"]["knots"], alpha=s["cost"]["alpha"], Qf=s["cost"]["Qf"],
        u_max=s["cost"]["u_max"], method=s["discretization"]["method"], cases=cases,
    )


def linear_problem(sc: Scenario, case: str = "unconstrained", method: str | None = None,
                   implementation_weights: bool = True) -> dict:
    """Keyword arguments for :class:`satgnc.guidance.L1Solver` in scaled units.

    ``implementation_weights``: terminal weight Qf / dt_scaled (what the published code converges to);
    False gives the paper's eq. (34) weight Qf."""
    from ..guidance import cw_discretize

    if not isinstance(sc, Scenario):
        raise TypeError(f"sc: must be a Scenario (see load()), got {type(sc).__name__}")
    if not isinstance(case, str):
        raise TypeError(f"case: must be a case name (str), got {type(case).__name__}")
    if case not in sc.cases:
        raise ValueError(f"case: unknown {case!r}; choose from {sorted(sc.cases)}")
    if method is not None and not isinstance(method, str):
        raise TypeError(f"method: must be None or a discretization name (str), got {type(method).__name__}")
    # implementation_weights="false" or 1j was read as True
    implementation_weights = as_bool(implementation_weights, "implementation_weights")
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
    if not isinstance(sc, Scenario):
        raise TypeError(f"sc: must be a Scenario (see load()), got {type(sc).__name__}")
    if case not in sc.cases:  # was a bare KeyError
        raise ValueError(f"case: unknown {case!r}; choose from {sorted(sc.cases)}")
    c = sc.cases[case]
    return dict(rho=float(c["rho"]), paper_eps=float(c["eps"]), stopping="paper", relaxation=1.0,
                adaptive_rho=False, paper_multiplier_rescale=True, max_iterations=100000)
