// Interior-point method of StateConstrainedAdmm (detail/state_ipm.hpp): Mehrotra predictor-corrector,
// one Riccati-structured LQR per Newton solve. Conventions (CVXOPT's coneqp): G x + s = h, s in K,
// z in K, NT scaling W with W s = W^{-1} z = lambda; the reduced Newton system
//   (P + G' W^2 G) dx = -(r_x + G'(W^2 r_z + W (lambda \ d_s))),  dz = W^2 (G dx + r_z) + W (lambda \ d_s),
//   ds = -r_z - G dx,
// where x = (controls, epigraph t, states); the dynamics hold exactly (x is the rollout of u), so the
// Newton step is an LQR with dx_0 = 0 and the costates implicit.
#include "detail/state_ipm.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "detail/ipm_kernel.hpp"

namespace satgnc::guidance::detail {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// |(a, b)| of a cone block's tail. Not std::hypot (a libm call, ~3 % of the cone bench's instructions):
// the blocks are rows of the equilibrated problem (escale) at interior iterates, far inside the range
// 1e-150 .. 1e150 where a*a + b*b neither overflows nor underflows to a lost digit.
double norm2(double a, double b) noexcept { return std::sqrt(a * a + b * b); }

// Largest a >= 0 with x + a dx in the SOC (x interior); +inf if unbounded.
double soc_step(const double* x, const double* dx) noexcept {
  const double a = dx[0] * dx[0] - dx[1] * dx[1] - dx[2] * dx[2];
  const double b = x[0] * dx[0] - x[1] * dx[1] - x[2] * dx[2];
  const double r = norm2(x[1], x[2]);
  const double c = (x[0] - r) * (x[0] + r);  // x'Jx without the cancellation of x0^2 - |x1|^2
  if (a >= 0.0 && b >= 0.0) return kInf;     // x'Jx grows along dx: the boundary is never reached
  const double disc = b * b - a * c;
  if (disc < 0.0) return kInf;
  return std::max(0.0, c / (-b + std::sqrt(disc)));
}

// u = lambda \ v (inverse of the arrow matrix of lambda), 3-vectors
void arrow_solve(const double* l, const double* v, double* u) noexcept {
  const double r = norm2(l[1], l[2]);
  const double det = (l[0] - r) * (l[0] + r);
  u[0] = (l[0] * v[0] - l[1] * v[1] - l[2] * v[2]) / det;
  u[1] = (v[1] - l[1] * u[0]) / l[0];
  u[2] = (v[2] - l[2] * u[0]) / l[0];
}

// x o y (Jordan product of the SOC), 3-vectors
void jordan(const double* x, const double* y, double* o) noexcept {
  o[0] = x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
  o[1] = x[0] * y[1] + y[0] * x[1];
  o[2] = x[0] * y[2] + y[0] * x[2];
}

// column j of M as an NX-vector view (NX = Eigen::Dynamic: M.rows())
template <int NX>
Eigen::Map<const Eigen::Matrix<double, NX, 1>> col(const Eigen::MatrixXd& M, int j) noexcept {
  return {M.data() + static_cast<Eigen::Index>(j) * M.rows(), M.rows()};
}
template <int NX>
Eigen::Map<Eigen::Matrix<double, NX, 1>> col(Eigen::MatrixXd& M, int j) noexcept {
  return {M.data() + static_cast<Eigen::Index>(j) * M.rows(), M.rows()};
}

// The CW pattern (x, y, z, vx, vy, vz; u = (ux, uy, uz)): the in-plane motion (x, y, vx, vy; ux, uy) and
// the out-of-plane one (z, vz; uz) decouple, so A and B are zero across the two (20 of 36, 10 of 18
// entries nonzero). cw_in_plane(n, i): entry i of a state (n = 6) or control (n = 3) vector is in-plane.
constexpr bool cw_in_plane(int n, int i) noexcept { return n == 6 ? i != 2 && i != 5 : i != 2; }
// bit l + K c: entry (l, c) of a K x C matrix of the pattern (A, B or their transposes) may be nonzero
template <int K, int C>
constexpr std::uint64_t cw_mask() noexcept {
  std::uint64_t m = 0;
  for (int c = 0; c < C; ++c)
    for (int l = 0; l < K; ++l)
      if (cw_in_plane(K, l) == cw_in_plane(C, c)) m |= std::uint64_t{1} << (l + K * c);
  return m;
}
// true where M (K x C) is exactly zero off cw_mask<K, C>()
template <int K, int C>
bool has_cw_pattern(const double* M) noexcept {
  for (int e = 0; e < K * C; ++e)
    if (!((cw_mask<K, C>() >> e) & 1U) && M[e] != 0.0) return false;
  return true;
}

// ipm::mm with the terms of Y's entries outside Mask (exactly zero) left out: each column's axpys
// are those of ipm::mm in the same order minus additions of exact zeros, so the result is bitwise
// ipm::mm's for finite X (the loops are unrolled so that the mask tests fold at compile time)
template <int R, int K, int C, int Mode, std::uint64_t Mask>
inline void mm_masked(const double* X, const double* Y, double* out) noexcept {
  static_assert(Mode == 0 || Mode == 1);
#pragma GCC unroll 8
  for (int j = 0; j < C; ++j) {
    double acc[R] = {};
#pragma GCC unroll 8
    for (int l = 0; l < K; ++l) {
      if (!((Mask >> (l + K * j)) & 1U)) continue;
      const double y = Y[l + K * j];
      for (int i = 0; i < R; ++i) acc[i] += X[i + R * l] * y;
    }
    for (int i = 0; i < R; ++i) {
      if constexpr (Mode == 0) out[i + R * j] = acc[i];
      if constexpr (Mode == 1) out[i + R * j] += acc[i];
    }
  }
}
// ipm::mm<R, K, C, Mode> (Mode 0 or 1) for Y one of A, B, A', B' (K x C): masked on the CW pattern when cw
template <int R, int K, int C, int Mode = 0>
inline void mm_cw(bool cw, const double* X, const double* Y, double* out) noexcept {
  if (cw)
    mm_masked<R, K, C, Mode, cw_mask<K, C>()>(X, Y, out);
  else
    ipm::mm<R, K, C, Mode>(X, Y, out);
}

// every entry finite: 0 * x is NaN exactly where x is not, and the sum vectorizes (allFinite tests
// entry by entry)
template <class Derived>
bool all_finite(const Eigen::DenseBase<Derived>& x) noexcept {
  return (x.derived().array() * 0.0).sum() == 0.0;
}

bool is_eq(const StateIpmProblem& p, int j) noexcept { return (*p.lo)(j) == (*p.hi)(j); }
bool has_upper(const StateIpmProblem& p, int j) noexcept {
  return (*p.cone_start)(j) == 0 && !is_eq(p, j) && std::isfinite((*p.hi)(j));
}
bool has_lower(const StateIpmProblem& p, int j) noexcept {
  return (*p.cone_start)(j) == 0 && !is_eq(p, j) && std::isfinite((*p.lo)(j));
}
}  // namespace

