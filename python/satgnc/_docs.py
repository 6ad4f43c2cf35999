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
    "OdSettings": {
        "method": ("OdMethod: gauss_newton (the struct's default), levenberg_marquardt (od.solve's default) "
                   "or newton."),
        "max_iterations": "Accepted steps at most (the history holds max_iterations + 1 rows); default 100.",
        "step_tol": ("Step test: |dx_i| <= step_tol (1 + |x_i|) for every component (km, km/s); default "
                     "1e-10."),
        "step_sigma_tol": "Gradient test: the step in formal sigmas (Mahalanobis length); default 1e-6.",
        "cost_tol": "Cost test: predicted relative cost decrease of a full step (unit-free); default 1e-6.",
        "residual_tol": ("Also converged when max |normalized residual| <= this (the paper's xi); 0 = off "
                         "(default)."),
        "rank_tol": "Singular values below rank_tol * s_max count as zero (numerical rank); default 1e-13.",
        "min_radius": "A state closer to the centre than this is diverged (km); default 6378.1363.",
        "mu": ("Gravitational parameter of the unbound test, specific energy >= 0 (km^3/s^2); default "
               "398600.4418."),
        "fit_sigma": "A solution fits when its RMS normalized residual <= fit_sigma (unit-free); default 3.",
        "min_range": "A smaller predicted range is degenerate_geometry (km); default 1e-6.",
        "gn_max_halvings": "Gauss-Newton line search: step halvings before status stalled; default 40.",
        "geodesic": ("Gauss-Newton and LM add the geodesic acceleration (Transtrum & Sethna 2012); default "
                     "True."),
        "valley_corrections": "Valley corrector steps per poor trial point, GN and LM (0 = off); default 3.",
        "extrapolate": ("GN and LM try the minimizer of a parabola fitted along an accepted step; default "
                        "True."),
        "lm_lambda0": "Initial Levenberg-Marquardt damping, relative to the More scaling; default 1e-3.",
        "lm_increase": "LM damping factor after a rejected step; default 10.",
        "lm_decrease": "LM damping factor after a very successful step (gain ratio > 0.75); default 0.1.",
        "lm_max_rejections": "LM rejected trials in a row before status stalled; default 30.",
        "lm_stall_tol": "After 3 LM steps each lowering the cost by < this fraction, try a Newton polish; "
                        "default 0.1.",
        "lm_polish_iterations": "Undamped Newton steps tried when LM creeps (kept if lower and converged); "
                                "default 10.",
    },
    "AdmmSettings": {
        "rho": "Initial ADMM penalty (> 0, unit-free on the equilibrated problem); default 0.2.",
        "max_iterations": "ADMM iterations at most (>= 1); default 10000.",
        "stopping": "Stopping rule: 'residuals' (primal/dual residuals and the duality gap) or 'paper'.",
        "eps_abs": "Absolute tolerance on both residuals (>= 0); default 1e-7.",
        "eps_rel": "Relative tolerance on both residuals (>= 0); default 1e-6.",
        "paper_eps": "Threshold of the paper's stopping rule ||U - Y||_2 / size (> 0); default 1e-3.",
        "relaxation": "Over-relaxation alpha in (0, 2); 1 = none (the paper's); default 1.8.",
        "adaptive_rho": "Residual balancing of rho (the OSQP rule); default True.",
        "adaptive_rho_interval": "Iterations between rho checks; default 25.",
        "adaptive_rho_tolerance": "Refactor only when rho changes by more than this factor; default 5.",
        "rho_min": "Lower bound of the adaptive rho; default 1e-12.",
        "rho_max": "Upper bound of the adaptive rho; default 1e6.",
        "cache_gains": "Reuse the Riccati gains while rho is unchanged (False: recursion every iteration); "
                       "default True.",
        "condensed": ("Condensed x/u step when there is no stage state cost and R is empty or diagonal; "
                      "default True."),
        "paper_multiplier_rescale": "The published implementation's multiplier rescaling after iteration 1; "
                                    "default False.",
        "track_best": "Keep the best iterate (returned on max_iterations); default True.",
        "polish": "Active-set polish with an optimality certificate (residual rule only); default True.",
        "polish_interval": "Iterations between polish attempts (>= 1); default 5.",
        "polish_max_free": "Largest free set the polish classifies (0 = 8 nx, capped at N nu); default 0.",
        "polish_tolerance": "Relative tolerance of the polish's optimality check; default 1e-7.",
        "polish_dual": "Also guess the active set from the dual estimate; default True.",
        "paper_global_rescale_iterations": ("The published implementation's global multiplier "
                                            "rescaling up to this iteration; default 0 (off)."),
        "polish_swaps": "Local repairs of a rejected dual guess (>= 0); default 3.",
        "eps_gap": ("Relative duality gap of the flown plan required for 'solved' (residual rule); default "
                    "1e-5."),
        "gap_floor": "Denominator floor of the relative gap (objective units, >= 0); default 1e-300.",
        "terminal_tolerance": "With a hard terminal state, 'solved' needs the miss <= this times the "
                              "miss of doing nothing (unit-free); default 1e-6.",
        "gap_check_interval": "Iterations between gap evaluations once the residuals pass (>= 1); default 5.",
        "inaccurate_factor": "'solved_inaccurate' at a limit: residuals and gap within this factor of "
                             "their tolerances; default 10.",
        "time_limit": "Wall-time limit of solve() (s); 0 = none (default).",
        "max_workspace_bytes": "Setup refuses a workspace estimated above this (bytes); default 512 MiB.",
        "infeasibility_check_interval": "Iterations between primal infeasibility checks (hard terminal state "
                                        "with box bounds); default 25.",
        "equilibrate": "Equilibrate the problem at setup (off under the paper rule); default True.",
        "method": "'admm_ipm' (ADMM then an interior-point endgame; default) or plain ADMM (residual rule "
                  "only; the paper rule always runs plain ADMM).",
        "ipm_after": "ADMM iterations before the interior-point endgame (>= 0); default 8.",
        "ipm_max_iterations": "Interior-point iterations per run (>= 1); default 60.",
        "ipm_tolerance": "Interior-point stopping tolerance (relative complementarity and stationarity); "
                         "default 1e-7.",
    },
    "GroundStation": {
        "name": "Station name.",
        "latitude_deg": "Geodetic latitude (deg, WGS-84).",
        "longitude_deg": "Longitude, east positive (deg).",
        "height_km": "Height above the WGS-84 ellipsoid (km).",
        "elevation_mask_deg": "Elevation below which the station does not observe (deg).",
        "itrf_to_enu": "Rotation (3, 3), rows east, north, up (geodetic vertical) in ITRF axes: "
                       "v_enu = itrf_to_enu v_itrf.",
    },
    "Ellipsoid": {
        "name": "Ellipsoid name (WGS-84, GRS-80, ...).",
        "a": "Equatorial radius (km).",
        "f": "Flattening (unit-free).",
    },
    "PolarModel": {
        "sigma": "Radius of the reference circular orbit (km).",
        "omega": "Angular rate of the reference orbit (rad/s).",
        "k": "Gravitational parameter of the model, k = sigma^3 omega^2 (km^3/s^2).",
    },
    "SpaceWeather": {
        "f107": "F10.7 solar radio flux of the previous day (sfu, 1e-22 W/m^2/Hz), in [0, 400].",
        "f107a": "81-day centred average of F10.7 (sfu), in [0, 400].",
        "ap": "Daily planetary geomagnetic index Ap (unit-free), in [0, 400].",
    },
    "KeplerStmPropagator": {
        "mu": "Gravitational parameter (km^3/s^2).",
    },
    "ForceModel": {
        "mu": "Central-body gravitational parameter (km^3/s^2).",
        "j2": "The J2 term (J2Gravity; its mu should equal mu), or None.",
        "drag": "The exponential drag term (ExponentialDrag), or None.",
        "atmosphere_drag": "Drag through a density model (AtmosphereDrag; independent of drag), or None.",
        "conservative": "True when every term derives from a potential (no drag): det(STM) = 1.",
    },
    "BoundaryCondition": {
        "t": "Time of the condition (s from the epoch).",
        "type": "ConditionType: range (eq. 9) or doppler (eq. 11).",
        "range": "Observed range (km).",
        "range_rate": "Observed range rate, for doppler (km/s).",
        "sigma_range": "Standard deviation of the range (km, > 0).",
        "sigma_range_rate": "Standard deviation of the range rate (km/s, > 0).",
        "station": "Index of the observing station.",
    },
    "RootSearchSettings": {
        "distinct_position_km": "Two solutions closer than this in position (km) ...",
        "distinct_velocity_kms": "... and in velocity (km/s) are the same root.",
        "distinct_sigma": "Solutions within this many formal sigmas (Mahalanobis distance) are one root.",
    },
    "J2Gravity": {
        "mu": "Gravitational parameter (km^3/s^2).",
        "j2": "Second zonal harmonic J2 (unit-free).",
        "radius": "Reference radius of J2 (km).",
    },
    "AtmosphereDrag": {
        "atmosphere": "The density model (AtmosphereModel: HarrisPriester, Nrlmsise00, ...; kg/m^3).",
        "sun": ("The Sun direction model (SunDirectionModel, geocentric GCRF), or None: the force model's "
                "ERFA Sun at its epoch."),
        "earth_rotation": ("EarthRotationModel (GCRF -> ITRF) the atmosphere co-rotates with, or None: "
                           "UniformRotation(0) about GCRF z from t = 0."),
        "cd": "Drag coefficient (unit-free, >= 0).",
        "area": "Cross-section area (m^2, >= 0).",
        "mass": "Spacecraft mass (kg, > 0).",
    },
    "EopTable": {
        "policy": "Out-of-range policy of the interpolation: 'error', 'hold_last' or 'zero'.",
    },
    "ErfaSun": {
        "epoch_jd1": "TT Julian date of t = 0, part 1 (days); the table's t is s after it.",
        "epoch_jd2": "TT Julian date of t = 0, part 2 (days).",
    },
    "ForceModelConfig": {
        "model": "The validated ForceModel built from the file (epoch set from [epoch] when given).",
        "epoch": "satgnc.time.Epoch of t = 0 ([epoch]), or None: J2000.0 TT.",
        "space_weather": "SpaceWeather of [space_weather] (F10.7, F10.7a in sfu; Ap) for the density models.",
        "gravity_model": "Gravity chosen in the file: 'point_mass', 'j2', 'egm2008' or 'file'.",
        "gravity_file": "Path of the .gfc coefficient file read ('' without a gravity field).",
        "atmosphere": "Density model chosen: '', 'harris_priester', 'exponential' or 'nrlmsise00'.",
        "earth_orientation": "Earth rotation chosen: 'uniform' or 'iau2006' (IAU 2006/2000A CIO with EOP).",
        "eop_file": "Path of the EOP file read (iau2006), else ''.",
        "ephemeris_file": "Path of the JPL DE .bsp file of [third_body] ephemeris, else '' (ERFA).",
        "source": "The TOML file the configuration was read from (or the source name given).",
        "radius": "[central_body] radius (km).",
    },
    "GravityCoefficients": {
        "name": "Model name from the .gfc header (e.g. 'EGM2008').",
        "tide_system": "Tide system of the coefficients, from the .gfc header (e.g. 'tide_free').",
        "max_degree": "Highest degree read (unit-free).",
    },
    "GravityField": {
        "degree": "Highest degree evaluated (unit-free; degrees 2..degree, ITRF).",
        "order": "Highest order evaluated (unit-free, <= degree).",
        "coefficients": "The GravityCoefficients the field evaluates (mu km^3/s^2, radius km).",
    },
    "HarrisPriester": {
        "n": "Exponent of the bulge's cosine (unit-free, in [2, 6]: 2 low inclination, 6 polar).",
        "lag": "Lag of the density bulge behind the Sun (rad, in [0, pi]).",
    },
    "IauEarthRotation": {
        "t_begin": "Start of the tabulated span (s after the epoch).",
        "t_end": "End of the tabulated span (s after the epoch).",
        "step": "Grid step of the slowly varying parts (s); the ERA is exact.",
    },
    "MeasurementModel": {
        "type": ("Observable name (str): 'one_way_range', 'two_way_range', 'one_way_range_rate', "
                 "'two_way_range_rate', 'azimuth_elevation' or 'right_ascension_declination'."),
        "size": "Values per measurement: 1 (range km, range rate km/s) or 2 (angle pairs, rad).",
        "troposphere": "True when the Saastamoinen troposphere delay is added (range observables; km).",
        "shapiro": "True when the Earth's Shapiro relativistic delay is added (range observables; km).",
    },
    "RotatingStationEphemeris": {
        "station": "The rotating satgnc.od.Station (r0 km at t = 0 in GCRF, omega rad/s about +z).",
    },
    "SolarRadiationPressure": {
        "cr": "Radiation pressure coefficient (unit-free, 1 absorbing .. 2 reflecting).",
        "shadow": "Earth shadow model: 'none', 'cylindrical' or 'conical'.",
    },
    "SpkEphemeris": {
        "path": "The .bsp file opened.",
        "internal_name": "The DAF file record's internal file name.",
        "pairs": "The (target, center) pairs of NAIF codes prepared at open.",
    },
    "ThirdBodies": {
        "sun": "True when the Sun's point mass is included (ERFA ephemeris, GCRF).",
        "moon": "True when the Moon's point mass is included (ERFA ephemeris, GCRF).",
    },
}

