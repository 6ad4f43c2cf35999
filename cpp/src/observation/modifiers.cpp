#include "satgnc/observation/modifiers.hpp"

#include <algorithm>
#include <cmath>

#include "satgnc/core/validate.hpp"
#include "satgnc/observation/light_time.hpp"

namespace satgnc::observation {

Weather standard_atmosphere(double height_km, double relative_humidity) noexcept {
  const double h = 1000.0 * std::clamp(height_km, -0.5, 11.0);  // m
  Weather w;
  w.pressure = 1013.25 * std::pow(1.0 - 2.2557e-5 * h, 5.2568);
  w.temperature = 288.15 - 6.5e-3 * h;
  const double T = w.temperature;
  w.water_vapour =
      std::clamp(relative_humidity, 0.0, 1.0) * std::exp(-37.2465 + 0.213166 * T - 2.56908e-4 * T * T);
  return w;
}

double saastamoinen_zenith_delay(const Weather& w, double latitude_rad, double height_km) noexcept {
  const double f = 1.0 - 0.00266 * std::cos(2.0 * latitude_rad) - 0.28e-6 * (1000.0 * height_km);
  const double hydrostatic = 0.0022768 * w.pressure / f;                           // m
  const double wet = 0.002277 * (1255.0 / w.temperature + 0.05) * w.water_vapour;  // m
  return 1e-3 * (hydrostatic + wet);                                               // km
}

double tropo_mapping(double el, double* dm_del) noexcept {
  const double s = std::sin(el);
  const double q = 0.002001 + s * s;
  const double m = 1.001 / std::sqrt(q);
  if (dm_del) *dm_del = -m * s * std::cos(el) / q;
  return m;
}

void validate_troposphere_options(double relative_humidity, TroposphereModel model, double wavelength_um) {
  core::require(std::isfinite(relative_humidity) && relative_humidity >= 0.0 && relative_humidity <= 1.0,
                "relative_humidity", "must be in [0, 1]");
  const int tm = static_cast<int>(model);
  core::require(tm >= 0 && tm <= 2, "troposphere_model",
                "unknown model (hint: saastamoinen, mendes_pavlis or marini_murray)");
  core::require(std::isfinite(wavelength_um) && wavelength_um >= 0.3 && wavelength_um <= 1.7, "wavelength_um",
                "must be in [0.3, 1.7] micrometres (the range of Ciddor's dispersion formula)");
}

const char* troposphere_model_name(TroposphereModel model) noexcept {
  switch (model) {
    case TroposphereModel::saastamoinen:
      return "saastamoinen";
    case TroposphereModel::mendes_pavlis:
      return "mendes_pavlis";
    case TroposphereModel::marini_murray:
      return "marini_murray";
  }
  return "unknown";
}

ZenithDelay mendes_pavlis_zenith_delay(const Weather& w, double latitude_rad, double height_km,
                                       double wavelength_um) noexcept {
  // Ciddor's dispersion constants (um^-2) and the CO2 content (ppm) of the IERS model.
  constexpr double k0 = 238.0185, k1 = 19990.975, k2 = 57.362, k3 = 579.55174;
  constexpr double w0 = 295.235, w1 = 2.6422, w2 = -0.032380, w3 = 0.004028;
  constexpr double co2_ppm = 375.0;
  const double s2 = 1.0 / (wavelength_um * wavelength_um);  // sigma^2, um^-2
  const double fs = 1.0 - 0.00266 * std::cos(2.0 * latitude_rad) - 0.28e-6 * (1000.0 * height_km);
  const double co2 = 1.0 + 0.534e-6 * (co2_ppm - 450.0);
  const double fh =
      0.01 * co2 * (k1 * (k0 + s2) / ((k0 - s2) * (k0 - s2)) + k3 * (k2 + s2) / ((k2 - s2) * (k2 - s2)));
  const double fnh = 0.003101 * (w0 + 3.0 * w1 * s2 + 5.0 * w2 * s2 * s2 + 7.0 * w3 * s2 * s2 * s2);
  ZenithDelay z;
  z.hydrostatic = 1e-3 * (2.416579e-3 * fh * w.pressure / fs);               // km
  z.wet = 1e-3 * (1e-4 * (5.316 * fnh - 3.759 * fh) * w.water_vapour / fs);  // km
  return z;
}

double fcul_mapping(double el, double latitude_rad, double height_km, double temperature_k,
                    double* dm_del) noexcept {
  const double t = temperature_k - 273.15;  // deg C
  const double c = std::cos(latitude_rad);
  const double H = 1000.0 * height_km;  // m
  const double a1 = 0.121008e-2 + 0.17295e-5 * t + 0.3191e-4 * c - 0.18478e-7 * H;
  const double a2 = 0.304965e-2 + 0.2346e-5 * t - 0.1035e-3 * c - 0.1856e-7 * H;
  const double a3 = 0.68777e-1 + 0.1972e-4 * t - 0.3458e-2 * c + 0.1060e-6 * H;
  const double num = 1.0 + a1 / (1.0 + a2 / (1.0 + a3));
  const double s = std::sin(el);
  const double q3 = s + a3;
  const double q2 = s + a2 / q3;
  const double den = s + a1 / q2;
  const double m = num / den;
  if (dm_del) {
    // d den / d s = 1 - a1 / q2^2 (1 - a2 / q3^2)
    const double dden = 1.0 - a1 / (q2 * q2) * (1.0 - a2 / (q3 * q3));
    *dm_del = -m / den * dden * std::cos(el);
  }
  return m;
}

double marini_murray_water_vapour(double temperature_k, double relative_humidity) noexcept {
  const double t = temperature_k - 273.15;  // deg C
  return relative_humidity * 6.11 * std::pow(10.0, 7.5 * t / (237.3 + t));
}

double marini_murray_delay(const Weather& w, double latitude_rad, double height_km, double wavelength_um,
                           double el, double* d_del) noexcept {
  const double P = w.pressure, T = w.temperature, c2 = std::cos(2.0 * latitude_rad);
  const double K = 1.163 - 0.00968 * c2 - 0.00104 * T + 0.00001435 * P;
  const double A = 0.002357 * P + 0.000141 * w.water_vapour;
  const double B = 1.084e-8 * P * T * K + 4.734e-8 * (P * P / T) * (2.0 / (3.0 - 1.0 / K));
  const double l2 = 1.0 / (wavelength_um * wavelength_um);
  const double f_lambda = 0.9650 + 0.0164 * l2 + 0.000228 * l2 * l2;
  const double f_site = 1.0 - 0.0026 * c2 - 0.00031 * height_km;
  const double s = std::sin(el), c = B / (A + B), q = s + 0.01;
  const double den = s + c / q;
  const double dR = 1e-3 * (f_lambda / f_site) * (A + B) / den;  // km
  if (d_del) *d_del = -dR / den * (1.0 - c / (q * q)) * std::cos(el);
  return dR;
}

double shapiro_delay(double r1, double r2, double rho, double mu, double* d_dsum, double* d_drho) noexcept {
  const double sum = r1 + r2;
  const double k = 2.0 * mu / (speed_of_light * speed_of_light);  // km
  if (!(sum > rho) || !(rho >= 0.0)) {
    if (d_dsum) *d_dsum = 0.0;
    if (d_drho) *d_drho = 0.0;
    return 0.0;
  }
  const double den = sum * sum - rho * rho;
  if (d_dsum) *d_dsum = -2.0 * k * rho / den;
  if (d_drho) *d_drho = 2.0 * k * sum / den;
  return k * std::log((sum + rho) / (sum - rho));
}

}  // namespace satgnc::observation
