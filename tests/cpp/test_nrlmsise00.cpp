// NRLMSISE-00: the model's 17 published test cases (every species, mass density, both temperatures),
// GTD7D's drag density, the switches, the AtmosphereModel inputs (day of year, UT, apparent solar
// time), the central-difference gradient against 4th-order differences, drag Jacobians, bad input.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>

#include "../../cpp/src/dynamics/detail/nrlmsise00_reference.hpp"  // private: the direct form, tested here
#include "error_checks.hpp"
#include "malloc_counter.hpp"
#include "satgnc/dynamics/atmosphere.hpp"
#include "satgnc/dynamics/nrlmsise00.hpp"
#include "testing.hpp"

using satgnc::Vec3;
namespace dyn = satgnc::dynamics;

namespace {

// The 17 standard test cases distributed with NRLMSISE-00 (inputs of the NRL test driver: day 172,
// 29000 s, 400 km, 60 N, 70 W, 16 h, F10.7a = F10.7 = 150, Ap = 4, all switches 1, each case changing
// one input). Outputs as printed by the public C release 20041227 of the model (D. Brodowski), file
// tests/msis_testoutput.txt of github.com/st-bender/pynrlmsise00 (commit d8d13fe5), cgs units:
// He, O, N2, O2, Ar (cm^-3), mass density (g/cm^3), H, N, anomalous O (cm^-3), Tinf, T (K).
// Cases 16 and 17 use switch 9 = -1 with all seven Ap-history values 100.
constexpr std::array<std::array<double, 11>, 17> kTable = {{
    {{6.665177E+05, 1.138806E+08, 1.998211E+07, 4.022764E+05, 3.557465E+03, 4.074714E-15, 3.475312E+04,
      4.095913E+06, 2.667273E+04, 1.250540E+03, 1.241416E+03}},
    {{3.407293E+06, 1.586333E+08, 1.391117E+07, 3.262560E+05, 1.559618E+03, 5.001846E-15, 4.854208E+04,
      4.380967E+06, 6.956682E+03, 1.166754E+03, 1.161710E+03}},
    {{1.123767E+05, 6.934130E+04, 4.247105E+01, 1.322750E-01, 2.618848E-05, 2.756772E-18, 2.016750E+04,
      5.741256E+03, 2.374394E+04, 1.239892E+03, 1.239891E+03}},
    {{5.411554E+07, 1.918893E+11, 6.115826E+12, 1.225201E+12, 6.023212E+10, 3.584426E-10, 1.059880E+07,
      2.615737E+05, 2.819879E-42, 1.027318E+03, 2.068878E+02}},
    {{1.851122E+06, 1.476555E+08, 1.579356E+07, 2.633795E+05, 1.588781E+03, 4.809630E-15, 5.816167E+04,
      5.478984E+06, 1.264446E+03, 1.212396E+03, 1.208135E+03}},
    {{8.673095E+05, 1.278862E+08, 1.822577E+07, 2.922214E+05, 2.402962E+03, 4.355866E-15, 3.686389E+04,
      3.897276E+06, 2.667273E+04, 1.220146E+03, 1.212712E+03}},
    {{5.776251E+05, 6.979139E+07, 1.236814E+07, 2.492868E+05, 1.405739E+03, 2.470651E-15, 5.291986E+04,
      1.069814E+06, 2.667273E+04, 1.116385E+03, 1.112999E+03}},
    {{3.740304E+05, 4.782720E+07, 5.240380E+06, 1.759875E+05, 5.501649E+02, 1.571889E-15, 8.896776E+04,
      1.979741E+06, 9.121815E+03, 1.031247E+03, 1.024848E+03}},
    {{6.748339E+05, 1.245315E+08, 2.369010E+07, 4.911583E+05, 4.578781E+03, 4.564420E-15, 3.244595E+04,
      5.370833E+06, 2.667273E+04, 1.306052E+03, 1.293374E+03}},
    {{5.528601E+05, 1.198041E+08, 3.495798E+07, 9.339618E+05, 1.096255E+04, 4.974543E-15, 2.686428E+04,
      4.889974E+06, 2.805445E+04, 1.361868E+03, 1.347389E+03}},
    {{1.375488E+14, 0.000000E+00, 2.049687E+19, 5.498695E+18, 2.451733E+17, 1.261066E-03, 0.000000E+00,
      0.000000E+00, 0.000000E+00, 1.027318E+03, 2.814648E+02}},
    {{4.427443E+13, 0.000000E+00, 6.597567E+18, 1.769929E+18, 7.891680E+16, 4.059139E-04, 0.000000E+00,
      0.000000E+00, 0.000000E+00, 1.027318E+03, 2.274180E+02}},
    {{2.127829E+12, 0.000000E+00, 3.170791E+17, 8.506280E+16, 3.792741E+15, 1.950822E-05, 0.000000E+00,
      0.000000E+00, 0.000000E+00, 1.027318E+03, 2.374389E+02}},
    {{1.412184E+11, 0.000000E+00, 2.104370E+16, 5.645392E+15, 2.517142E+14, 1.294709E-06, 0.000000E+00,
      0.000000E+00, 0.000000E+00, 1.027318E+03, 2.795551E+02}},
    {{1.254884E+10, 0.000000E+00, 1.874533E+15, 4.923051E+14, 2.239685E+13, 1.147668E-07, 0.000000E+00,
      0.000000E+00, 0.000000E+00, 1.027318E+03, 2.190732E+02}},
    {{5.196477E+05, 1.274494E+08, 4.850450E+07, 1.720838E+06, 2.354487E+04, 5.881940E-15, 2.500078E+04,
      6.279210E+06, 2.667273E+04, 1.426412E+03, 1.408608E+03}},
    {{4.260860E+07, 1.241342E+11, 4.929562E+12, 1.048407E+12, 4.993465E+10, 2.914304E-10, 8.831229E+06,
      2.252516E+05, 2.415246E-42, 1.027318E+03, 1.934071E+02}},
}};

dyn::Nrlmsise00Input test_case(int i) {
  dyn::Nrlmsise00Input in;  // defaults are the test driver's base case
  if (i == 1) in.day_of_year = 81;
  if (i == 2) {
    in.ut_seconds = 75000.0;
    in.altitude = 1000.0;
  }
  if (i == 3) in.altitude = 100.0;
  if (i == 4) in.latitude = 0.0;
  if (i == 5) in.longitude = 0.0;
  if (i == 6) in.local_solar_time = 4.0;
  if (i == 7) in.f107a = 70.0;
  if (i == 8) in.f107 = 180.0;
  if (i == 9) in.ap = 40.0;
  if (i >= 10 && i <= 14) in.altitude = std::array<double, 5>{0.0, 10.0, 30.0, 50.0, 70.0}[i - 10];
  if (i == 16) in.altitude = 100.0;
  if (i >= 15) in.ap_history = {{100.0, 100.0, 100.0, 100.0, 100.0, 100.0, 100.0}};
  return in;
}

std::array<double, 11> cgs(const dyn::Nrlmsise00Output& o) {
  const double c = 1.0e-6;  // m^-3 -> cm^-3
  return {{o.he * c, o.o * c, o.n2 * c, o.o2 * c, o.ar * c, o.mass_density * 1.0e-3, o.h * c, o.n * c,
           o.anomalous_o * c, o.exospheric_temperature, o.temperature}};
}

}  // namespace

