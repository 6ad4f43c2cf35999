"""Benchmark: nonlinear L1 rendezvous (issue 6 goals), all measured in one run on this machine.

* reference optimum: an independent SCP written here with cvxpy + Clarabel subproblems (same RK3 map
  and Jacobians, same line search), per case;
* satgnc SCP (linear ADMM subproblems) and satgnc iLQR-ADMM converged runs: time and relative gap;
* the paper-accuracy run (60 iterations) time;
* the hard terminal state (x_N = x_f on the chaser's relative state): satgnc SCP against the same
  cvxpy + Clarabel SCP with the terminal constraint (full steps);
* MPC re-plan times and closed-loop miss.

Times: median of repeats, thread CPU time (the machine is shared; wall time is also printed).
Run: .venv/bin/python bench/guidance_nonlinear.py [--quick]
"""

from __future__ import annotations

import sys
import time

import numpy as np
from satgnc import _satgnc as _c
from satgnc.papers import l1_admm_rendezvous as nl


def timed(fn, repeats=3):
    cpu, wall, out = [], [], None
    for _ in range(repeats):
        t0, w0 = time.thread_time(), time.perf_counter()
        out = fn()
        cpu.append(time.thread_time() - t0)
        wall.append(time.perf_counter() - w0)
    return out, float(np.median(cpu)), float(np.median(wall))


def cvxpy_scp(case, max_outer=20, tol=1e-10, hard=False):
    """Independent SCP: linearize with the map's Jacobians, solve the convex subproblem with
    cvxpy/Clarabel, backtracking on the true cost. ``hard``: x_N = x_f on the chaser's relative state
    in every subproblem, full steps until the subproblem's optimum stops moving (tol) and the
    nonlinear miss is below 1e-9 (the map is mildly nonlinear over the paper's horizon)."""
    import cvxpy as cp

    pr = case.problem
    Nh, w = pr.horizon, pr.stage_weight
    Qf = np.asarray(pr.Qf)
    mask = np.diag(Qf) > 0
    U = np.zeros((3, Nh))

    def true_cost(U):
        x = np.asarray(pr.x0)
        for k in range(Nh):
            x = case.dmap.step(k, x, U[:, k])[0]
        e = x - np.asarray(pr.x_target)
        return 0.5 * e @ Qf @ e + w * np.abs(U).sum()

    J = true_cost(U)
    outer = 0
    for _ in range(max_outer):
        outer += 1
        xs = [np.asarray(pr.x0)]
        As, Bs, cs = [], [], []
        for k in range(Nh):
            xn, A, B = case.dmap.step(k, xs[-1], U[:, k])
            As.append(A)
            Bs.append(B)
            cs.append(xn - A @ xs[-1] - B @ U[:, k])
            xs.append(xn)
        x = cp.Variable((12, Nh + 1))
        u = cp.Variable((3, Nh))
        cons = [x[:, 0] == np.asarray(pr.x0)]
        cons += [x[:, k + 1] == As[k] @ x[:, k] + Bs[k] @ u[:, k] + cs[k] for k in range(Nh)]
        if case.constrained:
            cons += [u <= np.asarray(pr.u_max)[:, None], u >= np.asarray(pr.u_min)[:, None]]
        q = np.sqrt(np.diag(Qf)[mask])
        obj = 0.5 * cp.sum_squares(cp.multiply(q, x[mask, Nh])) + w * cp.sum(cp.abs(u))
        if hard:
            cons += [x[mask, Nh] == np.asarray(pr.x_target)[mask]]
        prob = cp.Problem(cp.Minimize(obj), cons)
        prob.solve(solver=cp.CLARABEL, tol_gap_abs=1e-12, tol_gap_rel=1e-12, tol_feas=1e-12)
        Us = np.asarray(u.value)
        if hard:
            prev, U = J, Us
            J = true_cost(U)
            xN = np.asarray(pr.x0)
            for k in range(Nh):
                xN = case.dmap.step(k, xN, U[:, k])[0]
            miss = np.linalg.norm((xN - pr.x_target)[mask])
            if abs(prob.value - prev) <= tol * max(1.0, abs(J)) and miss < 1e-9:
                break
            J = prob.value  # compare subproblem optima between iterations
            continue
        pred = J - prob.value
        if pred <= tol * max(1.0, abs(J)):
            break
        t = 1.0
        while t > 1e-8:
            Jn = true_cost(U + t * (Us - U))
            if Jn <= J - 1e-4 * t * pred:
                U, J = U + t * (Us - U), Jn
                break
            t *= 0.5
        else:
            break
    return U, (true_cost(U) if hard else J), outer


