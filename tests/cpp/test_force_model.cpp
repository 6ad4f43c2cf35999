// Force-model accelerations and analytic Jacobians against central finite differences.
#include <cmath>
#include <stdexcept>
#include <string>

#include "satgnc/dynamics/force_model.hpp"
#include "testing.hpp"

using satgnc::Mat3;
using satgnc::Vec3;
namespace dyn = satgnc::dynamics;

namespace {

// Central differences of f(r, v) with respect to r (wrt_r) or v, step h_rel * scale.
template <typename F>
Mat3 fd_jacobian(F f, const Vec3& r, const Vec3& v, bool wrt_r, double h) {
  Mat3 j;
  for (int k = 0; k < 3; ++k) {
    Vec3 rp = r, rm = r, vp = v, vm = v;
    if (wrt_r) {
      rp[k] += h;
      rm[k] -= h;
    } else {
      vp[k] += h;
      vm[k] -= h;
    }
    j.col(k) = (f(rp, vp) - f(rm, vm)) / (2.0 * h);
  }
  return j;
}

dyn::ForceModel full_model() {
  dyn::ForceModel m;
  m.j2 = dyn::J2Gravity{};
  dyn::ExponentialDrag d;
  d.rho0 = 3.614e-13;  // kg/m^3 at 700 km (Vallado 4th ed. Table 8-4)
  d.h0 = 700.0;
  d.scale_height = 88.667;
  d.cd = 2.2;
  d.area = 10.0;
  d.mass = 500.0;
  m.drag = d;
  return m;
}

// Inclined LEO point well off every symmetry plane.
const Vec3 kR(-4502.0, 3870.0, 3420.0);
const Vec3 kV(-2.1, -5.3, 4.4);

}  // namespace

TEST(ForceModel, PointMassJacobianMatchesFiniteDifferences) {
  Vec3 a;
  Mat3 g;
  dyn::point_mass_jacobian(dyn::earth::mu, kR, a, g);
  auto f = [](const Vec3& r, const Vec3&) { return dyn::point_mass_acceleration(dyn::earth::mu, r); };
  SATGNC_EXPECT_REL(g, fd_jacobian(f, kR, kV, true, 1e-2), 1e-8);
  SATGNC_EXPECT_REL(a, dyn::point_mass_acceleration(dyn::earth::mu, kR), 1e-15);
  EXPECT_NEAR(g.trace(), 0.0, 1e-20);  // Laplace: gravity field is divergence-free
}

TEST(ForceModel, J2JacobianMatchesFiniteDifferences) {
  dyn::J2Gravity j2;
  Vec3 a;
  Mat3 g;
  dyn::j2_jacobian(j2, kR, a, g);
  auto f = [&](const Vec3& r, const Vec3&) { return dyn::j2_acceleration(j2, r); };
  SATGNC_EXPECT_REL(g, fd_jacobian(f, kR, kV, true, 1e-2), 1e-7);
  SATGNC_EXPECT_REL(a, dyn::j2_acceleration(j2, kR), 1e-15);
  EXPECT_NEAR(g.trace(), 0.0, 1e-6 * g.norm());  // the J2 potential is harmonic too
  // Symmetric: the field derives from a potential.
  EXPECT_LE((g - g.transpose()).norm(), 1e-12 * g.norm());
}

TEST(ForceModel, J2AccelerationIsMinusGradientOfPotential) {
  dyn::J2Gravity j2;
  const double h = 1e-3;
  Vec3 grad;
  for (int k = 0; k < 3; ++k) {
    Vec3 rp = kR, rm = kR;
    rp[k] += h;
    rm[k] -= h;
    grad[k] = (dyn::j2_potential(j2, rp) - dyn::j2_potential(j2, rm)) / (2 * h);
  }
  SATGNC_EXPECT_REL(-grad, dyn::j2_acceleration(j2, kR), 1e-8);
}

TEST(ForceModel, DragJacobiansMatchFiniteDifferences) {
  const dyn::ForceModel m = full_model();
  const dyn::ExponentialDrag& d = *m.drag;
  Vec3 a;
  Mat3 gr, gv;
  dyn::drag_jacobians(d, kR, kV, a, gr, gv);
  auto f = [&](const Vec3& r, const Vec3& v) { return dyn::drag_acceleration(d, r, v); };
  SATGNC_EXPECT_REL(gr, fd_jacobian(f, kR, kV, true, 1e-2), 1e-7);
  SATGNC_EXPECT_REL(gv, fd_jacobian(f, kR, kV, false, 1e-5), 1e-8);
  SATGNC_EXPECT_REL(a, dyn::drag_acceleration(d, kR, kV), 1e-15);
  // Drag opposes the velocity relative to the co-rotating atmosphere.
  const Vec3 vrel = kV - d.omega.cross(kR);
  EXPECT_NEAR(a.normalized().dot(vrel.normalized()), -1.0, 1e-14);
}