void StateIpm::setup(int nx, int nu, int N, int m) {
  nx_ = nx;
  nu_ = nu;
  N_ = N;
  m_ = m;
  const int nv = nu * N;
  eqrow_.setZero(m);
  u_.setZero(nu, N);
  t_.setZero(nu, N);
  X_.setZero(nx, N + 1);
  nu_eq_.setZero(m);
  req_.setZero(m);
  dnu_.setZero(m);
  for (auto* M : {&sc_, &zc_, &rc_, &dsc_, &dzc_, &corc_, &rhsc_, &dqc_}) M->setZero(4, nv);
  for (auto* M : {&ss_, &zs_, &rs_, &dss_, &dzs_, &cors_, &rhss_}) M->setZero(2, m);
  for (auto* v : {&scn_, &zcn_, &rcn_, &dscn_, &dzcn_, &corcn_, &rhscn_, &lamcn_}) v->setZero(m);
  for (auto* M : {&Wcn_, &Wicn_, &W2cn_}) M->setZero(9, m);
  Qx_.setZero(nx, nx * (N + 1));
  gx_.setZero(nx, N + 1);
  for (auto* M : {&huu_, &hut_, &htt_, &gu_, &gt_, &Rd_, &rr_, &du_, &dt_}) M->setZero(nu, N);
  dX_.setZero(nx, N + 1);
  for (auto* M : {&rr0_, &du_acc_, &res_u_}) M->setZero(nu, N);
  for (auto* M : {&gx0_, &dX_acc_}) M->setZero(nx, N + 1);
  for (auto* v : {&req0_, &dnu_acc_, &res_e_, &dnu_tot_, &req_keep_}) v->setZero(m);
  for (auto* M : {&ofs_, &dofs_}) M->setZero(2, m);
  du_tot_.setZero(nu, N);
  dX_tot_.setZero(nx, N + 1);
  P_.setZero(nx, nx * (N + 1));
  K_.setZero(nu, nx * N);
  Qi_.setZero(nu, nu * N);
  d_.setZero(nu, N);
  // equality rows: at most nx (applicable()), so the Schur blocks are sized nx, not m; the sweep's
  // blocks T, G, D are nx wide whatever ne (zero columns past ne): fixed-size stage products
  const int me = std::min(m, nx);
  Dall_.setZero(nu, nx * N);
  T_.setZero(nx, nx);
  T2_.setZero(nx, nx);
  Sf_.setZero(nx, nx);
  G_.setZero(nu, nx);
  CW_.setZero(nx, 3);
  Se_.setZero(me, me);
  tmp_nx_nx_.setZero(nx, nx);
  tmp_nx_nx2_.setZero(nx, nx);
  tmp_nu_nx_.setZero(nu, nx);
  RK_.setZero(nu, nx);
  Acl_.setZero(nx, nx);
  Quu_.setZero(nu, nu);
  p_.setZero(nx);
  wv_.setZero(nx);
  ex_.setZero(nx);
  dnu_pad_.setZero(nx);
  g_nu_.setZero(nu);
  tmp_nx_.setZero(nx);
  rhs_e_.setZero(me);
  has_lo_.setZero(nu);
  has_hi_.setZero(nu);
  llt_ = Eigen::LLT<Eigen::MatrixXd>(Eigen::MatrixXd::Identity(nu, nu));  // computed once: info() set
  llt_e_ = Eigen::LLT<Eigen::MatrixXd>(Eigen::MatrixXd::Identity(me, me));
}

bool StateIpm::applicable(const StateIpmProblem& p) noexcept {
  if (!(p.w->minCoeff() > 0.0)) return false;
  ne_ = 0;
  for (int j = 0; j < m_; ++j) {
    if ((*p.cone_start)(j) != 0 || !is_eq(p, j)) continue;
    if ((*p.node)(j) != N_) return false;
    eqrow_(ne_++) = j;
  }
  if (ne_ > nx_) return false;
  return true;
}

void StateIpm::rollout(const StateIpmProblem& p, const Eigen::MatrixXd& U,
                       Eigen::MatrixXd& X) const noexcept {
  if (nx_ == 6 && nu_ == 3)
    rollout_t<6, 3>(p, U, X);
  else
    rollout_t<Eigen::Dynamic, Eigen::Dynamic>(p, U, X);
}

template <int NX, int NU>
void StateIpm::rollout_t(const StateIpmProblem& p, const Eigen::MatrixXd& U,
                         Eigen::MatrixXd& X) const noexcept {
  const auto& dyn = p.prob->dynamics;
  const int nx = nx_, nu = nu_;
  X.col(0) = p.prob->x0;
  for (int k = 0; k < N_; ++k) {
    auto xn = col<NX>(X, k + 1);
    xn.noalias() =
        Eigen::Map<const Eigen::Matrix<double, NX, NX>>(dyn.A_at(k).data(), nx, nx) * col<NX>(X, k);
    xn.noalias() += Eigen::Map<const Eigen::Matrix<double, NX, NU>>(dyn.B_at(k).data(), nx, nu) *
                    Eigen::Map<const Eigen::Matrix<double, NU, 1>>(U.col(k).data(), nu);
    if (!dyn.c.empty())
      xn += Eigen::Map<const Eigen::Matrix<double, NX, 1>>((dyn.c.size() == 1 ? dyn.c[0] : dyn.c[k]).data(),
                                                           nx);
  }
}

void StateIpm::init(const StateIpmProblem& p) noexcept {
  iterations = 0;
  residuals_current_ = false;
  u_.setZero();
  t_.setOnes();
  nu_eq_.setZero();
  rollout(p, u_, X_);
  nlp_ = 0;
  ncone_ = 0;
  for (int i = 0; i < nu_; ++i) {
    has_lo_(i) = std::isfinite((*p.ulo)(i)) ? 1 : 0;
    has_hi_(i) = std::isfinite((*p.uhi)(i)) ? 1 : 0;
  }
  // slacks h - G x floored at 1 (infeasible start), unit duals
  zc_.setZero();
  sc_.setZero();
  for (int v = 0; v < N_ * nu_; ++v) {
    const int i = v % nu_;
    // floor of the initial slacks: 1, or a quarter of a narrow interval (else no interior point
    // with zero residual exists near the start and the first steps are tiny)
    const double wd = (*p.uhi)(i) - (*p.ulo)(i);
    const double fl = std::isfinite(wd) ? std::clamp(0.25 * wd, 1e-8, 1.0) : 1.0;
    // epigraph t and its slacks on the box's scale (a quarter of its width, at least 1): started
    // at 1 against a box of ~1e5 (equilibrated units), the first ~15 steps of a hard-terminal plan
    // only grew the slacks (step lengths 1e-8..1e-3); N = 100 cone, x_N = 0: 55 -> 31 iterations
    const double t0 = std::isfinite(wd) ? std::max(1.0, 0.25 * wd) : 1.0;
    t_(i, v / nu_) = t0;
    sc_(0, v) = sc_(1, v) = t0;
    zc_(0, v) = zc_(1, v) = 1.0;
    nlp_ += 2;
    if (has_lo_(i)) {
      sc_(2, v) = std::max(-(*p.ulo)(i), fl);
      zc_(2, v) = 1.0 / sc_(2, v);  // centred: s z = 1
      ++nlp_;
    }
    if (has_hi_(i)) {
      sc_(3, v) = std::max((*p.uhi)(i), fl);
      zc_(3, v) = 1.0 / sc_(3, v);
      ++nlp_;
    }
  }
  has_interval_rows_ = false;
  ss_.setZero();
  zs_.setZero();
  scn_.setZero();
  zcn_.setZero();
  for (int j = 0; j < m_; ++j) {
    const double e = (*p.escale)(j);
    const double cx = p.Crow->col(j).dot(X_.col((*p.node)(j)));
    if ((*p.cone_start)(j) == 1) {
      double s0 = e * (cx - (*p.off)(j));
      const double s1 = e * p.Crow->col(j + 1).dot(X_.col((*p.node)(j)));
      const double s2 = e * p.Crow->col(j + 2).dot(X_.col((*p.node)(j)));
      const double r = std::hypot(s1, s2);
      // at least 0.3 r inside the cone (and 1): started at distance 1 from the boundary with r ~ 1e4
      // (equilibrated units) the NT scaling is ill-conditioned and the first ~5 steps are 4e-4..0.1 of
      // the direction (N = 100 cone, x_N = 0). Seeded suites, IPM alone: docs/guidance_safety.md
      // "Session 11 (a16)"
      constexpr double kConeDepth = 0.3;
      const double depth = std::max(1.0, kConeDepth * r);
      if (s0 - r < depth) s0 = r + depth;
      scn_(j) = s0;
      scn_(j + 1) = s1;
      scn_(j + 2) = s2;
      // centred: z = J s / s'Js, so that s o z = e
      const double sJs = s0 * s0 - s1 * s1 - s2 * s2;
      zcn_(j) = s0 / sJs;
      zcn_(j + 1) = -s1 / sJs;
      zcn_(j + 2) = -s2 / sJs;
      ++ncone_;
      j += 2;
      continue;
    }
    const double wd = e * ((*p.hi)(j) - (*p.lo)(j));
    const double fl = std::isfinite(wd) ? std::clamp(0.25 * wd, 1e-8, 1.0) : 1.0;
    if (has_upper(p, j)) {
      const double r0 = e * ((*p.hi)(j)-cx);
      ss_(0, j) = r0 > 1e-8 ? r0 : fl;  // feasible at the start: no residual (thin wedges)
      zs_(0, j) = 1.0 / ss_(0, j);
      ++nlp_;
      has_interval_rows_ = true;
    }
    if (has_lower(p, j)) {
      const double r0 = e * (cx - (*p.lo)(j));
      ss_(1, j) = r0 > 1e-8 ? r0 : fl;
      zs_(1, j) = 1.0 / ss_(1, j);
      ++nlp_;
      has_interval_rows_ = true;
    }
  }
}

