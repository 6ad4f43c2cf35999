"""Docstrings with units for the compiled classes' properties, and summarising reprs, attached at
import (the classes come from the extension; ``help()``, Sphinx and the IDE read these).

Each entry replaces a property's empty docstring only (a docstring the binding has is kept); the class
docstrings below replace the bindings' (they add the units).
"""

from __future__ import annotations

from typing import Any

from . import _satgnc as _c

_PROPS: dict[str, dict[str, str]] = {
    "OdResult": {
        "info": "The solver's run record (OdInfo: status, iterations, residuals, solve time).",
        "status": "OdStatus: converged only when the convergence test holds at x0 with rank 6 (docs/od.md).",
        "message": "One line saying why the solve stopped.",
        "iterations": "Iterations taken (Newton, Gauss-Newton or Levenberg-Marquardt steps).",
        "evaluations": "Evaluations of the residuals and their Jacobian (propagations with the STM).",
        "x0": "The best iterate (lowest cost seen): state at t = 0 [r (km), v (km/s)], shape (6,).",
        "covariance": "Formal covariance (J^T W J)^-1 of x0, (6, 6): km^2, km^2/s, km^2/s^2 blocks.",
        "correlation": "Correlation matrix of x0 (unit-free), (6, 6).",
        "singular_values": "Singular values of the whitened Jacobian (rows divided by their sigma), (6,).",
        "rank": "Numerical rank of the whitened Jacobian (6 when the state is determined).",
        "condition_number": "Largest / smallest singular value of the whitened Jacobian (unit-free).",
        "cost": "0.5 * sum of the squared normalized residuals at x0 (unit-free; +inf when none evaluated).",
        "max_abs_normalized": "Largest |residual / sigma| at x0 (unit-free).",
        "fits": "True when the RMS normalized residual at x0 is <= OdSettings.fit_sigma (default 3).",
        "residuals": ("Observed minus computed at x0, one per observation (km for range, km/s for "
                      "range rate)."),
        "normalized": "Residuals divided by their sigma (unit-free), one per observation.",
        "range_residuals": "Range residuals at x0 (km); NaN where an observation is not a range.",
        "range_rate_residuals": "Range-rate residuals at x0 (km/s); NaN where not a range rate.",
        "history_x0": "Iterates, (iterations + 1, 6): km, km/s.",
        "history_residuals": "Residuals per iterate, (iterations + 1, n): km or km/s.",
        "history_range_residuals": "Range residuals per iterate (km), NaN where not a range.",
        "history_range_rate_residuals": "Range-rate residuals per iterate (km/s), NaN where not one.",
        "history_cost": "Cost per iterate (unit-free), (iterations + 1,).",
        "history_lambda": "Levenberg-Marquardt damping per iterate (unit-free; 0 for Gauss-Newton/Newton).",
    },
    "OdSolver": {
        "rows": "Number of measurement rows the solver fits.",
        "row_sigmas": "Sigma of every row (km for range, km/s for range rate).",
        "settings": "The validated OdSettings the solver was built with.",
    },
    "Station": {
        "r0": "Inertial position at t = 0 (km), (3,).",
        "omega": "Rotation rate about +z (rad/s).",
    },
    "Trajectory": {
        "times": "Output times (s), (n,).",
        "states": "States at the output times (km, km/s), (n, 6).",
        "stms": ("State transition matrices d x(t) / d x(t0) (km, km/s, s blocks), (n, 6, 6); None "
                 "without the STM."),
        "stats": "Integrator statistics (steps, rejected steps, right-hand-side evaluations).",
        "status": "Integrator status name ('success' when every output time was reached).",
        "success": "True when every output time was reached.",
        "t_reached": "Last time reached (s).",
        "message": "One line saying why the integration stopped.",
    },
    "ExponentialDrag": {
        "rho0": "Density at the reference height h0 (kg/m^3).",
        "h0": "Reference height above body_radius (km).",
        "scale_height": "Density scale height (km).",
        "cd": "Drag coefficient (unit-free).",
        "area": "Cross-section area (m^2).",
        "mass": "Spacecraft mass (kg).",
        "body_radius": "Radius the height is measured from (km).",
        "omega": "Atmosphere rotation vector (rad/s), (3,).",
    },
    "J2Gravity": {
        "mu": "Gravitational parameter (km^3/s^2).",
        "j2": "Second zonal harmonic J2 (unit-free).",
        "radius": "Reference radius of J2 (km).",
    },
}

_CLASS_DOCS = {
    "OdResult": "Result of a batch orbit determination: the best state x0 (km, km/s) at t = 0, its formal "
                "covariance, residuals (km, km/s) and the iteration history. See docs/od.md.",
    "OdSolver": "A reusable batch least-squares orbit determination solver (built once, solved many times).",
    "Station": "A ground station: inertial position r0 (km) at t = 0 rotating about +z at omega (rad/s).",
    "ExponentialDrag": "Exponential atmosphere drag: rho = rho0 exp(-(h - h0) / scale_height) with rho0 in "
                       "kg/m^3, h0 and scale_height in km, area in m^2, mass in kg, co-rotating at omega "
                       "(rad/s).",
}


def _od_result_repr(self: Any) -> str:
    import numpy as np

    x = np.asarray(self.x0)
    return (f"OdResult(status={self.status.name}, iterations={self.iterations}, cost={self.cost:.6g}, "
            f"fits={self.fits}, rank={self.rank}, r=[{x[0]:.3f}, {x[1]:.3f}, {x[2]:.3f}] km, "
            f"v=[{x[3]:.6f}, {x[4]:.6f}, {x[5]:.6f}] km/s)")


def _od_solver_repr(self: Any) -> str:
    return f"OdSolver(rows={self.rows}, method={self.settings.method.name})"


def attach() -> None:
    """Attach the docstrings and reprs above to the extension's classes (idempotent)."""
    for cls_name, props in _PROPS.items():
        cls = getattr(_c, cls_name, None)
        if cls is None:
            continue
        for name, doc in props.items():
            p = cls.__dict__.get(name)
            if isinstance(p, property) and not (p.__doc__ or "").strip():
                setattr(cls, name, property(p.fget, p.fset, p.fdel, doc))
        if cls_name in _CLASS_DOCS:  # these are complete, with the units the binding's lack
            try:
                cls.__doc__ = _CLASS_DOCS[cls_name]
            except (AttributeError, TypeError):
                pass
    for cls, rep in ((_c.OdResult, _od_result_repr), (_c.OdSolver, _od_solver_repr)):
        if "__repr__" not in vars(cls):  # a repr the binding defines wins
            cls.__repr__ = rep
