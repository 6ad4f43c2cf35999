#include "satgnc/guidance/ilqr_admm.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "detail/cholesky.hpp"
#include "detail/ilqr_admm_workspace.hpp"
#include "detail/model_step.hpp"
#include "detail/quadratic.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::guidance {

using core::require;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

// Checks on the calls ScpSolver makes inside its solve loop (warm start, stage bounds): the message
// strings are built only on failure, so a passing check does not allocate.
void check_dims(const Eigen::Ref<const MatrixXd>& M, int r, int c, const char* name) {
  if (M.rows() != r || M.cols() != c)
    require(false, name, "must be nu x N = " + std::to_string(r) + " x " + std::to_string(c));
}
void check_finite(const Eigen::Ref<const MatrixXd>& M, const char* name) {
  if (!M.allFinite()) core::require_finite(M, name);
}

double soft(double v, double t) { return v > t ? v - t : (v < -t ? v + t : 0.0); }

// Cholesky of a small fixed-size SPD matrix and solve L L^T X = R in place; false if not positive
// definite.
template <int NU, typename MU, typename RHS>
bool small_cholesky_solve(MU& M, RHS& R) {
  if (!detail::cholesky_factor_inplace<NU>(M)) return false;
  detail::cholesky_solve_inplace<NU>(M, R);
  return true;
}

// Fixed-size Riccati sweep (stack temporaries, no heap) for the common dimensions.
template <int NX, int NU>
bool backward_fixed(int N, const std::vector<MatrixXd>& Av, const std::vector<MatrixXd>& Bv,
                    std::vector<MatrixXd>& Kv, MatrixXd& dM, const MatrixXd& Qf, const VectorXd& eN,
                    const MatrixXd& U, const MatrixXd& Lam, const MatrixXd& Y, double w, double rho,
                    double reg, double& dv1, double& dv2) {
  using MX = Eigen::Matrix<double, NX, NX>;
  using MXU = Eigen::Matrix<double, NX, NU>;
  using MU = Eigen::Matrix<double, NU, NU>;
  using MUX = Eigen::Matrix<double, NU, NX>;
  using VX = Eigen::Matrix<double, NX, 1>;
  using VU = Eigen::Matrix<double, NU, 1>;
  MX S = Eigen::Map<const MX>(Qf.data());
  VX s = S * Eigen::Map<const VX>(eN.data());
  dv1 = 0.0;
  dv2 = 0.0;
  for (int k = N - 1; k >= 0; --k) {
    const Eigen::Map<const MX> A(Av[k].data());
    const Eigen::Map<const MXU> B(Bv[k].data());
    const MX SA = S.lazyProduct(A);
    const MXU SB = S.lazyProduct(B);
    const VX Qx = A.transpose() * s;
    VU Qu = B.transpose() * s;
    Qu += w * (rho * U.col(k) + Lam.col(k) - rho * Y.col(k));
    const MX Qxx = A.transpose().lazyProduct(SA);
    MU Quu = B.transpose().lazyProduct(SB);
    Quu.diagonal().array() += w * rho;
    const MUX Qux = B.transpose().lazyProduct(SA);
    MU Qr = Quu;
    Qr.diagonal().array() += reg;
    Eigen::Matrix<double, NU, NX + 1> R;  // [Qux Qu], then minus the solutions
    R.template leftCols<NX>() = Qux;
    R.col(NX) = Qu;
    if (!small_cholesky_solve<NU>(Qr, R)) return false;
    Eigen::Map<MUX> K(Kv[k].data());
    K = -R.template leftCols<NX>();
    const VU d = -R.col(NX);
    dM.col(k) = d;
    const VU Quud = Quu * d;
    dv1 += d.dot(Qu);
    dv2 += 0.5 * d.dot(Quud);
    s = Qx + K.transpose() * (Quud + Qu) + Qux.transpose() * d;
    const MUX T = Quu * K + Qux;
    MX Sn = Qxx;
    Sn.noalias() += K.transpose().lazyProduct(T);
    Sn.noalias() += Qux.transpose().lazyProduct(K);
    S = 0.5 * (Sn + Sn.transpose());
    if (!s.allFinite() || !S.allFinite()) return false;
  }
  return true;
}