// r_z = G x + s - h for every inequality, the equality residuals, the complementarity
void StateIpm::residuals(const StateIpmProblem& p) noexcept {
  if (nx_ == 6)
    residuals_t<6>(p);
  else
    residuals_t<Eigen::Dynamic>(p);
}

template <int NX>
void StateIpm::residuals_t(const StateIpmProblem& p) noexcept {
  rp_ = 0.0;
  sz_ = 0.0;
  for (int v = 0; v < N_ * nu_; ++v) {
    const int i = v % nu_, k = v / nu_;
    const double u = u_(i, k), t = t_(i, k);
    rc_(0, v) = u - t + sc_(0, v);
    rc_(1, v) = -u - t + sc_(1, v);
    rc_(2, v) = has_lo_(i) ? -u + (*p.ulo)(i) + sc_(2, v) : 0.0;
    rc_(3, v) = has_hi_(i) ? u - (*p.uhi)(i) + sc_(3, v) : 0.0;
    for (int q = 0; q < 4; ++q) {
      rp_ = std::max(rp_, std::abs(rc_(q, v)));
      sz_ += sc_(q, v) * zc_(q, v);
    }
  }
  for (int j = 0; j < m_; ++j) {
    const double e = (*p.escale)(j);
    const int nd = (*p.node)(j);
    if ((*p.cone_start)(j) == 1) {
      for (int q = 0; q < 3; ++q) {
        const double cx = col<NX>(*p.Crow, j + q).dot(col<NX>(X_, nd)) - (q == 0 ? (*p.off)(j) : 0.0);
        rcn_(j + q) = -e * cx + scn_(j + q);
        rp_ = std::max(rp_, std::abs(rcn_(j + q)));
        sz_ += scn_(j + q) * zcn_(j + q);
      }
      j += 2;
      continue;
    }
    const double cx = col<NX>(*p.Crow, j).dot(col<NX>(X_, nd));
    rs_(0, j) = has_upper(p, j) ? e * (cx - (*p.hi)(j)) + ss_(0, j) : 0.0;
    rs_(1, j) = has_lower(p, j) ? e * ((*p.lo)(j)-cx) + ss_(1, j) : 0.0;
    rp_ = std::max({rp_, std::abs(rs_(0, j)), std::abs(rs_(1, j))});
    sz_ += ss_(0, j) * zs_(0, j) + ss_(1, j) * zs_(1, j);
  }
  for (int a = 0; a < ne_; ++a) {
    const int j = eqrow_(a);
    req_(a) = col<NX>(*p.Crow, j).dot(col<NX>(X_, N_)) - (*p.lo)(j);
    rp_ = std::max(rp_, (*p.escale)(j)*std::abs(req_(a)));
  }
}

// NT scaling of each cone block; lambda
void StateIpm::scaling(const StateIpmProblem& p) noexcept {
  scaling_ok_ = true;
  for (int j = 0; j < m_; ++j) {
    if ((*p.cone_start)(j) != 1) continue;
    const Eigen::Vector3d s(scn_(j), scn_(j + 1), scn_(j + 2)), z(zcn_(j), zcn_(j + 1), zcn_(j + 2));
    // s'Js as (s0 - |s1|)(s0 + |s1|): near the boundary s0^2 - |s1|^2 cancels to rounding
    const double rs = norm2(s(1), s(2)), rz = norm2(z(1), z(2));
    const double sJs = (s(0) - rs) * (s(0) + rs);
    const double zJz = (z(0) - rz) * (z(0) + rz);
    if (!(sJs > 0.0) || !(zJz > 0.0)) {
      scaling_ok_ = false;  // on the boundary to rounding: the step fails, ADMM goes on
      j += 2;
      continue;
    }
    const Eigen::Vector3d sb = s / std::sqrt(sJs), zb = z / std::sqrt(zJz);
    const double gam = std::sqrt(0.5 * (1.0 + zb.dot(sb)));
    Eigen::Vector3d v(zb(0) + sb(0), zb(1) - sb(1), zb(2) - sb(2));
    v /= 2.0 * gam;
    // W^2 = beta^2 Q_v (Q_v = 2 v v' - J, v'Jv = 1, beta^2 = sqrt(z'Jz / s'Js)); W = beta Q_u with
    // u the Jordan square root of v, u = (v + e) / sqrt(2 (v0 + 1)) (closed form: an eigen-based
    // square root loses the small directions near the cone's boundary)
    const double beta = std::sqrt(std::sqrt(zJz / sJs));
    Eigen::Vector3d u = v;
    u(0) += 1.0;
    u /= std::sqrt(2.0 * (v(0) + 1.0));
    Eigen::Matrix3d W = 2.0 * u * u.transpose();
    W(0, 0) -= 1.0;
    W(1, 1) += 1.0;
    W(2, 2) += 1.0;
    Eigen::Matrix3d Wi = W;  // Q_u^-1 = J Q_u J
    Wi(0, 1) = -Wi(0, 1);
    Wi(1, 0) = -Wi(1, 0);
    Wi(0, 2) = -Wi(0, 2);
    Wi(2, 0) = -Wi(2, 0);
    W *= beta;
    Wi /= beta;
    const Eigen::Matrix3d W2 = W * W;
    Eigen::Map<Eigen::Matrix3d>(Wcn_.col(j).data()) = W;
    Eigen::Map<Eigen::Matrix3d>(Wicn_.col(j).data()) = Wi;
    Eigen::Map<Eigen::Matrix3d>(W2cn_.col(j).data()) = W2;
    const Eigen::Vector3d lam = W * s;
    lamcn_(j) = lam(0);
    lamcn_(j + 1) = lam(1);
    lamcn_(j + 2) = lam(2);
    j += 2;
  }
}

// Hessian of the Newton system and the Riccati factorization (with the equality Schur complement)
bool StateIpm::factor(const StateIpmProblem& p) noexcept {
  for (int v = 0; v < N_ * nu_; ++v) {
    const int i = v % nu_, k = v / nu_;
    double dq[4];
    for (int q = 0; q < 4; ++q) dq[q] = dqc_(q, v) = sc_(q, v) > 0.0 ? zc_(q, v) / sc_(q, v) : 0.0;
    huu_(i, k) = (*p.rdiag)(i) + dq[0] + dq[1] + dq[2] + dq[3];
    hut_(i, k) = dq[1] - dq[0];
    htt_(i, k) = dq[0] + dq[1];
    Rd_(i, k) = (*p.rdiag)(i) + 4.0 * dq[0] * dq[1] / (dq[0] + dq[1]) + dq[2] + dq[3];
  }
  // (6, 3) (the CW case): fixed-size stage blocks, the products unroll; any other size: dynamic
  if (nx_ == 6 && nu_ == 3) return factor_stages<6, 3>(p);
  return factor_stages<Eigen::Dynamic, Eigen::Dynamic>(p);
}

