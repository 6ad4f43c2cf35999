// Atmosphere density models: the AtmospherePoint (ERFA geodetic coordinates), the default
// finite-difference gradient and Harris-Priester (Montenbruck & Gill 2000, 3.5.2, Table 3.8).
#include "satgnc/dynamics/atmosphere.hpp"

#include <erfa.h>

#include <array>
#include <cmath>

#include "satgnc/core/validate.hpp"

namespace satgnc::dynamics {

namespace {
constexpr double kPi = 3.14159265358979323846;
// Table densities are in g/km^3: 1 g/km^3 = 1e-12 kg/m^3.
constexpr double kGramPerKm3 = 1.0e-12;
// eraGc2gd ellipsoid identifier of WGS-84 (ERFA documents 1 = WGS84, 2 = GRS80, 3 = WGS72).
constexpr int kErfaWgs84 = 1;

// Montenbruck & Gill, "Satellite Orbits" (2000), Table 3.8: Harris-Priester density for mean solar
// activity. Heights km; minimum (antapex) and maximum (apex) density g/km^3.
constexpr int kRows = 50;
constexpr std::array<double, kRows> kHeight = {
    100.0, 120.0, 130.0, 140.0, 150.0, 160.0, 170.0, 180.0, 190.0, 200.0, 210.0, 220.0, 230.0,
    240.0, 250.0, 260.0, 270.0, 280.0, 290.0, 300.0, 320.0, 340.0, 360.0, 380.0, 400.0, 420.0,
    440.0, 460.0, 480.0, 500.0, 520.0, 540.0, 560.0, 580.0, 600.0, 620.0, 640.0, 660.0, 680.0,
    700.0, 720.0, 740.0, 760.0, 780.0, 800.0, 840.0, 880.0, 920.0, 960.0, 1000.0};
constexpr std::array<double, kRows> kRhoMin = {
    4.974e+05, 2.490e+04, 8.377e+03, 3.899e+03, 2.122e+03, 1.263e+03, 8.008e+02, 5.283e+02, 3.617e+02,
    2.557e+02, 1.839e+02, 1.341e+02, 9.949e+01, 7.488e+01, 5.709e+01, 4.403e+01, 3.430e+01, 2.697e+01,
    2.139e+01, 1.708e+01, 1.099e+01, 7.214e+00, 4.824e+00, 3.274e+00, 2.249e+00, 1.558e+00, 1.091e+00,
    7.701e-01, 5.474e-01, 3.916e-01, 2.819e-01, 2.042e-01, 1.488e-01, 1.092e-01, 8.070e-02, 6.012e-02,
    4.519e-02, 3.430e-02, 2.632e-02, 2.043e-02, 1.607e-02, 1.281e-02, 1.036e-02, 8.496e-03, 7.069e-03,
    4.680e-03, 3.200e-03, 2.210e-03, 1.560e-03, 1.150e-03};
constexpr std::array<double, kRows> kRhoMax = {
    4.974e+05, 2.490e+04, 8.710e+03, 4.059e+03, 2.215e+03, 1.344e+03, 8.758e+02, 6.010e+02, 4.297e+02,
    3.162e+02, 2.396e+02, 1.853e+02, 1.455e+02, 1.157e+02, 9.308e+01, 7.555e+01, 6.182e+01, 5.095e+01,
    4.226e+01, 3.526e+01, 2.511e+01, 1.819e+01, 1.337e+01, 9.955e+00, 7.492e+00, 5.684e+00, 4.355e+00,
    3.362e+00, 2.612e+00, 2.042e+00, 1.605e+00, 1.267e+00, 1.005e+00, 7.997e-01, 6.390e-01, 5.123e-01,
    4.121e-01, 3.325e-01, 2.691e-01, 2.185e-01, 1.779e-01, 1.452e-01, 1.190e-01, 9.776e-02, 8.059e-02,
    5.741e-02, 4.210e-02, 3.130e-02, 2.360e-02, 1.810e-02};

// Layer i holds heights [kHeight[i], kHeight[i+1]); below the table, layer 0 (extrapolated).
int layer(double h) {
  int i = 0;
  while (i + 2 < kRows && h >= kHeight[static_cast<std::size_t>(i + 1)]) ++i;
  return i;
}

// Exponential interpolation in layer i: rho(h) = rho_i exp(-(h - h_i)/H), H = (h_{i+1} - h_i) /
// ln(rho_i / rho_{i+1}); returns rho (g/km^3) and d rho/dh = -rho/H.
void interpolate(const std::array<double, kRows>& table, int i, double h, double& rho, double& drho_dh) {
  const auto k = static_cast<std::size_t>(i);
  const double scale = (kHeight[k + 1] - kHeight[k]) / std::log(table[k] / table[k + 1]);
  rho = table[k] * std::exp((kHeight[k] - h) / scale);
  drho_dh = -rho / scale;
}

// Unit vector of the bulge apex in ITRF: the Sun direction turned east by lag about the z axis.
Vec3 bulge_apex(const Vec3& sun, double lag) {
  const double c = std::cos(lag), s = std::sin(lag);
  return Vec3(c * sun.x() - s * sun.y(), s * sun.x() + c * sun.y(), sun.z());
}
}  // namespace

AtmospherePoint atmosphere_point(double t, const Vec3& r_itrf, const Vec3& sun_itrf) noexcept {
  AtmospherePoint p;
  p.t = t;
  p.r_itrf = r_itrf;
  const double sn = sun_itrf.norm();
  p.sun_itrf = sn > 0.0 ? Vec3(sun_itrf / sn) : Vec3(Vec3::UnitX());
  double xyz_m[3] = {r_itrf.x() * 1e3, r_itrf.y() * 1e3, r_itrf.z() * 1e3};
  double elong = 0.0, phi = 0.0, height_m = 0.0;
  eraGc2gd(kErfaWgs84, xyz_m, &elong, &phi, &height_m);  // status 0 for WGS84 and finite, r != 0
  p.height = height_m * 1e-3;
  p.latitude = phi;
  p.longitude = elong;
  const double cp = std::cos(phi);
  p.up = Vec3(cp * std::cos(elong), cp * std::sin(elong), std::sin(phi));
  return p;
}

double AtmosphereModel::density_gradient(const AtmospherePoint& p, Vec3& grad_itrf) const noexcept {
  const double rho = density(p);
  const double step = gradient_step();
  for (int j = 0; j < 3; ++j) {
    Vec3 r = p.r_itrf;
    r[j] += step;
    grad_itrf[j] = (density(atmosphere_point(p.t, r, p.sun_itrf)) - rho) / step;
  }
  return rho;
}

HarrisPriester::HarrisPriester(double n, double lag) : n_(n), lag_(lag) {
  core::require(std::isfinite(n) && n >= 2.0 && n <= 6.0, "n",
                "must be in [2, 6] (Montenbruck & Gill: 2 for low inclination, 6 for polar orbits)");
  core::require(std::isfinite(lag) && lag >= 0.0 && lag <= kPi, "lag", "must be in [0, pi] rad",
                "Montenbruck & Gill use 30 deg = 0.523599 rad");
}

double HarrisPriester::density(const AtmospherePoint& p) const noexcept {
  Vec3 grad;
  // The analytic gradient costs a few multiplications more than the density: one code path.
  return density_gradient(p, grad);
}

double HarrisPriester::density_gradient(const AtmospherePoint& p, Vec3& grad_itrf) const noexcept {
  const double h = p.height;
  if (!(h <= max_table_height)) {  // above the table (or NaN): no atmosphere in this model
    grad_itrf.setZero();
    return h > max_table_height ? 0.0 : h;
  }
  const int i = layer(h);
  double dmin = 0.0, dmin_dh = 0.0, dmax = 0.0, dmax_dh = 0.0;
  interpolate(kRhoMin, i, h, dmin, dmin_dh);
  interpolate(kRhoMax, i, h, dmax, dmax_dh);
  // c = cos^2(psi/2) = (1 + cos psi)/2, q = c^(n/2) = cos^n(psi/2).
  const double rn = p.r_itrf.norm();
  const Vec3 rhat = p.r_itrf / rn;
  const Vec3 apex = bulge_apex(p.sun_itrf, lag_);
  const double cos_psi = apex.dot(rhat);
  const double c = 0.5 + 0.5 * cos_psi;
  const double q = std::pow(c, 0.5 * n_);
  const double dq_dc = 0.5 * n_ * std::pow(c, 0.5 * n_ - 1.0);  // n >= 2: finite at c = 0
  const double rho = dmin + (dmax - dmin) * q;
  // d cos psi / d r = (apex - cos psi rhat) / |r|; d h / d r = up.
  const Vec3 dcos = (apex - cos_psi * rhat) / rn;
  grad_itrf = (dmin_dh + (dmax_dh - dmin_dh) * q) * p.up + ((dmax - dmin) * dq_dc * 0.5) * dcos;
  grad_itrf *= kGramPerKm3;
  return rho * kGramPerKm3;
}

}  // namespace satgnc::dynamics
