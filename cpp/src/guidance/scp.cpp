#include "satgnc/guidance/scp.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>

#include "detail/quadratic.hpp"
#include "detail/scp_inner.hpp"
#include "detail/scp_workspace.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::guidance {

using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

// What the outer loop may conclude from the inner solver's status.
enum class Inner {
  solved,         // optimality test of the subproblem met
  inaccurate,     // a usable point, loose tolerances (or a rule that is not a convergence test)
  not_converged,  // stopped at a limit: a usable point, no claim
  infeasible,     // the linearized constraints cannot hold
  failed,         // no usable point
};

// No default: a new enumerator is a compiler warning (-Wswitch) until it is mapped here.
Inner classify(AdmmStatus s) {
  switch (s) {
    case AdmmStatus::solved:
      return Inner::solved;
    case AdmmStatus::solved_paper_rule:  // ||U - Y|| small is not an optimality test
    case AdmmStatus::solved_inaccurate:
      return Inner::inaccurate;
    case AdmmStatus::max_iterations:
    case AdmmStatus::time_limit:
      return Inner::not_converged;
    case AdmmStatus::terminal_unreachable:
    case AdmmStatus::primal_infeasible:
      return Inner::infeasible;
    case AdmmStatus::numerical_error:
    case AdmmStatus::unsolved:
      return Inner::failed;
  }
  return Inner::failed;
}

Inner classify(IlqrAdmmStatus s, StopRule rule) {
  switch (s) {
    case IlqrAdmmStatus::solved:
      return rule == StopRule::residuals ? Inner::solved : Inner::inaccurate;
    case IlqrAdmmStatus::solved_inaccurate:
      return Inner::inaccurate;
    case IlqrAdmmStatus::max_iterations:
    case IlqrAdmmStatus::time_limit:
      return Inner::not_converged;
    case IlqrAdmmStatus::propagation_failed:
    case IlqrAdmmStatus::ilqr_failed:
    case IlqrAdmmStatus::unsolved:
      return Inner::failed;
  }
  return Inner::failed;
}

}  // namespace

void ScpSettings::validate() const {
  core::require(max_outer >= 1, "max_outer", "must be >= 1");
  core::require_nonnegative(tol, "tol");
  core::require(armijo >= 0.0 && armijo < 1.0, "armijo", "must be in [0, 1)");
  core::require(line_search_iters >= 1, "line_search_iters", "must be >= 1");
  core::require_nonnegative(trust_radius, "trust_radius");
  core::require(tr_accept > 0.0 && tr_accept < 1.0, "tr_accept", "must be in (0, 1)");
  core::require(tr_grow_ratio >= tr_accept && tr_grow_ratio < 1.0, "tr_grow_ratio",
                "must be in [tr_accept, 1)");
  core::require(tr_shrink > 0.0 && tr_shrink < 1.0, "tr_shrink", "must be in (0, 1)");
  core::require(tr_grow > 1.0 && std::isfinite(tr_grow), "tr_grow", "must be finite and > 1");
  core::require_nonnegative(tr_min, "tr_min");
  core::require(std::isfinite(tol_inaccurate) && tol_inaccurate >= tol, "tol_inaccurate",
                "must be finite and >= tol");
  core::require_nonnegative(time_limit, "time_limit");
  core::require(std::isfinite(terminal_tol) && terminal_tol > 0.0, "terminal_tol", "must be finite and > 0");
  core::require(std::isfinite(terminal_tol_inaccurate) && terminal_tol_inaccurate >= terminal_tol,
                "terminal_tol_inaccurate", "must be finite and >= terminal_tol");
  core::require(
      globalization == ScpGlobalization::trust_region || globalization == ScpGlobalization::line_search,
      "globalization", "must be trust_region or line_search");
  core::require(inner_solver == ScpInner::ilqr_admm || inner_solver == ScpInner::linear_admm, "inner_solver",
                "must be ilqr_admm or linear_admm");
  inner.validate();
}

namespace {
// The problem without its hard terminal state (what IlqrAdmmSolver accepts: validation, the inner).
NonlinearL1Problem soft_copy(const NonlinearL1Problem& p) {
  NonlinearL1Problem q = p;
  q.terminal_equality = false;
  return q;
}
}  // namespace

ScpSolver::~ScpSolver() = default;

