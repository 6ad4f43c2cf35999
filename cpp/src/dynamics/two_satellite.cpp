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

// The CW frame R = [e_x e_y e_z] of the target (e_y = r/|r|, e_z = e_y x v / |e_y x v|, e_x = e_y x e_z)
// with |r| and |e_y x v|; false (R untouched) when either is not > 0. Shared by cw_frame and
// cw_frame_derivatives so that both compute R identically.
bool cw_axes(const Vec3& r_t, const Vec3& v_t, Mat3& R, double& rn, double& hn) {
  rn = r_t.norm();
  if (!(rn > 0.0)) return false;
  const Vec3 ey = r_t / rn;
  Vec3 ez = ey.cross(v_t);
  hn = ez.norm();
  if (!(hn > 0.0)) return false;
  ez /= hn;
  R.col(0) = ey.cross(ez);
  R.col(1) = ey;
  R.col(2) = ez;
  return true;
}

// Butcher tableaux (explicit, up to 4 stages).
struct Tableau {
  int stages;
  double a[4][4];
  double b[4];
};

constexpr Tableau kRk3 = {3,
                          {{0, 0, 0, 0}, {0.5, 0, 0, 0}, {-1.0, 2.0, 0, 0}, {0, 0, 0, 0}},
                          {1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0, 0.0}};
constexpr Tableau kRk4 = {4,
                          {{0, 0, 0, 0}, {0.5, 0, 0, 0}, {0, 0.5, 0, 0}, {0, 0, 1.0, 0}},
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
  double rn, hn;
  return cw_axes(r_t, v_t, R, rn, hn) && R.allFinite();
}

bool TwoSatelliteModel::cw_frame_derivatives(const Vec3& r_t, const Vec3& v_t, const Vec3& u, Mat3& R,
                                             Mat3& dRu_dr, Mat3& dRu_dv) {
  // R = [e_x e_y e_z] exactly as cw_frame computes it.
  double rn, hn;
  if (!cw_axes(r_t, v_t, R, rn, hn)) return false;
  const Vec3 ey = R.col(1), ez = R.col(2);
  // With P = de_y/dr = (I - e_y e_y^T)/|r|, h = e_y x v, de_z/dh = (I - e_z e_z^T)/|h|,
  // dh/dr = -skew(v) P, dh/dv = skew(e_y), de_x = skew(e_y) de_z - skew(e_z) de_y:
  //   d(R u)/dv = C skew(e_y),  d(R u)/dr = (-C skew(v) + u_y I - u_x skew(e_z)) P,
  //   C = (u_x skew(e_y) + u_z I) de_z/dh.
  // Row i of M skew(a) is m_i x a.
  Mat3 C = u.z() * Mat3::Identity();
  C(0, 1) -= u.x() * ey.z();
  C(0, 2) += u.x() * ey.y();
  C(1, 0) += u.x() * ey.z();
  C(1, 2) -= u.x() * ey.x();
  C(2, 0) -= u.x() * ey.y();
  C(2, 1) += u.x() * ey.x();
  C = (C - (C * ez) * ez.transpose()) / hn;
  Mat3 F;
  for (int i = 0; i < 3; ++i) {
    const Vec3 ci = C.row(i).transpose();
    dRu_dv.row(i) = ci.cross(ey).transpose();
    F.row(i) = v_t.cross(ci).transpose();
  }
  F.diagonal().array() += u.y();
  F(0, 1) += u.x() * ez.z();
  F(0, 2) -= u.x() * ez.y();
  F(1, 0) -= u.x() * ez.z();
  F(1, 2) += u.x() * ez.x();
  F(2, 0) += u.x() * ez.y();
  F(2, 1) -= u.x() * ez.x();
  dRu_dr = (F - (F * ey) * ey.transpose()) / rn;
  return R.allFinite();
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

bool TwoSatelliteModel::rhs_blocks(const Vec12& x, const Vec3& u, Vec12& xdot, JacobianBlocks& J) const {
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
    if (!cw_frame_derivatives(rt, vt, u, R, dRu_dr, dRu_dv)) return false;
  }
  const double im = 1.0 / p_.mass_chaser;
  ac += R * u * im;
  xdot.segment<3>(0) = w;
  xdot.segment<3>(3) = vt;
  xdot.segment<3>(6) = at - ac;
  xdot.segment<3>(9) = at;
  // chaser: rc = rt - d, vc = vt - w
  // d(ac)/dd = -ac_r, d(ac)/drt = ac_r + dRu_dr/m, d(ac)/dw = -ac_v, d(ac)/dvt = ac_v + dRu_dv/m
  J.wd = ac_r;
  J.wr = at_r - ac_r - dRu_dr * im;
  J.ww = ac_v;
  J.wv = at_v - ac_v - dRu_dv * im;
  J.vr = at_r;
  J.vv = at_v;
  J.wu = -R * im;
  return xdot.allFinite() && J.wd.allFinite() && J.wr.allFinite() && J.ww.allFinite() && J.wv.allFinite() &&
         J.vr.allFinite() && J.vv.allFinite();
}

