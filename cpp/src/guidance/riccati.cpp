// Riccati step with cached gains and an exact terminal constraint (see riccati.hpp).
#include "satgnc/guidance/riccati.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::guidance {

using Eigen::Dynamic;
using Eigen::Index;
using Eigen::Map;
using Eigen::Matrix;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {
// One backward Riccati stage before symmetrization, shared by the cached factorization and the full
// recursion (same operations in the same order): out = Q_k + A' P A - Qux' K, with Q_k = Q when
// use_q (Q acts on x_1..x_{N-1}) and 0 otherwise. AtP is scratch (receives A' P). No allocation.
template <class KBlock>
inline void riccati_stage(bool use_q, const MatrixXd& Q, const MatrixXd& A, const MatrixXd& P,
                          const MatrixXd& Qux, const KBlock& K, MatrixXd& AtP, MatrixXd& out) {
  AtP.noalias() = A.transpose() * P;
  if (use_q) {
    out = Q;
  } else {
    out.setZero();
  }
  out.noalias() += AtP * A;
  out.noalias() -= Qux.transpose() * K;
}
}  // namespace

void LtvDynamics::validate() const {
  using core::require;
  require(horizon >= 1, "horizon", "must be >= 1, got " + std::to_string(horizon));
  require(!A.empty() && !B.empty(), "A/B", "must hold 1 (time-invariant) or N matrices",
          "pass [A] for constant dynamics");
  require(A.size() == 1 || static_cast<int>(A.size()) == horizon, "A",
          "must hold 1 or N = " + std::to_string(horizon) + " matrices, got " + std::to_string(A.size()));
  require(B.size() == 1 || static_cast<int>(B.size()) == horizon, "B",
          "must hold 1 or N = " + std::to_string(horizon) + " matrices, got " + std::to_string(B.size()));
  require(c.empty() || c.size() == 1 || static_cast<int>(c.size()) == horizon, "c",
          "must hold 0, 1 or N vectors, got " + std::to_string(c.size()));
  const Index n = A[0].rows(), m = B[0].cols();
  require(n >= 1 && m >= 1, "A/B", "need nx >= 1 and nu >= 1");
  for (std::size_t k = 0; k < A.size(); ++k) {
    require(A[k].rows() == n && A[k].cols() == n, "A[" + std::to_string(k) + "]",
            "must be nx x nx = " + std::to_string(n) + " x " + std::to_string(n),
            "got " + std::to_string(A[k].rows()) + " x " + std::to_string(A[k].cols()));
    core::require_finite(A[k], "A[" + std::to_string(k) + "]");
  }
  for (std::size_t k = 0; k < B.size(); ++k) {
    require(B[k].rows() == n && B[k].cols() == m, "B[" + std::to_string(k) + "]",
            "must be nx x nu = " + std::to_string(n) + " x " + std::to_string(m),
            "got " + std::to_string(B[k].rows()) + " x " + std::to_string(B[k].cols()));
    core::require_finite(B[k], "B[" + std::to_string(k) + "]");
  }
  for (std::size_t k = 0; k < c.size(); ++k) {
    require(c[k].size() == n, "c[" + std::to_string(k) + "]",
            "must have nx = " + std::to_string(n) + " entries");
    core::require_finite(c[k], "c[" + std::to_string(k) + "]");
  }
}