ScpSolver::ScpSolver(const DiscreteModel& model, const NonlinearL1Problem& problem,
                     const ScpSettings& settings)
    : model_(model),
      prob_(problem),
      set_(settings),
      checker_(model, soft_copy(problem)),
      ws_(std::make_unique<detail::ScpWorkspace>()) {
  set_.validate();
  set_.inner_ilqr.validate();
  hard_ = problem.terminal_equality;
  core::require(
      !(hard_ && set_.inner_solver == ScpInner::ilqr_admm), "terminal_equality",
      "needs ScpSettings::inner_solver = linear_admm (the ilqr_admm inner has no terminal constraint)",
      "use the default inner solver");
  prob_ = checker_.problem();  // validated, x_target filled
  prob_.terminal_equality = hard_;
  nx_ = model.state_dim();
  nu_ = model.control_dim();
  N_ = prob_.horizon;
  res_.X = MatrixXd::Zero(nx_, N_ + 1);
  res_.U = MatrixXd::Zero(nu_, N_);
  res_.Lambda = MatrixXd::Zero(nu_, N_);
  res_.info.merit_history.reserve(static_cast<size_t>(set_.max_outer) + 1);
  res_.info.infeasibility_certificate = VectorXd::Zero(nx_);
  is_exo_.assign(nx_, 0);
  for (int i : model.exogenous_states()) is_exo_[i] = 1;  // validated by checker_
  has_exo_ = std::find(is_exo_.begin(), is_exo_.end(), 1) != is_exo_.end();
  for (int i = 0; i < nx_; ++i)
    if (!is_exo_[i]) endo_.push_back(i);
  reduced_ = hard_ && has_exo_;
  const int nxi = reduced_ ? static_cast<int>(endo_.size()) : nx_;  // the inner's state dimension
  ws_->lam_ = VectorXd::Zero(nxi);
  ws_->lam2_ = ws_->lam_;
  ws_->su_ = VectorXd::Zero(nu_);
  ws_->Ytmp_ = res_.U;
  ws_->Utmp_ = res_.U;
  ws_->Xtmp_ = res_.X;
  ws_->Xlin_ = res_.X;
  ws_->Ywarm_ = res_.U;
  ws_->Lwarm_ = res_.U;
  ws_->Tlo_ = res_.U;
  ws_->Thi_ = res_.U;
  ws_->Ucand_ = res_.U;
  lo_ = VectorXd::Constant(nu_, -std::numeric_limits<double>::infinity());
  hi_ = VectorXd::Constant(nu_, std::numeric_limits<double>::infinity());
  if (prob_.cost == ControlCost::l1_box) {
    lo_ = prob_.u_min;
    hi_ = prob_.u_max;
  }
  sub_.dynamics.horizon = N_;
  sub_.dynamics.A.assign(N_, MatrixXd::Zero(nx_, nx_));
  sub_.dynamics.B.assign(N_, MatrixXd::Zero(nx_, nu_));
  sub_.dynamics.c.assign(N_, VectorXd::Zero(nx_));
  sub_.x0 = prob_.x0;
  sub_.xf = prob_.x_target;
  sub_.Qf = prob_.Qf;
  sub_.terminal_equality = hard_;
  {
    std::vector<MatrixXd> A(N_, MatrixXd::Identity(nx_, nx_)), B(N_, MatrixXd::Zero(nx_, nu_));
    std::vector<VectorXd> c(N_, VectorXd::Zero(nx_));
    lin_ = std::make_unique<LinearDiscreteModel>(A, B, c);
    inner_ = std::make_unique<IlqrAdmmSolver>(*lin_, soft_copy(prob_), set_.inner_ilqr);
  }
  const double w = prob_.stage_weight;
  if (prob_.cost == ControlCost::group_l2) {
    sub_.group_l2_weight = w * prob_.alpha(0);
  } else {
    sub_.l1_weights = w * prob_.alpha;
    if (prob_.cost == ControlCost::l1_box) {
      sub_.u_lower = prob_.u_min;
      sub_.u_upper = prob_.u_max;
    }
  }
  if (reduced_) {
    // x_N = x_f on the non-exogenous states c only: x_c' = A_cc x_c + B_c u + (c_c + A_ct x_t), with
    // the exogenous trajectory x_t fixed by the rollout (full rank terminal constraint; Qf_cc only,
    // the rest of 1/2 e'Qf e is constant once e_c = 0)
    const int nc = static_cast<int>(endo_.size());
    red_ = sub_;
    red_.dynamics.A.assign(N_, MatrixXd::Identity(nc, nc));
    red_.dynamics.B.assign(N_, MatrixXd::Zero(nc, nu_));
    red_.dynamics.c.assign(N_, VectorXd::Zero(nc));
    red_.x0.resize(nc);
    red_.xf.resize(nc);
    red_.Qf.resize(nc, nc);
    for (int i = 0; i < nc; ++i) {
      red_.x0(i) = prob_.x0(endo_[i]);
      red_.xf(i) = prob_.x_target(endo_[i]);
      for (int j = 0; j < nc; ++j) red_.Qf(i, j) = prob_.Qf(endo_[i], endo_[j]);
    }
  }
  if (set_.inner_solver == ScpInner::linear_admm)
    admm_ = std::make_unique<AdmmSolver>(reduced_ ? red_ : sub_, set_.inner);
  const bool boxed = (lo_.array() > -std::numeric_limits<double>::infinity()).any() ||
                     (hi_.array() < std::numeric_limits<double>::infinity()).any();
  if (hard_ && admm_ && boxed) {
    // restoration subproblem: the same linearization and box, no fuel cost, 1/2 ||e_c||^2
    LtvProblem el = reduced_ ? red_ : sub_;
    el.terminal_equality = false;
    el.l1_weights.resize(0);
    el.group_l2_weight = 0.0;
    const int nel = static_cast<int>(el.x0.size());
    el.Qf = MatrixXd::Identity(nel, nel);
    if (!reduced_)
      for (int i = 0; i < nx_; ++i)
        if (is_exo_[i]) el.Qf(i, i) = 0.0;
    elastic_ = std::make_unique<AdmmSolver>(el, set_.inner);
  }
  ws_->Zu_ = MatrixXd::Zero(nu_, N_);
}

