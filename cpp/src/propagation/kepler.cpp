// Universal-variable two-body propagation with the analytic STM.
//
// Formulation (Battin 1999, sec. 4.5; Goodyear 1965): with sigma0 = r0.v0 / sqrt(mu), alpha = 1/a and
// the universal functions U_n(chi; alpha) = chi^n c_n(alpha chi^2), the universal Kepler equation is
//   F(chi) = r0 U1 + sigma0 U2 + U3 - sqrt(mu) dt = 0,  F' = r = r0 U0 + sigma0 U1 + U2 > 0,
// and the Lagrange coefficients are
//   f = 1 - U2/r0, g = (r0 U1 + sigma0 U2)/sqrt(mu), fdot = -sqrt(mu) U1/(r r0), gdot = 1 - U2/r.
// The STM follows from the chain rule through the three scalars (r0, sigma0, alpha) of x0, with chi
// implicit (dchi = -(F_p dp)/r) and dU_n/dalpha = (n U_{n+2} - chi U_{n+1})/2 at fixed chi, which
// holds for every conic, so nothing is singular at alpha = 0.
#include "satgnc/propagation/kepler.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "satgnc/core/validate.hpp"

namespace satgnc::propagation {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;
constexpr int kSeriesTerms = 17;  // |psi| < 4: 4^16 / 37! ~ 3e-35, far below eps

// 1/k! for k = 0..40, built at compile time.
struct InvFactorials {
  double v[41];
  constexpr InvFactorials() : v() {
    v[0] = 1.0;
    for (int k = 1; k < 41; ++k) v[k] = v[k - 1] / k;
  }
};
constexpr InvFactorials kInvFact{};

}  // namespace

void stumpff(double psi, double c[6]) {
  if (std::abs(psi) < 4.0) {
    // c4, c5 by Horner in (-psi); lower orders by c_k = 1/k! - psi c_{k+2} (no cancellation here).
    double c4 = 0.0, c5 = 0.0;
    for (int j = kSeriesTerms - 1; j >= 0; --j) {
      c4 = kInvFact.v[2 * j + 4] - psi * c4;
      c5 = kInvFact.v[2 * j + 5] - psi * c5;
    }
    c[4] = c4;
    c[5] = c5;
    c[2] = 0.5 - psi * c4;
    c[3] = 1.0 / 6.0 - psi * c5;
    c[0] = 1.0 - psi * c[2];
    c[1] = 1.0 - psi * c[3];
    return;
  }
  if (psi > 0.0) {
    const double s = std::sqrt(psi);
    const double sn = std::sin(s);
    const double h = std::sin(0.5 * s);
    c[0] = std::cos(s);
    c[1] = sn / s;
    c[2] = 2.0 * h * h / psi;
    c[3] = (s - sn) / (psi * s);
  } else {
    const double s = std::sqrt(-psi);
    const double sh = std::sinh(s);
    const double h = std::sinh(0.5 * s);
    c[0] = std::cosh(s);
    c[1] = sh / s;
    c[2] = 2.0 * h * h / (-psi);
    c[3] = (sh - s) / (-psi * s);
  }
  c[4] = (0.5 - c[2]) / psi;
  c[5] = (1.0 / 6.0 - c[3]) / psi;
}

