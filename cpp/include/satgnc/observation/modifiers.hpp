#pragma once
/// @file modifiers.hpp
/// Optional corrections of a range measurement (Orekit's "modifiers"): the tropospheric delay
/// (Saastamoinen zenith delay in a standard atmosphere, mapped to the elevation) and the Shapiro
/// (general-relativistic) delay of the Earth's gravity. Pure functions, allocation-free.
#include "satgnc/core/constants.hpp"

namespace satgnc::observation {

/// Meteorological conditions at a station.
struct Weather {
  double pressure = 1013.25;    ///< total pressure, hPa
  double temperature = 288.15;  ///< K
  double water_vapour = 0.0;    ///< partial pressure of water vapour, hPa
};

/// Standard atmosphere at height h (km above the ellipsoid; valid up to 11 km) with relative
/// humidity rh in [0, 1]: P = 1013.25 (1 - 2.2557e-5 h_m)^5.2568 hPa, T = 288.15 - 6.5e-3 h_m K
/// (the ICAO / US 1976 troposphere), water vapour e = rh * exp(-37.2465 + 0.213166 T - 2.56908e-4 T^2) hPa
/// (the saturation fit used with Saastamoinen's model by Berg 1948 and Orekit's standard
/// atmosphere). Heights outside [-0.5, 11] km are clamped to that range.
Weather standard_atmosphere(double height_km, double relative_humidity = 0.5) noexcept;

/// Zenith tropospheric delay (km) of Saastamoinen's model: hydrostatic part
/// 0.0022768 P / (1 - 0.00266 cos 2 phi - 0.28e-6 H) m (Saastamoinen 1972 with Davis et al. 1985;
/// IERS Conventions 2010, eq. 9.11: 2.3070 m at sea level, P = 1013.25 hPa, phi = 45 deg) plus the
/// wet part 0.002277 (1255 / T + 0.05) e m (Saastamoinen 1972). phi geodetic latitude (rad), height km.
double saastamoinen_zenith_delay(const Weather& weather, double latitude_rad, double height_km) noexcept;

/// Tropospheric mapping function of Black and Eisner (1984; RTCA DO-229 appendix A):
/// m(el) = 1.001 / sqrt(0.002001 + sin^2 el), el in rad; and its derivative dm/del in *dm_del.
double tropo_mapping(double elevation_rad, double* dm_del = nullptr) noexcept;

/// Tropospheric delay model of a run.
enum class TroposphereModel {
  /// Radio: Saastamoinen zenith delay (hydrostatic + wet) with the Black-Eisner mapping function.
  saastamoinen = 0,
  /// Optical (satellite laser ranging, the IERS Conventions 2010 model, section 9.2): Mendes-Pavlis
  /// zenith delay at the laser wavelength with the FCULa mapping function (Mendes et al. 2002).
  mendes_pavlis = 1,
  /// Optical, the older laser model (Marini and Murray 1973; IERS Conventions 1996, IERS TN 21,
  /// ch. 9): one closed form in sin(el) for elevations above 10 deg, at the laser wavelength.
  marini_murray = 2,
};

/// "saastamoinen", "mendes_pavlis" or "marini_murray".
const char* troposphere_model_name(TroposphereModel model) noexcept;

/// Checks the troposphere options that MeasurementSettings and od::BatchSettings share, at setup:
/// relative_humidity in [0, 1], a known model, wavelength_um in [0.3, 1.7] micrometres (the range of
/// Ciddor's dispersion formula). Throws std::invalid_argument naming the field and the rule.
void validate_troposphere_options(double relative_humidity, TroposphereModel model, double wavelength_um);

/// Zenith delays of one model, km.
struct ZenithDelay {
  double hydrostatic = 0.0;  ///< km
  double wet = 0.0;          ///< km (non-hydrostatic)
  /// Total zenith delay, km.
  double total() const noexcept { return hydrostatic + wet; }
};

/// Zenith delay at optical wavelengths of Mendes and Pavlis (2004, GRL 31 L14602; IERS Conventions
/// 2010 section 9.2 and its routine FCULZD_HPA): hydrostatic 2.416579e-3 f_h(lambda) P / f_s and
/// non-hydrostatic 1e-4 (5.316 f_nh(lambda) - 3.759 f_h(lambda)) e / f_s m, with
/// f_s = 1 - 0.00266 cos 2 phi - 0.28e-6 H (H in m), the dispersions f_h, f_nh of Ciddor's refractivity
/// at wave number 1 / lambda and 375 ppm CO2. Pressure and water vapour from `weather` (hPa),
/// phi geodetic latitude (rad), height km above the ellipsoid, wavelength_um in micrometres
/// (0.532 for a frequency-doubled Nd:YAG laser).
ZenithDelay mendes_pavlis_zenith_delay(const Weather& weather, double latitude_rad, double height_km,
                                       double wavelength_um) noexcept;

/// FCULa mapping function (Mendes et al. 2002, GRL 29(10) 1414; IERS Conventions 2010 section 9.2,
/// its routine FCUL_A): a continued fraction in sin(el) with a_i = a_i0 + a_i1 t + a_i2 cos phi + a_i3 H
/// (t surface temperature in deg C, H height in m). el elevation (rad), phi latitude (rad), height km,
/// temperature K; dm/del in *dm_del.
double fcul_mapping(double elevation_rad, double latitude_rad, double height_km, double temperature_k,
                    double* dm_del = nullptr) noexcept;

/// Water-vapour pressure (hPa) from the temperature (K) and relative humidity rh in [0, 1] as the IERS
/// Conventions 1996 (TN 21, ch. 9) give it for Marini-Murray (Rh in percent there):
/// e0 = rh x 6.11 x 10^(7.5 t / (237.3 + t)) hPa with t = T - 273.15 deg C.
double marini_murray_water_vapour(double temperature_k, double relative_humidity) noexcept;

/// Tropospheric range delay (km) of Marini and Murray (1973) for laser ranging, in the form of the IERS
/// Conventions 1996 (TN 21, ch. 9, eqs. 1-4; Orekit's MariniMurrayModel):
/// dR = f(lambda) / f(phi, H) x (A + B) / (sin E + (B / (A + B)) / (sin E + 0.01)) m, with
/// A = 0.002357 P0 + 0.000141 e0, K = 1.163 - 0.00968 cos 2 phi - 0.00104 T0 + 0.00001435 P0,
/// B = 1.084e-8 P0 T0 K + 4.734e-8 (P0^2 / T0) (2 / (3 - 1 / K)),
/// f(lambda) = 0.9650 + 0.0164 / lambda^2 + 0.000228 / lambda^4 (lambda in um; 1 for a ruby laser),
/// f(phi, H) = 1 - 0.0026 cos 2 phi - 0.00031 H (H km). P0 pressure and e0 water vapour (hPa), T0 K
/// from `weather`; phi geodetic latitude (rad), height km, wavelength_um in micrometres, elevation
/// rad (the model is stated for E > 10 deg); d dR / d E (km/rad) in *d_del. There is no separate
/// zenith delay and mapping: the elevation dependence is the closed form above.
double marini_murray_delay(const Weather& weather, double latitude_rad, double height_km,
                           double wavelength_um, double elevation_rad, double* d_del = nullptr) noexcept;

/// One-way Shapiro delay (km) of the Earth's gravity on a signal between points at geocentric
/// distances r1, r2 (km) separated by rho (km): (2 mu / c^2) ln((r1 + r2 + rho) / (r1 + r2 - rho))
/// (Moyer 2000, eq. 8-38 with the Earth as the only body; 1.7 cm from a station to GEO). Optional
/// partials d/d(r1 + r2) and d/d rho. Returns 0 when r1 + r2 <= rho (degenerate).
double shapiro_delay(double r1, double r2, double rho, double mu = core::earth::mu, double* d_dsum = nullptr,
                     double* d_drho = nullptr) noexcept;

}  // namespace satgnc::observation