TEST(ForceModel, DragMagnitudeAndUnits) {
  // rho = rho0 at h = h0: |a| = 0.5 Cd A/m rho |v_rel|^2 with SI conversion (1/m -> 1e3/km).
  dyn::ExponentialDrag d;
  d.rho0 = 1e-12;
  d.h0 = 500.0;
  d.scale_height = 60.0;
  d.cd = 2.0;
  d.area = 4.0;
  d.mass = 100.0;
  d.omega.setZero();
  const Vec3 r(d.body_radius + 500.0, 0, 0), v(0, 7.6, 0);
  const Vec3 a = dyn::drag_acceleration(d, r, v);
  const double expected = 0.5 * 2.0 * 4.0 / 100.0 * 1e-12 * (7600.0 * 7600.0) / 1000.0;  // km/s^2
  SATGNC_EXPECT_REL(a.norm(), expected, 1e-14);
  EXPECT_DOUBLE_EQ(dyn::exponential_density(d, d.body_radius + 560.0), 1e-12 * std::exp(-1.0));
}

TEST(ForceModel, CombinedJacobiansMatchFiniteDifferences) {
  const dyn::ForceModel m = full_model();
  Vec3 a;
  Mat3 gr, gv;
  m.acceleration_jacobians(0.0, kR, kV, a, gr, gv);
  auto f = [&](const Vec3& r, const Vec3& v) { return m.acceleration(0.0, r, v); };
  SATGNC_EXPECT_REL(gr, fd_jacobian(f, kR, kV, true, 1e-2), 1e-7);
  // da/dv of the sum is tiny (1e-9 1/s) next to |a| (1e-2 km/s^2): FD roundoff is eps |a| / h, so
  // use h = 1e-3 km/s and a 1e-5 tolerance here; the drag-only test above checks it to 1e-8.
  SATGNC_EXPECT_REL(gv, fd_jacobian(f, kR, kV, false, 1e-3), 1e-5);
  Vec3 ad;
  Mat3 gdr, gdv;
  dyn::drag_jacobians(*m.drag, kR, kV, ad, gdr, gdv);
  EXPECT_EQ(gv, gdv);
  SATGNC_EXPECT_REL(a, m.acceleration(0.0, kR, kV), 1e-15);
  EXPECT_FALSE(m.conservative());
  dyn::ForceModel g;
  g.j2 = dyn::J2Gravity{};
  EXPECT_TRUE(g.conservative());
  // Energy: potential of point mass + J2.
  EXPECT_NEAR(g.potential(kR), -dyn::earth::mu / kR.norm() + dyn::j2_potential(*g.j2, kR), 1e-12);
}

TEST(ForceModel, DragJacobianAtZeroRelativeVelocityIsFinite) {
  dyn::ExponentialDrag d;
  d.rho0 = 1e-12;
  d.h0 = 500;
  d.scale_height = 60;
  const Vec3 r(7000, 0, 0);
  const Vec3 v = d.omega.cross(r);  // co-rotating: v_rel = 0
  Vec3 a;
  Mat3 gr, gv;
  dyn::drag_jacobians(d, r, v, a, gr, gv);
  EXPECT_TRUE(a.allFinite() && gr.allFinite() && gv.allFinite());
  EXPECT_EQ(a.norm(), 0.0);
  EXPECT_EQ(gv.norm(), 0.0);
}

namespace {
std::string validation_error(const dyn::ForceModel& m) {
  try {
    m.validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(ForceModel, ValidateNamesTheField) {
  dyn::ForceModel m;
  EXPECT_EQ(validation_error(m), "");
  m.mu = -1.0;
  EXPECT_NE(validation_error(m).find("mu: must be finite and > 0"), std::string::npos);
  m.mu = std::nan("");
  EXPECT_NE(validation_error(m).find("mu:"), std::string::npos);
  m = dyn::ForceModel{};
  m.j2 = dyn::J2Gravity{};
  m.j2->radius = 0.0;
  EXPECT_NE(validation_error(m).find("j2.radius"), std::string::npos);
  m.j2 = dyn::J2Gravity{};
  m.j2->mu = 1.0;
  EXPECT_NE(validation_error(m).find("j2.mu: must equal the central-body mu"), std::string::npos);
  m = full_model();
  m.drag->mass = 0.0;
  EXPECT_NE(validation_error(m).find("drag.mass"), std::string::npos);
  m = full_model();
  m.drag->scale_height = -5.0;
  EXPECT_NE(validation_error(m).find("drag.scale_height"), std::string::npos);
  m = full_model();
  m.drag->rho0 = -1e-12;
  EXPECT_NE(validation_error(m).find("drag.rho0"), std::string::npos);
  m = full_model();
  m.drag->omega.x() = INFINITY;
  EXPECT_NE(validation_error(m).find("drag.omega"), std::string::npos);
}

TEST(ForceModel, ValidatePositionRefusesTheCentreAndBelowTheSurface) {
  dyn::ForceModel m = full_model();
  EXPECT_NO_THROW(m.validate_position(Vec3(7000.0, 0.0, 0.0)));
  try {
    m.validate_position(Vec3::Zero(), "r");
    ADD_FAILURE() << "r = 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("r: must be non-zero"), std::string::npos) << e.what();
  }
  EXPECT_THROW(m.validate_position(Vec3(6000.0, 0.0, 0.0)), std::invalid_argument);  // below, with drag
  EXPECT_THROW(m.validate_position(Vec3(NAN, 0.0, 0.0)), std::invalid_argument);
  m.drag.reset();
  EXPECT_NO_THROW(m.validate_position(Vec3(6000.0, 0.0, 0.0)));  // point mass + J2: no surface rule
  try {
    dyn::validate_density_radius(*full_model().drag, -1.0, "radius");
    ADD_FAILURE() << "radius -1 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("radius: is below the surface"), std::string::npos) << e.what();
  }
}