namespace {
KeplerStatus kepler_step_impl(const Vec6& x0, double dt, double mu, Vec6& x, Mat6* stm, KeplerInfo* info,
                              int max_iterations) {
  if (info) *info = KeplerInfo{};
  if (!(std::isfinite(mu) && mu > 0.0) || !std::isfinite(dt) || !x0.allFinite())
    return KeplerStatus::invalid_input;
  const Vec3 r0v = x0.head<3>();
  const Vec3 v0v = x0.tail<3>();
  const double r0 = r0v.norm();
  if (!(r0 > 0.0)) return KeplerStatus::invalid_input;
  const double sqmu = std::sqrt(mu);
  const double s0 = r0v.dot(v0v) / sqmu;
  const double alpha = 2.0 / r0 - v0v.squaredNorm() / mu;
  const double beta = 1.0 - alpha * r0;
  const double tau = sqmu * dt;
  if (info) info->alpha = alpha;

  if (dt == 0.0) {
    x = x0;
    if (stm) stm->setIdentity();
    return KeplerStatus::success;
  }

  // ---- initial guess
  double chi;
  const double taylor = tau / r0 - 0.5 * s0 * tau * tau / (r0 * r0 * r0);
  if (std::abs(tau) < 0.5 * r0 * std::sqrt(r0) && std::abs(alpha) * taylor * taylor < 1.0) {
    chi = taylor;  // short arc: second-order Taylor series of chi(t)
  } else if (alpha * r0 > 1e-6) {
    chi = tau * alpha;  // ellipse: mean rate of chi is sqrt(mu)/a
  } else if (alpha * r0 < -1e-6) {
    const double a = 1.0 / alpha;
    const double sg = dt > 0.0 ? 1.0 : -1.0;
    const double arg = -2.0 * mu * alpha * dt / (sqmu * s0 + sg * std::sqrt(-mu * a) * beta);
    chi = sg * std::sqrt(-a) * std::log(arg);  // Vallado (2013), Algorithm 8, hyperbolic guess
    if (!std::isfinite(chi) || chi * dt <= 0.0) chi = tau / r0;
  } else {
    chi = tau / r0;  // near-parabolic: the bracketed Laguerre iteration does the rest
  }
  if (!std::isfinite(chi) || chi * dt <= 0.0) chi = tau / r0;

  // ---- bracketed Laguerre iteration (F is increasing in chi: F' = r > 0)
  double lo = dt > 0.0 ? 0.0 : -kInf;
  double hi = dt > 0.0 ? kInf : 0.0;
  double c[6];
  bool converged = false;
  bool overflowed = false;
  int it = 0;
  double F = 0.0;
  double F_prev = kInf;
  for (it = 1; it <= max_iterations; ++it) {
    const double psi = alpha * chi * chi;
    stumpff(psi, c);
    const double U0 = c[0], U1 = chi * c[1], U2 = chi * chi * c[2], U3 = chi * chi * chi * c[3];
    F = r0 * U1 + s0 * U2 + U3 - tau;
    const double Fp = r0 * U0 + s0 * U1 + U2;
    if (!std::isfinite(F) || !std::isfinite(Fp)) {
      // Past the solution (hyperbolic growth): shrink towards the bracket side known to be short.
      overflowed = true;
      if (dt > 0.0)
        hi = chi;
      else
        lo = chi;
      chi = (std::isfinite(lo) && std::isfinite(hi)) ? 0.5 * (lo + hi) : 0.5 * chi;
      continue;
    }
    overflowed = false;
    if (F == 0.0) {
      converged = true;
      break;
    }
    if (F < 0.0)
      lo = std::max(lo, chi);
    else
      hi = std::min(hi, chi);
    const double Fpp = s0 * U0 + beta * U1;
    constexpr double n = 5.0;
    const double disc = (n - 1.0) * (n - 1.0) * Fp * Fp - n * (n - 1.0) * F * Fpp;
    const double den = Fp + std::copysign(std::sqrt(std::abs(disc)), Fp);
    const double delta = n * F / den;
    const double scale = r0 * std::abs(U1) + std::abs(s0 * U2) + std::abs(U3) + std::abs(tau);
    if (std::abs(delta) <= 4.0 * kEps * std::abs(chi) || std::abs(F) <= 4.0 * kEps * scale) {
      // At the roundoff floor of F: take the last correction only if it stays inside the bracket.
      const double chin = chi - delta;
      if (chin >= lo && chin <= hi) chi = chin;
      converged = true;
      break;
    }
    double chin = chi - delta;
    // Bisect when outside the bracket, or when |F| shrinks by less than half (exponential regime of
    // strong hyperbolas, where Newton-like steps creep by ~1/sqrt(-alpha)).
    const bool slow = std::abs(F) > 0.5 * F_prev && std::isfinite(lo) && std::isfinite(hi);
    if (!(chin > lo && chin < hi) || !std::isfinite(chin) || slow) chin = 0.5 * (lo + hi);
    F_prev = std::abs(F);
    chi = chin;
    if ((hi - lo) <= 4.0 * kEps * std::abs(chi)) {
      converged = true;
      break;
    }
  }
  if (info) {
    info->iterations = std::min(it, max_iterations);
    info->chi = chi;
  }
  if (!converged) return overflowed ? KeplerStatus::overflow : KeplerStatus::no_convergence;

  // ---- state at chi
  stumpff(alpha * chi * chi, c);
  const double chi2 = chi * chi;
  const double U0 = c[0], U1 = chi * c[1], U2 = chi2 * c[2], U3 = chi2 * chi * c[3];
  const double U4 = chi2 * chi2 * c[4], U5 = chi2 * chi2 * chi * c[5];
  const double r = r0 * U0 + s0 * U1 + U2;
  if (!std::isfinite(r) || !(r > 0.0)) return KeplerStatus::overflow;
  if (info) info->residual = std::abs(r0 * U1 + s0 * U2 + U3 - tau);
  const double f = 1.0 - U2 / r0;
  const double g = (r0 * U1 + s0 * U2) / sqmu;
  const double fd = -sqmu * U1 / (r * r0);
  const double gd = 1.0 - U2 / r;
  x.head<3>() = f * r0v + g * v0v;
  x.tail<3>() = fd * r0v + gd * v0v;
  if (!x.allFinite()) return KeplerStatus::overflow;
  if (!stm) return KeplerStatus::success;

  // ---- analytic STM. Scalar parameters p = (r0, sigma0, alpha), index R, S, A.
  enum { R = 0, S = 1, A = 2 };
  // Partials of U_n with respect to alpha at fixed chi.
  const double Ua[4] = {-0.5 * chi * U1, 0.5 * (U3 - chi * U2), 0.5 * (2.0 * U4 - chi * U3),
                        0.5 * (3.0 * U5 - chi * U4)};
  // dchi/dp from the implicit Kepler equation.
  double dchi[3];
  dchi[R] = -U1 / r;
  dchi[S] = -U2 / r;
  dchi[A] = -(r0 * Ua[1] + s0 * Ua[2] + Ua[3]) / r;
  const double dUdchi[3] = {-alpha * U1, U0, U1};  // dU0, dU1, dU2 / dchi
  double DU[3][3];                                 // DU[n][j] total derivative of U_n w.r.t. p_j
  for (int n = 0; n < 3; ++n)
    for (int j = 0; j < 3; ++j) DU[n][j] = dUdchi[n] * dchi[j] + (j == A ? Ua[n] : 0.0);
  double Df[3], Dg[3], Dfd[3], Dgd[3];
  for (int j = 0; j < 3; ++j) {
    const double Dr = (j == R ? U0 : 0.0) + (j == S ? U1 : 0.0) + r0 * DU[0][j] + s0 * DU[1][j] + DU[2][j];
    Df[j] = -DU[2][j] / r0 + (j == R ? U2 / (r0 * r0) : 0.0);
    Dg[j] = ((j == R ? U1 : 0.0) + r0 * DU[1][j] + (j == S ? U2 : 0.0) + s0 * DU[2][j]) / sqmu;
    Dfd[j] = -sqmu * (DU[1][j] - U1 * (Dr / r + (j == R ? 1.0 / r0 : 0.0))) / (r * r0);
    Dgd[j] = (-DU[2][j] + U2 * Dr / r) / r;
  }
  // Gradients of p with respect to x0 = [r0v; v0v].
  Vec6 gp[3];
  gp[R] << r0v / r0, Vec3::Zero();
  gp[S] << v0v / sqmu, r0v / sqmu;
  gp[A] << -2.0 * r0v / (r0 * r0 * r0), -2.0 * v0v / mu;
  Vec6 gf = Vec6::Zero(), gg = Vec6::Zero(), gfd = Vec6::Zero(), ggd = Vec6::Zero();
  for (int j = 0; j < 3; ++j) {
    gf += Df[j] * gp[j];
    gg += Dg[j] * gp[j];
    gfd += Dfd[j] * gp[j];
    ggd += Dgd[j] * gp[j];
  }
  Mat6& P = *stm;
  const Mat3 I = Mat3::Identity();
  P.topLeftCorner<3, 3>() = f * I;
  P.topRightCorner<3, 3>() = g * I;
  P.bottomLeftCorner<3, 3>() = fd * I;
  P.bottomRightCorner<3, 3>() = gd * I;
  P.topRows<3>() += r0v * gf.transpose() + v0v * gg.transpose();
  P.bottomRows<3>() += r0v * gfd.transpose() + v0v * ggd.transpose();
  if (!P.allFinite()) return KeplerStatus::overflow;
  return KeplerStatus::success;
}
}  // namespace

