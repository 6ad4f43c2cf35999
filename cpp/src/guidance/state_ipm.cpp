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
#include <limits>

#include "detail/ipm_kernel.hpp"

namespace satgnc::guidance::detail {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// Largest a >= 0 with x + a dx in the SOC (x interior); +inf if unbounded.
double soc_step(const double* x, const double* dx) noexcept {
  const double a = dx[0] * dx[0] - dx[1] * dx[1] - dx[2] * dx[2];
  const double b = x[0] * dx[0] - x[1] * dx[1] - x[2] * dx[2];
  const double r = std::hypot(x[1], x[2]);
  const double c = (x[0] - r) * (x[0] + r);  // x'Jx without the cancellation of x0^2 - |x1|^2
  if (a >= 0.0 && b >= 0.0) return kInf;     // x'Jx grows along dx: the boundary is never reached
  const double disc = b * b - a * c;
  if (disc < 0.0) return kInf;
  return std::max(0.0, c / (-b + std::sqrt(disc)));
}

// u = lambda \ v (inverse of the arrow matrix of lambda), 3-vectors
void arrow_solve(const double* l, const double* v, double* u) noexcept {
  const double r = std::hypot(l[1], l[2]);
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
  for (auto* M : {&sc_, &zc_, &rc_, &dsc_, &dzc_, &corc_, &rhsc_}) M->setZero(4, nv);
  for (auto* M : {&ss_, &zs_, &rs_, &dss_, &dzs_, &cors_, &rhss_}) M->setZero(2, m);
  for (auto* v : {&scn_, &zcn_, &rcn_, &dscn_, &dzcn_, &corcn_, &rhscn_, &lamcn_}) v->setZero(m);
  for (auto* M : {&Wcn_, &Wicn_, &W2cn_}) M->setZero(9, m);
  Qx_.setZero(nx, nx * (N + 1));
  gx_.setZero(nx, N + 1);
  for (auto* M : {&huu_, &hut_, &htt_, &gu_, &gt_, &Rd_, &rr_, &du_, &dt_}) M->setZero(nu, N);
  dX_.setZero(nx, N + 1);
  P_.setZero(nx, nx * (N + 1));
  PB_.setZero(nx, nu * N);
  K_.setZero(nu, nx * N);
  Qi_.setZero(nu, nu * N);
  Acl_.setZero(nx, nx * N);
  d_.setZero(nu, N);
  // equality rows: at most nx (applicable()), so the Schur blocks are sized nx, not m
  const int me = std::min(m, nx);
  Dall_.setZero(nu, me * N);
  T_.setZero(nx, me);
  T2_.setZero(nx, me);
  Z_.setZero(nx, me);
  Z2_.setZero(nx, me);
  Se_.setZero(me, me);
  tmp_nx_nx_.setZero(nx, nx);
  tmp_nx_nx2_.setZero(nx, nx);
  tmp_nu_nx_.setZero(nu, nx);
  Quu_.setZero(nu, nu);
  Inu_ = Eigen::MatrixXd::Identity(nu, nu);
  p_.setZero(nx);
  wv_.setZero(nx);
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
  const auto& dyn = p.prob->dynamics;
  X.col(0) = p.prob->x0;
  for (int k = 0; k < N_; ++k) {
    X.col(k + 1).noalias() = dyn.A_at(k) * X.col(k);
    X.col(k + 1).noalias() += dyn.B_at(k) * U.col(k);
    if (!dyn.c.empty()) X.col(k + 1) += dyn.c.size() == 1 ? dyn.c[0] : dyn.c[k];
  }
}

void StateIpm::init(const StateIpmProblem& p) noexcept {
  iterations = 0;
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
      if (s0 - r < 1.0) s0 = r + 1.0;
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
    }
    if (has_lower(p, j)) {
      const double r0 = e * (cx - (*p.lo)(j));
      ss_(1, j) = r0 > 1e-8 ? r0 : fl;
      zs_(1, j) = 1.0 / ss_(1, j);
      ++nlp_;
    }
  }
}

