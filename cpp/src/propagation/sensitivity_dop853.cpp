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
// column 6 + j of S adds [0; da/dp_j] (detail::variational_column, dop853.hpp).
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
    for (int j = 0; j < 6 + K; ++j) {
      const double* pc = y.data() + 6 + 6 * j;
      double* dc = dy.data() + 6 + 6 * j;
      if (j >= 6) {
        const Vec3 b = fm.acceleration_partial(params[static_cast<std::size_t>(j - 6)], t, r, v);
        detail::variational_column<VelocityDependent>(da_dr.data(), da_dv.data(), pc, dc, b.data());
      } else {
        detail::variational_column<VelocityDependent>(da_dr.data(), da_dv.data(), pc, dc);
      }
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
  std::vector<Vec6> states(n);
  std::vector<Mat6> stms(n);
  std::vector<SensitivityMatrix> sens(n, SensitivityMatrix::Zero(6, k));
  Trajectory& tr = st.trajectory;
  const std::vector<char> done =
      detail::dop853_two_arcs("propagate_dop853_sensitivity", t0, times, surface_radius, tr,
                              [&](const std::vector<std::size_t>& idx, const std::vector<double>& ts) {
                                const std::size_t m = idx.size();
                                std::vector<Vec6> xs(m);
                                std::vector<Mat6> ps(m);
                                std::vector<SensitivityMatrix> ss(m, SensitivityMatrix::Zero(6, k));
                                Dop853Info info;
                                switch (k) {
                                  case 1:
                                    dispatch_arc<1>(vd, fm, parameters, x0, t0, ts.data(), m, settings,
                                                    xs.data(), ps.data(), ss.data(), info, surface_radius);
                                    break;
                                  case 2:
                                    dispatch_arc<2>(vd, fm, parameters, x0, t0, ts.data(), m, settings,
                                                    xs.data(), ps.data(), ss.data(), info, surface_radius);
                                    break;
                                  default:
                                    dispatch_arc<3>(vd, fm, parameters, x0, t0, ts.data(), m, settings,
                                                    xs.data(), ps.data(), ss.data(), info, surface_radius);
                                    break;
                                }
                                for (std::size_t j = 0; j < info.outputs; ++j) {
                                  states[idx[j]] = xs[j];
                                  stms[idx[j]] = ps[j];
                                  sens[idx[j]] = ss[j];
                                }
                                return info;
                              });
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