KeplerStatus kepler_step(const Vec6& x0, double dt, double mu, Vec6& x, Mat6* stm, KeplerInfo* info,
                         int max_iterations) {
  const KeplerStatus status = kepler_step_impl(x0, dt, mu, x, stm, info, max_iterations);
  if (info) info->status = status;
  return status;
}

std::string kepler_failure_message(KeplerStatus s, double alpha, double dt) {
  if (s == KeplerStatus::overflow && !(alpha < 0.0)) {
    return std::string("the universal functions overflowed on this ") +
           (alpha > 0.0 ? "ellipse" : "parabola") + " (dt = " + std::to_string(dt) +
           " s; a degenerate, nearly radial orbit)";
  }
  return status_message(s);
}

namespace {
// |r| after s seconds from y (NaN when the step fails).
double radius_after(const Vec6& y, double s, double mu) {
  Vec6 x;
  if (kepler_step(y, s, mu, x, nullptr) != KeplerStatus::success)
    return std::numeric_limits<double>::quiet_NaN();
  return x.head<3>().norm();
}

// Bisection for |r(s)| = R on [lo, hi] with |r(lo)| > R >= |r(hi)|: the first crossing, to rounding.
double bisect_radius(const Vec6& y, double lo, double hi, double mu, double R) {
  for (int k = 0; k < 200 && hi - lo > 4.0 * kEps * std::max(1.0, hi); ++k) {
    const double mid = 0.5 * (lo + hi);
    const double r = radius_after(y, mid, mu);
    if (r > R)
      lo = mid;
    else
      hi = mid;  // also on a failed step (NaN): shrink towards the known-good side
  }
  return hi;
}
}  // namespace