// r_z = G x + s - h for every inequality, the equality residuals, the complementarity
void StateIpm::residuals(const StateIpmProblem& p) noexcept {
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
        const double cx = p.Crow->col(j + q).dot(X_.col(nd)) - (q == 0 ? (*p.off)(j) : 0.0);
        rcn_(j + q) = -e * cx + scn_(j + q);
        rp_ = std::max(rp_, std::abs(rcn_(j + q)));
        sz_ += scn_(j + q) * zcn_(j + q);
      }
      j += 2;
      continue;
    }
    const double cx = p.Crow->col(j).dot(X_.col(nd));
    rs_(0, j) = has_upper(p, j) ? e * (cx - (*p.hi)(j)) + ss_(0, j) : 0.0;
    rs_(1, j) = has_lower(p, j) ? e * ((*p.lo)(j)-cx) + ss_(1, j) : 0.0;
    rp_ = std::max({rp_, std::abs(rs_(0, j)), std::abs(rs_(1, j))});
    sz_ += ss_(0, j) * zs_(0, j) + ss_(1, j) * zs_(1, j);
  }
  for (int a = 0; a < ne_; ++a) {
    const int j = eqrow_(a);
    req_(a) = p.Crow->col(j).dot(X_.col(N_)) - (*p.lo)(j);
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
    const double rs = std::hypot(s(1), s(2)), rz = std::hypot(z(1), z(2));
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
  const auto& dyn = p.prob->dynamics;
  for (int v = 0; v < N_ * nu_; ++v) {
    const int i = v % nu_, k = v / nu_;
    double dq[4];
    for (int q = 0; q < 4; ++q) dq[q] = sc_(q, v) > 0.0 ? zc_(q, v) / sc_(q, v) : 0.0;
    huu_(i, k) = (*p.rdiag)(i) + dq[0] + dq[1] + dq[2] + dq[3];
    hut_(i, k) = dq[1] - dq[0];
    htt_(i, k) = dq[0] + dq[1];
    Rd_(i, k) = (*p.rdiag)(i) + 4.0 * dq[0] * dq[1] / (dq[0] + dq[1]) + dq[2] + dq[3];
  }
  Qx_.setZero();
  for (int k = 1; k < N_; ++k)
    if (p.has_Q) Qx_.middleCols(k * nx_, nx_) = p.prob->Q;
  Qx_.middleCols(N_ * nx_, nx_) += p.prob->Qf;
  for (int j = 0; j < m_; ++j) {
    const double e = (*p.escale)(j);
    auto Qk = Qx_.middleCols((*p.node)(j)*nx_, nx_);
    if ((*p.cone_start)(j) == 1) {
      const Eigen::Map<const Eigen::Matrix3d> W2(W2cn_.col(j).data());
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          const double f = e * e * W2(a, b);
          for (int c2 = 0; c2 < nx_; ++c2)
            for (int r2 = 0; r2 < nx_; ++r2) Qk(r2, c2) += f * (*p.Crow)(r2, j + a) * (*p.Crow)(c2, j + b);
        }
      j += 2;
      continue;
    }
    double dsum = 0.0;
    if (has_upper(p, j)) dsum += zs_(0, j) / ss_(0, j);
    if (has_lower(p, j)) dsum += zs_(1, j) / ss_(1, j);
    if (dsum == 0.0) continue;
    const double f = e * e * dsum;
    for (int c2 = 0; c2 < nx_; ++c2)
      for (int r2 = 0; r2 < nx_; ++r2) Qk(r2, c2) += f * (*p.Crow)(r2, j) * (*p.Crow)(c2, j);
  }
  P_.middleCols(N_ * nx_, nx_) = Qx_.middleCols(N_ * nx_, nx_);
  for (int k = N_ - 1; k >= 0; --k) {
    const auto& A = dyn.A_at(k);
    const auto& B = dyn.B_at(k);
    auto Pn = P_.middleCols((k + 1) * nx_, nx_);
    PB_.middleCols(k * nu_, nu_).noalias() = Pn * B;
    Quu_.noalias() = B.transpose() * PB_.middleCols(k * nu_, nu_);
    Quu_.diagonal() += Rd_.col(k);
    // near the end the barrier weights span ~1e12 and P loses definiteness to rounding: a tiny
    // diagonal shift (the direction is only proposed; the certificate is independent)
    if (!ipm::llt_with_shift(llt_, Quu_, 1e-12, 1e-5, 1e-300)) return false;
    auto Qi = Qi_.middleCols(k * nu_, nu_);
    Qi = Inu_;
    llt_.solveInPlace(Qi);
    tmp_nu_nx_.noalias() = PB_.middleCols(k * nu_, nu_).transpose() * A;
    K_.middleCols(k * nx_, nx_).noalias() = Qi * tmp_nu_nx_;
    Acl_.middleCols(k * nx_, nx_) = A;
    Acl_.middleCols(k * nx_, nx_).noalias() -= B * K_.middleCols(k * nx_, nx_);
    tmp_nx_nx2_.noalias() = Pn * A;
    tmp_nx_nx_.noalias() = A.transpose() * tmp_nx_nx2_;
    tmp_nx_nx_.noalias() -= tmp_nu_nx_.transpose() * K_.middleCols(k * nx_, nx_);
    tmp_nx_nx_ += Qx_.middleCols(k * nx_, nx_);
    P_.middleCols(k * nx_, nx_) = 0.5 * (tmp_nx_nx_ + tmp_nx_nx_.transpose());
    if (!P_.middleCols(k * nx_, nx_).allFinite()) return false;
  }
  if (ne_ == 0) return true;
  // response of the equality rows to their multipliers: S_E = E dx_N / d nu (negative definite)
  auto T = T_.leftCols(ne_);
  auto T2 = T2_.leftCols(ne_);
  for (int a = 0; a < ne_; ++a) T.col(a) = p.Crow->col(eqrow_(a));
  for (int k = N_ - 1; k >= 0; --k) {
    auto D = Dall_.middleCols(k * ne_, ne_);
    for (int a = 0; a < ne_; ++a) {
      g_nu_.noalias() = dyn.B_at(k).transpose() * T.col(a);
      D.col(a).noalias() = Qi_.middleCols(k * nu_, nu_) * g_nu_;
    }
    T2.noalias() = Acl_.middleCols(k * nx_, nx_).transpose() * T;
    T = T2;
  }
  auto Z = Z_.leftCols(ne_);
  auto Z2 = Z2_.leftCols(ne_);
  Z.setZero();
  for (int k = 0; k < N_; ++k) {
    Z2.noalias() = Acl_.middleCols(k * nx_, nx_) * Z;
    Z2.noalias() -= dyn.B_at(k) * Dall_.middleCols(k * ne_, ne_);
    Z = Z2;
  }
  auto S = Se_.topLeftCorner(ne_, ne_);
  for (int a = 0; a < ne_; ++a)
    for (int b = 0; b < ne_; ++b) S(a, b) = -p.Crow->col(eqrow_(a)).dot(Z.col(b));
  // Symmetrize in place: an .eval() here would allocate inside solve().
  for (int a = 0; a < ne_; ++a)
    for (int b = a + 1; b < ne_; ++b) S(a, b) = S(b, a) = 0.5 * (S(a, b) + S(b, a));
  // llt_e_ is sized min(m, nx) at setup; factor the whole block with an identity tail so that it
  // never resizes (a resize allocates) when this problem has fewer equality rows.
  const int m = static_cast<int>(Se_.rows());
  Se_.topRightCorner(ne_, m - ne_).setZero();
  Se_.bottomLeftCorner(m - ne_, ne_).setZero();
  Se_.bottomRightCorner(m - ne_, m - ne_).setIdentity();
  llt_e_.compute(Se_);
  for (double shift = 1e-12; llt_e_.info() != Eigen::Success && shift < 1e-5; shift *= 100.0) {
    S.diagonal().array() += shift * (S.diagonal().cwiseAbs().maxCoeff() + 1e-300);
    llt_e_.compute(Se_);
  }
  return llt_e_.info() == Eigen::Success;
}

