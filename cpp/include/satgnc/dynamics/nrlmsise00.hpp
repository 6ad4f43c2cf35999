#pragma once
/// @file nrlmsise00.hpp
/// NRLMSISE-00 empirical model of the neutral atmosphere (Picone, Hedin, Drob, Aikin 2002, JGR 107(A12)
/// 1468; the NRL reference Fortran GTD7/GTD7D is the definition), implemented here from the published
/// model with its coefficient tables shipped as data (cpp/data/nrlmsise00_coefficients.txt, compiled in).
/// Number densities in m^-3, mass density in kg/m^3, temperatures in K. docs/atmosphere.md has the
/// inputs, the range policy and the checks (the model's 17 published test cases).
#include <array>

#include "satgnc/dynamics/atmosphere.hpp"
#include "satgnc/dynamics/space_weather.hpp"

namespace satgnc::dynamics {

/// The model's own arguments (those of GTD7), in its units.
struct Nrlmsise00Input {
  int day_of_year = 172;           ///< 1..366 (the year itself is ignored by the model)
  double ut_seconds = 29000.0;     ///< universal time, s of the day, [0, 86400]
  double altitude = 400.0;         ///< geodetic altitude, km, [0, 1000] for evaluate_checked()
  double latitude = 60.0;          ///< geodetic latitude, deg, [-90, 90]
  double longitude = -70.0;        ///< east longitude, deg, [-360, 360]
  double local_solar_time = 16.0;  ///< local (apparent) solar time, hours, [0, 24]
  double f107a = 150.0;            ///< 81-day centred mean of F10.7, sfu, [0, 400]
  double f107 = 150.0;             ///< F10.7 of the previous day, sfu, [0, 400]
  double ap = 4.0;                 ///< daily Ap, [0, 400]
  /// Ap history, used when switch 9 is -1: daily Ap; 3-h ap now; 3, 6, 9 h before; mean of the eight
  /// 3-h values 12-33 h before; mean of the eight 36-57 h before. Each in [0, 400].
  std::array<double, 7> ap_history{{4.0, 4.0, 4.0, 4.0, 4.0, 4.0, 4.0}};

  /// Throw std::invalid_argument naming prefix.field (e.g. "nrlmsise00.altitude: must be in [0, 1000]
  /// km, got -1") unless every field is finite and in its range above.
  void validate(const char* prefix = "nrlmsise00") const;
};

/// Output of one evaluation (GTD7 / GTD7D), SI units.
struct Nrlmsise00Output {
  double he = 0.0;           ///< He number density, m^-3
  double o = 0.0;            ///< O, m^-3
  double n2 = 0.0;           ///< N2, m^-3
  double o2 = 0.0;           ///< O2, m^-3
  double ar = 0.0;           ///< Ar, m^-3
  double h = 0.0;            ///< H, m^-3
  double n = 0.0;            ///< N, m^-3
  double anomalous_o = 0.0;  ///< anomalous (hot) oxygen, m^-3
  /// Total mass density, kg/m^3: GTD7's (He, O, N2, O2, Ar, H, N) or, with anomalous_oxygen, GTD7D's
  /// "effective drag" density that adds the anomalous oxygen.
  double mass_density = 0.0;
  double exospheric_temperature = 0.0;  ///< K
  double temperature = 0.0;             ///< temperature at the altitude, K
};

/// Switches of the model (TSELEC), indexed as the Fortran's: switches[i] for i = 1..23 (index 0 is
/// ignored: satgnc is always SI). 1 = on, 0 = off, 2 = main effect off but cross terms on; switch 9 may be
/// -1 (use Input::ap_history instead of the daily Ap). Default: all 1 (the test cases' setting).
using Nrlmsise00Switches = std::array<double, 24>;

/// All switches on (1).
Nrlmsise00Switches nrlmsise00_default_switches() noexcept;

/// Throw std::invalid_argument naming "name[i]" unless every switch 1..23 is 0, 1 or 2 (switch 9 also -1).
void nrlmsise00_validate_switches(const Nrlmsise00Switches& switches, const char* name = "switches");

/// One evaluation of the model (GTD7; GTD7D's mass density with anomalous_oxygen). Inputs are used as
/// given (no range check; see Nrlmsise00Input::validate). Allocation-free, noexcept, thread-safe.
Nrlmsise00Output nrlmsise00(const Nrlmsise00Input& in, const Nrlmsise00Switches& switches,
                            bool anomalous_oxygen) noexcept;

/// Settings of the NRLMSISE-00 AtmosphereModel.
struct Nrlmsise00Settings {
  /// Epoch of t = 0 as a two-part TT Julian date, days (the ForceModel convention; default J2000.0 TT).
  /// Converted to UTC once (ERFA eraTttai, eraTaiutc) for the model's day of year and UT seconds; a
  /// leap second inside an arc shifts UT by 1 s (negligible for the model).
  double epoch_jd1 = 2451545.0;
  double epoch_jd2 = 0.0;      ///< second part of the TT Julian date, days
  SpaceWeather space_weather;  ///< F10.7 (previous day), F10.7a (81-day), daily Ap; constants
  /// Ap history (see Nrlmsise00Input::ap_history), used when use_ap_history is true.
  std::array<double, 7> ap_history{{4.0, 4.0, 4.0, 4.0, 4.0, 4.0, 4.0}};
  bool use_ap_history = false;  ///< true: switch 9 = -1 (the 7-element Ap history) whatever switches[9]
  /// true (default): GTD7D's drag density including anomalous oxygen (the one to use for drag above
  /// ~500 km); false: GTD7's total mass density.
  bool anomalous_oxygen = true;
  Nrlmsise00Switches switches = nrlmsise00_default_switches();  ///< see Nrlmsise00Switches
  /// Step of the central-difference density gradient, km (> 0, <= 1; default 0.01 km = 10 m).
  double gradient_step = 1.0e-2;