// Riccati sweep for a model with exogenous states t (df_t/dx_c = 0, df_t/du = 0), split from the
// others c. The value function's t-t block enters neither the gains nor the c-blocks, so only
// S_cc, S_ct and s_c are carried: about a third of the work of the full NX = NC + NT sweep, same
// gains (to rounding). ci / ti are the state indices of c and t.
template <int NC, int NT, int NU>
bool backward_reduced(int N, const int* ci, const int* ti, const std::vector<MatrixXd>& Av,
                      const std::vector<MatrixXd>& Bv, std::vector<MatrixXd>& Kv, MatrixXd& dM,
                      const MatrixXd& Qf, const VectorXd& eN, const MatrixXd& U, const MatrixXd& Lam,
                      const MatrixXd& Y, double w, double rho, double reg, double& dv1, double& dv2) {
  using MCC = Eigen::Matrix<double, NC, NC>;
  using MCT = Eigen::Matrix<double, NC, NT>;
  using MTT = Eigen::Matrix<double, NT, NT>;
  using MCU = Eigen::Matrix<double, NC, NU>;
  using MUC = Eigen::Matrix<double, NU, NC>;
  using MUT = Eigen::Matrix<double, NU, NT>;
  using MU = Eigen::Matrix<double, NU, NU>;
  using VC = Eigen::Matrix<double, NC, 1>;
  using VU = Eigen::Matrix<double, NU, 1>;
  constexpr int NR = NC + NT + 1;  // right-hand sides of the Quu solve: Qux_c, Qux_t, Qu
  MCC Scc;
  MCT Sct;
  VC sc;
  for (int i = 0; i < NC; ++i) {
    double v = 0.0;
    for (int j = 0; j < NC + NT; ++j) v += Qf(ci[i], j) * eN(j);
    sc(i) = v;
    for (int j = 0; j < NC; ++j) Scc(i, j) = Qf(ci[i], ci[j]);
    for (int j = 0; j < NT; ++j) Sct(i, j) = Qf(ci[i], ti[j]);
  }
  MCC Acc;
  MCT Act;
  MTT Att;
  MCU Bc;
  dv1 = 0.0;
  dv2 = 0.0;
  for (int k = N - 1; k >= 0; --k) {
    const MatrixXd& A = Av[k];
    const MatrixXd& B = Bv[k];
    for (int j = 0; j < NC; ++j)
      for (int i = 0; i < NC; ++i) Acc(i, j) = A(ci[i], ci[j]);
    for (int j = 0; j < NT; ++j) {
      for (int i = 0; i < NC; ++i) Act(i, j) = A(ci[i], ti[j]);
      for (int i = 0; i < NT; ++i) Att(i, j) = A(ti[i], ti[j]);
    }
    for (int j = 0; j < NU; ++j)
      for (int i = 0; i < NC; ++i) Bc(i, j) = B(ci[i], j);
    // c-rows of S A: (S A)_cc = S_cc A_cc, (S A)_ct = S_cc A_ct + S_ct A_tt
    const MCC Pc = Scc.lazyProduct(Acc);
    MCT Pt = Scc.lazyProduct(Act);
    Pt.noalias() += Sct.lazyProduct(Att);
    const MCU SBc = Scc.lazyProduct(Bc);
    MU Quu = Bc.transpose().lazyProduct(SBc);
    Quu.diagonal().array() += w * rho;
    Eigen::Matrix<double, NU, NR> R;  // [Qux_c Qux_t Qu], then minus the solutions
    R.template leftCols<NC>().noalias() = Bc.transpose().lazyProduct(Pc);
    R.template middleCols<NT>(NC).noalias() = Bc.transpose().lazyProduct(Pt);
    VU Qu = Bc.transpose() * sc;
    Qu += w * (rho * U.col(k) + Lam.col(k) - rho * Y.col(k));
    R.col(NC + NT) = Qu;
    const MUC Quxc = R.template leftCols<NC>();
    const MUT Quxt = R.template middleCols<NT>(NC);
    MU L = Quu;
    L.diagonal().array() += reg;
    if (!small_cholesky_solve<NU>(L, R)) return false;
    const MUC Kc = -R.template leftCols<NC>();
    const MUT Kt = -R.template middleCols<NT>(NC);
    const VU d = -R.col(NC + NT);
    MatrixXd& K = Kv[k];
    for (int i = 0; i < NC; ++i) K.col(ci[i]) = Kc.col(i);
    for (int i = 0; i < NT; ++i) K.col(ti[i]) = Kt.col(i);
    dM.col(k) = d;
    const VU Quud = Quu * d;
    dv1 += d.dot(Qu);
    dv2 += 0.5 * d.dot(Quud);
    // s_c = Qx_c + K_c^T (Quu d + Qu) + Qux_c^T d, Qx_c = A_cc^T s_c (A_tc = 0)
    VC sn = Acc.transpose() * sc;
    sn.noalias() += Kc.transpose() * (Quud + Qu);
    sn.noalias() += Quxc.transpose() * d;
    sc = sn;
    // S_c. = Qxx_c. + K_c^T (Quu K + Qux) + Qux_c^T K, Qxx_c. = A_cc^T (S A)_c.
    MUC Tc = Quxc;
    Tc.noalias() += Quu * Kc;
    MUT Tt = Quxt;
    Tt.noalias() += Quu * Kt;
    MCC Sn = Acc.transpose().lazyProduct(Pc);
    Sn.noalias() += Kc.transpose().lazyProduct(Tc);
    Sn.noalias() += Quxc.transpose().lazyProduct(Kc);
    Scc = 0.5 * (Sn + Sn.transpose());
    Sct.noalias() = Acc.transpose().lazyProduct(Pt);
    Sct.noalias() += Kc.transpose().lazyProduct(Tt);
    Sct.noalias() += Quxc.transpose().lazyProduct(Kt);
    if (!sc.allFinite() || !Scc.allFinite() || !Sct.allFinite()) return false;
  }
  return true;
}

}  // namespace