double kepler_time_to_radius(const Vec6& x0, double dt, double mu, double surface_radius) {
  if (!(std::isfinite(mu) && mu > 0.0) || !std::isfinite(dt) || !x0.allFinite() || dt == 0.0) return -1.0;
  // Two-body motion is time-reversible: the backward arc is the forward arc of the reversed velocity.
  Vec6 y = x0;
  if (dt < 0.0) y.tail<3>() = -y.tail<3>();
  const double T = std::abs(dt);
  const Vec3 r = y.head<3>(), v = y.tail<3>();
  const double r0 = r.norm();
  if (!(r0 > 0.0)) return 0.0;
  const double R = std::max(surface_radius, 0.0);
  if (r0 <= R) return 0.0;
  const double sqmu = std::sqrt(mu);
  const double rv = r.dot(v);
  const double v2 = v.squaredNorm();
  const double h2 = r.cross(v).squaredNorm();
  const Vec3 evec = ((v2 - mu / r0) * r - rv * v) / mu;
  const double e = evec.norm();
  const double rp = h2 / (mu * (1.0 + e));
  const double collision = 1e-9 * r0;  // periapsis this close to the centre: a collision orbit
  const double Rt = std::max(R, collision);
  if (rp > Rt) return -1.0;
  const double alpha = 2.0 / r0 - v2 / mu;
  double lo = 0.0, hi = T;
  if (alpha * r0 > 1e-12) {
    // Ellipse: next periapsis from the mean anomaly; r decreases on [tau - P/2, tau].
    const double a = 1.0 / alpha;
    const double n = std::sqrt(mu * alpha * alpha * alpha);
    const double esinE = rv / (sqmu * std::sqrt(a));
    const double ecosE = 1.0 - r0 * alpha;
    const double E = std::atan2(esinE, ecosE);
    const double M = E - esinE;
    const double P = 2.0 * kPi / n;
    double tau = M < 0.0 ? -M / n : (2.0 * kPi - M) / n;
    if (tau <= 0.0) tau = P;
    lo = std::max(0.0, tau - 0.5 * P);
    if (lo >= T) return -1.0;
    hi = std::min(tau, T);
    if (hi == tau && R <= collision) return tau;  // collision orbit: r = 0 exactly at periapsis
  } else {
    // Parabola or hyperbola: r falls only before the single periapsis, and is unimodal.
    if (rv >= 0.0) return -1.0;
    double a = 0.0, b = T;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double c1 = b - g * (b - a), c2 = a + g * (b - a);
    double f1 = radius_after(y, c1, mu), f2 = radius_after(y, c2, mu);
    for (int k = 0; k < 200 && b - a > 4.0 * kEps * std::max(1.0, b); ++k) {
      if (!(f1 > f2)) {  // minimum in [a, c2] (NaN: the step failed near the centre, keep the early part)
        b = c2;
        c2 = c1;
        f2 = f1;
        c1 = b - g * (b - a);
        f1 = radius_after(y, c1, mu);
      } else {
        a = c1;
        c1 = c2;
        f1 = f2;
        c2 = a + g * (b - a);
        f2 = radius_after(y, c2, mu);
      }
    }
    const double s_min = 0.5 * (a + b);
    const double r_end = radius_after(y, T, mu);
    if (r_end <= Rt) {
      hi = T;
    } else {
      const double r_min = radius_after(y, s_min, mu);
      if (!(r_min <= Rt) && std::isfinite(r_min)) return -1.0;
      hi = s_min;
      if (R <= collision) return s_min;
    }
  }
  const double r_hi = radius_after(y, hi, mu);
  if (r_hi > Rt) return -1.0;
  return bisect_radius(y, lo, hi, mu, Rt);
}

