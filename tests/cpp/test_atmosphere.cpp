// Atmosphere density models: Harris-Priester against Montenbruck & Gill's Table 3.8, its analytic
// gradient against 4th-order central differences, the default one-sided gradient, geodetic heights
// and bad input.
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "satgnc/dynamics/atmosphere.hpp"
#include "satgnc/dynamics/space_weather.hpp"
#include "testing.hpp"

using satgnc::Vec3;
namespace dyn = satgnc::dynamics;

namespace {

constexpr double kA = 6378.137;           // WGS-84 semi-major axis, km
constexpr double kB = 6356.752314245179;  // WGS-84 semi-minor axis, km
constexpr double kLag = 0.523599;         // M&G's bulge lag, rad

// M&G Table 3.8 (typed again here from the book, independently of the source): height km,
// minimum and maximum density g/km^3 (1e-12 kg/m^3).
constexpr std::array<double, 50> kH = {100, 120, 130, 140, 150, 160, 170, 180, 190, 200, 210, 220, 230,
                                       240, 250, 260, 270, 280, 290, 300, 320, 340, 360, 380, 400, 420,
                                       440, 460, 480, 500, 520, 540, 560, 580, 600, 620, 640, 660, 680,
                                       700, 720, 740, 760, 780, 800, 840, 880, 920, 960, 1000};
constexpr std::array<double, 50> kMin = {
    4.974e+05, 2.490e+04, 8.377e+03, 3.899e+03, 2.122e+03, 1.263e+03, 8.008e+02, 5.283e+02, 3.617e+02,
    2.557e+02, 1.839e+02, 1.341e+02, 9.949e+01, 7.488e+01, 5.709e+01, 4.403e+01, 3.430e+01, 2.697e+01,
    2.139e+01, 1.708e+01, 1.099e+01, 7.214e+00, 4.824e+00, 3.274e+00, 2.249e+00, 1.558e+00, 1.091e+00,
    7.701e-01, 5.474e-01, 3.916e-01, 2.819e-01, 2.042e-01, 1.488e-01, 1.092e-01, 8.070e-02, 6.012e-02,
    4.519e-02, 3.430e-02, 2.632e-02, 2.043e-02, 1.607e-02, 1.281e-02, 1.036e-02, 8.496e-03, 7.069e-03,
    4.680e-03, 3.200e-03, 2.210e-03, 1.560e-03, 1.150e-03};
constexpr std::array<double, 50> kMax = {
    4.974e+05, 2.490e+04, 8.710e+03, 4.059e+03, 2.215e+03, 1.344e+03, 8.758e+02, 6.010e+02, 4.297e+02,
    3.162e+02, 2.396e+02, 1.853e+02, 1.455e+02, 1.157e+02, 9.308e+01, 7.555e+01, 6.182e+01, 5.095e+01,
    4.226e+01, 3.526e+01, 2.511e+01, 1.819e+01, 1.337e+01, 9.955e+00, 7.492e+00, 5.684e+00, 4.355e+00,
    3.362e+00, 2.612e+00, 2.042e+00, 1.605e+00, 1.267e+00, 1.005e+00, 7.997e-01, 6.390e-01, 5.123e-01,
    4.121e-01, 3.325e-01, 2.691e-01, 2.185e-01, 1.779e-01, 1.452e-01, 1.190e-01, 9.776e-02, 8.059e-02,
    5.741e-02, 4.210e-02, 3.130e-02, 2.360e-02, 1.810e-02};

// Sun in the equator such that the bulge apex (Sun turned east by the lag) is +x.
const Vec3 kSunForApexX(std::cos(-kLag), std::sin(-kLag), 0.0);

// A point on the equator at geodetic height h (km) in direction +x (apex) or -x (antapex).
dyn::AtmospherePoint equator(double h, double sign) {
  return dyn::atmosphere_point(0.0, Vec3(sign * (kA + h), 0.0, 0.0), kSunForApexX);
}

}  // namespace

