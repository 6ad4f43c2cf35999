// NRLMSISE-00 (Picone, Hedin, Drob, Aikin 2002): the horizontal/temporal expansion G(L), the
// thermosphere (species by species: diffusive profile, turbopause mixing, chemistry corrections), the
// lower atmosphere (temperature splines and the mixed profile below 72.5 km), and the AtmosphereModel.
// Coefficients: the generated include from cpp/data/nrlmsise00_coefficients.txt (public domain, NRL).
#include "satgnc/dynamics/nrlmsise00.hpp"

#include <erfa.h>

#include <cmath>
#include <sstream>
#include <string>

#include "detail/nrlmsise00_profiles.hpp"
#include "detail/nrlmsise00_reference.hpp"
#include "satgnc/core/validate.hpp"

namespace satgnc::dynamics {

namespace {
namespace tables {
#include "satgnc_generated/nrlmsise00_coefficients.inc"
}  // namespace tables

using detail::msis::Gravity;
using detail::msis::Layer;
using detail::msis::ThermoProfile;

// Rows of the two-index tables.
inline const double* PD(int species) { return tables::kPD + 150 * species; }
inline const double* PTL(int r) { return tables::kPTL + 100 * r; }
inline const double* PMA(int r) { return tables::kPMA + 100 * r; }
inline double PDM(int species, int k) { return tables::kPDM[10 * species + k]; }
inline double PDL(int r, int k) { return tables::kPDL[25 * r + k]; }
inline double PTM(int k) { return tables::kPTM[k]; }
inline double PAVGM(int k) { return tables::kPAVGM[k]; }

constexpr double kDegToRad = 1.74533e-2;  // the model's own constants (DGTR, DR, HR, SR)
constexpr double kDayToRad = 1.72142e-2;
constexpr double kHourToRad = 0.2618;
constexpr double kSecToRad = 7.2722e-5;

// Switch values as the model uses them: sw = mod(switch, 2), cross-term switch swc = |switch| in {1, 2}.
struct Switches {
  double sw[24];
  double swc[24];
};
Switches decode(const Nrlmsise00Switches& s) noexcept {
  Switches out{};
  for (int i = 0; i < 24; ++i) {
    out.sw[i] = std::fmod(s[i], 2.0);
    const double a = std::fabs(s[i]);
    out.swc[i] = (a == 1.0 || a == 2.0) ? 1.0 : 0.0;
  }
  return out;
}

// cos and sin of one phase angle.
struct Phase {
  double c = 1.0;
  double s = 0.0;
  bool wide = false;  // |angle| > 2 pi: evaluated directly (see cos_g)
};
Phase phase(double angle) noexcept { return {std::cos(angle), std::sin(angle), std::fabs(angle) > 6.3}; }

// The phase constants of one parameter row, as cos / sin pairs: every periodic term of G(L) is
// cos(w (x - p[k])) = cos(w x) cos(w p[k]) + sin(w x) sin(w p[k]), with cos / sin(w x) once per
// evaluation (Basis) and these once per process. Upper rows (150 numbers) use the d, h, g, s pairs;
// lower rows (100 numbers) the d pairs.
struct RowPhases {
  Phase d13, d17, d31, d38, d81, d84, d86, d88;  // day of year (d17, d38, d86, d88 at twice the rate)
  Phase h124, h131;                              // local solar time
  Phase g63, g97, g118, g136;                    // longitude
  Phase s58, s71, s75, s79;                      // universal time
};
RowPhases upper_row(const double* p) noexcept {
  RowPhases r = {};
  r.d13 = phase(kDayToRad * p[13]);
  r.d17 = phase(2.0 * kDayToRad * p[17]);
  r.d31 = phase(kDayToRad * p[31]);
  r.d38 = phase(2.0 * kDayToRad * p[38]);
  r.h124 = phase(kHourToRad * p[124]);
  r.h131 = phase(kHourToRad * p[131]);
  r.g63 = phase(kDegToRad * p[63]);
  r.g97 = phase(kDegToRad * p[97]);
  r.g118 = phase(kDegToRad * p[118]);
  r.g136 = phase(kDegToRad * p[136]);
  r.s58 = phase(kSecToRad * p[58]);
  r.s71 = phase(kSecToRad * p[71]);
  r.s75 = phase(kSecToRad * p[75]);
  r.s79 = phase(kSecToRad * p[79]);
  return r;
}
RowPhases lower_row(const double* p) noexcept {
  RowPhases r = {};
  r.d13 = phase(kDayToRad * p[13]);
  r.d17 = phase(2.0 * kDayToRad * p[17]);
  r.d31 = phase(kDayToRad * p[31]);
  r.d38 = phase(2.0 * kDayToRad * p[38]);
  r.d81 = phase(kDayToRad * p[81]);
  r.d84 = phase(kDayToRad * p[84]);
  r.d86 = phase(2.0 * kDayToRad * p[86]);
  r.d88 = phase(2.0 * kDayToRad * p[88]);
  return r;
}
struct PhaseTables {
  RowPhases pt, ps, pd[9], ptl[4], pma[10];
};
// Computed on first use and immutable afterwards (thread-safe initialization of a local static).
const PhaseTables& phase_tables() noexcept {
  static const PhaseTables t = [] {
    PhaseTables r;
    r.pt = upper_row(tables::kPT);
    r.ps = upper_row(tables::kPS);
    for (int k = 0; k < 9; ++k) r.pd[k] = upper_row(PD(k));
    for (int k = 0; k < 4; ++k) r.ptl[k] = lower_row(PTL(k));
    for (int k = 0; k < 10; ++k) r.pma[k] = lower_row(PMA(k));
    return r;
  }();
  return t;
}

// The basis of the expansion at one point and time, shared by every G(L) of one evaluation, and the
// magnetic-activity terms that G(L) leaves for the lower-atmosphere expansion (as in the Fortran, the
// Ap-history term is the one of the last expansion that had one). direct: every periodic term as
// cos(w (x - p[k])), the Fortran's form (the reference the phase-table form is tested against).
struct Basis {
  const Nrlmsise00Input* in;
  const Switches* s;
  const PhaseTables* ph;
  bool direct;
  double plg[4][9];
  double ctloc, stloc, c2tloc, s2tloc, c3tloc, s3tloc;
  Phase day, day2;  // w doy, 2 w doy
  Phase lon;        // longitude
  Phase ut;         // w ut
  Phase ut_lon;     // w ut + 2 longitude
  double dfa = 0.0;
  double apdf = 0.0;
  double apt = 0.0;

