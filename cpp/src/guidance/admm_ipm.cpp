// Interior-point method of the ADMM solver (AdmmSettings::method): Mehrotra predictor-corrector on
// the equilibrated L1 + box problem. Per entry j = (k, i) of U the L1 term is an epigraph t_j with
// slacks s1 = t - u, s2 = t + u >= 0 (w_j > 0) and the box gives s3 = u - lo, s4 = hi - u >= 0. The
// Newton system eliminates t, s and z entry by entry into a diagonal D added to R, which leaves one
// equality-constrained LQR problem per step, solved by a time-varying Riccati recursion (with the
// terminal-constraint sensitivity for x_N = x_f). The condensed nx x nx form of that step was tried
// and dropped: ill-conditioned once D spans many decades (docs/guidance.md). The plan is accepted
// only through the solver's own gap test (admm_gap.cpp).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>

#include "detail/admm_workspace.hpp"
#include "detail/ipm_kernel.hpp"

namespace satgnc::guidance::detail {

using Eigen::ArrayXd;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

void AdmmWorkspace::ipm_setup() {
  ipm_ok_ = flat_ok_;  // L1 + box (no group-L2 or ball: second-order cones stay ADMM-only)
  if (!ipm_ok_) return;
  const Index n = static_cast<Index>(N_) * nu_;
  for (ArrayXd* a : {&is1_,  &is2_,  &is3_,  &is4_,  &iz1_,  &iz2_,  &iz3_,  &iz4_,  &id_,   &ilin_,
                     &irt_,  &idu_,  &idt_,  &ids1_, &ids2_, &ids3_, &ids4_, &idz1_, &idz2_, &idz3_,
                     &idz4_, &ia1_,  &ia2_,  &ia3_,  &ia4_,  &ib1_,  &ib2_,  &ib3_,  &ib4_,  &itv_,
                     &irp1_, &irp2_, &irp3_, &irp4_, &isi1_, &isi2_, &isi3_, &isi4_, &izs1_, &izs2_,
                     &izs3_, &izs4_, &ihut_, &ihtt_, &izi1_, &izi2_, &izi3_, &izi4_, &iszv_, &ipwv_})
    a->setZero(n);
  im1_ = (wrep_ > 0.0).cast<double>();
  im3_ = (lorep_ > -kInf).cast<double>();
  im4_ = (hirep_ < kInf).cast<double>();
  ipm_m_ = static_cast<int>(2.0 * im1_.sum() + im3_.sum() + im4_.sum());
  // the gap's vectorized conjugate (conj_g_flat, admm_gap.cpp): the same products as conj_g
  gch_ = wrep_ * hifin_.abs();
  gcl_ = wrep_ * lofin_.abs();
  gzok_ = (lorep_ <= 0.0 && hirep_ >= 0.0).cast<double>();
  gbuf_.setZero(n);
  iU_.setZero(nu_, N_);
  iX_.setZero(nx_, N_ + 1);
  idX_.setZero(nx_, N_ + 1);
  ie_.setZero(nx_);
  inu_.setZero(nx_);
  inun_.setZero(nx_);
  iep_.setZero(nx_);
  ie2_.setZero(nx_);
  ilu_ = Eigen::PartialPivLU<MatrixXd>(nx_);
  iS_.setZero(nx_, nx_);
  iK_.setZero(nu_, nx_ * N_);
  iQi_.setZero(nu_, nu_ * N_);
  iQux_.setZero(nu_, nx_ * N_);
  iKnu_.setZero(nu_, nx_ * N_);
  ikff_.setZero(nu_, N_);
  for (MatrixXd* m : {&iP_, &iPn_, &iL_, &iLn_, &iAcl_, &iZ_}) m->setZero(nx_, nx_);
  iBtP_.setZero(nu_, nx_);
  iBtL_.setZero(nu_, nx_);
  iQuu_.setZero(nu_, nu_);
  iInu_ = MatrixXd::Identity(nu_, nu_);
  ipm_setup_cw();
  illt_.compute(MatrixXd::Identity(
      nu_, nu_));  // sized and with its info set (a moved-from LLT(n) reads an unset info: UBSan)
  ip_.setZero(nx_);
  icU_.setZero(nu_, N_);
  icnu_.setZero(nx_);
  ice_.setZero(nx_);
  ipn_.setZero(nx_);
  iqu_.setZero(nu_);
  idx_.setZero(nx_);
  idxn_.setZero(nx_);
}

// Stage views of the stored per-stage blocks, fixed-size for the (6, 3) CW case (the products then
// unroll), dynamic otherwise; all storage is preallocated, nothing is allocated here.
template <int NX, int NU>
bool AdmmWorkspace::ipm_riccati_factor() noexcept {
  using MXX = Eigen::Matrix<double, NX, NX>;
  using MUX = Eigen::Matrix<double, NU, NX>;
  using MXU = Eigen::Matrix<double, NX, NU>;
  using MUU = Eigen::Matrix<double, NU, NU>;
  const bool term = prob_.terminal_equality;
  const LtvDynamics& d = prob_.dynamics;
  const bool has_r = prob_.R.size() != 0, has_q = prob_.Q.size() != 0;
  const Index nx = nx_, nu = nu_;
  Eigen::Map<MXX> P(iP_.data(), nx, nx), Pn(iPn_.data(), nx, nx), L(iL_.data(), nx, nx),
      Ln(iLn_.data(), nx, nx), Acl(iAcl_.data(), nx, nx), Z(iZ_.data(), nx, nx);
  Eigen::Map<MUX> BtP(iBtP_.data(), nu, nx), BtL(iBtL_.data(), nu, nx);
  Eigen::Map<MUU> Quu(iQuu_.data(), nu, nu);
  P = prob_.Qf;
  if (term) {
    L.setIdentity();
    Z.setZero();  // W: the nu-nu block of the value function; at k = 0 it is S = dx_N / dnu
  }
  for (int k = N_ - 1; k >= 0; --k) {
    const Eigen::Map<const MXX> A(d.A_at(k).data(), nx, nx);
    const Eigen::Map<const MXU> B(d.B_at(k).data(), nx, nu);
    Eigen::Map<MUU> Qi(iQi_.data() + k * nu * nu, nu, nu);
    Eigen::Map<MUX> Qux(iQux_.data() + k * nu * nx, nu, nx), K(iK_.data() + k * nu * nx, nu, nx),
        Knu(iKnu_.data() + k * nu * nx, nu, nx);
    BtP.noalias() = B.transpose() * P;
    Quu.noalias() = BtP * B;
    if (has_r) Quu += prob_.R;
    for (int i = 0; i < nu_; ++i) Quu(i, i) += id_(static_cast<Index>(k) * nu_ + i);
    // a relative shift of the stage Hessian where it lost definiteness to rounding
    if constexpr (NU == 3) {
      if (!ipm::ldl_inverse3_shifted(Quu, Qi, 1e-14, 1e-6, 0.0)) return false;
    } else {
      std::conditional_t<NU == Eigen::Dynamic, Eigen::LLT<MatrixXd>&, Eigen::LLT<MUU>> llt = llt_ref<NU>();
      if (!ipm::llt_with_shift(llt, Quu, 1e-14, 1e-6, 0.0)) return false;
      Qi.setIdentity();
      llt.solveInPlace(Qi);
    }
    Qux.noalias() = BtP * A;
    K.noalias() = -Qi * Qux;
    if (term) {
      BtL.noalias() = B.transpose() * L;
      Knu.noalias() = -Qi * BtL;
      Z.noalias() += BtL.transpose() * Knu;  // W_k = W_{k+1} - (B'L)' Quu^-1 (B'L)
      Acl = A;
      Acl.noalias() += B * K;
      Ln.noalias() = Acl.transpose() * L;
      L = Ln;
    }
    if (k == 0) break;
    Pn.noalias() = P * A;
    P.noalias() = A.transpose() * Pn;
    P.noalias() += Qux.transpose() * K;
    if (has_q) P += prob_.Q;
    Pn = P.transpose();
    P += Pn;
    P *= 0.5;
  }
  if (!P.allFinite()) return false;
  if (term) {
    // sensitivity S = dx_N / dnu = W_0 (envelope: x_N is the derivative of the value in nu)
    iS_ = iZ_;
  }
  return true;
}

// The (6, 3) CW stage of ipm_riccati_factor written out on column-major arrays (Eigen's fixed-size
// Map products were not inlined: ~3200 instructions per stage, callgrind). Every product is an axpy
// over a contiguous column (vectorized without reordering a sum), with A' and B' stored per stage;
// symmetric results are formed once per pair (i <= j) and mirrored: B'PB, A'PA + Qux'K (+ Q), the
// terminal W += (B'L)' Knu; L_k = A'L + K'(B'L) (= (A + BK)' L).
namespace {
using ipm::mm;  // out (r x c) = X (r x n) Y (n x c), column-major (detail/ipm_kernel.hpp)
// One stage of the terminal-constraint recursion (written out, the operations of the Eigen form) on an
// NX x NU block, column-major: Knu = -Qi B'L; W_k = W_{k+1} + (B'L)' Knu; L_k = A'L + K'(B'L). At, Bt:
// A', B' of the block; Qi, K: its Quu^-1 and gain; L, Z (W) updated in place; Ln scratch.
template <int NX, int NU>
void terminal_stage(const double* At, const double* Bt, const double* Qi, const double* K, double* L,
                    double* Z, double* Ln, double* Knu) noexcept {
  double BtL[NU * NX], QK[NX * NX];
  mm<NU, NX, NX>(Bt, L, BtL);  // B'L
  mm<NU, NU, NX>(Qi, BtL, Knu);
  for (int j = 0; j < NU * NX; ++j) Knu[j] = -Knu[j];
  double Kt[NX * NU], BtLt[NX * NU];
  for (int i = 0; i < NU; ++i)
    for (int j = 0; j < NX; ++j) {
      Kt[j + NX * i] = K[i + NU * j];
      BtLt[j + NX * i] = BtL[i + NU * j];
    }
  mm<NX, NU, NX>(BtLt, Knu, QK);
  for (int j = 0; j < NX * NX; ++j) Z[j] += QK[j];
  mm<NX, NX, NX>(At, L, Ln);
  mm<NX, NU, NX>(Kt, BtL, QK);
  for (int j = 0; j < NX * NX; ++j) L[j] = Ln[j] + QK[j];
}
}  // namespace

bool AdmmWorkspace::ipm_riccati_factor_63() noexcept {
  const bool term = prob_.terminal_equality;
  const LtvDynamics& d = prob_.dynamics;
  const bool has_r = prob_.R.size() != 0, has_q = prob_.Q.size() != 0;
  double* P = iP_.data();  // 6 x 6, column-major
  double* L = iL_.data();
  double* Z = iZ_.data();
  double* PA = iPn_.data();
  double* Ln = iLn_.data();
  double* At = iAcl_.data();                            // A' of the stage
  double PB[18], Bt[18] = {}, Quu[9], APA[36], QK[36];  // Bt set at k = N - 1 (B != Bprev)
  std::copy(prob_.Qf.data(), prob_.Qf.data() + 36, P);
  if (term) {
    for (int j = 0; j < 36; ++j) {
      L[j] = (j % 7 == 0) ? 1.0 : 0.0;
      Z[j] = 0.0;
    }
  }
  const double* Aprev = nullptr;
  const double* Bprev = nullptr;
  for (int k = N_ - 1; k >= 0; --k) {
    const double* A = d.A_at(k).data();
    const double* B = d.B_at(k).data();
    if (A != Aprev) {  // time-invariant dynamics: transposed once
      for (int i = 0; i < 6; ++i)
        for (int l = 0; l < 6; ++l) At[i + 6 * l] = A[l + 6 * i];
      Aprev = A;
    }
    if (B != Bprev) {
      for (int i = 0; i < 3; ++i)
        for (int l = 0; l < 6; ++l) Bt[i + 3 * l] = B[l + 6 * i];
      Bprev = B;
    }
    double* Qi = iQi_.data() + k * 9;
    double* Qux = iQux_.data() + k * 18;
    double* K = iK_.data() + k * 18;
    mm<6, 6, 3>(P, B, PB);     // P B
    mm<3, 6, 3>(Bt, PB, Quu);  // B'PB
    mm<6, 6, 6>(P, A, PA);     // P A
    mm<3, 6, 6>(Bt, PA, Qux);  // B'PA
    Eigen::Map<Eigen::Matrix3d> QuuM(Quu), QiM(Qi);
    QuuM = (0.5 * (QuuM + QuuM.transpose())).eval();
    if (has_r) QuuM += prob_.R;
    for (int i = 0; i < 3; ++i) QuuM(i, i) += id_(static_cast<Index>(k) * 3 + i);
    if (!ipm::ldl_inverse3_shifted(QuuM, QiM, 1e-14, 1e-6, 0.0)) return false;
    mm<3, 3, 6>(Qi, Qux, K);  // K = -Qi Qux
    for (int j = 0; j < 18; ++j) K[j] = -K[j];
    if (term) terminal_stage<6, 3>(At, Bt, Qi, K, L, Z, Ln, iKnu_.data() + k * 18);
    if (k == 0) break;
    // P_k = A'PA + Qux'K (+ Q), symmetrized
    double Quxt[18];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 6; ++j) Quxt[j + 6 * i] = Qux[i + 3 * j];
    mm<6, 6, 6>(At, PA, APA);
    mm<6, 3, 6>(Quxt, K, QK);
    for (int j = 0; j < 36; ++j) APA[j] += QK[j];
    if (has_q)
      for (int j = 0; j < 36; ++j) APA[j] += prob_.Q.data()[j];
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i) P[i + 6 * j] = 0.5 * (APA[i + 6 * j] + APA[j + 6 * i]);
  }
  for (int j = 0; j < 36; ++j)
    if (!std::isfinite(P[j])) return false;
  if (term) iS_ = iZ_;
  return true;
}

