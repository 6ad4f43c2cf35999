#pragma once
/// @file admm_workspace.hpp
/// Private workspace of guidance::AdmmSolver (not installed): every datum the solver owns, allocated
/// once in the constructor, grouped by part (problem copy, scaling, flags, buffers, polish, condensed
/// step, flat pass, gap, interior point, solve state), and the parts of the algorithm as member
/// functions, one file each (admm_setup.cpp, admm_iteration.cpp, admm_condensed.cpp,
/// admm_polish.cpp, admm_objective.cpp, admm_gap.cpp, admm_scaling.cpp, admm_ipm.cpp). Units are the
/// caller's (see admm.hpp); the solver works on the equilibrated copy prob_.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <type_traits>
#include <vector>

#include "quadratic.hpp"
#include "satgnc/guidance/admm.hpp"
#include "satgnc/guidance/riccati.hpp"

namespace satgnc::guidance::detail {

/// State indices of the Clohessy-Wiltshire in-plane (x, y, vx, vy) and out-of-plane (z, vz) blocks of
/// a (6, 3) problem (AdmmWorkspace::ipm_cw_); the controls are {0, 1} and {2}.
inline constexpr int kCwIn[4] = {0, 1, 3, 4}, kCwOut[2] = {2, 5};

/// The problem as given, the solver's equilibrated copy, the settings, sizes and the Riccati kernel.
struct AdmmProblemData {
  AdmmProblemData(const LtvProblem& problem, const AdmmSettings& settings) : prob_(problem), set_(settings) {}
  LtvProblem orig_;  ///< as given
  LtvProblem prob_;  ///< equilibrated (the solver's)
  AdmmSettings set_;
  std::optional<RiccatiSolver> ric_;  ///< built after equilibration (setup_scaling_and_riccati)
  int nx_ = 0, nu_ = 0, N_ = 0;
};

/// Equilibration (admm_scaling.cpp): u = D_u u~, cost times c.
struct AdmmScalingData {
  Eigen::VectorXd du_;   ///< control scaling D_u
  double cscale_ = 1.0;  ///< cost scaling c
  bool scaled_ = false;
};

/// What applies to this problem (set at setup) and the solver's between-solve flags.
struct AdmmFlags {
  bool has_box_ = false, has_l1_ = false, has_group_ = false, has_ball_ = false;
  bool warm_ = false;
  bool first_solve_ = true;
  bool polish_ok_ = false;
  bool dn_ok_ = false;         ///< smoothed-dual Newton candidates apply (plain L1 + box, condensed map)
  bool qp_polish_ok_ = false;  ///< QP polish applies (no L1, R diagonal > 0, Q = 0)
  bool dual_ok_ = false;       ///< all L1 weights > 0: active-set guess from the dual estimate
  bool cond_ok_ = false;       ///< Q = 0 and R empty or diagonal: M = PsiB_' is stored
  bool psi_ok_ = false;        ///< Psi_, PsiB_, xN0_ are allocated (polish or condensed step)
  bool flat_ok_ = false;       ///< no group-L2 / ball: the flat (vectorized) pass applies
  bool rf_on_ = false;         ///< Rf_ is nonzero
  bool ipm_ok_ = false;        ///< no group-L2 / ball: the IPM applies
  bool dual_at_u_ = false;     ///< res_.X, res_.U hold the x/u iterate: also try the dual bound there
};

/// Weights, bounds, linear terms, warm start, best iterate, scratch and the result.
struct AdmmBuffers {
  Eigen::VectorXd w_, lo_, hi_;
  Eigen::MatrixXd q_;             ///< linear state terms nx x (N+1) from Q, Qf and x_f
  Eigen::MatrixXd r_;             ///< linear control terms nu x N (Lambda - rho Y)
  Eigen::MatrixXd Yws_, Lws_;     ///< warm start
  Eigen::MatrixXd bU_, bY_, bL_;  ///< best iterate (X recomputed from U)
  Eigen::VectorXd v_, ynew_, uhat_, utmp_;
  mutable Eigen::VectorXd xtmp_, xtmp2_;  ///< scratch of the const objective evaluation
  AdmmResult res_;
};

/// Active-set, QP and smoothed-dual Newton polish (admm_polish.cpp).
struct AdmmPolishData {
  int fmax_ = 0;
  Eigen::MatrixXd Psi_;   ///< Phi(N, k+1), nx x nx N
  Eigen::MatrixXd PsiB_;  ///< (Phi(N, k+1) B_k)' stacked, N nu x nx
  Eigen::VectorXd xN0_;   ///< x_N for U = 0 (set at the start of each solve)
  Eigen::MatrixXd GF_, KKT_, Up_, Xp_, grad_;
  Eigen::VectorXd rhs_, sol_, pN_;
  Eigen::VectorXd pe_;  ///< terminal error x_N - x_f solved by the last soft-terminal polish
  Eigen::MatrixXd dn_qi_, dn_H_;
  Eigen::VectorXd dn_s_, dn_u_, dn_nu_, dn_g_, dn_d_, dn_t_, dn_e_;
  Eigen::PartialPivLU<Eigen::MatrixXd> dn_lu_;
  Eigen::MatrixXd Hq_, Sq_;  ///< H_F and the nx x nx system of the QP polish
  Eigen::VectorXd qb_;       ///< its right-hand side
  Eigen::PartialPivLU<Eigen::MatrixXd> q_lu_;
  std::vector<int> free_idx_;
  std::vector<double> fsign_;
  int gap_F_ = 0;    ///< free count of the dual guess by the largest jump in distance
  int viol_j_ = -1;  ///< most violated fixed entry of the last rejected polish (k nu + i)
  double viol_sign_ = 0.0;
  int bad_a_ = -1;        ///< free entry (position) furthest outside its sign / box
  double bad_val_ = 0.0;  ///< where it is fixed by the repair
  Eigen::MatrixXd Gd_;    ///< dual estimate -grad f(U) = Lambda + rho (U - Y_prev), nu x N
  Eigen::VectorXd winv_;
  std::vector<double> seld_;
  std::vector<int> seli_;
};

/// Condensed x/u step (AdmmSettings::condensed; admm_condensed.cpp).
struct AdmmCondensedData {
  Eigen::VectorXd dinv_;   ///< diagonal of (R + rho I)^-1, nu
  Eigen::MatrixXd Gax_;    ///< per-axis Gram matrices sum_k m_ki m_ki', nx x nx nu
  Eigen::MatrixXd Hc_;     ///< H = M D^-1 M', nx x nx
  Eigen::MatrixXd Sc_;     ///< I + H Qf (soft terminal) or H (hard), factored by cond_lu_
  double cond_rho_ = 0.0;  ///< rho of the current condensed factorization
  bool cond_rho_valid_ = false;
  Eigen::PartialPivLU<Eigen::MatrixXd> cond_lu_;
  Eigen::VectorXd cb_, ce_, cg_;  ///< right-hand side, terminal error / multiplier, Qf e
  Eigen::MatrixXd Tc_;            ///< D^-1 r, nu x N
};

/// Flat (vectorized) passes: per-entry weights and bounds replicated over the horizon (N nu).
struct AdmmFlatData {
  Eigen::ArrayXd wrep_, lorep_, hirep_, sigw_, fa_, fb_;
  Eigen::ArrayXd winvrep_, hifin_, lofin_;  ///< 1/w, finite bounds (0 where infinite), N nu
  /// conj_g_flat's constants: w |hi|, w |lo| (0 where infinite), 1 where lo <= 0 <= hi; its scratch
  Eigen::ArrayXd gch_, gcl_, gzok_, gbuf_;
};

/// Duality gap and infeasibility check (admm_gap.cpp).
struct AdmmGapData {
  Eigen::MatrixXd Hg_;          ///< Lagrangian gradient, nu x N
  Eigen::VectorXd lam_, lam2_;  ///< costate scratch, nx
  Eigen::VectorXd xN0all_;      ///< x_N for U = 0 (always computed)
  Eigen::VectorXd ycand_;       ///< infeasibility candidate, nx
  Eigen::VectorXd rg_;          ///< diagonal part of R moved into g for the dual bound (nu; zeros if none)
  Eigen::MatrixXd Rf_;          ///< R - diag(rg_), kept in the smooth part f
  Eigen::VectorXd pz_;          ///< the terminal multiplier used by the gap (zeros if soft terminal)
  std::vector<PwlBreak> brk_;   ///< breakpoints of the dual bound's derivative (N nu: one per entry)
};

/// Interior-point method (admm_ipm.cpp): per-entry arrays over the N nu entries of U.
struct AdmmIpmData {
  int ipm_m_ = 0;                                                 ///< number of inequality constraints
  Eigen::ArrayXd is1_, is2_, is3_, is4_, iz1_, iz2_, iz3_, iz4_;  ///< u, slacks, multipliers
  Eigen::ArrayXd im1_, im3_, im4_;              ///< 1 where the L1 pair / lower / upper constraint exists
  Eigen::ArrayXd id_, ilin_, irt_, idu_, idt_;  ///< diagonal D, linear term, r_t, steps
  Eigen::ArrayXd ids1_, ids2_, ids3_, ids4_, idz1_, idz2_, idz3_, idz4_;
  Eigen::ArrayXd ia1_, ia2_, ia3_, ia4_, ib1_, ib2_, ib3_, ib4_;  ///< affine steps (corrector terms)
  Eigen::ArrayXd itv_, irp1_, irp2_, irp3_, irp4_;  ///< epigraph t and primal residuals c(u, t) - s
  /// per-iteration ratios of ipm_factor, shared by the predictor and the corrector: 1 / s, z / s, and
  /// of the eliminated epigraph pair H_ut / H_tt = (r1 - r2) / (r1 + r2), 1 / H_tt = r1 r2 / (r1 + r2)
  /// (r = s / z, 0 where the pair is absent)
  Eigen::ArrayXd isi1_, isi2_, isi3_, isi4_, izs1_, izs2_, izs3_, izs4_, ihut_, ihtt_;
  Eigen::ArrayXd izi1_, izi2_, izi3_, izi4_;  ///< 1 / z (0 where absent), for ipm_max_step
  /// The step's pass (step_l1) also forms the next iteration's per-entry pieces (r_p, r_t,
  /// ipm_factor's ratios, the predictor's targets) and these terms of the complementarity s'z and of
  /// sum w |u|, summed by Eigen in ipm_residuals in the order of the expressions they replace
  Eigen::ArrayXd iszv_, ipwv_;
  double imaxs_ = 0.0, imaxz_ = 0.0;  ///< max(-ds / s), max(-dz / z) after the last ipm_newton (ipm_max_step)
  Eigen::VectorXd ie2_;               ///< the multiplier of the flown plan (certification)
  Eigen::MatrixXd iU_, iX_, idX_;     ///< IPM plan nu x N, its states and state step nx x (N+1)
  Eigen::VectorXd ie_, inu_, inun_, iep_;  ///< terminal error, multiplier, solved multiplier / error
  Eigen::MatrixXd iS_;  ///< terminal sensitivity dx_N / dnu of the IPM's Riccati factorization
  Eigen::PartialPivLU<Eigen::MatrixXd> ilu_;
  // Riccati path: per stage K_k, Quu_k^-1, Qux_k, Knu_k (nu x nx N or nu x nu N), scratch
  Eigen::MatrixXd iK_, iQi_, iQux_, iKnu_, iP_, iPn_, iL_, iLn_, iBtP_, iQuu_, iAcl_, iZ_, iBtL_;
  Eigen::MatrixXd ikff_;
  /// (6, 3) LTI problems whose in-plane (x, y, vx, vy; ux, uy) and out-of-plane (z, vz; uz) parts
  /// are exactly decoupled in A, B, Qf, Q and R (Clohessy-Wiltshire), with or without a hard terminal state:
  /// the Riccati factor runs on the 4 x 4 and 2 x 2 blocks (ipm_riccati_factor_cw). The blocks,
  /// column-major, and their transposes: A4 (16), B4 (8), A2 (4), B2 (2).
  bool ipm_cw_ = false;
  double cwA4_[16] = {}, cwB4_[8] = {}, cwA2_[4] = {}, cwB2_[2] = {};
  double cwA4t_[16] = {}, cwB4t_[8] = {}, cwA2t_[4] = {}, cwB2t_[2] = {};
  Eigen::VectorXd ip_, ipn_, iqu_, idx_, idxn_;
  Eigen::LLT<Eigen::MatrixXd> illt_;
  Eigen::MatrixXd iInu_;
  /// Checkpoint of the IPM: the iterate with the smallest stopping measure so far (plan, terminal
  /// multiplier and error), certified when the run ends without a certificate (admm_ipm.cpp).
  Eigen::MatrixXd icU_;
  Eigen::VectorXd icnu_, ice_;
};

/// Per-iteration statistics of the fused relaxation / prox / multiplier pass.
struct AdmmPassStats {
  double prim = 0.0, dual = 0.0, fro2 = 0.0, nU = 0.0, nY = 0.0, nL = 0.0;
  std::uint64_t signature = 0;  ///< hash of the active set of Y (zero / bound / free sign)
  int nfree = 0;
};

/// State of the running solve() (set by begin_solve, read by the loop steps and finish_solve).
struct AdmmSolveState {
  std::chrono::steady_clock::time_point solve_start_{};  ///< start of the running solve()
  int fact0_ = 0;                                        ///< Riccati factorizations before this solve
  double rho_ = 0.0;                                     ///< current penalty
  bool timed_ = false, gap_on_ = false, infeas_on_ = false;
  int last_gap_it_ = 0;
  bool ok_ = true;
  bool cond_ = false;  ///< the condensed x/u step is in use
  int cond_facts_ = 0;
  double a_ = 1.0;     ///< relaxation
  double dimU_ = 0.0;  ///< N nu
  double best_ = 0.0, best_prim_ = 0.0, best_dual_ = 0.0, best_paper_ = 0.0;
  AdmmStatus status_ = AdmmStatus::max_iterations;
  int it_ = 0;
  bool r_valid_ = false;  ///< r_ = Lambda - rho Y is produced by the previous pass
  bool paper_rule_ = false, polish_on_ = false, qp_polish_on_ = false;
  int next_dn_it_ = 50;
  std::uint64_t prev_sig_ = 0, tried_sig_ = 0, prev_dsig_ = 0, tried_dsig_ = 0;
  std::array<std::uint64_t, 16> failed_{};  ///< rejected dual guesses of this solve (ring)
  int n_failed_ = 0, next_failed_ = 0;
  std::array<std::uint64_t, 16> yfailed_{};  ///< rejected Y-pattern candidates (ring)
  int n_yfailed_ = 0, next_yfailed_ = 0;
  bool have_prev_ = false, have_tried_ = false, have_dprev_ = false, have_dtried_ = false;
  bool ipm_on_ = false;  ///< interior-point method: alone (kIpm) or as the endgame at ipm_at_
  int ipm_at_ = 0;
  bool ipm_only_ = false;
  // this iteration's pass
  AdmmPassStats st_;
  double prim_ = 0.0, dual_ = 0.0, nL_ = 0.0;
};

/// The workspace: all data above and the parts of the algorithm (see the file comment).
struct AdmmWorkspace : AdmmProblemData,
                       AdmmScalingData,
                       AdmmFlags,
                       AdmmBuffers,
                       AdmmPolishData,
                       AdmmCondensedData,
                       AdmmFlatData,
                       AdmmGapData,
                       AdmmIpmData,
                       AdmmSolveState {
  using PassStats = AdmmPassStats;

  /// Validates (std::invalid_argument naming the field) and allocates everything (admm_setup.cpp).
  AdmmWorkspace(const LtvProblem& problem, const AdmmSettings& settings);

  // setup steps (admm_setup.cpp)
  void setup_sizes_and_workspace_check();
  void setup_weights_and_bounds();
  void setup_scaling_and_riccati();
  void setup_buffers();
  void setup_dual_split();
  void setup_flat_pass();
  void setup_psi_and_condensed();
  void setup_qp_polish();
  void setup_polish();

  // solve steps (admm_iteration.cpp)
  const AdmmResult& solve() noexcept;
  void begin_solve() noexcept;
  void reset_loop_state() noexcept;
  void start_ipm_alone() noexcept;
  bool iterate_once() noexcept;  ///< false: stop (status_ set)
  bool xu_step() noexcept;
  bool pass_and_residuals() noexcept;
  void track_best() noexcept;
  bool polish_round() noexcept;  ///< true: a certified polish ended the solve
  bool polish_by_dual() noexcept;
  bool polish_by_pattern() noexcept;
  bool polish_by_dual_newton() noexcept;
  bool polish_qp_round() noexcept;
  bool polish_gap_ok() noexcept;
  /// A polished plan accepted (status solved) when polish_gap_ok(); else r_valid_ = false.
  bool accept_polish() noexcept;
  bool check_stop() noexcept;
  /// The relative gap test of every `solved` / `solved_inaccurate`: -tol <= gap <= tol. A gap below
  /// -tol (the dual bound above the plan's cost beyond the tolerance) means the plan is not feasible
  /// enough (hard terminal miss) or the bound is wrong; NaN / inf fail.
  static bool gap_within(double gap, double tol) noexcept { return std::abs(gap) <= tol; }
  bool ipm_endgame() noexcept;
  bool check_limits() noexcept;
  bool adapt_rho() noexcept;
  void finish_solve() noexcept;
  void restore_best_or_zero() noexcept;
  void check_inaccurate() noexcept;
  void warm_start(const Eigen::Ref<const Eigen::MatrixXd>& Y,
                  const Eigen::Ref<const Eigen::MatrixXd>& Lambda);
  void set_x0(const Eigen::Ref<const Eigen::VectorXd>& x0);
  void set_xf(const Eigen::Ref<const Eigen::VectorXd>& xf);
  void update_settings(const AdmmSettings& settings);
  bool update_dynamics(const std::vector<Eigen::MatrixXd>& A, const std::vector<Eigen::MatrixXd>& B,
                       const std::vector<Eigen::VectorXd>& c) noexcept;
  void update_linear_terms() noexcept;
  template <int NU>
  PassStats admm_pass(double rho, double a) noexcept;
  /// The same pass for L1 (+ box) without group-L2 or ball, as array expressions over all N nu
  /// entries (vectorized; identical values, the signature is a weighted sum instead of a hash).
  PassStats admm_pass_flat(double rho, double a, bool fro2) noexcept;

  // objective (admm_objective.cpp)
  double control_cost(const Eigen::Ref<const Eigen::VectorXd>& u) const noexcept;
  double trajectory_objective(const Eigen::Ref<const Eigen::MatrixXd>& X,
                              const Eigen::Ref<const Eigen::MatrixXd>& U) const noexcept;
  void rollout(const Eigen::Ref<const Eigen::MatrixXd>& U, Eigen::Ref<Eigen::MatrixXd> X) const noexcept;
  double objective_of(const Eigen::Ref<const Eigen::MatrixXd>& U) const;
  double terminal_miss_ratio() noexcept;

  // condensed step (admm_condensed.cpp)
  void update_psib() noexcept;
  bool cond_factor(double rho) noexcept;
  void cond_step() noexcept;

  // polish (admm_polish.cpp)
  bool try_polish(bool rank_by_dual) noexcept;
  int dual_candidate(std::uint64_t& signature) noexcept;
  /// Reduced KKT solve and optimality certificate for the candidate in Up_ (free_idx_, fsign_).
  bool polish_solve(int F) noexcept;
  int polish_build_kkt(int F) noexcept;
  bool polish_unpack(int F) noexcept;
  bool polish_optimality_violated() noexcept;
  bool polish_swaps(int& F) noexcept;
  /// After a certified soft-terminal polish: X_flown's terminal column from the solved error pe_.
  void polished_terminal() noexcept;
  bool qp_polish() noexcept;
  void accept_polished(bool term) noexcept;
  bool dual_newton() noexcept;
  double dn_curvature() noexcept;
  double dn_evaluate(const Eigen::VectorXd& nu, double eps) noexcept;
  int dn_newton_step(double eps) noexcept;
  int dn_candidate(double eps) noexcept;

  // duality gap and infeasibility (admm_gap.cpp)
  /// Backward costate sweep at (X, U) with terminal costate Qf (x_N - x_f) + p: fills Hg_ with the
  /// Lagrangian gradient grad f(U) + M' p (nu x N) and returns the smooth part f(U).
  double lagrangian_gradient(const Eigen::Ref<const Eigen::MatrixXd>& X,
                             const Eigen::Ref<const Eigen::MatrixXd>& U,
                             const Eigen::Ref<const Eigen::VectorXd>& p, bool with_cost) noexcept;
  /// Conjugate g*(s z) of the nonsmooth part at z = -Hg_ (infinite if outside its domain).
  double conj_g(double s) const noexcept;
  /// conj_g for L1 + box without a diagonal R part (flat_ok_, rg_ = 0) at an s where it is finite
  /// (s in [0, smax]): the per-entry terms as array expressions, summed in conj_g's order (the same
  /// value to the bit).
  double conj_g_flat(double s) noexcept;
  /// Largest value of the concave D(s) = -f s^2 + c1 s - g*(-s Hg_) seen by a golden-section search
  /// on [0, smax] (group-L2 / ball: not piecewise quadratic in s; R in g: see dual_argmax_pwq).
  double dual_max_golden(double f, double c1, double smax) const noexcept;
  /// The maximizer of the same D for L1 + box without R in g, exactly: D is concave piecewise
  /// quadratic, its derivative piecewise linear with one jump per entry at most (admm_gap.cpp).
  double dual_argmax_pwq(double f, double c1, double smax) noexcept;
  /// Fenchel dual bound D at the plan (X, U) with terminal multiplier p (see AdmmInfo); sets
  /// info primal/dual objective and duality_gap, returns the relative gap.
  double evaluate_gap(const Eigen::Ref<const Eigen::MatrixXd>& X, const Eigen::Ref<const Eigen::MatrixXd>& U,
                      const Eigen::Ref<const Eigen::VectorXd>& p, double P) noexcept;
  /// The Fenchel dual bound D built from the residuals at (X, U) (any control sequence), maximized
  /// over s exactly (L1 + box) or by golden section (R in g, group-L2 / ball, or `golden`: the
  /// tests compare the two).
  double dual_bound(const Eigen::Ref<const Eigen::MatrixXd>& X, const Eigen::Ref<const Eigen::MatrixXd>& U,
                    const Eigen::Ref<const Eigen::VectorXd>& p, bool golden = false) noexcept;
  /// Farkas test of candidate y for x_f unreachable within the box; true and stores it if it holds.
  bool check_infeasible(const Eigen::Ref<const Eigen::VectorXd>& y) noexcept;
  static double estimate_workspace_bytes(int nx, int nu, int N) noexcept;

  // equilibration (admm_scaling.cpp)
  void equilibrate_problem();
  void unscale_result() noexcept;

  // interior-point method (admm_ipm.cpp)
  /// Run the IPM from a cold start; true if its plan passes the gap / terminal tests, then the
  /// plan, its multipliers and X_flown are in res_. Leaves res_ U, Y, Lambda untouched otherwise.
  bool ipm_solve(bool warm) noexcept;  ///< warm: from ADMM's Y and Lambda
  /// time_limit > 0 and exceeded since solve_start_ (the IPM checks it per iteration: at -O0 one run
  /// of 60 iterations on N = 200 took seconds past a 0.5 s limit).
  bool out_of_time() const noexcept {
    return set_.time_limit > 0.0 &&
           std::chrono::duration<double>(std::chrono::steady_clock::now() - solve_start_).count() >
               set_.time_limit;
  }
  void ipm_setup();
  bool ipm_factor() noexcept;
  template <int NX, int NU>
  bool ipm_riccati_factor() noexcept;
  bool ipm_riccati_factor_63() noexcept;  ///< the same for (nx, nu) = (6, 3), written out
  bool ipm_riccati_factor_cw() noexcept;  ///< the same on the decoupled CW blocks (ipm_cw_)
  void ipm_setup_cw() noexcept;           ///< decides ipm_cw_ and gathers the blocks
  template <int NX, int NU>
  void ipm_riccati_sweep() noexcept;
  void ipm_riccati_sweep_63() noexcept;  ///< the same for (nx, nu) = (6, 3), written out
  void ipm_forward_63() noexcept;        ///< its forward pass
  void ipm_riccati_sweep_cw() noexcept;  ///< the same on the decoupled CW blocks (ipm_cw_)
  void ipm_forward_cw() noexcept;        ///< its forward pass
  template <int NU>
  auto llt_ref() noexcept -> std::conditional_t<NU == Eigen::Dynamic, Eigen::LLT<Eigen::MatrixXd>&,
                                                Eigen::LLT<Eigen::Matrix<double, NU, NU>>>;
  /// The largest steps to the boundary: of the slacks (primal) and of the multipliers (dual).
  struct IpmMaxStep {
    double primal = 0.0, dual = 0.0;
  };
  IpmMaxStep ipm_max_step() const noexcept;
  bool ipm_newton(bool corrector, double sigma_mu) noexcept;
  bool ipm_certify() noexcept;
  void ipm_start_warm() noexcept;
  void ipm_start_cold() noexcept;
  void ipm_center_and_balance(bool warm) noexcept;
  /// Residuals of the current interior point and their scales (ipm_residuals).
  struct IpmResiduals {
    double P = 0.0, gscale = 0.0, ru = 0.0, rt = 0.0, sz = 0.0, rp = 0.0, uscale = 0.0;
  };
  IpmResiduals ipm_residuals(double wmax) noexcept;
  bool ipm_predictor_corrector(double sz, double m) noexcept;
  template <bool Step>
  void ipm_step_and_pieces(double a, double ad) noexcept;
  void ipm_accept() noexcept;
};

}  // namespace satgnc::guidance::detail