namespace {
// y = M x for a small fixed-size column-major M, summed as a tree (pairs of columns) so the
// dependency chain of the recursions is log2(n) additions deep instead of n.
// out = M x + b; out must not alias x.
template <int NX, typename MM, typename VV, typename VB, typename VO>
inline void tree_matvec_add(const MM& M, const VV& x, const VB& b, VO& out) noexcept {
  if constexpr (NX == 6) {
    out = (((M.col(0) * x(0) + M.col(1) * x(1)) + (M.col(2) * x(2) + M.col(3) * x(3))) +
           (M.col(4) * x(4) + M.col(5) * x(5))) +
          b;
  } else {
    out.noalias() = M * x;
    out += b;
  }
}

void require_psd(const MatrixXd& M, Index n, const std::string& name, bool allow_empty) {
  using core::require;
  if (allow_empty && M.size() == 0) return;
  require(M.rows() == n && M.cols() == n, name,
          "must be " + std::to_string(n) + " x " + std::to_string(n) + ", got " + std::to_string(M.rows()) +
              " x " + std::to_string(M.cols()));
  core::require_finite(M, name);
  const double scale = std::max(1.0, M.cwiseAbs().maxCoeff());
  require((M - M.transpose()).cwiseAbs().maxCoeff() <= 1e-10 * scale, name, "must be symmetric",
          "pass (M + M') / 2");
  Eigen::SelfAdjointEigenSolver<MatrixXd> es(M, Eigen::EigenvaluesOnly);
  require(es.eigenvalues().minCoeff() >= -1e-10 * scale, name, "must be positive semidefinite",
          "weights are variances' inverses: no negative eigenvalues");
}
}  // namespace

RiccatiSolver::RiccatiSolver(const RiccatiProblem& problem) {
  init(problem.dynamics, problem.Q, problem.R, problem.Qf, problem.terminal_equality);
}

void RiccatiSolver::init(const LtvDynamics& dyn, const MatrixXd& Q, const MatrixXd& R, const MatrixXd& Qf,
                         bool terminal_equality) {
  dyn.validate();
  nx_ = dyn.nx();
  nu_ = dyn.nu();
  N_ = dyn.horizon;
  require_psd(Q, nx_, "Q", true);
  require_psd(R, nu_, "R", true);
  require_psd(Qf, nx_, "Qf", false);
  dyn_ = dyn;
  Q_ = Q;
  R_ = R;
  Qf_ = Qf;
  terminal_ = terminal_equality;
  factored_ = false;
  factorizations_ = 0;
  const Index n = nx_, m = nu_, N = N_;
  ws_.P.setZero(n, n * (N + 1));
  ws_.K.setZero(m, n * N);
  ws_.AclT.setZero(n, n * N);
  ws_.Acl.setZero(n, n * N);
  ws_.QuuInv.setZero(m, m * N);
  ws_.QuuInvBt.setZero(m, n * N);
  ws_.e.setZero(n, N);
  ws_.D.setZero(m, N);
  ws_.Hbuf.setZero(n, N);
  ws_.Wbuf.setZero(n, N);
  ws_.K2.setZero(m, n * N);
  ws_.D2.setZero(m, N);
  ws_.Inu = MatrixXd::Identity(m, m);
  if (terminal_) {
    ws_.T.setZero(m, n * N);
    ws_.Z.setZero(n, n * (N + 1));
    ws_.S.setZero(n, n);
    ws_.Spinv.setZero(n, n);
    ws_.eigvec.setZero(n, n);
    ws_.eigval.setZero(n);
  }
  ws_.BtP.setZero(m, n);
  ws_.Quu.setZero(m, m);
  ws_.Qux.setZero(m, n);
  ws_.AtP.setZero(n, n);
  ws_.tmp_nx_nx.setZero(n, n);
  ws_.tmp_nu_nu.setZero(m, m);
  ws_.Pn.setZero(n, n);
  ws_.W.setZero(n, n);
  ws_.Wn.setZero(n, n);
  // Factor the identity so that every member of the LLT (its info flag too) is initialised before the
  // move: Eigen 3.4 leaves m_info uninitialised in LLT(Index), which UBSan reports when moved.
  ws_.llt = Eigen::LLT<MatrixXd>(MatrixXd::Identity(m, m));
  ws_.p.setZero(n);
  ws_.w.setZero(n);
  ws_.tmp_nx.setZero(n);
  ws_.tmp_nu.setZero(m);
  ws_.nu_term.setZero(n);
  ws_.miss.setZero(n);
}