// Newton direction for the complementarity right-hand side d_s = -lambda o lambda - cor + sigma_mu e
// (cor = 0 for the affine step). Stores du, dt, dX, ds, dz, dnu.
void StateIpm::solve_newton(const StateIpmProblem& p, bool affine, double sigma_mu) noexcept {
  const auto& dyn = p.prob->dynamics;
  // gradient of the Lagrangian (r_x) plus G'(W^2 r_z + W (lambda \ d_s)); then dz needs the same v
  gx_.setZero();
  for (int k = 1; k <= N_; ++k) {
    if (k < N_ && !p.has_Q) continue;
    tmp_nx_ = X_.col(k) - p.prob->xf;
    gx_.col(k).noalias() += (k < N_ ? p.prob->Q : p.prob->Qf) * tmp_nx_;
  }
  for (int a = 0; a < ne_; ++a) gx_.col(N_) += nu_eq_(a) * p.Crow->col(eqrow_(a));
  for (int v = 0; v < N_ * nu_; ++v) {
    const int i = v % nu_, k = v / nu_;
    double vq[4];
    for (int q = 0; q < 4; ++q) {
      if (!(sc_(q, v) > 0.0)) {
        vq[q] = 0.0;
        rhsc_(q, v) = 0.0;
        continue;
      }
      const double s = sc_(q, v), z = zc_(q, v);
      const double ds = -s * z - (affine ? 0.0 : corc_(q, v)) + (affine ? 0.0 : sigma_mu);
      rhsc_(q, v) = ds / s;  // W (lambda \ d_s)
      vq[q] = z / s * rc_(q, v) + rhsc_(q, v);
    }
    const double zu = zc_(0, v) - zc_(1, v) - zc_(2, v) + zc_(3, v);
    gu_(i, k) = (*p.rdiag)(i)*u_(i, k) + zu + (vq[0] - vq[1] - vq[2] + vq[3]);
    gt_(i, k) = (*p.w)(i)-zc_(0, v) - zc_(1, v) + (-vq[0] - vq[1]);
    rr_(i, k) = gu_(i, k) - hut_(i, k) * gt_(i, k) / htt_(i, k);
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
        gx_.col(nd) -= e * (zcn_(j + q) + vv(q)) * p.Crow->col(j + q);
      }
      j += 2;
      continue;
    }
    double coef = 0.0;
    if (has_upper(p, j)) {
      const double s = ss_(0, j), z = zs_(0, j);
      const double ds = -s * z - (affine ? 0.0 : cors_(0, j)) + (affine ? 0.0 : sigma_mu);
      rhss_(0, j) = ds / s;
      coef += z + z / s * rs_(0, j) + rhss_(0, j);
    }
    if (has_lower(p, j)) {
      const double s = ss_(1, j), z = zs_(1, j);
      const double ds = -s * z - (affine ? 0.0 : cors_(1, j)) + (affine ? 0.0 : sigma_mu);
      rhss_(1, j) = ds / s;
      coef -= z + z / s * rs_(1, j) + rhss_(1, j);
    }
    if (coef != 0.0) gx_.col(nd) += e * coef * p.Crow->col(j);
  }
  // backward sweep (linear terms gx, rr), forward pass from dx_0 = 0
  p_ = gx_.col(N_);
  for (int k = N_ - 1; k >= 0; --k) {
    const auto& A = dyn.A_at(k);
    const auto& B = dyn.B_at(k);
    g_nu_ = rr_.col(k);
    g_nu_.noalias() += B.transpose() * p_;
    d_.col(k).noalias() = Qi_.middleCols(k * nu_, nu_) * g_nu_;
    // p_k = g_k + A' p - Qux' d, Qux' d = Qux' Quu^-1 (r + B' p) = K' (r + B' p)
    wv_.noalias() = A.transpose() * p_;
    wv_.noalias() -= K_.middleCols(k * nx_, nx_).transpose() * g_nu_;
    p_ = gx_.col(k) + wv_;
  }
  dX_.col(0).setZero();
  for (int k = 0; k < N_; ++k) {
    du_.col(k).noalias() = -K_.middleCols(k * nx_, nx_) * dX_.col(k);
    du_.col(k) -= d_.col(k);
    dX_.col(k + 1).noalias() = dyn.A_at(k) * dX_.col(k);
    dX_.col(k + 1).noalias() += dyn.B_at(k) * du_.col(k);
  }
  if (ne_ > 0) {
    // E (dx_N0 + Z dnu) = -r_eq, Z = dx_N / dnu = -S^-1... S = -E Z
    auto rhs = rhs_e_.head(ne_);
    for (int a = 0; a < ne_; ++a) rhs(a) = req_(a) + p.Crow->col(eqrow_(a)).dot(dX_.col(N_));
    rhs_e_.tail(rhs_e_.size() - ne_).setZero();  // identity tail of the padded factor
    llt_e_.solveInPlace(rhs_e_);                 // -E Z dnu = r_eq + E dx_N0  ->  dnu = S^-1 (r_eq + E dx_N0)
    dnu_.head(ne_) = rhs;
    for (int k = 0; k < N_; ++k) {
      du_.col(k).noalias() -= Dall_.middleCols(k * ne_, ne_) * dnu_.head(ne_);
      dX_.col(k + 1).noalias() = dyn.A_at(k) * dX_.col(k);
      dX_.col(k + 1).noalias() += dyn.B_at(k) * du_.col(k);
      if (k + 1 < N_) {
        du_.col(k + 1).noalias() = -K_.middleCols((k + 1) * nx_, nx_) * dX_.col(k + 1);
        du_.col(k + 1) -= d_.col(k + 1);
      }
    }
  }
  // recover dt, ds, dz
  for (int v = 0; v < N_ * nu_; ++v) {
    const int i = v % nu_, k = v / nu_;
    dt_(i, k) = -(gt_(i, k) + hut_(i, k) * du_(i, k)) / htt_(i, k);
    const double Gdx[4] = {du_(i, k) - dt_(i, k), -du_(i, k) - dt_(i, k), -du_(i, k), du_(i, k)};
    for (int q = 0; q < 4; ++q) {
      if (!(sc_(q, v) > 0.0)) {
        dsc_(q, v) = dzc_(q, v) = 0.0;
        continue;
      }
      dsc_(q, v) = -rc_(q, v) - Gdx[q];
      dzc_(q, v) = zc_(q, v) / sc_(q, v) * (Gdx[q] + rc_(q, v)) + rhsc_(q, v);
    }
  }
  for (int j = 0; j < m_; ++j) {
    const double e = (*p.escale)(j);
    const int nd = (*p.node)(j);
    if ((*p.cone_start)(j) == 1) {
      const Eigen::Map<const Eigen::Matrix3d> W2(W2cn_.col(j).data());
      Eigen::Vector3d g;
      for (int q = 0; q < 3; ++q) g(q) = -e * p.Crow->col(j + q).dot(dX_.col(nd)) + rcn_(j + q);
      const Eigen::Vector3d dz = W2 * g;
      for (int q = 0; q < 3; ++q) {
        dscn_(j + q) = -g(q);
        dzcn_(j + q) = dz(q) + rhscn_(j + q);
      }
      j += 2;
      continue;
    }
    const double cdx = e * p.Crow->col(j).dot(dX_.col(nd));
    if (has_upper(p, j)) {
      dss_(0, j) = -rs_(0, j) - cdx;
      dzs_(0, j) = zs_(0, j) / ss_(0, j) * (cdx + rs_(0, j)) + rhss_(0, j);
    }
    if (has_lower(p, j)) {
      dss_(1, j) = -rs_(1, j) + cdx;
      dzs_(1, j) = zs_(1, j) / ss_(1, j) * (-cdx + rs_(1, j)) + rhss_(1, j);
    }
  }
}