TEST(Nrlmsise00, ReproducesThePublishedTestTable) {
  const char* names[11] = {"He", "O", "N2", "O2", "Ar", "rho", "H", "N", "anomalous O", "Tinf", "T"};
  double worst = 0.0;
  for (int i = 0; i < 17; ++i) {
    dyn::Nrlmsise00Switches sw = dyn::nrlmsise00_default_switches();
    if (i >= 15) sw[9] = -1.0;
    const std::array<double, 11> got = cgs(dyn::nrlmsise00(test_case(i), sw, false));
    for (int k = 0; k < 11; ++k) {
      // Printed to 7 significant digits: the rounding is at most 5e-7 relative (half a unit of the 7th
      // digit over a mantissa >= 1); 1e-6 leaves room for a last-bit difference in exp/pow. Zeros are
      // exact zeros (species the model sets to 0 below 72.5 km).
      if (kTable[i][k] == 0.0) {
        EXPECT_EQ(got[k], 0.0) << "case " << i + 1 << " " << names[k];
      } else {
        worst = std::max(worst, satgnc::testing::rel_err(got[k], kTable[i][k]));
        EXPECT_LE(satgnc::testing::rel_err(got[k], kTable[i][k]), 1e-6)
            << "case " << i + 1 << " " << names[k] << ": " << got[k] << " vs " << kTable[i][k];
      }
    }
  }
  RecordProperty("max_relative_error", std::to_string(worst));
  std::printf("NRLMSISE-00 test table: max relative error %.3g over 17 cases x 11 outputs\n", worst);
}

