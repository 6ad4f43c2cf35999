#include "satgnc/dynamics/two_satellite.hpp"

#include <cmath>

#include "satgnc/core/validate.hpp"

namespace satgnc::dynamics {

namespace {

Mat3 skew(const Vec3& a) {
  Mat3 s;
  s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return s;
}

// Butcher tableaux (explicit, up to 4 stages).
struct Tableau {
  int stages;
  double a[4][4];
  double b[4];
};

constexpr Tableau kRk3 = {3, {{0, 0, 0, 0}, {0.5, 0, 0, 0}, {-1.0, 2.0, 0, 0}, {0, 0, 0, 0}},
                          {1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0, 0.0}};
constexpr Tableau kRk4 = {4, {{0, 0, 0, 0}, {0.5, 0, 0, 0}, {0, 0.5, 0, 0}, {0, 0, 1.0, 0}},
                          {1.0 / 6.0, 2.0 / 6.0, 2.0 / 6.0, 1.0 / 6.0}};

}  // namespace

void TwoSatelliteParams::validate() const {
  using core::require;
  using core::require_positive;
  require_positive(mu, "mu");
  require_positive(mass_chaser, "mass_chaser");
  require_positive(mass_target, "mass_target");
  require(std::isfinite(cd_chaser) && cd_chaser >= 0.0, "cd_chaser", "must be finite and >= 0");
  require(std::isfinite(cd_target) && cd_target >= 0.0, "cd_target", "must be finite and >= 0");
  require(std::isfinite(area_chaser) && area_chaser >= 0.0, "area_chaser", "must be finite and >= 0");
  require(std::isfinite(area_target) && area_target >= 0.0, "area_target", "must be finite and >= 0");
  require(std::isfinite(rho0) && rho0 >= 0.0, "rho0", "must be finite and >= 0 (kg/m^3)");
  require(std::isfinite(density_decay) && density_decay >= 0.0, "density_decay",
          "must be finite and >= 0 (1/m)");
  require(std::isfinite(density_radius), "density_radius", "must be finite (m)");
  core::require_finite(omega, "omega");
  if (j2_on) {
    require(std::isfinite(j2), "j2", "must be finite");
    require_positive(j2_radius, "j2_radius");
  }
}

TwoSatelliteModel::TwoSatelliteModel(const TwoSatelliteParams& params) : p_(params) { p_.validate(); }

bool TwoSatelliteModel::body_acceleration(const Vec3& r, const Vec3& v, double cam, Vec3& a, Mat3* da_dr,
                                          Mat3* da_dv) const {
  const double r2 = r.squaredNorm();
  if (!(r2 > 0.0) || !std::isfinite(r2)) return false;
  const double rn = std::sqrt(r2);
  const double r3 = r2 * rn;
  const Vec3 rhat = r / rn;
  a = -p_.mu / r3 * r;
  const bool jac = da_dr != nullptr && da_dv != nullptr;
  if (jac) {
    *da_dr = -p_.mu / r3 * (Mat3::Identity() - 3.0 * rhat * rhat.transpose());
    da_dv->setZero();
  }
  if (p_.j2_on) {
    // a = -(3/2) J2 mu Re^2 / r^5 [x (1 - 5 z^2/r^2), y (1 - 5 z^2/r^2), z (3 - 5 z^2/r^2)]
    const double c = -1.5 * p_.j2 * p_.mu * p_.j2_radius * p_.j2_radius;
    const double r5 = r3 * r2;
    const double z2 = r.z() * r.z();
    const double s = 5.0 * z2 / r2;
    const Vec3 g(r.x() * (1.0 - s), r.y() * (1.0 - s), r.z() * (3.0 - s));
    a += c / r5 * g;
    if (jac) {
      // d(c g / r^5)/dr = c (dg/dr / r^5 - 5 g r^T / r^7)
      // ds/dr = 10 z e_z / r^2 - 10 z^2 r / r^4
      Vec3 ds = -10.0 * z2 / (r2 * r2) * r;
      ds.z() += 10.0 * r.z() / r2;
      Mat3 dg = Mat3::Zero();
      dg(0, 0) = 1.0 - s;
      dg(1, 1) = 1.0 - s;
      dg(2, 2) = 3.0 - s;
      dg.row(0) -= r.x() * ds.transpose();
      dg.row(1) -= r.y() * ds.transpose();
      dg.row(2) -= r.z() * ds.transpose();
      *da_dr += c * (dg / r5 - 5.0 * g * r.transpose() / (r5 * r2));
    }
  }
  if (p_.drag_on && cam > 0.0 && p_.rho0 > 0.0) {
    const double sgn = p_.atmosphere == AtmosphereRotation::co_rotating ? -1.0 : 1.0;
    const Vec3 w = v + sgn * p_.omega.cross(r);
    const double wn = w.norm();
    const double rho = p_.rho0 * std::exp(-p_.density_decay * (rn - p_.density_radius));
    const double k = 0.5 * cam;
    a += -k * rho * wn * w;
    if (jac && wn > 0.0) {
      const Mat3 da_dw = -k * rho * (wn * Mat3::Identity() + w * w.transpose() / wn);
      const Vec3 drho_dr = -p_.density_decay * rho * rhat;
      // dw/dr = sgn * d(omega x r)/dr = sgn * skew(omega)
      *da_dr += -k * wn * w * drho_dr.transpose() + da_dw * (sgn * skew(p_.omega));
      *da_dv += da_dw;
    }
  }
  return a.allFinite();
}

bool TwoSatelliteModel::cw_frame(const Vec3& r_t, const Vec3& v_t, Mat3& R) {
  const double rn = r_t.norm();
  if (!(rn > 0.0)) return false;
  const Vec3 ey = r_t / rn;
  Vec3 ez = ey.cross(v_t);
  const double hn = ez.norm();
  if (!(hn > 0.0)) return false;
  ez /= hn;
  R.col(0) = ey.cross(ez);
  R.col(1) = ey;
  R.col(2) = ez;
  return R.allFinite();
}

void TwoSatelliteModel::cw_frame_derivatives(const Vec3& r_t, const Vec3& v_t, const Vec3& u, Mat3& dRu_dr,
                                             Mat3& dRu_dv) {
  const double rn = r_t.norm();
  const Vec3 ey = r_t / rn;
  const Mat3 dey_dr = (Mat3::Identity() - ey * ey.transpose()) / rn;
  const Vec3 h = ey.cross(v_t);
  const double hn = h.norm();
  const Vec3 ez = h / hn;
  const Mat3 dez_dh = (Mat3::Identity() - ez * ez.transpose()) / hn;
  // h = ey x v = -v x ey
  const Mat3 dh_dr = -skew(v_t) * dey_dr;
  const Mat3 dh_dv = skew(ey);
  const Mat3 dez_dr = dez_dh * dh_dr;
  const Mat3 dez_dv = dez_dh * dh_dv;
  // ex = ey x ez: d ex = skew(ey) d ez - skew(ez) d ey
  const Mat3 dex_dr = skew(ey) * dez_dr - skew(ez) * dey_dr;
  const Mat3 dex_dv = skew(ey) * dez_dv;
  dRu_dr = u.x() * dex_dr + u.y() * dey_dr + u.z() * dez_dr;
  dRu_dv = u.x() * dex_dv + u.z() * dez_dv;
}

bool TwoSatelliteModel::rhs(const Vec12& x, const Vec3& u, Vec12& xdot) const {
  const Vec3 d = x.segment<3>(0), rt = x.segment<3>(3), w = x.segment<3>(6), vt = x.segment<3>(9);
  const Vec3 rc = rt - d, vc = vt - w;
  Vec3 at, ac;
  if (!body_acceleration(rt, vt, p_.cd_target * p_.area_target / p_.mass_target, at)) return false;
  if (!body_acceleration(rc, vc, p_.cd_chaser * p_.area_chaser / p_.mass_chaser, ac)) return false;
  Vec3 uf = u;
  if (p_.control_frame == ControlFrame::target_cw) {
    Mat3 R;
    if (!cw_frame(rt, vt, R)) return false;
    uf = R * u;
  }
  ac += uf / p_.mass_chaser;
  xdot.segment<3>(0) = w;
  xdot.segment<3>(3) = vt;
  xdot.segment<3>(6) = at - ac;
  xdot.segment<3>(9) = at;
  return xdot.allFinite();
}

bool TwoSatelliteModel::rhs_jacobians(const Vec12& x, const Vec3& u, Vec12& xdot, Mat12& A,
                                      Mat12x3& B) const {
  const Vec3 d = x.segment<3>(0), rt = x.segment<3>(3), w = x.segment<3>(6), vt = x.segment<3>(9);
  const Vec3 rc = rt - d, vc = vt - w;
  Vec3 at, ac;
  Mat3 at_r, at_v, ac_r, ac_v;
  if (!body_acceleration(rt, vt, p_.cd_target * p_.area_target / p_.mass_target, at, &at_r, &at_v))
    return false;
  if (!body_acceleration(rc, vc, p_.cd_chaser * p_.area_chaser / p_.mass_chaser, ac, &ac_r, &ac_v))
    return false;
  Mat3 R = Mat3::Identity();
  Mat3 dRu_dr = Mat3::Zero(), dRu_dv = Mat3::Zero();
  if (p_.control_frame == ControlFrame::target_cw) {
    if (!cw_frame(rt, vt, R)) return false;
    cw_frame_derivatives(rt, vt, u, dRu_dr, dRu_dv);
  }
  const double im = 1.0 / p_.mass_chaser;
  ac += R * u * im;
  xdot.segment<3>(0) = w;
  xdot.segment<3>(3) = vt;
  xdot.segment<3>(6) = at - ac;
  xdot.segment<3>(9) = at;

  A.setZero();
  A.block<3, 3>(0, 6).setIdentity();
  A.block<3, 3>(3, 9).setIdentity();
  // chaser: rc = rt - d, vc = vt - w
  // d(ac)/dd = -ac_r, d(ac)/drt = ac_r + dRu_dr/m, d(ac)/dw = -ac_v, d(ac)/dvt = ac_v + dRu_dv/m
  A.block<3, 3>(6, 0) = ac_r;
  A.block<3, 3>(6, 3) = at_r - ac_r - dRu_dr * im;
  A.block<3, 3>(6, 6) = ac_v;
  A.block<3, 3>(6, 9) = at_v - ac_v - dRu_dv * im;
  A.block<3, 3>(9, 3) = at_r;
  A.block<3, 3>(9, 9) = at_v;
  B.setZero();
  B.block<3, 3>(6, 0) = -R * im;
  return xdot.allFinite() && A.allFinite();
}

bool TwoSatelliteModel::rk_step(int scheme, double h, const Vec12& x, const Vec3& u, Vec12& x_next, Mat12* A,
                                Mat12x3* B) const {
  const Tableau& tb = scheme == 3 ? kRk3 : kRk4;
  if (scheme != 3 && scheme != 4) return false;
  Vec12 k[4];
  const bool jac = A != nullptr && B != nullptr;
  Mat12 dk_dx[4];
  Mat12x3 dk_du[4];
  Vec12 xs;
  Mat12 J;
  Mat12x3 Ju;
  for (int i = 0; i < tb.stages; ++i) {
    xs = x;
    for (int j = 0; j < i; ++j)
      if (tb.a[i][j] != 0.0) xs += h * tb.a[i][j] * k[j];
    if (!jac) {
      if (!rhs(xs, u, k[i])) return false;
      continue;
    }
    if (!rhs_jacobians(xs, u, k[i], J, Ju)) return false;
    if (i == 0) {
      dk_dx[0] = J;
      dk_du[0] = Ju;
      continue;
    }
    // dxs/dx = I + h sum a_ij dk_j/dx ; dxs/du = h sum a_ij dk_j/du
    Mat12 dxs_dx = Mat12::Identity();
    Mat12x3 dxs_du = Mat12x3::Zero();
    for (int j = 0; j < i; ++j)
      if (tb.a[i][j] != 0.0) {
        dxs_dx += h * tb.a[i][j] * dk_dx[j];
        dxs_du += h * tb.a[i][j] * dk_du[j];
      }
    // J = [0 0 I 0; 0 0 0 I; * * * *; * * * *]: the top half of J M is the bottom half of M.
    dk_dx[i].topRows<6>() = dxs_dx.bottomRows<6>();
    dk_dx[i].bottomRows<6>().noalias() = J.bottomRows<6>().lazyProduct(dxs_dx);
    dk_du[i].topRows<6>() = dxs_du.bottomRows<6>();
    dk_du[i].bottomRows<6>().noalias() = J.bottomRows<6>().lazyProduct(dxs_du);
    dk_du[i] += Ju;
  }
  x_next = x;
  for (int i = 0; i < tb.stages; ++i) x_next += h * tb.b[i] * k[i];
  if (jac) {
    A->setIdentity();
    B->setZero();
    for (int i = 0; i < tb.stages; ++i) {
      *A += h * tb.b[i] * dk_dx[i];
      *B += h * tb.b[i] * dk_du[i];
    }
  }
  return x_next.allFinite();
}

Vec6 cw_relative_state(const Vec12& x) {
  const Vec3 rt = x.segment<3>(3), vt = x.segment<3>(9);
  Mat3 R;
  Vec6 out = Vec6::Constant(std::nan(""));
  if (!TwoSatelliteModel::cw_frame(rt, vt, R)) return out;
  const Vec3 omega_i = rt.cross(vt) / rt.squaredNorm();
  const Vec3 omega_cw = R.transpose() * omega_i;
  const Vec3 p = -(R.transpose() * x.segment<3>(0));
  const Vec3 v = -(R.transpose() * x.segment<3>(6)) - omega_cw.cross(p);
  out << p, v;
  return out;
}

Vec6 cw_relative_state_published(const Vec12& x, double mu) {
  const Vec3 rt = x.segment<3>(3), vt = x.segment<3>(9);
  const Vec3 rc = rt - x.segment<3>(0), vc = vt - x.segment<3>(6);
  Mat3 R;
  Vec6 out = Vec6::Constant(std::nan(""));
  if (!TwoSatelliteModel::cw_frame(rt, vt, R)) return out;
  const Vec3 hc = rc.cross(vc);
  const double rtn = rt.norm();
  const Vec3 om = hc / hc.norm() * std::sqrt(mu * rtn) / (rtn * rtn);
  const Vec3 p = R.transpose() * (rc - rt);
  const Vec3 v = R.transpose() * (vc - vt) - om.cross(p);
  out << p, v;
  return out;
}

Vec12 two_satellite_state(const Vec3& r_t, const Vec3& v_t, const Vec6& cw) {
  Mat3 R;
  Vec12 x = Vec12::Constant(std::nan(""));
  if (!TwoSatelliteModel::cw_frame(r_t, v_t, R)) return x;
  const Vec3 omega_cw = R.transpose() * (r_t.cross(v_t) / r_t.squaredNorm());
  const Vec3 p = cw.head<3>();
  const Vec3 v = cw.tail<3>();
  x.segment<3>(0) = -(R * p);
  x.segment<3>(3) = r_t;
  x.segment<3>(6) = -(R * (v + omega_cw.cross(p)));
  x.segment<3>(9) = v_t;
  return x;
}

}  // namespace satgnc::dynamics
