// Spherical-harmonic gravity: fully normalized Cunningham recursion (Montenbruck & Gill 2000, sec. 3.2)
// with ladder-operator first and second derivatives, and the ICGEM .gfc reader.
#include "satgnc/dynamics/gravity_field.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

#include "satgnc/core/validate.hpp"

namespace satgnc::dynamics {

namespace {

// a! / b! for small |a - b| (exact integer products in double).
double fact_ratio(int a, int b) {
  double p = 1.0;
  if (a >= b) {
    for (int k = b + 1; k <= a; ++k) p *= k;
    return p;
  }
  for (int k = a + 1; k <= b; ++k) p *= k;
  return 1.0 / p;
}

// N_nm / N_{n2,m2}, N_nm^2 = (2 - delta_m0) (2n + 1) (n - m)! / (n + m)! (unnormalized = N * normalized).
double norm_ratio(int n, int m, int n2, int m2) {
  const double d1 = m == 0 ? 1.0 : 2.0;
  const double d2 = m2 == 0 ? 1.0 : 2.0;
  const double q =
      d1 / d2 * (2.0 * n + 1.0) / (2.0 * n2 + 1.0) * fact_ratio(n - m, n2 - m2) * fact_ratio(n2 + m2, n + m);
  return std::sqrt(q);
}

std::string where(const std::string& source, int line) { return source + ":" + std::to_string(line); }

[[noreturn]] void gfc_error(const std::string& source, int line, const std::string& keyword,
                            const std::string& rule) {
  throw std::invalid_argument(where(source, line) + ": " + keyword + ": " + rule);
}

// Parse a Fortran- or C-style real ("1.0d0", "-0.48E-03").
bool parse_real(std::string tok, double& out) {
  for (char& ch : tok)
    if (ch == 'd' || ch == 'D') ch = 'e';
  try {
    std::size_t used = 0;
    out = std::stod(tok, &used);
    return used == tok.size() && std::isfinite(out);
  } catch (const std::exception&) {
    return false;
  }
}

bool parse_int(const std::string& tok, int& out) {
  try {
    std::size_t used = 0;
    const long v = std::stol(tok, &used);
    if (used != tok.size() || v < 0 || v > 100000) return false;
    out = static_cast<int>(v);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

void GravityCoefficients::validate() const {
  core::require_positive(mu, "coefficients.mu");
  core::require_positive(radius, "coefficients.radius");
  core::require(max_degree >= 0, "coefficients.max_degree", "must be >= 0");
  const auto n = static_cast<std::size_t>((max_degree + 1) * (max_degree + 2) / 2);
  core::require(c.size() == n && s.size() == n, "coefficients.c",
                "c and s must hold (max_degree + 1)(max_degree + 2)/2 = " + std::to_string(n) + " values");
  for (std::size_t i = 0; i < n; ++i)
    core::require(std::isfinite(c[i]) && std::isfinite(s[i]), "coefficients.c",
                  "must be finite (no NaN or Inf) at index " + std::to_string(i));
}

GravityCoefficients parse_gfc(std::istream& in, const std::string& source, int max_degree) {
  GravityCoefficients g;
  bool have_gm = false, have_radius = false, have_max = false, in_header = true;
  int file_max = -1;
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string key;
    if (!(ls >> key)) continue;
    if (in_header) {
      if (key == "end_of_head") {
        if (!have_gm) gfc_error(source, lineno, "earth_gravity_constant", "missing from the header");
        if (!have_radius) gfc_error(source, lineno, "radius", "missing from the header");
        if (!have_max) gfc_error(source, lineno, "max_degree", "missing from the header");
        if (max_degree > file_max)
          throw std::invalid_argument("max_degree: " + std::to_string(max_degree) +
                                      " is above the file's max_degree " + std::to_string(file_max) + " (" +
                                      source + ")");
        const int nmax = max_degree < 0 ? file_max : max_degree;
        g.max_degree = nmax;
        const auto size = static_cast<std::size_t>((nmax + 1) * (nmax + 2) / 2);
        g.c.assign(size, 0.0);
        g.s.assign(size, 0.0);
        in_header = false;
        continue;
      }
      std::string value;
      ls >> value;
      if (key == "modelname") {
        g.name = value;
      } else if (key == "tide_system") {
        g.tide_system = value;
      } else if (key == "earth_gravity_constant" || key == "radius") {
        double x = 0.0;
        if (!parse_real(value, x) || !(x > 0.0))
          gfc_error(source, lineno, key, "must be a positive number, got '" + value + "'");
        if (key == "radius") {
          g.radius = x * 1e-3;  // m -> km
          have_radius = true;
        } else {
          g.mu = x * 1e-9;  // m^3/s^2 -> km^3/s^2
          have_gm = true;
        }
      } else if (key == "max_degree") {
        if (!parse_int(value, file_max))
          gfc_error(source, lineno, key, "must be a non-negative integer, got '" + value + "'");
        have_max = true;
      } else if (key == "norm") {
        if (value != "fully_normalized")
          gfc_error(source, lineno, key,
                    "only fully_normalized coefficients are supported, got '" + value + "'");
      }
      continue;  // other header keywords and free text are ignored
    }
    if (key == "gfct" || key == "trnd" || key == "acos" || key == "asin" || key == "dot")
      gfc_error(source, lineno, key, "time-variable terms are not supported (static gfc files only)");
    if (key != "gfc") gfc_error(source, lineno, key, "unknown data keyword (expected 'gfc')");
    std::string tn, tm, tc, tsn;
    if (!(ls >> tn >> tm >> tc >> tsn))
      gfc_error(source, lineno, "gfc", "expected 'gfc L M C S [sigma_C sigma_S]'");
    int n = 0, m = 0;
    double cv = 0.0, sv = 0.0;
    if (!parse_int(tn, n) || !parse_int(tm, m) || m > n)
      gfc_error(source, lineno, "gfc",
                "degree and order must be integers with 0 <= M <= L, got '" + tn + " " + tm + "'");
    if (n > file_max)
      gfc_error(
          source, lineno, "gfc",
          "degree " + std::to_string(n) + " is above the header's max_degree " + std::to_string(file_max));
    if (!parse_real(tc, cv) || !parse_real(tsn, sv))
      gfc_error(source, lineno, "gfc", "C and S must be finite numbers, got '" + tc + "' '" + tsn + "'");
    if (n <= g.max_degree) {
      const auto i = static_cast<std::size_t>(GravityCoefficients::index(n, m));
      g.c[i] = cv;
      g.s[i] = sv;
    }
  }
  if (in_header) gfc_error(source, lineno, "end_of_head", "missing: the file ended inside the header");
  return g;
}

GravityCoefficients load_gfc(const std::string& path, int max_degree) {
  std::ifstream f(path);
  core::require(f.good(), "path", "cannot open '" + path + "'");
  return parse_gfc(f, path, max_degree);
}

GravityField::GravityField(std::shared_ptr<const GravityCoefficients> coefficients, int degree, int order,
                           std::shared_ptr<const frames::EarthRotationModel> rotation)
    : coef_(std::move(coefficients)), rotation_(std::move(rotation)), degree_(degree), order_(order) {
  core::require(coef_ != nullptr, "coefficients", "must not be null");
  core::require(rotation_ != nullptr, "rotation", "must not be null",
                "pass frames.UniformRotation() for the Earth turning about the inertial z axis");
  coef_->validate();
  core::require(degree >= 2, "degree", "must be >= 2, got " + std::to_string(degree),
                "degree 0 is ForceModel's point mass; degree 1 is zero in a centre-of-mass frame");
  core::require(
      degree <= coef_->max_degree, "degree",
      std::to_string(degree) + " is above the file's max_degree " + std::to_string(coef_->max_degree));
  core::require(order >= 0 && order <= degree, "order",
                "must be in [0, degree = " + std::to_string(degree) + "], got " + std::to_string(order));
  const int S = stride();
  const auto size = static_cast<std::size_t>(S * S);
  rec_a_.assign(size, 0.0);
  rec_b_.assign(size, 0.0);
  sect_.assign(static_cast<std::size_t>(S), 0.0);
  for (int m = 1; m < S; ++m)
    sect_[static_cast<std::size_t>(m)] = m == 1 ? std::sqrt(3.0) : std::sqrt((2.0 * m + 1.0) / (2.0 * m));
  for (int n = 1; n < S; ++n)
    for (int m = 0; m < n; ++m) {
      const double dn = n, dm = m;
      const auto k = static_cast<std::size_t>(n * S + m);
      rec_a_[k] = std::sqrt((2.0 * dn - 1.0) * (2.0 * dn + 1.0) / ((dn - dm) * (dn + dm)));
      if (n >= 2)
        rec_b_[k] = std::sqrt((2.0 * dn + 1.0) * (dn + dm - 1.0) * (dn - dm - 1.0) /
                              ((2.0 * dn - 3.0) * (dn + dm) * (dn - dm)));
    }
  ladder_.assign(size * 8, 0.0);
  for (int n = 2; n <= degree_; ++n)
    for (int m = 0; m <= std::min(n, order_); ++m) {
      double* f = &ladder_[static_cast<std::size_t>(8 * (n * S + m))];
      const double d = n - m;
      f[0] = (d + 1.0) * norm_ratio(n, m, n + 1, m);                                          // Dz
      f[1] = norm_ratio(n, m, n + 1, m + 1);                                                  // D+
      if (m >= 1) f[2] = (d + 2.0) * (d + 1.0) * norm_ratio(n, m, n + 1, m - 1);              // D-
      f[3] = (d + 1.0) * (d + 2.0) * norm_ratio(n, m, n + 2, m);                              // Dz Dz
      f[4] = (d + 1.0) * norm_ratio(n, m, n + 2, m + 1);                                      // D+ Dz
      if (m >= 1) f[5] = (d + 1.0) * (d + 2.0) * (d + 3.0) * norm_ratio(n, m, n + 2, m - 1);  // D- Dz
      f[6] = norm_ratio(n, m, n + 2, m + 2);                                                  // D+ D+
      if (m == 1) f[7] = n * (n + 1.0) * norm_ratio(n, 1, n + 2, 1);                          // D- D-, m = 1
      if (m >= 2) f[7] = (d + 1.0) * (d + 2.0) * (d + 3.0) * (d + 4.0) * norm_ratio(n, m, n + 2, m - 2);
    }
  v_.assign(size, 0.0);
  w_.assign(size, 0.0);
}

void GravityField::harmonics(const Vec3& r, int nmax, int mmax) const {
  const int S = stride();
  const double R = coef_->radius;
  const double r2 = r.squaredNorm();
  const double rho = R / r2;
  const double x0 = r.x() * rho, y0 = r.y() * rho, z0 = r.z() * rho, rr = R * rho;
  double* V = v_.data();
  double* W = w_.data();
  V[0] = R / std::sqrt(r2);
  W[0] = 0.0;
  for (int m = 0; m <= mmax; ++m) {
    const int mm = m * S + m;
    if (m > 0) {
      const int pm = (m - 1) * S + (m - 1);
      const double k = sect_[static_cast<std::size_t>(m)];
      V[mm] = k * (x0 * V[pm] - y0 * W[pm]);
      W[mm] = k * (x0 * W[pm] + y0 * V[pm]);
    }
    if (m + 1 > nmax) continue;
    {
      const int i = (m + 1) * S + m;
      const double a = rec_a_[static_cast<std::size_t>(i)] * z0;
      V[i] = a * V[mm];
      W[i] = a * W[mm];
    }
    for (int n = m + 2; n <= nmax; ++n) {
      const int i = n * S + m;
      const double a = rec_a_[static_cast<std::size_t>(i)] * z0;
      const double b = rec_b_[static_cast<std::size_t>(i)] * rr;
      V[i] = a * V[i - S] - b * V[i - 2 * S];
      W[i] = a * W[i - S] - b * W[i - 2 * S];
    }
  }
}

double GravityField::potential_fixed(const Vec3& r) const {
  harmonics(r, degree_, order_);
  const int S = stride();
  double u = 0.0;
  for (int n = 2; n <= degree_; ++n)
    for (int m = 0; m <= std::min(n, order_); ++m) {
      const int i = n * S + m;
      u += coef_->cnm(n, m) * v_[static_cast<std::size_t>(i)] +
           coef_->snm(n, m) * w_[static_cast<std::size_t>(i)];
    }
  return -coef_->mu / coef_->radius * u;
}

Vec3 GravityField::acceleration_fixed(const Vec3& r) const {
  harmonics(r, degree_ + 1, std::min(order_ + 1, degree_ + 1));
  const int S = stride();
  const double* V = v_.data();
  const double* W = w_.data();
  double dz = 0.0, pr = 0.0, pi = 0.0;
  for (int n = 2; n <= degree_; ++n) {
    for (int m = 0; m <= std::min(n, order_); ++m) {
      const double C = coef_->cnm(n, m), Sn = coef_->snm(n, m);
      const double* f = &ladder_[static_cast<std::size_t>(8 * (n * S + m))];
      int i = (n + 1) * S + m;
      dz -= f[0] * (C * V[i] + Sn * W[i]);
      if (m == 0) {
        i = (n + 1) * S + 1;
        pr -= f[1] * C * V[i];
        pi -= f[1] * C * W[i];
      } else {
        i = (n + 1) * S + m + 1;
        pr -= 0.5 * f[1] * (C * V[i] + Sn * W[i]);
        pi -= 0.5 * f[1] * (C * W[i] - Sn * V[i]);
        i = (n + 1) * S + m - 1;
        pr += 0.5 * f[2] * (C * V[i] + Sn * W[i]);
        pi -= 0.5 * f[2] * (C * W[i] - Sn * V[i]);
      }
    }
  }
  const double k = coef_->mu / (coef_->radius * coef_->radius);
  return Vec3(k * pr, k * pi, k * dz);
}

void GravityField::gradient_fixed(const Vec3& r, Vec3& a, Mat3& g) const {
  harmonics(r, degree_ + 2, std::min(order_ + 2, degree_ + 2));
  const int S = stride();
  const double* V = v_.data();
  const double* W = w_.data();
  double dz = 0.0, pr = 0.0, pi = 0.0, zz = 0.0, pzr = 0.0, pzi = 0.0, ppr = 0.0, ppi = 0.0;
  // c = C - i S and Y = V + i W: Re(c Y) = C V + S W, Im(c Y) = C W - S V.
  for (int n = 2; n <= degree_; ++n) {
    for (int m = 0; m <= std::min(n, order_); ++m) {
      const double C = coef_->cnm(n, m), Sn = coef_->snm(n, m);
      const double* f = &ladder_[static_cast<std::size_t>(8 * (n * S + m))];
      auto re = [&](int i) { return C * V[i] + Sn * W[i]; };
      auto im = [&](int i) { return C * W[i] - Sn * V[i]; };
      const int n1 = (n + 1) * S, n2 = (n + 2) * S;
      dz -= f[0] * re(n1 + m);
      zz += f[3] * re(n2 + m);
      if (m == 0) {
        pr -= f[1] * re(n1 + 1);
        pi -= f[1] * im(n1 + 1);
        pzr += f[4] * re(n2 + 1);
        pzi += f[4] * im(n2 + 1);
        ppr += f[6] * re(n2 + 2);
        ppi += f[6] * im(n2 + 2);
        continue;
      }
      pr += 0.5 * (-f[1] * re(n1 + m + 1) + f[2] * re(n1 + m - 1));
      pi += 0.5 * (-f[1] * im(n1 + m + 1) - f[2] * im(n1 + m - 1));
      pzr += 0.5 * (f[4] * re(n2 + m + 1) - f[5] * re(n2 + m - 1));
      pzi += 0.5 * (f[4] * im(n2 + m + 1) + f[5] * im(n2 + m - 1));
      if (m == 1) {
        // conj(c) Y_{n+2,1}: (C + i S)(V + i W).
        const int i = n2 + 1;
        ppr += 0.5 * (f[6] * re(n2 + 3) - f[7] * (C * V[i] - Sn * W[i]));
        ppi += 0.5 * (f[6] * im(n2 + 3) - f[7] * (C * W[i] + Sn * V[i]));
      } else {
        ppr += 0.5 * (f[6] * re(n2 + m + 2) + f[7] * re(n2 + m - 2));
        ppi += 0.5 * (f[6] * im(n2 + m + 2) - f[7] * im(n2 + m - 2));
      }
    }
  }
  const double R = coef_->radius;
  const double k1 = coef_->mu / (R * R);
  const double k2 = k1 / R;
  a = Vec3(k1 * pr, k1 * pi, k1 * dz);
  const double uzz = k2 * zz;
  const double uxx = 0.5 * k2 * (ppr - zz);
  const double uyy = 0.5 * k2 * (-ppr - zz);
  const double uxy = 0.5 * k2 * ppi;
  const double uxz = k2 * pzr;
  const double uyz = k2 * pzi;
  g << uxx, uxy, uxz, uxy, uyy, uyz, uxz, uyz, uzz;
}

Vec3 GravityField::acceleration(double t, const Vec3& r) const {
  Mat3 R;
  Vec3 w;
  rotation_->rotation(t, R, w);
  return R.transpose() * acceleration_fixed(R * r);
}

void GravityField::jacobian(double t, const Vec3& r, Vec3& a, Mat3& da_dr) const {
  Mat3 R;
  Vec3 w;
  rotation_->rotation(t, R, w);
  Vec3 af;
  Mat3 gf;
  gradient_fixed(R * r, af, gf);
  a = R.transpose() * af;
  da_dr = R.transpose() * gf * R;
}

double GravityField::potential(double t, const Vec3& r) const {
  Mat3 R;
  Vec3 w;
  rotation_->rotation(t, R, w);
  return potential_fixed(R * r);
}

}  // namespace satgnc::dynamics
