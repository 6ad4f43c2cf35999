// L1 ADMM with state constraints (satgnc/guidance/state_constraints.hpp; docs/guidance.md, "State
// constraints"). Private workspace, the Riccati step with per-node state weights, the projections,
// the dual bound and the infeasibility certificate.
#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "detail/cholesky.hpp"
#include "detail/dual_line.hpp"
#include "detail/state_ipm.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"
#include "satgnc/guidance/state_constraints.hpp"

namespace satgnc::guidance {
namespace detail {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEqualityRhoFactor = 1e3;  // OSQP: equality rows get 1e3 x rho
constexpr int kPolishSizes = 8;             // free-set sizes tried per polish attempt

// Projection onto the second-order cone {(t, x): ||x|| <= t} in place (3-vector).
void project_soc(double& t, double& x1, double& x2) noexcept {
  const double nx = std::hypot(x1, x2);
  if (nx <= t) return;
  if (nx <= -t) {
    t = x1 = x2 = 0.0;
    return;
  }
  const double a = 0.5 * (t + nx);
  x1 *= a / nx;
  x2 *= a / nx;
  t = a;
}
}  // namespace

struct StateAdmmWorkspace {
  LtvProblem prob;
  AdmmSettings st;
  int nx = 0, nu = 0, N = 0, m = 0;  // m: constraint rows
  int n_half = 0;                    // the first rows are the half-spaces, in order
  // rows: unit c_j (nx x m), node, bounds, cone-block start flag
  Eigen::MatrixXd Crow;
  Eigen::VectorXi node, cone_start;  // cone_start(j) = 1 at the first row of a cone block
  Eigen::VectorXd lo, hi, off;       // interval bounds; cone offset of the block's first row
  Eigen::VectorXd kappa, rho_row, cosang, escale;
  // cost
  Eigen::VectorXd w, rdiag, ulo, uhi;
  bool has_Q = false;
  // Riccati step (per node blocks side by side)
  Eigen::MatrixXd Qx, P, K, QuuInv, Acl, PB, d, q, r, qbase;
  Eigen::MatrixXd tmp_nx_nx, tmp_nx_nx2, tmp_nu_nx, Quu, Inu;
  Eigen::LLT<Eigen::MatrixXd> llt;
  Eigen::VectorXd p, wv, tmp_nx, tmp_nx2, g_nu;
  double rho = 0.0, rho_factored = -1.0;
  double rho_x = 0.0, rho_x_factored = -1.0;  // state rows: rho_j = rho_x kappa_j, adapted apart
  int factorizations = 0, rho_updates = 0;
  // iterates
  Eigen::MatrixXd X, U, Y, Yprev, Lam, Uhat;
  Eigen::VectorXd s, z, zprev, mu, shat, mu_check;
  Eigen::MatrixXd Xfree, Xf, costate, H, Cmu;
  Eigen::VectorXd lam_clean;
  bool warm = false;
  StateAdmmResult res;
  // ---- active-set polish (dense KKT on the free controls; allocation-free: sized at setup)
  Eigen::MatrixXd Srow, Kkt, Kkt0, Ufix, Ypol;
  Eigen::VectorXd kkt_rhs, kkt_sol, kkt_res, mu_pol, mu_best, nrm, unit_nx, sgn;
  Eigen::VectorXi piv, free_idx, act_idx, act_kind;
  int polish_attempts = 0;
  bool polish_sign_failed = false;  // the last polish() failed only on a free entry's sign or box
  bool polish_balanced = false;     // polish() shifts its KKT blocks each on its own scale (ipm_polish)
  // ---- dual recovery (recover_dual; sized at setup)
  Eigen::MatrixXd dr_G, dr_hq;
  Eigen::VectorXd dr_hmin, dr_hmax, dr_tgt, dr_lam, dr_rhs, dr_x, dr_y, mu_rec;
  Eigen::VectorXi dr_eq, dr_on, dr_pos;
  Eigen::MatrixXd U_ipm, X_ipm;  // the IPM's last plan while it is polished
  Eigen::VectorXd mu_ipm;
  std::vector<PwlBreak> kinks;  // dual_bound's line maximization (2 N nu, sized at setup)
  // ---- interior-point method (tried first; its plan is accepted only by the same tests)
  StateIpm ipm;
  StateIpmProblem ipd;
  bool ipm_ok = false;  // applicable (every L1 weight > 0, equality rows only at node N)

  // row vector c' dx_node/dU (length N nu, zero beyond node) into Srow.row(i); the CW case (6, 3) with
  // fixed-size products (a dual recovery on the N = 100 cone takes ~100 rows of ~50 stages each)
  void sensitivity_row(int i, const Eigen::Ref<const Eigen::VectorXd>& cvec, int nd) noexcept {
    if (nx == 6 && nu == 3)
      sensitivity_row_t<6, 3>(i, cvec, nd);
    else
      sensitivity_row_t<Eigen::Dynamic, Eigen::Dynamic>(i, cvec, nd);
  }
  template <int NX, int NU>
  void sensitivity_row_t(int i, const Eigen::Ref<const Eigen::VectorXd>& cvec, int nd) noexcept {
    Srow.row(i).tail((N - nd) * nu).setZero();
    tmp_nx = cvec;
    Eigen::Map<Eigen::Matrix<double, NX, 1>> v(tmp_nx.data(), nx), v2(tmp_nx2.data(), nx);
    Eigen::Map<Eigen::Matrix<double, NU, 1>> g(g_nu.data(), nu);
    for (int k = nd - 1; k >= 0; --k) {
      g.noalias() = Eigen::Map<const Eigen::Matrix<double, NX, NU>>(B(k).data(), nx, nu).transpose() * v;
      Srow.block(i, k * nu, 1, nu) = g.transpose();
      v2.noalias() = Eigen::Map<const Eigen::Matrix<double, NX, NX>>(A(k).data(), nx, nx).transpose() * v;
      v = v2;
    }
  }

  // in-place LU with partial pivoting of the leading n x n block of Kkt0; false if singular
  bool lu(int n) noexcept {
    for (int c = 0; c < n; ++c) {
      int pr = c;
      double best = std::abs(Kkt0(c, c));
      for (int rr = c + 1; rr < n; ++rr)
        if (std::abs(Kkt0(rr, c)) > best) {
          best = std::abs(Kkt0(rr, c));
          pr = rr;
        }
      if (!(best > 0.0) || !std::isfinite(best)) return false;
      piv(c) = pr;
      if (pr != c)
        for (int cc = 0; cc < n; ++cc) std::swap(Kkt0(c, cc), Kkt0(pr, cc));
      const double inv = 1.0 / Kkt0(c, c);
      for (int rr = c + 1; rr < n; ++rr) {
        const double f = Kkt0(rr, c) * inv;
        Kkt0(rr, c) = f;
        if (f != 0.0)
          for (int cc = c + 1; cc < n; ++cc) Kkt0(rr, cc) -= f * Kkt0(c, cc);
      }
    }
    return true;
  }
  void lu_solve(int n, Eigen::VectorXd& b) const noexcept {
    // full rows (L part included) were swapped during the factorization: all swaps first
    for (int c = 0; c < n; ++c)
      if (piv(c) != c) std::swap(b(c), b(piv(c)));
    for (int c = 0; c < n; ++c)
      for (int rr = c + 1; rr < n; ++rr) b(rr) -= Kkt0(rr, c) * b(c);
    for (int c = n - 1; c >= 0; --c) {
      double acc = b(c);
      for (int cc = c + 1; cc < n; ++cc) acc -= Kkt0(c, cc) * b(cc);
      b(c) = acc / Kkt0(c, c);
    }
  }

  // Guess the active set from (Y, Z), solve the equality-constrained problem on the free controls
  // (cone rows linearized at the current point, re-linearized 3 times), and return the candidate in
  // Ypol with row multipliers mu_pol. Without stage Q only. The caller certifies (gap, violation).
  // dual estimate -grad of the smooth part and the state rows at the LQR iterate (X, U, mu) into H
  // (negated: H = grad), the L1 switching function of the polish guess
  void gradient_estimate() noexcept {
    Cmu.setZero();
    for (int k = 1; k <= N; ++k) {
      if (k < N && !has_Q) continue;
      tmp_nx = X.col(k) - prob.xf;
      Cmu.col(k).noalias() = (k < N ? prob.Q : prob.Qf) * tmp_nx;
    }
    for (int j = 0; j < m; ++j) Cmu.col(node(j)) += mu(j) * Crow.col(j);
    costate_sweep();
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < nu; ++i) H(i, k) += rdiag(i) * U(i, k);
  }

  int count_active() const noexcept {
    int nact = 0;
    for (int j = 0; j < m; ++j) {
      if (cone_start(j) == 1) {
        nact += std::hypot(z(j + 1), z(j + 2)) >= (z(j) - off(j)) * (1.0 - 1e-9) ? 1 : 0;
        j += 2;
      } else {
        nact += (z(j) == hi(j) || z(j) == lo(j)) ? 1 : 0;
      }
    }
    return nact;
  }

