#pragma once
/// @file riccati.hpp
/// Riccati (LQR) step with affine terms for discrete linear time-varying problems, with the gains
/// cached between calls and an exact terminal equality constraint x_N = x_f through a terminal
/// multiplier and a precomputed sensitivity dx_N/dnu.
///
/// Problem solved by solve():
///   minimize   1/2 x_N' Qf x_N + q_N' x_N
///            + sum_{k=0}^{N-1} 1/2 x_k' Q x_k + q_k' x_k + 1/2 u_k' (R + rho I) u_k + r_k' u_k
///   subject to x_{k+1} = A_k x_k + B_k u_k + c_k,  x_0 given,  [x_N = x_f if terminal_equality].
/// Units are those of the caller (the guidance room uses m, m/s, N or a scaled set).
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <vector>

#include "satgnc/core/status.hpp"

namespace satgnc::guidance {

/// Discrete linear time-varying dynamics x_{k+1} = A_k x_k + B_k u_k + c_k, k = 0..N-1.
/// A, B hold either one entry (time-invariant, no N copies stored) or N entries; c holds 0
/// (no drift term), 1 or N entries.
struct LtvDynamics {
  std::vector<Eigen::MatrixXd> A;  ///< nx x nx each
  std::vector<Eigen::MatrixXd> B;  ///< nx x nu each
  std::vector<Eigen::VectorXd> c;  ///< nx each (optional)
  int horizon = 0;                 ///< N, number of control intervals (>= 1)

  int nx() const { return A.empty() ? 0 : static_cast<int>(A[0].rows()); }
  int nu() const { return B.empty() ? 0 : static_cast<int>(B[0].cols()); }
  const Eigen::MatrixXd& A_at(int k) const { return A.size() == 1 ? A[0] : A[k]; }
  const Eigen::MatrixXd& B_at(int k) const { return B.size() == 1 ? B[0] : B[k]; }
  /// Validates sizes and finiteness (std::invalid_argument naming the field and a hint).
  void validate() const;
};

/// Outcome of one Riccati solve (core/status.hpp: unsolved = factor() not called or failed,
/// solved, terminal_unreachable; kOk, kTerminalUnreachable, kNotFactored are deprecated aliases).
using core::RiccatiStatus;

/// Constant data of the Riccati step (units of the caller).
struct RiccatiProblem {
  LtvDynamics dynamics;  ///< validated by the solver
  Eigen::MatrixXd Q;     ///< stage state weight nx x nx (PSD) or 0x0 for none; applied to x_1..x_{N-1}
  Eigen::MatrixXd R;     ///< stage control weight nu x nu (PSD) or 0x0 for none
  Eigen::MatrixXd Qf;    ///< terminal weight nx x nx (PSD)
  bool terminal_equality = false;  ///< enforce x_N = x_f exactly in solve()
};

/// The buffers of RiccatiSolver: the cached factorization (per-stage blocks side by side) and the
/// scratch of its recursions. Sized once by the solver's constructor for (nx, nu, N); factor() and
/// solve() only write into it (no allocation). Held by value in the solver: the kernel runs inside
/// every ADMM iteration, and its loops read these buffers without a pointer indirection.
struct RiccatiWorkspace {
  // cached per stage (blocks side by side): P_k, K_k, (A-BK)', A-BK, Quu^-1, Quu^-1 B', P_{k+1} c_k
  Eigen::MatrixXd P, K, AclT, Acl, QuuInv, QuuInvBt, e;
  // terminal-constraint responses to a unit multiplier: controls T_k, states Z_k; sensitivity S
  Eigen::MatrixXd T, Z, S, Spinv, eigvec;
  Eigen::VectorXd eigval;
  // scratch
  Eigen::MatrixXd BtP, Quu, Qux, AtP, tmp_nx_nx, tmp_nu_nu, Pn, W, Wn;
  Eigen::LLT<Eigen::MatrixXd> llt;
  Eigen::MatrixXd D, K2, D2, Inu;
  Eigen::MatrixXd Hbuf, Wbuf;  ///< per-stage off-chain terms of the (6, 3) kernel, nx x N each
  Eigen::VectorXd p, w, tmp_nx, tmp_nu, nu_term, miss;
};

/// Riccati recursion with cached gains: a kernel inside ADMM (as OSQP's linear-system solver), not a
/// user solver. The constructor allocates; factor() and solve() do not.
class RiccatiSolver {
 public:
  /// Copy the constant data and allocate the workspace.
  /// @throws std::invalid_argument on inconsistent sizes, non-finite data or non-symmetric weights
  explicit RiccatiSolver(const RiccatiProblem& problem);

  /// Old two-step construction: an empty solver, then setup().
  [[deprecated("use RiccatiSolver(const RiccatiProblem&)")]] RiccatiSolver() = default;

  /// Copy the constant data and allocate the workspace (the old two-step construction).
  /// @param dyn  dynamics (validated)
  /// @param Q    stage state weight nx x nx (PSD) or 0x0 for none; applied to x_1..x_{N-1}
  /// @param R    stage control weight nu x nu (PSD) or 0x0 for none
  /// @param Qf   terminal weight nx x nx (PSD)
  /// @param terminal_equality  enforce x_N = x_f exactly in solve()
  /// @throws std::invalid_argument on inconsistent sizes, non-finite data or non-symmetric weights
  [[deprecated("use RiccatiSolver(const RiccatiProblem&)")]] void setup(const LtvDynamics& dyn,
                                                                        const Eigen::MatrixXd& Q,
                                                                        const Eigen::MatrixXd& R,
                                                                        const Eigen::MatrixXd& Qf,
                                                                        bool terminal_equality) {
    init(dyn, Q, R, Qf, terminal_equality);
  }

