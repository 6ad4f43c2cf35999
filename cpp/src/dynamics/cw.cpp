// Clohessy-Wiltshire model in the frame of the L1 rendezvous paper's implementation (see cw.hpp).
#include "satgnc/dynamics/cw.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::dynamics {

namespace {
// Rejects |n t| beyond kCwMaxAngle, naming the caller's time argument; builds no string on success.
void require_cw_angle(double n, double t, const char* name) {
  const double th = std::abs(n * t);
  if (th <= kCwMaxAngle) return;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g", th);
  core::require(false, name,
                "|n " + std::string(name) + "| = " + buf +
                    " rad exceeds 1e9 rad (~1.6e8 revolutions): the rounding of n t alone leaves fewer "
                    "than 6 correct digits in the CW matrices",
                "check the units: t in s, n in rad/s");
}
}  // namespace

CwModel::CwModel(double mean_motion, double chaser_mass) : n(mean_motion), mass(chaser_mass) {
  core::require_positive(mean_motion, "n");
  core::require_positive(chaser_mass, "mass");
  // n^2 enters A and the STM: n = 1e300 gave infinite entries, n = 1e-300 a zero n^2.
  core::require(mean_motion >= 1e-100 && mean_motion <= 1e100, "n",
                "must be in [1e-100, 1e100] rad/s (n^2 would overflow or underflow)", "check the units");
}

Mat6 CwModel::A() const {
  Mat6 a = Mat6::Zero();
  a.block<3, 3>(0, 3).setIdentity();
  a(3, 4) = 2.0 * n;
  a(4, 3) = -2.0 * n;
  a(4, 1) = 3.0 * n * n;
  a(5, 2) = -n * n;
  return a;
}

Mat63 CwModel::B() const {
  Mat63 b = Mat63::Zero();
  b.block<3, 3>(3, 0) = Mat3::Identity() / mass;
  return b;
}

CwMatrices cw_linear_model(const CwModel& model, CwFrame frame) {
  const CwMatrices paper{model.A(), model.B()};
  if (frame == CwFrame::paper) return paper;
  // hill component i = sign[i] * paper component perm[i] (states: x, y, z, vx, vy, vz; controls: first 3).
  constexpr int perm[6] = {1, 0, 2, 4, 3, 5};
  constexpr double sign[6] = {1.0, -1.0, 1.0, 1.0, -1.0, 1.0};
  // -0.0 for a zero entry under a sign flip would still compare equal; keep +0.0 all the same.
  auto flip = [](double v, double s) { return s < 0.0 && v != 0.0 ? -v : v; };
  CwMatrices hill;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) hill.A(i, j) = flip(paper.A(perm[i], perm[j]), sign[i] * sign[j]);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 6; ++i) hill.B(i, j) = flip(paper.B(perm[i], perm[j]), sign[i] * sign[j]);
  return hill;
}

Vec6 CwModel::rhs(const Vec6& x, const Vec3& u) const {
  Vec6 d;
  d.head<3>() = x.tail<3>();
  d(3) = 2.0 * n * x(4) + u(0) / mass;
  d(4) = -2.0 * n * x(3) + 3.0 * n * n * x(1) + u(1) / mass;
  d(5) = -n * n * x(2) + u(2) / mass;
  return d;
}

