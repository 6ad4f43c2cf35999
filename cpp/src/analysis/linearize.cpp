#include "satgnc/analysis/linearize.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "satgnc/core/validate.hpp"
#include "satgnc/dynamics/cw.hpp"
#include "satgnc/dynamics/measurement.hpp"

namespace satgnc::analysis {

using Eigen::MatrixXd;
using Eigen::VectorXd;

void LinearModel::validate() const {
  core::require(
      A.rows() > 0 && A.rows() == A.cols(), "A",
      "must be square and non-empty, got " + std::to_string(A.rows()) + "x" + std::to_string(A.cols()));
  core::require_finite(A, "A");
  core::require(B.size() == 0 || B.rows() == A.rows(), "B",
                "must have n = " + std::to_string(A.rows()) + " rows, got " + std::to_string(B.rows()));
  core::require_finite(B, "B");
  core::require(C.size() == 0 || C.cols() == A.rows(), "C",
                "must have n = " + std::to_string(A.rows()) + " columns, got " + std::to_string(C.cols()));
  core::require_finite(C, "C");
}

namespace {
VectorXd scale_or_ones(const VectorXd& v, Eigen::Index size, const std::string& name) {
  if (v.size() == 0) return VectorXd::Ones(size);
  core::require(v.size() == size, name,
                "must have " + std::to_string(size) + " entries, got " + std::to_string(v.size()));
  core::require(v.allFinite() && (v.array() > 0).all(), name, "all units must be finite and > 0");
  return v;
}
}  // namespace

LinearModel nondimensionalize(const LinearModel& m, const Units& u) {
  m.validate();
  core::require_positive(u.time, "units.time");
  const Eigen::Index n = m.A.rows();
  const VectorXd dx = scale_or_ones(u.state, n, "units.state");
  const VectorXd du = scale_or_ones(u.input, m.B.cols(), "units.input");
  const VectorXd dy = scale_or_ones(u.output, m.C.rows(), "units.output");
  LinearModel s;
  s.A = u.time * dx.cwiseInverse().asDiagonal() * m.A * dx.asDiagonal();
  s.B = u.time * dx.cwiseInverse().asDiagonal() * m.B * du.asDiagonal();
  s.C = dy.cwiseInverse().asDiagonal() * m.C * dx.asDiagonal();
  return s;
}

Units polar_units(double sigma, double omega, int n_outputs) {
  core::require_positive(sigma, "sigma");
  core::require_positive(omega, "omega");
  core::require(n_outputs >= 0, "n_outputs", "must be >= 0");
  Units u;
  u.time = 1.0 / omega;
  u.state = (VectorXd(4) << sigma, sigma * omega, sigma, sigma * omega).finished();
  u.input = VectorXd::Constant(2, sigma * omega * omega);
  u.output = VectorXd::Constant(n_outputs, sigma);
  return u;
}

Units cw_units(double n, double length, int n_outputs) {
  core::require_positive(n, "mean_motion");
  core::require_positive(length, "length");
  core::require(n_outputs >= 0, "n_outputs", "must be >= 0");
  Units u;
  u.time = 1.0 / n;
  u.state = (VectorXd(6) << length, length, length, length * n, length * n, length * n).finished();
  u.input = VectorXd::Constant(3, length * n * n);
  u.output = VectorXd::Constant(n_outputs, length);
  return u;
}

void fd_jacobian(const ModelFn& f, double t, const VectorXd& x, const VectorXd& u, MatrixXd& A, MatrixXd& B,
                 const FdSettings& fd) {
  core::require(static_cast<bool>(f), "f", "must be a callable");
  core::require_finite(x, "x");
  core::require_finite(u, "u");
  core::require_positive(fd.rel_step, "fd.rel_step");
  const VectorXd xs = scale_or_ones(fd.x_scale, x.size(), "fd.x_scale");
  const VectorXd us = scale_or_ones(fd.u_scale, u.size(), "fd.u_scale");
  const VectorXd f0 = f(t, x, u);
  const Eigen::Index n = f0.size();
  A.resize(n, x.size());
  B.resize(n, u.size());
  VectorXd xp = x;
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    const double h = fd.rel_step * std::max(std::abs(x(j)), xs(j));
    xp(j) = x(j) + h;
    const VectorXd fp = f(t, xp, u);
    xp(j) = x(j) - h;
    const VectorXd fm = f(t, xp, u);
    xp(j) = x(j);
    A.col(j) = (fp - fm) / (2.0 * h);
  }
  VectorXd up = u;
  for (Eigen::Index j = 0; j < u.size(); ++j) {
    const double h = fd.rel_step * std::max(std::abs(u(j)), us(j));
    up(j) = u(j) + h;
    const VectorXd fp = f(t, x, up);
    up(j) = u(j) - h;
    const VectorXd fm = f(t, x, up);
    up(j) = u(j);
    B.col(j) = (fp - fm) / (2.0 * h);
  }
}

