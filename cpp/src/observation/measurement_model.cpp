#include "satgnc/observation/measurement_model.hpp"

#include <cctype>
#include <cmath>

#include "satgnc/core/validate.hpp"
#include "satgnc/observation/modifiers.hpp"

namespace satgnc::observation {

namespace {
constexpr double kTwoPi = 6.283185307179586476925286766559;
constexpr double kC = speed_of_light;
using Row3 = Eigen::Matrix<double, 1, 3>;
using Row6 = Eigen::Matrix<double, 1, 6>;
using Rows36 = Eigen::Matrix<double, 3, 6>;

inline bool is_range(ObservableType t) {
  return t == ObservableType::one_way_range || t == ObservableType::two_way_range;
}
inline bool is_range_rate(ObservableType t) {
  return t == ObservableType::one_way_range_rate || t == ObservableType::two_way_range_rate;
}
inline bool is_two_way(ObservableType t) {
  return t == ObservableType::two_way_range || t == ObservableType::two_way_range_rate;
}
inline double wrap_2pi(double a) { return a < 0.0 ? a + kTwoPi : a; }
inline double wrap_pi(double a) {
  if (a > 0.5 * kTwoPi) return a - kTwoPi;
  if (a < -0.5 * kTwoPi) return a + kTwoPi;
  return a;
}

// Angle pair (longitude-like, latitude-like) of e = (x, y, z) with its 2 x 3 gradient:
// lon = atan2(y, x) in [0, 2 pi), lat = atan2(z, sqrt(x^2 + y^2)). Returns false at a pole.
inline bool angle_pair(const Vec3& e, double& lon, double& lat, Eigen::Matrix<double, 2, 3>& g) {
  const double h2 = e(0) * e(0) + e(1) * e(1);
  const double h = std::sqrt(h2);
  const double n2 = h2 + e(2) * e(2);
  if (!(h > 1e-12 * std::sqrt(n2))) return false;
  lon = wrap_2pi(std::atan2(e(1), e(0)));
  lat = std::atan2(e(2), h);
  g.row(0) = Row3(-e(1), e(0), 0.0) / h2;
  g.row(1) = Row3(-e(0) * e(2), -e(1) * e(2), h2) / (n2 * h);
  return true;
}
// Tropospheric delay of the run's model at a station: zenith delay (km) times the mapping at an
// elevation, with d delay / d elevation.
struct Troposphere {
  TroposphereModel model = TroposphereModel::saastamoinen;
  double zenith = 0.0;  // km
  double latitude = 0.0, height = 0.0, wavelength = 0.532;
  Weather weather;
  Troposphere(const MeasurementSettings& s, const StationEphemeris& station) noexcept
      : model(s.troposphere_model),
        latitude(station.latitude()),
        height(station.height()),
        wavelength(s.wavelength_um),
        weather(standard_atmosphere(height, s.relative_humidity)) {
    switch (model) {
      case TroposphereModel::mendes_pavlis:
        zenith = mendes_pavlis_zenith_delay(weather, latitude, height, wavelength).total();
        break;
      case TroposphereModel::marini_murray:  // its own water-vapour formula (IERS TN 21)
        weather.water_vapour = marini_murray_water_vapour(weather.temperature, s.relative_humidity);
        break;
      case TroposphereModel::saastamoinen:
        zenith = saastamoinen_zenith_delay(weather, latitude, height);
        break;
    }
  }
  double delay(double el, double* d_del) const noexcept {
    if (model == TroposphereModel::marini_murray)
      return marini_murray_delay(weather, latitude, height, wavelength, el, d_del);
    double dm = 0.0;
    const double m = model == TroposphereModel::mendes_pavlis
                         ? fcul_mapping(el, latitude, height, weather.temperature, &dm)
                         : tropo_mapping(el, &dm);
    if (d_del) *d_del = zenith * dm;
    return zenith * m;
  }
};
}  // namespace

const char* observable_name(ObservableType type) noexcept {
  switch (type) {
    case ObservableType::one_way_range:
      return "one_way_range";
    case ObservableType::two_way_range:
      return "two_way_range";
    case ObservableType::one_way_range_rate:
      return "one_way_range_rate";
    case ObservableType::two_way_range_rate:
      return "two_way_range_rate";
    case ObservableType::azimuth_elevation:
      return "azimuth_elevation";
    case ObservableType::right_ascension_declination:
      return "right_ascension_declination";
  }
  return "unknown";
}

ObservableType parse_observable(const std::string& text) {
  std::string n;
  for (char ch : text) {
    const char c = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    n += (c == '-' || c == ' ') ? '_' : c;
  }
  if (n == "azel") return ObservableType::azimuth_elevation;
  if (n == "radec") return ObservableType::right_ascension_declination;
  for (int i = 0; i <= 5; ++i) {
    const auto t = static_cast<ObservableType>(i);
    if (n == observable_name(t)) return t;
  }
  throw std::invalid_argument("type: unknown observable '" + text +
                              "' (hint: one of one_way_range, two_way_range, one_way_range_rate, "
                              "two_way_range_rate, azimuth_elevation, right_ascension_declination)");
}

int observable_size(ObservableType type) noexcept {
  return (type == ObservableType::azimuth_elevation || type == ObservableType::right_ascension_declination)
             ? 2
             : 1;
}

void MeasurementSettings::validate() const {
  const int t = static_cast<int>(type);
  core::require(t >= 0 && t <= 5, "type", "unknown observable");
  light_time.validate();
  const bool delayed = is_range(type) || is_range_rate(type);
  core::require(!(troposphere && !delayed), "troposphere",
                "applies to range observables only (range: the delay; range-rate: its rate), not " +
                    std::string(observable_name(type)));
  core::require(!(shapiro && !delayed), "shapiro",
                "applies to range observables only (range: the delay; range-rate: its rate), not " +
                    std::string(observable_name(type)));
  validate_troposphere_options(relative_humidity, troposphere_model, wavelength_um);
  core::require_positive(mu, "mu");
  core::require_positive(min_range, "min_range");
}

MeasurementModel::MeasurementModel(const MeasurementSettings& settings) : settings_(settings) {
  settings_.validate();
}

void MeasurementModel::predict(const StationEphemeris& station, double t, const Vec6& x, const Biases& bias,
                               Prediction& out) const noexcept {
  evaluate(station, t, x, bias, out, true);
  if (out.status != ObservationStatus::success && out.status != ObservationStatus::no_convergence) return;
  if (!settings_.time_bias_partials || is_range(settings_.type)) return;
  // d value / d time bias of the rate and angle observables: central difference over +-1 ms
  // (truncation ~h^2/6 |h'''| < 1e-10 relative on a LEO pass; rounding ~1e-13).
  constexpr double h = 1e-3;
  Prediction plus, minus;
  Biases b = bias;
  b.time = bias.time + h;
  evaluate(station, t, x, b, plus, false);
  b.time = bias.time - h;
  evaluate(station, t, x, b, minus, false);
  const bool angles = observable_size(settings_.type) == 2;
  for (int i = 0; i < out.size; ++i) {
    double diff = plus.value(i) - minus.value(i);
    if (angles && i == 0) diff = wrap_pi(diff);
    out.dbias(i, 1) = diff / (2.0 * h);
  }
}

void MeasurementModel::evaluate(const StationEphemeris& station, double t, const Vec6& x, const Biases& bias,
                                Prediction& out, bool want) const noexcept {
  const MeasurementSettings& s = settings_;
  const ObservableType type = s.type;
  out = Prediction{};
  out.size = observable_size(type);
  if (!x.allFinite() || !std::isfinite(t) || !std::isfinite(bias.range) || !std::isfinite(bias.time) ||
      !(x.head<3>().squaredNorm() > 0.0)) {
    out.status = ObservationStatus::invalid_input;
    return;
  }
  // True reception t + dt and the state there.
  const bool shifted = bias.time != 0.0;
  Vec6 xs = x;
  Mat6 Jshift;
  if (shifted) shift_state(x, bias.time, s.mu, xs, want ? &Jshift : nullptr);
  const double tr = t + bias.time;
  StationState sr;
  station.state(tr, sr);
  if (!sr.r.allFinite() || !sr.v.allFinite() || !sr.a.allFinite() || !sr.enu.allFinite()) {
    out.status = ObservationStatus::invalid_input;
    return;
  }
  // Down leg and the bounce state.
  const LightTimeLeg down = solve_down_leg(xs, sr.r, s.mu, s.light_time);
  bool converged = down.converged;
  out.tau_down = down.tau;
  out.iterations = down.iterations;
  Vec6 xb;
  Mat6 Jb;
  Vec6 xb_dt;
  shift_state(xs, -down.tau, s.mu, xb, &Jb, &xb_dt);
  const Vec3 rb = xb.head<3>();
  const Vec3 vb = xb.tail<3>();
  const Vec3 dd = rb - sr.r;
  const double rho_d = dd.norm();
  if (!(rho_d >= s.min_range)) {
    out.status = ObservationStatus::degenerate_geometry;
    return;
  }
  const Vec3 ud = dd / rho_d;
  const double den_d = kC + ud.dot(vb);
  const Row6 dtd = ud.transpose() * Jb.topRows<3>() / den_d;  // d tau_d / d xs
  const Mat6 Dxb = Jb - xb_dt * dtd;                          // d x_bounce / d xs (through tau_d too)
  const Rows36 Dr = Dxb.topRows<3>();
  const Rows36 Dv = Dxb.bottomRows<3>();
  const double taud_dot = ud.dot(vb - sr.v) / den_d;  // d tau_d / d t_r along the motion

  // Up leg.
  StationState st;
  Row6 dtu = Row6::Zero();
  Vec3 uu = Vec3::Zero();
  double rho_u = 0.0, tauu_dot = 0.0;
  if (is_two_way(type)) {
    const LightTimeLeg up = solve_up_leg(rb, station, tr - down.tau, down.tau, s.light_time, st);
    converged = converged && up.converged;
    out.tau_up = up.tau;
    out.iterations += up.iterations;
    const Vec3 du = rb - st.r;
    rho_u = du.norm();
    if (!(rho_u >= s.min_range) || !st.r.allFinite() || !st.v.allFinite() || !st.a.allFinite()) {
      out.status =
          !(rho_u >= s.min_range) ? ObservationStatus::degenerate_geometry : ObservationStatus::invalid_input;
      return;
    }
    uu = du / rho_u;
    const double den_u = kC - uu.dot(st.v);
    dtu = (uu.transpose() * Dr + uu.dot(st.v) * dtd) / den_u;
    tauu_dot = uu.dot(vb - st.v) * (1.0 - taud_dot) / den_u;
  }

  Eigen::Matrix<double, 2, 6> H = Eigen::Matrix<double, 2, 6>::Zero();  // d value / d xs
  switch (type) {
    case ObservableType::one_way_range:
      out.value(0) = kC * down.tau;
      H.row(0) = kC * dtd;
      out.dbias(0, 1) = kC * taud_dot;
      break;
    case ObservableType::two_way_range:
      out.value(0) = 0.5 * kC * (down.tau + out.tau_up);
      H.row(0) = 0.5 * kC * (dtd + dtu);
      out.dbias(0, 1) = 0.5 * kC * (taud_dot + tauu_dot);
      break;
    case ObservableType::one_way_range_rate:
    case ObservableType::two_way_range_rate: {
      const Vec3 wd = vb - sr.v;
      const double qd = ud.dot(wd);
      const Row6 gd = ((wd - qd * ud).transpose() / rho_d) * Dr + ud.transpose() * Dv;
      if (type == ObservableType::one_way_range_rate) {
        out.value(0) = qd;
        H.row(0) = gd;
        break;
      }
      const Vec3 wu = vb - st.v;
      const double qu = uu.dot(wu);
      const Row6 dT = dtd + dtu;
      const Rows36 Ddu = Dr + st.v * dT;
      const Rows36 Dwu = Dv + st.a * dT;
      const Row6 gu = ((wu - qu * uu).transpose() / rho_u) * Ddu + uu.transpose() * Dwu;
      out.value(0) = 0.5 * (qd + qu);
      H.row(0) = 0.5 * (gd + gu);
      break;
    }
    case ObservableType::azimuth_elevation:
    case ObservableType::right_ascension_declination: {
      const bool azel = type == ObservableType::azimuth_elevation;
      Eigen::Matrix<double, 2, 3> g;
      double lon = 0.0, lat = 0.0;
      // azimuth = atan2(E, N): the pair (N, E, U) gives lon = atan2(E, N), lat = elevation.
      const Vec3 e = azel ? Vec3(sr.enu.row(1).dot(dd), sr.enu.row(0).dot(dd), sr.enu.row(2).dot(dd)) : dd;
      if (!angle_pair(e, lon, lat, g)) {
        out.status = ObservationStatus::degenerate_geometry;
        return;
      }
      out.value << lon, lat;
      if (azel) {
        Mat3 M;
        M.row(0) = sr.enu.row(1);
        M.row(1) = sr.enu.row(0);
        M.row(2) = sr.enu.row(2);
        H = g * M * Dr;
      } else {
        H = g * Dr;
      }
      break;
    }
  }

  if (is_range(type)) {
    if (s.troposphere) {
      const Vec3 e(sr.enu.row(1).dot(dd), sr.enu.row(0).dot(dd), sr.enu.row(2).dot(dd));
      Eigen::Matrix<double, 2, 3> g;
      double az = 0.0, el = 0.0;
      const Troposphere tropo(s, station);
      if (angle_pair(e, az, el, g)) {
        Mat3 M;
        M.row(0) = sr.enu.row(1);
        M.row(1) = sr.enu.row(0);
        M.row(2) = sr.enu.row(2);
        double dd_del = 0.0;
        out.troposphere = tropo.delay(el, &dd_del);
        H.row(0) += dd_del * (g.row(1) * M * Dr);
      } else {
        out.troposphere = tropo.delay(0.25 * kTwoPi, nullptr);
      }
    }
    if (s.shapiro) {
      const double r1 = sr.r.norm(), r2 = rb.norm();
      double dsum = 0.0, drho = 0.0;
      out.shapiro = shapiro_delay(r1, r2, rho_d, s.mu, &dsum, &drho);
      H.row(0) += (dsum * (rb / r2).transpose() + drho * ud.transpose()) * Dr;
    }
    out.value(0) += out.troposphere + out.shapiro + bias.range;
    out.dbias(0, 0) = 1.0;
    if (!s.time_bias_partials) out.dbias(0, 1) = 0.0;
  }
  if (is_range_rate(type) && (s.troposphere || s.shapiro)) {
    // Range-rate modifiers: the rate of the delays along the down-leg geometry, a central difference
    // over +-h of the delay at reception t_r +- h with the bounce state two-body-shifted by +-h (the
    // rate of the light time itself, 2e-5 relative, is left out). Both legs of a two-way measurement
    // carry the same delay, so the mean of the legs carries its rate once. h = 0.1 s: truncation
    // (h / T)^2 / 6 < 2e-6 relative for the fastest change of a LEO pass (T ~ 30 s at 5 deg elevation).
    constexpr double h = 0.1;
    const Troposphere tropo(s, station);
    double delay[2] = {0.0, 0.0}, shap[2] = {0.0, 0.0};
    Row6 g_tropo[2] = {Row6::Zero(), Row6::Zero()}, g_shap[2] = {Row6::Zero(), Row6::Zero()};
    for (int k = 0; k < 2; ++k) {
      const double dt = k == 0 ? h : -h;
      Vec6 xh;
      Mat6 Jh;
      shift_state(xb, dt, s.mu, xh, &Jh);
      StationState sh;
      station.state(tr + dt, sh);
      const Vec3 rh = xh.head<3>();
      const Vec3 dh = rh - sh.r;
      if (s.troposphere) {
        Mat3 M;
        M.row(0) = sh.enu.row(1);
        M.row(1) = sh.enu.row(0);
        M.row(2) = sh.enu.row(2);
        Eigen::Matrix<double, 2, 3> g;
        double az = 0.0, el = 0.0;
        if (angle_pair(M * dh, az, el, g)) {
          double dd_del = 0.0;
          delay[k] = tropo.delay(el, &dd_del);
          if (want) g_tropo[k] = dd_del * (g.row(1) * M * Jh.topRows<3>());
        } else {
          delay[k] = tropo.delay(0.25 * kTwoPi, nullptr);
        }
      }
      if (s.shapiro) {
        const double r1 = sh.r.norm(), r2 = rh.norm(), rho = dh.norm();
        double dsum = 0.0, drho = 0.0;
        shap[k] = shapiro_delay(r1, r2, rho, s.mu, &dsum, &drho);
        if (want && rho > 0.0)
          g_shap[k] = (dsum * (rh / r2).transpose() + drho * (dh / rho).transpose()) * Jh.topRows<3>();
      }
    }
    out.troposphere = (delay[0] - delay[1]) / (2.0 * h);  // km/s for a range-rate
    out.shapiro = (shap[0] - shap[1]) / (2.0 * h);
    out.value(0) += out.troposphere + out.shapiro;
    if (want) H.row(0) += ((g_tropo[0] - g_tropo[1] + g_shap[0] - g_shap[1]) / (2.0 * h)) * Dxb;
  }
  if (want) out.dx = shifted ? Eigen::Matrix<double, 2, 6>(H * Jshift) : H;
  out.status = converged ? ObservationStatus::success : ObservationStatus::no_convergence;
}

}  // namespace satgnc::observation
