#include "satgnc/analysis/od_gramian.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <string>

#include "satgnc/analysis/linearize.hpp"
#include "satgnc/core/validate.hpp"
#include "satgnc/propagation/kepler.hpp"

namespace satgnc::analysis {

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif
Vec3 RotatingStation::position(double t) const {
  const double c = std::cos(rate * t), s = std::sin(rate * t);
  return Vec3(c * r0.x() - s * r0.y(), s * r0.x() + c * r0.y(), r0.z());
}

Vec3 RotatingStation::velocity(double t) const { return Vec3(0.0, 0.0, rate).cross(position(t)); }
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace {
Vec6 propagate(const Vec6& x0, double t, double mu, Mat6* stm) {
  Vec6 x;
  const propagation::KeplerStatus st = propagation::kepler_step(x0, t, mu, x, stm);
  core::require(st == propagation::KeplerStatus::success, "x0",
                std::string("Kepler propagation failed: ") + core::status_message(st));
  return x;
}

// rate_name: the station's rate field as the caller knows it (station.omega, or station.rate for the
// deprecated RotatingStation overload).
OdGramianReport gramian_of(const Vec6& x0, const dynamics::Station& station, const std::vector<double>& times,
                           OdMeasurement kind, double mu, const char* rate_name) {
  core::require_finite(x0, "x0");
  core::require_positive(mu, "mu");
  core::require_finite(station.r0, "station.r0");
  core::require_finite(station.omega, rate_name);
  core::require(!times.empty(), "times", "needs at least one observation time");
  for (size_t j = 0; j < times.size(); ++j) {
    core::require_finite(times[j], "times");
    core::require(j == 0 || times[j] > times[j - 1], "times", "must be strictly increasing");
  }
  std::vector<Eigen::MatrixXd> stms, H;
  for (double t : times) {
    Mat6 phi;
    const Vec6 x = propagate(x0, t, mu, &phi);
    const Vec6 s = station.state(t);
    const Vec3 R = s.head<3>(), V = s.tail<3>();
    Eigen::Matrix<double, 1, 6> hr, hd;
    range_partial(x.head<3>(), R, hr);
    range_rate_partial(x.head<3>(), x.tail<3>(), R, V, hd);
    Eigen::MatrixXd h(kind == OdMeasurement::both ? 2 : 1, 6);
    if (kind == OdMeasurement::range) h = hr;
    if (kind == OdMeasurement::range_rate) h = hd;
    if (kind == OdMeasurement::both) h << hr, hd;
    stms.emplace_back(phi);
    H.push_back(h);
  }
  OdGramianReport rep;
  rep.gramian = ltv_observability_gramian(stms, H);
  Eigen::Index rows = 0;
  for (const auto& h : H) rows += h.rows();
  Eigen::MatrixXd M(rows, 6);
  rows = 0;
  for (size_t j = 0; j < H.size(); ++j) {
    M.middleRows(rows, H[j].rows()) = H[j] * stms[j];
    rows += H[j].rows();
  }
  auto cond = [](const Eigen::MatrixXd& X, Eigen::VectorXd* sv_out) {
    const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(X).singularValues();
    if (sv_out) *sv_out = sv;
    if (sv.size() < 6 || sv(5) <= 0.0) return std::numeric_limits<double>::infinity();
    return sv(0) / sv(5);
  };
  rep.sensitivity_condition = cond(M, &rep.singular_values);
  const Eigen::VectorXd cn = M.colwise().norm().transpose().cwiseMax(1e-300).cwiseInverse();
  rep.jacobi_sensitivity_condition = cond(M * cn.asDiagonal(), nullptr);
  rep.times = times;
  const Eigen::VectorXd d = rep.gramian.W.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  rep.jacobi_condition = analyze_gramian(d.asDiagonal() * rep.gramian.W * d.asDiagonal()).condition;
  return rep;
}
}  // namespace

OdGramianReport od_observability_gramian(const Vec6& x0, const dynamics::Station& station,
                                         const std::vector<double>& times, OdMeasurement kind, double mu) {
  return gramian_of(x0, station, times, kind, mu, "station.omega");
}

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif
OdGramianReport od_observability_gramian(const Vec6& x0, const RotatingStation& station,
                                         const std::vector<double>& times, OdMeasurement kind, double mu) {
  return gramian_of(x0, dynamics::Station(station), times, kind, mu, "station.rate");
}
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

double elevation(const Vec6& x0, const dynamics::Station& station, double t, double mu) {
  const Vec6 x = propagate(x0, t, mu, nullptr);
  const Vec3 R = station.state(t).head<3>();
  const Vec3 d = x.head<3>() - R;
  return std::asin(d.dot(R) / (d.norm() * R.norm()));
}

std::pair<double, double> visibility_pass(const Vec6& x0, const dynamics::Station& station, double mu,
                                          double t_max, double dt) {
  core::require_positive(t_max, "t_max");
  core::require_positive(dt, "dt");
  core::require(elevation(x0, station, 0.0, mu) > 0.0, "x0", "the satellite is not visible at t = 0");
  auto edge = [&](double dir) {
    double inside = 0.0, t = 0.0;
    while (std::abs(t) < t_max) {
      t += dir * dt;
      if (elevation(x0, station, t, mu) <= 0.0) break;
      inside = t;
    }
    core::require(std::abs(t) < t_max, "t_max", "no horizon crossing within the search window");
    double out = t;
    while (std::abs(out - inside) > 1e-6) {
      const double mid = 0.5 * (inside + out);
      (elevation(x0, station, mid, mu) > 0.0 ? inside : out) = mid;
    }
    return inside;
  };
  return {edge(-1.0), edge(1.0)};
}

}  // namespace satgnc::analysis