void ScpSolver::set_initial_controls(const Eigen::Ref<const MatrixXd>& U0) {
  core::require(U0.rows() == nu_ && U0.cols() == N_, "U0",
                "must be nu x N = " + std::to_string(nu_) + " x " + std::to_string(N_));
  core::require_finite(U0, "U0");
  if (prob_.cost == ControlCost::l1_box) {
    bool inside = true;
    for (int k = 0; k < N_; ++k)
      inside = inside && (U0.col(k).array() >= lo_.array()).all() && (U0.col(k).array() <= hi_.array()).all();
    core::require(inside, "U0", "must lie inside the bounds u_min <= u <= u_max");
  }
  res_.U = U0;
  ws_->Ywarm_.setZero();
  ws_->Lwarm_.setZero();
}

void ScpSolver::set_initial_state(const Eigen::Ref<const VectorXd>& x0) {
  core::require(x0.size() == nx_, "x0", "must have nx = " + std::to_string(nx_) + " entries");
  core::require_finite(x0, "x0");
  prob_.x0 = x0;
  sub_.x0 = x0;
  if (reduced_) {
    for (size_t i = 0; i < endo_.size(); ++i) red_.x0(static_cast<Eigen::Index>(i)) = x0(endo_[i]);
    if (admm_) admm_->set_x0(red_.x0);
  }
  if (elastic_) elastic_->set_x0(reduced_ ? red_.x0 : sub_.x0);
  inner_->set_initial_state(x0);
  if (admm_ && !reduced_) admm_->set_x0(x0);
}

int ScpSolver::rollout(const MatrixXd& U, MatrixXd& X) const {
  X.col(0) = prob_.x0;
  for (int k = 0; k < N_; ++k)
    if (!model_.step(k, X.col(k).data(), U.col(k).data(), X.col(k + 1).data(), nullptr, nullptr)) return k;
  return -1;
}

double ScpSolver::control_cost(const MatrixXd& U) const {
  double c = 0.0;
  for (int k = 0; k < N_; ++k) {
    if (prob_.cost == ControlCost::group_l2)
      c += prob_.alpha(0) * U.col(k).norm();
    else
      c += prob_.alpha.dot(U.col(k).cwiseAbs());
  }
  return prob_.stage_weight * c;
}

double ScpSolver::terminal_cost(const Eigen::Ref<const VectorXd>& xN) const {
  return detail::half_weighted_error(prob_.Qf, xN, prob_.x_target);
}

double ScpSolver::constraint_miss(const Eigen::Ref<const VectorXd>& xN) const {
  double s = 0.0;
  for (int i = 0; i < nx_; ++i)
    if (!is_exo_[i]) s += (xN(i) - prob_.x_target(i)) * (xN(i) - prob_.x_target(i));
  return std::sqrt(s);
}