bool RiccatiSolver::factor_stage(int k, double rho) noexcept {
  const Index n = nx_, m = nu_;
  const MatrixXd& A = dyn_.A_at(k);
  const MatrixXd& B = dyn_.B_at(k);
  ws_.Pn = ws_.P.middleCols((k + 1) * n, n);
  ws_.BtP.noalias() = B.transpose() * ws_.Pn;
  if (R_.size() != 0) {
    ws_.Quu = R_;
  } else {
    ws_.Quu.setZero();
  }
  ws_.Quu.diagonal().array() += rho;
  ws_.Quu.noalias() += ws_.BtP * B;
  ws_.Qux.noalias() = ws_.BtP * A;
  ws_.llt.compute(ws_.Quu);
  if (ws_.llt.info() != Eigen::Success) return false;
  ws_.tmp_nu_nu = ws_.Inu;
  ws_.llt.solveInPlace(ws_.tmp_nu_nu);
  ws_.QuuInv.middleCols(k * m, m) = ws_.tmp_nu_nu;
  ws_.K.middleCols(k * n, n).noalias() = ws_.tmp_nu_nu * ws_.Qux;
  ws_.QuuInvBt.middleCols(k * n, n).noalias() = ws_.tmp_nu_nu * B.transpose();
  ws_.tmp_nx_nx = A;
  ws_.tmp_nx_nx.noalias() -= B * ws_.K.middleCols(k * n, n);
  ws_.Acl.middleCols(k * n, n) = ws_.tmp_nx_nx;
  ws_.AclT.middleCols(k * n, n) = ws_.tmp_nx_nx.transpose();
  // P_k = Q + A'P A - Qux' K (Q acts on x_1..x_{N-1})
  riccati_stage(Q_.size() != 0 && k >= 1, Q_, A, ws_.Pn, ws_.Qux, ws_.K.middleCols(k * n, n), ws_.AtP,
                ws_.tmp_nx_nx);
  ws_.AtP = ws_.tmp_nx_nx.transpose();
  ws_.tmp_nx_nx += ws_.AtP;
  ws_.P.middleCols(k * n, n) = 0.5 * ws_.tmp_nx_nx;
  if (!dyn_.c.empty()) {
    const VectorXd& c = dyn_.c.size() == 1 ? dyn_.c[0] : dyn_.c[k];
    ws_.e.col(k).noalias() = ws_.Pn * c;
  }
  return true;
}