namespace {
double rel_diff(const MatrixXd& a, const MatrixXd& b) {
  if (a.size() == 0) return 0.0;
  const double scale = std::max(a.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  return (a - b).cwiseAbs().maxCoeff() / scale;
}
}  // namespace

Linearization linearize(const ModelFn& f, const JacobianFn& jac, double t, const VectorXd& x,
                        const VectorXd& u, const FdSettings& fd) {
  core::require(static_cast<bool>(jac), "jac", "must be a callable");
  core::require_finite(t, "t");
  Linearization L;
  fd_jacobian(f, t, x, u, L.A_fd, L.B_fd, fd);
  jac(t, x, u, L.A, L.B);
  core::require(L.A.rows() == L.A_fd.rows() && L.A.cols() == L.A_fd.cols(), "jac",
                "A must be " + std::to_string(L.A_fd.rows()) + "x" + std::to_string(L.A_fd.cols()));
  core::require(L.B.rows() == L.B_fd.rows() && L.B.cols() == L.B_fd.cols(), "jac",
                "B must be " + std::to_string(L.B_fd.rows()) + "x" + std::to_string(L.B_fd.cols()));
  core::require_finite(L.A, "jac(A)");
  core::require_finite(L.B, "jac(B)");
  L.rel_err_A = rel_diff(L.A, L.A_fd);
  L.rel_err_B = rel_diff(L.B, L.B_fd);
  return L;
}

namespace {
MatrixXd selector(const std::vector<int>& rows, int n, const std::string& name) {
  MatrixXd C = MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()), n);
  for (size_t i = 0; i < rows.size(); ++i) {
    core::require(rows[i] >= 0 && rows[i] < n, name,
                  "indices must be in [0, " + std::to_string(n - 1) + "], got " + std::to_string(rows[i]));
    C(static_cast<Eigen::Index>(i), rows[i]) = 1.0;
  }
  return C;
}
}  // namespace

LinearModel polar_linear_model(const dynamics::PolarModel& m, const std::vector<int>& measured,
                               dynamics::PolarCoordinates c) {
  LinearModel lm;
  lm.A = m.A(c);
  lm.B = m.B(c);
  lm.C = selector(measured, 4, "measured");
  return lm;
}

LinearModel cw_model(double n, const std::vector<int>& measured) {
  core::require_positive(n, "mean_motion");
  // dynamics::CwModel's matrices in the Hill frame with unit mass (B = I: thrust accelerations).
  const dynamics::CwMatrices hill =
      dynamics::cw_linear_model(dynamics::CwModel(n, 1.0), dynamics::CwFrame::hill);
  LinearModel m;
  m.A = hill.A;
  m.B = hill.B;
  m.C = selector(measured, 6, "measured");
  return m;
}

Eigen::Matrix<double, 6, 6> two_body_jacobian(const Eigen::Vector3d& r, double mu) {
  core::require_positive(mu, "mu");
  core::require_finite(r, "r");
  const double rn = r.norm();
  core::require(rn > 0.0, "r", "must be nonzero");
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  A.topRightCorner<3, 3>().setIdentity();
  A.bottomLeftCorner<3, 3>() =
      mu / (rn * rn * rn) * (3.0 * r * r.transpose() / (rn * rn) - Eigen::Matrix3d::Identity());
  return A;
}

namespace {
// dynamics::predict_measurement with its degenerate-geometry test moved to rho > 0 exactly (the
// smallest positive double as min_range), throwing as these functions always did.
double predict_or_throw(dynamics::MeasurementType type, const Vec6& x, const Vec6& station,
                        Eigen::Matrix<double, 1, 6>& H) {
  double value = 0.0;
  if (!dynamics::predict_measurement(type, x, station, value, &H, std::numeric_limits<double>::denorm_min()))
    core::require(false, "r", "satellite coincides with the station (range 0)");
  return value;
}
}  // namespace

double range_partial(const Eigen::Vector3d& r, const Eigen::Vector3d& R, Eigen::Matrix<double, 1, 6>& H) {
  Vec6 x, s;
  x << r, Vec3::Zero();
  s << R, Vec3::Zero();
  return predict_or_throw(dynamics::MeasurementType::range, x, s, H);
}

double range_rate_partial(const Eigen::Vector3d& r, const Eigen::Vector3d& v, const Eigen::Vector3d& R,
                          const Eigen::Vector3d& V, Eigen::Matrix<double, 1, 6>& H) {
  Vec6 x, s;
  x << r, v;
  s << R, V;
  return predict_or_throw(dynamics::MeasurementType::range_rate, x, s, H);
}

}  // namespace satgnc::analysis
