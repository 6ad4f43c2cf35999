// CVODES propagator: state + variational equations, satgnc N_Vector, block-diagonal Newton solver.
#include "satgnc/propagation/cvodes.hpp"

#include <cvodes/cvodes.h>
#include <cvodes/cvodes_ls.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "detail/cvodes.hpp"
#include "detail/cvodes_orbit_newton.hpp"
#include "satgnc/core/no_malloc.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::propagation {

namespace {
constexpr int kStateDim = 6;
constexpr int kAugDim = 42;

[[noreturn]] void invalid(const std::string& name, const std::string& rule, const std::string& hint = "") {
  core::require(false, name, rule, hint);
  throw std::logic_error("unreachable");
}
}  // namespace

void CvodesSettings::validate() const {
  if (!(std::isfinite(rtol) && rtol > 0.0))
    invalid("rtol", "must be finite and > 0, got " + detail::format_g17(rtol),
            "1e-10 is a good start for orbits");
  if (!(rtol < 1.0))  // rtol = 1e300 "succeeded" with a trajectory no tolerance controlled
    invalid("rtol",
            "must be < 1 (a relative tolerance of 100 % controls nothing), got " + detail::format_g17(rtol),
            "1e-10 is a good start for orbits");
  if (!(std::isfinite(atol) && atol > 0.0))
    invalid("atol", "must be finite and > 0, got " + detail::format_g17(atol));
  const size_t na = atol_components.size();
  if (!(na == 0 || na == 6 || (na == 42 && with_stm)))
    invalid("atol_components", "must have 0, 6 or (with_stm) 42 entries, got " + std::to_string(na));
  for (size_t i = 0; i < na; ++i)
    if (!(std::isfinite(atol_components[i]) && atol_components[i] > 0.0))
      invalid("atol_components[" + std::to_string(i) + "]", "must be finite and > 0");
  if (max_steps <= 0) invalid("max_steps", "must be > 0, got " + std::to_string(max_steps));
  const int omax = method == CvodesMethod::adams ? 12 : 5;
  if (max_order < 0 || max_order > omax)
    invalid("max_order", "must be 0 (default) or 1.." + std::to_string(omax) + " for this method, got " +
                             std::to_string(max_order));
  if (!(std::isfinite(initial_step) && initial_step >= 0.0))
    invalid("initial_step",
            "must be finite and >= 0 (0: automatic), got " + detail::format_g17(initial_step));
  if (!(std::isfinite(max_step) && max_step >= 0.0))
    invalid("max_step", "must be finite and >= 0 (0: unbounded), got " + detail::format_g17(max_step));
  if (!(std::isfinite(surface_radius) && surface_radius >= 0.0))
    invalid("surface_radius",
            "must be finite and >= 0 km (0: no surface), got " + detail::format_g17(surface_radius));
}

struct CvodesPropagator::Impl {
  dynamics::ForceModel model;
  CvodesSettings settings;
  int n = kStateDim;
  detail::OrbitNewtonLu newton;  // M = I - gamma A(x_pred), shared by every 6-block
  // Failure bookkeeping (written only on failure).
  detail::RhsFailure rhs_failure;
  realtype tret_ = 0.0;  // time CVode returned (the root's time on CV_ROOT_RETURN)
  std::string cv_message;
  detail::CvodesHandles cv;  // the SUNDIALS objects (detail/cvodes.hpp); freed before cv_message

  Impl(const dynamics::ForceModel& m, const CvodesSettings& s) : model(m), settings(s) {}

  void check(int flag, const char* what) { detail::cvodes_check(flag, what, cv_message); }