bool RiccatiSolver::factor(double rho) noexcept {
  SATGNC_NO_MALLOC_SCOPE;
  factored_ = false;
  if (nx_ == 0 || !(rho >= 0.0) || !std::isfinite(rho)) return false;
  const Index n = nx_, N = N_;
  // Under x_N = x_f the terminal cost is constant on the feasible set: dropping it is exact and
  // avoids the cancellation between a large Qf and the terminal multiplier.
  if (terminal_) {
    ws_.P.middleCols(N * n, n).setZero();
  } else {
    ws_.P.middleCols(N * n, n) = Qf_;
  }
  for (int k = N_ - 1; k >= 0; --k) {
    if (!factor_stage(k, rho)) return false;
  }
  rho_ = rho;
  ++factorizations_;
  if (terminal_) {
    // Responses to a unit terminal multiplier (p_N = e_j), all nx columns at once.
    ws_.W.setIdentity();  // p_{k+1} for each unit multiplier
    for (Index k = N - 1; k >= 0; --k) {
      ws_.T.middleCols(k * n, n).noalias() = ws_.QuuInvBt.middleCols(k * n, n) * ws_.W;  // d_k
      ws_.Wn.noalias() = ws_.AclT.middleCols(k * n, n) * ws_.W;
      ws_.W = ws_.Wn;
    }
    ws_.Z.middleCols(0, n).setZero();
    for (Index k = 0; k < N; ++k) {
      const MatrixXd& A = dyn_.A_at(static_cast<int>(k));
      const MatrixXd& B = dyn_.B_at(static_cast<int>(k));
      // u = -K z - d  (stored over d), z+ = A z + B u
      ws_.tmp_nx_nx = ws_.Z.middleCols(k * n, n);
      ws_.T.middleCols(k * n, n) *= -1.0;
      ws_.T.middleCols(k * n, n).noalias() -= ws_.K.middleCols(k * n, n) * ws_.tmp_nx_nx;
      ws_.Z.middleCols((k + 1) * n, n).noalias() = A * ws_.tmp_nx_nx;
      ws_.Z.middleCols((k + 1) * n, n).noalias() += B * ws_.T.middleCols(k * n, n);
    }
    ws_.S = ws_.Z.middleCols(N * n, n);
    ws_.tmp_nx_nx = ws_.S.transpose();
    ws_.tmp_nx_nx += ws_.S;
    ws_.tmp_nx_nx *= 0.5;
    jacobi_eigen(ws_.tmp_nx_nx, ws_.eigvec, ws_.eigval);
    const double lmax = ws_.eigval.cwiseAbs().maxCoeff();
    rank_ = 0;
    ws_.Spinv.setZero();
    for (Index i = 0; i < n; ++i) {
      // 1e-14: an ill-conditioned but full-rank sensitivity (long CW horizons, scaled controls) is
      // still inverted; an exactly rank-deficient one has eigenvalues at rounding level (~1e-16)
      if (std::abs(ws_.eigval(i)) > 1e-14 * lmax && lmax > 0.0) {
        ++rank_;
        ws_.Spinv.noalias() += (1.0 / ws_.eigval(i)) * ws_.eigvec.col(i) * ws_.eigvec.col(i).transpose();
      }
    }
  }
  factored_ = true;
  return true;
}

template <int NX, int NU>
void RiccatiSolver::affine_sweep(const Eigen::Ref<const VectorXd>& x0, const Eigen::Ref<const MatrixXd>& q,
                                 const Eigen::Ref<const MatrixXd>& r, Eigen::Ref<MatrixXd> X,
                                 Eigen::Ref<MatrixXd> U) noexcept {
  // Hot loop: every operand is a Map of compile-time size (in the (6, 3) instantiation) on the
  // contiguous cached blocks; no dynamic-size expressions, no temporaries.
  using VX = Matrix<double, NX, 1>;
  using VU = Matrix<double, NU, 1>;
  using MXX = Matrix<double, NX, NX>;
  using MUX = Matrix<double, NU, NX>;
  using MUU = Matrix<double, NU, NU>;
  using MXU = Matrix<double, NX, NU>;
  const Index n = nx_, m = nu_, N = N_;
  const bool has_c = !dyn_.c.empty();
  const bool c_const = dyn_.c.size() == 1;
  const bool ti = dyn_.A.size() == 1 && dyn_.B.size() == 1;
  const Index qs = q.outerStride(), rs = r.outerStride(), xs = X.outerStride(), us = U.outerStride();
  const double* qd = q.data();
  const double* rd = r.data();
  double* Xd = X.data();
  double* Ud = U.data();
  const double* Ginv0 = ws_.QuuInv.data();
  const double* GB0 = ws_.QuuInvBt.data();
  const double* AclT0 = ws_.AclT.data();
  const double* K0 = ws_.K.data();
  const double* e0 = ws_.e.data();
  double* D0 = ws_.D.data();
  // fixed-size locals live on the stack; the dynamic instantiation uses the preallocated members
  Map<VX> p(ws_.p.data(), n), w(ws_.w.data(), n), x(ws_.tmp_nx.data(), n), xn(ws_.miss.data(), n);
  Map<VU> u(ws_.tmp_nu.data(), m);
  if (terminal_) {
    p.setZero();
  } else {
    p = Map<const VX>(qd + N * qs, n);
  }
  for (Index k = N - 1; k >= 0; --k) {
    if (has_c) {
      w = p + Map<const VX>(e0 + k * n, n);
    } else {
      w = p;
    }
    Map<const VU> rk(rd + k * rs, m);
    Map<VU> dk(D0 + k * m, m);
    Map<const MUU> Ginv(Ginv0 + k * m * m, m, m);
    Map<const MUX> GB(GB0 + k * m * n, m, n);
    Map<const MXX> AclT(AclT0 + k * n * n, n, n);
    Map<const MUX> K(K0 + k * m * n, m, n);
    dk.noalias() = Ginv * rk;
    dk.noalias() += GB * w;
    // off the dependency chain first, then one tree-summed n x n product on it
    xn.noalias() = K.transpose() * rk;  // products assigned alone: no temporary in the dynamic path
    xn = Map<const VX>(qd + k * qs, n) - xn;
    tree_matvec_add<NX>(AclT, w, xn, p);
  }
  // forward: u_k = -K_k x_k - d_k and x_{k+1} = (A - B K)_k x_k - B_k d_k + c_k: the chain is one
  // tree-summed n x n product; the control and the affine part are off it
  const double* Acl0 = ws_.Acl.data();
  x = x0;
  Map<VX>(Xd, n) = x;
  for (Index k = 0; k < N; ++k) {
    Map<const MUX> K(K0 + k * m * n, m, n);
    Map<const MXX> Acl(Acl0 + k * n * n, n, n);
    Map<const MXU> B(ti ? dyn_.B[0].data() : dyn_.B_at(static_cast<int>(k)).data(), n, m);
    Map<const VU> dk(D0 + k * m, m);
    u.noalias() = K * x;
    u = -u - dk;
    Map<VU>(Ud + k * us, m) = u;
    w.noalias() = B * dk;
    w = -w;
    if (has_c) w += Map<const VX>(c_const ? dyn_.c[0].data() : dyn_.c[k].data(), n);
    tree_matvec_add<NX>(Acl, x, w, xn);
    Map<VX>(Xd + (k + 1) * xs, n) = xn;
    x = xn;
  }
}