// Hill's solution written in this frame (radial y, x = minus along-track); 1 - cos computed as
// 2 sin^2(th/2) to avoid cancellation for small n t.
Mat6 CwModel::stm(double t) const {
  require_cw_angle(n, t, "t");
  const double th = n * t, s = std::sin(th), c = std::cos(th);
  const double omc = 2.0 * std::sin(0.5 * th) * std::sin(0.5 * th);
  Mat6 p = Mat6::Zero();
  // x row
  p(0, 0) = 1.0;
  p(0, 1) = -6.0 * (s - th);
  p(0, 3) = (4.0 * s - 3.0 * th) / n;
  p(0, 4) = 2.0 * omc / n;
  // y row
  p(1, 1) = 4.0 - 3.0 * c;
  p(1, 3) = -2.0 * omc / n;
  p(1, 4) = s / n;
  // z row
  p(2, 2) = c;
  p(2, 5) = s / n;
  // x' row
  p(3, 1) = 6.0 * n * omc;
  p(3, 3) = 4.0 * c - 3.0;
  p(3, 4) = 2.0 * s;
  // y' row
  p(4, 1) = 3.0 * n * s;
  p(4, 3) = -2.0 * s;
  p(4, 4) = c;
  // z' row
  p(5, 2) = -n * s;
  p(5, 5) = c;
  return p;
}

Mat63 CwModel::input_integral(double t) const {
  require_cw_angle(n, t, "t");
  const double th = n * t, s = std::sin(th);
  const double omc = 2.0 * std::sin(0.5 * th) * std::sin(0.5 * th);
  const double n2 = n * n;
  Mat63 g = Mat63::Zero();
  // column of u1 (x-acceleration): integral of the x0' column of Phi
  g(0, 0) = (4.0 * omc - 1.5 * th * th) / n2;
  g(1, 0) = -2.0 * (th - s) / n2;
  g(3, 0) = (4.0 * s - 3.0 * th) / n;
  g(4, 0) = -2.0 * omc / n;
  // column of u2 (y-acceleration)
  g(0, 1) = 2.0 * (th - s) / n2;
  g(1, 1) = omc / n2;
  g(3, 1) = 2.0 * omc / n;
  g(4, 1) = s / n;
  // column of u3 (z-acceleration)
  g(2, 2) = omc / n2;
  g(5, 2) = s / n;
  return g / mass;
}

CwDiscrete cw_discretize_zoh(const CwModel& model, double dt) {
  core::require_positive(dt, "dt");
  require_cw_angle(model.n, dt, "dt");
  return {model.stm(dt), model.input_integral(dt)};
}

CwDiscrete cw_discretize_expm(const CwModel& model, double dt) {
  core::require_positive(dt, "dt");
  require_cw_angle(model.n, dt, "dt");
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(9, 9);
  M.topLeftCorner(6, 6) = model.A() * dt;
  M.topRightCorner(6, 3) = model.B() * dt;
  const Eigen::MatrixXd E = expm(M);
  return {E.topLeftCorner(6, 6), E.topRightCorner(6, 3)};
}

CwDiscrete cw_discretize_midpoint(const CwModel& model, double dt) {
  core::require_positive(dt, "dt");
  require_cw_angle(model.n, dt, "dt");
  const Mat6 a = model.A();
  CwDiscrete d;
  d.Ad = Mat6::Identity() + dt * a + 0.5 * dt * dt * a * a;
  d.Bd = dt * (Mat6::Identity() + 0.5 * dt * a) * model.B();
  return d;
}

Eigen::MatrixXd expm(const Eigen::MatrixXd& M) {
  core::require(M.rows() == M.cols(), "M", "must be square");
  core::require_finite(M, "M");
  const double norm1 = M.cwiseAbs().colwise().sum().maxCoeff();
  int squarings = 0;
  if (norm1 > 0.5) squarings = static_cast<int>(std::ceil(std::log2(norm1 / 0.5)));
  const Eigen::MatrixXd X = M / std::ldexp(1.0, squarings);
  const Eigen::Index n = M.rows();
  // Horner evaluation of sum_{k<=18} X^k / k!
  Eigen::MatrixXd E = Eigen::MatrixXd::Identity(n, n);
  for (int k = 18; k >= 1; --k) {
    Eigen::MatrixXd t = X * E / static_cast<double>(k);
    E = Eigen::MatrixXd::Identity(n, n) + t;
  }
  for (int i = 0; i < squarings; ++i) E = (E * E).eval();
  return E;
}

}  // namespace satgnc::dynamics