double ScpSolver::true_cost(const MatrixXd& U, MatrixXd& X) const {
  // the merit: the true cost, plus mu ||e_c|| with a hard terminal state (mu_ = 0 otherwise)
  if (rollout(U, X) >= 0) return std::numeric_limits<double>::infinity();
  const double J = terminal_cost(X.col(N_)) + control_cost(U);
  return mu_ > 0.0 ? J + mu_ * constraint_miss(X.col(N_)) : J;
}

void ScpSolver::reduce_linearization() {
  const int nc = static_cast<int>(endo_.size());
  for (int k = 0; k < N_; ++k) {
    const MatrixXd& A = sub_.dynamics.A[k];
    for (int i = 0; i < nc; ++i) {
      double ci = sub_.dynamics.c[k](endo_[i]);
      for (int j = 0; j < nx_; ++j) {
        if (is_exo_[j]) ci += A(endo_[i], j) * res_.X(j, k);
      }
      red_.dynamics.c[k](i) = ci;
      for (int j = 0; j < nc; ++j) red_.dynamics.A[k](i, j) = A(endo_[i], endo_[j]);
      for (int j = 0; j < nu_; ++j) red_.dynamics.B[k](i, j) = sub_.dynamics.B[k](endo_[i], j);
    }
  }
}

double ScpSolver::infeasibility_margin(const VectorXd& y) {
  // y'(x_f - x_N(0)) - max_{lo <= U <= hi} y' M U on the inner's affine model (M_k' y =
  // B_k' Phi(N, k+1)' y), in the inner's states
  const LtvProblem& q = reduced_ ? red_ : sub_;
  double reach = 0.0;
  ws_->lam_ = y;
  for (int k = N_ - 1; k >= 0; --k) {
    ws_->su_.noalias() = q.dynamics.B[k].transpose() * ws_->lam_;
    for (int i = 0; i < nu_; ++i) {
      if (ws_->su_(i) == 0.0) continue;
      reach += ws_->su_(i) > 0.0 ? ws_->su_(i) * hi_(i) : ws_->su_(i) * lo_(i);  // +inf without that bound
    }
    ws_->lam2_.noalias() = q.dynamics.A[k].transpose() * ws_->lam_;
    ws_->lam_.swap(ws_->lam2_);
  }
  ws_->lam_ = q.x0;  // x_N(0)
  for (int k = 0; k < N_; ++k) {
    ws_->lam2_.noalias() = q.dynamics.A[k] * ws_->lam_;
    ws_->lam2_ += q.dynamics.c[k];
    ws_->lam_.swap(ws_->lam2_);
  }
  ws_->lam2_ = q.xf - ws_->lam_;
  return y.dot(ws_->lam2_) - reach;
}

double ScpSolver::model_cost(const MatrixXd& U) {
  ws_->Xlin_.col(0) = prob_.x0;
  for (int k = 0; k < N_; ++k) {
    ws_->Xlin_.col(k + 1).noalias() = sub_.dynamics.A[k] * ws_->Xlin_.col(k);
    ws_->Xlin_.col(k + 1).noalias() += sub_.dynamics.B[k] * U.col(k);
    ws_->Xlin_.col(k + 1) += sub_.dynamics.c[k];
  }
  const double J = terminal_cost(ws_->Xlin_.col(N_)) + control_cost(U);
  return mu_ > 0.0 ? J + mu_ * constraint_miss(ws_->Xlin_.col(N_)) : J;
}