// The (6, 3) kernel: every vector is a local fixed-size value (kept in registers, no aliasing with
// the outputs), and each serial recursion is a loop of one tree-summed 6x6 product plus one add, with
// everything else moved to independent passes over the stages:
//   pass 1 (independent): h_k = q_k - K_k' r_k
//   chain 1 (backward):   w_k = p_{k+1} + e_k (stored),  p_k = Acl_k' w_k + h_k
//   pass 2 (independent): d_k = Quu_k^-1 r_k + (Quu_k^-1 B_k') w_k,  f_k = c_k - B_k d_k
//   chain 2 (forward):    x_{k+1} = Acl_k x_k + f_k, then (independent) u_k = -K_k x_k - d_k.
void RiccatiSolver::affine_sweep_63(const Eigen::Ref<const VectorXd>& x0, const Eigen::Ref<const MatrixXd>& q,
                                    const Eigen::Ref<const MatrixXd>& r, Eigen::Ref<MatrixXd> X,
                                    Eigen::Ref<MatrixXd> U) noexcept {
  using V6 = Matrix<double, 6, 1>;
  using V3 = Matrix<double, 3, 1>;
  using M6 = Matrix<double, 6, 6>;
  using M36 = Matrix<double, 3, 6>;
  using M33 = Matrix<double, 3, 3>;
  using M63 = Matrix<double, 6, 3>;
  const Index N = N_;
  const bool has_c = !dyn_.c.empty();
  const bool c_const = dyn_.c.size() == 1;
  const bool ti = dyn_.B.size() == 1;
  const Index qs = q.outerStride(), rs = r.outerStride(), xs = X.outerStride(), us = U.outerStride();
  const double* qd = q.data();
  const double* rd = r.data();
  double* Xd = X.data();
  double* Ud = U.data();
  const double* K0 = ws_.K.data();
  const double* AclT0 = ws_.AclT.data();
  const double* Acl0 = ws_.Acl.data();
  const double* Ginv0 = ws_.QuuInv.data();
  const double* GB0 = ws_.QuuInvBt.data();
  const double* e0 = ws_.e.data();
  double* H0 = ws_.Hbuf.data();  // h_k, then f_k
  double* D0 = ws_.D.data();
  const double* c0 = has_c ? dyn_.c[0].data() : nullptr;
  V6 p = terminal_ ? V6::Zero() : V6(Map<const V6>(qd + N * qs));
  for (Index k = N - 1; k >= 0; --k) {
    const V6 w = has_c ? V6(p + Map<const V6>(e0 + 6 * k)) : p;
    const V3 rk = Map<const V3>(rd + k * rs);
    const Map<const M6> AT(AclT0 + 36 * k);
    // off the chain: d_k, f_k = c_k - B_k d_k, h_k = q_k - K_k' r_k
    const V3 d = Map<const M33>(Ginv0 + 9 * k) * rk + Map<const M36>(GB0 + 18 * k) * w;
    Map<V3>(D0 + 3 * k) = d;
    const Map<const M63> B(ti ? dyn_.B[0].data() : dyn_.B[static_cast<std::size_t>(k)].data());
    V6 f = -(B * d);
    if (has_c) f += Map<const V6>(c_const ? c0 : dyn_.c[static_cast<std::size_t>(k)].data());
    Map<V6>(H0 + 6 * k) = f;
    const V6 h = Map<const V6>(qd + k * qs) - Map<const M36>(K0 + 18 * k).transpose() * rk;
    p = (((AT.col(0) * w(0) + AT.col(1) * w(1)) + (AT.col(2) * w(2) + AT.col(3) * w(3))) +
         (AT.col(4) * w(4) + AT.col(5) * w(5))) +
        h;
  }
  V6 x = Map<const V6>(x0.data());
  Map<V6>(Xd + 0) = x;
  for (Index k = 0; k < N; ++k) {
    const Map<const M6> Ac(Acl0 + 36 * k);
    Map<V3>(Ud + k * us) = -(Map<const M36>(K0 + 18 * k) * x) - Map<const V3>(D0 + 3 * k);
    x = (((Ac.col(0) * x(0) + Ac.col(1) * x(1)) + (Ac.col(2) * x(2) + Ac.col(3) * x(3))) +
         (Ac.col(4) * x(4) + Ac.col(5) * x(5))) +
        Map<const V6>(H0 + 6 * k);
    Map<V6>(Xd + (k + 1) * xs) = x;
  }
}