  /// Throw std::invalid_argument naming prefix.field on non-finite epoch, space weather or Ap history
  /// out of [0, 400], a bad switch, or a gradient step outside (0, 1] km.
  void validate(const char* prefix = "nrlmsise00") const;
};

/// NRLMSISE-00 as an AtmosphereModel (for AtmosphereDrag). Inputs from the AtmospherePoint: geodetic
/// height (km), latitude and longitude (WGS-84, from ITRF), local apparent solar time from the Sun
/// direction in ITRF (12 h + the hour angle of the Sun, i.e. the longitude east of the anti-Sun
/// meridian), day of year and UT seconds from the epoch + t. Space weather constant over the arc.
/// Range policy inside a propagation (density() cannot throw): below 0 km the density of 0 km is
/// returned; above 1000 km the model's own exospheric (diffusive-equilibrium) profile is used as is.
/// The gradient is a central difference of density() along the three ITRF axes with gradient_step km
/// (truncation (step/H)^2/6 relative, 7e-9 for 10 m and a 50 km scale height; 6 extra evaluations).
class Nrlmsise00 final : public AtmosphereModel {
 public:
  /// Throws std::invalid_argument naming the field (Nrlmsise00Settings::validate).
  explicit Nrlmsise00(const Nrlmsise00Settings& settings = Nrlmsise00Settings{});
  double density(const AtmospherePoint& p) const noexcept override;
  double density_gradient(const AtmospherePoint& p, Vec3& grad_itrf) const noexcept override;
  double gradient_step() const noexcept override { return settings_.gradient_step; }
  /// The model's inputs at the point (day of year, UT, geodetic coordinates in deg, apparent LST).
  Nrlmsise00Input input(const AtmospherePoint& p) const noexcept;
  /// The full output (densities, temperatures) at the point.
  Nrlmsise00Output evaluate(const AtmospherePoint& p) const noexcept;
  const Nrlmsise00Settings& settings() const { return settings_; }  ///< as given

 private:
  Nrlmsise00Settings settings_;
  Nrlmsise00Switches switches_;       // with switch 9 = -1 when use_ap_history
  double utc_days_since_year_start_;  // UTC days from 1 January 0 h of year_ to the epoch
  int year_;
};

}  // namespace satgnc::dynamics
