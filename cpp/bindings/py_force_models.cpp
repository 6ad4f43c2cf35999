// pybind11 wrappers of the precise force models (issue 14 items 1-3, 5): Earth rotation models,
// gravity-field coefficients and the ICGEM reader, GravityField, ThirdBodies, SolarRadiationPressure,
// and their ForceModel fields. Registered after init_dynamics (ForceModel exists by then).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <typeinfo>

#include "checks.hpp"
#include "satgnc/dynamics/ephemeris_spk.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/dynamics/gravity_field.hpp"
#include "satgnc/dynamics/srp.hpp"
#include "satgnc/dynamics/third_body.hpp"
#include "satgnc/frames/earth_rotation.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {
namespace dy = satgnc::dynamics;
namespace fr = satgnc::frames;

// ValueError unless 0 <= m <= n <= max_degree (the index range of cnm / snm).
void check_degree_order(const dy::GravityCoefficients& g, int n, int m) {
  if (n < 0 || n > g.max_degree || m < 0 || m > n)
    throw py::value_error("n, m: need 0 <= m <= n <= max_degree = " + std::to_string(g.max_degree));
}

dy::ShadowModel shadow_of(const std::string& s) {
  if (s == "none") return dy::ShadowModel::none;
  if (s == "cylindrical") return dy::ShadowModel::cylindrical;
  if (s == "conical") return dy::ShadowModel::conical;
  throw std::invalid_argument("shadow: must be 'none', 'cylindrical' or 'conical', got '" + s + "'");
}

std::string shadow_name(dy::ShadowModel s) {
  switch (s) {
    case dy::ShadowModel::none:
      return "none";
    case dy::ShadowModel::cylindrical:
      return "cylindrical";
    case dy::ShadowModel::conical:
      return "conical";
  }
  return "?";
}

dy::ForceParameter parameter_of(const std::string& s) {
  if (s == "mu") return dy::ForceParameter::mu;
  if (s == "cr") return dy::ForceParameter::cr;
  if (s == "cd") return dy::ForceParameter::cd;
  throw std::invalid_argument("parameter: must be 'mu', 'cr' or 'cd', got '" + s + "'");
}

}  // namespace

/// EarthRotationModel and UniformRotation (called by init_frames before IauEarthRotation, and again
/// by init_force_models: the second call finds them registered).
void init_earth_rotation_models(py::module_& m) {
  // The frames room's interface; another room's bindings may register it first (then reuse it).
  if (py::detail::get_type_info(typeid(fr::EarthRotationModel)) == nullptr) {
    py::class_<fr::EarthRotationModel, std::shared_ptr<fr::EarthRotationModel>>(
        m, "EarthRotationModel", "Orientation of ITRF with respect to GCRF at t seconds after the epoch.")
        .def(
            "rotation",
            [](const fr::EarthRotationModel& r, double t) {
              Mat3 R;
              Vec3 w;
              r.rotation(t, R, w);
              return py::make_tuple(R, w);
            },
            py::arg("t"), "(gcrf_to_itrf 3x3, omega rad/s in GCRF) at t s after the epoch.");
  }
  if (py::detail::get_type_info(typeid(fr::UniformRotation)) == nullptr) {
    py::class_<fr::UniformRotation, fr::EarthRotationModel, std::shared_ptr<fr::UniformRotation>>(
        m, "UniformRotation",
        "Rotation about the inertial z axis by theta0 + omega t (rad; omega rad/s): the paper's / GMST-only "
        "Earth rotation. UniformRotation(0, 0) is the identity (ITRF = GCRF).")
        .def(py::init<double, double>(), py::arg("theta0") = 0.0, py::arg("omega") = core::earth::omega)
        .def_property_readonly("theta0", &fr::UniformRotation::theta0, "rad")
        .def_property_readonly("omega", &fr::UniformRotation::omega, "rad/s");
  }
}

