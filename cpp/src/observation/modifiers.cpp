#include "satgnc/observation/modifiers.hpp"

#include <algorithm>
#include <cmath>

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