  bool polish(int mode, int want) noexcept {
    polish_sign_failed = false;
    if (has_Q) return false;
    ++polish_attempts;
    // controls: mode 0 from Y's pattern (zero / at a bound / free with Y's sign); mode 1 from the
    // dual estimate G = -grad: |G_i| / w_i below 1 zero, above 1 at the bound of G's sign, the
    // (active rows + nx) entries nearest the switching condition |G_i| = w_i free
    int nF = 0;
    if (mode == 0) {
      for (int k = 0; k < N; ++k)
        for (int i = 0; i < nu; ++i) {
          const double y = Y(i, k);
          Ufix(i, k) = 0.0;
          sgn(k * nu + i) = y > 0.0 ? 1.0 : -1.0;
          if (y == 0.0) continue;
          if (y == ulo(i) || y == uhi(i)) {
            Ufix(i, k) = y;
            continue;
          }
          free_idx(nF++) = k * nu + i;
        }
    } else {
      if (!(w.minCoeff() > 0.0)) return false;
      if (want == nx + count_active()) gradient_estimate();  // first of the sequence of sizes
      want = std::min(N * nu, want);
      // the `want` entries with |ratio - 1| smallest: repeated selection over a flag vector
      for (int v = 0; v < N * nu; ++v) piv(v) = 0;
      for (int f = 0; f < want; ++f) {
        int best = -1;
        double bd = 1e300;
        for (int v = 0; v < N * nu; ++v) {
          if (piv(v)) continue;
          const int i = v % nu, k = v / nu;
          if (Y(i, k) != 0.0 && (Y(i, k) == ulo(i) || Y(i, k) == uhi(i))) continue;
          const double dd = std::abs(std::abs(H(i, k)) / w(i) - 1.0);
          if (dd < bd) {
            bd = dd;
            best = v;
          }
        }
        if (best < 0 || bd > 0.5) break;
        piv(best) = 1;
      }
      for (int k = 0; k < N; ++k)
        for (int i = 0; i < nu; ++i) {
          const int v = k * nu + i;
          const double G = -H(i, k);
          sgn(v) = G > 0.0 ? 1.0 : -1.0;
          Ufix(i, k) = 0.0;
          // at a bound only where Y is (the estimate's |G| > w alone is too noisy to fix an
          // entry at a far bound)
          const double y = Y(i, k);
          if (y != 0.0 && (y == ulo(i) || y == uhi(i))) {
            Ufix(i, k) = y;
            sgn(v) = y > 0.0 ? 1.0 : -1.0;
          } else if (piv(v)) {
            free_idx(nF++) = v;
          }
        }
    }
    // active rows: kind 1 upper / equality, -1 lower, 2 cone block (linearized), 3 cone apex
    int nA = 0, nE = 0;
    for (int j = 0; j < m; ++j) {
      if (cone_start(j) == 1) {
        const double t = z(j) - off(j), rr = std::hypot(z(j + 1), z(j + 2));
        if (t <= 1e-14 * (std::abs(off(j)) + 1.0) && rr <= 1e-14 * (std::abs(off(j)) + 1.0)) {
          act_idx(nA) = j;
          act_kind(nA++) = 3;
          nE += 3;
        } else if (rr > 0.0 && std::abs(rr - t) <= 1e-9 * std::max(rr, t)) {
          act_idx(nA) = j;
          act_kind(nA++) = 2;
          nE += 1;
        }
        j += 2;
        continue;
      }
      if (z(j) == hi(j)) {
        act_idx(nA) = j;
        act_kind(nA++) = 1;
        ++nE;
      } else if (z(j) == lo(j)) {
        act_idx(nA) = j;
        act_kind(nA++) = -1;
        ++nE;
      }
    }
    const int n = nF + nE;
    if (mode == 0 && nF > nx + nE) return false;  // Y's pattern not settled (more free than a vertex has)
    if (n == 0 || n > Kkt.rows() || nF == 0) return false;
    // x with the fixed controls (free ones at the current Y for the first linearization)
    Ypol = Ufix;
    for (int f = 0; f < nF; ++f) {
      const int v = free_idx(f), i = v % nu, k = v / nu;
      Ypol(i, k) = Y(i, k) * sgn(v) > 0.0 ? Y(i, k) : 0.0;
    }
    // terminal-cost sensitivity rows (Srow rows m..m+nx-1): e_r' dx_N/dU
    for (int r0 = 0; r0 < nx; ++r0) {
      unit_nx.setZero();
      unit_nx(r0) = 1.0;
      sensitivity_row(m + r0, unit_nx, N);
    }
    for (int pass = 0; pass < 4; ++pass) {
      rollout(Ypol, Xf, false);
      // constraint rows into Srow(0..nE-1) with rhs in kkt_rhs(nF + e)
      int e = 0;
      for (int a = 0; a < nA; ++a) {
        const int j = act_idx(a);
        if (act_kind(a) == 2) {
          // outward normal of the cone at the current point: (-1, x / ||x||) on (s0 - off, s1, s2)
          const double s0 = Crow.col(j).dot(Xf.col(node(j))) - off(j);
          const double s1 = Crow.col(j + 1).dot(Xf.col(node(j))), s2 = Crow.col(j + 2).dot(Xf.col(node(j)));
          double rr = std::hypot(s1, s2);
          double n1, n2;
          if (rr > 0.0) {
            n1 = s1 / rr;
            n2 = s2 / rr;
          } else {
            const double r2 = std::hypot(z(j + 1), z(j + 2));
            n1 = z(j + 1) / r2;
            n2 = z(j + 2) / r2;
            rr = 0.0;
          }
          nrm(j) = -1.0;
          nrm(j + 1) = n1;
          nrm(j + 2) = n2;
          tmp_nx = -Crow.col(j) + n1 * Crow.col(j + 1) + n2 * Crow.col(j + 2);
          sensitivity_row(e, tmp_nx, node(j));
          // n'(s(U) - off) = 0, linearized: current value (rr - s0) plus the change
          kkt_rhs(nF + e) = -(rr - s0);
          ++e;
        } else if (act_kind(a) == 3) {
          for (int q3 = 0; q3 < 3; ++q3) {
            sensitivity_row(e, Crow.col(j + q3), node(j));
            kkt_rhs(nF + e) = (q3 == 0 ? off(j) : 0.0) - Crow.col(j + q3).dot(Xf.col(node(j)));
            ++e;
          }
        } else {
          sensitivity_row(e, Crow.col(j), node(j));
          kkt_rhs(nF + e) = (act_kind(a) == 1 ? hi(j) : lo(j)) - Crow.col(j).dot(Xf.col(node(j)));
          ++e;
        }
      }
      // KKT in the change du of the free controls: [H + diag r, E'; E, 0] [du; lam] = [-grad; rhs]
      // H = G_NF' Qf G_NF, grad = G_NF' Qf (x_N - x_f) + w sign + r u
      tmp_nx = Xf.col(N) - prob.xf;
      tmp_nx2.noalias() = prob.Qf * tmp_nx;
      for (int f = 0; f < nF; ++f) {
        const int v = free_idx(f), i = v % nu, k = v / nu;
        double gr = 0.0;
        for (int r0 = 0; r0 < nx; ++r0) gr += Srow(m + r0, v) * tmp_nx2(r0);
        const double u = Ypol(i, k);
        gr += w(i) * sgn(v) + rdiag(i) * u;
        kkt_rhs(f) = -gr;
        for (int f2 = 0; f2 <= f; ++f2) {
          const int v2 = free_idx(f2);
          double h = 0.0;
          for (int r0 = 0; r0 < nx; ++r0)
            for (int r1 = 0; r1 < nx; ++r1) h += Srow(m + r0, v) * prob.Qf(r0, r1) * Srow(m + r1, v2);
          Kkt(f, f2) = Kkt(f2, f) = h + (f == f2 ? rdiag(i) : 0.0);
        }
        for (int e2 = 0; e2 < nE; ++e2) Kkt(nF + e2, f) = Kkt(f, nF + e2) = Srow(e2, v);
      }
      for (int e1 = 0; e1 < nE; ++e1)
        for (int e2 = 0; e2 < nE; ++e2) Kkt(nF + e1, nF + e2) = 0.0;
      // regularized factorization (quasi-definite), then iterative refinement on the exact system
      double dmax = 1e-300;
      for (int f = 0; f < nF; ++f) dmax = std::max(dmax, std::abs(Kkt(f, f)));
      double smax = 1e-300;
      for (int e1 = 0; e1 < nE; ++e1)
        for (int f = 0; f < nF; ++f) smax = std::max(smax, std::abs(Kkt(nF + e1, f)));
      const double delta = 1e-11 * std::max(dmax, smax);
      // balanced (ipm_polish): the constraint block's shift on its own scale (its Schur complement is
      // ~smax^2 / dmax; one shift for both blocks, with dmax >> smax, left the rows nearly unimposed)
      const double delta_e = polish_balanced ? 1e-11 * smax * smax / dmax : delta;
      // and a proximal term kept in the refined system: the L1 optimum is often not unique (impulse
      // traded between entries at no cost), its KKT then singular; the prox picks the optimal point
      // nearest the IPM's plan instead of refining towards an arbitrary far one
      if (polish_balanced)
        for (int f = 0; f < nF; ++f) Kkt(f, f) += 1e-9 * dmax;
      Kkt0.topLeftCorner(n, n) = Kkt.topLeftCorner(n, n);
      for (int f = 0; f < nF; ++f) Kkt0(f, f) += delta;
      for (int e1 = 0; e1 < nE; ++e1) Kkt0(nF + e1, nF + e1) -= delta_e;
      if (!lu(n)) return false;
      kkt_sol.head(n) = kkt_rhs.head(n);
      lu_solve(n, kkt_sol);
      for (int ref = 0; ref < 5; ++ref) {
        kkt_res.head(n) = kkt_rhs.head(n);
        kkt_res.head(n).noalias() -= Kkt.topLeftCorner(n, n) * kkt_sol.head(n);
        lu_solve(n, kkt_res);
        kkt_sol.head(n) += kkt_res.head(n);
      }
      if (!kkt_sol.head(n).allFinite()) return false;
      for (int f = 0; f < nF; ++f) {
        const int v = free_idx(f);
        Ypol(v % nu, v / nu) += kkt_sol(f);
      }
      bool has_cone = false;
      for (int a = 0; a < nA; ++a) has_cone = has_cone || act_kind(a) == 2;
      if (!has_cone) break;
    }
    // sign and box of the free entries must be kept
    for (int f = 0; f < nF; ++f) {
      const int v = free_idx(f), i = v % nu, k = v / nu;
      const double y1 = Ypol(i, k);
      if ((w(i) > 0.0 && y1 * sgn(v) <= 0.0) || y1 < ulo(i) || y1 > uhi(i)) {
        polish_sign_failed = true;  // Ypol keeps the KKT candidate (ipm_polish fixes those entries)
        return false;
      }
    }
    // row multipliers (KKT lam; stationarity grad + E' lam = 0 with the ADMM's sign convention)
    mu_pol.setZero();
    int e = 0;
    for (int a = 0; a < nA; ++a) {
      const int j = act_idx(a);
      if (act_kind(a) == 2) {
        const double l = kkt_sol(nF + e++);
        for (int q3 = 0; q3 < 3; ++q3) mu_pol(j + q3) = l * nrm(j + q3);
      } else if (act_kind(a) == 3) {
        for (int q3 = 0; q3 < 3; ++q3) mu_pol(j + q3) = kkt_sol(nF + e++);
      } else {
        mu_pol(j) = kkt_sol(nF + e++);
      }
    }
    return true;
  }