  /// Riccati backward recursion for the control weight R + rho I: caches the gains K_k,
  /// (R + rho I + B'PB)^-1, the closed-loop matrices and, with the terminal constraint, the
  /// sensitivity of x_N to the terminal multiplier. No allocation. Returns false if a stage
  /// Hessian is not positive definite (rho <= 0 with singular R).
  bool factor(double rho) noexcept;

  /// Affine backward sweep with the cached gains and forward rollout.
  /// @param x0 initial state (nx)
  /// @param q  linear state terms, nx x (N+1) (column k multiplies x_k; column N is q_N)
  /// @param r  linear control terms, nu x N
  /// @param xf terminal target (nx), used only with the terminal constraint
  /// @param X  output states nx x (N+1);  @param U output controls nu x N
  RiccatiStatus solve(const Eigen::Ref<const Eigen::VectorXd>& x0, const Eigen::Ref<const Eigen::MatrixXd>& q,
                      const Eigen::Ref<const Eigen::MatrixXd>& r, const Eigen::Ref<const Eigen::VectorXd>& xf,
                      Eigen::Ref<Eigen::MatrixXd> X, Eigen::Ref<Eigen::MatrixXd> U) noexcept;

  /// Reference path: the full textbook recursion (value function and affine terms together, stage
  /// Hessians refactored) for the same problem; used to check solve(). No allocation.
  RiccatiStatus solve_full(double rho, const Eigen::Ref<const Eigen::VectorXd>& x0,
                           const Eigen::Ref<const Eigen::MatrixXd>& q,
                           const Eigen::Ref<const Eigen::MatrixXd>& r,
                           const Eigen::Ref<const Eigen::VectorXd>& xf, Eigen::Ref<Eigen::MatrixXd> X,
                           Eigen::Ref<Eigen::MatrixXd> U) noexcept;

  int nx() const { return nx_; }
  int nu() const { return nu_; }
  int horizon() const { return N_; }
  double rho() const { return rho_; }
  /// Number of factor() calls since setup.
  int factorizations() const { return factorizations_; }
  /// Terminal multiplier nu of the last solve with the terminal constraint (nx).
  const Eigen::VectorXd& terminal_multiplier() const { return ws_.nu_term; }
  /// Sensitivity dx_N/dnu (nx x nx, negative semidefinite) of the current factorization.
  const Eigen::MatrixXd& terminal_sensitivity() const { return ws_.S; }
  /// The workspace (read-only): cached gains and scratch of the last factor() / solve().
  const RiccatiWorkspace& workspace() const noexcept { return ws_; }
  /// Rank of the terminal sensitivity (= dimension of the reachable subspace of x_N).
  int terminal_rank() const { return rank_; }

  /// Overwrite the stored dynamics of stage k (A_k nx x nx, B_k nx x nu, c_k nx or empty when no c
  /// is stored) in place, without allocation; call factor() afterwards. Returns false (nothing
  /// changed) on a bad k, a size mismatch, non-finite data, or when the stage is shared
  /// (time-invariant storage with N > 1).
  bool set_stage_dynamics(int k, const Eigen::Ref<const Eigen::MatrixXd>& A,
                          const Eigen::Ref<const Eigen::MatrixXd>& B,
                          const Eigen::Ref<const Eigen::VectorXd>& c) noexcept;

 private:
  void init(const LtvDynamics& dyn, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R,
            const Eigen::MatrixXd& Qf, bool terminal_equality);
  template <int NX, int NU>
  void affine_sweep(const Eigen::Ref<const Eigen::VectorXd>& x0, const Eigen::Ref<const Eigen::MatrixXd>& q,
                    const Eigen::Ref<const Eigen::MatrixXd>& r, Eigen::Ref<Eigen::MatrixXd> X,
                    Eigen::Ref<Eigen::MatrixXd> U) noexcept;
  void affine_sweep_63(const Eigen::Ref<const Eigen::VectorXd>& x0,
                       const Eigen::Ref<const Eigen::MatrixXd>& q, const Eigen::Ref<const Eigen::MatrixXd>& r,
                       Eigen::Ref<Eigen::MatrixXd> X, Eigen::Ref<Eigen::MatrixXd> U) noexcept;
  template <int NX, int NU>
  RiccatiStatus apply_terminal(const Eigen::Ref<const Eigen::VectorXd>& xf, Eigen::Ref<Eigen::MatrixXd> X,
                               Eigen::Ref<Eigen::MatrixXd> U) noexcept;
  bool factor_stage(int k, double rho) noexcept;

  LtvDynamics dyn_;
  Eigen::MatrixXd Q_, R_, Qf_;
  bool terminal_ = false;
  bool factored_ = false;
  int nx_ = 0, nu_ = 0, N_ = 0;
  double rho_ = 0.0;
  int factorizations_ = 0;
  int rank_ = 0;

  RiccatiWorkspace ws_;  // by value: the hot loops read its buffers without an indirection
};

/// Symmetric eigen-decomposition by cyclic Jacobi rotations, in place and allocation-free:
/// on return V holds the eigenvectors (columns) and w the eigenvalues of the symmetric S.
/// S is overwritten. Used for the terminal sensitivity pseudo-inverse.
void jacobi_eigen(Eigen::Ref<Eigen::MatrixXd> S, Eigen::Ref<Eigen::MatrixXd> V,
                  Eigen::Ref<Eigen::VectorXd> w) noexcept;

}  // namespace satgnc::guidance