// In-plane / out-of-plane split of the (6, 3) case: the state indices {0, 1, 3, 4} with controls
// {0, 1}, and {2, 5} with control 2. Taken when every coupling entry of A, B, Qf, Q and R is exactly
// zero (the Clohessy-Wiltshire maps are, and the diagonal equilibration keeps them so); then P_k, Quu_k
// and K_k stay block-diagonal, and ipm_riccati_factor_cw does the products on the blocks only
// (kCwIn, kCwOut).
void AdmmWorkspace::ipm_setup_cw() noexcept {
  ipm_cw_ = false;
  if (!(nx_ == 6 && nu_ == 3)) return;
  const LtvDynamics& d = prob_.dynamics;
  if (d.A.size() != 1 || d.B.size() != 1) return;
  const MatrixXd &A = d.A[0], &B = d.B[0];
  const auto in_plane = [](int i) { return i != 2 && i != 5; };
  const auto split_ok = [&](const MatrixXd& M) {  // no entry couples the two parts (M is 6 x 6)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i)
        if (in_plane(i) != in_plane(j) && M(i, j) != 0.0) return false;
    return true;
  };
  if (!split_ok(A) || !split_ok(prob_.Qf) || (prob_.Q.size() != 0 && !split_ok(prob_.Q))) return;
  for (int i = 0; i < 6; ++i)
    for (int c = 0; c < 3; ++c)
      if (in_plane(i) != (c != 2) && B(i, c) != 0.0) return;
  if (prob_.R.size() != 0)
    for (int c = 0; c < 2; ++c)
      if (prob_.R(c, 2) != 0.0 || prob_.R(2, c) != 0.0) return;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      cwA4_[i + 4 * j] = A(kCwIn[i], kCwIn[j]);
      cwA4t_[j + 4 * i] = A(kCwIn[i], kCwIn[j]);
    }
    for (int c = 0; c < 2; ++c) {
      cwB4_[j + 4 * c] = B(kCwIn[j], c);
      cwB4t_[c + 2 * j] = B(kCwIn[j], c);
    }
  }
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      cwA2_[i + 2 * j] = A(kCwOut[i], kCwOut[j]);
      cwA2t_[j + 2 * i] = A(kCwOut[i], kCwOut[j]);
    }
    cwB2_[j] = B(kCwOut[j], 2);
    cwB2t_[j] = B(kCwOut[j], 2);
  }
  ipm_cw_ = true;
}

