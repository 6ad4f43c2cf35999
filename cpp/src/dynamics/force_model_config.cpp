// The force-model TOML (issue 14 item 8), read with toml++: schema in force_model_config.hpp.
#include "satgnc/dynamics/force_model_config.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <memory>
#include <sstream>
#include <string>
#include <utility>

#include "satgnc/dynamics/nrlmsise00.hpp"
#include "satgnc/frames/earth_orientation.hpp"
#include "satgnc/frames/earth_rotation.hpp"
#include "satgnc/frames/eop.hpp"

namespace satgnc::dynamics {

namespace {

std::string describe(const std::string& file, int line, const std::string& key, const std::string& rule) {
  std::string s = file;
  if (line > 0) s += ":" + std::to_string(line);
  s += ": ";
  if (!key.empty()) s += key + ": ";
  return s + rule;
}

std::string fmt(double x) {
  std::ostringstream o;
  o.precision(10);
  o << x;
  return o.str();
}

std::string join(std::initializer_list<const char*> names) {
  std::string s;
  for (const char* n : names) s += (s.empty() ? "" : ", ") + std::string(n);
  return s;
}

int line_of(const toml::node& n) { return static_cast<int>(n.source().begin.line); }

const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    default:
      return "a date or time";
  }
}

// One [section] of the file: typed getters that name the file, the line, the section and the key.
class Section {
 public:
  Section(const std::string& file, std::string name, const toml::table* t, int line)
      : file_(file), name_(std::move(name)), t_(t), line_(line) {}

  bool present() const { return t_ != nullptr; }
  int line() const { return line_; }
  std::string key(const std::string& k) const { return "[" + name_ + "] " + k; }

  [[noreturn]] void fail(int line, const std::string& k, const std::string& rule) const {
    throw ForceModelConfigError(file_, line, k.empty() ? "[" + name_ + "]" : key(k), rule);
  }

  void only(std::initializer_list<const char*> known) const {
    if (t_ == nullptr) return;
    for (auto&& [k, v] : *t_) {
      bool ok = false;
      for (const char* n : known) ok = ok || k.str() == n;
      if (!ok)
        throw ForceModelConfigError(file_, static_cast<int>(k.source().begin.line), key(std::string(k.str())),
                                    "unknown key (known in [" + name_ + "]: " + join(known) + ")");
    }
  }

  const toml::node* node(const char* k) const { return t_ == nullptr ? nullptr : t_->get(k); }
  int line_of_key(const char* k) const {
    const toml::node* n = node(k);
    return n != nullptr ? line_of(*n) : line_;
  }

  std::optional<double> number(const char* k) const {
    const toml::node* n = node(k);
    if (n == nullptr) return std::nullopt;
    if (!n->is_number()) fail(line_of(*n), k, std::string("must be a number, got ") + type_name(*n));
    const double x = n->value<double>().value_or(NAN);
    if (!std::isfinite(x)) fail(line_of(*n), k, "must be finite, got " + fmt(x));
    return x;
  }
  double number(const char* k, double def) const { return number(k).value_or(def); }
  double required(const char* k, const char* unit) const {
    const auto x = number(k);
    if (!x) fail(line_, k, std::string("missing (required in [") + name_ + "], " + unit + ")");
    return *x;
  }
  // Range checks on a value that came from key k.
  void check(bool ok, const char* k, const std::string& rule, double x) const {
    if (!ok) fail(line_of_key(k), k, rule + ", got " + fmt(x));
  }

  std::optional<std::string> text(const char* k) const {
    const toml::node* n = node(k);
    if (n == nullptr) return std::nullopt;
    if (!n->is_string()) fail(line_of(*n), k, std::string("must be a string, got ") + type_name(*n));
    return std::string(*n->value<std::string_view>());
  }
  std::string choice(const char* k, const char* def, std::initializer_list<const char*> choices) const {
    const auto s = text(k);
    if (!s) return def;
    for (const char* c : choices)
      if (*s == c) return *s;
    fail(line_of_key(k), k, "unknown value '" + *s + "' (choices: " + join(choices) + ")");
  }

  std::optional<bool> flag(const char* k) const {
    const toml::node* n = node(k);
    if (n == nullptr) return std::nullopt;
    if (!n->is_boolean()) fail(line_of(*n), k, std::string("must be true or false, got ") + type_name(*n));
    return *n->value<bool>();
  }