  static int rhs(realtype t, N_Vector yv, N_Vector ydot, void* user) {
    auto* p = static_cast<Impl*>(user);
    const double* yd = N_VGetArrayPointer(yv);
    double* fd = N_VGetArrayPointer(ydot);
    const Eigen::Map<const Vec3> r(yd), v(yd + 3);
    if (!(r.squaredNorm() > 0.0) || !std::isfinite(r.squaredNorm() + v.squaredNorm())) {
      return p->rhs_failure.record(t);  // recoverable: CVODES retries with a smaller step, then fails
    }
    Vec3 a;
    if (p->n == kStateDim) {
      a = p->model.acceleration(t, r, v);
    } else {
      Mat3 g, d;
      p->model.acceleration_jacobians(t, r, v, a, g, d);
      const Eigen::Map<const Mat6> phi(yd + 6);
      Eigen::Map<Mat6> dphi(fd + 6);
      dphi.topRows<3>() = phi.bottomRows<3>();
      if (p->model.drag || p->model.atmosphere_drag)  // velocity-dependent terms (drag)
        dphi.bottomRows<3>().noalias() = g * phi.topRows<3>() + d * phi.bottomRows<3>();
      else
        dphi.bottomRows<3>().noalias() = g * phi.topRows<3>();
    }
    if (!a.allFinite()) return p->rhs_failure.record(t);
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

  void setup() {
    settings.validate();
    model.validate();
    n = settings.with_stm ? kAugDim : kStateDim;
    CvodesCorrector c = settings.corrector;
    if (c == CvodesCorrector::automatic) c = CvodesCorrector::newton;  // measured: see docs/propagation.md
    detail::CvodesSetup cs;
    cs.n = n;
    cs.adams = settings.method == CvodesMethod::adams;
    cs.serial_vector = settings.vector != CvodesVector::satgnc;
    cs.y_first = 1.0;
    cs.rhs = &Impl::rhs;
    cs.user_data = this;
    cs.rtol = settings.rtol;
    cs.atol = settings.atol;
    cs.atol_components = &settings.atol_components;  // 6 entries with the STM: the rest get atol
    cs.max_order = settings.max_order;
    cs.max_step = settings.max_step;
    cs.newton = c != CvodesCorrector::fixed_point;
    cs.ls_solve = &Impl::ls_solve;
    detail::cvodes_create(cs, cv, cv_message);
    // only entering the body is an impact
    if (settings.surface_radius > 0.0) detail::cvodes_root_downward(cv.mem, &Impl::surface_root, cv_message);
  }

  // g = |r|^2 - R^2: positive above the surface; CVODES stops where it crosses zero downward.
  static int surface_root(realtype, N_Vector yv, realtype* g, void* user) {
    const auto* p = static_cast<const Impl*>(user);
    const double* yd = N_VGetArrayPointer(yv);
    const double R = p->settings.surface_radius;
    g[0] = yd[0] * yd[0] + yd[1] * yd[1] + yd[2] * yd[2] - R * R;
    return 0;
  }

  static PropagationStatus map_flag(int flag) { return detail::cvodes_flag_status(flag); }

  void record(Trajectory& out, double t) const {
    const double* yd = N_VGetArrayPointer(cv.y);
    out.times.push_back(t);
    out.states.push_back(Eigen::Map<const Vec6>(yd));
    if (n == kAugDim) out.stms.push_back(Eigen::Map<const Mat6>(yd + 6));
  }

  void fill_stats(Trajectory& out) const {
    detail::cvodes_read_stats(cv.mem, out.stats);
    out.stats.lin_setups = newton.lin_setups;
  }

  void run(const Vec6& x0, double t0, const std::vector<double>& times, Trajectory& out) {
    validate_orbit_arc_input(x0, t0, times, kOneSidedArc, kGravitySingular);
    const double R = settings.surface_radius;
    if (R > 0.0 && !(x0.head<3>().norm() > R))
      invalid("x0",
              "starts at or below the surface: |r0| = " + detail::format_g17(x0.head<3>().norm()) +
                  " km <= surface_radius = " + detail::format_g17(R) + " km",
              "x0 = [r km, v km/s]; surface_radius = 0 disables the surface");
    out.times.clear();
    out.states.clear();
    out.stms.clear();
    out.times.reserve(times.size());
    out.states.reserve(times.size());
    if (n == kAugDim) out.stms.reserve(times.size());
    out.stats = PropagationStats{};
    out.status = PropagationStatus::success;
    out.message.clear();
    out.t_reached = t0;
    rhs_failure.failed = false;
    newton.lin_setups = 0;

    double* yd = N_VGetArrayPointer(cv.y);
    Eigen::Map<Vec6> ystate(yd);
    ystate = x0;
    if (n == kAugDim) Eigen::Map<Mat6>(yd + 6).setIdentity();
    size_t i = 0;
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
        tret_ = t0;
        flag = CVode(cv.mem, times[i], cv.y, &tret_, CV_NORMAL);
        CVodeGetNumSteps(cv.mem, &used);
      }
      if (flag < 0) {
        fail(out, flag, times[i], times.size());
        return;
      }
      if (flag == CV_ROOT_RETURN) {
        impact(out, tret_, times[i], times.size());
        return;
      }
      record(out, times[i]);
    }
    out.t_reached = times.back();
    fill_stats(out);
  }

  void impact(Trajectory& out, double t_hit, double target, size_t n_requested) {
    fill_stats(out);
    out.t_reached = t_hit;
    out.status = PropagationStatus::impact;
    // One snprintf into a stack buffer: a reused Trajectory keeps its message capacity, so an impact
    // in a reused workspace allocates nothing (test_cvodes.cpp).
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "CVODES: impact at t = %.17g s: |r| reached surface_radius = %.17g km before t = %.17g s "
                  "(%zu of %zu outputs returned)",
                  t_hit, settings.surface_radius, target, out.times.size(), n_requested);
    out.message.assign(buf);
  }

  void fail(Trajectory& out, int flag, double target, size_t n_requested) {
    fill_stats(out);
    realtype tcur = out.t_reached;
    if (out.stats.steps > 0) CVodeGetCurrentTime(cv.mem, &tcur);
    out.t_reached = tcur;
    out.status = map_flag(flag);
    if (flag == CV_TOO_MUCH_WORK)
      cv_message = "max_steps = " + std::to_string(settings.max_steps) + " steps taken (" +
                   std::to_string(out.stats.steps) + ")";
    out.message = std::string("CVODES stopped at t = ") + detail::format_g17(tcur) +
                  " s before reaching t = " + detail::format_g17(target) + " s (" +
                  std::to_string(out.times.size()) + " of " + std::to_string(n_requested) +
                  " outputs returned): " + status_message(out.status);
    rhs_failure.describe(out.message, "the force model", " s");
    if (!cv_message.empty()) out.message += " [CVODES: " + cv_message + "]";
    cv_message.clear();
  }
};