void IlqrAdmmSettings::validate() const {
  core::require_positive(rho, "rho");
  require(max_iter >= 1, "max_iter", "must be >= 1");
  require(ilqr_iters >= 1, "ilqr_iters", "must be >= 1");
  core::require_nonnegative(ilqr_tol, "ilqr_tol");
  core::require_nonnegative(eps_paper, "eps_paper");
  core::require_nonnegative(eps_abs, "eps_abs");
  core::require_nonnegative(eps_rel, "eps_rel");
  require(rho_factor > 1.0 && std::isfinite(rho_factor), "rho_factor", "must be finite and > 1");
  require(rho_balance > 1.0 && std::isfinite(rho_balance), "rho_balance", "must be finite and > 1");
  require(rho_update_every >= 1, "rho_update_every", "must be >= 1");
  core::require_nonnegative(reg_init, "reg_init");
  core::require_positive(reg_min, "reg_min");
  require(reg_max >= reg_min && std::isfinite(reg_max), "reg_max", "must be finite and >= reg_min");
  require(reg_factor > 1.0 && std::isfinite(reg_factor), "reg_factor", "must be finite and > 1");
  require(line_search_iters >= 1, "line_search_iters", "must be >= 1");
  require(ls_lower >= 0.0 && ls_upper > ls_lower, "ls_lower/ls_upper", "need 0 <= ls_lower < ls_upper");
  core::require_nonnegative(time_limit, "time_limit");
  require(inaccurate_factor >= 1.0 && std::isfinite(inaccurate_factor), "inaccurate_factor",
          "must be finite and >= 1");
}

IlqrAdmmSolver::~IlqrAdmmSolver() = default;
IlqrAdmmSolver::IlqrAdmmSolver(IlqrAdmmSolver&&) noexcept = default;