// ipm_riccati_factor_63 on the blocks: every sum over the skipped indices adds exact zeros there, so
// Quu, its inverse, K, Qux and P are the same numbers (the same ascending order of the nonzero terms;
// ipm_setup zeroed the off-block entries of the stored K, Qux, Knu, which are never written).
bool AdmmWorkspace::ipm_riccati_factor_cw() noexcept {
  const bool term = prob_.terminal_equality;
  const bool has_r = prob_.R.size() != 0, has_q = prob_.Q.size() != 0;
  double P4[16], P2[4];
  // hard terminal state: L_k = (A + B K)' L_{k+1} from L_N = I and W from 0, block-diagonal as well
  double L4[16] = {1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0};
  double L2[4] = {1.0, 0.0, 0.0, 1.0}, Z4[16] = {}, Z2[4] = {};
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) P4[i + 4 * j] = prob_.Qf(kCwIn[i], kCwIn[j]);
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) P2[i + 2 * j] = prob_.Qf(kCwOut[i], kCwOut[j]);
  // A' for ipm_riccati_sweep_63 (LTI: read from iAcl_ there)
  const double* A = prob_.dynamics.A[0].data();
  double* At = iAcl_.data();
  for (int i = 0; i < 6; ++i)
    for (int l = 0; l < 6; ++l) At[i + 6 * l] = A[l + 6 * i];
  for (int k = N_ - 1; k >= 0; --k) {
    double PB4[8], Quu4[4], PA4[16], Qux4[8], PB2[2], Quu2[1], PA2[4], Qux2[2];
    mm<4, 4, 2>(P4, cwB4_, PB4);
    mm<2, 4, 2>(cwB4t_, PB4, Quu4);
    mm<4, 4, 4>(P4, cwA4_, PA4);
    mm<2, 4, 4>(cwB4t_, PA4, Qux4);
    mm<2, 2, 1>(P2, cwB2_, PB2);
    mm<1, 2, 1>(cwB2t_, PB2, Quu2);
    mm<2, 2, 2>(P2, cwA2_, PA2);
    mm<1, 2, 2>(cwB2t_, PA2, Qux2);
    double Quu[9] = {Quu4[0], Quu4[1], 0.0, Quu4[2], Quu4[3], 0.0, 0.0, 0.0, Quu2[0]};
    double* Qi = iQi_.data() + k * 9;
    double* Qux = iQux_.data() + k * 18;
    double* K = iK_.data() + k * 18;
    Eigen::Map<Eigen::Matrix3d> QuuM(Quu), QiM(Qi);
    QuuM = (0.5 * (QuuM + QuuM.transpose())).eval();  // fixed-size: no allocation
    if (has_r) QuuM += prob_.R;
    for (int i = 0; i < 3; ++i) QuuM(i, i) += id_(static_cast<Index>(k) * 3 + i);
    if (!ipm::ldl_inverse3_shifted(QuuM, QiM, 1e-14, 1e-6, 0.0)) return false;
    // K = -Qi Qux on the blocks; Qux and K scattered into the stage's 3 x 6 arrays
    const double Qi4[4] = {Qi[0], Qi[1], Qi[3], Qi[4]}, Qi2 = Qi[8];
    double K4[8], K2[2];
    mm<2, 2, 4>(Qi4, Qux4, K4);
    for (int j = 0; j < 8; ++j) K4[j] = -K4[j];
    for (int j = 0; j < 2; ++j) K2[j] = -(Qi2 * Qux2[j]);
    for (int j = 0; j < 4; ++j)
      for (int c = 0; c < 2; ++c) {
        Qux[c + 3 * kCwIn[j]] = Qux4[c + 2 * j];
        K[c + 3 * kCwIn[j]] = K4[c + 2 * j];
      }
    for (int j = 0; j < 2; ++j) {
      Qux[2 + 3 * kCwOut[j]] = Qux2[j];
      K[2 + 3 * kCwOut[j]] = K2[j];
    }
    if (term) {  // terminal_stage on each block
      double Knu4[8], Knu2[2], Ln4[16], Ln2[4];
      terminal_stage<4, 2>(cwA4t_, cwB4t_, Qi4, K4, L4, Z4, Ln4, Knu4);
      terminal_stage<2, 1>(cwA2t_, cwB2t_, &Qi2, K2, L2, Z2, Ln2, Knu2);
      double* Knu = iKnu_.data() + k * 18;
      for (int j = 0; j < 4; ++j)
        for (int c = 0; c < 2; ++c) Knu[c + 3 * kCwIn[j]] = Knu4[c + 2 * j];
      for (int j = 0; j < 2; ++j) Knu[2 + 3 * kCwOut[j]] = Knu2[j];
    }
    if (k == 0) break;
    // P_k = A'PA + Qux'K (+ Q), symmetrized, per block
    double APA4[16], QK4[16], Qux4t[8], APA2[4], QK2[4];
    for (int c = 0; c < 2; ++c)
      for (int j = 0; j < 4; ++j) Qux4t[j + 4 * c] = Qux4[c + 2 * j];
    mm<4, 4, 4>(cwA4t_, PA4, APA4);
    mm<4, 2, 4>(Qux4t, K4, QK4);
    for (int j = 0; j < 16; ++j) APA4[j] += QK4[j];
    mm<2, 2, 2>(cwA2t_, PA2, APA2);
    mm<2, 1, 2>(Qux2, K2, QK2);  // Qux2' (2 x 1) K2 (1 x 2): Qux2 read as a column
    for (int j = 0; j < 4; ++j) APA2[j] += QK2[j];
    if (has_q) {
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) APA4[i + 4 * j] += prob_.Q(kCwIn[i], kCwIn[j]);
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) APA2[i + 2 * j] += prob_.Q(kCwOut[i], kCwOut[j]);
    }
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) P4[i + 4 * j] = 0.5 * (APA4[i + 4 * j] + APA4[j + 4 * i]);
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) P2[i + 2 * j] = 0.5 * (APA2[i + 2 * j] + APA2[j + 2 * i]);
  }
  for (double v : P4)
    if (!std::isfinite(v)) return false;
  for (double v : P2)
    if (!std::isfinite(v)) return false;
  if (term) {  // S = dx_N / dnu = W_0 (ipm_riccati_factor_63), its off-block entries zero
    iS_.setZero();
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) iS_(kCwIn[i], kCwIn[j]) = Z4[i + 4 * j];
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) iS_(kCwOut[i], kCwOut[j]) = Z2[i + 2 * j];
  }
  return true;
}

// The (6, 3) CW case of ipm_riccati_sweep written out (the products as axpys over contiguous
// columns, A' from ipm_riccati_factor_63 when the dynamics are time-invariant).
void AdmmWorkspace::ipm_riccati_sweep_63() noexcept {
  const LtvDynamics& d = prob_.dynamics;
  const bool has_r = prob_.R.size() != 0, has_q = prob_.Q.size() != 0;
  const bool lti = d.A.size() == 1;
  const double* Qf = prob_.Qf.data();
  double p[6], pn[6], qu[3];
  for (int i = 0; i < 6; ++i) p[i] = 0.0;
  for (int l = 0; l < 6; ++l)
    for (int i = 0; i < 6; ++i) p[i] += Qf[i + 6 * l] * ie_(l);
  for (int k = N_ - 1; k >= 0; --k) {
    const double* A = d.A_at(k).data();
    const double* B = d.B_at(k).data();
    const double* Qi = iQi_.data() + k * 9;
    const double* Qux = iQux_.data() + k * 18;
    double* kff = ikff_.data() + k * 3;
    const double* lin = ilin_.data() + k * 3;
    for (int i = 0; i < 3; ++i) {
      double acc = lin[i];
      if (has_r) {
        double ru = 0.0;
        for (int l = 0; l < 3; ++l) ru += prob_.R(i, l) * iU_(l, k);
        acc += ru;
      }
      double bp = 0.0;
      for (int l = 0; l < 6; ++l) bp += B[l + 6 * i] * p[l];
      qu[i] = acc + bp;
    }
    for (int i = 0; i < 3; ++i) kff[i] = -(Qi[i] * qu[0] + Qi[i + 3] * qu[1] + Qi[i + 6] * qu[2]);
    if (k == 0) break;
    if (lti) {
      const double* At = iAcl_.data();  // A' (ipm_riccati_factor_63)
      for (int i = 0; i < 6; ++i) pn[i] = 0.0;
      for (int l = 0; l < 6; ++l)
        for (int i = 0; i < 6; ++i) pn[i] += At[i + 6 * l] * p[l];
    } else {
      for (int i = 0; i < 6; ++i) {
        double acc = 0.0;
        for (int l = 0; l < 6; ++l) acc += A[l + 6 * i] * p[l];
        pn[i] = acc;
      }
    }
    for (int i = 0; i < 6; ++i)
      pn[i] += Qux[3 * i] * kff[0] + Qux[1 + 3 * i] * kff[1] + Qux[2 + 3 * i] * kff[2];
    if (has_q) {
      for (int i = 0; i < 6; ++i) {
        double acc = 0.0;
        for (int l = 0; l < 6; ++l) acc += prob_.Q(i, l) * (iX_(l, k) - prob_.xf(l));
        pn[i] += acc;
      }
    }
    for (int i = 0; i < 6; ++i) p[i] = pn[i];
  }
  ipm_forward_63();
}

// The forward pass of ipm_riccati_sweep_63 (twice with the terminal constraint: the second with
// the terminal multiplier's feedback).
void AdmmWorkspace::ipm_forward_63() noexcept {
  const bool term = prob_.terminal_equality;
  const LtvDynamics& d = prob_.dynamics;
  for (int pass = 0; pass < (term ? 2 : 1); ++pass) {
    double* X = idX_.data();
    for (int i = 0; i < 6; ++i) X[i] = 0.0;
    for (int k = 0; k < N_; ++k) {
      const double* A = d.A_at(k).data();
      const double* B = d.B_at(k).data();
      const double* K = iK_.data() + k * 18;
      const double* kff = ikff_.data() + k * 3;
      double* du = idu_.data() + k * 3;
      const double* xk = X + 6 * k;
      double* xn = X + 6 * (k + 1);
      double u[3] = {kff[0], kff[1], kff[2]};
      for (int l = 0; l < 6; ++l)
        for (int i = 0; i < 3; ++i) u[i] += K[i + 3 * l] * xk[l];
      if (pass == 1) {
        const double* Knu = iKnu_.data() + k * 18;
        for (int l = 0; l < 6; ++l)
          for (int i = 0; i < 3; ++i) u[i] += Knu[i + 3 * l] * inun_(l);
      }
      for (int i = 0; i < 3; ++i) du[i] = u[i];
      double x[6] = {};
      for (int l = 0; l < 6; ++l)
        for (int i = 0; i < 6; ++i) x[i] += A[i + 6 * l] * xk[l];
      for (int l = 0; l < 3; ++l)
        for (int i = 0; i < 6; ++i) x[i] += B[i + 6 * l] * u[l];
      for (int i = 0; i < 6; ++i) xn[i] = x[i];
    }
    if (term && pass == 0) {
      idx_ = -ie_ - idX_.col(N_);
      inun_ = ilu_.solve(idx_);
    }
  }
  iep_ = ie_ + idX_.col(N_);
}

