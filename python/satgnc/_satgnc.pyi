# Type stubs for the compiled module satgnc._satgnc. Each room appends its own section.
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

__version__: str

# ---------------------------------------------------------------- dynamics (propagation room)
EARTH_MU: float
EARTH_RADIUS: float
EARTH_J2: float
EARTH_OMEGA: float

class J2Gravity:
    mu: float
    j2: float
    radius: float
    def __init__(self, mu: float = ..., j2: float = ..., radius: float = ...) -> None: ...

class ExponentialDrag:
    rho0: float
    h0: float
    scale_height: float
    cd: float
    area: float
    mass: float
    body_radius: float
    omega: npt.NDArray[np.float64]
    def __init__(
        self,
        rho0: float,
        h0: float,
        scale_height: float,
        cd: float = 2.2,
        area: float = 1.0,
        mass: float = 1.0,
        body_radius: float = ...,
        omega: npt.ArrayLike = ...,
    ) -> None: ...
    def density(self, radius: float) -> float: ...

class ForceModel:
    mu: float
    j2: J2Gravity | None
    drag: ExponentialDrag | None
    def __init__(
        self, mu: float = ..., j2: J2Gravity | None = None, drag: ExponentialDrag | None = None
    ) -> None: ...
    def validate(self) -> None: ...
    @property
    def conservative(self) -> bool: ...
    def acceleration(self, r: npt.ArrayLike, v: npt.ArrayLike, t: float = 0.0) -> npt.NDArray[np.float64]: ...
    def acceleration_jacobians(
        self, r: npt.ArrayLike, v: npt.ArrayLike, t: float = 0.0
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    def potential(self, r: npt.ArrayLike) -> float: ...
    def energy(self, r: npt.ArrayLike, v: npt.ArrayLike) -> float: ...

# ---------------------------------------------------------------- propagation
class PropagationStats:
    steps: int
    rhs_evals: int
    error_test_fails: int
    nonlin_iters: int
    nonlin_conv_fails: int
    lin_setups: int
    last_step: float

class Trajectory:
    @property
    def times(self) -> npt.NDArray[np.float64]: ...
    @property
    def states(self) -> npt.NDArray[np.float64]: ...
    @property
    def stms(self) -> npt.NDArray[np.float64] | None: ...
    @property
    def stats(self) -> dict[str, int | float]: ...
    @property
    def status(self) -> str: ...
    @property
    def success(self) -> bool: ...
    @property
    def t_reached(self) -> float: ...
    @property
    def message(self) -> str: ...
    def __len__(self) -> int: ...

def status_message(status: str) -> str: ...

class CvodesPropagator:
    def __init__(
        self,
        force_model: ForceModel,
        method: str = "adams",
        rtol: float = 1e-10,
        atol: float | Sequence[float] = 1e-12,
        with_stm: bool = True,
        max_steps: int = 500000,
        max_order: int = 0,
        corrector: str = "auto",
        vector: str = "satgnc",
        initial_step: float = 0.0,
        max_step: float = 0.0,
        surface_radius: float = 0.0,
    ) -> None: ...
    def propagate(self, x0: npt.ArrayLike, t0: float, times: Sequence[float]) -> Trajectory: ...

# ---------------------------------------------------------------- propagation_analytic (kepler room)
def propagate_kepler(
    x0: npt.ArrayLike, t0: float, times: Sequence[float], mu: float, with_stm: bool = True,
    surface_radius: float = 0.0,
) -> Trajectory: ...
def propagate_dop853(
    x0: npt.ArrayLike,
    t0: float,
    times: Sequence[float],
    force_model: ForceModel,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    with_stm: bool = True,
    max_steps: int = 100000,
    surface_radius: float = 0.0,
) -> Trajectory: ...