IlqrAdmmSolver::IlqrAdmmSolver(const DiscreteModel& model, const NonlinearL1Problem& problem,
                               const IlqrAdmmSettings& settings)
    : model_(model), prob_(problem), set_(settings), ws_(std::make_unique<detail::IlqrAdmmWorkspace>()) {
  set_.validate();
  nx_ = model.state_dim();
  nu_ = model.control_dim();
  N_ = prob_.horizon;
  require(nx_ >= 1 && nu_ >= 1, "model", "state and control dimensions must be >= 1");
  require(N_ >= 1, "horizon", "must be >= 1");
  require(!prob_.terminal_equality, "terminal_equality",
          "not supported by IlqrAdmmSolver (its iLQR step has no terminal constraint)",
          "use ScpSolver with inner_solver = linear_admm, or a large Qf for a soft terminal state");
  const std::string nxs = std::to_string(nx_), nus = std::to_string(nu_);
  require(prob_.x0.size() == nx_, "x0",
          "must have nx = " + nxs + " entries, got " + std::to_string(prob_.x0.size()));
  core::require_finite(prob_.x0, "x0");
  if (prob_.x_target.size() == 0) prob_.x_target = VectorXd::Zero(nx_);
  require(prob_.x_target.size() == nx_, "x_target", "must have nx = " + nxs + " entries");
  core::require_finite(prob_.x_target, "x_target");
  require(prob_.Qf.rows() == nx_ && prob_.Qf.cols() == nx_, "Qf", "must be nx x nx = " + nxs + " x " + nxs);
  core::require_finite(prob_.Qf, "Qf");
  require((prob_.Qf - prob_.Qf.transpose()).cwiseAbs().maxCoeff() <=
              1e-12 * (1.0 + prob_.Qf.cwiseAbs().maxCoeff()),
          "Qf", "must be symmetric");
  require(prob_.alpha.size() == nu_, "alpha", "must have nu = " + nus + " entries");
  core::require_finite(prob_.alpha, "alpha");
  require((prob_.alpha.array() >= 0.0).all(), "alpha", "weights must be >= 0");
  core::require_positive(prob_.stage_weight, "stage_weight");
  if (prob_.cost == ControlCost::l1_box) {
    require(prob_.u_min.size() == nu_ && prob_.u_max.size() == nu_, "u_min/u_max",
            "must have nu = " + nus + " entries");
    require(!prob_.u_min.hasNaN() && !prob_.u_max.hasNaN(), "u_min/u_max", "must not be NaN");
    require((prob_.u_min.array() <= prob_.u_max.array()).all(), "u_min/u_max", "need u_min <= u_max");
    require((prob_.u_min.array() <= 0.0).all() && (prob_.u_max.array() >= 0.0).all(), "u_min/u_max",
            "the box must contain u = 0 (u_min <= 0 <= u_max)");
  }
  rho_ = set_.rho;
  {
    std::vector<int> exo = model.exogenous_states();
    std::vector<bool> is_exo(nx_, false);
    for (size_t i = 0; i < exo.size(); ++i) {
      require(exo[i] >= 0 && exo[i] < nx_ && (i == 0 || exo[i] > exo[i - 1]), "model.exogenous_states",
              "indices must be ascending and in [0, nx)");
      is_exo[exo[i]] = true;
    }
    n_exo_ = static_cast<int>(exo.size());
    exo_idx_ = exo;
    endo_idx_.clear();
    for (int i = 0; i < nx_; ++i)
      if (!is_exo[i]) endo_idx_.push_back(i);
  }

  res_.X = MatrixXd::Zero(nx_, N_ + 1);
  res_.U = MatrixXd::Zero(nu_, N_);
  res_.Y = MatrixXd::Zero(nu_, N_);
  res_.Lambda = MatrixXd::Zero(nu_, N_);
  ws_->A_.assign(N_, MatrixXd::Zero(nx_, nx_));
  ws_->B_.assign(N_, MatrixXd::Zero(nx_, nu_));
  ws_->K_.assign(N_, MatrixXd::Zero(nu_, nx_));
  ws_->d_ = MatrixXd::Zero(nu_, N_);
  ws_->Xn_ = MatrixXd::Zero(nx_, N_ + 1);
  ws_->Xtmp_ = ws_->Xn_;
  ws_->Xbest_ = ws_->Xn_;
  ws_->Un_ = MatrixXd::Zero(nu_, N_);
  ws_->Yprev_ = ws_->Un_;
  ws_->Ubest_ = ws_->Un_;
  ws_->Ybest_ = ws_->Un_;
  ws_->Lbest_ = ws_->Un_;
  ws_->V_ = ws_->Un_;
  Slo_ = ws_->Un_;
  Shi_ = ws_->Un_;
  ws_->S_ = MatrixXd::Zero(nx_, nx_);
  ws_->Qxx_ = ws_->S_;
  ws_->SA_ = ws_->S_;
  ws_->SB_ = MatrixXd::Zero(nx_, nu_);
  ws_->Quu_ = MatrixXd::Zero(nu_, nu_);
  ws_->L_ = ws_->Quu_;
  ws_->Qux_ = MatrixXd::Zero(nu_, nx_);
  ws_->QuuK_ = ws_->Qux_;
  ws_->s_ = VectorXd::Zero(nx_);
  ws_->Qx_ = ws_->s_;
  ws_->dx_ = ws_->s_;
  ws_->tmpx_ = ws_->s_;
  ws_->Qu_ = VectorXd::Zero(nu_);
  ws_->tmpu_ = ws_->Qu_;
}

void IlqrAdmmSolver::set_initial_controls(const Eigen::Ref<const MatrixXd>& U0) {
  check_dims(U0, nu_, N_, "U0");
  check_finite(U0, "U0");
  res_.U = U0;
  res_.Y.setZero();
  res_.Lambda.setZero();
  warm_ = false;
}

void IlqrAdmmSolver::warm_start(const Eigen::Ref<const MatrixXd>& U, const Eigen::Ref<const MatrixXd>& Y,
                                const Eigen::Ref<const MatrixXd>& Lambda) {
  check_dims(U, nu_, N_, "U");
  check_dims(Y, nu_, N_, "Y");
  check_dims(Lambda, nu_, N_, "Lambda");
  check_finite(U, "U");
  check_finite(Y, "Y");
  check_finite(Lambda, "Lambda");
  res_.U = U;
  res_.Y = Y;
  res_.Lambda = Lambda;
  warm_ = true;
}

void IlqrAdmmSolver::set_initial_state(const Eigen::Ref<const VectorXd>& x0) {
  require(x0.size() == nx_, "x0", "must have nx = " + std::to_string(nx_) + " entries");
  core::require_finite(x0, "x0");
  prob_.x0 = x0;
}