// Relative differences of the 11 outputs (cgs order of kTable) of two evaluations; exact zeros must match.
std::array<double, 11> rel_diffs(const dyn::Nrlmsise00Output& a, const dyn::Nrlmsise00Output& b) {
  const std::array<double, 11> x = cgs(a);
  const std::array<double, 11> y = cgs(b);
  std::array<double, 11> d{};
  for (int k = 0; k < 11; ++k)
    d[k] = y[k] == 0.0 ? (x[k] == 0.0 ? 0.0 : 1.0) : satgnc::testing::rel_err(x[k], y[k]);
  return d;
}

TEST(Nrlmsise00, PhaseTablesEqualTheDirectTrigonometry) {
  // The library's form (cos / sin of the day, local time and UT once per evaluation, of each row's
  // phase constants once per process, local-time harmonics by the angle-addition formulas) against
  // the Fortran's cos(w (x - p[k])) per term (detail::msis::nrlmsise00_direct): the same model up to
  // rounding. Tolerance 1e-14 relative on every output, except N2, O2 and Ar at the seeded points: 2e-14,
  // because the model itself moves them by up to 1.4e-14 when the local time changes by one ulp
  // (measured with the direct form: their densities above 600 km are exp(-40) of the temperature, which
  // multiplies a rounding of the exponent by ~40). Measured worst 2026-12-03: printed below.
  const char* names[11] = {"He", "O", "N2", "O2", "Ar", "rho", "H", "N", "anomalous O", "Tinf", "T"};
  std::array<double, 11> worst{};
  for (int i = 0; i < 17; ++i) {
    dyn::Nrlmsise00Switches sw = dyn::nrlmsise00_default_switches();
    if (i >= 15) sw[9] = -1.0;
    for (bool ao : {false, true}) {
      const std::array<double, 11> d = rel_diffs(dyn::nrlmsise00(test_case(i), sw, ao),
                                                 dyn::detail::msis::nrlmsise00_direct(test_case(i), sw, ao));
      for (int k = 0; k < 11; ++k) {
        EXPECT_LE(d[k], 1e-14) << "published case " << i + 1 << " " << names[k];
        worst[k] = std::max(worst[k], d[k]);
      }
    }
  }
  // Seeded points over the model's physical domain: 0-1000 km (a fifth below 120 km), every latitude,
  // longitude, local time, day and UT, F10.7a in [65, 250] sfu with F10.7 within 0.6-1.4 of it, Ap and
  // the Ap history in [0, 300], switch 9 = 1 or -1, and a fifth with random 0 / 1 / 2 switches.
  // (Unphysical space weather, e.g. F10.7 = 1 with F10.7a = 369, gives 1e35 K: no digits to compare.)
  std::mt19937_64 rng(20261203);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n = 0; n < 3000; ++n) {
    dyn::Nrlmsise00Input in;
    in.day_of_year = 1 + static_cast<int>(u(rng) * 366.0) % 366;
    in.ut_seconds = 86400.0 * u(rng);
    in.altitude = n < 600 ? 120.0 * u(rng) : 1000.0 * u(rng);
    in.latitude = 180.0 * u(rng) - 90.0;
    in.longitude = 720.0 * u(rng) - 360.0;
    in.local_solar_time = 24.0 * u(rng);
    in.f107a = 65.0 + 185.0 * u(rng);
    in.f107 = in.f107a * (0.6 + 0.8 * u(rng));
    in.ap = 300.0 * u(rng);
    for (double& a : in.ap_history) a = 300.0 * u(rng);
    dyn::Nrlmsise00Switches sw = dyn::nrlmsise00_default_switches();
    if (n % 3 == 1) sw[9] = -1.0;
    if (n % 5 == 2) {
      for (int k = 1; k < 24; ++k) sw[k] = static_cast<double>(static_cast<int>(u(rng) * 3.0) % 3);
      if (u(rng) < 0.3) sw[9] = -1.0;
    }
    const bool ao = n % 2 == 0;
    const std::array<double, 11> d =
        rel_diffs(dyn::nrlmsise00(in, sw, ao), dyn::detail::msis::nrlmsise00_direct(in, sw, ao));
    for (int k = 0; k < 11; ++k) {
      const double tol = (k >= 2 && k <= 4) ? 2e-14 : 1e-14;  // N2, O2, Ar: see above
      EXPECT_LE(d[k], tol) << "seeded point " << n << " at " << in.altitude << " km, " << names[k];
      worst[k] = std::max(worst[k], d[k]);
    }
  }
  std::string line;
  for (int k = 0; k < 11; ++k) {
    char buf[48];
    std::snprintf(buf, sizeof buf, " %s %.2g", names[k], worst[k]);
    line += buf;
  }
  RecordProperty("max_relative_difference", line);
  std::printf("NRLMSISE-00 phase tables vs direct cos, max relative difference (17 cases, 3000 points):%s\n",
              line.c_str());
}