TEST(Atmosphere, GeodeticPointOfErfa) {
  // Equator: height = |r| - a; pole: height = |z| - b (exact geometry; 1e-9 km is ERFA's iteration).
  const auto e = dyn::atmosphere_point(0.0, Vec3(0.0, kA + 400.0, 0.0), Vec3::UnitX());
  EXPECT_NEAR(e.height, 400.0, 1e-9);
  EXPECT_NEAR(e.latitude, 0.0, 1e-15);
  EXPECT_NEAR(e.longitude, M_PI / 2, 1e-15);
  EXPECT_LE((e.up - Vec3::UnitY()).norm(), 1e-15);
  const auto p = dyn::atmosphere_point(0.0, Vec3(0.0, 0.0, -(kB + 250.0)), Vec3(0.0, 3.0, 0.0));
  EXPECT_NEAR(p.height, 250.0, 1e-9);
  EXPECT_NEAR(p.latitude, -M_PI / 2, 1e-12);
  EXPECT_LE((p.up + Vec3::UnitZ()).norm(), 1e-12);
  EXPECT_LE((p.sun_itrf - Vec3::UnitY()).norm(), 1e-16);  // normalized
}

TEST(HarrisPriester, ReproducesMontenbruckGillTable38) {
  // At every table height: apex density = the maximum column, antapex = the minimum column. Relative
  // tolerance 1e-9: ERFA's geodetic height is good to 1e-12 km and rho changes by dh/H (H >= 6.7 km).
  const dyn::HarrisPriester hp;
  for (std::size_t i = 0; i < kH.size(); ++i) {
    SCOPED_TRACE("h = " + std::to_string(kH[i]));
    // The 1000 km row 1e-8 km inside the table (above it the density is 0): a 1e-10 relative change.
    const double h = i + 1 == kH.size() ? kH[i] - 1e-8 : kH[i];
    SATGNC_EXPECT_REL(hp.density(equator(h, +1.0)), kMax[i] * 1e-12, 1e-9);
    SATGNC_EXPECT_REL(hp.density(equator(h, -1.0)), kMin[i] * 1e-12, 1e-9);
  }
}

TEST(HarrisPriester, ExponentialBetweenRowsAndBulgeShape) {
  const dyn::HarrisPriester hp2(2.0), hp6(6.0);
  // Exponential interpolation: at the middle height the density is the geometric mean of the rows.
  for (std::size_t i = 0; i + 1 < kH.size(); ++i) {
    const double hm = 0.5 * (kH[i] + kH[i + 1]);
    SATGNC_EXPECT_REL(hp2.density(equator(hm, -1.0)), std::sqrt(kMin[i] * kMin[i + 1]) * 1e-12, 1e-9);
    SATGNC_EXPECT_REL(hp2.density(equator(hm, +1.0)), std::sqrt(kMax[i] * kMax[i + 1]) * 1e-12, 1e-9);
  }
  // psi = 90 deg: cos^n(45 deg) = 2^(-n/2): the mean for n = 2, min + (max - min)/8 for n = 6 (400 km).
  const auto side = dyn::atmosphere_point(0.0, Vec3(0.0, kA + 400.0, 0.0), kSunForApexX);
  SATGNC_EXPECT_REL(hp2.density(side), 0.5 * (2.249 + 7.492) * 1e-12, 1e-9);
  SATGNC_EXPECT_REL(hp6.density(side), (2.249 + (7.492 - 2.249) / 8.0) * 1e-12, 1e-9);
  // Above the table: no atmosphere (M&G). Below: the 100-120 km layer continued (documented).
  EXPECT_EQ(hp2.density(equator(1000.5, 1.0)), 0.0);
  const double h0 = 20.0 / std::log(4.974e5 / 2.490e4);
  SATGNC_EXPECT_REL(hp2.density(equator(50.0, 1.0)), 4.974e5 * std::exp(50.0 / h0) * 1e-12, 1e-9);
}

