// DOP853 propagation of the state, the STM and the parameter sensitivity dx/dp (issue 14 item 5).
#include <algorithm>
#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "satgnc/core/validate.hpp"
#include "satgnc/propagation/sensitivity.hpp"

namespace satgnc::propagation {

using dynamics::ForceModel;
using dynamics::ForceParameter;

dynamics::ForceParameter force_parameter_from_name(const std::string& name) {
  if (name == "mu") return ForceParameter::mu;
  if (name == "cd") return ForceParameter::cd;
  if (name == "cr") return ForceParameter::cr;
  core::require(false, "parameters", "unknown parameter '" + name + "'", "use 'mu', 'cd' or 'cr'");
  throw std::logic_error("unreachable");
}

std::vector<dynamics::ForceParameter> force_parameters_from_names(const std::vector<std::string>& names) {
  std::vector<dynamics::ForceParameter> ps;
  ps.reserve(names.size());
  for (const std::string& n : names) ps.push_back(force_parameter_from_name(n));
  return ps;
}

const char* force_parameter_name(dynamics::ForceParameter p) {
  switch (p) {
    case ForceParameter::mu:
      return "mu";
    case ForceParameter::cd:
      return "cd";
    case ForceParameter::cr:
      return "cr";
  }
  return "unknown";
}

void validate_sensitivity_parameters(const ForceModel& model, const std::vector<ForceParameter>& parameters) {
  core::require(parameters.size() <= static_cast<std::size_t>(kMaxSensitivityParameters), "parameters",
                "at most " + std::to_string(kMaxSensitivityParameters) + " parameters, got " +
                    std::to_string(parameters.size()));
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    const ForceParameter p = parameters[i];
    const std::string name = force_parameter_name(p);
    core::require(name != "unknown", "parameters", "unknown ForceParameter at index " + std::to_string(i));
    for (std::size_t j = 0; j < i; ++j)
      core::require(parameters[j] != p, "parameters", "'" + name + "' is given twice");
    if (p == ForceParameter::cr)
      core::require(model.srp.has_value(), "parameters", "'cr' needs an srp term in the force model");
    if (p == ForceParameter::cd)
      core::require(model.drag.has_value() || model.atmosphere_drag.has_value(), "parameters",
                    "'cd' needs a drag or atmosphere_drag term in the force model");
  }
}

namespace {

// Right-hand side of [x; Phi; S] (6 + 36 + 6K): every column c of [Phi S] obeys dc/dt = A c, and
// column 6 + j of S adds [0; da/dp_j]. Scalar loops as in detail::OrbitRhs (dop853.hpp).
template <int K, bool VelocityDependent>
struct SensitivityRhs {
  static constexpr int N = 42 + 6 * K;
  using Vec = Eigen::Matrix<double, N, 1>;
  const ForceModel& fm;
  std::array<ForceParameter, K> params;

  void operator()(double t, const Vec& y, Vec& dy) const {
    const Vec3 r = y.template head<3>();
    const Vec3 v = y.template segment<3>(3);
    Vec3 a;
    Mat3 da_dr, da_dv;
    fm.acceleration_jacobians(t, r, v, a, da_dr, da_dv);
    dy.template head<3>() = v;
    dy.template segment<3>(3) = a;
    const double* G = da_dr.data();  // column-major
    const double* H = da_dv.data();
    for (int j = 0; j < 6 + K; ++j) {
      const double* pc = y.data() + 6 + 6 * j;
      double* dc = dy.data() + 6 + 6 * j;
      const double p0 = pc[0], p1 = pc[1], p2 = pc[2], q0 = pc[3], q1 = pc[4], q2 = pc[5];
      double a0 = G[0] * p0 + G[3] * p1 + G[6] * p2;
      double a1 = G[1] * p0 + G[4] * p1 + G[7] * p2;
      double a2 = G[2] * p0 + G[5] * p1 + G[8] * p2;
      if constexpr (VelocityDependent) {
        a0 += H[0] * q0 + H[3] * q1 + H[6] * q2;
        a1 += H[1] * q0 + H[4] * q1 + H[7] * q2;
        a2 += H[2] * q0 + H[5] * q1 + H[8] * q2;
      }
      if (j >= 6) {
        const Vec3 b = fm.acceleration_partial(params[static_cast<std::size_t>(j - 6)], t, r, v);
        a0 += b[0];
        a1 += b[1];
        a2 += b[2];
      }
      dc[0] = q0;
      dc[1] = q1;
      dc[2] = q2;
      dc[3] = a0;
      dc[4] = a1;
      dc[5] = a2;
    }
  }
};

template <int K, bool VD>
void run_sensitivity_arc(const ForceModel& fm, const std::vector<ForceParameter>& parameters, const Vec6& x0,
                         double t0, const double* ts, std::size_t n, const Dop853Settings& settings,
                         Vec6* states, Mat6* stms, SensitivityMatrix* sens, Dop853Info& info,
                         double surface_radius) {
  using R = SensitivityRhs<K, VD>;
  using Vec = typename R::Vec;
  R rhs{fm, {}};
  for (int j = 0; j < K; ++j)
    rhs.params[static_cast<std::size_t>(j)] = parameters[static_cast<std::size_t>(j)];
  Dop853<R::N, R> integ(rhs, settings);
  Vec y0 = Vec::Zero();
  y0.template head<6>() = x0;
  Eigen::Map<Mat6>(y0.data() + 6).setIdentity();
  auto out = [&](std::size_t i, double, const Vec& y) {
    states[i] = y.template head<6>();
    stms[i] = Eigen::Map<const Mat6>(y.data() + 6);
    sens[i] = Eigen::Map<const Eigen::Matrix<double, 6, K>>(y.data() + 42);  // fixed max storage: no heap
  };
  if (surface_radius > 0.0) {
    const double r2 = surface_radius * surface_radius;
    info = integ.solve(t0, y0, ts, n, out,
                       [r2](double, const Vec& y) { return y.template head<3>().squaredNorm() - r2; });
  } else {
    info = integ.solve(t0, y0, ts, n, out);
  }
}

template <int K>
void dispatch_arc(bool velocity_dependent, const ForceModel& fm, const std::vector<ForceParameter>& p,
                  const Vec6& x0, double t0, const double* ts, std::size_t n, const Dop853Settings& s,
                  Vec6* states, Mat6* stms, SensitivityMatrix* sens, Dop853Info& info, double surface) {
  if (velocity_dependent)
    run_sensitivity_arc<K, true>(fm, p, x0, t0, ts, n, s, states, stms, sens, info, surface);
  else
    run_sensitivity_arc<K, false>(fm, p, x0, t0, ts, n, s, states, stms, sens, info, surface);
}

}  // namespace

