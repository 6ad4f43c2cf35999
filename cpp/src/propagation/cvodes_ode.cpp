// Generic N-dimensional CVODES integrator (see cvodes_ode.hpp).
#include "satgnc/propagation/cvodes_ode.hpp"

#include <cvodes/cvodes.h>
#include <cvodes/cvodes_ls.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "detail/cvodes.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::propagation {

void CvodesOdeSettings::validate(int n) const {
  using core::require;
  require(std::isfinite(rtol) && rtol > 0.0, "rtol",
          "must be finite and > 0, got " + detail::format_g17(rtol));
  require(std::isfinite(atol) && atol > 0.0, "atol",
          "must be finite and > 0, got " + detail::format_g17(atol));
  require(atol_components.empty() || static_cast<int>(atol_components.size()) == n, "atol_components",
          "must be empty or have n = " + std::to_string(n) + " entries, got " +
              std::to_string(atol_components.size()));
  for (size_t i = 0; i < atol_components.size(); ++i)
    require(std::isfinite(atol_components[i]) && atol_components[i] > 0.0,
            "atol_components[" + std::to_string(i) + "]", "must be finite and > 0");
  require(max_steps > 0, "max_steps", "must be > 0, got " + std::to_string(max_steps));
  const int omax = method == CvodesMethod::adams ? 12 : 5;
  require(max_order >= 0 && max_order <= omax, "max_order",
          "must be 0 (default) or 1.." + std::to_string(omax) + " for this method, got " +
              std::to_string(max_order));
  require(std::isfinite(max_step) && max_step >= 0.0, "max_step", "must be finite and >= 0 (0: unbounded)");
}

struct CvodesOde::Impl {
  int n;
  Rhs f;
  Jacobian jac;
  CvodesOdeSettings settings;
  Eigen::MatrixXd J, M;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;
  double lu_t = 0.0, lu_gamma = 0.0;
  bool lu_valid = false;
  PropagationStats stats;
  std::string message;
  std::string cv_message;
  double t_reached = 0.0;
  detail::RhsFailure rhs_failure;
  ImpactFunction impact;
  detail::CvodesHandles cv;  // the SUNDIALS objects (detail/cvodes.hpp); freed before the members above

  Impl(int dim, Rhs rhs, const CvodesOdeSettings& s, Jacobian j)
      : n(dim), f(std::move(rhs)), jac(std::move(j)), settings(s) {}

  static int rhs(realtype t, N_Vector yv, N_Vector ydot, void* user) {
    auto* p = static_cast<Impl*>(user);
    double* fd = N_VGetArrayPointer(ydot);
    bool ok = p->f(t, N_VGetArrayPointer(yv), fd);
    for (int i = 0; ok && i < p->n; ++i) ok = std::isfinite(fd[i]);
    if (!ok) return p->rhs_failure.record(t);  // recoverable: CVODES retries with a smaller step, then fails
    return 0;
  }

  // As in CvodesPropagator: CVODES 6.4 does not call setup() on a matrix-embedded solver, so solve()
  // refreshes M = I - gamma J(y_pred) whenever (t, gamma) changed (modified Newton per step).
  static int ls_solve(SUNLinearSolver s, SUNMatrix, N_Vector x, N_Vector b, realtype) {
    auto* p = static_cast<Impl*>(s->content);
    realtype tcur, gamma;
    N_Vector ypred;
    if (!detail::cvodes_newton_point(p->cv.mem, tcur, gamma, ypred)) return SUNLS_PACKAGE_FAIL_UNREC;
    if (!p->lu_valid || tcur != p->lu_t || gamma != p->lu_gamma) {
      if (!p->jac(tcur, N_VGetArrayPointer(ypred), p->J.data()) || !p->J.allFinite())
        return SUNLS_PACKAGE_FAIL_REC;
      p->M.setIdentity();
      p->M.noalias() -= gamma * p->J;
      p->lu.compute(p->M);
      p->lu_t = tcur;
      p->lu_gamma = gamma;
      p->lu_valid = true;
      ++p->stats.lin_setups;
    }
    Eigen::Map<Eigen::VectorXd> xv(N_VGetArrayPointer(x), p->n);
    const Eigen::Map<const Eigen::VectorXd> bv(N_VGetArrayPointer(b), p->n);
    xv.noalias() = p->lu.solve(bv);
    return SUNLS_SUCCESS;
  }

  void setup() {
    core::require(n >= 1, "n", "must be >= 1");
    core::require(static_cast<bool>(f), "rhs", "must be a callable");
    settings.validate(n);
    if (jac) {
      J.setZero(n, n);
      M.setZero(n, n);
      lu = Eigen::PartialPivLU<Eigen::MatrixXd>(n);
    }
    detail::CvodesSetup cs;
    cs.n = n;
    cs.adams = settings.method == CvodesMethod::adams;
    cs.rhs = &Impl::rhs;
    cs.user_data = this;
    cs.rtol = settings.rtol;
    cs.atol = settings.atol;
    cs.atol_components = &settings.atol_components;  // empty or n entries (validated)
    cs.max_order = settings.max_order;
    cs.max_step = settings.max_step;
    cs.newton = static_cast<bool>(jac);
    cs.ls_solve = &Impl::ls_solve;
    detail::cvodes_create(cs, cv, cv_message);
  }