// ipm_riccati_sweep_63 and ipm_forward_63 on the decoupled CW blocks (ipm_cw_): every skipped term
// is an exact zero of the off-block entries (of A, B, Qf, Q, R and of the stored Quu^-1, Qux, K, Knu),
// and the kept terms are summed in the same ascending order, so the numbers are the same.
void AdmmWorkspace::ipm_riccati_sweep_cw() noexcept {
  const bool has_r = prob_.R.size() != 0, has_q = prob_.Q.size() != 0;
  const double* Qf = prob_.Qf.data();
  const double* e = ie_.data();
  double p4[4], p2[2];
  for (int a = 0; a < 4; ++a) {
    double acc = 0.0;
    for (int b = 0; b < 4; ++b) acc += Qf[kCwIn[a] + 6 * kCwIn[b]] * e[kCwIn[b]];
    p4[a] = acc;
  }
  for (int a = 0; a < 2; ++a) {
    double acc = 0.0;
    for (int b = 0; b < 2; ++b) acc += Qf[kCwOut[a] + 6 * kCwOut[b]] * e[kCwOut[b]];
    p2[a] = acc;
  }
  const double* R = has_r ? prob_.R.data() : nullptr;
  const double* Q = has_q ? prob_.Q.data() : nullptr;
  for (int k = N_ - 1; k >= 0; --k) {
    const double* Qi = iQi_.data() + k * 9;
    const double* Qux = iQux_.data() + k * 18;
    double* kff = ikff_.data() + k * 3;
    const double* lin = ilin_.data() + k * 3;
    const double* u = iU_.data() + k * 3;
    double qu[3];
    for (int i = 0; i < 2; ++i) {
      double acc = lin[i];
      if (has_r) acc += R[i] * u[0] + R[i + 3] * u[1];
      double bp = 0.0;
      for (int b = 0; b < 4; ++b) bp += cwB4_[b + 4 * i] * p4[b];
      qu[i] = acc + bp;
    }
    {
      double acc = lin[2];
      if (has_r) acc += R[8] * u[2];
      qu[2] = acc + (cwB2_[0] * p2[0] + cwB2_[1] * p2[1]);
    }
    kff[0] = -(Qi[0] * qu[0] + Qi[3] * qu[1]);
    kff[1] = -(Qi[1] * qu[0] + Qi[4] * qu[1]);
    kff[2] = -(Qi[8] * qu[2]);
    if (k == 0) break;
    double pn4[4], pn2[2];
    for (int a = 0; a < 4; ++a) {
      double acc = 0.0;
      for (int b = 0; b < 4; ++b) acc += cwA4_[b + 4 * a] * p4[b];
      const int i = kCwIn[a];
      acc += Qux[3 * i] * kff[0] + Qux[1 + 3 * i] * kff[1];
      if (has_q) {
        double qa = 0.0;
        for (int b = 0; b < 4; ++b) qa += Q[i + 6 * kCwIn[b]] * (iX_(kCwIn[b], k) - prob_.xf(kCwIn[b]));
        acc += qa;
      }
      pn4[a] = acc;
    }
    for (int a = 0; a < 2; ++a) {
      const int i = kCwOut[a];
      double acc = cwA2_[2 * a] * p2[0] + cwA2_[1 + 2 * a] * p2[1];
      acc += Qux[2 + 3 * i] * kff[2];
      if (has_q) {
        double qa = 0.0;
        for (int b = 0; b < 2; ++b) qa += Q[i + 6 * kCwOut[b]] * (iX_(kCwOut[b], k) - prob_.xf(kCwOut[b]));
        acc += qa;
      }
      pn2[a] = acc;
    }
    for (int a = 0; a < 4; ++a) p4[a] = pn4[a];
    for (int a = 0; a < 2; ++a) p2[a] = pn2[a];
  }
  ipm_forward_cw();
}

void AdmmWorkspace::ipm_forward_cw() noexcept {
  const bool term = prob_.terminal_equality;
  for (int pass = 0; pass < (term ? 2 : 1); ++pass) {
    double x4[4] = {}, x2[2] = {};
    double* X = idX_.data();
    for (int i = 0; i < 6; ++i) X[i] = 0.0;
    const double* nun = inun_.data();
    for (int k = 0; k < N_; ++k) {
      const double* K = iK_.data() + k * 18;
      const double* kff = ikff_.data() + k * 3;
      double* du = idu_.data() + k * 3;
      double u0 = kff[0], u1 = kff[1], u2 = kff[2];
      for (int b = 0; b < 4; ++b) {
        u0 += K[3 * kCwIn[b]] * x4[b];
        u1 += K[1 + 3 * kCwIn[b]] * x4[b];
      }
      u2 += K[2 + 3 * kCwOut[0]] * x2[0];
      u2 += K[2 + 3 * kCwOut[1]] * x2[1];
      if (pass == 1) {
        const double* Knu = iKnu_.data() + k * 18;
        for (int b = 0; b < 4; ++b) {
          u0 += Knu[3 * kCwIn[b]] * nun[kCwIn[b]];
          u1 += Knu[1 + 3 * kCwIn[b]] * nun[kCwIn[b]];
        }
        u2 += Knu[2 + 3 * kCwOut[0]] * nun[kCwOut[0]];
        u2 += Knu[2 + 3 * kCwOut[1]] * nun[kCwOut[1]];
      }
      du[0] = u0;
      du[1] = u1;
      du[2] = u2;
      double y4[4] = {}, y2[2] = {};
      for (int b = 0; b < 4; ++b)
        for (int a = 0; a < 4; ++a) y4[a] += cwA4_[a + 4 * b] * x4[b];
      for (int a = 0; a < 4; ++a) {
        y4[a] += cwB4_[a] * u0;
        y4[a] += cwB4_[a + 4] * u1;
      }
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) y2[a] += cwA2_[a + 2 * b] * x2[b];
      for (int a = 0; a < 2; ++a) y2[a] += cwB2_[a] * u2;
      double* xn = X + 6 * (k + 1);
      for (int a = 0; a < 4; ++a) xn[kCwIn[a]] = x4[a] = y4[a];
      for (int a = 0; a < 2; ++a) xn[kCwOut[a]] = x2[a] = y2[a];
    }
    if (term && pass == 0) {
      idx_ = -ie_ - idX_.col(N_);
      inun_ = ilu_.solve(idx_);
    }
  }
  iep_ = ie_ + idX_.col(N_);
}

template <int NU>
auto AdmmWorkspace::llt_ref() noexcept -> std::conditional_t<NU == Eigen::Dynamic, Eigen::LLT<MatrixXd>&,
                                                             Eigen::LLT<Eigen::Matrix<double, NU, NU>>> {
  if constexpr (NU == Eigen::Dynamic) {
    return illt_;
  } else {
    return Eigen::LLT<Eigen::Matrix<double, NU, NU>>();
  }
}

// Affine backward sweep (linear terms: R u + lin on u, Q (x_k - x_f) on stage states, Qf e at N) and
// forward rollout of the step; with a hard terminal state, the multiplier from the sensitivity and a
// second forward pass.
template <int NX, int NU>
void AdmmWorkspace::ipm_riccati_sweep() noexcept {
  using MXX = Eigen::Matrix<double, NX, NX>;
  using MUX = Eigen::Matrix<double, NU, NX>;
  using MXU = Eigen::Matrix<double, NX, NU>;
  using MUU = Eigen::Matrix<double, NU, NU>;
  using VX = Eigen::Matrix<double, NX, 1>;
  using VU = Eigen::Matrix<double, NU, 1>;
  const bool term = prob_.terminal_equality;
  const LtvDynamics& d = prob_.dynamics;
  const bool has_r = prob_.R.size() != 0, has_q = prob_.Q.size() != 0;
  const Index nx = nx_, nu = nu_;
  Eigen::Map<VX> p(ip_.data(), nx), pn(ipn_.data(), nx), dx(idx_.data(), nx);
  Eigen::Map<VU> qu(iqu_.data(), nu);
  p.noalias() = prob_.Qf * ie_;
  for (int k = N_ - 1; k >= 0; --k) {
    const Eigen::Map<const MXX> A(d.A_at(k).data(), nx, nx);
    const Eigen::Map<const MXU> B(d.B_at(k).data(), nx, nu);
    const Eigen::Map<const MUU> Qi(iQi_.data() + k * nu * nu, nu, nu);
    const Eigen::Map<const MUX> Qux(iQux_.data() + k * nu * nx, nu, nx);
    Eigen::Map<VU> kff(ikff_.data() + k * nu, nu);
    qu = Eigen::Map<const VU>(ilin_.data() + k * nu, nu);
    if (has_r) qu.noalias() += prob_.R * iU_.col(k);
    qu.noalias() += B.transpose() * p;
    kff.noalias() = -Qi * qu;
    if (k == 0) break;
    pn.noalias() = A.transpose() * p;
    pn.noalias() += Qux.transpose() * kff;
    if (has_q) {
      dx = iX_.col(k) - prob_.xf;
      pn.noalias() += prob_.Q * dx;
    }
    p = pn;
  }
  for (int pass = 0; pass < (term ? 2 : 1); ++pass) {
    idX_.col(0).setZero();
    for (int k = 0; k < N_; ++k) {
      const Eigen::Map<const MXX> A(d.A_at(k).data(), nx, nx);
      const Eigen::Map<const MXU> B(d.B_at(k).data(), nx, nu);
      const Eigen::Map<const MUX> K(iK_.data() + k * nu * nx, nu, nx);
      Eigen::Map<VU> du(idu_.data() + k * nu, nu);
      const Eigen::Map<const VX> xk(idX_.data() + k * nx, nx);
      Eigen::Map<VX> xn(idX_.data() + (k + 1) * nx, nx);
      du = Eigen::Map<const VU>(ikff_.data() + k * nu, nu);
      du.noalias() += K * xk;
      if (pass == 1) du.noalias() += Eigen::Map<const MUX>(iKnu_.data() + k * nu * nx, nu, nx) * inun_;
      xn.noalias() = A * xk;
      xn.noalias() += B * du;
    }
    if (term && pass == 0) {
      idx_ = -ie_ - idX_.col(N_);
      inun_ = ilu_.solve(idx_);
    }
  }
  iep_ = ie_ + idX_.col(N_);
}

template bool AdmmWorkspace::ipm_riccati_factor<Eigen::Dynamic, Eigen::Dynamic>() noexcept;
template void AdmmWorkspace::ipm_riccati_sweep<6, 3>() noexcept;
template void AdmmWorkspace::ipm_riccati_sweep<Eigen::Dynamic, Eigen::Dynamic>() noexcept;

// D_j (the eliminated epigraph / box block) from the current slacks and multipliers, then the
// factorization of the structured LQR step with R + diag(D).
bool AdmmWorkspace::ipm_factor() noexcept {
  const bool term = prob_.terminal_equality;
  // The per-entry ratios, D = 4 / (r1 + r2) of the pair (r_m = s_m / z_m, bounded where z_m / s_m
  // overflows), H_ut and H_tt are formed by step_l1 (ipm_step_and_pieces). Without a box its arrays
  // stay exactly zero (s3 = s4 = 1, z3 = z4 = 0, masks 0), so they are not formed.
  if (!(ipm_cw_                ? ipm_riccati_factor_cw()
        : nx_ == 6 && nu_ == 3 ? ipm_riccati_factor_63()
                               : ipm_riccati_factor<Eigen::Dynamic, Eigen::Dynamic>()))
    return false;
  if (!term) return true;
  ilu_.compute(iS_);
  const auto piv = ilu_.matrixLU().diagonal().cwiseAbs();
  return std::isfinite(piv.maxCoeff()) && piv.minCoeff() > 1e-13 * piv.maxCoeff();
}