def main(quick=False):
    rows = []
    for constrained in (False, True):
        case = nl.paper_case(constrained)
        (U_ref, J_ref, outer_ref), t_ref, w_ref = timed(lambda case=case: cvxpy_scp(case), repeats=1)
        print(
            f"{case.name}: cvxpy/Clarabel SCP J = {J_ref:.10f} in {outer_ref} outer, {t_ref:.2f} s CPU",
            flush=True,
        )
        for eps in (1e-6,) if quick else (1e-6, 1e-7):
            s, t_s, w_s = timed(
                lambda case=case, eps=eps: nl.solve_scp(case, eps=eps, tol=1e-8), repeats=1 if quick else 3
            )
            gap = (s.info.objective - J_ref) / J_ref
            rows.append(
                (
                    case.name,
                    f"satgnc SCP (linear ADMM inner, eps {eps:g})",
                    gap,
                    t_s,
                    w_s,
                    f"{s.info.outer_iterations} outer / {s.info.inner_iterations} inner",
                )
            )
        dcase = nl.paper_case(constrained, discretization="dop853")
        sd, t_d, w_d = timed(lambda dcase=dcase: nl.solve_scp(dcase, eps=1e-6, tol=1e-8), repeats=1)
        flown = nl.miss(nl.fly(dcase, dcase.to_si(sd.U), truth_params=nl.model_params()))[0]
        rows.append(
            (
                case.name,
                "satgnc SCP on the DOP853 map (eps 1e-6)",
                float("nan"),
                t_d,
                w_d,
                f"{sd.info.outer_iterations} outer, J {sd.info.objective:.7f}, flown miss {flown:.3f} m",
            )
        )
        paper, t_p, w_p = timed(lambda case=case: nl.solve_paper(case), repeats=3 if quick else 10)
        rows.append(
            (
                case.name,
                "iLQR-ADMM paper settings (stops at 60)",
                (paper.info.objective_u - J_ref) / J_ref,
                t_p,
                w_p,
                f"{paper.info.iterations} iterations",
            )
        )
        if not quick:
            st = _c.IlqrAdmmSettings()
            st.rho = 1.0
            st.adaptive_rho = True
            st.eps_abs = st.eps_rel = 1e-7
            st.max_iter = 30000

            def run(case=case, st=st):
                sol = _c.IlqrAdmmSolver(case.dmap, case.problem, st)
                sol.set_initial_controls(np.zeros((3, nl.N)))
                sol.solve()
                return sol

            sol, t_i, w_i = timed(run, repeats=1)
            rows.append(
                (
                    case.name,
                    "iLQR-ADMM converged (adaptive rho)",
                    (sol.info.objective_y - J_ref) / J_ref,
                    t_i,
                    w_i,
                    f"{sol.info.iterations} iterations",
                )
            )
        hcase = nl.paper_case(constrained, terminal_equality=True)
        (U_h, J_h, outer_h), t_h, _ = timed(lambda hcase=hcase: cvxpy_scp(hcase, hard=True), repeats=1)
        print(f"{case.name}, x_N = x_f: cvxpy/Clarabel SCP J = {J_h:.10f} in {outer_h} outer, "
              f"{t_h:.2f} s CPU", flush=True)
        sh, t_sh, w_sh = timed(lambda hcase=hcase: nl.solve_scp(hcase, eps=1e-6, tol=1e-8),
                               repeats=1 if quick else 3)
        rows.append(
            (
                case.name,
                "satgnc SCP, hard terminal state x_N = x_f (eps 1e-6)",
                (sh.info.objective - J_h) / J_h,
                t_sh,
                w_sh,
                f"{nl.SCP_STATUS_NAMES[int(sh.info.status)]}, {sh.info.outer_iterations} outer / "
                f"{sh.info.inner_iterations} inner, miss {sh.info.terminal_constraint_miss:.1e}, "
                f"{t_h / max(t_sh, 1e-9):.0f}x faster than the cvxpy SCP",
            )
        )
        m = nl.mpc(case)
        rows.append(
            (
                case.name,
                "MPC re-plan (10 N/remaining warm iterations, cap 120; CVODES truth)",
                float("nan"),
                float(np.median(m["solve_times"])),
                float(np.max(m["solve_times"])),
                f"miss {nl.miss(m['X'])[0]:.2f} m, max|u| {np.abs(m['U']).max():.4f} N",
            )
        )
    print()
    print("| case | solver | rel. gap to cvxpy/Clarabel SCP | CPU s (median) | wall s | notes |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        gap = "n/a" if r[2] != r[2] else f"{r[2]:.2e}"  # NaN: another transcription, or MPC
        print(f"| {r[0]} | {r[1]} | {gap} | {r[3]:.4f} | {r[4]:.4f} | {r[5]} |")
    print("\n(MPC rows: CPU time median and max per re-plan in the time columns.)")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