  // ---- dual recovery on a converged plan (Up, Xp): least-squares row multipliers on its active set.
  // Where the active rows are degenerate (a closing-velocity wedge pinned by box rows) the dual optimal
  // face is unbounded and the IPM's multipliers run off along it while its plan converges; the
  // near-minimum-norm multipliers solving the stationarity of the free controls are then a bounded
  // point of that face. Active set: rows whose slack, in control units (e_j x slack), is <= 1e-6 of the
  // plan's largest control; rows of the wrong sign leave it, controls whose allowed interval for
  // h = grad of the smooth part + S' mu is violated join the equations at the violated end (an
  // active-set loop of at most kDualPasses passes). Only proposes mu: the caller certifies with the
  // Fenchel bound, which holds for any mu (weak duality), so a poor recovery costs only the attempt.
  bool recover_dual(const Eigen::MatrixXd& Up, const Eigen::MatrixXd& Xp, Eigen::VectorXd& out) noexcept {
    constexpr int kDualPasses = 8;
    const int nv = N * nu;
    double umag = 0.0;
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < nu; ++i) umag = std::max(umag, std::abs(Up(i, k)));
    if (!(umag > 0.0) || !std::isfinite(umag)) return false;
    const double tz = 1e-7 * umag;
    // allowed interval [dr_hmin, dr_hmax] of h_v (-h_v in the subdifferential of the control part)
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < nu; ++i) {
        const int v = k * nu + i;
        const double u = Up(i, k);
        double a, b;
        if (std::abs(u) <= tz) {
          a = -w(i);
          b = w(i);
          if (ulo(i) >= -tz) a = -kInf;  // lower bound at 0: one-sided
          if (uhi(i) <= tz) b = kInf;
        } else {
          const double g = (u > 0.0 ? w(i) : -w(i)) + rdiag(i) * u;
          a = b = -g;
          if (u > 0.0 && uhi(i) - u <= tz) a = -kInf;  // at the upper bound: h <= -(w + r u)
          if (u < 0.0 && u - ulo(i) <= tz) b = kInf;
        }
        dr_hmin(v) = a;
        dr_hmax(v) = b;
        dr_eq(v) = a == b ? 1 : 0;
      }
    // gradient of the smooth part through the costates
    Cmu.setZero();
    for (int k = 1; k <= N; ++k) {
      if (k < N && !has_Q) continue;
      tmp_nx = Xp.col(k) - prob.xf;
      Cmu.col(k).noalias() = (k < N ? prob.Q : prob.Qf) * tmp_nx;
    }
    costate_sweep();
    dr_hq = H;
    // active rows: kind 1 upper, -1 lower, 0 equality (free sign), 2 cone boundary (scalar >= 0)
    int nA = 0;
    for (int j = 0; j < m; ++j) {
      const double e = escale(j);
      const int nd = node(j);
      if (cone_start(j) == 1) {
        const double t = Crow.col(j).dot(Xp.col(nd)) - off(j);
        const double s1 = Crow.col(j + 1).dot(Xp.col(nd)), s2 = Crow.col(j + 2).dot(Xp.col(nd));
        const double rr = std::hypot(s1, s2);
        if (rr > 0.0 && e * (t - rr) <= 1e-6 * umag) {
          nrm(j) = -1.0;
          nrm(j + 1) = s1 / rr;
          nrm(j + 2) = s2 / rr;
          tmp_nx = -Crow.col(j) + nrm(j + 1) * Crow.col(j + 1) + nrm(j + 2) * Crow.col(j + 2);
          sensitivity_row(nA, tmp_nx, nd);
          act_idx(nA) = j;
          act_kind(nA++) = 2;
        }
        j += 2;
        continue;
      }
      const double rv = Crow.col(j).dot(Xp.col(nd));
      int kind = -2;
      if (lo(j) == hi(j))
        kind = 0;
      else if (std::isfinite(hi(j)) && e * (hi(j) - rv) <= 1e-6 * umag)
        kind = 1;
      else if (std::isfinite(lo(j)) && e * (rv - lo(j)) <= 1e-6 * umag)
        kind = -1;
      if (kind == -2) continue;
      sensitivity_row(nA, Crow.col(j), nd);
      act_idx(nA) = j;
      act_kind(nA++) = kind;
    }
    if (nA == 0) return false;
    for (int a = 0; a < nA; ++a) dr_on(a) = 1;
    dr_lam.head(nA).setZero();
    for (int pass = 0; pass < kDualPasses; ++pass) {
      // normal equations of min sum_eq (S_v' lam - (target_v - hq_v))^2 over the enabled rows
      int nE = 0;
      for (int a = 0; a < nA; ++a)
        if (dr_on(a)) dr_pos(nE++) = a;
      if (nE == 0) return false;
      auto G = dr_G.topLeftCorner(nE, nE);
      G.setZero();
      auto rhs = dr_rhs.head(nE);
      rhs.setZero();
      for (int v = 0; v < nv; ++v) {
        if (!dr_eq(v)) continue;
        const double tgt = dr_hmin(v) == dr_hmax(v) ? dr_hmin(v) : dr_tgt(v);
        const double bv = tgt - dr_hq(v % nu, v / nu);
        for (int a = 0; a < nE; ++a) {
          const double sa = Srow(dr_pos(a), v);
          if (sa == 0.0) continue;
          rhs(a) += sa * bv;
          for (int b = 0; b <= a; ++b) G(a, b) += sa * Srow(dr_pos(b), v);
        }
      }
      double gmax = 0.0;
      for (int a = 0; a < nE; ++a) gmax = std::max(gmax, G(a, a));
      if (!(gmax > 0.0) || !std::isfinite(gmax)) return false;
      // Tikhonov eps, iterated (proximal) so that the solution tends to the minimum-norm least squares
      const double eps = 1e-12 * gmax;
      for (int a = 0; a < nE; ++a) G(a, a) += eps;
      if (!detail::cholesky_factor_inplace<Eigen::Dynamic>(G)) return false;
      auto x = dr_x.head(nE);
      x.setZero();
      for (int ref = 0; ref < 4; ++ref) {
        auto y = dr_y.head(nE);
        y = rhs + eps * x;
        detail::cholesky_solve_inplace<Eigen::Dynamic>(G, y);
        x = y;
      }
      if (!x.allFinite()) return false;
      dr_lam.head(nA).setZero();
      for (int a = 0; a < nE; ++a) dr_lam(dr_pos(a)) = x(a);
      bool changed = false;
      for (int a = 0; a < nA; ++a) {  // wrong signs leave the active set
        if (!dr_on(a)) continue;
        const int kd = act_kind(a);
        const double l = dr_lam(a);
        if ((kd == 1 || kd == 2) && l < 0.0) {
          dr_on(a) = 0;
          changed = true;
        } else if (kd == -1 && l > 0.0) {
          dr_on(a) = 0;
          changed = true;
        }
      }
      if (changed) continue;
      // h = hq + S' lam; controls outside their interval join the equations at the violated end
      for (int v = 0; v < nv; ++v) {
        if (dr_eq(v)) continue;
        double h = dr_hq(v % nu, v / nu);
        for (int a = 0; a < nA; ++a) h += dr_lam(a) * Srow(a, v);
        const double slack = 1e-12 * (std::abs(w(v % nu)) + std::abs(h));
        if (h < dr_hmin(v) - slack) {
          dr_eq(v) = 1;
          dr_tgt(v) = dr_hmin(v);
          changed = true;
        } else if (h > dr_hmax(v) + slack) {
          dr_eq(v) = 1;
          dr_tgt(v) = dr_hmax(v);
          changed = true;
        }
      }
      if (!changed) break;
    }
    out.setZero();
    for (int a = 0; a < nA; ++a) {
      const int j = act_idx(a);
      if (act_kind(a) == 2) {
        for (int q3 = 0; q3 < 3; ++q3) out(j + q3) = dr_lam(a) * nrm(j + q3);
      } else {
        out(j) = dr_lam(a);
      }
    }
    return out.allFinite();
  }

  // Active-set polish of a converged interior-point plan Up (flown Xp): its near-zero and near-bound
  // controls (tzr of the largest control) and its rows within ta of their bounds (e_j x slack, control
  // units, relative to the largest control) are snapped onto them, and polish(0) solves the
  // equality-constrained KKT on that active set (rank-deficient active rows regularized) into Ypol /
  // mu_pol. The IPM's plan sits a little inside rows whose multipliers are small (seen: slack 6e-6
  // relative, Clarabel's multiplier 7e-3 against ~1e2 for the others), so no multiplier computed at
  // that plan certifies it; the polished plan lies on them. Y and z (the ADMM's iterate) are kept in
  // Yprev / zprev (the ADMM's per-iteration scratch) and restored. The caller certifies.
  bool ipm_polish(const Eigen::MatrixXd& Up, const Eigen::MatrixXd& Xp, double ta, double tzr) noexcept {
    const double umag = Up.cwiseAbs().maxCoeff();
    if (!(umag > 0.0) || !std::isfinite(umag)) return false;
    const double tz = tzr * umag;
    Yprev = Y;
    zprev = z;
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < nu; ++i) {
        double u = Up(i, k);
        if (std::abs(u) <= tz)
          u = 0.0;
        else if (uhi(i) - u <= tz)
          u = uhi(i);
        else if (u - ulo(i) <= tz)
          u = ulo(i);
        Y(i, k) = u;
      }
    rows_of(Xp, z);
    // candidates: rows within ta of a bound (cones: of their surface), with that distance in nrm
    int nc = 0;
    for (int j = 0; j < m; ++j) {
      const double e = escale(j);
      double dist = kInf;
      if (cone_start(j) == 1) {
        const double t = z(j) - off(j), rr = std::hypot(z(j + 1), z(j + 2));
        if (t > 0.0 && rr > 0.0) dist = e * std::abs(t - rr);
      } else if (std::isfinite(hi(j)) && std::abs(hi(j) - z(j)) <= std::abs(z(j) - lo(j))) {
        dist = e * std::abs(hi(j) - z(j));
      } else if (std::isfinite(lo(j))) {
        dist = e * std::abs(z(j) - lo(j));
      }
      if (dist <= ta * umag) {
        act_idx(nc) = j;
        nrm(nc++) = dist;
      }
      if (cone_start(j) == 1) j += 2;
    }
    // nearest first, each kept only when its sensitivity on the free controls is independent of the
    // rows kept before it (Gram-Schmidt, 1e-9 relative): degenerate active rows (a wedge pinned by box
    // rows) make the KKT singular with slightly inconsistent right-hand sides otherwise
    int nk = 0;
    for (int c = 0; c < nc; ++c) {
      int best = c;
      for (int c2 = c + 1; c2 < nc; ++c2)
        if (nrm(c2) < nrm(best)) best = c2;
      std::swap(act_idx(c), act_idx(best));
      std::swap(nrm(c), nrm(best));
      const int j = act_idx(c);
      if (cone_start(j) == 1) {
        const double rr = std::hypot(z(j + 1), z(j + 2));
        tmp_nx = -Crow.col(j) + (z(j + 1) / rr) * Crow.col(j + 1) + (z(j + 2) / rr) * Crow.col(j + 2);
      } else {
        tmp_nx = Crow.col(j);
      }
      sensitivity_row(nk, tmp_nx, node(j));
      for (int k = 0; k < N; ++k)  // only the free controls move in the KKT
        for (int i = 0; i < nu; ++i) {
          const double y = Y(i, k);
          if (y == 0.0 || y == ulo(i) || y == uhi(i)) Srow(nk, k * nu + i) = 0.0;
        }
      const double n0 = Srow.row(nk).norm();
      if (!(n0 > 0.0)) continue;
      for (int b = 0; b < nk; ++b) {
        const double dot = Srow.row(nk).dot(Srow.row(b));
        Srow.row(nk) -= dot * Srow.row(b);
      }
      const double n1 = Srow.row(nk).norm();
      if (!(n1 > 1e-9 * n0)) continue;
      Srow.row(nk) /= n1;
      act_kind(nk++) = j;  // kept
    }
    for (int b = 0; b < nk; ++b) {
      const int j = act_kind(b);
      if (cone_start(j) == 1) {
        const double t = z(j) - off(j), rr = std::hypot(z(j + 1), z(j + 2));
        z(j + 1) *= t / rr;
        z(j + 2) *= t / rr;
      } else if (std::isfinite(hi(j)) && std::abs(hi(j) - z(j)) <= std::abs(z(j) - lo(j))) {
        z(j) = hi(j);
      } else {
        z(j) = lo(j);
      }
    }
    // the others just off their bounds: polish() takes a row as active only when z sits on it exactly
    for (int j = 0; j < m; ++j) {
      if (cone_start(j) == 1) {
        j += 2;
        continue;
      }
      bool kept = false;
      for (int b = 0; b < nk && !kept; ++b) kept = act_kind(b) == j;
      if (kept) continue;
      if (z(j) == hi(j)) z(j) = std::nextafter(hi(j), -kInf);
      if (z(j) == lo(j)) z(j) = std::nextafter(lo(j), kInf);
    }
    // a free entry the KKT step takes through zero (or out of the box) is fixed there and the KKT
    // solved again (an active-set step; at most 4 rounds)
    bool ok = false;
    polish_balanced = true;
    for (int round = 0; round < 4 && !ok; ++round) {
      ok = polish(0, 0);
      if (ok || !polish_sign_failed || !Ypol.allFinite()) break;
      for (int k = 0; k < N; ++k)
        for (int i = 0; i < nu; ++i) {
          const double y = Y(i, k), y1 = Ypol(i, k);
          if (y == 0.0 || y == ulo(i) || y == uhi(i)) continue;
          if (w(i) > 0.0 && y1 * y <= 0.0)
            Y(i, k) = 0.0;
          else if (y1 > uhi(i))
            Y(i, k) = uhi(i);
          else if (y1 < ulo(i))
            Y(i, k) = ulo(i);
        }
    }
    polish_balanced = false;
    Y = Yprev;
    z = zprev;
    return ok;
  }

  const Eigen::MatrixXd& A(int k) const { return prob.dynamics.A_at(k); }
  const Eigen::MatrixXd& B(int k) const { return prob.dynamics.B_at(k); }
  bool has_c() const { return !prob.dynamics.c.empty(); }
  const Eigen::VectorXd& c(int k) const {
    return prob.dynamics.c.size() == 1 ? prob.dynamics.c[0] : prob.dynamics.c[k];
  }

  // ---- row scaling kappa_j = 1 / ||c_j' dx_node/dU||^2 (cone blocks: one value, their largest)
  void compute_kappa_row(int j) noexcept {
    // backward: v' = c_j'; sum over k < node of ||v' B_k||^2 with v' <- v' A_k
    tmp_nx = Crow.col(j);
    double acc = 0.0;
    for (int k = node(j) - 1; k >= 0; --k) {
      g_nu.noalias() = B(k).transpose() * tmp_nx;
      acc += g_nu.squaredNorm();
      tmp_nx2.noalias() = A(k).transpose() * tmp_nx;
      tmp_nx = tmp_nx2;
    }
    kappa(j) = acc > 0.0 && std::isfinite(acc) ? 1.0 / acc : 1.0;
    if (lo(j) == hi(j)) kappa(j) *= kEqualityRhoFactor;
  }
  void compute_kappa() noexcept {
    for (int j = 0; j < m; ++j) compute_kappa_row(j);
    for (int j = 0; j < m; ++j) {
      if (cone_start(j) != 1) continue;
      const double kmin = std::min({kappa(j), kappa(j + 1), kappa(j + 2)});
      kappa(j) = kappa(j + 1) = kappa(j + 2) = kmin;
    }
  }

  // Equilibration as AdmmSolver's (admm_scaling.cpp): u = D_u u~ per axis and the cost times c
  // (powers of two, exact), so that the largest scaled L1 weight is 1 and the mean curvature of the
  // terminal cost along the control axes is 256. States are not scaled (the rows stay in state units).
  Eigen::VectorXd du;
  double cscale = 1.0;
  void equilibrate() {
    du = Eigen::VectorXd::Ones(nu);
    cscale = 1.0;
    const bool qf_zero = prob.Qf.cwiseAbs().maxCoeff() == 0.0;
    const Eigen::MatrixXd W = qf_zero ? Eigen::MatrixXd::Identity(nx, nx) : prob.Qf;
    Eigen::VectorXd h = Eigen::VectorXd::Zero(nu);
    Eigen::MatrixXd Phi = Eigen::MatrixXd::Identity(nx, nx);
    for (int k = N - 1; k >= 0; --k) {
      const Eigen::MatrixXd MB = Phi * B(k);
      h += (MB.transpose() * W * MB).diagonal();
      Phi = (Phi * A(k)).eval();
    }
    h /= static_cast<double>(N);
    h += rdiag;
    if (!h.allFinite() || !(h.maxCoeff() > 0.0)) return;
    const double hmax = h.maxCoeff();
    Eigen::VectorXd dp(nu);
    const bool by_weight = w.minCoeff() > 0.0;
    for (int i = 0; i < nu; ++i)
      dp(i) = by_weight ? 1.0 / w(i) : 1.0 / std::sqrt(h(i) > 1e-12 * hmax ? h(i) : hmax);
    constexpr double kCurvature = 256.0;
    const double hbar = (h.array() * dp.array().square()).mean();
    double wmax = 0.0;
    for (int i = 0; i < nu; ++i) wmax = std::max(wmax, dp(i) * w(i));
    double a = 1.0, c = kCurvature / hbar;
    if (wmax > 0.0) {
      a = kCurvature * wmax / hbar;
      c = 1.0 / (a * wmax);
    }
    const auto pow2 = [](double v) { return std::exp2(std::round(std::log2(std::clamp(v, 1e-150, 1e150)))); };
    Eigen::VectorXd d2 = a * dp;
    for (int i = 0; i < nu; ++i) d2(i) = pow2(d2(i));
    const double c2 = pow2(c);
    if (!d2.allFinite() || !std::isfinite(c2)) return;
    du = d2;
    cscale = c2;
    for (auto& Bk : prob.dynamics.B) Bk = (Bk * du.asDiagonal()).eval();
    prob.Qf *= cscale;
    if (has_Q) prob.Q *= cscale;
    rdiag = cscale * rdiag.cwiseProduct(du).cwiseProduct(du);
    w = cscale * w.cwiseProduct(du);
    ulo = ulo.cwiseQuotient(du);
    uhi = uhi.cwiseQuotient(du);
  }

  void set_rho_rows() noexcept {
    rho_row = rho_x * kappa;
    escale = kappa.cwiseSqrt();
  }

  // ---- per-node state weights and Riccati factorization with R = rho I (diag R is in the prox)
  bool factor() noexcept {
    set_rho_rows();
    Qx.setZero();
    for (int k = 1; k < N; ++k)
      if (has_Q) Qx.middleCols(k * nx, nx) = prob.Q;
    Qx.middleCols(N * nx, nx) = prob.Qf;
    for (int j = 0; j < m; ++j)  // rank-one updates, element-wise (no temporary)
      for (int c2 = 0; c2 < nx; ++c2)
        for (int r2 = 0; r2 < nx; ++r2) Qx(r2, node(j) * nx + c2) += rho_row(j) * Crow(r2, j) * Crow(c2, j);
    P.middleCols(N * nx, nx) = Qx.middleCols(N * nx, nx);
    for (int k = N - 1; k >= 0; --k) {
      auto Pn = P.middleCols((k + 1) * nx, nx);
      PB.middleCols(k * nu, nu).noalias() = Pn * B(k);
      Quu.noalias() = B(k).transpose() * PB.middleCols(k * nu, nu);
      Quu.diagonal().array() += rho;
      llt.compute(Quu);
      if (llt.info() != Eigen::Success) return false;
      auto Qi = QuuInv.middleCols(k * nu, nu);
      Qi = Inu;
      llt.solveInPlace(Qi);
      tmp_nu_nx.noalias() = PB.middleCols(k * nu, nu).transpose() * A(k);  // Qux = B'PA
      K.middleCols(k * nx, nx).noalias() = Qi * tmp_nu_nx;
      Acl.middleCols(k * nx, nx) = A(k);
      Acl.middleCols(k * nx, nx).noalias() -= B(k) * K.middleCols(k * nx, nx);
      // P_k = Qx_k + A' P A - Qux' K
      tmp_nx_nx2.noalias() = Pn * A(k);
      tmp_nx_nx.noalias() = A(k).transpose() * tmp_nx_nx2;
      tmp_nx_nx.noalias() -= tmp_nu_nx.transpose() * K.middleCols(k * nx, nx);
      tmp_nx_nx += Qx.middleCols(k * nx, nx);
      P.middleCols(k * nx, nx) = 0.5 * (tmp_nx_nx + tmp_nx_nx.transpose());
      if (!P.middleCols(k * nx, nx).allFinite()) return false;
    }
    rho_factored = rho;
    rho_x_factored = rho_x;
    ++factorizations;
    return true;
  }

  // ---- affine sweep with the cached gains and rollout: X, U from q (nx x N+1), r (nu x N)
  void sweep() noexcept {
    p = q.col(N);
    for (int k = N - 1; k >= 0; --k) {
      auto Pn = P.middleCols((k + 1) * nx, nx);
      wv = p;
      if (has_c()) wv.noalias() += Pn * c(k);
      g_nu = r.col(k);
      g_nu.noalias() += B(k).transpose() * wv;
      d.col(k).noalias() = QuuInv.middleCols(k * nu, nu) * g_nu;
      // p_k = q_k + Acl'(w - P B d) + K'(rho d - r)
      wv.noalias() -= PB.middleCols(k * nu, nu) * d.col(k);
      p = q.col(k);
      p.noalias() += Acl.middleCols(k * nx, nx).transpose() * wv;
      g_nu = rho * d.col(k) - r.col(k);
      p.noalias() += K.middleCols(k * nx, nx).transpose() * g_nu;
    }
    X.col(0) = prob.x0;
    for (int k = 0; k < N; ++k) {
      U.col(k).noalias() = -K.middleCols(k * nx, nx) * X.col(k);
      U.col(k) -= d.col(k);
      X.col(k + 1).noalias() = A(k) * X.col(k);
      X.col(k + 1).noalias() += B(k) * U.col(k);
      if (has_c()) X.col(k + 1) += c(k);
    }
  }

  void rollout(const Eigen::MatrixXd& Uc, Eigen::MatrixXd& Xo, bool zero) noexcept {
    if (nx == 6 && nu == 3)  // the CW case: fixed-size products (the IPM's loop rolls out every step)
      rollout_t<6, 3>(Uc, Xo, zero);
    else
      rollout_t<Eigen::Dynamic, Eigen::Dynamic>(Uc, Xo, zero);
  }
  template <int NX, int NU>
  void rollout_t(const Eigen::MatrixXd& Uc, Eigen::MatrixXd& Xo, bool zero) noexcept {
    using VX = Eigen::Matrix<double, NX, 1>;
    Xo.col(0) = prob.x0;
    for (int k = 0; k < N; ++k) {
      Eigen::Map<VX> xn(Xo.col(k + 1).data(), nx);
      xn.noalias() = Eigen::Map<const Eigen::Matrix<double, NX, NX>>(A(k).data(), nx, nx) *
                     Eigen::Map<const VX>(Xo.col(k).data(), nx);
      if (!zero)
        xn.noalias() += Eigen::Map<const Eigen::Matrix<double, NX, NU>>(B(k).data(), nx, nu) *
                        Eigen::Map<const Eigen::Matrix<double, NU, 1>>(Uc.col(k).data(), nu);
      if (has_c()) xn += Eigen::Map<const VX>(c(k).data(), nx);
    }
  }

  void rows_of(const Eigen::MatrixXd& Xs, Eigen::VectorXd& out) const noexcept {
    for (int j = 0; j < m; ++j) out(j) = Crow.col(j).dot(Xs.col(node(j)));
  }

  // projection of v onto K (in place)
  void project(Eigen::VectorXd& v) const noexcept {
    for (int j = 0; j < m; ++j) {
      if (cone_start(j) == 1) {
        double t = v(j) - off(j), x1 = v(j + 1), x2 = v(j + 2);
        project_soc(t, x1, x2);
        v(j) = t + off(j);
        v(j + 1) = x1;
        v(j + 2) = x2;
        j += 2;
      } else {
        v(j) = std::min(std::max(v(j), lo(j)), hi(j));
      }
    }
  }

  // largest violation of the rows by the row values sv (state units; cones: distance-like)
  double violation_of(const Eigen::VectorXd& sv) const noexcept {
    double viol = 0.0;
    for (int j = 0; j < m; ++j) {
      if (cone_start(j) == 1) {
        const double e = std::hypot(sv(j + 1), sv(j + 2)) - (sv(j) - off(j));
        viol = std::max(viol, e * cosang(j));
        j += 2;
      } else {
        viol = std::max({viol, sv(j) - hi(j), lo(j) - sv(j)});
      }
    }
    return viol;
  }

  double prox(double v, int i) const noexcept {
    // argmin w|y| + r/2 y^2 + rho/2 (y - v)^2 on [lo, hi]
    const double a = rho * v;
    const double sft = a > w(i) ? a - w(i) : (a < -w(i) ? a + w(i) : 0.0);
    return std::min(std::max(sft / (rdiag(i) + rho), ulo(i)), uhi(i));
  }

  double objective(const Eigen::MatrixXd& Xs, const Eigen::MatrixXd& Us) noexcept {
    double J = 0.0;
    for (int k = 1; k <= N; ++k) {
      if (k < N && !has_Q) continue;
      tmp_nx = Xs.col(k) - prob.xf;
      tmp_nx2.noalias() = (k < N ? prob.Q : prob.Qf) * tmp_nx;
      J += 0.5 * tmp_nx.dot(tmp_nx2);
    }
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < nu; ++i) {
        const double u = Us(i, k);
        J += w(i) * std::abs(u) + 0.5 * rdiag(i) * u * u;
      }
    return J;
  }

  // lam_clean <- lam with the signs a finite support function needs (intervals) and cone blocks in
  // the polar cone; returns the support function sigma_K(lam_clean).
  double clean_and_support(const Eigen::VectorXd& lam) noexcept {
    double sig = 0.0;
    for (int j = 0; j < m; ++j) {
      if (cone_start(j) == 1) {
        // polar of the SOC is -SOC: lam in -SOC <=> -lam in SOC
        double t = -lam(j), x1 = -lam(j + 1), x2 = -lam(j + 2);
        project_soc(t, x1, x2);
        lam_clean(j) = -t;
        lam_clean(j + 1) = -x1;
        lam_clean(j + 2) = -x2;
        sig += lam_clean(j) * off(j);
        j += 2;
      } else {
        double l = lam(j);
        if (l > 0.0 && !std::isfinite(hi(j))) l = 0.0;
        if (l < 0.0 && !std::isfinite(lo(j))) l = 0.0;
        lam_clean(j) = l;
        sig += l > 0.0 ? l * hi(j) : (l < 0.0 ? l * lo(j) : 0.0);
      }
    }
    return sig;
  }

  // H (nu x N) = sum_k M_k' mu_k for per-node state multipliers Cmu (nx x N+1): h_k = B_k' pi_{k+1},
  // pi_k = Cmu_k + A_k' pi_{k+1}, pi_N = Cmu_N.
  void costate_sweep() noexcept {
    if (nx == 6 && nu == 3)
      costate_sweep_t<6, 3>();
    else
      costate_sweep_t<Eigen::Dynamic, Eigen::Dynamic>();
  }
  template <int NX, int NU>
  void costate_sweep_t() noexcept {
    using VX = Eigen::Matrix<double, NX, 1>;
    Eigen::Map<VX> pi(tmp_nx.data(), nx), pi2(tmp_nx2.data(), nx);
    pi = Eigen::Map<const VX>(Cmu.col(N).data(), nx);
    for (int k = N - 1; k >= 0; --k) {
      Eigen::Map<Eigen::Matrix<double, NU, 1>>(H.col(k).data(), nu).noalias() =
          Eigen::Map<const Eigen::Matrix<double, NX, NU>>(B(k).data(), nx, nu).transpose() * pi;
      pi2.noalias() = Eigen::Map<const Eigen::Matrix<double, NX, NX>>(A(k).data(), nx, nx).transpose() * pi;
      pi = pi2 + Eigen::Map<const VX>(Cmu.col(k).data(), nx);
    }
  }

  // g*(v) per entry of the control part
  double gconj(double v, int i) const noexcept {
    double u;
    if (rdiag(i) > 0.0) {
      const double sft = v > w(i) ? v - w(i) : (v < -w(i) ? v + w(i) : 0.0);
      u = std::min(std::max(sft / rdiag(i), ulo(i)), uhi(i));
    } else {
      u = v > w(i) ? uhi(i) : (v < -w(i) ? ulo(i) : 0.0);
      if (!std::isfinite(u)) return kInf;
    }
    if (u == 0.0) return 0.0;
    return v * u - w(i) * std::abs(u) - 0.5 * rdiag(i) * u * u;
  }

  // Fenchel dual bound D <= optimum from the multipliers mu (rows), at the flown trajectory Xf.
  double dual_bound(const Eigen::VectorXd& muv) noexcept {
    const double sig = clean_and_support(muv);
    // per-node multipliers: Q_k e_k + C_k' lam
    Cmu.setZero();
    double F2 = 0.0, L = -sig;
    for (int k = 1; k <= N; ++k) {
      if (k < N && !has_Q) continue;
      tmp_nx = Xf.col(k) - prob.xf;
      tmp_nx2.noalias() = (k < N ? prob.Q : prob.Qf) * tmp_nx;
      F2 += 0.5 * tmp_nx.dot(tmp_nx2);
      Cmu.col(k) += tmp_nx2;
      L -= tmp_nx2.dot(prob.xf);
    }
    for (int j = 0; j < m; ++j) Cmu.col(node(j)) += lam_clean(j) * Crow.col(j);
    rollout(Y, Xfree, true);
    for (int k = 1; k <= N; ++k) L += Cmu.col(k).dot(Xfree.col(k));
    costate_sweep();
    // largest s with g*(-s h) finite
    double smax = 2.0;
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < nu; ++i) {
        if (rdiag(i) > 0.0) continue;
        const double v = -H(i, k);
        if (v > w(i) && !std::isfinite(uhi(i))) smax = std::min(smax, w(i) / v);
        if (v < -w(i) && !std::isfinite(ulo(i))) smax = std::min(smax, w(i) / -v);
      }
    auto D = [&](double sc) {
      double gsum = 0.0;
      for (int k = 0; k < N; ++k)
        for (int i = 0; i < nu; ++i) gsum += gconj(-sc * H(i, k), i);
      return sc * L - sc * sc * F2 - gsum;
    };
    // D is concave and piecewise quadratic in s: its maximizer from its kinks (dual_line.hpp),
    // evaluated here; D(1) (the multipliers as given) and D(0) = 0 kept as candidates
    const double s_star = concave_dual_argmax(H, w, rdiag, ulo, uhi, L, F2, smax, kinks);
    const double best = std::max({D(s_star), D(std::min(1.0, smax)), D(0.0)});
    return std::isfinite(best) ? best : -kInf;
  }

  // Farkas test of the direction lam (rows): for every U in the box, lam' C x(U) > sigma_K(lam)
  bool infeasibility_certificate(const Eigen::VectorXd& lam) noexcept {
    if (!(lam.norm() > 0.0) || !lam.allFinite()) return false;
    const double sig = clean_and_support(lam);
    if (!(lam_clean.norm() > 0.0)) return false;
    Cmu.setZero();
    for (int j = 0; j < m; ++j) Cmu.col(node(j)) += lam_clean(j) * Crow.col(j);
    rollout(Y, Xfree, true);
    double val = 0.0, mag = std::abs(sig);
    for (int k = 1; k <= N; ++k) {
      const double t = Cmu.col(k).dot(Xfree.col(k));
      val += t;
      mag += std::abs(t);
    }
    costate_sweep();
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < nu; ++i) {
        const double h = H(i, k);
        if (h == 0.0) continue;
        const double t = std::min(h * ulo(i), h * uhi(i));
        if (!std::isfinite(t)) return false;
        val += t;
        mag += std::abs(t);
      }
    return val - sig > 1e-9 * mag && val - sig > 0.0;
  }
};

}  // namespace detail