template <int NX, int NU>
RiccatiStatus RiccatiSolver::apply_terminal(const Eigen::Ref<const VectorXd>& xf, Eigen::Ref<MatrixXd> X,
                                            Eigen::Ref<MatrixXd> U) noexcept {
  using VX = Matrix<double, NX, 1>;
  using VU = Matrix<double, NU, 1>;
  using MXX = Matrix<double, NX, NX>;
  using MUX = Matrix<double, NU, NX>;
  const Index n = nx_, m = nu_, N = N_;
  const Index xs = X.outerStride(), us = U.outerStride();
  Map<VX> miss(ws_.miss.data(), n), nt(ws_.nu_term.data(), n);
  miss = Map<const VX>(xf.data(), n) - Map<const VX>(X.data() + N * xs, n);
  const double miss0 = miss.norm();
  nt.noalias() = Map<const MXX>(ws_.Spinv.data(), n, n) * miss;
  const double* T0 = ws_.T.data();
  const double* Z0 = ws_.Z.data();
  double* Xd = X.data();
  double* Ud = U.data();
  for (Index k = 0; k < N; ++k) {
    Map<VU>(Ud + k * us, m).noalias() += Map<const MUX>(T0 + k * m * n, m, n) * nt;
    Map<VX>(Xd + (k + 1) * xs, n).noalias() += Map<const MXX>(Z0 + (k + 1) * n * n, n, n) * nt;
  }
  if (rank_ < n) {
    const double after = (xf - X.col(N)).norm();
    if (after > 1e-6 * std::max(miss0, xf.norm()) && after > 1e-300)
      return RiccatiStatus::terminal_unreachable;
  }
  return RiccatiStatus::solved;
}

