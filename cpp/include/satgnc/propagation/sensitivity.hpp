#pragma once
/// @file sensitivity.hpp
/// Parameter sensitivity alongside the STM (issue 14 item 5): the 6 x k matrix S(t) = dx(t)/dp for a
/// chosen subset p of the force model's parameters (ForceParameter: mu, Cd, Cr), integrated with the
/// state and the STM Phi(t) = dx(t)/dx(t0) through the variational system
///   dPhi/dt = A Phi,   dS/dt = A S + [0; da/dp],   A = [[0, I], [da/dr, da/dv]],   S(t0) = 0,
/// which grows from 6 + 36 to 6 + 36 + 6k equations. Both DOP853 (dop853.hpp) and CVODES (cvodes.hpp)
/// integrate it; the steps allocate nothing (SATGNC_NO_MALLOC_SCOPE). The partials da/dp come from
/// ForceModel::acceleration_partial, so a parameter added there (e.g. an empirical acceleration) is
/// one enum value and one name here. Units: x in km, km/s; S column j in km (or km/s) per unit of
/// p_j: per km^3/s^2 for mu, per unit Cd, per unit Cr. With no parameter the functions return
/// exactly what propagate_dop853 / CvodesPropagator return (the same call).
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "satgnc/core/types.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/propagation/cvodes.hpp"
#include "satgnc/propagation/dop853.hpp"
#include "satgnc/propagation/trajectory.hpp"

namespace satgnc::propagation {

/// Largest number of parameters in one sensitivity propagation (each ForceParameter at most once).
inline constexpr int kMaxSensitivityParameters = 3;

/// 6 x k sensitivity matrix dx/dp (rows r km, v km/s; column j per unit of parameter j).
using SensitivityMatrix = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxSensitivityParameters>;

/// The ForceParameter named `name`: "mu", "cd" or "cr" (lower case). Throws
/// std::invalid_argument("parameters: unknown parameter '<name>' ...") naming the accepted names.
dynamics::ForceParameter force_parameter_from_name(const std::string& name);
/// The ForceParameters named by `names` in order (choosing the parameters by name, as Python does:
/// {"cd", "cr"}); throws like force_parameter_from_name.
std::vector<dynamics::ForceParameter> force_parameters_from_names(const std::vector<std::string>& names);
/// The name of a ForceParameter ("mu", "cd", "cr").
const char* force_parameter_name(dynamics::ForceParameter p);

/// Throw std::invalid_argument naming `parameters` unless there are at most kMaxSensitivityParameters,
/// none repeated, and each has its term in `model` (cr needs srp, cd needs drag or atmosphere_drag).
void validate_sensitivity_parameters(const dynamics::ForceModel& model,
                                     const std::vector<dynamics::ForceParameter>& parameters);

/// A propagation with its parameter sensitivities: trajectory.states, trajectory.stms (always filled)
/// and one 6 x k sensitivity per output time (the same times as trajectory.times).
struct SensitivityTrajectory {
  Trajectory trajectory;                             ///< states (km, km/s), STMs, stats, status
  std::vector<dynamics::ForceParameter> parameters;  ///< the k parameters, in the columns' order
  std::vector<SensitivityMatrix> sensitivities;      ///< dx(t_i)/dp, 6 x k; empty columns when k = 0
};

/// DOP853 propagation of the state, the STM and dx/dp for `parameters` (any order, each at most
/// once; empty: the plain STM propagation, bit-for-bit propagate_dop853(..., with_stm = true)).
/// Times and surface_radius as in propagate_dop853 (two arcs from t0). The error control covers the
/// state, the STM and S (so with k > 0 the steps, and Phi in its last digits, differ from the k = 0 run).
/// @throws std::invalid_argument naming the argument (bad x0/t0/times/settings/model/parameters).
SensitivityTrajectory propagate_dop853_sensitivity(const dynamics::ForceModel& model, const Vec6& x0,
                                                   double t0, const std::vector<double>& times,
                                                   const std::vector<dynamics::ForceParameter>& parameters,
                                                   const Dop853Settings& settings = {},
                                                   double surface_radius = 0.0);

/// CVODES propagator of the state, the STM and dx/dp, bound to one force model and one parameter
/// set: the CVODES memory is sized once (6 + 36 + 6k) and reused by every propagate() call.
/// settings.with_stm must be true; atol_components may hold 0, 6 or 42 entries (S entries get atol).
/// The Newton corrector solves every 6-block (state, STM columns, S columns) with one LU of
/// I - gamma A, as CvodesPropagator does.
class CvodesSensitivityPropagator {
 public:
  /// Validate model, settings and parameters; allocate every CVODES resource (throws
  /// std::invalid_argument naming the argument, std::runtime_error when SUNDIALS cannot allocate).
  CvodesSensitivityPropagator(const dynamics::ForceModel& model,
                              const std::vector<dynamics::ForceParameter>& parameters,
                              const CvodesSettings& settings = {});
  ~CvodesSensitivityPropagator();
  CvodesSensitivityPropagator(CvodesSensitivityPropagator&&) noexcept;
  CvodesSensitivityPropagator& operator=(CvodesSensitivityPropagator&&) noexcept;
  CvodesSensitivityPropagator(const CvodesSensitivityPropagator&) = delete;
  CvodesSensitivityPropagator& operator=(const CvodesSensitivityPropagator&) = delete;

  /// Propagate x0 (km, km/s) at t0 (s) to `times` (CVODES rules: strictly monotone, one side of t0).
  SensitivityTrajectory propagate(const Vec6& x0, double t0, const std::vector<double>& times);
  /// Same into `out`; allocation-free (SATGNC_NO_MALLOC_SCOPE) once `out` has the capacity.
  void propagate(const Vec6& x0, double t0, const std::vector<double>& times, SensitivityTrajectory& out);

  /// The parameters, in the columns' order.
  const std::vector<dynamics::ForceParameter>& parameters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot convenience: build a CvodesSensitivityPropagator and propagate once.
SensitivityTrajectory propagate_cvodes_sensitivity(const dynamics::ForceModel& model, const Vec6& x0,
                                                   double t0, const std::vector<double>& times,
                                                   const std::vector<dynamics::ForceParameter>& parameters,
                                                   const CvodesSettings& settings = {});

}  // namespace satgnc::propagation