using detail::StateAdmmWorkspace;

namespace {

void check_nodes(const std::vector<int>& nodes, int N, const std::string& name) {
  core::require(!nodes.empty(), name, "must list at least one node");
  for (int n : nodes)
    core::require(
        n >= 1 && n <= N, name,
        "nodes must be in 1..N = " + std::to_string(N) + " (x_0 is given), got " + std::to_string(n));
}

void check_index(const std::array<int, 3>& idx, int nx, const std::string& name) {
  for (int i : idx)
    core::require(i >= 0 && i < nx, name, "state indices must be in 0..nx-1 = " + std::to_string(nx - 1));
}

struct RowBuilder {
  int nx;
  std::vector<Eigen::VectorXd> c;
  std::vector<int> node, cone;
  std::vector<double> lo, hi, off, cosang;
  void add(int k, Eigen::VectorXd a, double l, double h) {
    const double nrm = a.norm();
    c.push_back(a / nrm);
    node.push_back(k);
    cone.push_back(0);
    lo.push_back(l / nrm);
    hi.push_back(h / nrm);
    off.push_back(0.0);
    cosang.push_back(1.0);
  }
};

}  // namespace

StateConstrainedAdmm::StateConstrainedAdmm(const LtvProblem& problem, const StateConstraints& cons,
                                           const AdmmSettings& settings)
    : ws_(std::make_unique<StateAdmmWorkspace>()) {
  settings.validate();
  auto& w = *ws_;
  w.prob = problem;
  w.st = settings;
  problem.dynamics.validate();
  const int nx = problem.dynamics.nx(), nu = problem.dynamics.nu(), N = problem.dynamics.horizon;
  w.nx = nx;
  w.nu = nu;
  w.N = N;
  core::require(problem.x0.size() == nx && problem.x0.allFinite(), "x0", "must have nx finite entries");
  if (w.prob.xf.size() == 0) w.prob.xf = Eigen::VectorXd::Zero(nx);
  core::require(w.prob.xf.size() == nx && w.prob.xf.allFinite(), "xf", "must have nx finite entries");
  if (w.prob.Qf.size() == 0) w.prob.Qf = Eigen::MatrixXd::Zero(nx, nx);
  core::require(w.prob.Qf.rows() == nx && w.prob.Qf.cols() == nx && w.prob.Qf.allFinite(), "Qf",
                "must be nx x nx and finite");
  w.has_Q = problem.Q.size() > 0;
  if (w.has_Q)
    core::require(problem.Q.rows() == nx && problem.Q.cols() == nx && problem.Q.allFinite(), "Q",
                  "must be nx x nx and finite");
  w.rdiag = Eigen::VectorXd::Zero(nu);
  if (problem.R.size() > 0) {
    core::require(problem.R.rows() == nu && problem.R.cols() == nu && problem.R.allFinite(), "R",
                  "must be nu x nu and finite");
    Eigen::MatrixXd off = problem.R;
    off.diagonal().setZero();
    core::require(off.isZero(0.0), "R", "must be diagonal with state constraints (closed-form prox)");
    w.rdiag = problem.R.diagonal();
    core::require((w.rdiag.array() >= 0.0).all(), "R", "diagonal must be >= 0");
  }
  core::require(problem.group_l2_weight == 0.0, "group_l2_weight",
                "must be 0 with state constraints (not supported)");
  core::require(problem.u_norm_max == 0.0, "u_norm_max", "must be 0 with state constraints (not supported)");
  core::require(settings.stopping == StoppingRule::kResiduals, "stopping",
                "must be the residual rule with state constraints");
  w.w = problem.l1_weights.size() ? problem.l1_weights : Eigen::VectorXd::Zero(nu);
  core::require(w.w.size() == nu && (w.w.array() >= 0.0).all() && w.w.allFinite(), "l1_weights",
                "must have nu entries >= 0");
  w.ulo = problem.u_lower.size() ? problem.u_lower : Eigen::VectorXd::Constant(nu, -detail::kInf);
  w.uhi = problem.u_upper.size() ? problem.u_upper : Eigen::VectorXd::Constant(nu, detail::kInf);
  core::require(w.ulo.size() == nu && w.uhi.size() == nu, "u_lower", "must have nu entries");
  core::require((w.ulo.array() <= w.uhi.array()).all(), "u_lower", "must be <= u_upper");
  core::require((w.ulo.array() <= 0.0).all() && (w.uhi.array() >= 0.0).all(), "u_lower",
                "the control box must contain 0 with state constraints");

  // ---- rows
  RowBuilder rb{nx, {}, {}, {}, {}, {}, {}, {}};
  for (std::size_t i = 0; i < cons.half_spaces.size(); ++i) {
    const auto& h = cons.half_spaces[i];
    const std::string nm = "half_spaces[" + std::to_string(i) + "]";
    core::require(
        h.node >= 1 && h.node <= N, nm + ".node",
        "must be in 1..N = " + std::to_string(N) + " (x_0 is given), got " + std::to_string(h.node));
    core::require(h.a.size() == nx && h.a.allFinite() && h.a.norm() > 0.0, nm + ".a",
                  "must have nx finite entries, not all zero");
    core::require(std::isfinite(h.b), nm + ".b", "must be finite");
    rb.add(h.node, h.a, -detail::kInf, h.b);
  }
  w.n_half = static_cast<int>(rb.c.size());
  for (std::size_t i = 0; i < cons.boxes.size(); ++i) {
    const auto& bx = cons.boxes[i];
    const std::string nm = "boxes[" + std::to_string(i) + "]";
    check_nodes(bx.nodes, N, nm + ".nodes");
    core::require(bx.lower.size() == nx && bx.upper.size() == nx, nm + ".lower", "must have nx entries");
    core::require(!bx.lower.hasNaN() && !bx.upper.hasNaN(), nm + ".lower", "must not be NaN");
    for (int e = 0; e < nx; ++e)
      core::require(bx.lower(e) <= bx.upper(e), nm + ".lower",
                    "must be <= upper (entry " + std::to_string(e) + ")");
    for (int k : bx.nodes)
      for (int e = 0; e < nx; ++e) {
        if (!std::isfinite(bx.lower(e)) && !std::isfinite(bx.upper(e))) continue;
        rb.add(k, Eigen::VectorXd::Unit(nx, e), bx.lower(e), bx.upper(e));
      }
  }
  for (std::size_t i = 0; i < cons.closing_velocity.size(); ++i) {
    const auto& cv = cons.closing_velocity[i];
    const std::string nm = "closing_velocity[" + std::to_string(i) + "]";
    check_nodes(cv.nodes, N, nm + ".nodes");
    check_index(cv.position_index, nx, nm + ".position_index");
    check_index(cv.velocity_index, nx, nm + ".velocity_index");
    core::require(cv.axis.allFinite() && cv.axis.norm() > 0.0, nm + ".axis", "must be finite and nonzero");
    core::require(cv.intercept.size() >= 1 && cv.intercept.size() == cv.slope.size(), nm + ".intercept",
                  "must have one entry per segment, as slope");
    core::require(cv.intercept.allFinite() && cv.slope.allFinite(), nm + ".intercept", "must be finite");
    const Eigen::Vector3d ax = cv.axis.normalized();
    for (int k : cv.nodes)
      for (int sgm = 0; sgm < cv.intercept.size(); ++sgm)
        for (int sign : {1, -1}) {
          Eigen::VectorXd a = Eigen::VectorXd::Zero(nx);
          for (int e = 0; e < 3; ++e) {
            a(cv.velocity_index[e]) += sign * ax(e);
            a(cv.position_index[e]) -= cv.slope(sgm) * ax(e);
          }
          core::require(a.norm() > 0.0, nm, "a segment gives a zero row");
          rb.add(k, a, -detail::kInf, cv.intercept(sgm));
        }
  }
  for (std::size_t i = 0; i < cons.cones.size(); ++i) {
    const auto& cn = cons.cones[i];
    const std::string nm = "cones[" + std::to_string(i) + "]";
    check_nodes(cn.nodes, N, nm + ".nodes");
    check_index(cn.position_index, nx, nm + ".position_index");
    core::require(cn.axis.allFinite() && cn.axis.norm() > 0.0, nm + ".axis", "must be finite and nonzero");
    core::require(std::isfinite(cn.half_angle) && cn.half_angle > 0.0 && cn.half_angle < 0.5 * M_PI,
                  nm + ".half_angle", "must be in (0, pi/2) rad");
    core::require(std::isfinite(cn.apex_offset), nm + ".apex_offset", "must be finite");
    const Eigen::Vector3d a = cn.axis.normalized();
    Eigen::Vector3d b1 = a.unitOrthogonal();
    Eigen::Vector3d b2 = a.cross(b1);
    const double t = std::tan(cn.half_angle);
    for (int k : cn.nodes) {
      const Eigen::Vector3d dirs[3] = {t * a, b1, b2};
      for (int rr = 0; rr < 3; ++rr) {
        Eigen::VectorXd row = Eigen::VectorXd::Zero(nx);
        for (int e = 0; e < 3; ++e) row(cn.position_index[e]) += dirs[rr](e);
        rb.c.push_back(row);
        rb.node.push_back(k);
        rb.cone.push_back(rr == 0 ? 1 : 2);
        rb.lo.push_back(-detail::kInf);
        rb.hi.push_back(detail::kInf);
        rb.off.push_back(rr == 0 ? t * cn.apex_offset : 0.0);
        rb.cosang.push_back(std::cos(cn.half_angle));
      }
    }
  }
  if (problem.terminal_equality)
    for (int e = 0; e < nx; ++e) rb.add(N, Eigen::VectorXd::Unit(nx, e), w.prob.xf(e), w.prob.xf(e));
  const int m = static_cast<int>(rb.c.size());
  core::require(m >= 1, "constraints", "no state constraint given (use AdmmSolver)");
  w.m = m;
  w.Crow.resize(nx, m);
  w.node.resize(m);
  w.cone_start.resize(m);
  w.lo.resize(m);
  w.hi.resize(m);
  w.off.resize(m);
  w.cosang.resize(m);
  for (int j = 0; j < m; ++j) {
    w.Crow.col(j) = rb.c[j];
    w.node(j) = rb.node[j];
    w.cone_start(j) = rb.cone[j];
    w.lo(j) = rb.lo[j];
    w.hi(j) = rb.hi[j];
    w.off(j) = rb.off[j];
    w.cosang(j) = rb.cosang[j];
  }
  // ---- workspace
  w.kappa.resize(m);
  w.rho_row.resize(m);
  w.escale.resize(m);
  w.Qx.resize(nx, nx * (N + 1));
  w.P.resize(nx, nx * (N + 1));
  w.K.resize(nu, nx * N);
  w.QuuInv.resize(nu, nu * N);
  w.Acl.resize(nx, nx * N);
  w.PB.resize(nx, nu * N);
  w.d.resize(nu, N);
  w.q.resize(nx, N + 1);
  w.qbase.resize(nx, N + 1);
  w.r.resize(nu, N);
  w.tmp_nx_nx.resize(nx, nx);
  w.tmp_nx_nx2.resize(nx, nx);
  w.tmp_nu_nx.resize(nu, nx);
  w.Quu.resize(nu, nu);
  w.Inu = Eigen::MatrixXd::Identity(nu, nu);
  w.llt = Eigen::LLT<Eigen::MatrixXd>(Eigen::MatrixXd::Identity(nu, nu));  // computed: info() set (UBSan)
  w.p.resize(nx);
  w.wv.resize(nx);
  w.tmp_nx.resize(nx);
  w.tmp_nx2.resize(nx);
  w.g_nu.resize(nu);
  for (auto* M : {&w.X, &w.Xfree, &w.Xf, &w.Cmu}) M->setZero(nx, N + 1);
  for (auto* M : {&w.U, &w.Y, &w.Yprev, &w.Lam, &w.Uhat, &w.H}) M->setZero(nu, N);
  for (auto* v : {&w.s, &w.z, &w.zprev, &w.mu, &w.shat, &w.mu_check, &w.lam_clean}) v->setZero(m);
  auto& R = w.res;
  R.X.setZero(nx, N + 1);
  R.X_flown.setZero(nx, N + 1);
  R.U.setZero(nu, N);
  R.Y.setZero(nu, N);
  R.Lambda.setZero(nu, N);
  R.terminal_multiplier.setZero(nx);
  R.infeasibility_certificate.setZero(m);
  R.state_multipliers.setZero(m);
  R.state_consensus.setZero(m);
  // base linear terms: -Q xf (k = 1..N-1), -Qf xf (k = N)
  if (settings.equilibrate)
    w.equilibrate();
  else
    w.du = Eigen::VectorXd::Ones(nu);
  w.qbase.setZero();
  for (int k = 1; k < N; ++k)
    if (w.has_Q) w.qbase.col(k).noalias() = -w.prob.Q * w.prob.xf;
  w.qbase.col(N).noalias() = -w.prob.Qf * w.prob.xf;
  // polish workspace (dense, sized once): sensitivities of the rows and of x_N to every control, and
  // the KKT on the free controls and active rows, n = nF + nE: nE <= m (one equation per interval row,
  // per cone block on its surface, three at its apex) and nF <= min(N nu, nx + m) (polish() takes at
  // most nx + nE free entries from Y's pattern and nx + count_active() <= nx + m from the dual estimate).
  // That bound, not N nu + 4 m + nx, sizes the two dense n x n matrices (N = 100 cone: 606 instead of
  // 1530, 5.9 MB instead of 37.5 MB); polish() rejects a larger system, which cannot occur
  const int nv = N * nu, kmax = std::min(nv, nx + m) + m;
  w.Srow.setZero(m + nx, nv);
  w.Kkt.setZero(kmax, kmax);
  w.kkt_rhs.setZero(kmax);
  w.kkt_sol.setZero(kmax);
  w.kkt_res.setZero(kmax);
  w.Kkt0.setZero(kmax, kmax);
  w.piv.setZero(std::max(kmax, nv));
  w.free_idx.setZero(nv);
  w.act_idx.setZero(m);
  w.act_kind.setZero(m);
  w.Ufix.setZero(nu, N);
  w.Ypol.setZero(nu, N);
  w.mu_pol.setZero(m);
  w.mu_best.setZero(m);
  w.dr_G.setZero(m, m);
  w.U_ipm.setZero(nu, N);
  w.X_ipm.setZero(nx, N + 1);
  w.mu_ipm.setZero(m);
  w.dr_hq.setZero(nu, N);
  for (auto* v : {&w.dr_hmin, &w.dr_hmax, &w.dr_tgt}) v->setZero(nv);
  for (auto* v : {&w.dr_lam, &w.dr_rhs, &w.dr_x, &w.dr_y, &w.mu_rec}) v->setZero(m);
  w.dr_eq.setZero(nv);
  w.kinks.resize(2 * static_cast<std::size_t>(nv));
  w.dr_on.setZero(m);
  w.dr_pos.setZero(m);
  w.nrm.setZero(m);
  w.unit_nx.setZero(nx);
  w.sgn.setZero(nv);
  w.compute_kappa();
  w.set_rho_rows();
  w.ipm.setup(nx, nu, N, m);
  w.ipd.prob = &w.prob;
  w.ipd.has_Q = w.has_Q;
  w.ipd.w = &w.w;
  w.ipd.rdiag = &w.rdiag;
  w.ipd.ulo = &w.ulo;
  w.ipd.uhi = &w.uhi;
  w.ipd.Crow = &w.Crow;
  w.ipd.node = &w.node;
  w.ipd.cone_start = &w.cone_start;
  w.ipd.lo = &w.lo;
  w.ipd.hi = &w.hi;
  w.ipd.off = &w.off;
  w.ipd.escale = &w.escale;
  w.ipm_ok = w.ipm.applicable(w.ipd);
  w.rho = settings.rho;
  w.rho_x = settings.rho;
  core::require(w.factor(), "rho", "Riccati factorization failed (hint: check Q, Qf PSD)");
}

