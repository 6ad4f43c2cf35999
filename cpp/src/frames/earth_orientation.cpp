// frames: IAU 2006/2000A CIO-based GCRS <-> ITRS through ERFA, and IauEarthRotation (grid + ERA).
#include "satgnc/frames/earth_orientation.hpp"

#include <erfa.h>
#include <erfam.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::frames {

namespace {

Mat3 from_erfa(const double r[3][3]) {
  Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = r[i][j];
  return m;
}

// r_tirs = R3(era) r_cirs (ERFA's eraRz convention: a rotation of the frame by +era).
Mat3 r3(double era) {
  const double c = std::cos(era), s = std::sin(era);
  Mat3 m;
  m << c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0;
  return m;
}

EarthOrientation assemble(double x, double y, double s, double era, double xp_rad, double yp_rad, double sp,
                          double lod) {
  EarthOrientation o;
  double rc2i[3][3];
  eraC2ixys(x, y, s, rc2i);
  double rpom[3][3];
  eraPom00(xp_rad, yp_rad, sp, rpom);
  o.q = from_erfa(rc2i);
  o.w = from_erfa(rpom);
  o.era = era;
  o.gcrs_to_itrs = o.w * r3(era) * o.q;
  o.omega = kEarthRotationRate * (1.0 - lod / ERFA_DAYSEC);
  return o;
}

}  // namespace

EarthOrientation earth_orientation(const core::Epoch& epoch, const EopValues& eop) {
  const core::JulianDate tt = epoch.jd(core::TimeScale::tt);
  const core::JulianDate ut1 = (epoch + (eop.ut1_utc - epoch.tai_minus_utc())).jd(core::TimeScale::tai);
  double x = 0.0, y = 0.0, s = 0.0;
  eraXys06a(tt.jd1, tt.jd2, &x, &y, &s);
  x += eop.dx * ERFA_DAS2R;
  y += eop.dy * ERFA_DAS2R;
  return assemble(x, y, s, eraEra00(ut1.jd1, ut1.jd2), eop.xp * ERFA_DAS2R, eop.yp * ERFA_DAS2R,
                  eraSp00(tt.jd1, tt.jd2), eop.lod);
}

EarthOrientation earth_orientation(const core::Epoch& epoch, const EopTable& table) {
  return earth_orientation(epoch, table.at(epoch));
}

Mat3 gcrs_to_itrs_matrix(const core::Epoch& epoch, const EopTable& table) {
  return earth_orientation(epoch, table).gcrs_to_itrs;
}

Vec3 gcrs_to_itrs(const Vec3& r_gcrs, const core::Epoch& epoch, const EopTable& table) {
  return gcrs_to_itrs_matrix(epoch, table) * r_gcrs;
}

Vec3 itrs_to_gcrs(const Vec3& r_itrs, const core::Epoch& epoch, const EopTable& table) {
  return gcrs_to_itrs_matrix(epoch, table).transpose() * r_itrs;
}

Vec6 gcrs_to_itrs(const Vec6& x_gcrs, const EarthOrientation& o) {
  const Mat3 rq = r3(o.era) * o.q;
  const Vec3 r_tirs = rq * x_gcrs.head<3>();
  const Vec3 w(0.0, 0.0, o.omega);
  const Vec3 v_tirs = rq * x_gcrs.tail<3>() - w.cross(r_tirs);
  Vec6 out;
  out << o.w * r_tirs, o.w * v_tirs;
  return out;
}

Vec6 itrs_to_gcrs(const Vec6& x_itrs, const EarthOrientation& o) {
  const Mat3 rq = r3(o.era) * o.q;
  const Vec3 r_tirs = o.w.transpose() * x_itrs.head<3>();
  const Vec3 v_tirs = o.w.transpose() * x_itrs.tail<3>();
  const Vec3 w(0.0, 0.0, o.omega);
  Vec6 out;
  out << rq.transpose() * r_tirs, rq.transpose() * (v_tirs + w.cross(r_tirs));
  return out;
}

Vec6 gcrs_to_itrs(const Vec6& x_gcrs, const core::Epoch& epoch, const EopTable& table) {
  return gcrs_to_itrs(x_gcrs, earth_orientation(epoch, table));
}

Vec6 itrs_to_gcrs(const Vec6& x_itrs, const core::Epoch& epoch, const EopTable& table) {
  return itrs_to_gcrs(x_itrs, earth_orientation(epoch, table));
}

Mat3 gcrs_to_eme2000_matrix() {
  double rb[3][3], rp[3][3], rbp[3][3];
  eraBp06(ERFA_DJ00, 0.0, rb, rp, rbp);  // the bias is constant; the date only matters for rp, rbp
  return from_erfa(rb);
}