TEST(Nrlmsise00, DragDensityAddsAnomalousOxygen) {
  // GTD7D: mass density + 16 amu x anomalous O (1.66e-24 g per amu, the model's constant).
  for (int i : {0, 2, 5}) {
    const auto a = dyn::nrlmsise00(test_case(i), dyn::nrlmsise00_default_switches(), false);
    const auto d = dyn::nrlmsise00(test_case(i), dyn::nrlmsise00_default_switches(), true);
    const double expected = a.mass_density + 16.0 * 1.66e-27 * a.anomalous_o;  // kg/m^3 (1.66e-27 kg/amu)
    SATGNC_EXPECT_REL(d.mass_density, expected, 1e-14);                        // same sums, rounding only
    EXPECT_GT(d.mass_density, a.mass_density);
  }
  // At 1000 km (case 3) anomalous O adds 2.4e4 cm^-3 x 16 amu = 6.3e-19 g/cm^3 to 2.757e-18: +23 %.
  const auto a = dyn::nrlmsise00(test_case(2), dyn::nrlmsise00_default_switches(), false);
  const auto d = dyn::nrlmsise00(test_case(2), dyn::nrlmsise00_default_switches(), true);
  EXPECT_NEAR(d.mass_density / a.mass_density, 1.229, 0.002);  // 1 + 16*2.374394e4*1.66e-24/2.756772e-18
}

TEST(Nrlmsise00, SwitchesTurnEffectsOff) {
  // Switch 7 (diurnal) off: the local-time dependence of Tinf disappears except the semi/terdiurnal terms;
  // with 7, 8 and 14 all off, Tinf no longer depends on local solar time at all (to rounding).
  dyn::Nrlmsise00Switches sw = dyn::nrlmsise00_default_switches();
  sw[7] = 0.0;
  sw[8] = 0.0;
  sw[14] = 0.0;
  dyn::Nrlmsise00Input a = test_case(0);
  dyn::Nrlmsise00Input b = test_case(0);
  b.local_solar_time = 4.0;
  const double ta = dyn::nrlmsise00(a, sw, false).exospheric_temperature;
  const double tb = dyn::nrlmsise00(b, sw, false).exospheric_temperature;
  // Magnetic terms carry cos(local time) through swc[7] only (still 1 with switch 7 = 0): Ap = 4 gives
  // apdf = 0, so those terms vanish and the difference is rounding.
  EXPECT_NEAR(ta, tb, 1e-9);
  const auto full = dyn::nrlmsise00(b, dyn::nrlmsise00_default_switches(), false);
  EXPECT_GT(std::abs(full.exospheric_temperature - tb), 10.0);  // the diurnal tide is tens of K
}