namespace {

void init_gravity(py::module_& m) {
  py::class_<dy::GravityCoefficients, std::shared_ptr<dy::GravityCoefficients>>(
      m, "GravityCoefficients",
      "Fully normalized spherical-harmonic coefficients (read with load_gfc): mu km^3/s^2, radius km.")
      .def_readonly("name", &dy::GravityCoefficients::name)
      .def_readonly("tide_system", &dy::GravityCoefficients::tide_system)
      .def_readonly("mu", &dy::GravityCoefficients::mu, "GM, km^3/s^2")
      .def_readonly("radius", &dy::GravityCoefficients::radius, "reference radius, km")
      .def_readonly("max_degree", &dy::GravityCoefficients::max_degree)
      .def(
          "cnm",
          [](const dy::GravityCoefficients& g, int n, int mm) {
            check_degree_order(g, n, mm);
            return g.cnm(n, mm);
          },
          py::arg("n"), py::arg("m"), "Fully normalized C_nm.")
      .def(
          "snm",
          [](const dy::GravityCoefficients& g, int n, int mm) {
            check_degree_order(g, n, mm);
            return g.snm(n, mm);
          },
          py::arg("n"), py::arg("m"), "Fully normalized S_nm.")
      .def("__repr__", [](const dy::GravityCoefficients& g) {
        std::ostringstream s;
        s.precision(12);
        s << "GravityCoefficients(name='" << g.name << "', max_degree=" << g.max_degree << ", mu=" << g.mu
          << ", radius=" << g.radius << ")";
        return s.str();
      });
  m.def(
      "load_gfc",
      [](const std::string& path, int max_degree) {
        return std::make_shared<dy::GravityCoefficients>(dy::load_gfc(path, max_degree));
      },
      py::arg("path"), py::arg("max_degree") = -1,
      "Read an ICGEM .gfc file up to max_degree (-1: the file's). ValueError names the file, the line "
      "and the keyword.");

  py::class_<dy::GravityField>(
      m, "GravityField",
      "Spherical-harmonic gravity (degrees 2..degree) evaluated in ITRF: accelerations km/s^2, "
      "gradients 1/s^2, potential km^2/s^2; positions km (GCRF unless the method says ITRF).")
      .def(py::init([](std::shared_ptr<dy::GravityCoefficients> c, int degree, std::optional<int> order,
                       std::shared_ptr<fr::EarthRotationModel> rotation) {
             if (!rotation) rotation = std::make_shared<fr::UniformRotation>();
             return dy::GravityField(std::move(c), degree, order.value_or(degree), std::move(rotation));
           }),
           py::arg("coefficients"), py::arg("degree"), py::arg("order") = py::none(),
           py::arg("rotation") = py::none())
      .def_property_readonly("degree", &dy::GravityField::degree)
      .def_property_readonly("order", &dy::GravityField::order)
      .def_property_readonly("mu", &dy::GravityField::mu, "km^3/s^2")
      .def_property_readonly("radius", &dy::GravityField::radius, "km")
      .def_property_readonly("coefficients",
                             [](const dy::GravityField& f) {
                               return std::const_pointer_cast<dy::GravityCoefficients>(f.coefficients_ptr());
                             })
      .def(
          "acceleration",
          [](const dy::GravityField& f, py::handle r, double t) {
            return f.acceleration(t, checks::eigen_arg<Vec3>(r, "r"));
          },
          py::arg("r"), py::arg("t") = 0.0, "Acceleration km/s^2 (GCRF) at r km (GCRF), t s.")
      .def(
          "jacobian",
          [](const dy::GravityField& f, py::handle r, double t) {
            Vec3 a;
            Mat3 g;
            f.jacobian(t, checks::eigen_arg<Vec3>(r, "r"), a, g);
            return py::make_tuple(a, g);
          },
          py::arg("r"), py::arg("t") = 0.0, "(a km/s^2, da/dr 1/s^2), GCRF.")
      .def(
          "potential",
          [](const dy::GravityField& f, py::handle r, double t) {
            return f.potential(t, checks::eigen_arg<Vec3>(r, "r"));
          },
          py::arg("r"), py::arg("t") = 0.0, "Potential energy per unit mass, km^2/s^2 (a = -grad V).")
      .def(
          "acceleration_fixed",
          [](const dy::GravityField& f, py::handle r) {
            return f.acceleration_fixed(checks::eigen_arg<Vec3>(r, "r"));
          },
          py::arg("r_itrf"), "Acceleration km/s^2 in ITRF at r km (ITRF).")
      .def(
          "gradient_fixed",
          [](const dy::GravityField& f, py::handle r) {
            Vec3 a;
            Mat3 g;
            f.gradient_fixed(checks::eigen_arg<Vec3>(r, "r"), a, g);
            return py::make_tuple(a, g);
          },
          py::arg("r_itrf"), "(a km/s^2, da/dr 1/s^2) in ITRF at r km (ITRF).")
      .def(
          "potential_fixed",
          [](const dy::GravityField& f, py::handle r) {
            return f.potential_fixed(checks::eigen_arg<Vec3>(r, "r"));
          },
          py::arg("r_itrf"), "Potential energy per unit mass km^2/s^2 at r km (ITRF).")
      .def("__repr__", [](const dy::GravityField& f) {
        std::ostringstream s;
        s << "GravityField('" << f.coefficients().name << "', degree=" << f.degree()
          << ", order=" << f.order() << ")";
        return s.str();
      });
}

void init_third_body_srp(py::module_& m) {
  py::class_<dy::ThirdBodies>(m, "ThirdBodies",
                              "Sun and Moon point masses with the indirect term (ERFA ephemerides); "
                              "mu_sun, mu_moon km^3/s^2.")
      .def(py::init([](bool sun, bool moon, double mu_sun, double mu_moon) {
             dy::ThirdBodies t;
             t.sun = sun;
             t.moon = moon;
             t.mu_sun = mu_sun;
             t.mu_moon = mu_moon;
             t.validate();
             return t;
           }),
           py::arg("sun") = true, py::arg("moon") = true, py::arg("mu_sun") = dy::ThirdBodies{}.mu_sun,
           py::arg("mu_moon") = dy::ThirdBodies{}.mu_moon)
      .def_readwrite("sun", &dy::ThirdBodies::sun)
      .def_readwrite("moon", &dy::ThirdBodies::moon)
      .def_readwrite("mu_sun", &dy::ThirdBodies::mu_sun, "km^3/s^2")
      .def_readwrite("mu_moon", &dy::ThirdBodies::mu_moon, "km^3/s^2")
      .def("__repr__", [](const dy::ThirdBodies& t) {
        return std::string("ThirdBodies(sun=") + (t.sun ? "True" : "False") +
               ", moon=" + (t.moon ? "True" : "False") + ")";
      });
  m.def("sun_position", &dy::sun_position, py::arg("jd1"), py::arg("jd2") = 0.0,
        "Geocentric Sun (km, GCRF) at the TT Julian date jd1 + jd2 (ERFA eraEpv00).");
  m.def("moon_position", &dy::moon_position, py::arg("jd1"), py::arg("jd2") = 0.0,
        "Geocentric Moon (km, GCRF) at the TT Julian date jd1 + jd2 (ERFA eraMoon98).");

  py::class_<dy::SolarRadiationPressure>(
      m, "SolarRadiationPressure",
      "Cannonball SRP: area m^2, mass kg, cr, pressure N/m^2 at 1 AU, shadow 'none' | 'cylindrical' | "
      "'conical', radii km.")
      .def(py::init([](double area, double mass, double cr, const std::string& shadow, double pressure) {
             dy::SolarRadiationPressure p;
             p.area = area;
             p.mass = mass;
             p.cr = cr;
             p.shadow = shadow_of(shadow);
             p.pressure = pressure;
             p.validate();
             return p;
           }),
           py::arg("area") = 1.0, py::arg("mass") = 1.0, py::arg("cr") = 1.3, py::arg("shadow") = "conical",
           py::arg("pressure") = 4.56e-6)
      .def_readwrite("area", &dy::SolarRadiationPressure::area, "m^2")
      .def_readwrite("mass", &dy::SolarRadiationPressure::mass, "kg")
      .def_readwrite("cr", &dy::SolarRadiationPressure::cr)
      .def_readwrite("pressure", &dy::SolarRadiationPressure::pressure, "N/m^2 at 1 AU")
      .def_readwrite("occulting_radius", &dy::SolarRadiationPressure::occulting_radius, "km")
      .def_readwrite("sun_radius", &dy::SolarRadiationPressure::sun_radius, "km")
      .def_property(
          "shadow", [](const dy::SolarRadiationPressure& p) { return shadow_name(p.shadow); },
          [](dy::SolarRadiationPressure& p, const std::string& s) { p.shadow = shadow_of(s); })
      .def(
          "shadow_fraction",
          [](const dy::SolarRadiationPressure& p, py::handle sun, py::handle r) {
            return dy::srp_shadow(p, checks::eigen_arg<Vec3>(sun, "sun"), checks::eigen_arg<Vec3>(r, "r"));
          },
          py::arg("sun"), py::arg("r"), "Lit fraction of the Sun's disc in [0, 1]; sun, r geocentric km.")
      .def(
          "acceleration",
          [](const dy::SolarRadiationPressure& p, py::handle sun, py::handle r) {
            return dy::srp_acceleration(p, checks::eigen_arg<Vec3>(sun, "sun"),
                                        checks::eigen_arg<Vec3>(r, "r"));
          },
          py::arg("sun"), py::arg("r"), "SRP acceleration km/s^2; sun, r geocentric km.")
      .def("__repr__", [](const dy::SolarRadiationPressure& p) {
        std::ostringstream s;
        s.precision(12);
        s << "SolarRadiationPressure(area=" << p.area << ", mass=" << p.mass << ", cr=" << p.cr
          << ", shadow='" << shadow_name(p.shadow) << "')";
        return s.str();
      });
}

void init_spk_ephemeris(py::module_& m) {
  py::class_<dy::SpkEphemeris, std::shared_ptr<dy::SpkEphemeris>>(
      m, "SpkEphemeris",
      "A JPL DE ephemeris (NAIF SPK .bsp, Chebyshev types 2 and 3) opened for (target, center) pairs of "
      "NAIF codes (10 Sun, 301 Moon, 399 Earth, 3 Earth-Moon barycentre, 0 solar-system barycentre); "
      "epochs TDB s past J2000; km, km/s; J2000 (ICRF) axes.")
      .def(py::init([](const std::string& path, const std::vector<std::pair<int, int>>& pairs) {
             return std::make_shared<dy::SpkEphemeris>(path, pairs);
           }),
           py::arg("path"), py::arg("pairs") = dy::SpkEphemeris::geocentric_sun_moon(),
           py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("path", &dy::SpkEphemeris::path)
      .def_property_readonly("internal_name", &dy::SpkEphemeris::internal_name)
      .def_property_readonly("pairs", &dy::SpkEphemeris::pairs)
      .def_property_readonly("start_et", &dy::SpkEphemeris::start_et, "TDB s past J2000")
      .def_property_readonly("end_et", &dy::SpkEphemeris::end_et, "TDB s past J2000")
      .def_property_readonly(
          "segments",
          [](const dy::SpkEphemeris& e) {
            py::list out;
            for (const dy::SpkSegmentInfo& s : e.segments()) {
              py::dict d;
              d["target"] = s.target;
              d["center"] = s.center;
              d["frame"] = s.frame;
              d["type"] = s.type;
              d["start_et"] = s.start_et;
              d["end_et"] = s.end_et;
              d["name"] = s.name;
              out.append(d);
            }
            return out;
          },
          "Every segment descriptor: dicts with target, center, frame, type, start_et, end_et (TDB s), name.")
      .def(
          "covers",
          [](const dy::SpkEphemeris& e, py::handle et) { return e.covers(checks::real_arg(et, "et")); },
          py::arg("et"))
      .def(
          "position",
          [](const dy::SpkEphemeris& e, int target, int center, py::handle et) {
            try {
              return e.position(target, center, checks::real_arg(et, "et"));
            } catch (const std::out_of_range& ex) {
              throw py::value_error(ex.what());
            }
          },
          py::arg("target"), py::arg("center"), py::arg("et"),
          "Position (km) of target from center at et (TDB s past J2000); ValueError outside the coverage.")
      .def(
          "positions",
          [](const dy::SpkEphemeris& e, int target, int center, py::handle ets) {
            const std::vector<double> t = checks::vector_arg(ets, "ets");
            Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> out(static_cast<Eigen::Index>(t.size()),
                                                                          3);
            std::string error;
            {
              py::gil_scoped_release release;
              try {
                for (std::size_t i = 0; i < t.size(); ++i)
                  out.row(static_cast<Eigen::Index>(i)) = e.position(target, center, t[i]).transpose();
              } catch (const std::exception& ex) {
                error = ex.what();
              }
            }
            if (!error.empty()) throw py::value_error(error);
            return out;
          },
          py::arg("target"), py::arg("center"), py::arg("ets"),
          "Positions (n, 3) km of target from center at the epochs ets (n,) TDB s past J2000 (one C++ loop).")
      .def(
          "state",
          [](const dy::SpkEphemeris& e, int target, int center, py::handle et) {
            Vec3 r, v;
            try {
              e.state(target, center, checks::real_arg(et, "et"), r, v);
            } catch (const std::out_of_range& ex) {
              throw py::value_error(ex.what());
            }
            return py::make_tuple(r, v);
          },
          py::arg("target"), py::arg("center"), py::arg("et"),
          "(position km, velocity km/s) of target from center at et (TDB s past J2000).")
      .def_static("tdb_seconds_from_tt", &dy::SpkEphemeris::tdb_seconds_from_tt, py::arg("jd1"),
                  py::arg("jd2") = 0.0,
                  "TDB s past J2000 of the TT Julian date jd1 + jd2 (ERFA eraDtdb, geocentre).")
      .def("__repr__", [](const dy::SpkEphemeris& e) {
        return "SpkEphemeris('" + e.path() + "', " + std::to_string(e.segments().size()) + " segments)";
      });
}

void init_force_model_fields(py::module_& m) {
  auto fm = py::reinterpret_borrow<py::class_<dy::ForceModel>>(m.attr("ForceModel"));
  fm.def_readwrite("gravity", &dy::ForceModel::gravity, "GravityField or None (excludes j2)")
      .def_readwrite("third_body", &dy::ForceModel::third_body, "ThirdBodies or None")
      .def_readwrite("srp", &dy::ForceModel::srp, "SolarRadiationPressure or None")
      .def_readwrite("epoch_jd1", &dy::ForceModel::epoch_jd1, "TT Julian date of t = 0, part 1 (days)")
      .def_readwrite("epoch_jd2", &dy::ForceModel::epoch_jd2, "TT Julian date of t = 0, part 2 (days)")
      .def("set_epoch", &dy::ForceModel::set_epoch, py::arg("epoch"),
           "Set epoch_jd1/2 to the TT Julian date of a satgnc.time.Epoch (the epoch of t = 0).")
      .def_property(
          "ephemeris_step_days", [](const dy::ForceModel& f) { return f.ephemeris.step_days(); },
          [](dy::ForceModel& f, double step) { f.ephemeris = dy::EphemerisInterpolator(step); },
          "Node spacing (days) of the interpolated ERFA Sun and Moon; 0: ERFA at every evaluation.")
      .def_property(
          "spk_ephemeris",
          [](const dy::ForceModel& f) {
            return std::const_pointer_cast<dy::SpkEphemeris>(f.ephemeris.spk());
          },
          [](dy::ForceModel& f, std::shared_ptr<dy::SpkEphemeris> e) {
            f.ephemeris = e ? dy::EphemerisInterpolator(std::shared_ptr<const dy::SpkEphemeris>(e))
                            : dy::EphemerisInterpolator();
          },
          "SpkEphemeris (a JPL DE file) whose Sun and Moon serve third_body, srp and the drag's Sun, or None "
          "(ERFA, interpolated on 1/8-day nodes).")
      .def(
          "potential_at",
          [](const dy::ForceModel& f, py::handle r, double t) {
            const Vec3 rr = checks::eigen_arg<Vec3>(r, "r");
            f.validate_position(rr, "r");
            return f.potential(t, rr);
          },
          py::arg("r"), py::arg("t"),
          "Potential energy per unit mass V(t, r) of every gravity term (third bodies included), km^2/s^2.")
      .def(
          "acceleration_partial",
          [](const dy::ForceModel& f, const std::string& p, py::handle r, py::handle v, double t) {
            const Vec3 rr = checks::eigen_arg<Vec3>(r, "r");
            f.validate_position(rr, "r");
            return f.acceleration_partial(parameter_of(p), t, rr, checks::eigen_arg<Vec3>(v, "v"));
          },
          py::arg("parameter"), py::arg("r"), py::arg("v"), py::arg("t") = 0.0,
          "d a / d p (km/s^2 per unit p) for p = 'mu' (km^3/s^2), 'cr' or 'cd'.");
}

}  // namespace

void init_force_models(py::module_& m) {
  init_earth_rotation_models(m);
  init_gravity(m);
  init_third_body_srp(m);
  init_spk_ephemeris(m);
  init_force_model_fields(m);
}

}  // namespace satgnc::bindings