void IlqrAdmmSolver::set_rho(double rho) {
  core::require_positive(rho, "rho");
  rho_ = rho;
}

void IlqrAdmmSolver::set_time_limit(double seconds) {
  if (!(std::isfinite(seconds) && seconds >= 0.0)) core::require_nonnegative(seconds, "time_limit");
  set_.time_limit = seconds;
}

bool IlqrAdmmSolver::out_of_time() const {
  return set_.time_limit > 0.0 &&
         std::chrono::duration<double>(std::chrono::steady_clock::now() - solve_start_).count() >=
             set_.time_limit;
}

void IlqrAdmmSolver::set_stage_bounds(const Eigen::Ref<const MatrixXd>& lo,
                                      const Eigen::Ref<const MatrixXd>& hi) {
  if (prob_.cost == ControlCost::group_l2)
    require(false, "set_stage_bounds",
            "not available for group_l2 (the prox of the norm plus a box has no closed form)");
  check_dims(lo, nu_, N_, "lo");
  check_dims(hi, nu_, N_, "hi");
  if (lo.hasNaN() || hi.hasNaN()) require(false, "lo/hi", "must not be NaN");
  if (!(lo.array() <= hi.array()).all()) require(false, "lo/hi", "need lo <= hi");
  Slo_ = lo;
  Shi_ = hi;
  stage_bounds_ = true;
}

int IlqrAdmmSolver::rollout(const Eigen::Ref<const MatrixXd>& U, Eigen::Ref<MatrixXd> Xout) const {
  Xout.col(0) = prob_.x0;
  for (int k = 0; k < N_; ++k) {
    if (!detail::model_step(model_, k, Xout.col(k).data(), U.col(k).data(), Xout.col(k + 1).data(), nullptr,
                            nullptr))
      return k;
  }
  return -1;
}

double IlqrAdmmSolver::terminal_cost(const Eigen::Ref<const VectorXd>& xN) const {
  return detail::half_weighted_error(prob_.Qf, xN, prob_.x_target);
}

double IlqrAdmmSolver::control_cost(const Eigen::Ref<const MatrixXd>& U) const {
  double c = 0.0;
  if (prob_.cost == ControlCost::group_l2) {
    for (int k = 0; k < N_; ++k) c += prob_.alpha(0) * U.col(k).norm();
  } else {
    for (int k = 0; k < N_; ++k)
      for (int i = 0; i < nu_; ++i) c += prob_.alpha(i) * std::abs(U(i, k));
  }
  return prob_.stage_weight * c;
}

double IlqrAdmmSolver::true_cost(const Eigen::Ref<const MatrixXd>& U) {
  if (rollout(U, ws_->Xtmp_) >= 0) return std::numeric_limits<double>::infinity();
  return terminal_cost(ws_->Xtmp_.col(N_)) + control_cost(U);
}

double IlqrAdmmSolver::subproblem_cost(const MatrixXd& X, const MatrixXd& U) const {
  double c = 0.0;
  for (int k = 0; k < N_; ++k)
    for (int i = 0; i < nu_; ++i) {
      const double u = U(i, k);
      c += 0.5 * rho_ * u * u + (res_.Lambda(i, k) - rho_ * res_.Y(i, k)) * u;
    }
  return terminal_cost(X.col(N_)) + prob_.stage_weight * c;
}

bool IlqrAdmmSolver::linearize() {
  if (jac_valid_) return true;
  for (int k = 0; k < N_; ++k) {
    if (!detail::model_step(model_, k, res_.X.col(k).data(), res_.U.col(k).data(),
                            ws_->Xtmp_.col(k + 1).data(), ws_->A_[k].data(), ws_->B_[k].data()))
      return false;
  }
  jac_valid_ = true;
  return true;
}

