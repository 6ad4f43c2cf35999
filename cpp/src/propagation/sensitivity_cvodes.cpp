// CVODES propagation of the state, the STM and the parameter sensitivity dx/dp (issue 14 item 5):
// the CvodesPropagator scheme (detail/cvodes.hpp) on 6 + 36 + 6k equations.
#include <cvodes/cvodes.h>
#include <cvodes/cvodes_ls.h>

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "detail/cvodes.hpp"
#include "detail/cvodes_orbit_newton.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"
#include "satgnc/propagation/sensitivity.hpp"

namespace satgnc::propagation {

using dynamics::ForceParameter;

struct CvodesSensitivityPropagator::Impl {
  dynamics::ForceModel model;
  std::vector<ForceParameter> params;
  CvodesSettings settings;
  int k = 0;
  int n = 42;
  bool velocity_dependent = false;
  detail::OrbitNewtonLu newton;  // M = I - gamma A(x_pred), shared by every 6-block
  detail::RhsFailure rhs_failure;
  realtype tret = 0.0;
  std::string cv_message;
  detail::CvodesHandles cv;

  Impl(const dynamics::ForceModel& m, const std::vector<ForceParameter>& p, const CvodesSettings& s)
      : model(m), params(p), settings(s) {}

  static int rhs(realtype t, N_Vector yv, N_Vector ydot, void* user) {
    auto* p = static_cast<Impl*>(user);
    const double* yd = N_VGetArrayPointer(yv);
    double* fd = N_VGetArrayPointer(ydot);
    const Eigen::Map<const Vec3> r(yd), v(yd + 3);
    if (!(r.squaredNorm() > 0.0) || !std::isfinite(r.squaredNorm() + v.squaredNorm()))
      return p->rhs_failure.record(t);
    Vec3 a;
    Mat3 g, d;
    p->model.acceleration_jacobians(t, r, v, a, g, d);
    if (!a.allFinite()) return p->rhs_failure.record(t);
    const int cols = 6 + p->k;
    const Eigen::Map<const Eigen::Matrix<double, 6, Eigen::Dynamic>> c(yd + 6, 6, cols);
    Eigen::Map<Eigen::Matrix<double, 6, Eigen::Dynamic>> dc(fd + 6, 6, cols);
    for (int j = 0; j < cols; ++j) {
      dc.col(j).head<3>() = c.col(j).tail<3>();
      Vec3 b = g * c.col(j).head<3>();
      if (p->velocity_dependent) b.noalias() += d * c.col(j).tail<3>();
      if (j >= 6)
        b += p->model.acceleration_partial(p->params[static_cast<std::size_t>(j - 6)], t, Vec3(r), Vec3(v));
      dc.col(j).tail<3>() = b;
    }
    fd[0] = yd[3];
    fd[1] = yd[4];
    fd[2] = yd[5];
    fd[3] = a[0];
    fd[4] = a[1];
    fd[5] = a[2];
    return 0;
  }

  // Matrix-embedded linear solver: x = M^-1 b block by block (detail/cvodes_orbit_newton.hpp).
  static int ls_solve(SUNLinearSolver s, SUNMatrix, N_Vector x, N_Vector b, realtype) {
    auto* p = static_cast<Impl*>(s->content);
    return p->newton.solve(p->cv.mem, p->model, p->n, x, b);
  }

  static int surface_root(realtype, N_Vector yv, realtype* g, void* user) {
    const auto* p = static_cast<const Impl*>(user);
    const double* yd = N_VGetArrayPointer(yv);
    const double R = p->settings.surface_radius;
    g[0] = yd[0] * yd[0] + yd[1] * yd[1] + yd[2] * yd[2] - R * R;
    return 0;
  }

  void setup() {
    settings.validate();
    model.validate();
    validate_sensitivity_parameters(model, params);
    core::require(settings.with_stm, "settings.with_stm",
                  "must be true for a sensitivity propagation (S needs the STM's variational system)");
    k = static_cast<int>(params.size());
    n = 42 + 6 * k;
    velocity_dependent = model.drag.has_value() || model.atmosphere_drag.has_value();
    CvodesCorrector c = settings.corrector;
    if (c == CvodesCorrector::automatic) c = CvodesCorrector::newton;
    detail::CvodesSetup cs;
    cs.n = n;
    cs.adams = settings.method == CvodesMethod::adams;
    cs.serial_vector = settings.vector != CvodesVector::satgnc;
    cs.y_first = 1.0;
    cs.rhs = &Impl::rhs;
    cs.user_data = this;
    cs.rtol = settings.rtol;
    cs.atol = settings.atol;
    cs.atol_components = &settings.atol_components;  // 0, 6 or 42 entries: S entries get atol
    cs.max_order = settings.max_order;
    cs.max_step = settings.max_step;
    cs.newton = c != CvodesCorrector::fixed_point;
    cs.ls_solve = &Impl::ls_solve;
    detail::cvodes_create(cs, cv, cv_message);
    if (settings.surface_radius > 0.0) detail::cvodes_root_downward(cv.mem, &Impl::surface_root, cv_message);
  }

  void check(int flag, const char* what) { detail::cvodes_check(flag, what, cv_message); }