CvodesPropagator::CvodesPropagator(const dynamics::ForceModel& model, const CvodesSettings& settings)
    : impl_(std::make_unique<Impl>(model, settings)) {
  impl_->setup();
}
CvodesPropagator::~CvodesPropagator() = default;
CvodesPropagator::CvodesPropagator(CvodesPropagator&&) noexcept = default;
CvodesPropagator& CvodesPropagator::operator=(CvodesPropagator&&) noexcept = default;

Trajectory CvodesPropagator::propagate(const Vec6& x0, double t0, const std::vector<double>& times) {
  Trajectory out;
  impl_->run(x0, t0, times, out);
  return out;
}

void CvodesPropagator::propagate(const Vec6& x0, double t0, const std::vector<double>& times,
                                 Trajectory& out) {
  // Allocation-free into a reused Trajectory (test_cvodes.cpp counts operator new); the guard sees
  // Eigen only: CVODES's own mallocs (none after setup in this path) are seen by that counter.
  SATGNC_NO_MALLOC_SCOPE;
  impl_->run(x0, t0, times, out);
}

const dynamics::ForceModel& CvodesPropagator::model() const { return impl_->model; }
const CvodesSettings& CvodesPropagator::settings() const { return impl_->settings; }

Trajectory propagate_cvodes(const dynamics::ForceModel& model, const Vec6& x0, double t0,
                            const std::vector<double>& times, const CvodesSettings& settings) {
  CvodesPropagator p(model, settings);
  return p.propagate(x0, t0, times);
}

}  // namespace satgnc::propagation