RiccatiStatus RiccatiSolver::solve(const Eigen::Ref<const VectorXd>& x0, const Eigen::Ref<const MatrixXd>& q,
                                   const Eigen::Ref<const MatrixXd>& r, const Eigen::Ref<const VectorXd>& xf,
                                   Eigen::Ref<MatrixXd> X, Eigen::Ref<MatrixXd> U) noexcept {
  SATGNC_NO_MALLOC_SCOPE;
  if (!factored_) return RiccatiStatus::unsolved;
  if (nx_ == 6 && nu_ == 3) {
    affine_sweep_63(x0, q, r, X, U);
    return terminal_ ? apply_terminal<6, 3>(xf, X, U) : RiccatiStatus::solved;
  }
  affine_sweep<Dynamic, Dynamic>(x0, q, r, X, U);
  return terminal_ ? apply_terminal<Dynamic, Dynamic>(xf, X, U) : RiccatiStatus::solved;
}

RiccatiStatus RiccatiSolver::solve_full(double rho, const Eigen::Ref<const VectorXd>& x0,
                                        const Eigen::Ref<const MatrixXd>& q,
                                        const Eigen::Ref<const MatrixXd>& r,
                                        const Eigen::Ref<const VectorXd>& xf, Eigen::Ref<MatrixXd> X,
                                        Eigen::Ref<MatrixXd> U) noexcept {
  if (terminal_ && !factored_) return RiccatiStatus::unsolved;
  const Index n = nx_, m = nu_, N = N_;
  // value function V_k(x) = 1/2 x' P x + p' x, recomputed from scratch (eqs. (12)-(21) of the paper)
  if (terminal_) {  // see factor()
    ws_.W.setZero();
    ws_.p.setZero();
  } else {
    ws_.W = Qf_;  // P_{k+1}
    ws_.p = q.col(N);
  }
  for (Index k = N - 1; k >= 0; --k) {
    const MatrixXd& A = dyn_.A_at(static_cast<int>(k));
    const MatrixXd& B = dyn_.B_at(static_cast<int>(k));
    ws_.w = ws_.p;
    if (!dyn_.c.empty()) ws_.w.noalias() += ws_.W * (dyn_.c.size() == 1 ? dyn_.c[0] : dyn_.c[k]);
    ws_.BtP.noalias() = B.transpose() * ws_.W;
    if (R_.size() != 0) {
      ws_.Quu = R_;
    } else {
      ws_.Quu.setZero();
    }
    ws_.Quu.diagonal().array() += rho;
    ws_.Quu.noalias() += ws_.BtP * B;
    ws_.Qux.noalias() = ws_.BtP * A;
    ws_.tmp_nu = r.col(k);
    ws_.tmp_nu.noalias() += B.transpose() * ws_.w;  // qu
    ws_.llt.compute(ws_.Quu);
    if (ws_.llt.info() != Eigen::Success) return RiccatiStatus::unsolved;
    ws_.K2.middleCols(k * n, n) = ws_.Qux;
    auto Kk = ws_.K2.middleCols(k * n, n);
    ws_.llt.solveInPlace(Kk);
    ws_.D2.col(k) = ws_.tmp_nu;
    auto dk = ws_.D2.col(k);
    ws_.llt.solveInPlace(dk);
    // p_k = q_k + A' w - Qux' d_k ;  P_k = Q + A' P A - Qux' K
    ws_.p = q.col(k);
    ws_.p.noalias() += A.transpose() * ws_.w;
    ws_.p.noalias() -= ws_.Qux.transpose() * ws_.D2.col(k);
    riccati_stage(Q_.size() != 0 && k >= 1, Q_, A, ws_.W, ws_.Qux, ws_.K2.middleCols(k * n, n), ws_.AtP,
                  ws_.Wn);
    ws_.W = ws_.Wn.transpose();
    ws_.W += ws_.Wn;
    ws_.W *= 0.5;
  }
  ws_.tmp_nx = x0;
  X.col(0) = ws_.tmp_nx;
  for (Index k = 0; k < N; ++k) {
    const MatrixXd& A = dyn_.A_at(static_cast<int>(k));
    const MatrixXd& B = dyn_.B_at(static_cast<int>(k));
    ws_.tmp_nu.noalias() = ws_.K2.middleCols(k * n, n) * ws_.tmp_nx;
    ws_.tmp_nu = -ws_.tmp_nu - ws_.D2.col(k);
    U.col(k) = ws_.tmp_nu;
    X.col(k + 1).noalias() = A * ws_.tmp_nx;
    X.col(k + 1).noalias() += B * ws_.tmp_nu;
    if (!dyn_.c.empty()) X.col(k + 1) += dyn_.c.size() == 1 ? dyn_.c[0] : dyn_.c[k];
    ws_.tmp_nx = X.col(k + 1);
  }
  (void)m;
  if (terminal_) {
    return nx_ == 6 && nu_ == 3 ? apply_terminal<6, 3>(xf, X, U) : apply_terminal<Dynamic, Dynamic>(xf, X, U);
  }
  return RiccatiStatus::solved;
}

