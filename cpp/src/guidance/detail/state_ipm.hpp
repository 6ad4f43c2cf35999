#pragma once
// Private: the interior-point method of StateConstrainedAdmm (state_constraints.hpp). Mehrotra
// predictor-corrector on the equilibrated problem: per control entry the epigraph t >= |u| and the
// box (eliminated into a diagonal of R), per state row its interval slacks (rows scaled by
// escale: unit sensitivity to the controls), per cone block the Nesterov-Todd scaled SOC, the
// equality rows at node N by their multipliers (an ne x ne Schur complement). Every Newton step
// is one LQR solved by a Riccati recursion: O(N) per iteration, no dense KKT. Allocation-free
// after setup(). It only proposes (Y, mu): the caller certifies (violation, Fenchel gap).
#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "satgnc/guidance/admm.hpp"

namespace satgnc::guidance::detail {

/// Views of the caller's (equilibrated) problem and rows; the caller owns them.
struct StateIpmProblem {
  const LtvProblem* prob = nullptr;  ///< B scaled, Qf, Q, xf, x0, dynamics offsets
  bool has_Q = false;
  const Eigen::VectorXd *w = nullptr, *rdiag = nullptr, *ulo = nullptr, *uhi = nullptr;
  const Eigen::MatrixXd* Crow = nullptr;  ///< nx x m unit rows
  const Eigen::VectorXi *node = nullptr, *cone_start = nullptr;
  const Eigen::VectorXd *lo = nullptr, *hi = nullptr, *off = nullptr, *escale = nullptr;
};

class StateIpm {
 public:
  /// Sizes every buffer (allocates).
  void setup(int nx, int nu, int N, int m);
  /// True when the IPM applies: every L1 weight > 0, equality rows only at node N.
  bool applicable(const StateIpmProblem& p) noexcept;
  /// Cold start (u = 0, slacks shifted into the cones, unit duals).
  void init(const StateIpmProblem& p) noexcept;
  /// One predictor-corrector step; false on a numerical failure (factorization, non-finite).
  bool step(const StateIpmProblem& p) noexcept;
  /// Complementarity s'z summed over all cones (scaled problem).
  double complementarity() const noexcept { return sz_; }
  /// Largest primal residual |G x + s - h| and equality residual.
  double primal_residual() const noexcept { return rp_; }
  /// The plan (clipped to the control box) and the row multipliers in the ADMM's convention
  /// (gradient f + C' mu = 0 on the unit rows; cone blocks in the polar cone).
  void export_solution(const StateIpmProblem& p, Eigen::MatrixXd& Y, Eigen::VectorXd& mu) const noexcept;
  int iterations = 0;

 private:
  void rollout(const StateIpmProblem& p, const Eigen::MatrixXd& U, Eigen::MatrixXd& X) const noexcept;
  template <int NX, int NU>
  void rollout_t(const StateIpmProblem& p, const Eigen::MatrixXd& U, Eigen::MatrixXd& X) const noexcept;
  void residuals(const StateIpmProblem& p) noexcept;
  template <int NX>
  void residuals_t(const StateIpmProblem& p) noexcept;
  void scaling(const StateIpmProblem& p) noexcept;
  bool factor(const StateIpmProblem& p) noexcept;
  template <int NX, int NU>
  bool factor_stages(const StateIpmProblem& p) noexcept;
  bool riccati_63(const StateIpmProblem& p) noexcept;
  void solve_newton(const StateIpmProblem& p, bool affine, double sigma_mu) noexcept;
  template <int NX, int NU>
  void solve_newton_t(const StateIpmProblem& p, bool affine, double sigma_mu) noexcept;
  template <int NX, int NU>
  void sweep_stages(const StateIpmProblem& p) noexcept;
  template <int NX, int NU>
  double newton_residual(const StateIpmProblem& p) noexcept;
  template <int NX, int NU>
  void refine(const StateIpmProblem& p) noexcept;
  template <int NX, int NU>
  void debias(const StateIpmProblem& p) noexcept;
  double max_step() const noexcept;
  // Barrier weight of side q of interval row j in the reduced Newton system, 1 / (s/z + delta): the
  // dual regularization delta (a proximal term on the row multipliers, Clarabel / proxsuite style;
  // scaled units) bounds it. Unbounded, the weights of the active rows of a degenerate problem (thin
  // closing-velocity wedges pinned by boxes) reached ~1e12, the Riccati recursion lost its digits to
  // cancellation and the run stopped on a failed factorization mid-way. Seeded box / mixed suites
  // (IPM alone, 30 each): delta 0: 12 / 10 certified; 1e-7: 28 / 24; 1e-6: 28 / 25;
  // 1e-5: - / 17; 1e-4: - / 12 (mixed only; 2026-12-03).
  double row_weight(int q, int j) const noexcept { return 1.0 / (ss_(q, j) / zs_(q, j) + kDualReg); }
  static constexpr double kDualReg = 1e-6;

