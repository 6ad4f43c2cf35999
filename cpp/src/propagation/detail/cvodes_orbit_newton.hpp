#pragma once
// Private to the propagation room: the matrix-embedded Newton linear solver of the orbit integrators
// on CVODES (CvodesPropagator, CvodesSensitivityPropagator).
#include <Eigen/LU>

#include "cvodes.hpp"
#include "satgnc/dynamics/force_model.hpp"

namespace satgnc::propagation::detail {

/// Block-diagonal Newton matrix M = I - gamma A(x_pred), A the 6 x 6 state Jacobian, shared by the
/// state and every variational column (STM, parameter sensitivities: their source terms do not enter
/// M). CVODES 6.4 never calls setup() on a matrix-embedded solver (it disables lsetup for that type),
/// so solve() refreshes M itself whenever the step (t, gamma) changed: modified Newton with the
/// Jacobian at the predicted state, refreshed every step. The coupling block d(A Phi)/dx (second
/// derivatives of the force) is neglected; Newton then converges linearly on the variational part,
/// which costs iterations but not accuracy (the residual is exact). No allocation.
struct OrbitNewtonLu {
  Eigen::PartialPivLU<Mat6> lu;
  long lin_setups = 0;  ///< factorizations since the last reset (PropagationStats::lin_setups)
  double lu_t = 0.0, lu_gamma = 0.0;

  /// x = M^-1 b block by block over the n (a multiple of 6) entries; a SUNLS_* flag.
  int solve(void* mem, const dynamics::ForceModel& model, int n, N_Vector x, N_Vector b) noexcept {
    realtype tcur, gamma;
    N_Vector ypred;
    if (!cvodes_newton_point(mem, tcur, gamma, ypred)) return SUNLS_PACKAGE_FAIL_UNREC;
    if (lin_setups == 0 || tcur != lu_t || gamma != lu_gamma) {
      const double* yd = N_VGetArrayPointer(ypred);
      const Eigen::Map<const Vec3> r(yd), v(yd + 3);
      Vec3 a;
      Mat3 g, d;
      model.acceleration_jacobians(tcur, r, v, a, g, d);
      Mat6 m = Mat6::Identity();
      m.topRightCorner<3, 3>().diagonal().array() -= gamma;
      m.bottomLeftCorner<3, 3>() = -gamma * g;
      m.bottomRightCorner<3, 3>() -= gamma * d;
      if (!m.allFinite()) return SUNLS_PACKAGE_FAIL_REC;
      lu.compute(m);
      lu_t = tcur;
      lu_gamma = gamma;
      ++lin_setups;
    }
    const double* bd = N_VGetArrayPointer(b);
    double* xd = N_VGetArrayPointer(x);
    for (int k = 0; k < n; k += 6) {
      Eigen::Map<Vec6> xk(xd + k);
      xk = lu.solve(Eigen::Map<const Vec6>(bd + k));
    }
    return SUNLS_SUCCESS;
  }
};

}  // namespace satgnc::propagation::detail