namespace {
// The L1 pair's elementwise passes of ipm_newton fused into one loop each (nine array passes were
// ~9 % of the solve's samples): per entry the operations of the array expressions they replace, in
// the same order, so the numbers are the same; __restrict lets the loops vectorize without alias
// checks (every output array is distinct from every input).
struct L1Pre {
  const double *m1, *w, *z1, *z2, *zs1, *zs2, *rp1, *rp2, *a1, *b1, *a2, *b2, *si1, *si2, *hut;
};
// the corrector's targets dz (z + (z / s) rp and the Mehrotra term; the predictor's are formed by
// step_l1), r_t, g_t and, without a box, the sweep's linear term
template <bool Lin>
void newton_l1_pre(Index n, double smu, const L1Pre& a, double* __restrict dz1, double* __restrict dz2,
                   double* __restrict rt, double* __restrict dt, double* __restrict lin) noexcept {
  const double* __restrict m1 = a.m1, * __restrict w = a.w, * __restrict z1 = a.z1, * __restrict z2 = a.z2, * __restrict zs1 = a.zs1, * __restrict zs2 = a.zs2, * __restrict rp1 = a.rp1, * __restrict rp2 = a.rp2, * __restrict a1 = a.a1, * __restrict b1 = a.b1, * __restrict a2 = a.a2, * __restrict b2 = a.b2, * __restrict si1 = a.si1, * __restrict si2 = a.si2, * __restrict hut = a.hut;
  for (Index j = 0; j < n; ++j) {
    const double d1 = m1[j] * ((z1[j] + (a1[j] * b1[j] - smu) * si1[j]) + zs1[j] * rp1[j]);
    const double d2 = m1[j] * ((z2[j] + (a2[j] * b2[j] - smu) * si2[j]) + zs2[j] * rp2[j]);
    const double r = m1[j] * ((w[j] - z1[j]) - z2[j]), g = d1 + d2;
    dz1[j] = d1;
    dz2[j] = d2;
    rt[j] = r;
    dt[j] = g;
    if constexpr (Lin) lin[j] = (((z1[j] - z2[j]) - d1) + d2) - hut[j] * (r + g);
  }
}
// Two entries per vector (GCC extension, as propagation/detail/dop853_lanes.inc) where a loop carries a
// floating-point maximum, which GCC does not vectorize; the same code on double for an odd last entry.
using V2 = double __attribute__((vector_size(16)));
template <class T>
T ld(const double* p) noexcept {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <class T>
void st(double* p, const T& v) noexcept {
  std::memcpy(p, &v, sizeof v);
}
// std::max(acc, v) per lane (a NaN v is skipped, as std::max skips it); a maximum is the same value in
// any order of the entries
template <class T>
T vmax(const T& acc, const T& v) noexcept {
  return v > acc ? v : acc;
}
// one constraint pair's arrays in the back-substitution (the L1 pair's, or the box's lower / upper)
struct PostPair {
  const double *zs1, *zs2, *rp1, *rp2, *si1, *si2, *zi1, *zi2;
  double *ds1, *ds2, *dz1, *dz2;
};
struct L1Post {
  const double *m1, *rt, *htt, *hut, *du, *m3, *m4;
  double* dt;
  PostPair l1, box;  // box: with Box only
};
// dz = -q - (z / s) ds, ds += rp from the pair's ds before rp (c1, c2), and the step-length maxima
// max(-ds / s) (ms), max(-dz / z) (mz) by the reciprocals
template <class T>
[[gnu::always_inline]] inline void newton_post_pair(const PostPair& p, Index j, const T& c1, const T& c2,
                                                    T& ms, T& mz) noexcept {
  const T z1 = -ld<T>(p.dz1 + j) - ld<T>(p.zs1 + j) * c1, z2 = -ld<T>(p.dz2 + j) - ld<T>(p.zs2 + j) * c2;
  const T v1 = c1 + ld<T>(p.rp1 + j), v2 = c2 + ld<T>(p.rp2 + j);
  ms = vmax(vmax(ms, -v1 * ld<T>(p.si1 + j)), -v2 * ld<T>(p.si2 + j));
  mz = vmax(vmax(mz, -z1 * ld<T>(p.zi1 + j)), -z2 * ld<T>(p.zi2 + j));
  st(p.dz1 + j, z1);
  st(p.dz2 + j, z2);
  st(p.ds1 + j, v1);
  st(p.ds2 + j, v2);
}
// back-substitution: dt = -(r_t + g_t) / H_tt - (H_ut / H_tt) du, ds = +-(dt -+ du) + rp, dz = -q - (z / s)
// ds; with a box ds3 = du + rp3, ds4 = -du + rp4 where present (the order of the box's array
// expressions), dz likewise; and ipm_max_step's maximum over the constraints (ms, mz)
template <bool Box, class T>
[[gnu::always_inline]] inline void newton_l1_post_at(const L1Post& a, Index j, T& ms, T& mz) noexcept {
  const T m = ld<T>(a.m1 + j), du = ld<T>(a.du + j);
  const T t = -(ld<T>(a.rt + j) + ld<T>(a.dt + j)) * ld<T>(a.htt + j) - ld<T>(a.hut + j) * du;
  st(a.dt + j, t);
  newton_post_pair(a.l1, j, m * (t - du), m * (t + du), ms, mz);
  if constexpr (Box) newton_post_pair(a.box, j, ld<T>(a.m3 + j) * du, -ld<T>(a.m4 + j) * du, ms, mz);
}
template <bool Box>
void newton_l1_post(Index n, const L1Post& a, double& ms_out, double& mz_out) noexcept {
  V2 ms = {0.0, 0.0}, mz = {0.0, 0.0};
  Index j = 0;
  for (; j + 2 <= n; j += 2) newton_l1_post_at<Box>(a, j, ms, mz);
  double m1 = std::max(ms[0], ms[1]), m2 = std::max(mz[0], mz[1]);
  for (; j < n; ++j) newton_l1_post_at<Box>(a, j, m1, m2);
  ms_out = m1;
  mz_out = m2;
}
// the step's direction and the iterate it updates; dt, dz1, dz2 are overwritten with the next
// predictor's targets
struct L1Step {
  const double* __restrict m1, * __restrict w, * __restrict du, * __restrict ds1, * __restrict ds2;
  double* __restrict dt, * __restrict dz1, * __restrict dz2;
  double* __restrict u, * __restrict t, * __restrict s1, * __restrict s2, * __restrict z1, * __restrict z2;
  // the box (Box): masks, finite bounds, steps (dz3, dz4 overwritten as dz1, dz2), slacks, multipliers
  const double* __restrict m3, * __restrict m4, * __restrict lo, * __restrict hi, * __restrict ds3, * __restrict ds4;
  double* __restrict dz3, * __restrict dz4, * __restrict s3, * __restrict s4, * __restrict z3, * __restrict z4;
};
// what the step's pass forms for the next iteration (and ipm_step_and_pieces<false> for the start)
struct L1Next {
  double* __restrict rp1, * __restrict rp2, * __restrict rt, * __restrict szv, * __restrict pwv;
  double* __restrict si1, * __restrict si2, * __restrict zs1, * __restrict zs2, * __restrict zi1, * __restrict zi2;
  double* __restrict d, * __restrict hut, * __restrict htt, * __restrict lin;
  double* __restrict rp3, * __restrict rp4, * __restrict si3, * __restrict si4, * __restrict zs3, * __restrict zs4;
  double* __restrict zi3, * __restrict zi4;  // the box (Box)
};
// u, t and the slacks stepped by a, the multipliers by ad, in one pass (take_step and the masks of
// absent pairs, s = 1), and from the new point the per-entry pieces of the next iteration: ipm_residuals'
// r_p, r_t and the terms of its sums (summed by Eigen in the order of the expressions they replace),
// ipm_factor's ratios and the predictor's newton_l1_pre; each the same operations in the same order as
// the code it replaces. No reductions here: GCC does not vectorize a floating-point maximum; the
// restrict-qualified members of the structs passed by value let it vectorize without alias checks.
// Step = false: no step, only the pieces of the current point (the IPM's start).
template <bool Box, bool Step = true>
void step_l1(Index n, double a, double ad, const L1Step p, const L1Next o) noexcept {
  for (Index j = 0; j < n; ++j) {
    const double m = p.m1[j];
    double uj = p.u[j], tj = p.t[j], sa = p.s1[j], sb = p.s2[j], za = p.z1[j], zb = p.z2[j];
    if constexpr (Step) {
      uj = p.u[j] + a * p.du[j];
      tj = p.t[j] + a * p.dt[j];
      const double v1 = p.s1[j] + a * p.ds1[j], v2 = p.s2[j] + a * p.ds2[j];
      sa = m * v1 + (1.0 - m);
      sb = m * v2 + (1.0 - m);
      za = p.z1[j] + ad * p.dz1[j];
      zb = p.z2[j] + ad * p.dz2[j];
      p.u[j] = uj;
      p.t[j] = tj;
      p.s1[j] = sa;
      p.s2[j] = sb;
      p.z1[j] = za;
      p.z2[j] = zb;
    }
    // ipm_residuals
    const double ra = m * ((tj - uj) - sa), rb = m * ((tj + uj) - sb), r = m * ((p.w[j] - za) - zb);
    o.rp1[j] = ra;
    o.rp2[j] = rb;
    o.rt[j] = r;
    o.pwv[j] = p.w[j] * std::abs(uj);
    double szj = m * (sa * za + sb * zb);
    // the box's step, residuals and ratios (the same order of operations as the box's array expressions)
    double m3 = 0.0, m4 = 0.0, sc = 0.0, sd = 0.0, zc = 0.0, zd = 0.0, rc = 0.0, rd = 0.0, cc = 0.0, cd = 0.0;
    if constexpr (Box) {
      m3 = p.m3[j];
      m4 = p.m4[j];
      sc = p.s3[j];
      sd = p.s4[j];
      zc = p.z3[j];
      zd = p.z4[j];
      if constexpr (Step) {
        const double v3 = p.s3[j] + a * p.ds3[j], v4 = p.s4[j] + a * p.ds4[j];
        sc = m3 * v3 + (1.0 - m3);
        sd = m4 * v4 + (1.0 - m4);
        zc = p.z3[j] + ad * p.dz3[j];
        zd = p.z4[j] + ad * p.dz4[j];
        p.s3[j] = sc;
        p.s4[j] = sd;
        p.z3[j] = zc;
        p.z4[j] = zd;
      }
      rc = m3 * ((uj - p.lo[j]) - sc);
      rd = m4 * ((p.hi[j] - uj) - sd);
      o.rp3[j] = rc;
      o.rp4[j] = rd;
      szj = (szj + m3 * sc * zc) + m4 * sd * zd;
      const double ic = 1.0 / sc, id = 1.0 / sd;
      cc = zc * ic;
      cd = zd * id;
      o.si3[j] = ic;
      o.si4[j] = id;
      o.zs3[j] = cc;
      o.zs4[j] = cd;
      o.zi3[j] = m3 / (zc + (1.0 - m3));
      o.zi4[j] = m4 / (zd + (1.0 - m4));
    }
    o.szv[j] = szj;
    // ipm_factor. Absent pairs (m = 0: s = 1, z = 0, where s / z is inf and ipm_factor selects 0) divide
    // by z + 1 and are multiplied by m = 0, giving its +0; present ones by z + 0 = z (z > 0) and by m = 1:
    // the same numbers without a select (GCC does not if-convert the selected products, which might trap)
    const double ia = 1.0 / sa, ib = 1.0 / sb, ca = za * ia, cb = zb * ib;
    const double ga = za + (1.0 - m), gb = zb + (1.0 - m);
    o.si1[j] = ia;
    o.si2[j] = ib;
    o.zs1[j] = ca;
    o.zs2[j] = cb;
    o.zi1[j] = m / ga;
    o.zi2[j] = m / gb;
    const double qa = sa / ga, qb = sb / gb, q = 1.0 / (qa + qb);
    const double h = m * ((qa - qb) * q);
    if constexpr (Box) {
      o.d[j] = m * (4.0 * q) + (m3 * cc + m4 * cd);
    } else {
      o.d[j] = m * (4.0 * q);
    }
    o.hut[j] = h;
    o.htt[j] = m * (qa * qb * q);
    // the predictor's newton_l1_pre and, with a box, ipm_newton's box targets and linear term
    const double ea = za + ca * ra, eb = zb + cb * rb, g = ea + eb;
    p.dz1[j] = ea;
    p.dz2[j] = eb;
    p.dt[j] = g;
    if constexpr (Box) {
      const double ec = zc + cc * rc, ed = zd + cd * rd;
      p.dz3[j] = ec;
      p.dz4[j] = ed;
      o.lin[j] = (((((((za - zb) - zc) + zd) - ea) + eb) + ec) - ed) - h * (r + g);
    } else {
      o.lin[j] = (((za - zb) - ea) + eb) - h * (r + g);
    }
  }
}
}  // namespace

// One Newton direction with complementarity targets rc = s z (predictor) or s z + ds_a dz_a - sigma
// mu (corrector, smu = sigma mu): idu_, idt_, ids*, idz* and the terminal quantities iep_, inun_.
bool AdmmWorkspace::ipm_newton(bool corrector, double smu) noexcept {
  // q_m = (rc_m + z_m rp_m) / s_m (zero for absent constraints: s = 1, z = 0 there); infeasible
  // start: rp = c(u, t) - s is driven to zero by the steps
  // the L1 pair's part in one pass (newton_l1_pre: the same operations as the array expressions)
  const Index n = static_cast<Index>(N_) * nu_;
  const bool lin = !has_box_;
  const L1Pre a{im1_.data(),  wrep_.data(), iz1_.data(),  iz2_.data(),  izs1_.data(),
                izs2_.data(), irp1_.data(), irp2_.data(), ia1_.data(),  ib1_.data(),
                ia2_.data(),  ib2_.data(),  isi1_.data(), isi2_.data(), ihut_.data()};
  if (corrector) {  // the predictor's targets and linear term are formed by step_l1
    lin ? newton_l1_pre<true>(n, smu, a, idz1_.data(), idz2_.data(), irt_.data(), idt_.data(), ilin_.data())
        : newton_l1_pre<false>(n, smu, a, idz1_.data(), idz2_.data(), irt_.data(), idt_.data(), ilin_.data());
  }
  if (has_box_ && corrector) {
    idz3_ = im3_ * (iz3_ + (ia3_ * ib3_ - smu) * isi3_ + izs3_ * irp3_);
    idz4_ = im4_ * (iz4_ + (ia4_ * ib4_ - smu) * isi4_ + izs4_ * irp4_);
    // linear term of the reduced step: -sum z a + g_u - H_ut (r_t + g_t) / H_tt (without a box
    // newton_l1_pre forms it: the box terms are exact zeros there)
    ilin_ = iz1_ - iz2_ - iz3_ + iz4_ - idz1_ + idz2_ + idz3_ - idz4_ - ihut_ * (irt_ + idt_);
  }
  if (ipm_cw_) {
    ipm_riccati_sweep_cw();
  } else if (nx_ == 6 && nu_ == 3) {
    ipm_riccati_sweep_63();
  } else {
    ipm_riccati_sweep<Eigen::Dynamic, Eigen::Dynamic>();
  }
  if (!idu_.allFinite()) return false;
  // back-substitution: dt, ds, dz
  // dt = -(r_t + g_t) / H_tt - (H_ut / H_tt) du with 1 / H_tt = r1 r2 / (r1 + r2), H_ut / H_tt =
  // (r1 - r2) / (r1 + r2)
  const L1Post b{im1_.data(),
                 irt_.data(),
                 ihtt_.data(),
                 ihut_.data(),
                 idu_.data(),
                 im3_.data(),
                 im4_.data(),
                 idt_.data(),
                 {izs1_.data(), izs2_.data(), irp1_.data(), irp2_.data(), isi1_.data(), isi2_.data(),
                  izi1_.data(), izi2_.data(), ids1_.data(), ids2_.data(), idz1_.data(), idz2_.data()},
                 {izs3_.data(), izs4_.data(), irp3_.data(), irp4_.data(), isi3_.data(), isi4_.data(),
                  izi3_.data(), izi4_.data(), ids3_.data(), ids4_.data(), idz3_.data(), idz4_.data()}};
  // without a box ids3, ids4, idz3, idz4 stay zero (ipm_setup; their swaps exchange zeros)
  if (has_box_) {
    newton_l1_post<true>(n, b, imaxs_, imaxz_);
  } else {
    newton_l1_post<false>(n, b, imaxs_, imaxz_);
  }
  return true;
}

auto AdmmWorkspace::ipm_max_step() const noexcept -> IpmMaxStep {
  // the largest a with v + a dv >= 0: 1 / max(-dv / v) over all entries (the entries with dv >= 0
  // give <= 0), by the reciprocals of ipm_factor (1 / s, and 1 / z, 0 where the constraint is
  // absent) instead of a division per entry and call (8 of them per entry and step were 5-8 % of the
  // solve's samples); the slacks' and the multipliers' apart (ipm_predictor_corrector). The maxima
  // are formed by ipm_newton's back-substitution (newton_l1_post; without a box the box steps are 0).
  return {imaxs_ > 0.0 ? 1.0 / imaxs_ : kInf, imaxz_ > 0.0 ? 1.0 / imaxz_ : kInf};
}

// The independent acceptance test (the same as ADMM's): |relative duality gap| of the plan <= eps_gap
// and the terminal miss, on the rolled-out plan.
bool AdmmWorkspace::ipm_certify() noexcept {
  const bool term = prob_.terminal_equality;
  // the plan in the box (the slacks are carried apart from u: rounding may put u outside by an ulp)
  for (int k = 0; k < N_; ++k)
    for (int i = 0; i < nu_; ++i) iU_(i, k) = std::clamp(iU_(i, k), lo_(i), hi_(i));
  rollout(iU_, res_.X_flown);
  if (term) {
    // the multiplier estimate for the flown plan: the IPM's costate at x_N is nu + Qf e with its
    // carried e; with the rolled-out e the same costate needs nu + Qf (e_carried - e_rolled) (any
    // multiplier gives a valid dual bound; this one keeps the IPM's stationarity)
    xtmp_ = ie_ + prob_.xf - res_.X_flown.col(N_);
    ie2_.noalias() = prob_.Qf * xtmp_;
    ie2_ += inu_;
  } else {
    // the carried terminal error (updated by the linear steps, as the polish solves it) keeps its
    // digits when it is small against x_N(0); it must agree with the rollout to rounding
    xtmp_ = res_.X_flown.col(N_) - prob_.xf - ie_;
    if (!(xtmp_.norm() <= 1e-9 * (xN0all_.norm() + prob_.xf.norm() + ie_.norm()))) return false;
    res_.X_flown.col(N_) = prob_.xf + ie_;
  }
  dual_at_u_ = false;
  const double P = trajectory_objective(res_.X_flown, iU_);
  const VectorXd& pm = term ? ie2_ : pz_;
  return gap_within(evaluate_gap(res_.X_flown, iU_, pm, P), set_.eps_gap) && terminal_miss_ratio() <= 1.0;
}

bool AdmmWorkspace::ipm_solve(bool warm) noexcept {
  const bool term = prob_.terminal_equality;
  AdmmInfo& info = res_.info;
  if (warm)
    ipm_start_warm();
  else
    ipm_start_cold();
  ipm_center_and_balance(warm);
  xtmp2_ = xN0all_ - prob_.xf;
  const double e_ref = 1e-2 * set_.terminal_tolerance * xtmp2_.norm();
  const double m = std::max(ipm_m_, 1);
  const double wmax = w_.maxCoeff();
  ipm_step_and_pieces<false>(0.0, 0.0);  // the start's per-entry pieces
  int it = 0, cert_failures = 0;
  double fail_gap = kInf;  // the smallest |gap| of a failed certification
  double ru_prev = kInf;
  bool ok = false;
  // checkpoint: the iterate with the smallest stopping measure (each test's value over its threshold)
  double best_meas = kInf;
  int best_it = -1;
  bool best_tried = false;
  for (; it <= set_.ipm_max_iterations; ++it) {
    if (out_of_time()) break;
    const IpmResiduals r = ipm_residuals(wmax);
    if (!std::isfinite(r.P) || !std::isfinite(r.ru) || !std::isfinite(r.sz)) break;
    const double tol = set_.ipm_tolerance;
    // stationarity has a rounding floor when the gradient's terms cancel (stage Q far from x_f):
    // once it stops decreasing, the independent gap test decides
    const bool ru_ok =
        r.ru <= 1e3 * tol * r.gscale || (r.ru >= 0.5 * ru_prev && r.sz <= tol * tol * std::abs(r.P));
    ru_prev = r.ru;
    {
      const double meas = std::max(
          {r.sz / (tol * std::abs(r.P)), r.rp / (1e3 * tol * r.uscale), r.ru / (1e3 * tol * r.gscale),
           r.rt / (1e3 * tol * std::max(wmax, 1e-300)), term ? ie_.norm() / std::max(e_ref, 1e-300) : 0.0});
      if (meas < best_meas) {
        best_meas = meas;
        best_it = it;
        best_tried = false;
        icU_ = iU_;
        icnu_ = inu_;
        ice_ = ie_;
      }
    }
    if (r.sz <= tol * std::abs(r.P) && r.rp <= 1e3 * tol * r.uscale && ru_ok &&
        r.rt <= 1e3 * tol * std::max(wmax, 1e-300) && (!term || ie_.norm() <= e_ref)) {
      info.duality_gap = kInf;  // set by ipm_certify's gap evaluation (stays inf if it stops before)
      if (ipm_certify()) {
        ok = true;
        break;
      }
      if (best_it == it) best_tried = true;  // the checkpoint itself failed the test
      // a failed test counts unless its gap halved the best failed one: with a stage Q far from x_f
      // the gap's rounding floor lies near eps_gap and a run still closing it is not stopped
      // (suite #337 under a rounding-level change of ipm_factor: gaps 4.2e-5, 4.0e-5, 1.9e-5 at IPM
      // iterations 45 / 48 / 49 ended the run, eps_gap 1e-5; certified at 50 with this rule)
      const double g = std::abs(info.duality_gap);
      const bool closing = std::isfinite(fail_gap) && g < 0.5 * fail_gap;
      if (!closing && ++cert_failures >= 3) break;
      fail_gap = std::min(fail_gap, g);
    }
    if (it == set_.ipm_max_iterations) break;
    if (!ipm_predictor_corrector(r.sz, m)) break;
  }
  info.ipm_iterations += it;
  // Without a certificate (a failed factorization or step, the iteration limit): the checkpoint
  // through the same independent test. Degenerate LPs with a hard terminal state (an optimum with
  // fewer free entries than nx) drive mu to ~1e-13 while the terminal sensitivity loses rank, and
  // the last steps wreck the terminal error (measured: e 3e-6 -> 2-13 m, then the factorization
  // fails, 17-26 iterations in); the checkpoint of ~10^4 x tolerance or better is tried.
  if (!ok && !best_tried && best_meas <= 1e4) {
    // swapped (no allocation), and back if it fails: method = "ipm" returns its last plan then
    iU_.swap(icU_);
    inu_.swap(icnu_);
    ie_.swap(ice_);
    ok = ipm_certify();
    if (!ok) {
      iU_.swap(icU_);
      inu_.swap(icnu_);
      ie_.swap(ice_);
    }
  }
  if (!ok) return false;
  ipm_accept();
  return true;
}

// Warm start from ADMM's iterate.
void AdmmWorkspace::ipm_start_warm() noexcept {
  const Index n = static_cast<Index>(N_) * nu_;
  Eigen::Map<ArrayXd> u(iU_.data(), n);
  {
    // from ADMM's iterate: u = Y (in the box), multipliers from Lambda = -grad f at its fixed point
    // (-grad f = z1 - z2 - z3 + z4): the L1 pair takes clamp(Lambda, -w, w), the box the rest;
    // slacks floored at 1e-2 of the plan's scale, multipliers at kZFloor of the multipliers' scale.
    // Measured on the suite (best of 3, back-to-back): a multiplier floor of 1e-2 (was) / 1e-1 /
    // 0.3 / 1 -> median 12 / 11 / 11 / 12 IPM iterations, p95 29 / 20 / 18 / 18: ADMM's multipliers
    // of the entries it sets to 0 are far from centred, and a floor near the weight's scale keeps
    // the first steps long; 1e-3 took 15 (p95 41).
    constexpr double kZFloor = 0.3;
    Eigen::Map<const ArrayXd> y(res_.Y.data(), n), lam(res_.Lambda.data(), n);
    u = y.max(lorep_).min(hirep_);
    const double tau = 1e-2 * std::max(u.abs().maxCoeff(), 1e-300);
    const double zf = kZFloor * std::max({w_.maxCoeff(), lam.abs().maxCoeff(), 1e-300});
    itv_ = im1_ * (u.abs() + tau);
    is1_ = im1_ * (itv_ - u) + (1.0 - im1_);
    is2_ = im1_ * (itv_ + u) + (1.0 - im1_);
    is3_ = im3_ * (u - lofin_).max(tau) + (1.0 - im3_);
    is4_ = im4_ * (hifin_ - u).max(tau) + (1.0 - im4_);
    ia1_ = lam.max(-wrep_).min(wrep_);  // scratch: the L1 part of Lambda
    iz1_ = im1_ * (0.5 * (wrep_ + ia1_)).max(kZFloor * wrep_);
    iz2_ = im1_ * (0.5 * (wrep_ - ia1_)).max(kZFloor * wrep_);
    iz3_ = im3_ * ((ia1_ - lam).max(0.0) + zf);
    iz4_ = im4_ * ((lam - ia1_).max(0.0) + zf);
  }
}

// Cold start.
void AdmmWorkspace::ipm_start_cold() noexcept {
  const Index n = static_cast<Index>(N_) * nu_;
  Eigen::Map<ArrayXd> u(iU_.data(), n);
  {
    // cold start: u = 0 (the box midpoint if 0 is not inside), t = |u| + 1, z1 = z2 = w / 2 (r_t = 0),
    // box multipliers 1 / s
    for (Index j = 0; j < n; ++j) {
      const double lo = lorep_(j), hi = hirep_(j);
      double v = 0.0;
      if (!(lo < 0.0 && hi > 0.0)) {
        if (std::isfinite(lo) && std::isfinite(hi)) {
          v = 0.5 * (lo + hi);
        } else if (std::isfinite(lo)) {
          v = std::max(0.0, lo) + 1.0;
        } else {
          v = std::min(0.0, hi) - 1.0;
        }
      }
      u(j) = v;
    }
    // infeasible start: t = |u| + 1 and slacks at least 1 (a box narrower than that starts outside,
    // its residual c(u, t) - s decays with the steps), z1 = z2 = w / 2 (r_t = 0), box multipliers 1
    itv_ = im1_ * (u.abs() + 1.0);
    is1_ = im1_ * (itv_ - u).max(1.0) + (1.0 - im1_);
    is2_ = im1_ * (itv_ + u).max(1.0) + (1.0 - im1_);
    is3_ = im3_ * (u - lofin_).max(1.0) + (1.0 - im3_);
    is4_ = im4_ * (hifin_ - u).max(1.0) + (1.0 - im4_);
    iz1_ = 0.5 * im1_ * wrep_;
    iz2_ = iz1_;
  }
}

// Mehrotra's shift of the start, its states and terminal error, and (cold) balanced box multipliers.
void AdmmWorkspace::ipm_center_and_balance(bool warm) noexcept {
  const Index n = static_cast<Index>(N_) * nu_;
  // Mehrotra's shift toward the central path: s += 1/2 s'z / sum z, z += 1/2 s'z / sum s
  const double sz0 = (im1_ * (is1_ * iz1_ + is2_ * iz2_) + im3_ * is3_ * iz3_ + im4_ * is4_ * iz4_).sum();
  const double zs = (im1_ * (iz1_ + iz2_) + im3_ * iz3_ + im4_ * iz4_).sum();
  const double ss = (im1_ * (is1_ + is2_) + im3_ * is3_ + im4_ * is4_).sum();
  if (zs > 0.0 && ss > 0.0) {
    const double ds = 0.5 * sz0 / zs, dz = 0.5 * sz0 / ss;
    is1_ += im1_ * ds;
    is2_ += im1_ * ds;
    is3_ += im3_ * ds;
    is4_ += im4_ * ds;
    itv_ += im1_ * ds;  // keeps s1, s2 consistent with t
    iz1_ += im1_ * dz;
    iz2_ += im1_ * dz;
    iz3_ += im3_ * dz;
    iz4_ += im4_ * dz;
  }
  inu_.setZero();
  rollout(iU_, iX_);
  ie_ = iX_.col(N_) - prob_.xf;
  // box multipliers that balance the gradient at the start (-grad f = z1 - z2 - z3 + z4): a box
  // that binds at the optimum otherwise needs many centering steps to grow its multipliers
  if (!warm) {
    lagrangian_gradient(iX_, iU_, pz_, true);
    for (int k = 0; k < N_; ++k)
      for (int i = 0; i < nu_; ++i) Hg_(i, k) += rg_(i) * iU_(i, k);
    Eigen::Map<const ArrayXd> g0(Hg_.data(), n);
    iz3_ = im3_ * (1.0 + (g0 - im1_ * wrep_).max(0.0));
    iz4_ = im4_ * (1.0 + (-g0 - im1_ * wrep_).max(0.0));
  }
}

// Residuals of the current point and their scales.
AdmmWorkspace::IpmResiduals AdmmWorkspace::ipm_residuals(double wmax) noexcept {
  const bool term = prob_.terminal_equality;
  const Index n = static_cast<Index>(N_) * nu_;
  Eigen::Map<ArrayXd> u(iU_.data(), n);
  IpmResiduals res;
  {
    // residuals of the current point: stationarity r_u = grad f + M' nu - sum z a, r_t, complementarity
    double P = 0.0, gpart = 0.0;  // gpart: the largest term of the gradient (they cancel in a QP)
    Eigen::Map<ArrayXd> grad(Hg_.data(), n);
    {
      // states from the plan itself (stage terms only: no rollout without a stage Q), the terminal
      // state from the carried error
      if (prob_.Q.size() != 0) rollout(iU_, iX_);
      iX_.col(N_) = prob_.xf + ie_;
      P = lagrangian_gradient(iX_, iU_, term ? inu_ : pz_, true);
      gpart = grad.abs().maxCoeff();
      // the diagonal of R moved into g (rg_; zeros without R: then the loop would add +-0 to the
      // gradient, P and gpart, which changes only the sign of a zero that abs drops)
      if ((rg_.array() != 0.0).any())
        for (Index k = 0, j = 0; k < N_; ++k)
          for (Index i = 0; i < nu_; ++i, ++j) {
            const double r = rg_(i);
            gpart = std::max(gpart, std::abs(r * u(j)));
            grad(j) += r * u(j);
            P += 0.5 * r * u(j) * u(j);
          }
    }
    P += ipwv_.sum();  // the per-entry pieces formed by step_l1 (ipm_step_and_pieces)
    const double gscale = std::max({gpart, wmax, 1e-300});
    // without a box z3 = z4 = +0: x - 0 + 0 differs from x only in the sign of a zero, which abs drops
    const double ru = has_box_ ? (grad + iz1_ - iz2_ - iz3_ + iz4_).abs().maxCoeff()
                               : (grad + iz1_ - iz2_).abs().maxCoeff();
    double rp, uscale;
    // Eigen's maxima and sums on the stored arrays: the same elements in the same order as the
    // expressions they replace
    const double sz = iszv_.sum(), rt = irt_.abs().maxCoeff();
    if (has_box_) {
      rp = std::max(
          {irp1_.abs().maxCoeff(), irp2_.abs().maxCoeff(), irp3_.abs().maxCoeff(), irp4_.abs().maxCoeff()});
      uscale = std::max(
          {u.abs().maxCoeff(), (im3_ * lofin_).abs().maxCoeff(), (im4_ * hifin_).abs().maxCoeff(), 1e-300});
    } else {
      rp = std::max(irp1_.abs().maxCoeff(), irp2_.abs().maxCoeff());
      uscale = std::max(u.abs().maxCoeff(), 1e-300);
    }
    res.P = P;
    res.gscale = gscale;
    res.ru = ru;
    res.rt = rt;
    res.sz = sz;
    res.rp = rp;
    res.uscale = uscale;
  }
  return res;
}

// step_l1 on the workspace's arrays: the step by (a, ad) and the next iteration's per-entry pieces
// (Step), or the pieces of the current point alone (the start: ipm_residuals, ipm_factor and the
// predictor's ipm_newton read them, so each per-entry formula exists once)
template <bool Step>
void AdmmWorkspace::ipm_step_and_pieces(double a, double ad) noexcept {
  const Index n = static_cast<Index>(N_) * nu_;
  Eigen::Map<ArrayXd> u(iU_.data(), n);
  const L1Step p{im1_.data(),  wrep_.data(), idu_.data(),  ids1_.data(), ids2_.data(),  idt_.data(),
                 idz1_.data(), idz2_.data(), u.data(),     itv_.data(),  is1_.data(),   is2_.data(),
                 iz1_.data(),  iz2_.data(),  im3_.data(),  im4_.data(),  lofin_.data(), hifin_.data(),
                 ids3_.data(), ids4_.data(), idz3_.data(), idz4_.data(), is3_.data(),   is4_.data(),
                 iz3_.data(),  iz4_.data()};
  const L1Next o{irp1_.data(), irp2_.data(), irt_.data(),  iszv_.data(), ipwv_.data(), isi1_.data(),
                 isi2_.data(), izs1_.data(), izs2_.data(), izi1_.data(), izi2_.data(), id_.data(),
                 ihut_.data(), ihtt_.data(), ilin_.data(), irp3_.data(), irp4_.data(), isi3_.data(),
                 isi4_.data(), izs3_.data(), izs4_.data(), izi3_.data(), izi4_.data()};
  if (has_box_) {
    step_l1<true, Step>(n, a, ad, p, o);
  } else {  // the box's s = 1, z = 0 and steps 0 stay exactly so
    step_l1<false, Step>(n, a, ad, p, o);
  }
}

// One Mehrotra predictor-corrector step from complementarity sz over m constraints; false stops.
bool AdmmWorkspace::ipm_predictor_corrector(double sz, double m) noexcept {
  const bool term = prob_.terminal_equality;
  const Index n = static_cast<Index>(N_) * nu_;
  Eigen::Map<ArrayXd> u(iU_.data(), n);
  {
    if (!ipm_factor() || !ipm_newton(false, 0.0)) return false;
    // predictor: affine step length and the centering parameter sigma = (mu_aff / mu)^3
    const double mu = sz / m;
    // Primal (u, t, s, e) and dual (z, nu) steps of their own lengths, as in LP interior-point codes:
    // the slacks' limit no longer cuts the multipliers' step and the other way round. Stationarity
    // then falls by (1 - a_dual) plus (a_primal - a_dual) H du, H the quadratic part of the cost: with
    // a stage Q that term is large and the fragile stage-Q problems lose their certificate (suite
    // #337), so with a stage Q both take the smaller length (the single step as before). Suite (400
    // problems): 4576 -> 4158 IPM iterations over the certified ones, median 10 -> 9 (docs/guidance.md,
    // session 12 (b12)).
    const bool split = prob_.Q.size() == 0;
    const auto common = [split](IpmMaxStep st) {
      if (!split) st.primal = st.dual = std::min(st.primal, st.dual);
      return st;
    };
    const IpmMaxStep aff = common(ipm_max_step());
    const double ap_aff = std::min(1.0, aff.primal), ad_aff = std::min(1.0, aff.dual);
    // the affine step moves to ia / ib (swapped, no copy: ipm_newton overwrites ids / idz whole)
    ia1_.swap(ids1_);
    ia2_.swap(ids2_);
    ia3_.swap(ids3_);
    ia4_.swap(ids4_);
    ib1_.swap(idz1_);
    ib2_.swap(idz2_);
    ib3_.swap(idz3_);
    ib4_.swap(idz4_);
    const auto l1_aff = im1_ * ((is1_ + ap_aff * ia1_) * (iz1_ + ad_aff * ib1_) +
                                (is2_ + ap_aff * ia2_) * (iz2_ + ad_aff * ib2_));
    double sz_aff;
    if (has_box_) {
      sz_aff = (l1_aff + im3_ * (is3_ + ap_aff * ia3_) * (iz3_ + ad_aff * ib3_) +
                im4_ * (is4_ + ap_aff * ia4_) * (iz4_ + ad_aff * ib4_))
                   .sum();
    } else {  // the box's terms are exact +0 (s = 1, z = 0, steps +0): the first addition of one turns a
              // -0 into +0, the second is the identity
      sz_aff = (l1_aff + 0.0).sum();
    }
    const double mu_aff = sz_aff / m;
    const double sigma = ipm::mehrotra_sigma(mu_aff, mu);
    if (!ipm_newton(true, sigma * mu)) return false;
    // adaptive fraction to the boundary (suite: 5324 -> 4832 IPM iterations, docs/guidance.md)
    const double tau = ipm::fraction_to_boundary(sigma);
    const IpmMaxStep st = common(ipm_max_step());
    const double a = std::min(1.0, tau * st.primal), ad = std::min(1.0, tau * st.dual);
    if (!(std::min(a, ad) > 1e-12)) return false;
    // the step and, from the new point, the next iteration's per-entry pieces in one pass
    ipm_step_and_pieces<true>(a, ad);
    if (term) inu_ += ad * (inun_ - inu_);
    ie_ += a * (iep_ - ie_);
  }
  return true;
}

// The certified plan into the result.
void AdmmWorkspace::ipm_accept() noexcept {
  const bool term = prob_.terminal_equality;
  // the certified plan: Lambda = -(grad f + M' p) from the gap's costate sweep (Hg_ without the
  // diagonal of R moved into g)
  res_.U = iU_;
  res_.Y = iU_;
  for (int k = 0; k < N_; ++k)
    for (int i = 0; i < nu_; ++i) res_.Lambda(i, k) = -(Hg_(i, k) + rg_(i) * iU_(i, k));
  res_.X = res_.X_flown;
  if (term) res_.terminal_multiplier = ie2_;
}

}  // namespace satgnc::guidance::detail
