// Two-satellite discrete map from DOP853 integration of the state, STM and control sensitivity.
#include "satgnc/propagation/propagated_map.hpp"

#include <cmath>
#include <limits>

#include "detail/map_scaling.hpp"
#include "satgnc/core/validate.hpp"
#include "satgnc/propagation/dop853.hpp"

namespace satgnc::propagation {

namespace {
using dynamics::Mat12;
using dynamics::Mat12x3;
using dynamics::Vec12;
constexpr int kAug = 12 + 144 + 36;
using VecAug = Eigen::Matrix<double, kAug, 1>;

// Right-hand sides in the solver's (scaled) variables z = x / sx, v = u / su:
//   z' = f(Sx z, Su v) / sx,  Phi_s' = As Phi_s,  Gam_s' = As Gam_s + Bs,
// As = Sx^-1 A Sx, Bs = Sx^-1 B Su. A failure (radius below min_radius, non-finite) writes NaN, which
// DOP853 turns into a rejected step and finally a failure status.
struct Rhs {
  const dynamics::TwoSatelliteModel* model = nullptr;
  const Vec12* sx = nullptr;
  const Vec3* su = nullptr;
  double min_r2 = 0.0;
  Vec3 u = Vec3::Zero();  // SI, set per interval

  bool above_surface(const Vec12& x) const {
    const double rt2 = x.segment<3>(3).squaredNorm();
    const double rc2 = (x.segment<3>(3) - x.head<3>()).squaredNorm();
    return rt2 >= min_r2 && rc2 >= min_r2;
  }
};

struct StateRhs : Rhs {
  void operator()(double, const Vec12& z, Vec12& dz) const {
    const Vec12 x = z.cwiseProduct(*sx);
    if (!above_surface(x) || !model->rhs(x, u, dz)) {
      dz.setConstant(std::numeric_limits<double>::quiet_NaN());
      return;
    }
    dz.array() /= sx->array();
  }
};

struct AugRhs : Rhs {
  void operator()(double, const VecAug& y, VecAug& dy) const {
    const Vec12 x = y.head<12>().cwiseProduct(*sx);
    Vec12 f;
    Mat12 A;
    Mat12x3 B;
    if (!above_surface(x) || !model->rhs_jacobians(x, u, f, A, B)) {
      dy.setConstant(std::numeric_limits<double>::quiet_NaN());
      return;
    }
    dy.head<12>() = f.cwiseQuotient(*sx);
    // Rows 0-5 of A are [0 I] (d' = w, r_t' = v_t): row i of A Phi is row i+6 of Phi. Rows 6-11 dense.
    Eigen::Matrix<double, 6, 12> As;
    for (int j = 0; j < 12; ++j)
      for (int i = 0; i < 6; ++i) As(i, j) = A(6 + i, j) * (*sx)(j) / (*sx)(6 + i);
    Eigen::Matrix<double, 6, 3> Bs;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 6; ++i) Bs(i, j) = B(6 + i, j) * (*su)(j) / (*sx)(6 + i);
    const Eigen::Map<const Mat12> Phi(y.data() + 12);
    const Eigen::Map<const Mat12x3> Gam(y.data() + 156);
    Eigen::Map<Mat12> dPhi(dy.data() + 12);
    Eigen::Map<Mat12x3> dGam(dy.data() + 156);
    for (int i = 0; i < 6; ++i) {
      const double c = (*sx)(6 + i) / (*sx)(i);
      dPhi.row(i) = c * Phi.row(6 + i);
      dGam.row(i) = c * Gam.row(6 + i);
    }
    dPhi.bottomRows<6>().noalias() = As * Phi;
    dGam.bottomRows<6>().noalias() = As * Gam;
    dGam.bottomRows<6>() += Bs;
  }
};
}  // namespace

struct PropagatedTwoSatelliteMap::Work {
  StateRhs state_rhs;
  AugRhs aug_rhs;
  propagation::Dop853<12, StateRhs> state_int;
  propagation::Dop853<kAug, AugRhs> aug_int;
  VecAug y0;
  Work(const propagation::Dop853Settings& ds) : state_int(state_rhs, ds), aug_int(aug_rhs, ds) {}
};

PropagatedTwoSatelliteMap::PropagatedTwoSatelliteMap(const dynamics::TwoSatelliteModel& model,
                                                     const PropagatedMapSettings& settings)
    : model_(model), s_(settings) {
  using core::require;
  core::require_positive(s_.dt, "dt");
  core::require_positive(s_.rtol, "rtol");
  core::require_nonnegative(s_.atol, "atol");
  require(s_.max_steps > 0, "max_steps", "must be > 0");
  require(std::isfinite(s_.min_radius) && s_.min_radius >= 0.0, "min_radius", "must be finite and >= 0 (m)");
  detail::set_map_scaling(s_.state_scale, s_.control_scale, sx_, su_);
  propagation::Dop853Settings ds;
  ds.rtol = s_.rtol;
  ds.atol = s_.atol;
  ds.max_steps = s_.max_steps;
  propagation::dop853_validate_settings(ds);  // names rtol (> 10 eps) etc.
  work_ = std::make_unique<Work>(ds);
  for (Rhs* r : {static_cast<Rhs*>(&work_->state_rhs), static_cast<Rhs*>(&work_->aug_rhs)}) {
    r->model = &model_;
    r->sx = &sx_;
    r->su = &su_;
    r->min_r2 = s_.min_radius * s_.min_radius;
  }
}

PropagatedTwoSatelliteMap::~PropagatedTwoSatelliteMap() = default;

bool PropagatedTwoSatelliteMap::step(int k, const double* x, const double* u, double* x_next, double* A,
                                     double* B) const {
  Work& w = *work_;
  info_ = PropagatedMapInfo();
  info_.interval = k;
  const Eigen::Map<const Vec12> z0(x);
  const Vec3 us = Eigen::Map<const Vec3>(u).cwiseProduct(su_);
  const bool jac = A != nullptr && B != nullptr;
  propagation::Dop853Info di;
  const double t_end = s_.dt;
  if (!jac) {
    w.state_rhs.u = us;
    Eigen::Map<Vec12> xn(x_next);
    di = w.state_int.solve(0.0, z0, &t_end, 1, [&](std::size_t, double, const Vec12& y) { xn = y; });
  } else {
    w.aug_rhs.u = us;
    w.y0.head<12>() = z0;
    Eigen::Map<Mat12>(w.y0.data() + 12).setIdentity();
    Eigen::Map<Mat12x3>(w.y0.data() + 156).setZero();
    di = w.aug_int.solve(0.0, w.y0, &t_end, 1, [&](std::size_t, double, const VecAug& y) {
      Eigen::Map<Vec12> xn(x_next);
      Eigen::Map<Mat12> a(A);
      Eigen::Map<Mat12x3> b(B);
      xn = y.head<12>();
      a = Eigen::Map<const Mat12>(y.data() + 12);
      b = Eigen::Map<const Mat12x3>(y.data() + 156);
    });
  }
  info_.status = static_cast<int>(di.status);
  info_.steps = di.steps;
  info_.rejected = di.rejected;
  info_.rhs_evals = di.rhs_evals;
  info_.t_reached = di.t_reached;
  info_.ok = di.status == propagation::Dop853Status::success && di.outputs == 1 &&
             Eigen::Map<const Vec12>(x_next).allFinite() &&
             (!jac || (Eigen::Map<const Mat12>(A).allFinite() && Eigen::Map<const Mat12x3>(B).allFinite()));
  return info_.ok;
}

}  // namespace satgnc::propagation