TEST(Nrlmsise00, ModelInputsFromThePoint) {
  // Epoch 2003-06-21 08:03:20 UTC (day 172, 29000 s) as a TT date: UTC + 64.184 s (32 leap seconds).
  dyn::Nrlmsise00Settings s;
  s.epoch_jd1 = 2452811.5;
  s.epoch_jd2 = (29000.0 + 64.184) / 86400.0;
  s.anomalous_oxygen = false;
  const dyn::Nrlmsise00 model(s);
  // The Sun on the ITRF x axis: longitude 0 is local noon; 70 W is 12 - 70/15 h = 7.333 h.
  const double lat = 60.0 * M_PI / 180.0;
  const double lon = -70.0 * M_PI / 180.0;
  const double a = 6378.137, e2 = 6.69437999014e-3, h = 400.0;
  const double nrad = a / std::sqrt(1.0 - e2 * std::sin(lat) * std::sin(lat));
  const Vec3 r((nrad + h) * std::cos(lat) * std::cos(lon), (nrad + h) * std::cos(lat) * std::sin(lon),
               (nrad * (1.0 - e2) + h) * std::sin(lat));
  const dyn::AtmospherePoint p = dyn::atmosphere_point(3600.0, r, Vec3::UnitX());
  const dyn::Nrlmsise00Input in = model.input(p);
  EXPECT_EQ(in.day_of_year, 172);
  EXPECT_NEAR(in.ut_seconds, 32600.0, 1e-4);  // 29000 s + 3600 s; 1e-4 s: the Julian-date split rounding
  EXPECT_NEAR(in.altitude, 400.0, 1e-9);      // ERFA eraGc2gd inverse of the formula above
  EXPECT_NEAR(in.latitude, 60.0, 1e-9);
  EXPECT_NEAR(in.longitude, -70.0, 1e-9);
  EXPECT_NEAR(in.local_solar_time, 12.0 - 70.0 / 15.0, 1e-9);
  // density() is the model's mass density at those inputs (kg/m^3)
  const double direct = dyn::nrlmsise00(in, s.switches, false).mass_density;
  EXPECT_DOUBLE_EQ(model.density(p), direct);
  // Day of year rolls over at the end of the year: +200 days from day 172 of 2003 is day 7 of 2004.
  const dyn::Nrlmsise00Input later = model.input(dyn::atmosphere_point(200.0 * 86400.0, r, Vec3::UnitX()));
  EXPECT_EQ(later.day_of_year, 172 + 200 - 365);
  // Below 0 km the density of 0 km (the stated policy)
  const Vec3 deep = r * (6000.0 / r.norm());
  const dyn::AtmospherePoint pd = dyn::atmosphere_point(0.0, deep, Vec3::UnitX());
  EXPECT_LT(pd.height, 0.0);
  EXPECT_EQ(model.input(pd).altitude, 0.0);
}

TEST(Nrlmsise00, GradientAgainstFourthOrderDifferences) {
  dyn::Nrlmsise00Settings s;
  s.epoch_jd1 = 2460000.5;
  const dyn::Nrlmsise00 model(s);
  const Vec3 sun = Vec3(0.3, -0.9, 0.2).normalized();
  for (const Vec3& r : {Vec3(6778.0, 0.0, 0.0), Vec3(1200.0, 6500.0, 1800.0), Vec3(-3000.0, 2000.0, 6300.0),
                        Vec3(4000.0, -4000.0, -3500.0)}) {
    const dyn::AtmospherePoint p = dyn::atmosphere_point(1234.0, r, sun);
    Vec3 grad;
    const double rho = model.density_gradient(p, grad);
    EXPECT_DOUBLE_EQ(rho, model.density(p));
    Vec3 fd;
    const double h = 0.5;  // km: 4th-order truncation (h/H)^4/30 ~ 2e-10 for H = 50 km
    for (int i = 0; i < 3; ++i) {
      auto at = [&](double dx) {
        Vec3 q = r;
        q[i] += dx;
        return model.density(dyn::atmosphere_point(1234.0, q, sun));
      };
      fd[i] = (-at(2 * h) + 8 * at(h) - 8 * at(-h) + at(-2 * h)) / (12 * h);
    }
    // Central difference with 10 m inside the model: (h/H)^2/6 ~ 7e-9 relative; the 4th-order reference
    // is good to ~1e-9. 1e-6 of the gradient's norm covers both and the model's non-smooth joins.
    EXPECT_LE(satgnc::testing::rel_err(grad, fd), 1e-6) << grad.transpose() << "\n" << fd.transpose();
  }
}

