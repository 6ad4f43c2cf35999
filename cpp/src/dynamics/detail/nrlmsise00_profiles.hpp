#pragma once
// Private pieces of NRLMSISE-00: the vertical profiles (Bates temperature above the lower-thermosphere
// junction, cubic splines of 1/T in geopotential height below it, hydrostatic densities), the turbopause
// blending and the chemistry / dissociation corrections. Picone et al. 2002 and the NRL Fortran's
// documented structure (DENSU, DENSM, DNET, CCOR, CCOR2, SCALH). All fixed-size, allocation-free.
#include <cmath>

namespace satgnc::dynamics::detail::msis {

inline constexpr double kRgas = 831.4;  // gas constant in the model's units (cgs, 1e-7 scaled)

// x^2 as a product (the Fortran's x**2; std::pow(x, 2.0) costs a libm call).
inline double sq(double x) noexcept { return x * x; }

// Gravity at the surface (cm/s^2) and the effective Earth radius (km) of the model at latitude lat (deg).
struct Gravity {
  double gsurf;
  double re;
};
inline Gravity gravity_at(double lat_deg) noexcept {
  const double c2 = std::cos(2.0 * 1.74533e-2 * lat_deg);
  const double g = 980.616 * (1.0 - 0.0026373 * c2);
  return {g, 2.0 * g / (3.085462e-6 + 2.27e-9 * c2) * 1.0e-5};
}

// Geopotential height of z above zl (km) for the model's Earth radius.
inline double geopotential(double z, double zl, double re) noexcept {
  return (z - zl) * (re + zl) / (re + z);
}

// Cubic spline through n <= 5 nodes (x ascending): second derivatives with end slopes yp1, ypn.
template <int N>
void spline_second_derivatives(const double* x, const double* y, int n, double yp1, double ypn,
                               double* y2) noexcept {
  double u[N];
  y2[0] = -0.5;
  u[0] = (3.0 / (x[1] - x[0])) * ((y[1] - y[0]) / (x[1] - x[0]) - yp1);
  for (int i = 1; i < n - 1; ++i) {
    const double sig = (x[i] - x[i - 1]) / (x[i + 1] - x[i - 1]);
    const double p = sig * y2[i - 1] + 2.0;
    y2[i] = (sig - 1.0) / p;
    const double slope = (y[i + 1] - y[i]) / (x[i + 1] - x[i]) - (y[i] - y[i - 1]) / (x[i] - x[i - 1]);
    u[i] = (6.0 * slope / (x[i + 1] - x[i - 1]) - sig * u[i - 1]) / p;
  }
  const double qn = 0.5;
  const double un = (3.0 / (x[n - 1] - x[n - 2])) * (ypn - (y[n - 1] - y[n - 2]) / (x[n - 1] - x[n - 2]));
  y2[n - 1] = (un - qn * u[n - 2]) / (qn * y2[n - 2] + 1.0);
  for (int k = n - 2; k >= 0; --k) y2[k] = y2[k] * y2[k + 1] + u[k];
}

// Value of the spline at xv.
inline double spline_value(const double* x, const double* y, const double* y2, int n, double xv) noexcept {
  int lo = 0;
  int hi = n - 1;
  while (hi - lo > 1) {
    const int mid = (hi + lo) / 2;
    if (x[mid] > xv)
      hi = mid;
    else
      lo = mid;
  }
  const double h = x[hi] - x[lo];
  const double a = (x[hi] - xv) / h;
  const double b = (xv - x[lo]) / h;
  return a * y[lo] + b * y[hi] + ((a * a * a - a) * y2[lo] + (b * b * b - b) * y2[hi]) * h * h / 6.0;
}

// Integral of the spline from x[0] to xv (xv >= x[0]).
inline double spline_integral(const double* x, const double* y, const double* y2, int n, double xv) noexcept {
  double sum = 0.0;
  for (int lo = 0, hi = 1; xv > x[lo] && hi < n; ++lo, ++hi) {
    const double xx = (hi < n - 1 && xv >= x[hi]) ? x[hi] : xv;
    const double h = x[hi] - x[lo];
    const double a = (x[hi] - xx) / h;
    const double b = (xx - x[lo]) / h;
    const double a2 = a * a;
    const double b2 = b * b;
    sum +=
        ((1.0 - a2) * y[lo] / 2.0 + b2 * y[hi] / 2.0 +
         ((-(1.0 + a2 * a2) / 4.0 + a2 / 2.0) * y2[lo] + (b2 * b2 / 4.0 - b2 / 2.0) * y2[hi]) * h * h / 6.0) *
        h;
  }
  return sum;
}

// Temperature nodes of one spline layer: heights z (descending, km), temperatures t (K), gradients at
// the first and last node (K/km).
template <int N>
struct Layer {
  double z[N];
  double t[N];
  double grad_first;
  double grad_last;
};

// Spline of 1/T in normalized geopotential height through a layer, evaluated at height z (km): sets
// tz (K) and returns the integral for the hydrostatic density, with the normalization zgdif.
template <int N>
struct LayerEval {
  double tz;
  double integral;
  double zgdif;
};
template <int N>
LayerEval<N> eval_layer(const Layer<N>& L, double z, double re) noexcept {
  double xs[N], ys[N], y2[N];
  const double z1 = L.z[0];
  const double z2 = L.z[N - 1];
  const double zgdif = geopotential(z2, z1, re);
  for (int k = 0; k < N; ++k) {
    xs[k] = geopotential(L.z[k], z1, re) / zgdif;
    ys[k] = 1.0 / L.t[k];
  }
  const double t1 = L.t[0];
  const double t2 = L.t[N - 1];
  const double yd1 = -L.grad_first / (t1 * t1) * zgdif;
  const double ratio = (re + z2) / (re + z1);
  const double yd2 = -L.grad_last / (t2 * t2) * zgdif * ratio * ratio;
  spline_second_derivatives<N>(xs, ys, N, yd1, yd2, y2);
  const double x = geopotential(z, z1, re) / zgdif;
  const double y = spline_value(xs, ys, y2, N, x);
  return {1.0 / y, spline_integral(xs, ys, y2, N, x), zgdif};
}

// Thermospheric profile (DENSU): Bates temperature T(z) = tinf - (tinf - tlb) exp(-s zeta(z, zlb)) above
// the junction lower.z[0] and the spline of the lower-thermosphere layer below it (its first node and
// gradient come from the Bates profile at the junction). Density of a species of mass xm (amu) with
// thermal-diffusion factor alpha, dlb at zlb. xm = 0: temperature only (returned in tz).
struct ThermoProfile {
  double tinf, tlb, s, zlb;
  Layer<5> lower;  // z: 5 nodes from the junction down to 72.5 km; t[1..4], grad_last set; [0] from Bates
  Gravity g;
};
inline double thermo_density(const ThermoProfile& P, double alt, double dlb, double xm, double alpha,
                             double& tz) noexcept {
  const double re = P.g.re;
  const double za = P.lower.z[0];
  const double z = alt > za ? alt : za;
  const double zg2 = geopotential(z, P.zlb, re);
  const double tt = P.tinf - (P.tinf - P.tlb) * std::exp(-P.s * zg2);
  tz = tt;
  LayerEval<5> below{tt, 0.0, 0.0};
  if (alt < za) {
    Layer<5> L = P.lower;
    const double r = (re + P.zlb) / (re + za);
    L.t[0] = tt;
    L.grad_first = (P.tinf - tt) * P.s * r * r;
    const double zl = alt > L.z[4] ? alt : L.z[4];
    below = eval_layer<5>(L, zl, re);
    tz = below.tz;
  }
  if (xm == 0.0) return tz;
  const double glb = P.g.gsurf / sq(1.0 + P.zlb / re);
  const double gamma = xm * glb / (P.s * kRgas * P.tinf);
  double e = std::exp(-P.s * gamma * zg2);
  if (e > 50.0 || tt <= 0.0) e = 50.0;
  double d = dlb * std::pow(P.tlb / tt, 1.0 + alpha + gamma) * e;
  if (alt >= za) return d;
  const double glb1 = P.g.gsurf / sq(1.0 + za / re);
  double expl = xm * glb1 * below.zgdif / kRgas * below.integral;
  if (expl > 50.0 || tz <= 0.0) expl = 50.0;
  return d * std::pow(tt / tz, 1.0 + alpha) * std::exp(-expl);
}

// Hydrostatic density (d0 at the layer's top) and temperature through one lower-atmosphere layer.
template <int N>
double layer_density(const Layer<N>& L, double alt, double d0, double xm, const Gravity& g,
                     double& tz) noexcept {
  const LayerEval<N> e = eval_layer<N>(L, alt, g.re);
  tz = e.tz;
  if (xm == 0.0) return d0;
  const double glb = g.gsurf / sq(1.0 + L.z[0] / g.re);
  double expl = xm * glb * e.zgdif / kRgas * e.integral;
  if (expl > 50.0) expl = 50.0;
  return d0 * (L.t[0] / tz) * std::exp(-expl);
}

// Turbopause blending of the diffusive density dd and the fully mixed one dm (DNET).
inline double blend_mixed(double dd, double dm, double zhm, double xmm, double xm) noexcept {
  const double a = zhm / (xmm - xm);
  if (!(dm > 0.0 && dd > 0.0)) {
    if (dd == 0.0 && dm == 0.0) dd = 1.0;
    if (dm == 0.0) return dd;
    if (dd == 0.0) return dm;
  }
  const double ylog = a * std::log(dm / dd);
  if (ylog < -10.0) return dd;
  if (ylog > 10.0) return dm;
  return dd * std::pow(1.0 + std::exp(ylog), 1.0 / a);
}

// Chemistry / dissociation correction factor (CCOR): exp(r / (1 + exp((z - zh)/h1))).
inline double chem_factor(double z, double r, double h1, double zh) noexcept {
  const double e = (z - zh) / h1;
  if (e > 70.0) return 1.0;
  if (e < -70.0) return std::exp(r);
  return std::exp(r / (1.0 + std::exp(e)));
}

// Two-scale version (CCOR2).
inline double chem_factor2(double z, double r, double h1, double zh, double h2) noexcept {
  const double e1 = (z - zh) / h1;
  const double e2 = (z - zh) / h2;
  if (e1 > 70.0 || e2 > 70.0) return 1.0;
  if (e1 < -70.0 && e2 < -70.0) return std::exp(r);
  return std::exp(r / (1.0 + 0.5 * (std::exp(e1) + std::exp(e2))));
}

// Scale height (km) at z for mass xm and temperature t (SCALH).
inline double scale_height(double z, double xm, double t, const Gravity& g) noexcept {
  const double gz = g.gsurf / sq(1.0 + z / g.re);
  return kRgas * t / (gz * xm);
}

}  // namespace satgnc::dynamics::detail::msis