Vec3 gcrs_to_eme2000(const Vec3& v_gcrs) { return gcrs_to_eme2000_matrix() * v_gcrs; }

Vec3 eme2000_to_gcrs(const Vec3& v_eme2000) { return gcrs_to_eme2000_matrix().transpose() * v_eme2000; }

// ---------------------------------------------------------------- IauEarthRotation

IauEarthRotation::IauEarthRotation(const core::Epoch& epoch, const EopTable& eop, double t_begin,
                                   double t_end, double step)
    : epoch_(epoch), t_begin_(t_begin), t_end_(t_end), step_(step) {
  core::require_finite(t_begin, "t_begin");
  core::require_finite(t_end, "t_end");
  core::require(t_begin <= t_end, "t_end", "must be >= t_begin");
  core::require(std::isfinite(step) && step > 0.0 && step <= 86400.0, "step", "must be in (0, 86400] s");
  const double nodes = std::ceil((t_end - t_begin) / step) + 4.0;
  core::require(nodes <= 1e6, "step", "the span / step gives more than 10^6 grid nodes");
  const auto n = static_cast<std::size_t>(nodes);
  t_first_ = t_begin - step;
  tt0_ = epoch.jd(core::TimeScale::tt);
  for (auto* v : {&x_, &y_, &s_, &xp_, &yp_, &ut1_tai_, &lod_}) v->resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const core::Epoch e = epoch + (t_first_ + static_cast<double>(k) * step);
    const EopValues v = eop.at(e);  // the policy applies here, at setup
    const core::JulianDate tt = e.jd(core::TimeScale::tt);
    double x = 0.0, y = 0.0, s = 0.0;
    eraXys06a(tt.jd1, tt.jd2, &x, &y, &s);
    x_[k] = x + v.dx * ERFA_DAS2R;
    y_[k] = y + v.dy * ERFA_DAS2R;
    s_[k] = s;
    xp_[k] = v.xp * ERFA_DAS2R;
    yp_[k] = v.yp * ERFA_DAS2R;
    ut1_tai_[k] = v.ut1_utc - e.tai_minus_utc();
    lod_[k] = v.lod;
  }
}

EarthOrientation IauEarthRotation::orientation(double t) const noexcept {
  const std::size_t n = x_.size();
  const double u = (t - t_first_) / step_;
  double kf = std::floor(u);
  if (!(kf >= 1.0)) kf = 1.0;  // also catches NaN
  if (kf > static_cast<double>(n - 3)) kf = static_cast<double>(n - 3);
  const auto k = static_cast<std::size_t>(kf);
  const double p = u - kf;
  // 4-point Lagrange on equally spaced nodes k-1 .. k+2 (p = 0 at node k).
  const double wm = -p * (p - 1.0) * (p - 2.0) / 6.0;
  const double w0 = (p + 1.0) * (p - 1.0) * (p - 2.0) / 2.0;
  const double w1 = -(p + 1.0) * p * (p - 2.0) / 2.0;
  const double w2 = (p + 1.0) * p * (p - 1.0) / 6.0;
  auto lag = [&](const std::vector<double>& f) {
    return wm * f[k - 1] + w0 * f[k] + w1 * f[k + 1] + w2 * f[k + 2];
  };
  const double dt_days = t / ERFA_DAYSEC;
  // UT1 = TAI + (UT1 - TAI); TAI two-part JD of the epoch, shifted by t.
  const core::Epoch& e = epoch_;
  const double tai_days_whole = std::floor(static_cast<double>(e.tai_whole()) / ERFA_DAYSEC);
  const double tai_rest =
      (static_cast<double>(e.tai_whole()) - tai_days_whole * ERFA_DAYSEC + e.tai_fraction()) / ERFA_DAYSEC;
  const double era = eraEra00(ERFA_DJ00 + tai_days_whole, tai_rest + dt_days + lag(ut1_tai_) / ERFA_DAYSEC);
  const double sp = eraSp00(tt0_.jd1, tt0_.jd2 + dt_days);
  return assemble(lag(x_), lag(y_), lag(s_), era, lag(xp_), lag(yp_), sp, lag(lod_));
}

void IauEarthRotation::rotation(double t, Mat3& gcrf_to_itrf, Vec3& omega_gcrf) const noexcept {
  const EarthOrientation o = orientation(t);
  gcrf_to_itrf = o.gcrs_to_itrs;
  // The rotation about the CIP, expressed in GCRS: Q^T R3^T (0, 0, omega) = Q^T (0, 0, omega).
  omega_gcrf = o.q.transpose() * Vec3(0.0, 0.0, o.omega);
}

}  // namespace satgnc::frames