int ScpSolver::restore(double& J, double time_left) {
  const LtvDynamics& d = reduced_ ? red_.dynamics : sub_.dynamics;
  if (!elastic_->update_dynamics(d.A, d.B, d.c)) return -1;
  elastic_->warm_start(res_.U, ws_->Zu_);
  if (time_left > 0.0) {
    const double own = set_.inner.time_limit;
    elastic_->set_time_limit(own > 0.0 ? std::min(own, time_left) : time_left);
  }
  const AdmmResult& r = elastic_->solve();
  res_.info.inner_iterations += r.info.iterations;
  if (time_left > 0.0 && r.info.status == AdmmStatus::time_limit) return -2;
  const Inner in = classify(r.info.status);
  if (in == Inner::failed || in == Inner::infeasible || !r.Y.allFinite()) return -1;
  // predicted / actual decrease of 1/2 ||e_c||^2 along U + t (Y - U); the model is exact at U
  const double miss = constraint_miss(res_.X.col(N_));
  const double m0 = 0.5 * miss * miss;
  ws_->Ucand_ = r.Y;
  const double mu = mu_;
  mu_ = 0.0;  // model_cost's rollout only
  model_cost(ws_->Ucand_);
  mu_ = mu;
  const double mlin = constraint_miss(ws_->Xlin_.col(N_));
  const double pred = m0 - 0.5 * mlin * mlin;
  // Stationary: the linearization predicts less than terminal_tol_inaccurate (1e-4) of 1/2 miss^2
  // (the restoration subproblem's minimizer set is flat; ADMM creeps along it by ~1e-6 per step)
  if (!(pred > set_.terminal_tol_inaccurate * m0)) return 0;
  double t = 1.0;
  for (int ls = 0; ls < set_.line_search_iters; ++ls, t *= 0.5) {
    ws_->Utmp_ = res_.U + t * (ws_->Ucand_ - res_.U);
    if (rollout(ws_->Utmp_, ws_->Xtmp_) >= 0) continue;
    const double mn = constraint_miss(ws_->Xtmp_.col(N_));
    if (m0 - 0.5 * mn * mn >= set_.armijo * t * pred && mn < miss) {
      res_.U.swap(ws_->Utmp_);
      res_.X.swap(ws_->Xtmp_);
      J = terminal_cost(res_.X.col(N_)) + control_cost(res_.U) + mu_ * mn;
      res_.info.last_step = t;
      return 1;
    }
  }
  return 2;
}

const ScpResult& ScpSolver::solve() noexcept {
  SATGNC_NO_MALLOC_SCOPE;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  ScpInfo& info = res_.info;
  {
    std::vector<double> h;  // keep the reserved capacity of the history (no allocation)
    VectorXd cert;
    h.swap(info.merit_history);
    cert.swap(info.infeasibility_certificate);
    info = ScpInfo();
    info.merit_history.swap(h);
    info.infeasibility_certificate.swap(cert);
    info.merit_history.clear();
    info.infeasibility_certificate.setZero();
  }
  mu_ = 0.0;
  ScpStatus st;
  try {
    st = solve_impl();
  } catch (const std::exception&) {
    st = ScpStatus::inner_failed;
  }
  info.status = st;
  // The returned iterate is the current one: every accepted step lowered the true cost.
  if (info.merit_history.empty()) {  // the initial guess does not roll out
    info.objective = info.terminal_miss = std::numeric_limits<double>::infinity();
  } else {
    // the merit's last entry is the true cost unless a penalty term was added
    info.objective =
        mu_ > 0.0 ? terminal_cost(res_.X.col(N_)) + control_cost(res_.U) : info.merit_history.back();
    info.terminal_miss = (res_.X.col(N_) - prob_.x_target).norm();
    info.terminal_constraint_miss = constraint_miss(res_.X.col(N_));
  }
  info.penalty = mu_;
  double viol = 0.0;
  for (int k = 0; k < N_; ++k)
    for (int i = 0; i < nu_; ++i)
      viol = std::max(viol, std::max(lo_(i) - res_.U(i, k), res_.U(i, k) - hi_(i)));
  info.bound_violation = viol;
  info.iterations = info.outer_iterations;  // core::InfoBase mirrors
  info.primal_residual = info.terminal_constraint_miss;
  info.dual_residual = info.predicted_decrease;
  info.solve_time = std::chrono::duration<double>(Clock::now() - t0).count();
  return res_;
}