// The backward recursion of factor_stages for (nx, nu) = (6, 3) on column-major arrays (ipm::mm): per
// stage Qux = (A'PB)' = B'PA, Quu = B'PB + Rd, K = Quu^-1 Qux, P_k = (A - BK)'P(A - BK) + K'Rd K + Q_k
// (symmetrized); with equality rows G = B'T, D = Quu^-1 G, S += G'D, T_k = A'T - K'G. A', B' are
// transposed once per distinct stage matrix (time-invariant dynamics: once).
bool StateIpm::riccati_63(const StateIpmProblem& p) noexcept {
  const auto& dyn = p.prob->dynamics;
  const bool eq = ne_ > 0;
  double At[36], Bt[18], PB[18], Quu[9], Qux[18], Quxt[18], G[18], Gt[18], APA[36];
  // T is kept transposed (T' A - G' K needs no transpose of K) in two buffers swapped per stage (no copy)
  double Tbuf[72];
  double* Tt = Tbuf;
  double* Tt2 = Tbuf + 36;
  if (eq) ipm::transpose<6, 6>(T_.data(), Tt);
  double* S = Sf_.data();
  const double* Aprev = nullptr;
  const double* Bprev = nullptr;
  bool cw = false;  // A and B of the CW pattern: their zero terms are skipped (bitwise the same products)
  for (int k = N_ - 1; k >= 0; --k) {
    const double* A = dyn.A_at(k).data();
    const double* B = dyn.B_at(k).data();
    if (A != Aprev || B != Bprev) {
      ipm::transpose<6, 6>(A, At);
      ipm::transpose<6, 3>(B, Bt);
      cw = has_cw_pattern<6, 6>(A) && has_cw_pattern<6, 3>(B);
    }
    Aprev = A;
    Bprev = B;
    const double* Pn = P_.data() + (k + 1) * 36;
    double* Qi = Qi_.data() + k * 9;
    double* K = K_.data() + k * 18;
    mm_cw<6, 6, 3>(cw, Pn, B, PB);
    // Qux' = A'PB (P symmetric): six-row products vectorize fully, three-row ones by halves
    ipm::mm<6, 6, 3>(At, PB, Quxt);
    ipm::transpose<6, 3>(Quxt, Qux);
    ipm::mm<3, 6, 3>(Bt, PB, Quu);
    Eigen::Map<Eigen::Matrix3d> QuuM(Quu), QiM(Qi);
    QuuM.diagonal() += Rd_.col(k);
    // near the end the barrier weights span ~1e12 and P loses definiteness to rounding: a tiny
    // diagonal shift (the direction is only proposed; the certificate is independent)
    if (!ipm::ldl_inverse3_shifted(QuuM, QiM, 1e-12, 1e-5, 1e-300)) return false;
    ipm::mm<3, 3, 6>(Qi, Qux, K);
    if (eq) {
      double* D = Dall_.data() + k * 18;
      mm_cw<6, 6, 3>(cw, Tt, B, Gt);  // G' = T'B: the same sums as B'T, in the same order
      ipm::transpose<6, 3>(Gt, G);
      ipm::mm<3, 3, 6>(Qi, G, D);
      ipm::mm<6, 3, 6, 1>(Gt, D, S);
    }
    if (k == 0) break;  // P_0 and T_0 are never used (x_0 is given)
    if (eq) {
      mm_cw<6, 6, 6>(cw, Tt, A, Tt2);  // T_k' = T'A - G'K
      ipm::mm<6, 3, 6, -1>(Gt, K, Tt2);
      std::swap(Tt, Tt2);
    }
    // P_k = (A - BK)' P (A - BK) + K' Rd K + Q: a sum of PSD terms, definite by construction. The
    // form A'PA - Qux'K is a difference of terms ~ the barrier weights (1e6..1e12 on degenerate rows):
    // on 5 of the 7 uncertified box / mixed seeds it made Quu grossly indefinite (diagonal -13..-45)
    // and the run stopped on a failed factorization (IPM alone, box 28 -> 29, mixed 25 -> 27 of 30)
    double Acl[36], PAc[36], Aclt[36], Kt[18], RK[18];
    std::copy(A, A + 36, Acl);
    ipm::mm<6, 3, 6, -1>(B, K, Acl);
    ipm::mm<6, 6, 6>(Pn, Acl, PAc);
    ipm::transpose<6, 6>(Acl, Aclt);
    ipm::mm<6, 6, 6>(Aclt, PAc, APA);
    ipm::transpose<3, 6>(K, Kt);
    for (int c = 0; c < 6; ++c)
      for (int i = 0; i < 3; ++i) RK[i + 3 * c] = Rd_(i, k) * K[i + 3 * c];
    ipm::mm<6, 3, 6, 1>(Kt, RK, APA);
    const double* Qk = Qx_.data() + k * 36;
    double* Pk = P_.data() + k * 36;
    double probe = 0.0;  // 0 * x is NaN exactly where x is not finite: one test instead of 36
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i) {
        Pk[i + 6 * j] = 0.5 * (APA[i + 6 * j] + APA[j + 6 * i]) + Qk[i + 6 * j];
        probe += 0.0 * Pk[i + 6 * j];
      }
    if (!(probe == 0.0)) return false;
  }
  return true;
}