  void record(SensitivityTrajectory& out, double t) const {
    const double* yd = N_VGetArrayPointer(cv.y);
    out.trajectory.times.push_back(t);
    out.trajectory.states.push_back(Eigen::Map<const Vec6>(yd));
    out.trajectory.stms.push_back(Eigen::Map<const Mat6>(yd + 6));
    out.sensitivities.push_back(Eigen::Map<const Eigen::Matrix<double, 6, Eigen::Dynamic>>(yd + 42, 6, k));
  }

  void fill_stats(Trajectory& tr) const {
    detail::cvodes_read_stats(cv.mem, tr.stats);
    tr.stats.lin_setups = newton.lin_setups;
  }

  void run(const Vec6& x0, double t0, const std::vector<double>& times, SensitivityTrajectory& out) {
    validate_orbit_arc_input(x0, t0, times, kOneSidedArc, kGravitySingular);
    const double R = settings.surface_radius;
    if (R > 0.0 && !(x0.head<3>().norm() > R))
      core::require(false, "x0",
                    "starts at or below the surface: |r0| = " + detail::format_g17(x0.head<3>().norm()) +
                        " km <= surface_radius = " + detail::format_g17(R) + " km");
    Trajectory& tr = out.trajectory;
    tr.times.clear();
    tr.states.clear();
    tr.stms.clear();
    out.sensitivities.clear();
    tr.times.reserve(times.size());
    tr.states.reserve(times.size());
    tr.stms.reserve(times.size());
    out.sensitivities.reserve(times.size());
    if (out.parameters != params) out.parameters = params;
    tr.stats = PropagationStats{};
    tr.status = PropagationStatus::success;
    tr.message.clear();
    tr.t_reached = t0;
    rhs_failure.failed = false;
    newton.lin_setups = 0;
    SATGNC_NO_MALLOC_SCOPE;
    double* yd = N_VGetArrayPointer(cv.y);
    for (int i = 0; i < n; ++i) yd[i] = 0.0;
    Eigen::Map<Vec6> y_state(yd);
    y_state = x0;
    Eigen::Map<Mat6>(yd + 6).setIdentity();
    std::size_t i = 0;
    if (times[0] == t0) {
      record(out, t0);
      ++i;
    }
    if (i == times.size()) return;
    const double dir = times.back() > t0 ? 1.0 : -1.0;
    check(CVodeReInit(cv.mem, t0, cv.y), "CVodeReInit");
    check(CVodeSetInitStep(cv.mem, dir * settings.initial_step), "CVodeSetInitStep");
    check(CVodeSetStopTime(cv.mem, times.back()), "CVodeSetStopTime");
    long used = 0;
    for (; i < times.size(); ++i) {
      int flag = CV_TOO_MUCH_WORK;
      const long remaining = settings.max_steps - used;
      if (remaining > 0) {
        CVodeSetMaxNumSteps(cv.mem, remaining);
        tret = t0;
        flag = CVode(cv.mem, times[i], cv.y, &tret, CV_NORMAL);
        CVodeGetNumSteps(cv.mem, &used);
      }
      if (flag < 0 || flag == CV_ROOT_RETURN) {
        fill_stats(tr);
        realtype tcur = tr.t_reached;
        if (flag == CV_ROOT_RETURN) {
          tcur = tret;
          tr.status = PropagationStatus::impact;
        } else {
          if (tr.stats.steps > 0) CVodeGetCurrentTime(cv.mem, &tcur);
          tr.status = detail::cvodes_flag_status(flag);
        }
        tr.t_reached = tcur;
        char buf[256];
        std::snprintf(
            buf, sizeof buf, "CVODES (sensitivity) stopped at t = %.17g s before t = %.17g s: %s", tcur,
            times[i],
            flag == CV_ROOT_RETURN ? "impact: |r| reached surface_radius" : status_message(tr.status));
        tr.message.assign(buf);
        return;
      }
      record(out, times[i]);
    }
    tr.t_reached = times.back();
    fill_stats(tr);
  }
};

CvodesSensitivityPropagator::CvodesSensitivityPropagator(const dynamics::ForceModel& model,
                                                         const std::vector<ForceParameter>& parameters,
                                                         const CvodesSettings& settings)
    : impl_(std::make_unique<Impl>(model, parameters, settings)) {
  impl_->setup();
}
CvodesSensitivityPropagator::~CvodesSensitivityPropagator() = default;
CvodesSensitivityPropagator::CvodesSensitivityPropagator(CvodesSensitivityPropagator&&) noexcept = default;
CvodesSensitivityPropagator& CvodesSensitivityPropagator::operator=(CvodesSensitivityPropagator&&) noexcept =
    default;

SensitivityTrajectory CvodesSensitivityPropagator::propagate(const Vec6& x0, double t0,
                                                             const std::vector<double>& times) {
  SensitivityTrajectory out;
  impl_->run(x0, t0, times, out);
  return out;
}

void CvodesSensitivityPropagator::propagate(const Vec6& x0, double t0, const std::vector<double>& times,
                                            SensitivityTrajectory& out) {
  impl_->run(x0, t0, times, out);
}

const std::vector<ForceParameter>& CvodesSensitivityPropagator::parameters() const { return impl_->params; }

SensitivityTrajectory propagate_cvodes_sensitivity(const dynamics::ForceModel& model, const Vec6& x0,
                                                   double t0, const std::vector<double>& times,
                                                   const std::vector<ForceParameter>& parameters,
                                                   const CvodesSettings& settings) {
  CvodesSensitivityPropagator p(model, parameters, settings);
  return p.propagate(x0, t0, times);
}

}  // namespace satgnc::propagation