StateConstrainedAdmm::~StateConstrainedAdmm() = default;
StateConstrainedAdmm::StateConstrainedAdmm(StateConstrainedAdmm&&) noexcept = default;
StateConstrainedAdmm& StateConstrainedAdmm::operator=(StateConstrainedAdmm&&) noexcept = default;

int StateConstrainedAdmm::rows() const { return ws_->m; }
const Eigen::VectorXi& StateConstrainedAdmm::row_nodes() const { return ws_->node; }
const StateAdmmResult& StateConstrainedAdmm::result() const { return ws_->res; }
int StateConstrainedAdmm::nx() const { return ws_->nx; }
int StateConstrainedAdmm::nu() const { return ws_->nu; }
int StateConstrainedAdmm::horizon() const { return ws_->N; }
void StateConstrainedAdmm::cold_start() noexcept { ws_->warm = false; }

double StateConstrainedAdmm::violation(const Eigen::Ref<const Eigen::MatrixXd>& X) const {
  core::require(X.rows() == ws_->nx && X.cols() == ws_->N + 1, "X", "must be nx x (N+1)");
  Eigen::VectorXd sv(ws_->m);
  ws_->rows_of(X, sv);
  return ws_->violation_of(sv);
}

bool StateConstrainedAdmm::set_x0(const Eigen::Ref<const Eigen::VectorXd>& x0) noexcept {
  if (x0.size() != ws_->nx || !x0.allFinite()) return false;
  ws_->prob.x0 = x0;
  return true;
}