// The state Hessians Q_k (cost + rows), the backward Riccati recursion and, with equality rows, in the
// same sweep their Schur complement S = sum_k G_k' Quu_k^-1 G_k, G_k = B_k' T_{k+1}, T_N = E',
// T_k = (A_k - B_k K_k)' T_{k+1} (E dx_N = -S dnu + E dx_N(dnu = 0)). T is kept nx wide (columns past ne
// zero) so that every block has the stage's fixed size. Views on storage sized at setup: no allocation.
template <int NX, int NU>
bool StateIpm::factor_stages(const StateIpmProblem& p) noexcept {
  using MXX = Eigen::Matrix<double, NX, NX>;
  using MXU = Eigen::Matrix<double, NX, NU>;
  using MUX = Eigen::Matrix<double, NU, NX>;
  using MUU = Eigen::Matrix<double, NU, NU>;
  using MX3 = Eigen::Matrix<double, NX, 3>;
  const auto& dyn = p.prob->dynamics;
  const int nx = nx_, nu = nu_;
  const auto stage = [nx](Eigen::MatrixXd& M, int k) {
    return Eigen::Map<MXX>(M.data() + k * nx * nx, nx, nx);
  };
  // each stage written once (a whole-array setZero first was a 29 kB memset per factor)
  for (int k = 0; k < N_; ++k) {
    auto Qk = stage(Qx_, k);
    if (p.has_Q && k > 0)
      Qk = p.prob->Q;
    else
      Qk.setZero();
  }
  stage(Qx_, N_) = p.prob->Qf;
  Eigen::Map<MX3> CW(CW_.data(), nx, 3);
  for (int j = 0; j < m_; ++j) {
    const double e = (*p.escale)(j);
    auto Qk = stage(Qx_, (*p.node)(j));
    const double* c = p.Crow->data() + static_cast<Eigen::Index>(j) * nx;  // unit row j (contiguous)
    if ((*p.cone_start)(j) == 1) {
      const Eigen::Map<const Eigen::Matrix3d> W2(W2cn_.col(j).data());
      const Eigen::Map<const MX3> Cb(c, nx, 3);  // the block's three rows, side by side
      CW.noalias() = Cb * W2;
      CW *= e * e;
      Qk.noalias() += CW * Cb.transpose();
      j += 2;
      continue;
    }
    double dsum = 0.0;
    if (has_upper(p, j)) dsum += row_weight(0, j);
    if (has_lower(p, j)) dsum += row_weight(1, j);
    if (dsum == 0.0) continue;
    const double f = e * e * dsum;
    for (int c2 = 0; c2 < nx; ++c2)
      for (int r2 = 0; r2 < nx; ++r2) Qk(r2, c2) += f * c[r2] * c[c2];
  }
  const bool eq = ne_ > 0;
  if (eq) {
    Eigen::Map<MXX> T(T_.data(), nx, nx);
    T.setZero();
    for (int a = 0; a < ne_; ++a) T.col(a) = p.Crow->col(eqrow_(a));
    Sf_.setZero();
  }
  stage(P_, N_) = stage(Qx_, N_);
  if constexpr (NX == 6 && NU == 3) {
    if (!riccati_63(p)) return false;
  } else {
    Eigen::Map<MXX> T(T_.data(), nx, nx), T2(T2_.data(), nx, nx), S(Sf_.data(), nx, nx);
    Eigen::Map<MXX> PA(tmp_nx_nx2_.data(), nx, nx), APA(tmp_nx_nx_.data(), nx, nx);
    Eigen::Map<MUX> Qux(tmp_nu_nx_.data(), nu, nx), G(G_.data(), nu, nx), RK(RK_.data(), nu, nx);
    Eigen::Map<MXX> Acl(Acl_.data(), nx, nx);
    Eigen::Map<MUU> Quu(Quu_.data(), nu, nu);
    for (int k = N_ - 1; k >= 0; --k) {
      const Eigen::Map<const MXX> A(dyn.A_at(k).data(), nx, nx);
      const Eigen::Map<const MXU> B(dyn.B_at(k).data(), nx, nu);
      const auto Pn = stage(P_, k + 1);
      Eigen::Map<MUU> Qi(Qi_.data() + static_cast<Eigen::Index>(k) * nu * nu, nu, nu);
      Eigen::Map<MUX> K(K_.data() + static_cast<Eigen::Index>(k) * nu * nx, nu, nx);
      PA.noalias() = Pn * A;
      Qux.noalias() = B.transpose() * PA;  // B'PA (P symmetric)
      G.noalias() = B.transpose() * Pn;    // scratch here (a product of three would allocate a temporary)
      Quu.noalias() = G * B;
      Quu.diagonal() += Rd_.col(k);
      // near the end the barrier weights span ~1e12 and P loses definiteness to rounding: a tiny
      // diagonal shift (the direction is only proposed; the certificate is independent)
      if (!ipm::llt_with_shift(llt_, Quu, 1e-12, 1e-5, 1e-300)) return false;
      Qi.setIdentity();
      llt_.solveInPlace(Qi);
      K.noalias() = Qi * Qux;
      if (eq) {
        Eigen::Map<MUX> D(Dall_.data() + static_cast<Eigen::Index>(k) * nu * nx, nu, nx);
        G.noalias() = B.transpose() * T;
        D.noalias() = Qi * G;
        S.noalias() += G.transpose() * D;
      }
      if (k == 0) break;  // P_0 and T_0 are never used (x_0 is given)
      if (eq) {
        T2.noalias() = A.transpose() * T;  // (A - B K)' T
        T2.noalias() -= K.transpose() * G;
        T = T2;
      }
      // P_k = (A - BK)' P (A - BK) + K' Rd K + Q, a sum of PSD terms (riccati_63's form and reason: the
      // difference A'PA - Qux'K of terms ~ the barrier weights made Quu indefinite)
      Acl = A;
      Acl.noalias() -= B * K;
      PA.noalias() = Pn * Acl;
      APA.noalias() = Acl.transpose() * PA;
      RK.noalias() = Rd_.col(k).asDiagonal() * K;
      APA.noalias() += K.transpose() * RK;
      APA += stage(Qx_, k);
      auto Pk = stage(P_, k);
      Pk = 0.5 * (APA + APA.transpose());
      if (!Pk.allFinite()) return false;
    }
  }
  if (!eq) return true;
  // response of the equality rows to their multipliers, S (ne x ne, positive definite): padded to the
  // factor's setup size with an identity tail so that the LLT never resizes (a resize allocates)
  Se_.setIdentity();
  for (int a = 0; a < ne_; ++a)
    for (int b = 0; b < ne_; ++b) Se_(a, b) = 0.5 * (Sf_(a, b) + Sf_(b, a));
  auto Sh = Se_.topLeftCorner(ne_, ne_);
  llt_e_.compute(Se_);
  for (double shift = 1e-12; llt_e_.info() != Eigen::Success && shift < 1e-5; shift *= 100.0) {
    Sh.diagonal().array() += shift * (Sh.diagonal().cwiseAbs().maxCoeff() + 1e-300);
    llt_e_.compute(Se_);
  }
  return llt_e_.info() == Eigen::Success;
}

// Newton direction for the complementarity right-hand side d_s = -lambda o lambda - cor + sigma_mu e
// (cor = 0 for the affine step). Stores du, dt, dX, ds, dz, dnu.
void StateIpm::solve_newton(const StateIpmProblem& p, bool affine, double sigma_mu) noexcept {
  if (nx_ == 6 && nu_ == 3)
    solve_newton_t<6, 3>(p, affine, sigma_mu);
  else
    solve_newton_t<Eigen::Dynamic, Eigen::Dynamic>(p, affine, sigma_mu);
}