  std::optional<long long> integer(const char* k) const {
    const toml::node* n = node(k);
    if (n == nullptr) return std::nullopt;
    if (!n->is_integer()) fail(line_of(*n), k, std::string("must be an integer, got ") + type_name(*n));
    return *n->value<long long>();
  }

 private:
  const std::string& file_;
  std::string name_;
  const toml::table* t_;
  int line_;
};

std::string resolve(const std::string& base_dir, const std::string& p) {
  if (p.empty() || p.front() == '/' || base_dir.empty() || base_dir == ".") return p;
  return base_dir + "/" + p;
}

}  // namespace

ForceModelConfigError::ForceModelConfigError(std::string file, int line, std::string key, std::string rule)
    : std::invalid_argument(describe(file, line, key, rule)),
      file_(std::move(file)),
      line_(line),
      key_(std::move(key)),
      rule_(std::move(rule)) {}

ForceModelConfig parse_force_model_config(std::string_view text, const std::string& source,
                                          const std::string& base_dir, const std::string& egm2008_path) {
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw ForceModelConfigError(source, static_cast<int>(e.source().begin.line), "",
                                "TOML syntax: " + std::string(e.description()));
  }
  static constexpr std::initializer_list<const char*> kSections = {
      "central_body", "epoch", "earth_orientation", "gravity", "third_body", "srp", "drag", "space_weather"};
  for (auto&& [k, v] : root) {
    bool ok = false;
    for (const char* n : kSections) ok = ok || k.str() == n;
    const int line = static_cast<int>(k.source().begin.line);
    if (!v.is_table())
      throw ForceModelConfigError(source, line, std::string(k.str()),
                                  "must be a [section] (a table), got " + std::string(type_name(v)) +
                                      " (every setting belongs to a section)");
    if (!ok)
      throw ForceModelConfigError(source, line, "[" + std::string(k.str()) + "]",
                                  "unknown section (known: " + join(kSections) + ")");
  }
  auto section = [&](const char* name) {
    const toml::table* t = root.get_as<toml::table>(name);
    return Section(source, name, t, t != nullptr ? static_cast<int>(t->source().begin.line) : 0);
  };

  ForceModelConfig cfg;
  cfg.source = source;

  // [central_body]
  const Section cb = section("central_body");
  cb.only({"mu", "radius"});
  const std::optional<double> mu_given = cb.number("mu");
  if (mu_given) cb.check(*mu_given > 0.0, "mu", "must be > 0 km^3/s^2", *mu_given);
  const double radius = cb.number("radius", core::earth::radius);
  cb.check(radius > 0.0, "radius", "must be > 0 km", radius);

  // [epoch]
  const Section ep = section("epoch");
  ep.only({"time", "scale"});
  if (ep.present()) {
    const auto t = ep.text("time");
    if (!t) ep.fail(ep.line(), "time", "missing (an ISO 8601 date, e.g. \"2024-03-20T12:00:00\")");
    const std::string scale = ep.choice("scale", "utc", {"utc", "tai", "tt", "gps", "tdb"});
    try {
      cfg.epoch = core::Epoch::parse(*t, core::time_scale_from_name(scale));
    } catch (const std::invalid_argument& e) {
      ep.fail(ep.line_of_key("time"), "time", e.what());
    }
  }

  // [earth_orientation]
  const Section eo = section("earth_orientation");
  eo.only({"model", "eop", "days", "theta0_deg"});
  cfg.earth_orientation = eo.choice("model", "uniform", {"uniform", "iau2006"});
  std::shared_ptr<const frames::EarthRotationModel> rotation;
  if (cfg.earth_orientation == "uniform") {
    if (eo.node("eop") != nullptr) eo.fail(eo.line_of_key("eop"), "eop", "only with model = \"iau2006\"");
    const double theta0 = eo.number("theta0_deg", 0.0);
    rotation = std::make_shared<frames::UniformRotation>(theta0 * M_PI / 180.0, core::earth::omega);
  } else {
    if (eo.node("theta0_deg") != nullptr)
      eo.fail(eo.line_of_key("theta0_deg"), "theta0_deg", "only with model = \"uniform\"");
    if (!cfg.epoch) eo.fail(eo.line_of_key("model"), "model", "\"iau2006\" needs an [epoch] section");
    const auto eop = eo.text("eop");
    if (!eop) eo.fail(eo.line(), "eop", "missing (an IERS finals2000A or C04 file; model \"iau2006\")");
    const double days = eo.number("days", 7.0);
    eo.check(days > 0.0 && days <= 3660.0, "days", "must be in (0, 3660] days", days);
    cfg.eop_file = resolve(base_dir, *eop);
    try {
      const frames::EopTable table = frames::EopTable::read(cfg.eop_file);
      rotation = std::make_shared<frames::IauEarthRotation>(*cfg.epoch, table, -86400.0, days * 86400.0);
    } catch (const std::invalid_argument& e) {
      eo.fail(eo.line_of_key("eop"), "eop", e.what());
    } catch (const std::runtime_error& e) {
      eo.fail(eo.line_of_key("eop"), "eop", e.what());
    }
  }

  ForceModel& fm = cfg.model;
  // [gravity]
  const Section gr = section("gravity");
  gr.only({"model", "file", "degree", "order", "j2"});
  cfg.gravity_model = gr.choice("model", "point_mass", {"point_mass", "j2", "egm2008", "file"});
  const bool field = cfg.gravity_model == "egm2008" || cfg.gravity_model == "file";
  for (const char* k : {"degree", "order"})
    if (!field && gr.node(k) != nullptr)
      gr.fail(gr.line_of_key(k), k, "only with model = \"egm2008\" or \"file\"");
  if (cfg.gravity_model != "j2" && gr.node("j2") != nullptr)
    gr.fail(gr.line_of_key("j2"), "j2", "only with model = \"j2\"");
  if (cfg.gravity_model != "file" && gr.node("file") != nullptr)
    gr.fail(gr.line_of_key("file"), "file", "only with model = \"file\"");
  double mu = mu_given.value_or(core::earth::mu);
  if (field) {
    const long long degree = gr.integer("degree").value_or(20);
    gr.check(degree >= 2 && degree <= 360, "degree", "must be in [2, 360]", static_cast<double>(degree));
    const long long order = gr.integer("order").value_or(degree);
    gr.check(order >= 0 && order <= degree, "order", "must be in [0, degree]", static_cast<double>(order));
    if (cfg.gravity_model == "file") {
      const auto f = gr.text("file");
      if (!f) gr.fail(gr.line(), "file", "missing (an ICGEM .gfc path; model \"file\")");
      cfg.gravity_file = resolve(base_dir, *f);
    } else {
      if (egm2008_path.empty())
        gr.fail(gr.line_of_key("model"), "model",
                "\"egm2008\" needs the path of the shipped file: pass egm2008_path (Python: "
                "satgnc.dynamics.EGM2008_PATH) or use model = \"file\"");
      cfg.gravity_file = egm2008_path;
    }
    std::shared_ptr<const GravityCoefficients> coef;
    try {
      coef =
          std::make_shared<const GravityCoefficients>(load_gfc(cfg.gravity_file, static_cast<int>(degree)));
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      const char* k = what.find("max_degree") != std::string::npos ? "degree" : "file";
      gr.fail(gr.line_of_key(cfg.gravity_model == "file" ? k : "degree"), k, what);
    }
    if (!mu_given) mu = coef->mu;
    fm.gravity.emplace(coef, static_cast<int>(degree), static_cast<int>(order), rotation);
  } else if (cfg.gravity_model == "j2") {
    const double j2 = gr.number("j2", core::earth::j2);
    gr.check(std::abs(j2) < 1.0, "j2", "must be in (-1, 1)", j2);
    fm.j2 = J2Gravity{mu, j2, radius};
  }
  fm.mu = mu;

  // [third_body]
  const Section tb = section("third_body");
  tb.only({"sun", "moon", "ephemeris"});
  if (tb.present()) {
    ThirdBodies t;
    t.sun = tb.flag("sun").value_or(true);
    t.moon = tb.flag("moon").value_or(true);
    if (t.sun || t.moon) fm.third_body = t;
    // A JPL DE file (SPK .bsp) replaces ERFA's Sun and Moon for the third bodies, SRP and drag.
    const auto eph = tb.text("ephemeris");
    if (eph && *eph != "erfa") {
      const int line = tb.line_of_key("ephemeris");
      if (eph->empty())
        tb.fail(line, "ephemeris", "must be \"erfa\" or the path of a JPL DE .bsp file, got \"\"");
      cfg.ephemeris_file = resolve(base_dir, *eph);
      try {
        fm.ephemeris = EphemerisInterpolator(std::make_shared<const SpkEphemeris>(cfg.ephemeris_file));
      } catch (const std::invalid_argument& e) {
        tb.fail(line, "ephemeris", e.what());
      }
      const core::JulianDate jd =
          cfg.epoch ? cfg.epoch->jd(core::TimeScale::tt) : core::JulianDate{2451545.0, 0.0};
      const double et = fm.ephemeris.tdb_seconds(jd.jd1, jd.jd2);
      const SpkEphemeris& spk = *fm.ephemeris.spk();
      if (!spk.covers(et))
        tb.fail(line, "ephemeris",
                "the epoch " + format_tdb_seconds(et) + " is outside " + cfg.ephemeris_file + "'s coverage " +
                    format_tdb_seconds(spk.start_et()) + " to " + format_tdb_seconds(spk.end_et()));
    }
  }

  // [srp]
  const Section sr = section("srp");
  sr.only({"area", "mass", "cr", "shadow"});
  if (sr.present()) {
    SolarRadiationPressure s;
    s.area = sr.required("area", "m^2");
    sr.check(s.area >= 0.0, "area", "must be >= 0 m^2", s.area);
    s.mass = sr.required("mass", "kg");
    sr.check(s.mass > 0.0, "mass", "must be > 0 kg", s.mass);
    s.cr = sr.number("cr", 1.3);
    sr.check(s.cr >= 0.0 && s.cr <= 3.0, "cr", "must be in [0, 3]", s.cr);
    const std::string sh = sr.choice("shadow", "conical", {"conical", "cylindrical", "none"});
    s.shadow = sh == "conical"       ? ShadowModel::conical
               : sh == "cylindrical" ? ShadowModel::cylindrical
                                     : ShadowModel::none;
    s.occulting_radius = radius;
    fm.srp = s;
  }

  // [drag]
  const Section dr = section("drag");
  dr.only({"area", "mass", "cd", "atmosphere", "rho0", "h0", "scale_height", "hp_n", "hp_lag_deg"});
  if (dr.present()) {
    const double area = dr.required("area", "m^2");
    dr.check(area >= 0.0, "area", "must be >= 0 m^2", area);
    const double mass = dr.required("mass", "kg");
    dr.check(mass > 0.0, "mass", "must be > 0 kg", mass);
    const double cd = dr.number("cd", 2.2);
    dr.check(cd >= 0.0 && cd <= 10.0, "cd", "must be in [0, 10]", cd);
    cfg.atmosphere =
        dr.choice("atmosphere", "harris_priester", {"harris_priester", "exponential", "nrlmsise00"});
    const bool expo = cfg.atmosphere == "exponential";
    const bool msis = cfg.atmosphere == "nrlmsise00";
    for (const char* k : {"rho0", "h0", "scale_height"})
      if (!expo && dr.node(k) != nullptr)
        dr.fail(dr.line_of_key(k), k, "only with atmosphere = \"exponential\"");
    for (const char* k : {"hp_n", "hp_lag_deg"})
      if (cfg.atmosphere != "harris_priester" && dr.node(k) != nullptr)
        dr.fail(dr.line_of_key(k), k, "only with atmosphere = \"harris_priester\"");
    if (msis) {
      // Built after [space_weather] is read (below): the model holds the space weather and epoch.
      AtmosphereDrag a;
      a.earth_rotation = rotation;
      a.cd = cd;
      a.area = area;
      a.mass = mass;
      fm.atmosphere_drag = a;
    } else if (expo) {
      ExponentialDrag d;
      d.rho0 = dr.required("rho0", "kg/m^3");
      dr.check(d.rho0 > 0.0, "rho0", "must be > 0 kg/m^3", d.rho0);
      d.h0 = dr.required("h0", "km");
      dr.check(d.h0 >= 0.0, "h0", "must be >= 0 km", d.h0);
      d.scale_height = dr.required("scale_height", "km");
      dr.check(d.scale_height > 0.0, "scale_height", "must be > 0 km", d.scale_height);
      d.body_radius = radius;
      d.cd = cd;
      d.area = area;
      d.mass = mass;
      fm.drag = d;
    } else {
      const double n = dr.number("hp_n", 2.0);
      dr.check(n >= 2.0 && n <= 6.0, "hp_n", "must be in [2, 6]", n);
      const double lag = dr.number("hp_lag_deg", 30.0);
      dr.check(lag >= 0.0 && lag <= 180.0, "hp_lag_deg", "must be in [0, 180] deg", lag);
      AtmosphereDrag a;
      a.atmosphere = std::make_shared<HarrisPriester>(n, lag * M_PI / 180.0);
      a.earth_rotation = rotation;
      a.cd = cd;
      a.area = area;
      a.mass = mass;
      fm.atmosphere_drag = a;
    }
  }

  // [space_weather]
  const Section sw = section("space_weather");
  sw.only({"f107", "f107a", "ap"});
  cfg.space_weather.f107 = sw.number("f107", cfg.space_weather.f107);
  sw.check(cfg.space_weather.f107 >= 0.0 && cfg.space_weather.f107 <= SpaceWeather::max_f107, "f107",
           "must be in [0, 400] sfu", cfg.space_weather.f107);
  cfg.space_weather.f107a = sw.number("f107a", cfg.space_weather.f107a);
  sw.check(cfg.space_weather.f107a >= 0.0 && cfg.space_weather.f107a <= SpaceWeather::max_f107, "f107a",
           "must be in [0, 400] sfu", cfg.space_weather.f107a);
  cfg.space_weather.ap = sw.number("ap", cfg.space_weather.ap);
  sw.check(cfg.space_weather.ap >= 0.0 && cfg.space_weather.ap <= SpaceWeather::max_ap, "ap",
           "must be in [0, 400]", cfg.space_weather.ap);

  if (cfg.atmosphere == "nrlmsise00") {
    // NRLMSISE-00 takes its day of year and UT from the epoch of t = 0 (TT two-part JD) and the
    // space weather of [space_weather]; the ForceModel epoch alone does not reach it.
    Nrlmsise00Settings ms;
    ms.space_weather = cfg.space_weather;
    if (cfg.epoch) {
      const core::JulianDate jd = cfg.epoch->jd(core::TimeScale::tt);
      ms.epoch_jd1 = jd.jd1;
      ms.epoch_jd2 = jd.jd2;
    }
    fm.atmosphere_drag->atmosphere = std::make_shared<Nrlmsise00>(ms);
  }

  cfg.radius = radius;
  if (cfg.epoch) fm.set_epoch(*cfg.epoch);
  try {
    fm.validate();
  } catch (const std::invalid_argument& e) {
    throw ForceModelConfigError(source, 0, "",
                                std::string("the force model it describes is invalid: ") + e.what());
  }
  return cfg;
}

