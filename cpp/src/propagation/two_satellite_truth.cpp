// CVODES truth flight of the two-satellite model (see two_satellite_truth.hpp).
#include "satgnc/propagation/two_satellite_truth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::propagation {

using dynamics::Mat12;
using dynamics::Mat12x3;
using dynamics::Vec12;

propagation::CvodesOdeSettings default_truth_settings() {
  propagation::CvodesOdeSettings s;
  s.rtol = 1e-11;
  s.atol_components.assign(12, 1e-6);
  for (int i = 6; i < 12; ++i) s.atol_components[static_cast<size_t>(i)] = 1e-9;
  return s;
}

struct TwoSatelliteTruth::Impl {
  struct Data {
    dynamics::TwoSatelliteModel model;
    Vec3 u = Vec3::Zero();
    explicit Data(const dynamics::TwoSatelliteModel& m) : model(m) {}
  };
  std::unique_ptr<Data> data;
  propagation::CvodesOde ode;
  std::string message;

  static propagation::CvodesOde make(Data* d, const propagation::CvodesOdeSettings& s) {
    auto rhs = [d](double, const double* y, double* ydot) {
      Vec12 f;
      if (!d->model.rhs(Eigen::Map<const Vec12>(y), d->u, f)) return false;
      Eigen::Map<Vec12> out(ydot);
      out = f;
      return true;
    };
    auto jac = [d](double, const double* y, double* J) {
      Vec12 f;
      Mat12 A;
      Mat12x3 B;
      if (!d->model.rhs_jacobians(Eigen::Map<const Vec12>(y), d->u, f, A, B)) return false;
      Eigen::Map<Mat12> out(J);
      out = A;
      return true;
    };
    return propagation::CvodesOde(12, rhs, s, jac);
  }

  Impl(const dynamics::TwoSatelliteModel& m, const propagation::CvodesOdeSettings& s)
      : data(std::make_unique<Data>(m)), ode(make(data.get(), s)) {
    const double R = m.params().j2_radius;
    ode.set_impact_function([R](double, const double* y) { return surface_margin(y, R); });
  }

  // min(|r_t|^2, |r_c|^2) - R^2 with r_c = r_t - d: > 0 while both bodies are above the surface.
  static double surface_margin(const double* y, double R) {
    const Eigen::Map<const Vec3> d(y), rt(y + 3);
    return std::min(rt.squaredNorm(), (rt - d).squaredNorm()) - R * R;
  }
};

TwoSatelliteTruth::TwoSatelliteTruth(const dynamics::TwoSatelliteModel& model,
                                     const propagation::CvodesOdeSettings& settings)
    : impl_(std::make_unique<Impl>(model, settings)) {}
TwoSatelliteTruth::~TwoSatelliteTruth() = default;
TwoSatelliteTruth::TwoSatelliteTruth(TwoSatelliteTruth&&) noexcept = default;
TwoSatelliteTruth& TwoSatelliteTruth::operator=(TwoSatelliteTruth&&) noexcept = default;

PropagationStatus TwoSatelliteTruth::step(Eigen::Ref<Eigen::VectorXd> x,
                                          const Eigen::Ref<const Eigen::VectorXd>& u, double dt) noexcept {
  impl_->message.clear();
  if (x.size() != 12 || u.size() != 3 || !u.allFinite() || !(std::isfinite(dt) && dt > 0.0)) {
    impl_->message = "invalid input: x needs 12 entries, u 3 finite entries, dt > 0";
    return PropagationStatus::solver_failure;
  }
  impl_->data->u = u;
  const PropagationStatus st = impl_->ode.integrate(0.0, x, dt);
  if (st != PropagationStatus::success) impl_->message = impl_->ode.message();
  return st;
}

TruthFlight TwoSatelliteTruth::fly(const Eigen::Ref<const Eigen::VectorXd>& x0,
                                   const Eigen::Ref<const Eigen::MatrixXd>& U, double dt) {
  core::require(x0.size() == 12, "x0", "must have 12 entries [d, r_t, w, v_t] (m, m/s)");
  core::require(U.rows() == 3 && U.cols() >= 1, "U", "must be 3 x N (N >= 1), newtons");
  core::require_positive(dt, "dt");
  core::require_finite(x0, "x0");
  const double R = impl_->data->model.params().j2_radius;
  const double rt = x0.segment<3>(3).norm(), rc = (x0.segment<3>(3) - x0.head<3>()).norm();
  if (!(std::min(rt, rc) > R))
    core::require(false, "x0",
                  std::string(rt <= R ? "the target" : "the chaser") +
                      " starts at or below the Earth's surface: |r| = " + std::to_string(std::min(rt, rc)) +
                      " m <= R = " + std::to_string(R) + " m",
                  "x0 = [d = r_t - r_c, r_t, w, v_t] in m and m/s");
  TruthFlight out;
  const int N = static_cast<int>(U.cols());
  out.X.setConstant(12, N + 1, std::numeric_limits<double>::quiet_NaN());
  out.X.col(0) = x0;
  Eigen::VectorXd x = x0;
  for (int k = 0; k < N; ++k) {
    const PropagationStatus st = step(x, U.col(k), dt);
    out.steps += impl_->ode.stats().steps;
    out.rhs_evals += impl_->ode.stats().rhs_evals;
    if (st != PropagationStatus::success) {
      out.status = st;
      out.t_reached = k * dt + impl_->ode.t_reached();
      out.failed_interval = k;
      out.message = "interval " + std::to_string(k) + ": " + impl_->message;
      return out;
    }
    out.X.col(k + 1) = x;
  }
  out.t_reached = N * dt;
  return out;
}

const std::string& TwoSatelliteTruth::message() const { return impl_->message; }
const propagation::CvodesOde& TwoSatelliteTruth::integrator() const { return impl_->ode; }
const dynamics::TwoSatelliteModel& TwoSatelliteTruth::model() const { return impl_->data->model; }

}  // namespace satgnc::propagation