  // cos(w (x - p)) from the evaluation's (x) and the row's (p) phases, or directly.
  static double cos_diff(const Phase& x, const Phase& p) noexcept { return x.c * p.c + x.s * p.s; }
  double cos_day(const Phase& p, double pk) const noexcept {
    return direct ? std::cos(kDayToRad * (in->day_of_year - pk)) : cos_diff(day, p);
  }
  double cos_day2(const Phase& p, double pk) const noexcept {
    return direct ? std::cos(2.0 * kDayToRad * (in->day_of_year - pk)) : cos_diff(day2, p);
  }
};

void init_basis(Basis& b, const Nrlmsise00Input& in, const Switches& s, bool direct) noexcept {
  b.in = &in;
  b.s = &s;
  b.ph = &phase_tables();
  b.direct = direct;
  for (auto& row : b.plg)
    for (double& v : row) v = 0.0;
  const double c = std::sin(in.latitude * kDegToRad);
  const double sn = std::cos(in.latitude * kDegToRad);
  const double c2 = c * c;
  const double c4 = c2 * c2;
  const double s2 = sn * sn;
  double (&P)[4][9] = b.plg;
  P[0][1] = c;
  P[0][2] = 0.5 * (3.0 * c2 - 1.0);
  P[0][3] = 0.5 * (5.0 * c * c2 - 3.0 * c);
  P[0][4] = (35.0 * c4 - 30.0 * c2 + 3.0) / 8.0;
  P[0][5] = (63.0 * c2 * c2 * c - 70.0 * c2 * c + 15.0 * c) / 8.0;
  P[0][6] = (11.0 * c * P[0][5] - 5.0 * P[0][4]) / 6.0;
  P[1][1] = sn;
  P[1][2] = 3.0 * c * sn;
  P[1][3] = 1.5 * (5.0 * c2 - 1.0) * sn;
  P[1][4] = 2.5 * (7.0 * c2 * c - 3.0 * c) * sn;
  P[1][5] = 1.875 * (21.0 * c4 - 14.0 * c2 + 1.0) * sn;
  P[1][6] = (11.0 * c * P[1][5] - 6.0 * P[1][4]) / 5.0;
  P[2][2] = 3.0 * s2;
  P[2][3] = 15.0 * s2 * c;
  P[2][4] = 7.5 * (7.0 * c2 - 1.0) * s2;
  P[2][5] = 3.0 * c * P[2][4] - 2.0 * P[2][3];
  P[2][6] = (11.0 * c * P[2][5] - 7.0 * P[2][4]) / 4.0;
  P[2][7] = (13.0 * c * P[2][6] - 8.0 * P[2][5]) / 5.0;
  P[3][3] = 15.0 * s2 * sn;
  P[3][4] = 105.0 * s2 * sn * c;
  P[3][5] = (9.0 * c * P[3][4] - 7.0 * P[3][3]) / 2.0;
  P[3][6] = (11.0 * c * P[3][5] - 8.0 * P[3][4]) / 3.0;
  const double tl = in.local_solar_time * kHourToRad;
  b.stloc = std::sin(tl);
  b.ctloc = std::cos(tl);
  if (direct) {
    b.s2tloc = std::sin(2.0 * tl);
    b.c2tloc = std::cos(2.0 * tl);
    b.s3tloc = std::sin(3.0 * tl);
    b.c3tloc = std::cos(3.0 * tl);
    return;
  }
  // double- and triple-angle formulas (the harmonics from one sin / cos pair)
  b.s2tloc = 2.0 * b.stloc * b.ctloc;
  b.c2tloc = (b.ctloc - b.stloc) * (b.ctloc + b.stloc);
  b.s3tloc = b.s2tloc * b.ctloc + b.c2tloc * b.stloc;
  b.c3tloc = b.c2tloc * b.ctloc - b.s2tloc * b.stloc;
  b.day = phase(kDayToRad * in.day_of_year);
  b.day2 = phase(2.0 * kDayToRad * in.day_of_year);
  if (in.longitude > -1000.0) {  // -1000 or below: the model's "no longitude" (its terms are off)
    const double lon = kDegToRad * in.longitude;
    b.lon = phase(lon);
    b.ut = phase(kSecToRad * in.ut_seconds);
    b.ut_lon = phase(kSecToRad * in.ut_seconds + 2.0 * lon);
  }
}

// Geomagnetic activity function of one 3-h ap value (Picone 2002, eq. A24d).
double ap_function(double a, const double* p) noexcept {
  const double k = std::fabs(p[24]);
  return a - 4.0 + (p[25] - 1.0) * (a - 4.0 + (std::exp(-k * (a - 4.0)) - 1.0) / k);
}

// Exponentially weighted history of the 3-h ap (eqs. A24a-c).
double ap_history_term(double ex, const double* p, const std::array<double, 7>& ap) noexcept {
  const double norm = 1.0 + (1.0 - std::pow(ex, 19.0)) / (1.0 - ex) * std::sqrt(ex);
  const double recent =
      ap_function(ap[2], p) * ex + ap_function(ap[3], p) * ex * ex + ap_function(ap[4], p) * ex * ex * ex;
  const double older =
      (ap_function(ap[5], p) * std::pow(ex, 4.0) + ap_function(ap[6], p) * std::pow(ex, 12.0)) *
      (1.0 - std::pow(ex, 8.0)) / (1.0 - ex);
  return (ap_function(ap[1], p) + recent + older) / norm;
}

// G(L) for the upper atmosphere (GLOBE7): the relative variation of a parameter set p (150 numbers).
double expansion(const double* p, const RowPhases& ph, Basis& b) noexcept {
  const Nrlmsise00Input& in = *b.in;
  const double* sw = b.s->sw;
  const double* swc = b.s->swc;
  const double (&P)[4][9] = b.plg;
  double t[14] = {};
  const double cd32 = b.cos_day(ph.d31, p[31]);
  const double cd18 = b.cos_day2(ph.d17, p[17]);
  const double cd14 = b.cos_day(ph.d13, p[13]);
  const double cd39 = b.cos_day2(ph.d38, p[38]);
  const double tloc = in.local_solar_time;
  const Phase tl{b.ctloc, b.stloc};
  // cos(w (x - p[k])) for local time, longitude and UT, directly or from the phases
  auto cos_h = [&](int k, const Phase& q) {
    return b.direct ? std::cos(kHourToRad * (tloc - p[k])) : Basis::cos_diff(tl, q);
  };
  // A phase far outside a turn (kPT[136] = -92535 deg, 1615 rad) stays direct: either form carries
  // ~2e-13 rad of argument rounding there, so the phase-table cosine would differ from the Fortran's
  // by that much (measured: 2.7e-15 relative in Tinf, 7e-14 in Ar with it tabled).
  auto cos_g = [&](int k, const Phase& q) {
    return b.direct || q.wide ? std::cos(kDegToRad * (in.longitude - p[k])) : Basis::cos_diff(b.lon, q);
  };
  auto cos_s = [&](int k, const Phase& q) {
    return b.direct ? std::cos(kSecToRad * (in.ut_seconds - p[k])) : Basis::cos_diff(b.ut, q);
  };

  // solar activity
  const double df = in.f107 - in.f107a;
  b.dfa = in.f107a - 150.0;
  const double dfa = b.dfa;
  t[0] = p[19] * df * (1.0 + p[59] * dfa) + p[20] * df * df + p[21] * dfa + p[29] * dfa * dfa;
  const double f1 = 1.0 + (p[47] * dfa + p[19] * df + p[20] * df * df) * swc[1];
  const double f2 = 1.0 + (p[49] * dfa + p[19] * df + p[20] * df * df) * swc[1];
  // time independent, annual and semiannual (symmetric and asymmetric)
  t[1] = p[1] * P[0][2] + p[2] * P[0][4] + p[22] * P[0][6] + p[14] * P[0][2] * dfa * swc[1] + p[26] * P[0][1];
  t[2] = p[18] * cd32;
  t[3] = (p[15] + p[16] * P[0][2]) * cd18;
  t[4] = f1 * (p[9] * P[0][1] + p[10] * P[0][3]) * cd14;
  t[5] = p[37] * P[0][1] * cd39;
  // diurnal, semidiurnal, terdiurnal tides
  if (sw[7] != 0.0) {
    const double a71 = p[11] * P[1][2] * cd14 * swc[5];
    const double a72 = p[12] * P[1][2] * cd14 * swc[5];
    t[6] = f2 * ((p[3] * P[1][1] + p[4] * P[1][3] + p[27] * P[1][5] + a71) * b.ctloc +
                 (p[6] * P[1][1] + p[7] * P[1][3] + p[28] * P[1][5] + a72) * b.stloc);
  }
  if (sw[8] != 0.0) {
    const double a81 = (p[23] * P[2][3] + p[35] * P[2][5]) * cd14 * swc[5];
    const double a82 = (p[33] * P[2][3] + p[36] * P[2][5]) * cd14 * swc[5];
    t[7] = f2 * ((p[5] * P[2][2] + p[41] * P[2][4] + a81) * b.c2tloc +
                 (p[8] * P[2][2] + p[42] * P[2][4] + a82) * b.s2tloc);
  }
  if (sw[14] != 0.0) {
    t[13] = f2 * ((p[39] * P[3][3] + (p[93] * P[3][4] + p[46] * P[3][6]) * cd14 * swc[5]) * b.s3tloc +
                  (p[40] * P[3][3] + (p[94] * P[3][4] + p[48] * P[3][6]) * cd14 * swc[5]) * b.c3tloc);
  }
  // magnetic activity
  const bool history = sw[9] == -1.0;
  if (history) {
    if (p[51] != 0.0) {
      double ex = std::exp(-10800.0 * std::fabs(p[51]) / (1.0 + p[138] * (45.0 - std::fabs(in.latitude))));
      if (ex > 0.99999) ex = 0.99999;
      double q[150];
      for (int i = 0; i < 150; ++i) q[i] = p[i];
      if (q[24] < 1.0e-4) q[24] = 1.0e-4;
      b.apt = ap_history_term(ex, q, in.ap_history);
      t[8] =
          b.apt * (p[50] + p[96] * P[0][2] + p[54] * P[0][4] +
                   (p[125] * P[0][1] + p[126] * P[0][3] + p[127] * P[0][5]) * cd14 * swc[5] +
                   (p[128] * P[1][1] + p[129] * P[1][3] + p[130] * P[1][5]) * swc[7] * cos_h(131, ph.h131));
    }
  } else {
    const double apd = in.ap - 4.0;
    const double p44 = p[43] < 0.0 ? 1.0e-5 : p[43];
    b.apdf = apd + (p[44] - 1.0) * (apd + (std::exp(-p44 * apd) - 1.0) / p44);
    if (sw[9] != 0.0) {
      t[8] =
          b.apdf * (p[32] + p[45] * P[0][2] + p[34] * P[0][4] +
                    (p[100] * P[0][1] + p[101] * P[0][3] + p[102] * P[0][5]) * cd14 * swc[5] +
                    (p[121] * P[1][1] + p[122] * P[1][3] + p[123] * P[1][5]) * swc[7] * cos_h(124, ph.h124));
    }
  }
  if (sw[10] != 0.0 && in.longitude > -1000.0) {
    const double lon = kDegToRad * in.longitude;
    const double clon = b.direct ? std::cos(lon) : b.lon.c;
    const double slon = b.direct ? std::sin(lon) : b.lon.s;
    if (sw[11] != 0.0) {  // longitudinal
      t[10] = (1.0 + p[80] * dfa * swc[1]) *
              ((p[64] * P[1][2] + p[65] * P[1][4] + p[66] * P[1][6] + p[103] * P[1][1] + p[104] * P[1][3] +
                p[105] * P[1][5] + swc[5] * (p[109] * P[1][1] + p[110] * P[1][3] + p[111] * P[1][5]) * cd14) *
                   clon +
               (p[90] * P[1][2] + p[91] * P[1][4] + p[92] * P[1][6] + p[106] * P[1][1] + p[107] * P[1][3] +
                p[108] * P[1][5] + swc[5] * (p[112] * P[1][1] + p[113] * P[1][3] + p[114] * P[1][5]) * cd14) *
                   slon);
    }
    if (sw[12] != 0.0) {  // universal time, and UT x longitude
      t[11] = (1.0 + p[95] * P[0][1]) * (1.0 + p[81] * dfa * swc[1]) *
              (1.0 + p[119] * P[0][1] * swc[5] * cd14) *
              ((p[68] * P[0][1] + p[69] * P[0][3] + p[70] * P[0][5]) * cos_s(71, ph.s71));
      t[11] += swc[11] * (p[76] * P[2][3] + p[77] * P[2][5] + p[78] * P[2][7]) *
               (b.direct ? std::cos(kSecToRad * (in.ut_seconds - p[79]) + 2.0 * lon)
                         : Basis::cos_diff(b.ut_lon, ph.s79)) *
               (1.0 + p[137] * dfa * swc[1]);
    }
    if (sw[13] != 0.0) {  // UT / longitude x magnetic activity
      if (history) {
        if (p[51] != 0.0) {
          t[12] = b.apt * swc[11] * (1.0 + p[132] * P[0][1]) *
                      ((p[52] * P[1][2] + p[98] * P[1][4] + p[67] * P[1][6]) * cos_g(97, ph.g97)) +
                  b.apt * swc[11] * swc[5] * (p[133] * P[1][1] + p[134] * P[1][3] + p[135] * P[1][5]) * cd14 *
                      cos_g(136, ph.g136) +
                  b.apt * swc[12] * (p[55] * P[0][1] + p[56] * P[0][3] + p[57] * P[0][5]) * cos_s(58, ph.s58);
        }
      } else {
        t[12] = b.apdf * swc[11] * (1.0 + p[120] * P[0][1]) *
                    ((p[60] * P[1][2] + p[61] * P[1][4] + p[62] * P[1][6]) * cos_g(63, ph.g63)) +
                b.apdf * swc[11] * swc[5] * (p[115] * P[1][1] + p[116] * P[1][3] + p[117] * P[1][5]) * cd14 *
                    cos_g(118, ph.g118) +
                b.apdf * swc[12] * (p[83] * P[0][1] + p[84] * P[0][3] + p[85] * P[0][5]) * cos_s(75, ph.s75);
      }
    }
  }
  double g = p[30];
  for (int i = 0; i < 14; ++i) g += std::fabs(sw[i + 1]) * t[i];
  return g;
}

// G(L) for the lower atmosphere (GLOB7S): parameter sets of 100 numbers (PTL, PMA rows).
double expansion_lower(const double* p, const RowPhases& ph, const Basis& b) noexcept {
  const Nrlmsise00Input& in = *b.in;
  const double* sw = b.s->sw;
  const double* swc = b.s->swc;
  const double (&P)[4][9] = b.plg;
  double t[14] = {};
  const double cd32 = b.cos_day(ph.d31, p[31]);
  const double cd18 = b.cos_day2(ph.d17, p[17]);
  const double cd14 = b.cos_day(ph.d13, p[13]);
  const double cd39 = b.cos_day2(ph.d38, p[38]);
  t[0] = p[21] * b.dfa;
  t[1] =
      p[1] * P[0][2] + p[2] * P[0][4] + p[22] * P[0][6] + p[26] * P[0][1] + p[14] * P[0][3] + p[59] * P[0][5];
  t[2] = (p[18] + p[47] * P[0][2] + p[29] * P[0][4]) * cd32;
  t[3] = (p[15] + p[16] * P[0][2] + p[30] * P[0][4]) * cd18;
  t[4] = (p[9] * P[0][1] + p[10] * P[0][3] + p[20] * P[0][5]) * cd14;
  t[5] = p[37] * P[0][1] * cd39;
  if (sw[7] != 0.0) {
    const double a71 = p[11] * P[1][2] * cd14 * swc[5];
    const double a72 = p[12] * P[1][2] * cd14 * swc[5];
    t[6] =
        (p[3] * P[1][1] + p[4] * P[1][3] + a71) * b.ctloc + (p[6] * P[1][1] + p[7] * P[1][3] + a72) * b.stloc;
  }
  if (sw[8] != 0.0) {
    const double a81 = (p[23] * P[2][3] + p[35] * P[2][5]) * cd14 * swc[5];
    const double a82 = (p[33] * P[2][3] + p[36] * P[2][5]) * cd14 * swc[5];
    t[7] = (p[5] * P[2][2] + p[41] * P[2][4] + a81) * b.c2tloc +
           (p[8] * P[2][2] + p[42] * P[2][4] + a82) * b.s2tloc;
  }
  if (sw[14] != 0.0) t[13] = p[39] * P[3][3] * b.s3tloc + p[40] * P[3][3] * b.c3tloc;
  if (sw[9] == 1.0) t[8] = b.apdf * (p[32] + p[45] * P[0][2] * swc[2]);
  if (sw[9] == -1.0) t[8] = p[50] * b.apt + p[96] * P[0][2] * b.apt * swc[2];
  if (!(sw[10] == 0.0 || sw[11] == 0.0 || in.longitude <= -1000.0)) {
    const double lon = kDegToRad * in.longitude;
    const double clon = b.direct ? std::cos(lon) : b.lon.c;
    const double slon = b.direct ? std::sin(lon) : b.lon.s;
    t[10] =
        (1.0 +
         P[0][1] * (p[80] * swc[5] * b.cos_day(ph.d81, p[81]) + p[85] * swc[6] * b.cos_day2(ph.d86, p[86])) +
         p[83] * swc[3] * b.cos_day(ph.d84, p[84]) + p[87] * swc[4] * b.cos_day2(ph.d88, p[88])) *
        ((p[64] * P[1][2] + p[65] * P[1][4] + p[66] * P[1][6] + p[74] * P[1][1] + p[75] * P[1][3] +
          p[76] * P[1][5]) *
             clon +
         (p[90] * P[1][2] + p[91] * P[1][4] + p[92] * P[1][6] + p[77] * P[1][1] + p[78] * P[1][3] +
          p[79] * P[1][5]) *
             slon);
  }
  double g = 0.0;
  for (int i = 0; i < 14; ++i) g += std::fabs(sw[i + 1]) * t[i];
  return g;
}

// Heights of the nodes (km).
constexpr double kZn2[4] = {72.5, 55.0, 45.0, 32.5};
constexpr double kZn3[5] = {32.5, 20.0, 15.0, 10.0, 0.0};
constexpr double kZmix = 62.5;

// Result of the thermospheric part (GTS7) in the model's cgs units.
struct Thermo {
  double d[9];  // He, O, N2, O2, Ar, mass (g/cm^3), H, N, anomalous O (cm^-3)
  double tinf;
  double tz;
  double dm28;  // fully mixed N2 at the altitude (for the lower atmosphere)
  ThermoProfile prof;
};

// Diffusive density of a species at z and, below its mixing limit, its blend with the mixed profile.
struct SpeciesDensity {
  double d;
  double base;  // mixed density at the turbopause-height reference (for the ground mixing ratio)
  bool mixed;
};

Thermo thermosphere(double z, Basis& b) noexcept {
  const Nrlmsise00Input& in = *b.in;
  const double* sw = b.s->sw;
  Thermo th{};
  const double za = PDL(1, 15);
  ThermoProfile& P = th.prof;
  P.g = detail::msis::gravity_at(b.s->sw[2] == 0.0 ? 45.0 : in.latitude);
  const double tinf0 = PTM(0) * tables::kPT[0];
  th.tinf = z > za ? tinf0 * (1.0 + sw[16] * expansion(tables::kPT, b.ph->pt, b)) : tinf0;
  const double g0 = z > 72.5 ? PTM(3) * tables::kPS[0] * (1.0 + sw[19] * expansion(tables::kPS, b.ph->ps, b))
                             : PTM(3) * tables::kPS[0];
  const double tlb = PTM(1) * (1.0 + sw[17] * expansion(PD(3), b.ph->pd[3], b)) * PD(3)[0];
  P.tinf = th.tinf;
  P.tlb = tlb;
  P.s = g0 / (th.tinf - tlb);
  P.zlb = PTM(5);
  P.lower.z[0] = za;
  P.lower.z[1] = 110.0;
  P.lower.z[2] = 100.0;
  P.lower.z[3] = 90.0;
  P.lower.z[4] = 72.5;
  const double ptl_base[4] = {PTM(6) * PTL(0)[0], PTM(2) * PTL(1)[0], PTM(7) * PTL(2)[0], PTM(4) * PTL(3)[0]};
  const double grad_base = PTM(8) * PMA(8)[0];
  if (z < 300.0) {
    P.lower.t[1] = ptl_base[0] / (1.0 - sw[18] * expansion_lower(PTL(0), b.ph->ptl[0], b));
    P.lower.t[2] = ptl_base[1] / (1.0 - sw[18] * expansion_lower(PTL(1), b.ph->ptl[1], b));
    P.lower.t[3] = ptl_base[2] / (1.0 - sw[18] * expansion_lower(PTL(2), b.ph->ptl[2], b));
    P.lower.t[4] = ptl_base[3] / (1.0 - sw[18] * sw[20] * expansion_lower(PTL(3), b.ph->ptl[3], b));
    P.lower.grad_last = grad_base * (1.0 + sw[18] * sw[20] * expansion_lower(PMA(8), b.ph->pma[8], b)) *
                        P.lower.t[4] * P.lower.t[4] / (ptl_base[3] * ptl_base[3]);
  } else {
    for (int k = 0; k < 4; ++k) P.lower.t[k + 1] = ptl_base[k];
    P.lower.grad_last = grad_base * P.lower.t[4] * P.lower.t[4] / (ptl_base[3] * ptl_base[3]);
  }
  const double xmm = PDM(2, 4);
  const bool mixing = sw[15] != 0.0;
  double tz = 0.0;

  // N2: diffusive density; mixed below 160 km (the mixed N2 also feeds the lower atmosphere)
  const double g28 = sw[21] * expansion(PD(2), b.ph->pd[2], b);
  // plg[0][1] = sin(latitude), the same product as the Fortran's sin(DGTR * lat)
  const double zhf =
      PDL(1, 24) * (1.0 + sw[5] * PDL(0, 24) * b.plg[0][1] * b.cos_day(b.ph->pt.d13, tables::kPT[13]));
  const double db28 = PDM(2, 0) * std::exp(g28) * PD(2)[0];
  th.d[2] = thermo_density(P, z, db28, 28.0, 0.0, tz);
  const double zh28 = PDM(2, 2) * zhf;
  const double zhm = PDM(2, 3) * PDL(1, 5);
  const double b28 = thermo_density(P, zh28, db28, 28.0 - xmm, -1.0, tz);
  if (z <= 160.0) {
    th.dm28 = thermo_density(P, z, b28, xmm, 0.0, tz);
    if (mixing) th.d[2] = detail::msis::blend_mixed(th.d[2], th.dm28, zhm, xmm, 28.0);
  }

  // One species: diffusive at z, and below its limit blended with the fully mixed profile.
  auto species = [&](int pd_row, int pdm_row, double mass, double alpha, bool below) -> SpeciesDensity {
    const double gl = sw[21] * expansion(PD(pd_row), b.ph->pd[pd_row], b);
    const double db = PDM(pdm_row, 0) * std::exp(gl) * PD(pd_row)[0];
    SpeciesDensity r{thermo_density(P, z, db, mass, alpha, tz), 0.0, false};
    if (mixing && below) {
      r.base = thermo_density(P, PDM(pdm_row, 2), db, mass - xmm, alpha - 1.0, tz);
      const double dm = thermo_density(P, z, r.base, xmm, 0.0, tz);
      r.d = detail::msis::blend_mixed(r.d, dm, zhm, xmm, mass);
      r.mixed = true;
    }
    return r;
  };
  using detail::msis::chem_factor;
  using detail::msis::chem_factor2;
  const double solar = 1.0 + sw[1] * PDL(0, 23) * (in.f107a - 150.0);

  // He (ground mixing ratio)
  SpeciesDensity he = species(0, 0, 4.0, -0.38, z < 200.0);
  if (he.mixed)
    he.d *= chem_factor(z, std::log(b28 * PDM(0, 1) / he.base), PDM(0, 5) * PDL(1, 1), PDM(0, 4) * PDL(1, 0));
  th.d[0] = he.d;
  // O (departure from diffusive equilibrium near 150 km with F10.7, then chemistry)
  SpeciesDensity o = species(1, 1, 16.0, 0.0, z <= 300.0);
  if (o.mixed) {
    o.d *= chem_factor2(z, PDM(1, 1) * PDL(1, 16) * solar, PDM(1, 5) * PDL(1, 3), PDM(1, 4) * PDL(1, 2),
                        PDM(1, 5) * PDL(1, 4));
    o.d *= chem_factor(z, PDM(1, 3) * PDL(1, 14), PDM(1, 7) * PDL(1, 13), PDM(1, 6) * PDL(1, 12));
  }
  th.d[1] = o.d;
  // O2 (ground mixing ratio below 250 km; departure from diffusive equilibrium at all heights)
  SpeciesDensity o2 = species(4, 3, 32.0, 0.0, z <= 250.0);
  if (o2.mixed)
    o2.d *= chem_factor(z, std::log(b28 * PDM(3, 1) / o2.base), PDM(3, 5) * PDL(1, 7), PDM(3, 4) * PDL(1, 6));
  if (mixing)
    o2.d *= chem_factor2(z, PDM(3, 3) * PDL(1, 23) * solar, PDM(3, 7) * PDL(1, 22), PDM(3, 6) * PDL(1, 21),
                         PDM(3, 7) * PDL(0, 22));
  th.d[3] = o2.d;
  // Ar
  SpeciesDensity ar = species(5, 4, 40.0, 0.17, z <= 240.0);
  if (ar.mixed)
    ar.d *= chem_factor(z, std::log(b28 * PDM(4, 1) / ar.base), PDM(4, 5) * PDL(1, 9), PDM(4, 4) * PDL(1, 8));
  th.d[4] = ar.d;
  // H (ground mixing ratio, chemistry)
  SpeciesDensity h = species(6, 5, 1.0, -0.38, z <= 320.0);
  if (h.mixed) {
    h.d *= chem_factor(z, std::log(b28 * PDM(5, 1) * std::fabs(PDL(1, 17)) / h.base), PDM(5, 5) * PDL(1, 11),
                       PDM(5, 4) * PDL(1, 10));
    h.d *= chem_factor(z, PDM(5, 3) * PDL(1, 20), PDM(5, 7) * PDL(1, 19), PDM(5, 6) * PDL(1, 18));
  }
  th.d[6] = h.d;
  // N (ground mixing ratio, chemistry)
  SpeciesDensity n = species(7, 6, 14.0, 0.0, z <= 450.0);
  if (n.mixed) {
    n.d *= chem_factor(z, std::log(b28 * PDM(6, 1) * std::fabs(PDL(0, 2)) / n.base), PDM(6, 5) * PDL(0, 1),
                       PDM(6, 4) * PDL(0, 0));
    n.d *= chem_factor(z, PDM(6, 3) * PDL(0, 5), PDM(6, 7) * PDL(0, 4), PDM(6, 6) * PDL(0, 3));
  }
  th.d[7] = n.d;
  // anomalous (hot) oxygen: isothermal at tho with a Chapman-like lower cut-off
  {
    const double gl = sw[21] * expansion(PD(8), b.ph->pd[8], b);
    const double db = PDM(7, 0) * std::exp(gl) * PD(8)[0];
    const double tho = PDM(7, 9) * PDL(0, 6);
    ThermoProfile hot = P;
    hot.tinf = tho;
    hot.tlb = tho;
    const double dd = thermo_density(hot, z, db, 16.0, 0.0, tz);
    const double zsht = PDM(7, 5);
    const double zmho = PDM(7, 4);
    const double zsho = detail::msis::scale_height(zmho, 16.0, tho, P.g);
    th.d[8] = dd * std::exp(-zsht / zsho * (std::exp(-(z - zmho) / zsht) - 1.0));
  }
  th.d[5] = 1.66e-24 * (4.0 * th.d[0] + 16.0 * th.d[1] + 28.0 * th.d[2] + 32.0 * th.d[3] + 40.0 * th.d[4] +
                        th.d[6] + 14.0 * th.d[7]);
  thermo_density(P, std::fabs(z), 1.0, 0.0, 0.0, th.tz);
  return th;
}

}  // namespace

Nrlmsise00Switches nrlmsise00_default_switches() noexcept {
  Nrlmsise00Switches s{};
  for (double& v : s) v = 1.0;
  return s;
}

namespace {
Nrlmsise00Output evaluate_model(const Nrlmsise00Input& in, const Nrlmsise00Switches& switches,
                                bool anomalous_oxygen, bool direct) noexcept {
  const Switches s = decode(switches);
  Basis b{};
  init_basis(b, in, s, direct);
  const double alt = in.altitude;
  const Thermo th = thermosphere(alt > kZn2[0] ? alt : kZn2[0], b);
  double d[9];
  for (int i = 0; i < 9; ++i) d[i] = th.d[i];
  double tz = th.tz;
  if (alt < kZn2[0]) {
    // Lower mesosphere / upper stratosphere and below: splines of 1/T through nodes whose temperatures
    // are expansions (PMA rows) about the averages PAVGM; densities mixed, with the thermospheric
    // species ratios faded in linearly from 62.5 to 72.5 km.
    const double* sw = s.sw;
    const Gravity g = th.prof.g;
    Layer<4> meso{};
    for (int k = 0; k < 4; ++k) meso.z[k] = kZn2[k];
    meso.grad_first = th.prof.lower.grad_last;
    meso.t[0] = th.prof.lower.t[4];
    meso.t[1] = PMA(0)[0] * PAVGM(0) / (1.0 - sw[20] * expansion_lower(PMA(0), b.ph->pma[0], b));
    meso.t[2] = PMA(1)[0] * PAVGM(1) / (1.0 - sw[20] * expansion_lower(PMA(1), b.ph->pma[1], b));
    meso.t[3] = PMA(2)[0] * PAVGM(2) / (1.0 - sw[20] * sw[22] * expansion_lower(PMA(2), b.ph->pma[2], b));
    const double b3 = PMA(2)[0] * PAVGM(2);
    meso.grad_last = PAVGM(8) * PMA(9)[0] *
                     (1.0 + sw[20] * sw[22] * expansion_lower(PMA(9), b.ph->pma[9], b)) * meso.t[3] *
                     meso.t[3] / (b3 * b3);
    Layer<5> strat{};
    for (int k = 0; k < 5; ++k) strat.z[k] = kZn3[k];
    strat.t[0] = meso.t[3];
    strat.grad_first = meso.grad_last;
    if (alt <= kZn3[0]) {
      for (int k = 1; k <= 4; ++k)
        strat.t[k] =
            PMA(k + 2)[0] * PAVGM(k + 2) / (1.0 - sw[22] * expansion_lower(PMA(k + 2), b.ph->pma[k + 2], b));
      const double b6 = PMA(6)[0] * PAVGM(6);
      strat.grad_last = PMA(7)[0] * PAVGM(7) * (1.0 + sw[22] * expansion_lower(PMA(7), b.ph->pma[7], b)) *
                        strat.t[4] * strat.t[4] / (b6 * b6);
    }
    const double xmm = PDM(2, 4);
    // Mixed profile: down through the mesospheric layer, then the stratospheric one.
    auto mixed = [&](double d0, double xm, double& t_out) {
      const double zm = alt > kZn2[3] ? alt : kZn2[3];
      double dd = detail::msis::layer_density<4>(meso, zm, d0, xm, g, t_out);
      if (alt > kZn3[0]) return dd;
      return detail::msis::layer_density<5>(strat, alt, dd, xm, g, t_out);
    };
    const double dmc = alt > kZmix ? 1.0 - (kZn2[0] - alt) / (kZn2[0] - kZmix) : 0.0;
    const double dz28 = th.d[2];
    double dmr = th.d[2] / th.dm28 - 1.0;
    d[2] = mixed(th.dm28, xmm, tz) * (1.0 + dmr * dmc);
    dmr = th.d[0] / (dz28 * PDM(0, 1)) - 1.0;
    d[0] = d[2] * PDM(0, 1) * (1.0 + dmr * dmc);
    d[1] = 0.0;
    d[8] = 0.0;
    dmr = th.d[3] / (dz28 * PDM(3, 1)) - 1.0;
    d[3] = d[2] * PDM(3, 1) * (1.0 + dmr * dmc);
    dmr = th.d[4] / (dz28 * PDM(4, 1)) - 1.0;
    d[4] = d[2] * PDM(4, 1) * (1.0 + dmr * dmc);
    d[6] = 0.0;
    d[7] = 0.0;
    d[5] = 1.66e-24 * (4.0 * d[0] + 28.0 * d[2] + 32.0 * d[3] + 40.0 * d[4]);
    mixed(1.0, 0.0, tz);
  }
  Nrlmsise00Output out;
  constexpr double per_cm3 = 1.0e6;  // cm^-3 -> m^-3
  out.he = d[0] * per_cm3;
  out.o = d[1] * per_cm3;
  out.n2 = d[2] * per_cm3;
  out.o2 = d[3] * per_cm3;
  out.ar = d[4] * per_cm3;
  out.h = d[6] * per_cm3;
  out.n = d[7] * per_cm3;
  out.anomalous_o = d[8] * per_cm3;
  double mass = d[5];
  if (anomalous_oxygen) mass += 1.66e-24 * 16.0 * d[8];
  out.mass_density = mass * 1.0e3;  // g/cm^3 -> kg/m^3
  out.exospheric_temperature = th.tinf;
  out.temperature = tz;
  return out;
}
}  // namespace

Nrlmsise00Output nrlmsise00(const Nrlmsise00Input& in, const Nrlmsise00Switches& switches,
                            bool anomalous_oxygen) noexcept {
  return evaluate_model(in, switches, anomalous_oxygen, false);
}

namespace detail::msis {
Nrlmsise00Output nrlmsise00_direct(const Nrlmsise00Input& in, const Nrlmsise00Switches& switches,
                                   bool anomalous_oxygen) noexcept {
  return evaluate_model(in, switches, anomalous_oxygen, true);
}
}  // namespace detail::msis

namespace {
void require_in(double v, double lo, double hi, const std::string& name, const char* unit) {
  if (std::isfinite(v) && v >= lo && v <= hi) return;
  std::ostringstream rule;
  rule << "must be in [" << lo << ", " << hi << "]" << unit << ", got " << v;
  core::require(false, name, rule.str());
}
}  // namespace

void Nrlmsise00Input::validate(const char* prefix) const {
  const std::string p = std::string(prefix) + ".";
  if (day_of_year < 1 || day_of_year > 366)
    core::require(false, p + "day_of_year", "must be in [1, 366], got " + std::to_string(day_of_year));
  require_in(ut_seconds, 0.0, 86400.0, p + "ut_seconds", " s");
  require_in(altitude, 0.0, 1000.0, p + "altitude", " km");
  require_in(latitude, -90.0, 90.0, p + "latitude", " deg");
  require_in(longitude, -360.0, 360.0, p + "longitude", " deg");
  require_in(local_solar_time, 0.0, 24.0, p + "local_solar_time", " h");
  require_in(f107a, 0.0, SpaceWeather::max_f107, p + "f107a", " sfu");
  require_in(f107, 0.0, SpaceWeather::max_f107, p + "f107", " sfu");
  require_in(ap, 0.0, SpaceWeather::max_ap, p + "ap", "");
  for (int i = 0; i < 7; ++i)
    require_in(ap_history[i], 0.0, SpaceWeather::max_ap, p + "ap_history[" + std::to_string(i) + "]", "");
}

void nrlmsise00_validate_switches(const Nrlmsise00Switches& switches, const char* name) {
  for (int i = 1; i < 24; ++i) {
    const double v = switches[i];
    const bool ok = v == 0.0 || v == 1.0 || v == 2.0 || (i == 9 && v == -1.0);
    if (!ok) {
      std::ostringstream rule;
      rule << "must be 0, 1 or 2" << (i == 9 ? " (or -1 for the Ap history)" : "") << ", got " << v;
      core::require(false, std::string(name) + "[" + std::to_string(i) + "]", rule.str());
    }
  }
}

void Nrlmsise00Settings::validate(const char* prefix) const {
  const std::string p = std::string(prefix) + ".";
  core::require(std::isfinite(epoch_jd1) && std::isfinite(epoch_jd2), p + "epoch_jd1", "must be finite");
  space_weather.validate((p + "space_weather").c_str());
  for (int i = 0; i < 7; ++i)
    require_in(ap_history[i], 0.0, SpaceWeather::max_ap, p + "ap_history[" + std::to_string(i) + "]", "");
  nrlmsise00_validate_switches(switches, (p + "switches").c_str());
  if (!(std::isfinite(gradient_step) && gradient_step > 0.0 && gradient_step <= 1.0)) {
    std::ostringstream rule;
    rule << "must be in (0, 1] km, got " << gradient_step;
    core::require(false, p + "gradient_step", rule.str());
  }
}

namespace {
bool leap_year(int y) noexcept { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }
}  // namespace

Nrlmsise00::Nrlmsise00(const Nrlmsise00Settings& settings) : settings_(settings) {
  settings_.validate();
  switches_ = settings_.switches;
  if (settings_.use_ap_history) switches_[9] = -1.0;
  // TT -> TAI -> UTC, then the calendar date of the epoch.
  double tai1 = 0.0, tai2 = 0.0, utc1 = 0.0, utc2 = 0.0;
  eraTttai(settings_.epoch_jd1, settings_.epoch_jd2, &tai1, &tai2);
  if (eraTaiutc(tai1, tai2, &utc1, &utc2) < 0) {  // dubious years still give a date: only errors refuse
    core::require(false, "nrlmsise00.epoch_jd1", "must be a date ERFA can convert to UTC");
  }
  int iy = 0, im = 0, id = 0;
  double fd = 0.0;
  if (eraJd2cal(utc1, utc2, &iy, &im, &id, &fd) != 0)
    core::require(false, "nrlmsise00.epoch_jd1", "must be a date ERFA can convert to a calendar date");
  double j0 = 0.0, jan1 = 0.0;
  eraCal2jd(iy, 1, 1, &j0, &jan1);
  double jday = 0.0;
  eraCal2jd(iy, im, id, &j0, &jday);
  year_ = iy;
  utc_days_since_year_start_ = (jday - jan1) + fd;
}

Nrlmsise00Input Nrlmsise00::input(const AtmospherePoint& p) const noexcept {
  Nrlmsise00Input in;
  double days = utc_days_since_year_start_ + p.t / 86400.0;
  int year = year_;
  for (int guard = 0; guard < 10000 && days >= (leap_year(year) ? 366.0 : 365.0); ++guard) {
    days -= leap_year(year) ? 366.0 : 365.0;
    ++year;
  }
  for (int guard = 0; guard < 10000 && days < 0.0; ++guard) {
    --year;
    days += leap_year(year) ? 366.0 : 365.0;
  }
  const double whole = std::floor(days);
  in.day_of_year = static_cast<int>(whole) + 1;
  in.ut_seconds = (days - whole) * 86400.0;
  in.altitude = p.height < 0.0 ? 0.0 : p.height;
  constexpr double rad_to_deg = 57.29577951308232;
  in.latitude = p.latitude * rad_to_deg;
  in.longitude = p.longitude * rad_to_deg;
  // Local apparent solar time: 12 h + hour angle of the Sun (longitude east of the sub-solar meridian).
  const double sun_lon = std::atan2(p.sun_itrf.y(), p.sun_itrf.x());
  double lst = 12.0 + (p.longitude - sun_lon) * rad_to_deg / 15.0;
  lst = std::fmod(lst, 24.0);
  if (lst < 0.0) lst += 24.0;
  in.local_solar_time = lst;
  const SpaceWeather& w = settings_.space_weather;
  in.f107 = w.f107;
  in.f107a = w.f107a;
  in.ap = w.ap;
  in.ap_history = settings_.ap_history;
  return in;
}

Nrlmsise00Output Nrlmsise00::evaluate(const AtmospherePoint& p) const noexcept {
  return nrlmsise00(input(p), switches_, settings_.anomalous_oxygen);
}

double Nrlmsise00::density(const AtmospherePoint& p) const noexcept { return evaluate(p).mass_density; }

double Nrlmsise00::density_gradient(const AtmospherePoint& p, Vec3& grad_itrf) const noexcept {
  const double h = settings_.gradient_step;
  for (int i = 0; i < 3; ++i) {
    Vec3 rp = p.r_itrf;
    Vec3 rm = p.r_itrf;
    rp[i] += h;
    rm[i] -= h;
    const double dp = density(atmosphere_point(p.t, rp, p.sun_itrf));
    const double dm = density(atmosphere_point(p.t, rm, p.sun_itrf));
    grad_itrf[i] = (dp - dm) / (2.0 * h);
  }
  return density(p);
}

}  // namespace satgnc::dynamics