TEST(HarrisPriester, GradientAgainstFourthOrderDifferences) {
  // Off-table heights, off-symmetry points, both exponents. 4th-order central differences with a
  // 1e-2 km step: truncation ~ (h/H)^4 ~ 1e-8 for H >= 7 km; tolerance 1e-6 relative to |grad|.
  const Vec3 sun = Vec3(0.3, -0.8, 0.45).normalized();
  const std::array<Vec3, 4> points = {Vec3(-4502.0, 3870.0, 3420.0), Vec3(2100.0, -5200.0, 3300.0),
                                      Vec3(6600.0, 300.0, -1205.0), Vec3(-100.0, 200.0, 6500.0)};
  for (double n : {2.0, 6.0}) {
    const dyn::HarrisPriester hp(n);
    for (const Vec3& r : points) {
      const auto p = dyn::atmosphere_point(0.0, r, sun);
      ASSERT_GT(p.height, 100.0);
      ASSERT_LT(p.height, 1000.0);
      Vec3 grad;
      const double rho = hp.density_gradient(p, grad);
      EXPECT_EQ(rho, hp.density(p));
      Vec3 fd;
      const double h = 1e-2;
      auto f = [&](const Vec3& x) { return hp.density(dyn::atmosphere_point(0.0, x, sun)); };
      for (int k = 0; k < 3; ++k) {
        Vec3 e = Vec3::Zero();
        e[k] = h;
        fd[k] = (-f(r + 2 * e) + 8 * f(r + e) - 8 * f(r - e) + f(r - 2 * e)) / (12 * h);
      }
      SATGNC_EXPECT_REL(grad, fd, 1e-6);
    }
  }
}

namespace {
// A model with only density(): the base class's one-sided difference gives its gradient.
struct ExponentialShell final : dyn::AtmosphereModel {
  double density(const dyn::AtmospherePoint& p) const noexcept override {
    return 3.0e-12 * std::exp(-(p.height - 400.0) / 60.0);
  }
};
}  // namespace

TEST(Atmosphere, DefaultOneSidedGradient) {
  // Exact gradient: -rho/H * up. Forward difference with step 1e-3 km: relative error step/(2H) =
  // 8.3e-6 along up; tolerance 1.5e-5.
  const ExponentialShell m;
  const auto p = dyn::atmosphere_point(0.0, Vec3(-4502.0, 3870.0, 3420.0), Vec3::UnitX());
  Vec3 grad;
  const double rho = m.density_gradient(p, grad);
  SATGNC_EXPECT_REL(grad, Vec3((-rho / 60.0) * p.up), 1.5e-5);
  EXPECT_EQ(m.gradient_step(), 1e-3);
}

TEST(HarrisPriester, BadInputNamesTheArgument) {
  auto message = [](double n, double lag) {
    try {
      dyn::HarrisPriester hp(n, lag);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no throw");
  };
  EXPECT_EQ(message(1.0, 0.5).rfind("n: must be in [2, 6]", 0), 0u) << message(1.0, 0.5);
  EXPECT_EQ(message(7.0, 0.5).rfind("n: must be in [2, 6]", 0), 0u);
  EXPECT_EQ(message(NAN, 0.5).rfind("n: ", 0), 0u);
  EXPECT_EQ(message(2.0, -0.1).rfind("lag: must be in [0, pi] rad", 0), 0u) << message(2.0, -0.1);
  EXPECT_EQ(message(2.0, 4.0).rfind("lag: ", 0), 0u);
  EXPECT_EQ(message(6.0, 0.0), "no throw");
}

TEST(SpaceWeather, DefaultsAndRangesNameTheField) {
  const dyn::SpaceWeather w;
  EXPECT_EQ(w.f107, 150.0);  // the NRLMSISE-00 reference cases' moderate activity
  EXPECT_EQ(w.f107a, 150.0);
  EXPECT_EQ(w.ap, 4.0);
  EXPECT_NO_THROW(w.validate());
  auto message = [](double f107, double f107a, double ap) {
    dyn::SpaceWeather s;
    s.f107 = f107;
    s.f107a = f107a;
    s.ap = ap;
    try {
      s.validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no throw");
  };
  EXPECT_EQ(message(-1.0, 150.0, 4.0), "space_weather.f107: must be in [0, 400] sfu, got -1");
  EXPECT_EQ(message(401.0, 150.0, 4.0), "space_weather.f107: must be in [0, 400] sfu, got 401");
  EXPECT_EQ(message(150.0, NAN, 4.0).rfind("space_weather.f107a: must be in [0, 400] sfu", 0), 0u);
  EXPECT_EQ(message(150.0, 150.0, 400.5), "space_weather.ap: must be in [0, 400], got 400.5");
  EXPECT_EQ(message(150.0, 150.0, -3.0), "space_weather.ap: must be in [0, 400], got -3");
  EXPECT_EQ(message(0.0, 400.0, 400.0), "no throw");  // the closed range's ends
}