bool StateConstrainedAdmm::set_half_space(int i, int node, const Eigen::Ref<const Eigen::VectorXd>& a,
                                          double b) noexcept {
  auto& w = *ws_;
  if (i < 0 || i >= w.n_half || node < 1 || node > w.N || a.size() != w.nx || !a.allFinite() ||
      !std::isfinite(b))
    return false;
  const double nrm = a.norm();
  if (!(nrm > 0.0)) return false;
  w.Crow.col(i) = a / nrm;
  w.node(i) = node;
  w.hi(i) = b / nrm;
  w.compute_kappa_row(i);  // half-spaces are interval rows: only their own scale changes
  w.escale(i) = std::sqrt(w.kappa(i));
  w.rho_row(i) = w.rho_x * w.kappa(i);
  w.rho_factored = -1.0;  // the ADMM refactors at its next solve; the IPM factors per step anyway
  return true;
}

const StateAdmmResult& StateConstrainedAdmm::solve() noexcept {
  SATGNC_NO_MALLOC_SCOPE;
  auto& w = *ws_;
  auto& R = w.res;
  auto& info = R.info;
  const auto& st = w.st;
  const auto t0 = std::chrono::steady_clock::now();
  info = AdmmInfo();
  R.ipm_plan = false;
  const int N = w.N, m = w.m;
  // A polished candidate (Ypol, mu_pol) is accepted only by the violation and gap tests; |gap|: a plan
  // below the dual bound is infeasible beyond rounding (a missed active row).
  const auto polish_certified = [&w, &st](double& viol) noexcept {
    w.rollout(w.Ypol, w.Xf, false);
    w.rows_of(w.Xf, w.shat);
    viol = w.violation_of(w.shat);
    const double vtol = st.eps_abs + st.eps_rel * w.Xf.cwiseAbs().maxCoeff();
    const double P = w.objective(w.Xf, w.Ypol);
    const double D = w.dual_bound(w.mu_pol);
    const double gap = (P - D) / std::max({std::abs(P), std::abs(D), st.gap_floor});
    return viol <= vtol && std::abs(gap) <= (st.eps_gap > 0.0 ? st.eps_gap : 1e-9);
  };
  if (!w.warm) {
    w.Y.setZero();
    w.Lam.setZero();
    w.z.setZero();
    w.project(w.z);
    w.mu.setZero();
    w.rho = st.rho;
    w.rho_x = st.rho;
  }
  w.mu_check = w.mu;
  const int fact0 = w.factorizations;
  const int polish0 = w.polish_attempts;
  const double alpha = st.relaxation;
  AdmmStatus status = AdmmStatus::max_iterations;
  double prim = detail::kInf, dual = detail::kInf, eps_p = 0.0, eps_d = 0.0;
  // interior-point method first: O(N) per step (Riccati), ~20-40 steps; accepted only by the
  // violation and Fenchel-gap tests below (the same as ADMM's); otherwise ADMM runs as before
  bool ipm_solved = false;
  // a certified IPM plan (Ypol, its row values shat) with the multipliers that certify it
  const auto accept_ipm_plan = [&](const Eigen::VectorXd& mu) {
    w.Y = w.Ypol;
    w.mu = mu;
    w.z = w.shat;
    w.project(w.z);
    w.Lam.setZero();
    ipm_solved = true;
    status = AdmmStatus::solved;
  };
  double D_best = -detail::kInf;
  bool ipm_exported = false;   // Ypol holds an IPM plan of this solve
  bool ipm_candidate = false;  // U_ipm / X_ipm hold the IPM's last plan (finite, not certified)
  if (w.ipm_ok && st.method != AdmmMethod::kAdmm) {
    w.ipm.init(w.ipd);
    for (int t = 0; t < st.ipm_max_iterations; ++t) {
      if (!w.ipm.step(w.ipd)) break;
      w.ipm.export_solution(w.ipd, w.Ypol, w.mu_pol);
      ipm_exported = true;
      w.rollout(w.Ypol, w.Xf, false);
      const double P = w.objective(w.Xf, w.Ypol);
      if (w.ipm.complementarity() > 1e-3 * std::max(std::abs(P), st.gap_floor)) continue;
      // every iterate's multipliers give a valid lower bound (weak duality): keep the largest. Near
      // the end the IPM's duals jitter by ~1e-8 relative (Schur complement of a hard terminal state
      // with barrier weights ~1e12) while its plan still converges, so the best bound certifies.
      const double Dk = w.dual_bound(w.mu_pol);
      if (Dk > D_best) {
        D_best = Dk;
        w.mu_best = w.mu_pol;
      }
      w.rows_of(w.Xf, w.shat);
      const double viol = w.violation_of(w.shat);
      const double vtol = st.eps_abs + st.eps_rel * w.Xf.cwiseAbs().maxCoeff();
      if (viol > vtol) continue;
      const double eps_gap = st.eps_gap > 0.0 ? st.eps_gap : 1e-9;
      const auto rel_gap = [&](double D) {
        return (P - D) / std::max({std::abs(P), std::abs(D), st.gap_floor});
      };
      // the plan has converged but the IPM's multipliers do not certify it (they run off along an
      // unbounded dual face): least-squares multipliers on the plan's active set, certified by the
      // same Fenchel bound (valid for any multipliers)
      if (std::abs(rel_gap(D_best)) > eps_gap &&
          w.ipm.complementarity() <= 1e-6 * std::max(std::abs(P), st.gap_floor) &&
          w.recover_dual(w.Ypol, w.Xf, w.mu_rec)) {
        ++info.dual_recoveries;
        const double Dr = w.dual_bound(w.mu_rec);
        if (Dr > D_best) {
          D_best = Dr;
          w.mu_best = w.mu_rec;
        }
      }
      const double gap = rel_gap(D_best);
      if (std::abs(gap) <= eps_gap) {
        accept_ipm_plan(w.mu_best);
        prim = w.ipm.primal_residual();
        dual = w.ipm.complementarity();
        break;
      }
    }
    // the IPM's plan converged without a certificate: polish it on its active set
    if (!ipm_solved && ipm_exported && w.Ypol.allFinite()) {
      ipm_candidate = true;
      w.U_ipm = w.Ypol;
      w.mu_ipm = w.mu_pol;
      w.rollout(w.U_ipm, w.X_ipm, false);
      const double P0 = w.objective(w.X_ipm, w.U_ipm);
      if (w.ipm.complementarity() <= 1e-6 * std::max(std::abs(P0), st.gap_floor)) {
        // (row tolerance, control tolerance): the IPM's zero controls and inactive rows approach their
        // kinks and bounds slowly (seen: 1e-7..1e-6 of the largest control), so a few cuts are tried
        constexpr double kCuts[4][2] = {{1e-6, 1e-7}, {1e-4, 1e-7}, {1e-4, 1e-5}, {1e-3, 1e-4}};
        for (const auto& cut : kCuts) {
          if (!w.ipm_polish(w.U_ipm, w.X_ipm, cut[0], cut[1])) continue;
          double viol = 0.0;
          if (polish_certified(viol)) {
            accept_ipm_plan(w.mu_pol);
            info.polished = info.certified = true;
            prim = viol;
            dual = w.ipm.complementarity();
            break;
          }
        }
      }
      if (!ipm_solved) {
        w.Ypol = w.U_ipm;
        w.mu_pol = w.mu_ipm;
      }
    }
    info.ipm_iterations = w.ipm.iterations;
    info.ipm_solved = ipm_solved;
    // method = ipm alone and not certified: return the IPM's last plan (with the best dual bound
    // seen) as the best iterate, evaluated below on the problem as given, never the starting plan
    if (!ipm_solved && st.method == AdmmMethod::kIpm && ipm_exported && w.Ypol.allFinite()) {
      w.Y = w.Ypol;
      w.mu = D_best > -detail::kInf ? w.mu_best : w.mu_pol;
      prim = w.ipm.primal_residual();
      dual = w.ipm.complementarity();
    }
  }
  const bool run_admm = !ipm_solved && st.method != AdmmMethod::kIpm;
  if (run_admm && (w.rho != w.rho_factored || w.rho_x != w.rho_x_factored) && !w.factor()) {
    info.status = AdmmStatus::numerical_error;
    info.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return R;
  }
  int it = 0;
  int last_gap_it = -1000000;
  bool ok_residuals = false;
  for (it = 1; run_admm && it <= st.max_iterations; ++it) {
    // linear terms of the x/u step
    w.q = w.qbase;
    for (int j = 0; j < m; ++j)
      w.q.col(w.node(j)).noalias() += (w.mu(j) - w.rho_row(j) * w.z(j)) * w.Crow.col(j);
    w.r = w.Lam - w.rho * w.Y;
    w.sweep();
    w.rows_of(w.X, w.s);
    // relaxation, prox / projection, multipliers
    w.Uhat = alpha * w.U + (1.0 - alpha) * w.Y;
    w.shat = alpha * w.s + (1.0 - alpha) * w.z;
    w.Yprev = w.Y;
    w.zprev = w.z;
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < w.nu; ++i) w.Y(i, k) = w.prox(w.Uhat(i, k) + w.Lam(i, k) / w.rho, i);
    w.Lam.noalias() += w.rho * (w.Uhat - w.Y);
    for (int j = 0; j < m; ++j) w.z(j) = w.shat(j) + w.mu(j) / w.rho_row(j);
    w.project(w.z);
    for (int j = 0; j < m; ++j) w.mu(j) += w.rho_row(j) * (w.shat(j) - w.z(j));
    if (!w.Y.allFinite() || !w.mu.allFinite() || !w.X.allFinite()) {
      status = AdmmStatus::numerical_error;
      break;
    }
    // residuals
    // residuals of the row-scaled problem (row j times e_j = sqrt(kappa_j), so that every
    // consensus variable has unit sensitivity to the controls; multipliers mu_j / e_j)
    double ps = 0.0, dz = 0.0, ss = 0.0, ms = 0.0;
    for (int j = 0; j < m; ++j) {
      const double e = w.escale(j);
      ps = std::max(ps, e * std::abs(w.s(j) - w.z(j)));
      dz = std::max(dz, w.rho_x * e * std::abs(w.z(j) - w.zprev(j)));
      ss = std::max({ss, e * std::abs(w.s(j)), e * std::abs(w.z(j))});
      ms = std::max(ms, std::abs(w.mu(j)) / e);
    }
    const double pu = (w.U - w.Y).cwiseAbs().maxCoeff();
    const double du_ = w.rho * (w.Y - w.Yprev).cwiseAbs().maxCoeff();
    const double spu = std::max(w.U.cwiseAbs().maxCoeff(), w.Y.cwiseAbs().maxCoeff());
    const double sdu = w.Lam.cwiseAbs().maxCoeff();
    prim = std::max(pu, ps);
    dual = std::max(du_, dz);
    const double sc_p = std::max(spu, ss);
    const double sc_d = std::max(sdu, ms);
    eps_p = st.eps_abs + st.eps_rel * sc_p;
    eps_d = st.eps_abs + st.eps_rel * sc_d;
    ok_residuals = prim <= eps_p && dual <= eps_d;
    if (ok_residuals && it - last_gap_it >= st.gap_check_interval) {
      last_gap_it = it;
      w.rollout(w.Y, w.Xf, false);
      w.rows_of(w.Xf, w.shat);
      const double viol = w.violation_of(w.shat);
      const double vtol = st.eps_abs + st.eps_rel * w.Xf.cwiseAbs().maxCoeff();
      const double P = w.objective(w.Xf, w.Y);
      const double D = w.dual_bound(w.mu);
      const double gap = (P - D) / std::max({std::abs(P), std::abs(D), st.gap_floor});
      if (viol <= vtol && (st.eps_gap <= 0.0 || std::abs(gap) <= st.eps_gap)) {
        status = AdmmStatus::solved;
        break;
      }
    }
    // active-set polish: a candidate accepted only by the same violation and gap tests
    const int want0 = st.polish && it % 25 == 0 ? w.nx + w.count_active() : 0;
    for (int t = 0; t <= std::min(want0, detail::kPolishSizes) && status != AdmmStatus::solved; ++t) {
      // t = 0: Y's pattern; then the dual-estimate guess with want0, want0 - 1, ... free entries
      // (at most kPolishSizes sizes per attempt: each is a dense KKT solve)
      if (!(t == 0 ? w.polish(0, 0) : w.polish(1, want0 + 1 - t))) continue;
      double viol = 0.0;
      if (polish_certified(viol)) {
        w.Y = w.Ypol;
        w.mu = w.mu_pol;
        info.polished = info.certified = true;
        status = AdmmStatus::solved;
        break;
      }
    }
    if (status == AdmmStatus::solved) break;
    // infeasibility: the change of the state multipliers over the interval as a Farkas direction
    if (st.infeasibility_check_interval > 0 && it % st.infeasibility_check_interval == 0) {
      w.shat = w.mu - w.mu_check;
      if (w.infeasibility_certificate(w.shat)) {
        R.infeasibility_certificate = w.lam_clean / w.lam_clean.norm();
        status = AdmmStatus::primal_infeasible;
        break;
      }
      w.mu_check = w.mu;
    }
    if (st.time_limit > 0.0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > st.time_limit) {
      status = AdmmStatus::time_limit;
      break;
    }
    // adaptive rho (OSQP residual balancing on normalized residuals)
    // (controls and state rows each balanced on their own normalized residuals)
    if (st.adaptive_rho && it % st.adaptive_rho_interval == 0) {
      const auto next = [&](double r0, double p, double sp, double d, double sd) {
        const double pn = p / std::max(sp, 1e-300), dn = d / std::max(sd, 1e-300);
        double ratio = dn > 0.0 ? std::sqrt(pn / dn) : 100.0;
        if (!std::isfinite(ratio)) ratio = 1.0;
        ratio = std::min(std::max(ratio, 1e-2), 1e2);
        const double nr = std::min(std::max(r0 * ratio, st.rho_min), st.rho_max);
        return (nr > r0 * st.adaptive_rho_tolerance || nr < r0 / st.adaptive_rho_tolerance) ? nr : r0;
      };
      const double nu_rho = next(w.rho, pu, spu, du_, sdu);
      const double nx_rho = next(w.rho_x, ps, ss, dz, ms);
      if (nu_rho != w.rho || nx_rho != w.rho_x) {
        // mu and Lambda are unscaled multipliers: nothing to rescale
        w.rho = nu_rho;
        w.rho_x = nx_rho;
        ++w.rho_updates;
        ++info.rho_updates;
        if (!w.factor()) {
          status = AdmmStatus::numerical_error;
          break;
        }
      }
    }
  }
  if (it > st.max_iterations) it = st.max_iterations;
  if (!run_admm) it = 0;
  // neither method certified (admm_ipm): return the better of ADMM's plan and the IPM's last one, by
  // the honest rule: the lower true objective among the plans within the violation tolerance, else the
  // smaller violation relative to its tolerance (ties keep ADMM's); the status stays ADMM's
  if (ipm_candidate && run_admm && status != AdmmStatus::solved && status != AdmmStatus::primal_infeasible) {
    const auto judge = [&w, &st](const Eigen::MatrixXd& Us, const Eigen::MatrixXd& Xs, double& P,
                                 double& rv) {
      w.rows_of(Xs, w.shat);
      const double vtol = st.eps_abs + st.eps_rel * Xs.cwiseAbs().maxCoeff();
      const double viol = w.violation_of(w.shat);
      P = w.objective(Xs, Us);
      rv = vtol > 0.0 ? viol / vtol : viol;
      if (!std::isfinite(P) || std::isnan(rv)) rv = detail::kInf;
      return std::isfinite(P) && viol <= vtol;
    };
    double Pa = 0.0, ra = 0.0, Pb = 0.0, rb = 0.0;
    w.rollout(w.Y, w.Xf, false);
    const bool ok_a = judge(w.Y, w.Xf, Pa, ra);
    const bool ok_b = judge(w.U_ipm, w.X_ipm, Pb, rb);
    if (ok_b ? (!ok_a || Pb < Pa) : (!ok_a && rb < ra)) {
      w.Y = w.U_ipm;
      w.mu = D_best > -detail::kInf ? w.mu_best : w.mu_ipm;
      w.rows_of(w.X_ipm, w.z);
      w.project(w.z);
      w.Lam.setZero();
      prim = w.ipm.primal_residual();
      dual = w.ipm.complementarity();
      R.ipm_plan = true;
    }
  }
  // final evaluation on the problem as given
  w.rollout(w.Y, w.Xf, false);
  w.rows_of(w.Xf, w.shat);
  R.max_violation = w.violation_of(w.shat);
  R.violation_tolerance = st.eps_abs + st.eps_rel * w.Xf.cwiseAbs().maxCoeff();
  const double P = w.objective(w.Xf, w.Y);
  double D = status == AdmmStatus::primal_infeasible ? -detail::kInf : w.dual_bound(w.mu);
  if (R.ipm_plan) D = std::max(D, D_best);  // every IPM iterate's bound is valid (weak duality)
  const double gap = (P - D) / std::max({std::abs(P), std::abs(D), st.gap_floor});
  if (status == AdmmStatus::max_iterations || status == AdmmStatus::time_limit) {
    // the IPM's plan is a rollout (no consensus residual): its primal and dual tests are the
    // violation and the gap themselves
    const double f = st.inaccurate_factor;
    if ((R.ipm_plan || (prim <= f * eps_p && dual <= f * eps_d)) &&
        R.max_violation <= f * R.violation_tolerance && std::abs(gap) <= f * st.eps_gap)
      status = AdmmStatus::solved_inaccurate;
  }
  info.status = status;
  info.iterations = it;
  info.polish_attempts = w.polish_attempts - polish0;
  info.primal_residual = prim;
  info.dual_residual = dual;
  info.eps_primal = eps_p;
  info.eps_dual = eps_d;
  info.objective = P;
  info.primal_objective = P;
  info.dual_objective = D;
  info.duality_gap = gap;
  info.objective_u = w.objective(w.X, w.U);
  info.terminal_miss = (w.Xf.col(N) - w.prob.xf).norm();
  info.rho = w.rho;
  info.factorizations = w.factorizations - fact0;
  info.paper_criterion = (w.U - w.Y).norm() / (double(N) * w.nu);
  // unscale: u = D_u u~, Lambda = Lambda~ / (c D_u), mu = mu~ / c, J = J~ / c (states unscaled)
  R.X = w.X;
  R.X_flown = w.Xf;
  for (int k = 0; k < N; ++k)
    for (int i = 0; i < w.nu; ++i) {
      R.U(i, k) = w.U(i, k) * w.du(i);
      R.Y(i, k) = w.Y(i, k) * w.du(i);
      R.Lambda(i, k) = w.Lam(i, k) / (w.cscale * w.du(i));
    }
  R.state_multipliers = w.mu / w.cscale;
  info.objective /= w.cscale;
  info.primal_objective /= w.cscale;
  info.dual_objective /= w.cscale;
  info.objective_u /= w.cscale;
  R.state_consensus = w.z;
  if (status != AdmmStatus::primal_infeasible) R.infeasibility_certificate.setZero();
  w.warm = status != AdmmStatus::numerical_error;
  info.solve_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return R;
}

}  // namespace satgnc::guidance