template <int NX, int NU>
void StateIpm::solve_newton_t(const StateIpmProblem& p, bool affine, double sigma_mu) noexcept {
  using MXX = Eigen::Matrix<double, NX, NX>;
  using VX = Eigen::Matrix<double, NX, 1>;
  const int nx = nx_;
  // gradient of the Lagrangian (r_x) plus G'(W^2 r_z + W (lambda \ d_s)); then dz needs the same v
  // each column written once (no whole-array setZero first)
  for (int k = 0; k <= N_; ++k) {
    if (k == 0 || (k < N_ && !p.has_Q)) {
      col<NX>(gx_, k).setZero();
      continue;
    }
    Eigen::Map<VX> dxk(tmp_nx_.data(), nx);
    dxk = col<NX>(X_, k) - Eigen::Map<const VX>(p.prob->xf.data(), nx);
    col<NX>(gx_, k).noalias() = Eigen::Map<const MXX>((k < N_ ? p.prob->Q : p.prob->Qf).data(), nx, nx) * dxk;
  }
  for (int a = 0; a < ne_; ++a) col<NX>(gx_, N_) += nu_eq_(a) * col<NX>(*p.Crow, eqrow_(a));
  // control entry v = (i, k): its four rows are contiguous (column v of the 4-row arrays) and its
  // entries of the nu x N arrays are entry v: raw pointers (the (q, v) index arithmetic was ~1/4 of
  // these loops)
  for (int v = 0; v < N_ * nu_; ++v) {
    const int i = v % nu_;
    const double *sc = sc_.data() + 4 * v, *zc = zc_.data() + 4 * v, *rc = rc_.data() + 4 * v;
    const double *cor = corc_.data() + 4 * v, *dq = dqc_.data() + 4 * v;
    double* rh = rhsc_.data() + 4 * v;
    double vq[4];
    for (int q = 0; q < 4; ++q) {
      if (!(sc[q] > 0.0)) {
        vq[q] = 0.0;
        rh[q] = 0.0;
        continue;
      }
      const double s = sc[q], z = zc[q];
      const double ds = -s * z - (affine ? 0.0 : cor[q]) + (affine ? 0.0 : sigma_mu);
      rh[q] = ds / s;                 // W (lambda \ d_s)
      vq[q] = dq[q] * rc[q] + rh[q];  // dq = z / s: the division of factor(), bitwise
    }
    const double zu = zc[0] - zc[1] - zc[2] + zc[3];
    const double gu = (*p.rdiag)(i)*u_.data()[v] + zu + (vq[0] - vq[1] - vq[2] + vq[3]);
    const double gt = (*p.w)(i)-zc[0] - zc[1] + (-vq[0] - vq[1]);
    gu_.data()[v] = gu;
    gt_.data()[v] = gt;
    rr_.data()[v] = gu - hut_.data()[v] * gt / htt_.data()[v];
  }
  for (int j = 0; j < m_; ++j) {
    const double e = (*p.escale)(j);
    const int nd = (*p.node)(j);
    if ((*p.cone_start)(j) == 1) {
      const Eigen::Map<const Eigen::Matrix3d> W(Wcn_.col(j).data()), W2(W2cn_.col(j).data());
      double ds[3], lss[3], tmp[3];
      jordan(&lamcn_(j), &lamcn_(j), lss);
      for (int q = 0; q < 3; ++q)
        ds[q] = -lss[q] - (affine ? 0.0 : corcn_(j + q)) + (q == 0 && !affine ? sigma_mu : 0.0);
      arrow_solve(&lamcn_(j), ds, tmp);
      const Eigen::Vector3d wds = W * Eigen::Vector3d(tmp[0], tmp[1], tmp[2]);
      const Eigen::Vector3d rz(rcn_(j), rcn_(j + 1), rcn_(j + 2));
      const Eigen::Vector3d vv = W2 * rz + wds;
      for (int q = 0; q < 3; ++q) {
        rhscn_(j + q) = wds(q);
        // G = -e C: G'(z + v)
        col<NX>(gx_, nd) -= e * (zcn_(j + q) + vv(q)) * col<NX>(*p.Crow, j + q);
      }
      j += 2;
      continue;
    }
    double coef = 0.0;
    if (has_upper(p, j)) {
      const double s = ss_(0, j), z = zs_(0, j);
      const double ds = -s * z - (affine ? 0.0 : cors_(0, j)) + (affine ? 0.0 : sigma_mu);
      rhss_(0, j) = ds / z;
      coef += z + row_weight(0, j) * (rs_(0, j) + rhss_(0, j));
    }
    if (has_lower(p, j)) {
      const double s = ss_(1, j), z = zs_(1, j);
      const double ds = -s * z - (affine ? 0.0 : cors_(1, j)) + (affine ? 0.0 : sigma_mu);
      rhss_(1, j) = ds / z;
      coef -= z + row_weight(1, j) * (rs_(1, j) + rhss_(1, j));
    }
    if (coef != 0.0) col<NX>(gx_, nd) += e * coef * col<NX>(*p.Crow, j);
  }
  refine<NX, NU>(p);
  // the corrector's direction is the step; the predictor's only sets sigma and the corrector terms
  ofs_.setZero();
  if (!affine) debias<NX, NU>(p);
  // recover dt, ds, dz
  for (int v = 0; v < N_ * nu_; ++v) {  // raw pointers as above
    const double *sc = sc_.data() + 4 * v, *rc = rc_.data() + 4 * v;
    const double *rh = rhsc_.data() + 4 * v, *dq = dqc_.data() + 4 * v;
    double *ds = dsc_.data() + 4 * v, *dz = dzc_.data() + 4 * v;
    const double du = du_.data()[v];
    const double dt = -(gt_.data()[v] + hut_.data()[v] * du) / htt_.data()[v];
    dt_.data()[v] = dt;
    const double Gdx[4] = {du - dt, -du - dt, -du, du};
    for (int q = 0; q < 4; ++q) {
      if (!(sc[q] > 0.0)) {
        ds[q] = dz[q] = 0.0;
        continue;
      }
      ds[q] = -rc[q] - Gdx[q];
      dz[q] = dq[q] * (Gdx[q] + rc[q]) + rh[q];
    }
  }
  for (int j = 0; j < m_; ++j) {
    const double e = (*p.escale)(j);
    const int nd = (*p.node)(j);
    if ((*p.cone_start)(j) == 1) {
      const Eigen::Map<const Eigen::Matrix3d> W2(W2cn_.col(j).data());
      Eigen::Vector3d g;
      for (int q = 0; q < 3; ++q) g(q) = -e * col<NX>(*p.Crow, j + q).dot(col<NX>(dX_, nd)) + rcn_(j + q);
      const Eigen::Vector3d dz = W2 * g;
      for (int q = 0; q < 3; ++q) {
        dscn_(j + q) = -g(q);
        dzcn_(j + q) = dz(q) + rhscn_(j + q);
      }
      j += 2;
      continue;
    }
    const double cdx = e * col<NX>(*p.Crow, j).dot(col<NX>(dX_, nd));
    // with the offsets of debias(): complementarity linearized exactly, the primal row off by the
    // last correction's delta dz only (ofs = delta dz of the previous round)
    if (has_upper(p, j)) {
      dzs_(0, j) = row_weight(0, j) * (cdx + rs_(0, j) + rhss_(0, j) + ofs_(0, j));
      dss_(0, j) = -rs_(0, j) - cdx - ofs_(0, j) + kDualReg * dzs_(0, j);
    }
    if (has_lower(p, j)) {
      dzs_(1, j) = row_weight(1, j) * (-cdx + rs_(1, j) + rhss_(1, j) + ofs_(1, j));
      dss_(1, j) = -rs_(1, j) + cdx - ofs_(1, j) + kDualReg * dzs_(1, j);
    }
  }
}

// The LQR of one Newton step with the factor's gains: backward sweep of the linear terms (gx, rr),
// with equality rows E dx_N(dnu = 0) = -sum_k D_k' g_k accumulated on the way and dnu = S^-1 (r_eq +
// E dx_N(0)); then one forward pass from dx_0 = 0 with du_k = -K_k dx_k - d_k - D_k dnu.
template <int NX, int NU>
void StateIpm::sweep_stages(const StateIpmProblem& p) noexcept {
  using MXX = Eigen::Matrix<double, NX, NX>;
  using MXU = Eigen::Matrix<double, NX, NU>;
  using MUX = Eigen::Matrix<double, NU, NX>;
  using MUU = Eigen::Matrix<double, NU, NU>;
  using VX = Eigen::Matrix<double, NX, 1>;
  using VU = Eigen::Matrix<double, NU, 1>;
  const auto& dyn = p.prob->dynamics;
  const int nx = nx_, nu = nu_;
  const bool eq = ne_ > 0;
  Eigen::Map<VX> pk(p_.data(), nx), wv(wv_.data(), nx), ex(ex_.data(), nx), dnu(dnu_pad_.data(), nx);
  Eigen::Map<VU> g(g_nu_.data(), nu);
  pk = gx_.col(N_);
  ex.setZero();
  for (int k = N_ - 1; k >= 0; --k) {
    const Eigen::Map<const MXX> A(dyn.A_at(k).data(), nx, nx);
    const Eigen::Map<const MXU> B(dyn.B_at(k).data(), nx, nu);
    const Eigen::Map<const MUU> Qi(Qi_.data() + static_cast<Eigen::Index>(k) * nu * nu, nu, nu);
    const Eigen::Map<const MUX> K(K_.data() + static_cast<Eigen::Index>(k) * nu * nx, nu, nx);
    g = rr_.col(k);
    g.noalias() += B.transpose() * pk;
    Eigen::Map<VU>(d_.col(k).data(), nu).noalias() = Qi * g;
    if (eq)
      ex.noalias() -=
          Eigen::Map<const MUX>(Dall_.data() + static_cast<Eigen::Index>(k) * nu * nx, nu, nx).transpose() *
          g;
    if (k == 0) break;
    // p_k = g_k + A' p - Qux' d, Qux' d = Qux' Quu^-1 (r + B' p) = K' (r + B' p)
    wv.noalias() = A.transpose() * pk;
    wv.noalias() -= K.transpose() * g;
    pk = gx_.col(k) + wv;
  }
  dnu.setZero();
  if (eq) {
    // -E Z dnu = r_eq + E dx_N(0), S = -E Z  ->  dnu = S^-1 (r_eq + E dx_N(0))
    rhs_e_.setZero();  // identity tail of the padded factor
    for (int a = 0; a < ne_; ++a) rhs_e_(a) = req_(a) + ex(a);
    llt_e_.solveInPlace(rhs_e_);
    for (int a = 0; a < ne_; ++a) dnu(a) = dnu_(a) = rhs_e_(a);
  }
  dX_.col(0).setZero();
  for (int k = 0; k < N_; ++k) {
    const Eigen::Map<const MXX> A(dyn.A_at(k).data(), nx, nx);
    const Eigen::Map<const MXU> B(dyn.B_at(k).data(), nx, nu);
    const Eigen::Map<const MUX> K(K_.data() + static_cast<Eigen::Index>(k) * nu * nx, nu, nx);
    const Eigen::Map<const VX> x(dX_.col(k).data(), nx);
    Eigen::Map<VU> du(du_.col(k).data(), nu);
    du.noalias() = -K * x;
    du -= Eigen::Map<const VU>(d_.col(k).data(), nu);
    if (eq)
      du.noalias() -=
          Eigen::Map<const MUX>(Dall_.data() + static_cast<Eigen::Index>(k) * nu * nx, nu, nx) * dnu;
    Eigen::Map<VX> xn(dX_.col(k + 1).data(), nx);
    xn.noalias() = A * x;
    xn.noalias() += B * du;
  }
}