  static int impact_root(realtype t, N_Vector yv, realtype* g, void* user) {
    const auto* p = static_cast<const Impl*>(user);
    g[0] = p->impact(t, N_VGetArrayPointer(yv));
    return std::isfinite(g[0]) ? 0 : 1;  // a non-finite g is a root-function failure (CV_RTFUNC_FAIL)
  }

  void set_impact(ImpactFunction g) {
    core::require(static_cast<bool>(g), "impact_function", "must be a callable");
    const bool first = !impact;
    impact = std::move(g);
    if (first) detail::cvodes_root_downward(cv.mem, &Impl::impact_root, cv_message);
  }

  static PropagationStatus map_flag(int flag) { return detail::cvodes_flag_status(flag); }

  void fill_stats() { detail::cvodes_read_stats(cv.mem, stats); }

  PropagationStatus integrate(double t0, Eigen::Ref<Eigen::VectorXd> yin, double t1) {
    stats = PropagationStats{};
    message.clear();
    cv_message.clear();
    rhs_failure.failed = false;
    lu_valid = false;
    t_reached = t0;
    if (yin.size() != n || !yin.allFinite() || !std::isfinite(t0) || !std::isfinite(t1) || t1 == t0) {
      message = "invalid input: y must have n = " + std::to_string(n) +
                " finite entries and t0, t1 must be finite and distinct";
      return PropagationStatus::solver_failure;
    }
    if (impact && !(impact(t0, yin.data()) > 0.0)) {
      message = "impact: the state starts at or inside the surface (impact function <= 0 at t = " +
                detail::format_g17(t0) + ")";
      return PropagationStatus::impact;
    }
    Eigen::Map<Eigen::VectorXd> yv(N_VGetArrayPointer(cv.y), n);
    yv = yin;
    int flag = CVodeReInit(cv.mem, t0, cv.y);
    if (flag >= 0) flag = CVodeSetStopTime(cv.mem, t1);
    if (flag >= 0) flag = CVodeSetMaxNumSteps(cv.mem, settings.max_steps);
    realtype tret = t0;
    if (flag >= 0) flag = CVode(cv.mem, t1, cv.y, &tret, CV_NORMAL);
    fill_stats();
    t_reached = tret;
    if (flag < 0) {
      realtype tcur = t0;
      if (stats.steps > 0) CVodeGetCurrentTime(cv.mem, &tcur);
      t_reached = tcur;
      const PropagationStatus st = map_flag(flag);
      message = "CVODES stopped at t = " + detail::format_g17(tcur) +
                " before reaching t = " + detail::format_g17(t1) + ": " + status_message(st);
      if (flag == CV_TOO_MUCH_WORK) message += " (max_steps = " + std::to_string(settings.max_steps) + ")";
      rhs_failure.describe(message, "the right-hand side", "");
      if (!cv_message.empty()) message += " [CVODES: " + cv_message + "]";
      if (stats.steps > 0) yin = yv;  // last accepted state
      return st;
    }
    yin = yv;
    if (flag == CV_ROOT_RETURN) {
      message = "impact at t = " + detail::format_g17(tret) +
                " (the impact function reached 0) before t = " + detail::format_g17(t1);
      return PropagationStatus::impact;
    }
    return PropagationStatus::success;
  }
};

CvodesOde::CvodesOde(int n, Rhs rhs, const CvodesOdeSettings& settings, Jacobian jacobian)
    : impl_(std::make_unique<Impl>(n, std::move(rhs), settings, std::move(jacobian))) {
  impl_->setup();
}
CvodesOde::~CvodesOde() = default;
CvodesOde::CvodesOde(CvodesOde&&) noexcept = default;
CvodesOde& CvodesOde::operator=(CvodesOde&&) noexcept = default;

PropagationStatus CvodesOde::integrate(double t0, Eigen::Ref<Eigen::VectorXd> y, double t1) noexcept {
  // Eigen allocates nothing here after setup (J, M and the LU are sized in the constructor) as long as
  // the caller's rhs and Jacobian do not; the failure messages (std::string) are outside Eigen's view.
  SATGNC_NO_MALLOC_SCOPE;
  try {
    return impl_->integrate(t0, y, t1);
  } catch (...) {
    impl_->message = "unexpected exception in the right-hand side or Jacobian callback";
    return PropagationStatus::solver_failure;
  }
}

void CvodesOde::set_impact_function(ImpactFunction g) { impl_->set_impact(std::move(g)); }

int CvodesOde::dim() const { return impl_->n; }
const CvodesOdeSettings& CvodesOde::settings() const { return impl_->settings; }
const PropagationStats& CvodesOde::stats() const { return impl_->stats; }
const std::string& CvodesOde::message() const { return impl_->message; }
double CvodesOde::t_reached() const { return impl_->t_reached; }

}  // namespace satgnc::propagation