  int nx_ = 0, nu_ = 0, N_ = 0, m_ = 0, ne_ = 0, nlp_ = 0, ncone_ = 0;
  double sz_ = 0.0, rp_ = 0.0;
  bool scaling_ok_ = true;
  bool has_interval_rows_ = false;  // some state row has a finite upper or lower side (init())
  bool residuals_current_ = false;  // residuals() of the current iterate done (end of step())
  Eigen::VectorXi eqrow_;           // the equality rows (all at node N)
  // primal / dual iterates: controls and epigraph, equality multipliers
  Eigen::MatrixXd u_, t_, X_;
  Eigen::VectorXd nu_eq_;
  // control inequalities (4 per entry: t - u, t + u, u - lo, hi - u), state rows (upper, lower),
  // cone blocks (3 entries at the block's rows)
  Eigen::MatrixXd sc_, zc_, rc_, dsc_, dzc_, corc_, rhsc_;
  Eigen::MatrixXd dqc_;  // z / s of each control row (0 where absent), from factor(): both Newton solves
  Eigen::MatrixXd ss_, zs_, rs_, dss_, dzs_, cors_, rhss_;
  Eigen::VectorXd scn_, zcn_, rcn_, dscn_, dzcn_, corcn_, rhscn_, lamcn_;
  Eigen::MatrixXd Wcn_, Wicn_, W2cn_;  // 9 x m: NT scaling of each cone block (column-major 3 x 3)
  Eigen::VectorXd req_, dnu_;
  // Newton system: per-node state Hessian and gradients, per-entry (u, t) blocks
  Eigen::MatrixXd Qx_, gx_, huu_, hut_, htt_, gu_, gt_, Rd_, rr_;
  Eigen::MatrixXd du_, dt_, dX_;
  // iterative refinement of the Newton solve: the right-hand side, the accumulated direction and the
  // residual of the unshifted reduced system (sized at setup)
  Eigen::MatrixXd gx0_, rr0_, du_acc_, dX_acc_, res_u_;
  Eigen::VectorXd req0_, dnu_acc_, res_e_;
  // debias(): offsets of the row equations (delta dz per side), their change, the direction so far
  Eigen::MatrixXd ofs_, dofs_, du_tot_, dX_tot_;
  Eigen::VectorXd dnu_tot_, req_keep_;
  // Riccati (per-stage blocks side by side, column-major: fixed-size views in the (6, 3) case)
  Eigen::MatrixXd P_, K_, Qi_, d_, Dall_, T_, T2_, Sf_, G_, CW_, Se_, tmp_nx_nx_, tmp_nx_nx2_, tmp_nu_nx_,
      Quu_, Acl_, RK_;
  Eigen::VectorXd p_, wv_, ex_, dnu_pad_, g_nu_, tmp_nx_, rhs_e_;
  Eigen::LLT<Eigen::MatrixXd> llt_, llt_e_;
  Eigen::VectorXi has_lo_, has_hi_;
};

}  // namespace satgnc::guidance::detail
