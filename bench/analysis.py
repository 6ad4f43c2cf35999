"""Rank-test benchmark (one run): wrong verdicts on planted random systems and timing at 50 states.

Planted systems: n in [3, 30], m in [1, 3], planted controllable dimension r in [1, n], time scale
ts = 10^U(-4, 0) applied to A only, hidden by a random orthogonal similarity. Well-posed: the planted
controllable pair (A11, B1) has PBH distance min_lambda sigma_min([A11 - lambda I, B1]) above 1e-6 of
||[A11 B1]||_F. A verdict counts as wrong when the rank differs from r (satgnc's "not robustly
decidable" also counts as wrong). Peers: numpy.linalg.matrix_rank of the Kalman matrix (default
tolerance) and a plain SVD staircase (one fixed tolerance n eps ||[A B]||_F for every stair).
Usage: python bench/analysis.py [--count N] [--seed S]
"""

from __future__ import annotations

import argparse

import numpy as np
import satgnc.analysis as an
from _timing import timeit


def planted(rng, n, m, r, ts):
    while True:
        A11 = rng.standard_normal((r, r))
        B1 = rng.standard_normal((r, m))
        ev = np.linalg.eigvals(A11)
        dist = min(np.linalg.svd(np.hstack([A11 - lam * np.eye(r), B1]), compute_uv=False)[-1] for lam in ev)
        if dist >= 1e-6 * np.linalg.norm(np.hstack([A11, B1])):
            break
    At = np.zeros((n, n))
    At[:r, :r] = A11
    At[:r, r:] = rng.standard_normal((r, n - r))
    At[r:, r:] = rng.standard_normal((n - r, n - r))
    Bt = np.zeros((n, m))
    Bt[:r] = B1
    q, rr = np.linalg.qr(rng.standard_normal((n, n)))
    U = q * np.sign(np.diag(rr))
    return ts * U @ At @ U.T, U @ Bt


def kalman(A, B):
    n, m = B.shape
    K = np.empty((n, n * m))
    K[:, :m] = B
    for k in range(1, n):
        K[:, k * m:(k + 1) * m] = A @ K[:, (k - 1) * m:k * m]
    return K


def plain_staircase(A, B):
    """Textbook SVD staircase with one absolute tolerance for every stair."""
    n = A.shape[0]
    tol = n * np.finfo(float).eps * np.linalg.norm(np.hstack([A, B]))
    A = A.copy()
    u, s, _ = np.linalg.svd(B)
    r = int(np.sum(s > tol))
    if r == 0:
        return 0
    A = u.T @ A @ u
    pos, prev = r, r
    while pos < n:
        blk = A[pos:, pos - prev:pos]
        u, s, _ = np.linalg.svd(blk)
        r = int(np.sum(s > tol))
        if r == 0:
            break
        A[pos:, :] = u.T @ A[pos:, :]
        A[:, pos:] = A[:, pos:] @ u
        pos, prev = pos + r, r
    return pos


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--count", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=12345)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    wrong = {"satgnc staircase": 0, "satgnc staircase (not robust)": 0, "numpy matrix_rank(Kalman)": 0,
             "plain SVD staircase": 0}
    full = 0
    for _ in range(args.count):
        n = int(rng.integers(3, 31))
        m = int(rng.integers(1, 4))
        r = n if rng.random() < 0.25 else int(rng.integers(1, n + 1))
        full += r == n
        ts = 10.0 ** rng.uniform(-4, 0)
        A, B = planted(rng, n, m, r, ts)
        rep = an.controllability(A, B)
        if rep.rank != r or rep.verdict == "not robustly decidable":
            wrong["satgnc staircase"] += 1
        if rep.verdict == "not robustly decidable":
            wrong["satgnc staircase (not robust)"] += 1
        if np.linalg.matrix_rank(kalman(A, B)) != r:
            wrong["numpy matrix_rank(Kalman)"] += 1
        if plain_staircase(A, B) != r:
            wrong["plain SVD staircase"] += 1
    print(f"planted systems: {args.count} (fully controllable: {full}), seed {args.seed}")
    for k, v in wrong.items():
        print(f"  {k:32s} wrong: {v:4d}  ({100.0 * v / args.count:.2f} %)")

    print("timing at n = 50 (ms per call, random Gaussian A, B):")
    for m in (1, 2, 3):
        A = rng.standard_normal((50, 50))
        B = rng.standard_normal((50, m))
        t_st = timeit(lambda A=A, B=B: an.controllability(A, B))
        t_np = timeit(lambda A=A, B=B: np.linalg.matrix_rank(kalman(A, B)))
        line = f"  m = {m}: satgnc staircase {1e3 * t_st:.3f}, numpy Kalman + SVD {1e3 * t_np:.3f}"
        try:
            import control

            t_pc = timeit(lambda A=A, B=B: np.linalg.matrix_rank(control.ctrb(A, B)))
            line += f", python-control ctrb + matrix_rank {1e3 * t_pc:.3f}"
        except ImportError:
            pass
        print(line + f"  (ratio numpy / satgnc = {t_np / t_st:.2f})")


if __name__ == "__main__":
    main()
