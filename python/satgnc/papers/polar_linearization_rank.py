"""Printed intermediate matrices of polar_linearization_rank.md (section 4) as data, and their check.

Each entry is a function of omega returning the matrix exactly as printed in the paper, so the test and
the report can show where the paper's typesetting differs from the algebra.
"""

from __future__ import annotations

import numpy as np

from ..analysis import kalman_matrix, polar_linear_model

# Section 4.1 / 4.2 as printed (w = omega).
PRINTED = {
    "A^2": lambda w: np.array([[3 * w**2, 0, 0, 2 * w], [0, -w**2, 0, 0], [0, -2 * w, 0, 0],
                               [-6 * w**3, 0, 0, -4 * w**2]]),
    "A^3": lambda w: np.array([[0, -w**2, 0, 0], [-3 * w**4, 0, 0, -2 * w**3], [-6 * w**3, 0, 0, -4 * w**2],
                               [0, 2 * w**3, 0, 0]]),
    "AB": lambda w: np.array([[1, 0], [0, 2 * w], [0, 1], [-2 * w, 0]]),
    "A^2B": lambda w: np.array([[0, 2 * w], [-w**2, 0], [-2 * w, 0], [0, -4 * w**2]]),
    "A^3B": lambda w: np.array([[-w**2, 0], [0, -2 * w**3], [0, -4 * w**2], [2 * w**3, 0]]),
    "[B AB A^2B A^3B]": lambda w: np.array([
        [0, 0, 1, 0, 0, 2 * w, -w**2, 0], [1, 0, 0, 2 * w, -w**2, 0, 0, -2 * w**3],
        [0, 0, 0, 1, -2 * w, 0, 0, -4 * w**2], [0, 1, -2 * w, 0, 0, -4 * w**2, 2 * w**3, 0]]),
    "Kalman(B1 radial)": lambda w: np.array([[0, 1, 0, -w**2], [1, 0, -w**2, 0], [0, 0, -2 * w, 0],
                                             [0, -2 * w, 0, 2 * w**3]]),
    "Kalman(B2 tangential)": lambda w: np.array([[0, 0, 2 * w, 0], [0, 2 * w, 0, -2 * w**3],
                                                 [0, 1, 0, -4 * w**2], [1, 0, -4 * w**2, 0]]),
    "CA": lambda w: np.array([[0, 1, 0, 0], [0, 0, 0, 1]]),
    "CA^2": lambda w: np.array([[-3 * w**2, 0, 0, 2 * w], [0, -2 * w, 0, 0]]),
    "CA^3": lambda w: np.array([[0, -w**2, 0, 0], [-6 * w**3, 0, 0, -4 * w**2]]),
    "[C; CA; CA^2; CA^3]": lambda w: np.array([
        [1, 0, 0, 0], [0, 0, 1, 0], [0, 1, 0, 0], [0, 0, 0, 1], [3 * w**2, 0, 0, 2 * w], [0, -2 * w, 0, 0],
        [0, -w**2, 0, 0], [-6 * w**3, 0, 0, -4 * w**2]]),
    "Obsv(C1 radius)": lambda w: np.array([[1, 0, 0, 0], [0, 1, 0, 0], [3 * w**2, 0, 0, 2 * w],
                                           [0, -w**2, 0, 0]]),
    "Obsv(C2 angle)": lambda w: np.array([[0, 0, 1, 0], [0, 0, 0, 1], [0, -2 * w, 0, 0],
                                          [-6 * w**3, 0, 0, -4 * w**2]]),
}

# The paper's stated ranks (section 4; also python/satgnc/data/paper_tables.json).
PAPER_RANKS = {"controllability": {"both": 4, "radial only (u1)": 3, "tangential only (u2)": 4},
               "observability": {"radius + angle": 4, "radius only": 3, "angle only": 4}}


def computed(w: float) -> dict[str, np.ndarray]:
    """The same matrices from the algebra (sigma = 1, any omega)."""
    A, B, C = polar_linear_model(1.0, w)
    A2, A3 = A @ A, A @ A @ A
    return {
        "A^2": A2, "A^3": A3, "AB": A @ B, "A^2B": A2 @ B, "A^3B": A3 @ B,
        "[B AB A^2B A^3B]": kalman_matrix(A, B=B),
        "Kalman(B1 radial)": kalman_matrix(A, B=B[:, [0]]),
        "Kalman(B2 tangential)": kalman_matrix(A, B=B[:, [1]]),
        "CA": C @ A, "CA^2": C @ A2, "CA^3": C @ A3,
        "[C; CA; CA^2; CA^3]": kalman_matrix(A, C=C),
        "Obsv(C1 radius)": kalman_matrix(A, C=C[[0]]),
        "Obsv(C2 angle)": kalman_matrix(A, C=C[[1]]),
    }


def compare(w: float = 2.0) -> dict[str, list[tuple[int, int, float, float]]]:
    """For each printed matrix, the entries (row, col, printed, computed) that differ at omega = w
    (w = 2 by default: at w = 1 a slip between w and w^2 would hide)."""
    comp = computed(w)
    out = {}
    for name, f in PRINTED.items():
        p = f(w).astype(float)
        c = comp[name]
        diff = np.argwhere(~np.isclose(p, c, rtol=1e-14, atol=1e-14))
        out[name] = [(int(i), int(j), float(p[i, j]), float(c[i, j])) for i, j in diff]
    return out