// Residual of the reduced Newton system (the LQR of sweep_stages with the unshifted Rd and state
// Hessians Qx) at the current (du, dX, dnu) for the right-hand side saved in (gx0, rr0, req0):
// res_u_k = Rd_k du_k + rr0_k + B_k' lam_{k+1}, lam_k = Qx_k dX_k + gx0_k + A_k' lam_{k+1},
// lam_N = Qx_N dX_N + gx0_N + E' dnu; res_e = E dX_N + req0. Returns max |res| relative to the
// right-hand side's scale.
template <int NX, int NU>
double StateIpm::newton_residual(const StateIpmProblem& p) noexcept {
  using MXX = Eigen::Matrix<double, NX, NX>;
  using MXU = Eigen::Matrix<double, NX, NU>;
  using VX = Eigen::Matrix<double, NX, 1>;
  using VU = Eigen::Matrix<double, NU, 1>;
  const auto& dyn = p.prob->dynamics;
  const int nx = nx_, nu = nu_;
  const auto stage = [nx](const Eigen::MatrixXd& M, int k) {
    return Eigen::Map<const MXX>(M.data() + static_cast<Eigen::Index>(k) * nx * nx, nx, nx);
  };
  Eigen::Map<VX> lam(p_.data(), nx), wv(wv_.data(), nx);
  lam.noalias() = stage(Qx_, N_) * col<NX>(dX_, N_);
  lam += col<NX>(gx0_, N_);
  for (int a = 0; a < ne_; ++a) lam += dnu_(a) * col<NX>(*p.Crow, eqrow_(a));
  double r = 0.0, scale = 0.0;
  for (int k = N_ - 1; k >= 0; --k) {
    const Eigen::Map<const MXX> A(dyn.A_at(k).data(), nx, nx);
    const Eigen::Map<const MXU> B(dyn.B_at(k).data(), nx, nu);
    Eigen::Map<VU> res(res_u_.col(k).data(), nu);
    res.noalias() = B.transpose() * lam;
    for (int i = 0; i < nu; ++i) {
      const double a = Rd_(i, k) * du_(i, k), b = rr0_(i, k);
      scale = std::max({scale, std::abs(a), std::abs(b), std::abs(res(i))});
      res(i) += a + b;
      r = std::max(r, std::abs(res(i)));
    }
    if (k == 0) break;
    wv.noalias() = A.transpose() * lam;
    lam.noalias() = stage(Qx_, k) * col<NX>(dX_, k);
    lam += col<NX>(gx0_, k) + wv;
  }
  for (int a = 0; a < ne_; ++a) {
    const double e = (*p.escale)(eqrow_(a));
    res_e_(a) = col<NX>(*p.Crow, eqrow_(a)).dot(col<NX>(dX_, N_)) + req0_(a);
    scale = std::max(scale, e * std::abs(req0_(a)));
    r = std::max(r, e * std::abs(res_e_(a)));
  }
  return scale > 0.0 ? r / scale : 0.0;
}

// Newton solve with iterative refinement: near the end the barrier weights span ~1e12, the stage
// factorizations are shifted (ldl_inverse3_shifted) and the Riccati recursion loses digits to
// cancellation, so the direction of one sweep can be far from the Newton direction (the steps
// shrink and the run stalls short of its certificate). Up to kRefine corrections, each a sweep on
// the residual of the unshifted system with the same factorization, kept while the residual falls.
template <int NX, int NU>
void StateIpm::refine(const StateIpmProblem& p) noexcept {
  constexpr int kRefine = 3;
  constexpr double kTol = 1e-12;
  gx0_ = gx_;
  rr0_ = rr_;
  req0_.head(ne_) = req_.head(ne_);
  sweep_stages<NX, NU>(p);
  // only with interval rows (the regularized ones, whose barrier weights reach ~1e12 on degenerate
  // problems): cone-only problems (the N = 100 bench) were certified without it, and the residual
  // costs ~30 % of a step there (callgrind)
  if (!has_interval_rows_) return;
  double r = newton_residual<NX, NU>(p);
  for (int it = 0; it < kRefine && r > kTol; ++it) {
    du_acc_ = du_;
    dX_acc_ = dX_;
    dnu_acc_.head(ne_) = dnu_.head(ne_);
    gx_.setZero();
    rr_ = res_u_;
    req_.head(ne_) = res_e_.head(ne_);
    sweep_stages<NX, NU>(p);
    du_ += du_acc_;
    dX_ += dX_acc_;
    dnu_.head(ne_) += dnu_acc_.head(ne_);
    const double r1 = newton_residual<NX, NU>(p);
    if (!(r1 < 0.5 * r)) {  // no progress: keep the previous direction
      du_ = du_acc_;
      dX_ = dX_acc_;
      dnu_.head(ne_) = dnu_acc_.head(ne_);
      break;
    }
    r = r1;
  }
  gx_ = gx0_;
  rr_ = rr0_;
  req_.head(ne_) = req0_.head(ne_);
}