double StateIpm::max_step() const noexcept {
  double a = kInf;
  const auto ratio = [&a](double x, double dx) {
    if (dx < 0.0) a = std::min(a, -x / dx);
  };
  for (int v = 0; v < N_ * nu_; ++v)
    for (int q = 0; q < 4; ++q)
      if (sc_(q, v) > 0.0) {
        ratio(sc_(q, v), dsc_(q, v));
        ratio(zc_(q, v), dzc_(q, v));
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
  residuals(p);
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
  for (int v = 0; v < N_ * nu_; ++v)
    for (int q = 0; q < 4; ++q) sz_a += (sc_(q, v) + aa * dsc_(q, v)) * (zc_(q, v) + aa * dzc_(q, v));
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
  const double a = std::min(1.0, 0.99 * full_step());
  if (!(a > 0.0)) return false;
  ipm::take_step(a, u_, du_, t_, dt_, sc_, dsc_, zc_, dzc_, ss_, dss_, zs_, dzs_, scn_, dscn_, zcn_, dzcn_);
  nu_eq_.head(ne_) += a * dnu_.head(ne_);
  rollout(p, u_, X_);
  residuals(p);
  return u_.allFinite() && zc_.allFinite() && zs_.allFinite() && zcn_.allFinite() && std::isfinite(sz_);
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