SensitivityTrajectory propagate_dop853_sensitivity(const ForceModel& model, const Vec6& x0, double t0,
                                                   const std::vector<double>& times,
                                                   const std::vector<ForceParameter>& parameters,
                                                   const Dop853Settings& settings, double surface_radius) {
  model.validate();
  validate_sensitivity_parameters(model, parameters);
  SensitivityTrajectory st;
  st.parameters = parameters;
  const int k = static_cast<int>(parameters.size());
  if (k == 0) {  // the plain STM propagation, the same call (bit-for-bit)
    st.trajectory = propagate_dop853(model, x0, t0, times, settings, true, surface_radius);
    st.sensitivities.assign(st.trajectory.times.size(), SensitivityMatrix(6, 0));
    return st;
  }
  validate_orbit_arc_input(x0, t0, times, kTwoSidedArc, kGravitySingular);
  dop853_validate_settings(settings);
  dop853_validate_surface(x0, surface_radius);
  // A private copy: the gravity field and the ephemeris cache evaluate into their own workspace.
  const ForceModel fm = model;
  const bool vd = fm.drag.has_value() || fm.atmosphere_drag.has_value();
  const std::size_t n = times.size();
  std::vector<std::size_t> fwd, bwd;  // two arcs from t0, as propagate_dop853_with
  for (std::size_t i = 0; i < n; ++i) (times[i] >= t0 ? fwd : bwd).push_back(i);
  const bool ascending = n < 2 || times.front() <= times.back();
  if (!ascending) std::reverse(fwd.begin(), fwd.end());
  if (ascending) std::reverse(bwd.begin(), bwd.end());
  std::vector<Vec6> states(n);
  std::vector<Mat6> stms(n);
  std::vector<SensitivityMatrix> sens(n, SensitivityMatrix::Zero(6, k));
  std::vector<char> done(n, 0);
  Trajectory& tr = st.trajectory;
  tr.status = PropagationStatus::success;
  tr.t_reached = t0;
  bool failed = false;
  auto arc = [&](const std::vector<std::size_t>& idx, const char* name) {
    if (idx.empty() || failed) return;
    const std::size_t m = idx.size();
    std::vector<double> ts(m);
    std::vector<Vec6> xs(m);
    std::vector<Mat6> ps(m);
    std::vector<SensitivityMatrix> ss(m, SensitivityMatrix::Zero(6, k));
    for (std::size_t j = 0; j < m; ++j) ts[j] = times[idx[j]];
    Dop853Info info;
    switch (k) {
      case 1:
        dispatch_arc<1>(vd, fm, parameters, x0, t0, ts.data(), m, settings, xs.data(), ps.data(), ss.data(),
                        info, surface_radius);
        break;
      case 2:
        dispatch_arc<2>(vd, fm, parameters, x0, t0, ts.data(), m, settings, xs.data(), ps.data(), ss.data(),
                        info, surface_radius);
        break;
      default:
        dispatch_arc<3>(vd, fm, parameters, x0, t0, ts.data(), m, settings, xs.data(), ps.data(), ss.data(),
                        info, surface_radius);
        break;
    }
    for (std::size_t j = 0; j < info.outputs; ++j) {
      states[idx[j]] = xs[j];
      stms[idx[j]] = ps[j];
      sens[idx[j]] = ss[j];
      done[idx[j]] = 1;
    }
    tr.stats.steps += info.steps;
    tr.stats.rhs_evals += info.rhs_evals;
    tr.stats.error_test_fails += info.rejected;
    if (info.steps > 0) tr.stats.last_step = info.h_last;
    tr.t_reached = info.t_reached;
    if (info.status == Dop853Status::event) {
      failed = true;
      tr.status = PropagationStatus::impact;
      tr.message = std::string("propagate_dop853_sensitivity (") + name +
                   " arc): impact at t = " + std::to_string(info.t_reached) +
                   " s: |r| reached surface_radius = " + std::to_string(surface_radius) + " km";
    } else if (info.status != Dop853Status::success) {
      failed = true;
      tr.status = dop853_to_propagation_status(info.status);
      tr.message = std::string("propagate_dop853_sensitivity (") + name +
                   " arc): " + status_message(info.status) +
                   "; reached t = " + std::to_string(info.t_reached) + " s after " +
                   std::to_string(info.steps) + " steps";
    }
  };
  if (!bwd.empty() && times.front() < t0) {
    arc(bwd, "backward");
    arc(fwd, "forward");
  } else {
    arc(fwd, "forward");
    arc(bwd, "backward");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!done[i]) continue;
    tr.times.push_back(times[i]);
    tr.states.push_back(states[i]);
    tr.stms.push_back(stms[i]);
    st.sensitivities.push_back(sens[i]);
  }
  return st;
}

}  // namespace satgnc::propagation