bool IlqrAdmmSolver::backward_pass(double reg, double& dv1, double& dv2) {
  const double w = prob_.stage_weight;
  if (nx_ == 12 && nu_ == 3 && n_exo_ == 6) {
    ws_->dx_ = res_.X.col(N_) - prob_.x_target;
    return backward_reduced<6, 6, 3>(N_, endo_idx_.data(), exo_idx_.data(), ws_->A_, ws_->B_, ws_->K_,
                                     ws_->d_, prob_.Qf, ws_->dx_, res_.U, res_.Lambda, res_.Y, w, rho_, reg,
                                     dv1, dv2);
  }
  if ((nx_ == 12 || nx_ == 6) && nu_ == 3) {
    ws_->dx_ = res_.X.col(N_) - prob_.x_target;
    if (nx_ == 12)
      return backward_fixed<12, 3>(N_, ws_->A_, ws_->B_, ws_->K_, ws_->d_, prob_.Qf, ws_->dx_, res_.U,
                                   res_.Lambda, res_.Y, w, rho_, reg, dv1, dv2);
    return backward_fixed<6, 3>(N_, ws_->A_, ws_->B_, ws_->K_, ws_->d_, prob_.Qf, ws_->dx_, res_.U,
                                res_.Lambda, res_.Y, w, rho_, reg, dv1, dv2);
  }
  ws_->S_ = prob_.Qf;
  ws_->s_.noalias() = prob_.Qf * (res_.X.col(N_) - prob_.x_target);
  dv1 = 0.0;
  dv2 = 0.0;
  for (int k = N_ - 1; k >= 0; --k) {
    const MatrixXd& A = ws_->A_[k];
    const MatrixXd& B = ws_->B_[k];
    ws_->SA_.noalias() = ws_->S_ * A;
    ws_->SB_.noalias() = ws_->S_ * B;
    ws_->Qx_.noalias() = A.transpose() * ws_->s_;
    ws_->Qu_.noalias() = B.transpose() * ws_->s_;
    for (int i = 0; i < nu_; ++i)
      ws_->Qu_(i) += w * (rho_ * res_.U(i, k) + res_.Lambda(i, k) - rho_ * res_.Y(i, k));
    ws_->Qxx_.noalias() = A.transpose() * ws_->SA_;
    ws_->Quu_.noalias() = B.transpose() * ws_->SB_;
    ws_->Quu_.diagonal().array() += w * rho_;
    ws_->Qux_.noalias() = B.transpose() * ws_->SA_;
    ws_->L_ = ws_->Quu_;
    ws_->L_.diagonal().array() += reg;
    if (!detail::cholesky_factor_inplace<Eigen::Dynamic>(ws_->L_)) return false;
    MatrixXd& K = ws_->K_[k];
    K = -ws_->Qux_;
    detail::cholesky_solve_inplace<Eigen::Dynamic>(ws_->L_, K);
    auto d = ws_->d_.col(k);
    d = -ws_->Qu_;
    detail::cholesky_solve_inplace<Eigen::Dynamic>(ws_->L_, d);
    ws_->tmpu_.noalias() = ws_->Quu_ * d;
    dv1 += d.dot(ws_->Qu_);
    dv2 += 0.5 * d.dot(ws_->tmpu_);
    // s = Qx + K^T (Quu d + Qu) + Qux^T d
    ws_->tmpu_ += ws_->Qu_;
    ws_->s_ = ws_->Qx_;
    ws_->s_.noalias() += K.transpose() * ws_->tmpu_;
    ws_->s_.noalias() += ws_->Qux_.transpose() * d;
    // S = Qxx + K^T Quu K + K^T Qux + Qux^T K
    ws_->QuuK_.noalias() = ws_->Quu_ * K;
    ws_->S_ = ws_->Qxx_;
    ws_->S_.noalias() += K.transpose() * ws_->QuuK_;
    ws_->S_.noalias() += K.transpose() * ws_->Qux_;
    ws_->S_.noalias() += ws_->Qux_.transpose() * K;
    // symmetrize
    for (int i = 0; i < nx_; ++i)
      for (int j = i + 1; j < nx_; ++j) {
        const double v = 0.5 * (ws_->S_(i, j) + ws_->S_(j, i));
        ws_->S_(i, j) = v;
        ws_->S_(j, i) = v;
      }
    if (!ws_->s_.allFinite() || !ws_->S_.allFinite()) return false;
  }
  return true;
}

bool IlqrAdmmSolver::forward_pass(double dv1, double dv2, double& J) {
  double a = 1.0;
  for (int ls = 0; ls < set_.line_search_iters; ++ls, a *= 0.5) {
    ws_->Xn_.col(0) = prob_.x0;
    bool ok = true;
    // The full step is usually accepted: linearize along it on the way (the gains K_k are already
    // computed, so A_k, B_k may be overwritten; they are recomputed if this step is rejected).
    const bool with_jac = ls == 0;
    jac_valid_ = false;
    for (int k = 0; k < N_ && ok; ++k) {
      ws_->dx_ = ws_->Xn_.col(k) - res_.X.col(k);
      ws_->Un_.col(k) = res_.U.col(k) + a * ws_->d_.col(k);
      ws_->Un_.col(k).noalias() += ws_->K_[k] * ws_->dx_;
      ok = detail::model_step(model_, k, ws_->Xn_.col(k).data(), ws_->Un_.col(k).data(),
                              ws_->Xn_.col(k + 1).data(), with_jac ? ws_->A_[k].data() : nullptr,
                              with_jac ? ws_->B_[k].data() : nullptr);
    }
    if (!ok) continue;
    const double Jn = subproblem_cost(ws_->Xn_, ws_->Un_);
    if (!std::isfinite(Jn)) continue;
    const double expected = -a * (dv1 + a * dv2);
    bool accept;
    if (expected > 0.0) {
      const double z = (J - Jn) / expected;
      accept = z >= set_.ls_lower && z <= set_.ls_upper;
    } else {
      accept = Jn <= J;  // no predicted decrease: accept only a non-increase
    }
    if (accept) {
      jac_valid_ = with_jac;
      res_.X.swap(ws_->Xn_);
      res_.U.swap(ws_->Un_);
      J = Jn;
      return true;
    }
  }
  return false;
}