#: Docstrings of the properties every pybind11 enum of the extension has (attached when empty).
_ENUM_PROPS: dict[str, str] = {
    "value": "The enumerator's integer value (the C++ enum's).",
    "message": "One line describing this status (the C++ status table's message).",
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


#: Compiled result and info classes that get the one-line summary repr of :class:`satgnc._results.Result`
#: (scalars as values, arrays as dtype and shape), instead of pybind11's ``<... object at 0x...>``.
_SUMMARY_REPR = ("IlqrAdmmInfo", "LookAngles", "Measurement", "OdInfo", "PropagatedMapInfo",
                 "PropagationStats", "Root", "RootSearchResult", "ScpInfo", "SensitivityTrajectory",
                 "TrackingData")


def _summary_repr(self: Any) -> str:
    from ._results import _summary

    names = [k for k, v in vars(type(self)).items() if isinstance(v, property)]
    parts = []
    for n in names:
        try:
            parts.append(f"{n}={_summary(getattr(self, n))}")
        except Exception:  # a property that cannot be read in this state (e.g. not solved yet)
            continue
    return f"{type(self).__name__}({', '.join(parts)})"


def _set_doc(cls: Any, name: str, doc: str) -> None:
    """Give ``cls.name`` (a property) the docstring ``doc`` when it has none."""
    p = cls.__dict__.get(name)
    if isinstance(p, property) and not (p.__doc__ or "").strip():
        setattr(cls, name, property(p.fget, p.fset, p.fdel, doc))


def attach() -> None:
    """Attach the docstrings and reprs above to the extension's classes (idempotent)."""
    for cls_name, props in _PROPS.items():
        cls = getattr(_c, cls_name, None)
        if cls is None:
            continue
        for name, doc in props.items():
            _set_doc(cls, name, doc)
        if cls_name in _CLASS_DOCS:  # these are complete, with the units the binding's lack
            try:
                cls.__doc__ = _CLASS_DOCS[cls_name]
            except (AttributeError, TypeError):
                pass
    for obj in vars(_c).values():
        if isinstance(obj, type) and hasattr(obj, "__members__"):  # a pybind11 enum
            for name, doc in _ENUM_PROPS.items():
                _set_doc(obj, name, doc)
    summary = [(getattr(_c, n), _summary_repr) for n in _SUMMARY_REPR if hasattr(_c, n)]
    for cls, rep in ((_c.OdResult, _od_result_repr), (_c.OdSolver, _od_solver_repr), *summary):
        if "__repr__" not in vars(cls):  # a repr the binding defines wins
            cls.__repr__ = rep
