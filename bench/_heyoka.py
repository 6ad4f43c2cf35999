"""heyoka.py systems shared by the benchmarks (heyoka is installed by ``make bench``)."""

from __future__ import annotations

import satgnc

MU = satgnc.EARTH_MU
RE = satgnc.EARTH_RADIUS
J2 = satgnc.EARTH_J2


def j2_variational_system() -> list:
    """The 42-dim system of point mass + J2 (km, s) with its 6x6 variational equations, row-major STM.

    The state is (x, y, z, vx, vy, vz, p00, p01, ..., p55); built by hand (heyoka differentiates the
    acceleration symbolically), as in ``bench/propagation.py`` and ``bench/propagation_ensemble.py``.
    """
    import heyoka as hy

    xs = hy.make_vars("x", "y", "z", "vx", "vy", "vz")
    x, y, z = xs[:3]
    r2 = x * x + y * y + z * z
    r = hy.sqrt(r2)
    kp = MU / (r2 * r)
    kj = -1.5 * J2 * MU * RE * RE / (r2 * r2 * r)
    s = 5.0 * z * z / r2
    acc = [-kp * x + kj * x * (1.0 - s), -kp * y + kj * y * (1.0 - s), -kp * z + kj * z * (3.0 - s)]
    G = [[hy.diff(acc[i], xs[j]) for j in range(3)] for i in range(3)]
    ps = hy.make_vars(*[f"p{i}{j}" for i in range(6) for j in range(6)])
    P = [[ps[6 * i + j] for j in range(6)] for i in range(6)]
    sys = [(xs[i], xs[i + 3]) for i in range(3)] + [(xs[3 + i], acc[i]) for i in range(3)]
    for i in range(6):
        for j in range(6):
            rhs = P[i + 3][j] if i < 3 else hy.sum([G[i - 3][k] * P[k][j] for k in range(3)])
            sys.append((P[i][j], rhs))
    return sys