int IlqrAdmmSolver::ilqr_step(double& J) {
  double reg = reg_;
  while (true) {
    if (!linearize()) return 2;
    double dv1 = 0.0, dv2 = 0.0;
    bool ok = backward_pass(reg, dv1, dv2);
    if (ok) {
      // Converged subproblem: predicted decrease below rounding of J.
      if (-(dv1 + dv2) <= 1e-15 * (1.0 + std::abs(J))) {
        reg_ = reg;
        return 1;
      }
      if (forward_pass(dv1, dv2, J)) {
        res_.info.max_regularization = std::max(res_.info.max_regularization, reg);
        reg_ = reg / set_.reg_factor;
        if (reg_ < set_.reg_min) reg_ = set_.reg_init;
        return 0;
      }
    }
    // A tiny predicted decrease that the line search cannot realize is rounding: converged.
    if (ok && -(dv1 + dv2) <= 1e-10 * (1.0 + std::abs(J))) {
      reg_ = set_.reg_init;
      return 1;
    }
    reg = std::max(reg * set_.reg_factor, set_.reg_min);
    if (reg > set_.reg_max) return 2;
    if (out_of_time()) return 3;  // each retry costs an iLQR iteration
  }
}

void IlqrAdmmSolver::prox(const MatrixXd& V, MatrixXd& Yout) const {
  const double inv = 1.0 / rho_;
  if (prob_.cost == ControlCost::group_l2) {
    const double t = prob_.alpha(0) * inv;
    for (int k = 0; k < N_; ++k) {
      const double nrm = V.col(k).norm();
      const double f = nrm > t ? 1.0 - t / nrm : 0.0;
      Yout.col(k) = f * V.col(k);
    }
    return;
  }
  for (int k = 0; k < N_; ++k)
    for (int i = 0; i < nu_; ++i) {
      double y = soft(V(i, k), prob_.alpha(i) * inv);
      if (prob_.cost == ControlCost::l1_box) y = std::min(std::max(y, prob_.u_min(i)), prob_.u_max(i));
      // 1-D: the prox of |.| plus an interval is the prox of |.| clipped to it (exact).
      if (stage_bounds_) y = std::min(std::max(y, Slo_(i, k)), Shi_(i, k));
      Yout(i, k) = y;
    }
}