Trajectory propagate_kepler(const Vec6& x0, double t0, const std::vector<double>& times, double mu,
                            bool with_stm, double surface_radius) {
  validate_orbit_arc_input(x0, t0, times, kTwoSidedArc,
                           "the two-body problem is singular at the centre of the body");
  core::require_positive(mu, "mu");
  core::require_nonnegative(surface_radius, "surface_radius");
  core::require(x0.head<3>().norm() > surface_radius, "x0",
                "starts below the surface: |r0| = " + std::to_string(x0.head<3>().norm()) +
                    " km <= surface_radius = " + std::to_string(surface_radius) + " km");
  Trajectory tr;
  tr.status = PropagationStatus::success;
  tr.times.reserve(times.size());
  tr.states.reserve(times.size());
  if (with_stm) tr.stms.reserve(times.size());
  tr.t_reached = t0;
  // The impact check runs once over the whole arc (times are monotone): the farthest time from t0.
  double t_far = t0;
  for (double t : times)
    if (std::abs(t - t0) > std::abs(t_far - t0)) t_far = t;
  const double s_impact = kepler_time_to_radius(x0, t_far - t0, mu, surface_radius);
  const double dir = t_far >= t0 ? 1.0 : -1.0;
  for (double t : times) {
    if (s_impact >= 0.0 && (t - t0) * dir > s_impact) {
      tr.status = PropagationStatus::impact;
      tr.t_reached = t0 + dir * s_impact;
      tr.message = "propagate_kepler: impact at t = " + std::to_string(tr.t_reached) + " s: |r| reached " +
                   (surface_radius > 0.0 ? "surface_radius = " + std::to_string(surface_radius) + " km"
                                         : std::string("0 (a collision orbit through the centre)")) +
                   " before the requested time " + std::to_string(t) + " s";
      return tr;
    }
    Vec6 x;
    Mat6 phi;
    KeplerInfo info;
    const KeplerStatus st = kepler_step(x0, t - t0, mu, x, with_stm ? &phi : nullptr, &info);
    tr.stats.nonlin_iters += info.iterations;
    if (st != KeplerStatus::success) {
      tr.status = PropagationStatus::convergence_failures;
      tr.message = std::string("propagate_kepler: ") + kepler_failure_message(st, info.alpha, t - t0) +
                   " at t = " + std::to_string(t) + " s (dt = " + std::to_string(t - t0) + " s)";
      return tr;
    }
    tr.stats.steps += 1;
    tr.times.push_back(t);
    tr.states.push_back(x);
    if (with_stm) tr.stms.push_back(phi);
    tr.t_reached = t;
  }
  return tr;
}

}  // namespace satgnc::propagation