ForceModelConfig load_force_model_config(const std::string& path, const std::string& egm2008_path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ForceModelConfigError(path, 0, "", "cannot open the file");
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::size_t slash = path.find_last_of('/');
  const std::string base = slash == std::string::npos ? "." : path.substr(0, slash);
  return parse_force_model_config(ss.str(), path, base, egm2008_path);
}

TwoSatelliteParams two_satellite_params(const ForceModelConfig& config, const TwoSatelliteParams& base) {
  const ForceModel& fm = config.model;
  auto refuse = [&](bool has, const char* section, const char* what) {
    if (has)
      throw ForceModelConfigError(config.source, 0, section,
                                  std::string("the two-satellite truth model has no ") + what +
                                      " (it takes point_mass or j2 gravity and exponential drag)");
  };
  refuse(fm.gravity.has_value(), "[gravity]", "spherical-harmonic field");
  refuse(fm.third_body.has_value(), "[third_body]", "Sun or Moon");
  refuse(fm.srp.has_value(), "[srp]", "solar radiation pressure");
  refuse(fm.atmosphere_drag.has_value(), "[drag] atmosphere",
         "Harris-Priester density (use \"exponential\")");
  TwoSatelliteParams p = base;
  p.mu = fm.mu * 1e9;
  p.j2_on = fm.j2.has_value();
  if (fm.j2) p.j2 = fm.j2->j2;
  p.j2_radius = config.radius * 1e3;
  p.drag_on = fm.drag.has_value();
  if (fm.drag) {
    const ExponentialDrag& d = *fm.drag;
    p.rho0 = d.rho0 * std::exp(d.h0 / d.scale_height);
    p.density_decay = 1.0 / (d.scale_height * 1e3);
    p.density_radius = d.body_radius * 1e3;
    p.omega = d.omega;
    p.cd_chaser = p.cd_target = d.cd;
    p.area_chaser = p.area_target = d.area;
    p.mass_chaser = p.mass_target = d.mass;
  }
  p.validate();
  return p;
}

ForceModel load_force_model(const std::string& path, const std::string& egm2008_path) {
  return load_force_model_config(path, egm2008_path).model;
}

}  // namespace satgnc::dynamics