ScpStatus ScpSolver::solve_impl() {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  ScpInfo& info = res_.info;
  const bool tr = set_.globalization == ScpGlobalization::trust_region;
  const bool ilqr = set_.inner_solver == ScpInner::ilqr_admm;
  const bool timed = set_.time_limit > 0.0;
  const auto elapsed = [&t0]() { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  // Exact box trust region inside the subproblem (prox of L1 + interval); otherwise the step is scaled.
  const bool box_tr = tr && ilqr && prob_.cost != ControlCost::group_l2;
  const int fail = rollout(res_.U, res_.X);
  if (fail >= 0) {
    info.failed_interval = fail;
    return ScpStatus::propagation_failed;
  }
  double J = terminal_cost(res_.X.col(N_)) + control_cost(res_.U);  // the merit (mu_ = 0 here)
  info.merit_history.push_back(J);
  // Hard terminal state: reference of the terminal tolerance (x0 itself, and the initial guess).
  double tref = 0.0;
  if (hard_) {
    tref = std::max(constraint_miss(prob_.x0), constraint_miss(res_.X.col(N_)));
    info.terminal_reference = tref;
  }
  const auto terminal_ok = [&](double factor) {
    return !hard_ || constraint_miss(res_.X.col(N_)) <= factor * tref;
  };
  // Raise mu to new_mu and re-evaluate the merit of the current iterate.
  const auto raise_penalty = [&](double new_mu) {
    mu_ = new_mu;
    J = terminal_cost(res_.X.col(N_)) + control_cost(res_.U) + mu_ * constraint_miss(res_.X.col(N_));
    if (info.merit_history.size() == 1)
      info.merit_history[0] = J;  // still the initial guess: its merit at the first penalty
    else
      ++info.penalty_updates;
  };
  double Delta = set_.trust_radius > 0.0 ? set_.trust_radius : kInf;
  info.trust_radius = Delta;
  bool lin_valid = false, first_inner = true;
  // Predicted decrease of a subproblem solved at the current iterate with the trust region inactive
  // (what solved_inaccurate may rely on); +inf when there is none.
  double cert_pred = kInf;
  Inner cert_inner = Inner::failed;
  ScpStatus status = ScpStatus::max_outer;
  for (int it = 1; it <= set_.max_outer; ++it) {
    if (timed && elapsed() >= set_.time_limit) {
      status = ScpStatus::time_limit;
      break;
    }
    info.outer_iterations = it;
    if (!lin_valid) {
      // Linearize along (X, U): c_k makes the affine model exact at the current trajectory.
      for (int k = 0; k < N_; ++k) {
        if (!model_.step(k, res_.X.col(k).data(), res_.U.col(k).data(), ws_->Xtmp_.col(k + 1).data(),
                         sub_.dynamics.A[k].data(), sub_.dynamics.B[k].data())) {
          info.failed_interval = k;
          return ScpStatus::propagation_failed;
        }
        VectorXd& c = sub_.dynamics.c[k];  // products in place: no temporaries
        c = ws_->Xtmp_.col(k + 1);
        c.noalias() -= sub_.dynamics.A[k] * res_.X.col(k);
        c.noalias() -= sub_.dynamics.B[k] * res_.U.col(k);
      }
      if (ilqr) {
        for (int k = 0; k < N_; ++k) lin_->set(k, sub_.dynamics.A[k], sub_.dynamics.B[k], sub_.dynamics.c[k]);
      } else {
        if (reduced_) reduce_linearization();
        const LtvDynamics& d = reduced_ ? red_.dynamics : sub_.dynamics;
        if (!admm_->update_dynamics(d.A, d.B, d.c)) {
          info.inner_status = AdmmStatus::numerical_error;
          return ScpStatus::inner_failed;
        }
      }
      lin_valid = true;
      if (timed && elapsed() >= set_.time_limit) {  // the Jacobians can be the expensive part
        info.merit_history.push_back(J);
        return ScpStatus::time_limit;
      }
    }
    // Convex subproblem (warm-started from the previous one), within the remaining time.
    const double remaining = timed ? set_.time_limit - elapsed() : 0.0;
    Inner in;
    bool inner_out_of_time = false;
    if (ilqr) {
      if (timed) {
        const double own = set_.inner_ilqr.time_limit;
        inner_->set_time_limit(std::max(own > 0.0 ? std::min(own, remaining) : remaining, 1e-300));
      }
      if (box_tr && std::isfinite(Delta)) {
        for (int k = 0; k < N_; ++k)
          for (int i = 0; i < nu_; ++i) {
            ws_->Tlo_(i, k) = std::max(res_.U(i, k) - Delta, lo_(i));
            ws_->Thi_(i, k) = std::min(res_.U(i, k) + Delta, hi_(i));
          }
        inner_->set_stage_bounds(ws_->Tlo_, ws_->Thi_);
      } else {
        inner_->clear_stage_bounds();
      }
      if (first_inner)
        inner_->set_initial_controls(res_.U);
      else
        inner_->warm_start(res_.U, ws_->Ywarm_, ws_->Lwarm_);
      const IlqrAdmmStatus ist = inner_->solve().info.status;
      const IlqrAdmmResult& r = inner_->result();
      info.inner_iterations += r.info.iterations;
      info.inner_ilqr_status = ist;
      in = classify(ist, set_.inner_ilqr.stop);
      inner_out_of_time = ist == IlqrAdmmStatus::time_limit;
      detail::keep_warm_start(r, in != Inner::failed && in != Inner::infeasible, ws_->Ywarm_, ws_->Lwarm_);
    } else {
      if (timed) {
        const double own = set_.inner.time_limit;
        admm_->set_time_limit(std::max(own > 0.0 ? std::min(own, remaining) : remaining, 1e-300));
      }
      if (!first_inner)
        admm_->warm_start(ws_->Ywarm_, ws_->Lwarm_);
      else
        admm_->cold_start();
      const AdmmResult& r = admm_->solve();
      info.inner_iterations += r.info.iterations;
      info.inner_status = r.info.status;
      in = classify(r.info.status);
      inner_out_of_time = r.info.status == AdmmStatus::time_limit;
      detail::keep_warm_start(r, in != Inner::failed && in != Inner::infeasible, ws_->Ywarm_, ws_->Lwarm_);
      if (in == Inner::infeasible) {
        // in full coordinates (zeros on the exogenous states when the inner saw the others only)
        const VectorXd& y = r.infeasibility_certificate;
        for (int i = 0; i < static_cast<int>(y.size()); ++i)
          info.infeasibility_certificate(reduced_ ? endo_[i] : i) = y(i);
        info.infeasibility_margin = y.squaredNorm() > 0.0 ? infeasibility_margin(y) : 0.0;
      } else if (hard_ && in != Inner::failed) {
        // exact penalty: mu above the multiplier norm of the constrained (non-exogenous) states
        double pn = 0.0;
        for (int i = 0; i < static_cast<int>(r.terminal_multiplier.size()); ++i)
          if (reduced_ || !is_exo_[i]) pn += r.terminal_multiplier(i) * r.terminal_multiplier(i);
        pn = std::sqrt(pn);
        if (std::isfinite(pn) && mu_ < 1.5 * pn) raise_penalty(2.0 * pn);
      }
    }
    first_inner = false;
    info.inner_solved = in == Inner::solved;
    if (in == Inner::infeasible && elastic_ && info.inner_status == AdmmStatus::primal_infeasible) {
      // Infeasible on this linearization, which may be an artifact of it (the box reaches further
      // elsewhere on a nonlinear model): lower the true miss first; report only at a stationary point.
      const int rs = restore(J, timed ? std::max(set_.time_limit - elapsed(), 1e-300) : 0.0);
      if (rs == -2) {  // out of time inside the restoration subproblem
        info.merit_history.push_back(J);
        return ScpStatus::time_limit;
      }
      if (rs == 1) {
        info.merit_history.push_back(J);
        ++info.restoration_steps;
        lin_valid = false;
        cert_pred = kInf;
        continue;
      }
      if (rs < 0) {
        info.merit_history.push_back(J);
        return ScpStatus::inner_failed;
      }
      if (rs == 2) ++info.rejected_steps;  // predicted but not realized: no step lowers the miss either
    }
    if (in == Inner::infeasible) {
      info.merit_history.push_back(J);
      return ScpStatus::inner_infeasible;
    }
    if (timed && inner_out_of_time && elapsed() >= set_.time_limit) {
      // the subproblem's answer is partial: the current iterate (its true cost) is returned
      info.merit_history.push_back(J);
      return ScpStatus::time_limit;
    }
    if (in == Inner::failed || !ws_->Ywarm_.allFinite() || !ws_->Lwarm_.allFinite()) {
      info.merit_history.push_back(J);
      return ScpStatus::inner_failed;
    }
    res_.Lambda = ws_->Lwarm_;
    // Candidate: the subproblem's minimizer, scaled into the trust region when it is not inside it.
    ws_->Ucand_ = ws_->Ywarm_;
    bool tr_active = false;
    const double full_step = (ws_->Ucand_ - res_.U).cwiseAbs().maxCoeff();
    if (tr && std::isfinite(Delta)) {
      if (box_tr) {
        const double tiny = 1e-12 * std::max(1.0, Delta);
        for (int k = 0; k < N_ && !tr_active; ++k)
          for (int i = 0; i < nu_; ++i)
            if ((ws_->Tlo_(i, k) > lo_(i) && ws_->Ucand_(i, k) <= ws_->Tlo_(i, k) + tiny) ||
                (ws_->Thi_(i, k) < hi_(i) && ws_->Ucand_(i, k) >= ws_->Thi_(i, k) - tiny)) {
              tr_active = true;
              break;
            }
      } else if (full_step > Delta) {
        ws_->Ucand_ = res_.U + (Delta / full_step) * (ws_->Ucand_ - res_.U);
        tr_active = true;
      }
    }
    const double step = (ws_->Ucand_ - res_.U).cwiseAbs().maxCoeff();
    const double pred = J - model_cost(ws_->Ucand_);  // the model is exact at U: model(U) = J
    info.predicted_decrease = pred;
    const double scale = std::max(1.0, std::abs(J));
    if (!tr_active) {
      cert_pred = pred;
      cert_inner = in;
    }
    if (pred <= set_.tol * scale) {
      if (in == Inner::solved && pred < -set_.tol_inaccurate * scale) {
        // A "solved" subproblem that is worse than the current iterate, which is feasible for it.
        // (Not with a hard terminal state: the iterate is then not feasible for the subproblem.)
        if (!hard_ || terminal_ok(set_.terminal_tol)) {
          info.merit_history.push_back(J);
          return ScpStatus::inner_failed;
        }
      }
      if (hard_ && !terminal_ok(set_.terminal_tol)) {
        // Stationary for the merit but off the target: mu is too small to weigh the miss (its
        // multiplier estimate was loose). Raise it so that the penalty term dominates, and go on.
        const double miss = constraint_miss(res_.X.col(N_));
        raise_penalty(std::max(10.0 * mu_, scale / std::max(miss, 1e-300)));
        info.merit_history.push_back(J);
        cert_pred = kInf;
        continue;
      }
      info.merit_history.push_back(J);
      info.last_step = 0.0;
      // pred < -tol: the subproblem's answer is worse than U_k, which is feasible for it, so the
      // inner solve is not accurate to tol and certifies nothing finer (solved_inaccurate below).
      if (in == Inner::solved && !tr_active) {
        if (pred >= -set_.tol * scale) return ScpStatus::solved;
        break;
      }
      // Stationary within the trust region: widen it; or the inner stopped short: continue it.
      if (tr_active) Delta *= set_.tr_grow;
      info.trust_radius = Delta;
      continue;
    }
    bool accepted = false;
    bool out_of_time = false;
    if (tr) {
      const double Jn = true_cost(ws_->Ucand_, ws_->Xtmp_);
      const double ratio = (J - Jn) / pred;
      if (std::isfinite(Jn) && Jn < J && ratio >= set_.tr_accept) {
        res_.U.swap(ws_->Ucand_);
        res_.X.swap(ws_->Xtmp_);
        J = Jn;
        accepted = true;
        if (ratio > set_.tr_grow_ratio && std::isfinite(Delta)) Delta = std::max(Delta, set_.tr_grow * step);
        info.last_step = 1.0;
      } else {
        Delta = set_.tr_shrink * std::min(Delta, step);
        info.last_step = 0.0;
      }
    } else {
      double t = 1.0;
      for (int ls = 0; ls < set_.line_search_iters; ++ls, t *= 0.5) {
        if (ls > 0 && timed && elapsed() >= set_.time_limit) {
          out_of_time = true;
          break;
        }
        ws_->Utmp_ = res_.U + t * (ws_->Ucand_ - res_.U);
        const double Jn = true_cost(ws_->Utmp_, ws_->Xtmp_);
        if (std::isfinite(Jn) && Jn < J && Jn <= J - set_.armijo * t * pred) {
          res_.U.swap(ws_->Utmp_);
          res_.X.swap(ws_->Xtmp_);
          J = Jn;
          accepted = true;
          break;
        }
      }
      info.last_step = accepted ? t : 0.0;
    }
    info.trust_radius = Delta;
    info.merit_history.push_back(J);
    if (out_of_time) return ScpStatus::time_limit;
    if (accepted) {
      lin_valid = false;
      cert_pred = kInf;
      continue;
    }
    ++info.rejected_steps;
    // A decrease at the loose tolerance that the true cost cannot realize: shrinking further only
    // chases rounding (the status becomes solved_inaccurate below).
    const bool at_rounding =
        !tr_active && (in == Inner::solved || in == Inner::inaccurate) && pred <= set_.tol_inaccurate * scale;
    if (!tr || at_rounding || Delta < set_.tr_min * std::max(1.0, res_.U.cwiseAbs().maxCoeff())) {
      status = ScpStatus::line_search_failed;
      break;
    }
  }
  // At a limit: the loose test on the last subproblem solved at the returned iterate.
  if ((cert_inner == Inner::solved || cert_inner == Inner::inaccurate) && std::isfinite(cert_pred) &&
      terminal_ok(set_.terminal_tol_inaccurate)) {
    const double scale = std::max(1.0, std::abs(J));
    if (cert_pred <= set_.tol_inaccurate * scale && cert_pred >= -set_.tol_inaccurate * scale)
      status = ScpStatus::solved_inaccurate;
  }
  return status;
}

}  // namespace satgnc::guidance