TEST(Nrlmsise00, DragJacobianAgainstFourthOrderDifferences) {
  dyn::Nrlmsise00Settings s;
  s.epoch_jd1 = 2460000.5;
  dyn::AtmosphereDrag d;
  d.atmosphere = std::make_shared<dyn::Nrlmsise00>(s);
  d.sun = std::make_shared<dyn::FixedSun>(Vec3(1.0, 0.5, 0.2));
  d.cd = 2.2;
  d.area = 10.0;
  d.mass = 500.0;
  const Vec3 r(6778.0, 300.0, -200.0), v(0.1, 6.0, 4.5);
  Vec3 a;
  satgnc::Mat3 da_dr, da_dv;
  dyn::atmosphere_drag_jacobians(d, 100.0, r, v, a, da_dr, da_dv);
  satgnc::Mat3 fr, fv;
  const double hr = 0.5, hv = 1e-3;  // km, km/s
  for (int i = 0; i < 3; ++i) {
    auto ar = [&](double dx) {
      Vec3 q = r;
      q[i] += dx;
      return dyn::atmosphere_drag_acceleration(d, 100.0, q, v);
    };
    auto av = [&](double dx) {
      Vec3 q = v;
      q[i] += dx;
      return dyn::atmosphere_drag_acceleration(d, 100.0, r, q);
    };
    fr.col(i) = (-ar(2 * hr) + 8 * ar(hr) - 8 * ar(-hr) + ar(-2 * hr)) / (12 * hr);
    fv.col(i) = (-av(2 * hv) + 8 * av(hv) - 8 * av(-hv) + av(-2 * hv)) / (12 * hv);
  }
  EXPECT_LE(satgnc::testing::rel_err(da_dr, fr), 1e-6);  // as the density gradient above
  EXPECT_LE(satgnc::testing::rel_err(da_dv, fv), 1e-9);  // quadratic in v: 4th order is exact to rounding
  EXPECT_GT(a.norm(), 0.0);
}

TEST(Nrlmsise00, EvaluationIsAllocationFreeAndStateless) {
  dyn::Nrlmsise00Switches hist = dyn::nrlmsise00_default_switches();
  hist[9] = -1.0;
  dyn::Nrlmsise00Settings s;
  s.epoch_jd1 = 2460000.5;
  const dyn::Nrlmsise00 model(s);
  const dyn::AtmospherePoint p = dyn::atmosphere_point(10.0, Vec3(6500.0, 100.0, 50.0), Vec3::UnitY());
  Vec3 grad;
  double sink = 0.0;
  g_mallocs = 0;
  g_count = true;
  const auto first = dyn::nrlmsise00(test_case(15), hist, false);
  for (int i = 0; i < 17; ++i) sink += dyn::nrlmsise00(test_case(i), hist, true).mass_density;
  sink += model.density_gradient(p, grad);
  const auto again = dyn::nrlmsise00(test_case(15), hist, false);
  g_count = false;
  EXPECT_EQ(g_mallocs.load(), 0);  // no heap allocation in the evaluation or the gradient
  EXPECT_GT(sink, 0.0);
  EXPECT_EQ(first.mass_density, again.mass_density);  // no hidden state between calls
  EXPECT_EQ(first.temperature, again.temperature);
}

TEST(Nrlmsise00, BadInputNamesTheArgument) {
  auto message = [](auto f) { return satgnc::testing::message_of(f, "no throw"); };
  dyn::Nrlmsise00Input in;
  in.altitude = -1.0;
  EXPECT_NE(message([&] { in.validate(); }).find("nrlmsise00.altitude: must be in [0, 1000] km"),
            std::string::npos);
  in.altitude = 1500.0;
  EXPECT_NE(message([&] { in.validate(); }).find("nrlmsise00.altitude"), std::string::npos);
  in = {};
  in.f107 = 500.0;
  EXPECT_NE(message([&] { in.validate(); }).find("nrlmsise00.f107: must be in [0, 400] sfu, got 500"),
            std::string::npos);
  in = {};
  in.ap_history[3] = -2.0;
  EXPECT_NE(message([&] { in.validate(); }).find("nrlmsise00.ap_history[3]"), std::string::npos);
  dyn::Nrlmsise00Settings s;
  s.space_weather.ap = 401.0;
  EXPECT_NE(message([&] { dyn::Nrlmsise00 m(s); }).find("nrlmsise00.space_weather.ap"), std::string::npos);
  s = {};
  s.switches[4] = -1.0;
  EXPECT_NE(message([&] { dyn::Nrlmsise00 m(s); }).find("nrlmsise00.switches[4]: must be 0, 1 or 2"),
            std::string::npos);
  s = {};
  s.gradient_step = 0.0;
  EXPECT_NE(message([&] { dyn::Nrlmsise00 m(s); }).find("nrlmsise00.gradient_step"), std::string::npos);
  s = {};
  s.switches[9] = -1.0;
  EXPECT_EQ(message([&] { dyn::Nrlmsise00 m(s); }), "no throw");
}