// Removes the bias of the dual regularization from the Newton direction (Clarabel's refinement against
// the unregularized KKT, done on the row blocks). The regularized row equation is
// G dx - (s/z + delta) dz = -(r + d_s/z); against the exact one (delta = 0) it leaves the residual
// delta dz, which is what the step carries into the next iterate's primal residual: r+ = (1 - a) r +
// a delta dz. On an active row (s/z << delta, weight ~ 1/delta) that is r+ ~ r: the row's violation
// never closed (mixed seed 4 case 29: s'z 1e-18, one row 5.6e-4 outside its bound from iteration 20
// to 200, every later step blocked by its slack). Fixed point ofs = delta dz(ofs): each round solves the
// regularized system for the change of the offsets (same factorization, right-hand side on the rows
// only) and adds it; the contraction factor per row is delta / (delta + s/z + its stiffness).
template <int NX, int NU>
void StateIpm::debias(const StateIpmProblem& p) noexcept {
  // rounds, IPM alone (mixed / box certified of 30), debiasing both solves: 0: 27 / 29; 1: 27 / 29; 2, 3,
  // 6: 28 / 30; the corrector's only (kept: ~half the cost), 3 rounds: 29 / 30
  constexpr int kRounds = 3;
  if (!has_interval_rows_) return;
  // only where the regularization changes a weight by more than 2x (s/z < delta): elsewhere the bias
  // delta dz is below the step's own (1 - a) r
  bool active = false;
  for (int j = 0; j < m_ && !active; ++j)
    for (int q = 0; q < 2; ++q)
      if (ss_(q, j) > 0.0 && ss_(q, j) < kDualReg * zs_(q, j)) active = true;
  if (!active) return;
  req_keep_.head(ne_) = req_.head(ne_);
  for (int round = 0; round < kRounds; ++round) {
    double dmax = 0.0, omax = 0.0;
    gx_.setZero();
    for (int j = 0; j < m_; ++j) {
      if ((*p.cone_start)(j) == 1) {
        j += 2;
        continue;
      }
      const double e = (*p.escale)(j);
      const int nd = (*p.node)(j);
      const double cdx = e * col<NX>(*p.Crow, j).dot(col<NX>(dX_, nd));
      double coef = 0.0;
      for (int q = 0; q < 2; ++q) {
        if (!(ss_(q, j) > 0.0)) continue;
        const double sg = q == 0 ? 1.0 : -1.0;
        const double w = row_weight(q, j);
        const double dz = w * (sg * cdx + rs_(q, j) + rhss_(q, j) + ofs_(q, j));
        dofs_(q, j) = kDualReg * dz - ofs_(q, j);
        dmax = std::max(dmax, std::abs(dofs_(q, j)));
        omax = std::max({omax, std::abs(ofs_(q, j)), std::abs(rs_(q, j) + rhss_(q, j))});
        coef += sg * w * dofs_(q, j);
      }
      if (coef != 0.0) col<NX>(gx_, nd) += e * coef * col<NX>(*p.Crow, j);
    }
    if (!(dmax > 1e-14 * omax)) break;
    du_tot_ = du_;
    dX_tot_ = dX_;
    dnu_tot_.head(ne_) = dnu_.head(ne_);
    rr_.setZero();
    req_.head(ne_).setZero();
    refine<NX, NU>(p);
    du_ += du_tot_;
    dX_ += dX_tot_;
    dnu_.head(ne_) += dnu_tot_.head(ne_);
    ofs_ += dofs_;
  }
  req_.head(ne_) = req_keep_.head(ne_);
}

double StateIpm::max_step() const noexcept {
  double a = kInf;
  // -x / dx (dx < 0) divided only where it can be below a: x > a |dx| (1 + 4 eps), with a |dx| a normal
  // number, gives x / |dx| > a exactly, and its rounded quotient >= a: the same minimum as dividing
  // everywhere, at a fraction of the divisions (latency-bound)
  constexpr double kScreen = 1.0 + 4.0 * std::numeric_limits<double>::epsilon();
  const auto ratio = [&a](double x, double dx) {
    if (!(dx < 0.0)) return;
    const double b = a * -dx;
    if (b >= std::numeric_limits<double>::min() && x > b * kScreen) return;
    a = std::min(a, -x / dx);
  };
  // control rows absent (an infinite bound) have s = z = 0 and ds = dz = 0 (set so by every Newton
  // solve): never a ratio, so one pass over the arrays without a presence test
  for (Eigen::Index e = 0; e < sc_.size(); ++e) {
    ratio(sc_.data()[e], dsc_.data()[e]);
    ratio(zc_.data()[e], dzc_.data()[e]);
  }
  for (int j = 0; j < m_; ++j)
    for (int q = 0; q < 2; ++q)
      if (ss_(q, j) > 0.0) {
        ratio(ss_(q, j), dss_(q, j));
        ratio(zs_(q, j), dzs_(q, j));
      }
  // cone blocks: step() (it knows the block flags)
  return a;
}

bool StateIpm::step(const StateIpmProblem& p) noexcept {
  ++iterations;
  if (!residuals_current_) residuals(p);  // else computed at the end of the previous step
  scaling(p);
  if (!scaling_ok_ || !factor(p)) return false;
  const double mu = sz_ / std::max(1, nlp_ + ncone_);
  const auto full_step = [&]() {
    double a = max_step();
    for (int j = 0; j < m_; ++j) {
      if ((*p.cone_start)(j) != 1) continue;
      a = std::min({a, soc_step(&scn_(j), &dscn_(j)), soc_step(&zcn_(j), &dzcn_(j))});
      j += 2;
    }
    return a;
  };
  // predictor
  solve_newton(p, true, 0.0);
  const double aa = std::min(1.0, full_step());
  // predicted complementarity and Mehrotra's sigma
  double sz_a = 0.0;
  for (Eigen::Index e = 0; e < sc_.size(); ++e)  // (q, v) in storage order, raw: no index arithmetic
    sz_a += (sc_.data()[e] + aa * dsc_.data()[e]) * (zc_.data()[e] + aa * dzc_.data()[e]);
  for (int j = 0; j < m_; ++j) {
    for (int q = 0; q < 2; ++q) sz_a += (ss_(q, j) + aa * dss_(q, j)) * (zs_(q, j) + aa * dzs_(q, j));
    sz_a += (scn_(j) + aa * dscn_(j)) * (zcn_(j) + aa * dzcn_(j));
  }
  const double sig = ipm::mehrotra_sigma(sz_a, sz_);
  // corrector terms (W^-1 dz_a) o (W ds_a)
  corc_ = dsc_.cwiseProduct(dzc_);
  cors_ = dss_.cwiseProduct(dzs_);
  for (int j = 0; j < m_; ++j) {
    if ((*p.cone_start)(j) != 1) continue;
    const Eigen::Map<const Eigen::Matrix3d> W(Wcn_.col(j).data()), Wi(Wicn_.col(j).data());
    const Eigen::Vector3d a = Wi * Eigen::Vector3d(dzcn_(j), dzcn_(j + 1), dzcn_(j + 2));
    const Eigen::Vector3d b = W * Eigen::Vector3d(dscn_(j), dscn_(j + 1), dscn_(j + 2));
    jordan(a.data(), b.data(), &corcn_(j));
    j += 2;
  }
  solve_newton(p, false, sig * mu);
  // the adaptive fraction to the boundary (up to 1 - 1e-6 as sigma -> 0) without interval rows only:
  // their dual regularization leaves each direction inexact (debias() contracts the bias, it does not
  // remove it), and stepping that close to the boundary stalled the gap test at 4e-8 on the seeded
  // mixed / coupled problems (one lost in each); there the fixed 0.99
  const double tau = has_interval_rows_ ? 0.99 : ipm::fraction_to_boundary(sig);
  const double a = std::min(1.0, tau * full_step());
  if (!(a > 0.0)) return false;
  ipm::take_step(a, u_, du_, t_, dt_, sc_, dsc_, zc_, dzc_, ss_, dss_, zs_, dzs_, scn_, dscn_, zcn_, dzcn_);
  nu_eq_.head(ne_) += a * dnu_.head(ne_);
  rollout(p, u_, X_);
  residuals(p);
  residuals_current_ = true;
  return all_finite(u_) && all_finite(zc_) && all_finite(zs_) && all_finite(zcn_) && std::isfinite(sz_);
}

void StateIpm::export_solution(const StateIpmProblem& p, Eigen::MatrixXd& Y,
                               Eigen::VectorXd& mu) const noexcept {
  for (int k = 0; k < N_; ++k)
    for (int i = 0; i < nu_; ++i) Y(i, k) = std::min(std::max(u_(i, k), (*p.ulo)(i)), (*p.uhi)(i));
  mu.setZero();
  for (int j = 0; j < m_; ++j) {
    const double e = (*p.escale)(j);
    if ((*p.cone_start)(j) == 1) {
      for (int q = 0; q < 3; ++q) mu(j + q) = -e * zcn_(j + q);
      j += 2;
      continue;
    }
    mu(j) = e * (zs_(0, j) - zs_(1, j));
  }
  for (int a = 0; a < ne_; ++a) mu(eqrow_(a)) = nu_eq_(a);
}

}  // namespace satgnc::guidance::detail