bool TwoSatelliteModel::rhs_jacobians(const Vec12& x, const Vec3& u, Vec12& xdot, Mat12& A,
                                      Mat12x3& B) const {
  JacobianBlocks J;
  if (!rhs_blocks(x, u, xdot, J)) return false;
  A.setZero();
  A.block<3, 3>(0, 6).setIdentity();
  A.block<3, 3>(3, 9).setIdentity();
  A.block<3, 3>(6, 0) = J.wd;
  A.block<3, 3>(6, 3) = J.wr;
  A.block<3, 3>(6, 6) = J.ww;
  A.block<3, 3>(6, 9) = J.wv;
  A.block<3, 3>(9, 3) = J.vr;
  A.block<3, 3>(9, 9) = J.vv;
  B.setZero();
  B.block<3, 3>(6, 0) = J.wu;
  return true;
}

bool TwoSatelliteModel::rk_step_jacobian(int scheme, double h, const Vec12& x, const Vec3& u, Vec12& x_next,
                                         Mat12& A, Mat12x3& B) const {
  // Stage derivatives in the chaser (c = [d, w]) / target (t = [r_t, v_t]) split. The target moves on
  // its own (dt'/dc = 0, dt'/du = 0) and position rows of f are velocities, so D_i = df/dx M_i
  // (M_i = d(stage state)/dx) needs only the 3x3 blocks of JacobianBlocks times 3-row slices of M_i:
  // about 500 multiply-adds per stage instead of 1080 for the dense 12x12 and 12x3 products.
  using M6 = Eigen::Matrix<double, 6, 6>;
  using M63 = Eigen::Matrix<double, 6, 3>;
  const Tableau& tb = scheme == 3 ? kRk3 : kRk4;
  Vec12 k[4];
  M6 Dcc[4], Dct[4], Dtt[4];
  M63 Dcu[4];
  Vec12 xs;
  JacobianBlocks J;
  M6 Mcc, Mct, Mtt;
  M63 Mcu;
  // M = I (c-c, t-t) + sum_j coef[j] D_j, written without clearing whole matrices (small memsets are
  // slow here).
  auto combine = [&](const double* coef, int n) {
    bool first = true;
    for (int j = 0; j < n; ++j) {
      if (coef[j] == 0.0) continue;
      const double c = h * coef[j];
      if (first) {
        Mcc.noalias() = c * Dcc[j];
        Mct.noalias() = c * Dct[j];
        Mtt.noalias() = c * Dtt[j];
        Mcu.noalias() = c * Dcu[j];
        first = false;
      } else {
        Mcc.noalias() += c * Dcc[j];
        Mct.noalias() += c * Dct[j];
        Mtt.noalias() += c * Dtt[j];
        Mcu.noalias() += c * Dcu[j];
      }
    }
    Mcc.diagonal().array() += 1.0;
    Mtt.diagonal().array() += 1.0;
  };
  for (int i = 0; i < tb.stages; ++i) {
    xs = x;
    for (int j = 0; j < i; ++j)
      if (tb.a[i][j] != 0.0) xs += h * tb.a[i][j] * k[j];
    if (!rhs_blocks(xs, u, k[i], J)) return false;
    if (i == 0) {  // M = I: D = df/dx itself
      const Mat3 Z = Mat3::Zero(), I = Mat3::Identity();
      Dcc[0] << Z, I, J.wd, J.ww;
      Dct[0] << Z, Z, J.wr, J.wv;
      Dtt[0] << Z, I, J.vr, J.vv;
      Dcu[0] << Z, J.wu;
      continue;
    }
    combine(tb.a[i], i);
    // rows [d', w'] of D_cc = [M_cc rows w; wd M_cc rows d + ww M_cc rows w], and so on.
    Dcc[i].topRows<3>() = Mcc.bottomRows<3>();
    Dcc[i].bottomRows<3>().noalias() = J.wd.lazyProduct(Mcc.topRows<3>());
    Dcc[i].bottomRows<3>().noalias() += J.ww.lazyProduct(Mcc.bottomRows<3>());
    Dct[i].topRows<3>() = Mct.bottomRows<3>();
    Dct[i].bottomRows<3>().noalias() = J.wd.lazyProduct(Mct.topRows<3>());
    Dct[i].bottomRows<3>().noalias() += J.ww.lazyProduct(Mct.bottomRows<3>());
    Dct[i].bottomRows<3>().noalias() += J.wr.lazyProduct(Mtt.topRows<3>());
    Dct[i].bottomRows<3>().noalias() += J.wv.lazyProduct(Mtt.bottomRows<3>());
    Dtt[i].topRows<3>() = Mtt.bottomRows<3>();
    Dtt[i].bottomRows<3>().noalias() = J.vr.lazyProduct(Mtt.topRows<3>());
    Dtt[i].bottomRows<3>().noalias() += J.vv.lazyProduct(Mtt.bottomRows<3>());
    Dcu[i].topRows<3>() = Mcu.bottomRows<3>();
    Dcu[i].bottomRows<3>() = J.wu;
    Dcu[i].bottomRows<3>().noalias() += J.wd.lazyProduct(Mcu.topRows<3>());
    Dcu[i].bottomRows<3>().noalias() += J.ww.lazyProduct(Mcu.bottomRows<3>());
  }
  x_next = x;
  for (int i = 0; i < tb.stages; ++i) x_next += h * tb.b[i] * k[i];
  combine(tb.b, tb.stages);
  // back to the state order [d, r_t, w, v_t]: c = {0, 1, 2, 6, 7, 8}, t = {3, 4, 5, 9, 10, 11}
  constexpr int kc[2] = {0, 6}, kt[2] = {3, 9};
  for (int bi = 0; bi < 2; ++bi) {
    for (int bj = 0; bj < 2; ++bj) {
      A.block<3, 3>(kc[bi], kc[bj]) = Mcc.block<3, 3>(3 * bi, 3 * bj);
      A.block<3, 3>(kc[bi], kt[bj]) = Mct.block<3, 3>(3 * bi, 3 * bj);
      A.block<3, 3>(kt[bi], kt[bj]) = Mtt.block<3, 3>(3 * bi, 3 * bj);
      A.block<3, 3>(kt[bi], kc[bj]).setZero();
    }
    B.block<3, 3>(kc[bi], 0) = Mcu.block<3, 3>(3 * bi, 0);
    B.block<3, 3>(kt[bi], 0).setZero();
  }
  return x_next.allFinite() && A.allFinite() && B.allFinite();
}

bool TwoSatelliteModel::rk_step(int scheme, double h, const Vec12& x, const Vec3& u, Vec12& x_next, Mat12* A,
                                Mat12x3* B) const {
  if (scheme != 3 && scheme != 4) return false;
  if (A != nullptr && B != nullptr) return rk_step_jacobian(scheme, h, x, u, x_next, *A, *B);
  const Tableau& tb = scheme == 3 ? kRk3 : kRk4;
  Vec12 k[4];
  Vec12 xs;
  for (int i = 0; i < tb.stages; ++i) {
    xs = x;
    for (int j = 0; j < i; ++j)
      if (tb.a[i][j] != 0.0) xs += h * tb.a[i][j] * k[j];
    if (!rhs(xs, u, k[i])) return false;
  }
  x_next = x;
  for (int i = 0; i < tb.stages; ++i) x_next += h * tb.b[i] * k[i];
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