const IlqrAdmmResult& IlqrAdmmSolver::solve() noexcept {
  SATGNC_NO_MALLOC_SCOPE;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  solve_start_ = t0;
  IlqrAdmmInfo& info = res_.info;
  info = IlqrAdmmInfo();
  reg_ = set_.reg_init;
  jac_valid_ = false;
  const double w = prob_.stage_weight;
  const double sqrt_n = std::sqrt(static_cast<double>(N_ * nu_));
  const auto elapsed = [&t0]() { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  const int fail = rollout(res_.U, res_.X);
  if (fail >= 0) {
    info.status = IlqrAdmmStatus::propagation_failed;
    info.failed_interval = fail;
    info.rho = rho_;
    info.objective_u = info.objective_y = info.terminal_miss = std::numeric_limits<double>::infinity();
    info.solve_time = elapsed();
    return res_;
  }
  double best_primal = std::numeric_limits<double>::infinity(), best_dual = best_primal;
  IlqrAdmmStatus status = IlqrAdmmStatus::max_iterations;
  for (int it = 1; it <= set_.max_iter; ++it) {
    if (set_.time_limit > 0.0 && it > 1 && elapsed() >= set_.time_limit) {
      status = IlqrAdmmStatus::time_limit;
      break;
    }
    info.iterations = it;
    double J = subproblem_cost(res_.X, res_.U);
    bool failed = false;
    for (int j = 0; j < set_.ilqr_iters; ++j) {
      // out of time: the y- and multiplier steps below still run (cheap), the next iteration stops
      if (j > 0 && out_of_time()) break;
      const double J0 = J;
      const int r = ilqr_step(J);
      if (r == 2) {
        failed = true;
        break;
      }
      if (r == 1 || r == 3) break;
      ++info.ilqr_iterations;
      if (set_.ilqr_iters > 1 && (J0 - J) <= set_.ilqr_tol * (1.0 + std::abs(J0))) break;
    }
    if (failed) {
      status = IlqrAdmmStatus::ilqr_failed;
      break;
    }
    // y-step and multiplier step
    ws_->Yprev_ = res_.Y;
    ws_->V_ = res_.U + res_.Lambda / rho_;
    prox(ws_->V_, res_.Y);
    res_.Lambda += rho_ * (res_.U - res_.Y);
    if (it == 1 && set_.paper_multiplier_rescale) {
      for (int i = 0; i < nu_; ++i) {
        const double m = res_.Lambda.row(i).cwiseAbs().maxCoeff();
        if (m > 0.0) res_.Lambda.row(i) *= prob_.alpha(i) / m;
      }
    }
    const double primal = (res_.U - res_.Y).norm();
    const double dual = w * rho_ * (res_.Y - ws_->Yprev_).norm();
    info.primal_residual = primal;
    info.dual_residual = dual;
    info.paper_criterion = primal / (N_ * nu_);
    if (primal < best_primal) {
      best_primal = primal;
      best_dual = dual;
      ws_->Ubest_ = res_.U;
      ws_->Ybest_ = res_.Y;
      ws_->Lbest_ = res_.Lambda;
      ws_->Xbest_ = res_.X;
    }
    bool done;
    if (set_.stop == StopRule::paper) {
      done = info.paper_criterion <= set_.eps_paper;
    } else {
      const double eps_p = set_.eps_abs * sqrt_n + set_.eps_rel * std::max(res_.U.norm(), res_.Y.norm());
      const double eps_d = set_.eps_abs * sqrt_n + set_.eps_rel * w * res_.Lambda.norm();
      done = primal <= eps_p && dual <= eps_d && it > 1;
      if (!done && set_.adaptive_rho && it % set_.rho_update_every == 0) {
        const double rp = primal / std::max(eps_p, 1e-300), rd = dual / std::max(eps_d, 1e-300);
        if (rp > set_.rho_balance * rd) {
          rho_ *= set_.rho_factor;
          ++info.rho_updates;
        } else if (rd > set_.rho_balance * rp) {
          rho_ /= set_.rho_factor;
          ++info.rho_updates;
        }
      }
    }
    if (done) {
      status = IlqrAdmmStatus::solved;
      break;
    }
  }
  // Without success the best iterate (smallest ||U - Y||) is returned, whichever limit stopped it.
  if (status != IlqrAdmmStatus::solved && set_.return_best && std::isfinite(best_primal)) {
    res_.U.swap(ws_->Ubest_);
    res_.Y.swap(ws_->Ybest_);
    res_.Lambda.swap(ws_->Lbest_);
    res_.X.swap(ws_->Xbest_);
    info.primal_residual = best_primal;
    info.dual_residual = best_dual;
    info.paper_criterion = best_primal / (N_ * nu_);
  }
  if ((status == IlqrAdmmStatus::max_iterations || status == IlqrAdmmStatus::time_limit) &&
      set_.stop == StopRule::residuals && info.iterations > 1) {
    const double f = set_.inaccurate_factor;
    const double eps_p = f * (set_.eps_abs * sqrt_n + set_.eps_rel * std::max(res_.U.norm(), res_.Y.norm()));
    const double eps_d = f * (set_.eps_abs * sqrt_n + set_.eps_rel * w * res_.Lambda.norm());
    if (info.primal_residual <= eps_p && info.dual_residual <= eps_d)
      status = IlqrAdmmStatus::solved_inaccurate;
  }
  info.rho = rho_;
  info.lqr_passes = info.ilqr_iterations + info.iterations;
  info.objective_u = true_cost(res_.U);
  const int fail_y = rollout(res_.Y, ws_->Xtmp_);
  if (fail_y >= 0) {
    info.objective_y = info.terminal_miss = std::numeric_limits<double>::infinity();
    // "solved" promises a plan that flies on the model.
    if (status == IlqrAdmmStatus::solved || status == IlqrAdmmStatus::solved_inaccurate) {
      status = IlqrAdmmStatus::propagation_failed;
      info.failed_interval = fail_y;
    }
  } else {
    info.objective_y = terminal_cost(ws_->Xtmp_.col(N_)) + control_cost(res_.Y);
    info.terminal_miss = (ws_->Xtmp_.col(N_) - prob_.x_target).norm();
  }
  info.status = status;
  info.solve_time = elapsed();
  return res_;
}

}  // namespace satgnc::guidance
