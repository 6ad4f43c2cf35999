// dynamics::GravityField and the ICGEM reader: J2-only field vs the J2 term, gradient and acceleration
// vs 4th-order finite differences (EGM2008 70x70 and a random field of degree 120), Laplace, rotation,
// the shipped coefficients' published values, bad files, and no allocation in evaluation.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include "derivative_checks.hpp"
#include "malloc_counter.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/dynamics/gravity_field.hpp"
#include "satgnc/frames/earth_rotation.hpp"

namespace {
using satgnc::Mat3;
using satgnc::Vec3;
using satgnc::testing::fd4;
namespace dy = satgnc::dynamics;
using satgnc::frames::UniformRotation;

std::shared_ptr<const dy::GravityCoefficients> egm2008(int degree = 70) {
  return std::make_shared<const dy::GravityCoefficients>(dy::load_gfc(SATGNC_GFC_PATH, degree));
}

std::shared_ptr<const UniformRotation> identity() {
  return std::make_shared<const UniformRotation>(0.0, 0.0);
}

// Random field of degree n: Kaula-like magnitudes 1e-5 / n^2, fully normalized.
std::shared_ptr<const dy::GravityCoefficients> random_field(int nmax, unsigned seed) {
  dy::GravityCoefficients g;
  g.name = "random";
  g.mu = 398600.4415;
  g.radius = 6378.1363;
  g.max_degree = nmax;
  const auto size = static_cast<std::size_t>((nmax + 1) * (nmax + 2) / 2);
  g.c.assign(size, 0.0);
  g.s.assign(size, 0.0);
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  for (int n = 2; n <= nmax; ++n)
    for (int m = 0; m <= n; ++m) {
      const auto i = static_cast<std::size_t>(dy::GravityCoefficients::index(n, m));
      g.c[i] = 1e-5 / (n * n) * nd(rng);
      if (m > 0) g.s[i] = 1e-5 / (n * n) * nd(rng);
    }
  g.c[static_cast<std::size_t>(dy::GravityCoefficients::index(2, 0))] = -4.84e-4;
  return std::make_shared<const dy::GravityCoefficients>(g);
}

// Points: LEO at several latitudes, one 1e-4 rad from the pole, one on the equator, one at GEO.
std::vector<Vec3> points() {
  return {Vec3(6778.0, 0.0, 0.0),        Vec3(4000.0, -3000.0, 4500.0), Vec3(-2500.0, 3500.0, -5500.0),
          Vec3(0.7, 0.0, 6900.0),        Vec3(1.0e-3, -0.5, -7000.0),   Vec3(30000.0, 28000.0, 1000.0),
          Vec3(-5000.0, -4000.0, 1500.0)};
}

TEST(GravityField, ShippedEgm2008HasThePublishedLowDegreeCoefficients) {
  const auto g = egm2008();
  EXPECT_EQ(g->name, "EGM2008");
  EXPECT_EQ(g->max_degree, 70);
  EXPECT_EQ(g->tide_system, "tide_free");
  // Pavlis et al. (2012), EGM2008 tide-free: exact decimal values of the file (parsing is exact to 1 ulp).
  EXPECT_DOUBLE_EQ(g->cnm(2, 0), -0.484165143790815e-03);
  EXPECT_DOUBLE_EQ(g->cnm(2, 2), 0.243938357328313e-05);
  EXPECT_DOUBLE_EQ(g->snm(2, 2), -0.140027370385934e-05);
  EXPECT_DOUBLE_EQ(g->mu, 398600.4415);    // 0.3986004415E+15 m^3/s^2
  EXPECT_DOUBLE_EQ(g->radius, 6378.1363);  // 0.63781363E+07 m
  // Truncation: a request below the file's degree keeps only that many coefficients.
  EXPECT_EQ(dy::load_gfc(SATGNC_GFC_PATH, 8).c.size(), 45u);
}

TEST(GravityField, J2OnlyFieldEqualsTheJ2TermWhenTheRotationIsIdentity) {
  dy::GravityCoefficients g;
  g.mu = satgnc::core::earth::mu;
  g.radius = satgnc::core::earth::radius;
  g.max_degree = 2;
  g.c.assign(6, 0.0);
  g.s.assign(6, 0.0);
  g.c[3] = -satgnc::core::earth::j2 / std::sqrt(5.0);  // C20 normalized = -J2 / sqrt(5)
  const dy::GravityField f(std::make_shared<const dy::GravityCoefficients>(g), 2, 0, identity());
  const dy::J2Gravity j2;
  for (const Vec3& r : points()) {
    Vec3 a, aj;
    Mat3 G, Gj;
    f.jacobian(123.0, r, a, G);
    dy::j2_jacobian(j2, r, aj, Gj);
    // Two formulas of the same term: agreement to a few ulps of the largest entry.
    SATGNC_EXPECT_REL(a, aj, 1e-13);
    SATGNC_EXPECT_REL(G, Gj, 1e-12);
    SATGNC_EXPECT_REL(f.acceleration(0.0, r), aj, 1e-13);
    EXPECT_NEAR(f.potential(0.0, r), dy::j2_potential(j2, r), 1e-13 * std::abs(dy::j2_potential(j2, r)));
  }
}

TEST(GravityField, Egm2008GradientAndAccelerationMatchFourthOrderDifferences) {
  const dy::GravityField f(egm2008(), 70, 70, identity());
  for (const Vec3& r : points()) {
    Vec3 a;
    Mat3 G;
    f.gradient_fixed(r, a, G);
    // Acceleration and gradient evaluations agree exactly (same harmonics).
    SATGNC_EXPECT_REL(f.acceleration_fixed(r), a, 1e-14);
    // Gradient vs FD of the acceleration, h = 1 km: truncation ~ h^4 |a^(5)| is ~1e-9 relative at
    // degree 70 in LEO; rounding 1e-16 |a| / h ~1e-21 1/s^2. Tolerance 1e-7 of the largest entry.
    const Mat3 Gfd = fd4([&](const Vec3& x) { return f.acceleration_fixed(x); }, r, 1.0);
    SATGNC_EXPECT_REL(G, Gfd, 1e-7);
    // Symmetric (a Hessian) and trace-free (Laplace) to rounding.
    EXPECT_LE((G - G.transpose()).norm(), 1e-12 * G.norm());
    EXPECT_LE(std::abs(G.trace()), 1e-12 * G.norm());
    // Acceleration vs -grad V by FD (h = 1 km; V ~ 1e-2 km^2/s^2 in LEO, rounding 1e-18 / 1 km).
    Mat3 dummy;
    Vec3 gfd;
    for (int j = 0; j < 3; ++j) {
      Vec3 e = Vec3::Zero();
      e[j] = 1.0;
      gfd[j] = -(-f.potential_fixed(r + 2 * e) + 8 * f.potential_fixed(r + e) - 8 * f.potential_fixed(r - e) +
                 f.potential_fixed(r - 2 * e)) /
               12.0;
    }
    SATGNC_EXPECT_REL(a, gfd, 1e-7);
  }
}

TEST(GravityField, Degree120RandomFieldIsStableAndConsistent) {
  const dy::GravityField f(random_field(120, 7), 120, 120, identity());
  for (const Vec3& r : points()) {
    Vec3 a;
    Mat3 G;
    f.gradient_fixed(r, a, G);
    ASSERT_TRUE(a.allFinite() && G.allFinite());
    // h = 0.5 km resolves degree 120 (wavelength ~330 km at the surface): tolerance 1e-6.
    const Mat3 Gfd = fd4([&](const Vec3& x) { return f.acceleration_fixed(x); }, r, 0.5);
    SATGNC_EXPECT_REL(G, Gfd, 1e-6);
    EXPECT_LE(std::abs(G.trace()), 1e-11 * G.norm());
  }
}

TEST(GravityField, ZonalFieldOnTheAxisPointsAlongTheAxis) {
  // Only zonal terms: on the z axis the acceleration is along z, and the gradient is diagonal with
  // Gxx = Gyy (the recursion is singularity-free at the pole).
  auto g = *egm2008(20);
  for (int n = 2; n <= 20; ++n)
    for (int m = 1; m <= n; ++m) {
      g.c[static_cast<std::size_t>(dy::GravityCoefficients::index(n, m))] = 0.0;
      g.s[static_cast<std::size_t>(dy::GravityCoefficients::index(n, m))] = 0.0;
    }
  const dy::GravityField f(std::make_shared<const dy::GravityCoefficients>(g), 20, 20, identity());
  Vec3 a;
  Mat3 G;
  f.gradient_fixed(Vec3(0.0, 0.0, 7000.0), a, G);
  EXPECT_LE(a.head<2>().norm(), 1e-15 * std::abs(a.z()));
  EXPECT_NEAR(G(0, 0), G(1, 1), 1e-13 * std::abs(G(0, 0)));
  EXPECT_LE(std::abs(G(0, 1)) + std::abs(G(0, 2)) + std::abs(G(1, 2)), 1e-13 * G.norm());
}

TEST(GravityField, InertialEvaluationRotatesIntoTheEarthFixedFrame) {
  const auto rot = std::make_shared<const UniformRotation>(0.4, 7.292115e-5);
  const dy::GravityField f(egm2008(30), 30, 30, rot);
  const Vec3 r(5000.0, -3000.0, 3500.0);
  const double t = 5000.0;
  Mat3 R;
  Vec3 w;
  rot->rotation(t, R, w);
  SATGNC_EXPECT_REL(f.acceleration(t, r), (R.transpose() * f.acceleration_fixed(R * r)).eval(), 1e-15);
  Vec3 a;
  Mat3 G;
  f.jacobian(t, r, a, G);
  const Mat3 Gfd = fd4([&](const Vec3& x) { return f.acceleration(t, x); }, r, 1.0);
  SATGNC_EXPECT_REL(G, Gfd, 1e-7);
}

TEST(GravityField, EvaluationAllocatesNothing) {
  const dy::GravityField f(egm2008(), 70, 70, identity());
  Vec3 a;
  Mat3 G;
  const Vec3 r(6778.0, 100.0, 200.0);
  g_mallocs = 0;
  g_count = true;
  f.gradient_fixed(r, a, G);
  a += f.acceleration(10.0, r);
  const double v = f.potential(10.0, r);
  g_count = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_TRUE(std::isfinite(v));
}

TEST(GravityField, FullForceModelEvaluationAllocatesNothing) {
  // Field + Sun + Moon + SRP: the field's workspace and the ephemeris nodes are sized at setup; a
  // jump of t by days refreshes the Hermite nodes (two ERFA calls each) without allocating.
  dy::ForceModel fm;
  fm.mu = 398600.4415;
  fm.gravity.emplace(egm2008(), 70, 70, std::make_shared<const UniformRotation>());
  fm.third_body = dy::ThirdBodies{};
  fm.srp = dy::SolarRadiationPressure{};
  fm.validate();
  const Vec3 r(6778.0, 100.0, 200.0), v(0.0, 7.6, 1.0);
  Vec3 a;
  Mat3 ar, av;
  g_mallocs = 0;
  g_count = true;
  for (double t : {0.0, 60.0, 2.0 * 86400.0, -86400.0}) {
    fm.acceleration_jacobians(t, r, v, a, ar, av);
    a += fm.acceleration(t, r, v);
    a += fm.acceleration_partial(dy::ForceParameter::cr, t, r, v);
  }
  const double e = fm.energy(10.0, r, v);
  g_count = false;
  EXPECT_EQ(g_mallocs.load(), 0);
  EXPECT_TRUE(std::isfinite(e) && a.allFinite());
}

TEST(GravityField, ForceModelWithTheFieldMatchesTheFieldAndRefusesJ2) {
  dy::ForceModel fm;
  fm.mu = 398600.4415;
  fm.gravity.emplace(egm2008(20), 20, 20, identity());
  fm.validate();
  const Vec3 r(6778.0, 100.0, 200.0), v(0.0, 7.6, 1.0);
  Vec3 a;
  Mat3 ar, av;
  fm.acceleration_jacobians(0.0, r, v, a, ar, av);
  SATGNC_EXPECT_REL(a, (dy::point_mass_acceleration(fm.mu, r) + fm.gravity->acceleration(0.0, r)).eval(),
                    1e-15);
  SATGNC_EXPECT_REL(fm.acceleration(0.0, r, v), a, 1e-15);
  EXPECT_TRUE(fm.conservative());
  // d a / d mu = a_gravity / mu (every gravity term is linear in GM).
  SATGNC_EXPECT_REL(fm.acceleration_partial(dy::ForceParameter::mu, 0.0, r, v), (a / fm.mu).eval(), 1e-15);
  dy::ForceModel bad = fm;
  bad.j2 = dy::J2Gravity{};
  bad.j2->mu = fm.mu;
  try {
    bad.validate();
    FAIL() << "j2 with a field must throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("gravity: cannot be combined with j2"), std::string::npos)
        << e.what();
  }
  dy::ForceModel wrong_mu = fm;
  wrong_mu.mu = 398600.4415e9;  // m^3/s^2 by mistake
  EXPECT_THROW(wrong_mu.validate(), std::invalid_argument);
}

std::string what_of(const std::string& text, int degree = -1) {
  std::istringstream in(text);
  try {
    dy::parse_gfc(in, "bad.gfc", degree);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

const char* kHeader =
    "product_type gravity_field\n"
    "earth_gravity_constant 0.3986004415E+15\n"
    "radius 0.63781363E+07\n"
    "max_degree 3\n"
    "norm fully_normalized\n"
    "end_of_head ====\n";

TEST(GravityField, GfcReaderNamesTheFileTheLineAndTheKeyword) {
  const std::string ok = std::string(kHeader) + "gfc 2 0 -0.48D-03 0.0D0\ngfc 3 1 1.0e-6 2.0e-6 0 0\n";
  std::istringstream in(ok);
  const auto g = dy::parse_gfc(in, "ok.gfc");
  EXPECT_DOUBLE_EQ(g.cnm(2, 0), -0.48e-3);  // Fortran D exponent
  EXPECT_DOUBLE_EQ(g.snm(3, 1), 2.0e-6);
  EXPECT_EQ(what_of(std::string(kHeader) + "gfc 2 0 -0.48x-03 0.0\n"),
            "bad.gfc:7: gfc: C and S must be finite numbers, got '-0.48x-03' '0.0'");
  EXPECT_EQ(what_of(std::string(kHeader) + "gfc 4 0 1.0 0.0\n"),
            "bad.gfc:7: gfc: degree 4 is above the header's max_degree 3");
  EXPECT_EQ(what_of(std::string(kHeader) + "gfc 2 3 1.0 0.0\n"),
            "bad.gfc:7: gfc: degree and order must be integers with 0 <= M <= L, got '2 3'");
  EXPECT_EQ(what_of(std::string(kHeader) + "gfc 2 0\n"),
            "bad.gfc:7: gfc: expected 'gfc L M C S [sigma_C sigma_S]'");
  EXPECT_EQ(what_of(std::string(kHeader) + "gfct 2 0 1.0 0.0 20000101\n"),
            "bad.gfc:7: gfct: time-variable terms are not supported (static gfc files only)");
  EXPECT_EQ(what_of("radius 0.63781363E+07\nmax_degree 3\nend_of_head\n"),
            "bad.gfc:3: earth_gravity_constant: missing from the header");
  EXPECT_EQ(what_of("earth_gravity_constant 3.9e14\nradius -1\n"),
            "bad.gfc:2: radius: must be a positive number, got '-1'");
  EXPECT_EQ(what_of("earth_gravity_constant 3.9e14\n"),
            "bad.gfc:1: end_of_head: missing: the file ended inside the header");
  EXPECT_EQ(what_of(std::string(kHeader), 5), "max_degree: 5 is above the file's max_degree 3 (bad.gfc)");
  EXPECT_THROW(dy::load_gfc("/nonexistent/file.gfc"), std::invalid_argument);
}

TEST(GravityField, ConstructorRefusesBadDegreeOrderAndNullPointers) {
  const auto g = egm2008(10);
  try {
    dy::GravityField f(g, 12, 12, identity());
    FAIL() << "degree above the file's must throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "degree: 12 is above the file's max_degree 10");
  }
  EXPECT_THROW(dy::GravityField(g, 1, 0, identity()), std::invalid_argument);
  EXPECT_THROW(dy::GravityField(g, 10, 11, identity()), std::invalid_argument);
  EXPECT_THROW(dy::GravityField(nullptr, 10, 10, identity()), std::invalid_argument);
  EXPECT_THROW(dy::GravityField(g, 10, 10, nullptr), std::invalid_argument);
}

}  // namespace
