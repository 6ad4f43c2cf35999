"""``satgnc rank``: actuator / sensor-loss tables of the polar or CW model at an orbit."""

from __future__ import annotations

import argparse

from . import _orbit, cw_model, cw_units, format_loss_table, loss_table, polar_linear_model, polar_units


def _rank(args: argparse.Namespace) -> int:
    sigma, omega = _orbit(args.orbit, "--orbit")
    if args.model == "polar":
        A, B, C = polar_linear_model(sigma, omega)
        units = polar_units(sigma, omega, n_outputs=2) if args.units == "dimensionless" else None
        inputs, outputs = ["u1 radial", "u2 tangential"], ["radius", "angle"]
        head = f"polar model, sigma = {sigma:.6g} km, omega = {omega:.6g} rad/s"
    else:
        A, B, C = cw_model(omega)
        units = cw_units(omega, 1.0, n_outputs=3) if args.units == "dimensionless" else None
        inputs = ["ax radial", "ay along-track", "az normal"]
        outputs = ["x radial", "y along-track", "z normal"]
        head = f"CW (Hill frame x radial, y along-track, z normal), n = {omega:.6g} rad/s, m, m/s"
    n = A.shape[0]
    print(f"# {head}; units: {args.units}")
    print(format_loss_table(loss_table(A, B=B, units=units), inputs, n, "## actuators (controllability)"))
    print()
    print(format_loss_table(loss_table(A, C=C, units=units), outputs, n, "## sensors (observability)"))
    return 0


def register(subparsers) -> None:
    """Add ``satgnc rank``."""
    p = subparsers.add_parser("rank", help="controllability / observability loss tables (polar or CW)")
    p.add_argument("--model", choices=["polar", "cw"], default="polar")
    p.add_argument("--orbit", default="leo", help="leo, geo, one (sigma = omega = 1) or 'sigma,omega' "
                   "(km, rad/s)")
    p.add_argument("--units", choices=["physical", "dimensionless"], default="physical",
                   help="test in km/s units or in time 1/omega, length sigma (default physical)")
    p.set_defaults(func=_rank)
