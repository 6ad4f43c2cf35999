#include "satgnc/guidance/scp.hpp"

#include <cmath>
#include <exception>
#include <limits>

#include "satgnc/core/validate.hpp"

namespace satgnc::guidance {

using Eigen::MatrixXd;
using Eigen::VectorXd;

const char* status_message(ScpStatus s) {
  switch (s) {
    case ScpStatus::solved:
      return "solved: predicted decrease of the convex model below tol";
    case ScpStatus::max_outer:
      return "max_outer reached";
    case ScpStatus::propagation_failed:
      return "the dynamics failed (see failed_interval)";
    case ScpStatus::inner_failed:
      return "the convex subproblem solver failed (see inner_status)";
    case ScpStatus::line_search_failed:
      return "no step decreased the true cost; current iterate returned";
    case ScpStatus::not_run:
      return "solve() not called";
  }
  return "unknown status";
}

void ScpSettings::validate() const {
  core::require(max_outer >= 1, "max_outer", "must be >= 1");
  core::require_nonnegative(tol, "tol");
  core::require(armijo >= 0.0 && armijo < 1.0, "armijo", "must be in [0, 1)");
  core::require(line_search_iters >= 1, "line_search_iters", "must be >= 1");
  inner.validate();
}

ScpSolver::ScpSolver(const DiscreteModel& model, const NonlinearL1Problem& problem,
                     const ScpSettings& settings)
    : model_(model), prob_(problem), set_(settings), checker_(model, problem) {
  set_.validate();
  set_.inner_ilqr.validate();
  prob_ = checker_.problem();  // validated, x_target filled
  nx_ = model.state_dim();
  nu_ = model.control_dim();
  N_ = prob_.horizon;
  res_.X = MatrixXd::Zero(nx_, N_ + 1);
  res_.U = MatrixXd::Zero(nu_, N_);
  res_.Lambda = MatrixXd::Zero(nu_, N_);
  Ytmp_ = res_.U;
  Utmp_ = res_.U;
  Xtmp_ = res_.X;
  Ywarm_ = res_.U;
  Lwarm_ = res_.U;
  sub_.dynamics.horizon = N_;
  sub_.dynamics.A.assign(N_, MatrixXd::Zero(nx_, nx_));
  sub_.dynamics.B.assign(N_, MatrixXd::Zero(nx_, nu_));
  sub_.dynamics.c.assign(N_, VectorXd::Zero(nx_));
  sub_.x0 = prob_.x0;
  sub_.xf = prob_.x_target;
  sub_.Qf = prob_.Qf;
  {
    std::vector<MatrixXd> A(N_, MatrixXd::Identity(nx_, nx_)), B(N_, MatrixXd::Zero(nx_, nu_));
    std::vector<VectorXd> c(N_, VectorXd::Zero(nx_));
    lin_ = std::make_unique<LinearDiscreteModel>(A, B, c);
    inner_ = std::make_unique<IlqrAdmmSolver>(*lin_, prob_, set_.inner_ilqr);
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
  if (set_.inner_solver == ScpInner::linear_admm) admm_ = std::make_unique<AdmmSolver>(sub_, set_.inner);
}

void ScpSolver::set_initial_controls(const Eigen::Ref<const MatrixXd>& U0) {
  core::require(U0.rows() == nu_ && U0.cols() == N_, "U0",
                "must be nu x N = " + std::to_string(nu_) + " x " + std::to_string(N_));
  core::require_finite(U0, "U0");
  res_.U = U0;
  Ywarm_.setZero();
  Lwarm_.setZero();
}

void ScpSolver::set_initial_state(const Eigen::Ref<const VectorXd>& x0) {
  core::require(x0.size() == nx_, "x0", "must have nx = " + std::to_string(nx_) + " entries");
  core::require_finite(x0, "x0");
  prob_.x0 = x0;
  sub_.x0 = x0;
  inner_->set_initial_state(x0);
  if (admm_) admm_->set_x0(x0);
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

double ScpSolver::true_cost(const MatrixXd& U, MatrixXd& X) const {
  if (rollout(U, X) >= 0) return std::numeric_limits<double>::infinity();
  const VectorXd e = X.col(N_) - prob_.x_target;
  return 0.5 * e.dot(prob_.Qf * e) + control_cost(U);
}

ScpStatus ScpSolver::solve() noexcept {
  ScpInfo& info = res_.info;
  info = ScpInfo();
  try {
    const int fail = rollout(res_.U, res_.X);
    if (fail >= 0) {
      info.status = ScpStatus::propagation_failed;
      info.failed_interval = fail;
      return info.status;
    }
    double J = true_cost(res_.U, Xtmp_);
    info.status = ScpStatus::max_outer;
    for (int it = 1; it <= set_.max_outer; ++it) {
      info.outer_iterations = it;
      // Linearize along (X, U): c_k makes the affine model exact at the current trajectory.
      for (int k = 0; k < N_; ++k) {
        if (!model_.step(k, res_.X.col(k).data(), res_.U.col(k).data(), Xtmp_.col(k + 1).data(),
                         sub_.dynamics.A[k].data(), sub_.dynamics.B[k].data())) {
          info.status = ScpStatus::propagation_failed;
          info.failed_interval = k;
          return info.status;
        }
        sub_.dynamics.c[k] =
            Xtmp_.col(k + 1) - sub_.dynamics.A[k] * res_.X.col(k) - sub_.dynamics.B[k] * res_.U.col(k);
      }
      const MatrixXd* Ysub;
      double J_lin;
      if (set_.inner_solver == ScpInner::ilqr_admm) {
        for (int k = 0; k < N_; ++k) lin_->set(k, sub_.dynamics.A[k], sub_.dynamics.B[k], sub_.dynamics.c[k]);
        if (it == 1) {
          inner_->set_initial_controls(res_.U);
        } else {
          inner_->warm_start(res_.U, Ywarm_, Lwarm_);
        }
        const IlqrAdmmStatus st = inner_->solve();
        const IlqrAdmmResult& r = inner_->result();
        info.inner_iterations += r.info.iterations;
        info.inner_ilqr_status = st;
        if (st == IlqrAdmmStatus::propagation_failed || st == IlqrAdmmStatus::ilqr_failed ||
            !r.Y.allFinite()) {
          info.status = ScpStatus::inner_failed;
          return info.status;
        }
        Ywarm_ = r.Y;
        Lwarm_ = r.Lambda;
        J_lin = r.info.objective_y;
        Ysub = &Ywarm_;
      } else {
        if (!admm_->update_dynamics(sub_.dynamics.A, sub_.dynamics.B, sub_.dynamics.c)) {
          info.status = ScpStatus::inner_failed;
          info.inner_status = AdmmStatus::kNumericalError;
          return info.status;
        }
        if (it > 1)
          admm_->warm_start(Ywarm_, Lwarm_);
        else
          admm_->cold_start();
        const AdmmResult& r = admm_->solve();
        info.inner_iterations += r.info.iterations;
        info.inner_status = r.info.status;
        if (r.info.status == AdmmStatus::kNumericalError || !r.Y.allFinite()) {
          info.status = ScpStatus::inner_failed;
          return info.status;
        }
        Ywarm_ = r.Y;
        Lwarm_ = r.Lambda;
        J_lin = r.info.objective;
        Ysub = &Ywarm_;
      }
      res_.Lambda = Lwarm_;
      const double pred = J - J_lin;  // J_lin(U) = J_true(U) by construction of c_k
      info.predicted_decrease = pred;
      if (pred < -1e-6 * std::max(1.0, std::abs(J))) {  // the convex model cannot be worse than U
        info.status = ScpStatus::inner_failed;
        break;
      }
      if (pred <= set_.tol * std::max(1.0, std::abs(J))) {
        info.status = ScpStatus::solved;
        break;
      }
      double t = 1.0;
      bool accepted = false;
      for (int ls = 0; ls < set_.line_search_iters; ++ls, t *= 0.5) {
        Utmp_ = res_.U + t * (*Ysub - res_.U);
        const double Jn = true_cost(Utmp_, Xtmp_);
        if (std::isfinite(Jn) && Jn <= J - set_.armijo * t * pred) {
          res_.U.swap(Utmp_);
          res_.X.swap(Xtmp_);
          J = Jn;
          accepted = true;
          break;
        }
      }
      info.last_step = accepted ? t : 0.0;
      if (!accepted) {
        // A predicted decrease at the inner solver's accuracy that cannot be realized: converged.
        info.status =
            pred <= 1e-7 * std::max(1.0, std::abs(J)) ? ScpStatus::solved : ScpStatus::line_search_failed;
        break;
      }
    }
    info.objective = J;
    if (rollout(res_.U, res_.X) >= 0) info.objective = std::numeric_limits<double>::infinity();
  } catch (const std::exception&) {
    info.status = ScpStatus::inner_failed;
  }
  return info.status;
}

}  // namespace satgnc::guidance