void jacobi_eigen(Eigen::Ref<MatrixXd> S, Eigen::Ref<MatrixXd> V, Eigen::Ref<VectorXd> w) noexcept {
  const Index n = S.rows();
  V.setIdentity();
  for (int sweep = 0; sweep < 100; ++sweep) {
    double off = 0.0, diag = 0.0;
    for (Index i = 0; i < n; ++i) {
      diag += S(i, i) * S(i, i);
      for (Index j = i + 1; j < n; ++j) off += S(i, j) * S(i, j);
    }
    if (off <= 1e-32 * diag || off == 0.0) break;
    for (Index p = 0; p < n; ++p) {
      for (Index q = p + 1; q < n; ++q) {
        const double apq = S(p, q);
        if (apq == 0.0) continue;
        const double theta = (S(q, q) - S(p, p)) / (2.0 * apq);
        const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (Index k = 0; k < n; ++k) {  // columns p, q
          const double skp = S(k, p), skq = S(k, q);
          S(k, p) = c * skp - s * skq;
          S(k, q) = s * skp + c * skq;
        }
        for (Index k = 0; k < n; ++k) {  // rows p, q
          const double spk = S(p, k), sqk = S(q, k);
          S(p, k) = c * spk - s * sqk;
          S(q, k) = s * spk + c * sqk;
        }
        for (Index k = 0; k < n; ++k) {
          const double vkp = V(k, p), vkq = V(k, q);
          V(k, p) = c * vkp - s * vkq;
          V(k, q) = s * vkp + c * vkq;
        }
      }
    }
  }
  w = S.diagonal();
}

bool RiccatiSolver::set_stage_dynamics(int k, const Eigen::Ref<const MatrixXd>& A,
                                       const Eigen::Ref<const MatrixXd>& B,
                                       const Eigen::Ref<const VectorXd>& c) noexcept {
  if (k < 0 || k >= N_) return false;
  const auto ku = static_cast<std::size_t>(k);
  if ((dyn_.A.size() == 1 && N_ > 1) || (dyn_.B.size() == 1 && N_ > 1)) return false;
  if (A.rows() != nx_ || A.cols() != nx_ || B.rows() != nx_ || B.cols() != nu_) return false;
  if (!A.allFinite() || !B.allFinite() || !c.allFinite()) return false;
  if (dyn_.c.empty() ? c.size() != 0 : (c.size() != nx_ || (dyn_.c.size() == 1 && N_ > 1))) return false;
  dyn_.A[ku] = A;
  dyn_.B[ku] = B;
  if (!dyn_.c.empty()) dyn_.c[ku] = c;
  factored_ = false;
  return true;
}

}  // namespace satgnc::guidance
