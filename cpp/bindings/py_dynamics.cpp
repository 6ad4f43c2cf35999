// pybind11 wrappers for the dynamics room: force-model terms, the CW and polar models, stations and
// measurement models, the two-satellite model and the discrete-model interface (Earth constants:
// py_core.cpp).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "checks.hpp"
#include "satgnc/core/validate.hpp"
#include "satgnc/dynamics/cw.hpp"
#include "satgnc/dynamics/discrete_model.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/dynamics/measurement.hpp"
#include "satgnc/dynamics/polar.hpp"
#include "satgnc/dynamics/station.hpp"
#include "satgnc/dynamics/two_satellite.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {

// Gravity is singular at r = 0 and the drag model is out of its range below the surface: refuse
// such a position (ForceModel::validate_position) instead of returning NaN or 1e37 kg/m^3.
Vec3 position_arg(const dynamics::ForceModel& f, py::handle h) {
  const Vec3 r = checks::eigen_arg<Vec3>(h, "r");
  f.validate_position(r, "r");
  return r;
}

// |r| of 1e-160 km passes the non-zero test but |r|^3 underflows: refuse a non-finite result.
template <typename T>
const T& finite_result(const T& value, const Vec3& r) {
  if (!value.allFinite()) {
    std::ostringstream s;
    s << "r: |r| = " << r.norm() << " km is too close to the centre: the acceleration overflows";
    throw py::value_error(s.str());
  }
  return value;
}

namespace dy = satgnc::dynamics;

dy::PolarCoordinates coords(const std::string& c) {
  if (c == "scaled") return dy::PolarCoordinates::scaled;
  if (c == "raw") return dy::PolarCoordinates::raw;
  throw std::invalid_argument("coordinates: must be 'scaled' or 'raw', got '" + c + "'");
}

// Clohessy-Wiltshire calls (blocks moved from py_guidance.cpp, issue 12).
void init_cw(py::module_& m) {
  namespace dyn = satgnc::dynamics;
  m.def(
      "cw_matrices",
      [](double n, double mass) {
        dyn::CwModel cw(n, mass);
        return py::make_tuple(Eigen::MatrixXd(cw.A()), Eigen::MatrixXd(cw.B()));
      },
      py::arg("n"), py::arg("mass"));
  m.def(
      "cw_stm",
      [](py::handle n, py::handle t) {  // checks: cw_stm(t=nan) was a NaN matrix, complex t was truncated
        return Eigen::MatrixXd(dyn::CwModel(checks::real_arg(n, "n"), 1.0).stm(checks::real_arg(t, "t")));
      },
      py::arg("n"), py::arg("t"));
  m.def(
      "cw_discretize",
      [](double n, double mass, double dt, const std::string& method) {
        dyn::CwModel cw(n, mass);
        dyn::CwDiscrete d;
        if (method == "zoh") {
          d = dyn::cw_discretize_zoh(cw, dt);
        } else if (method == "expm") {
          d = dyn::cw_discretize_expm(cw, dt);
        } else if (method == "midpoint") {
          d = dyn::cw_discretize_midpoint(cw, dt);
        } else {
          throw std::invalid_argument("method: must be 'zoh', 'expm' or 'midpoint', got '" + method + "'");
        }
        return py::make_tuple(Eigen::MatrixXd(d.Ad), Eigen::MatrixXd(d.Bd));
      },
      py::arg("n"), py::arg("mass"), py::arg("dt"), py::arg("method") = "zoh");
}

// The polar model (block moved from py_analysis.cpp, issue 12).
void init_polar(py::module_& m) {
  using Eigen::MatrixXd;
  using V4 = Eigen::Vector4d;
  using V2 = Eigen::Vector2d;
  namespace ck = checks;
  py::class_<dy::PolarModel>(m, "PolarModel", "Planar polar-coordinate satellite model (km, s)")
      .def(py::init([](py::handle sigma, py::handle omega) {
             return dy::PolarModel(ck::real_arg(sigma, "sigma"), ck::real_arg(omega, "omega"));
           }),
           py::arg("sigma"), py::arg("omega"))
      .def_static(
          "from_mu",
          [](py::handle sigma, py::handle mu) {
            return dy::PolarModel::from_mu(ck::real_arg(sigma, "sigma"), ck::real_arg(mu, "mu"));
          },
          py::arg("sigma"), py::arg("mu"))
      .def_property_readonly("sigma", &dy::PolarModel::sigma)
      .def_property_readonly("omega", &dy::PolarModel::omega)
      .def_property_readonly("k", &dy::PolarModel::k)
      .def(
          "rhs",
          [](const dy::PolarModel& p, py::handle t, py::handle s, py::handle u) {
            return p.rhs(ck::real_arg(t, "t"), ck::eigen_arg<V4>(s, "s"), ck::eigen_arg<V2>(u, "u"));
          },
          py::arg("t"), py::arg("s"), py::arg("u"))
      .def(
          "jacobians",
          [](const dy::PolarModel& p, py::handle t, py::handle s, py::handle u) {
            dy::PolarModel::MatA A;
            dy::PolarModel::MatB B;
            p.jacobians(ck::real_arg(t, "t"), ck::eigen_arg<V4>(s, "s"), ck::eigen_arg<V2>(u, "u"), A, B);
            return py::make_tuple(MatrixXd(A), MatrixXd(B));
          },
          py::arg("t"), py::arg("s"), py::arg("u"))
      .def(
          "reference",
          [](const dy::PolarModel& p, py::handle t) { return p.reference(ck::real_arg(t, "t")); },
          py::arg("t"))
      .def(
          "to_deviation",
          [](const dy::PolarModel& p, py::handle t, py::handle s, const std::string& c) {
            return p.to_deviation(ck::real_arg(t, "t"), ck::eigen_arg<V4>(s, "s"), coords(c));
          },
          py::arg("t"), py::arg("s"), py::arg("coordinates") = "scaled")
      .def(
          "from_deviation",
          [](const dy::PolarModel& p, py::handle t, py::handle x, const std::string& c) {
            return p.from_deviation(ck::real_arg(t, "t"), ck::eigen_arg<V4>(x, "x"), coords(c));
          },
          py::arg("t"), py::arg("x"), py::arg("coordinates") = "scaled")
      .def(
          "deviation_rhs",
          [](const dy::PolarModel& p, py::handle t, py::handle x, py::handle u, const std::string& c) {
            return p.deviation_rhs(ck::real_arg(t, "t"), ck::eigen_arg<V4>(x, "x"), ck::eigen_arg<V2>(u, "u"),
                                   coords(c));
          },
          py::arg("t"), py::arg("x"), py::arg("u"), py::arg("coordinates") = "scaled")
      .def(
          "A", [](const dy::PolarModel& p, const std::string& c) { return MatrixXd(p.A(coords(c))); },
          py::arg("coordinates") = "scaled")
      .def(
          "B", [](const dy::PolarModel& p, const std::string& c) { return MatrixXd(p.B(coords(c))); },
          py::arg("coordinates") = "scaled");
}

// Ellipsoids, stations and the range / range-rate models (blocks moved from py_od.cpp, issue 12;
// the Python names keep their od_ prefix).
void init_tracking(py::module_& m) {
  using namespace satgnc::dynamics;
  py::class_<Ellipsoid>(m, "Ellipsoid")
      .def(py::init([](const std::string& name, double a, double f) {
             // Names must outlive the struct: keep known names, else a static copy pool.
             static std::vector<std::unique_ptr<std::string>> pool;
             pool.push_back(std::make_unique<std::string>(name));
             return Ellipsoid{pool.back()->c_str(), a, f};
           }),
           py::arg("name"), py::arg("a"), py::arg("f"))
      .def_property_readonly("name", [](const Ellipsoid& e) { return std::string(e.name); })
      .def_readonly("a", &Ellipsoid::a)
      .def_readonly("f", &Ellipsoid::f)
      .def("__repr__", [](const Ellipsoid& e) {
        return "Ellipsoid(" + std::string(e.name) + ", a=" + std::to_string(e.a) +
               " km, 1/f=" + (e.f > 0 ? std::to_string(1.0 / e.f) : std::string("inf")) + ")";
      });
  m.def("od_ellipsoid_by_name", &ellipsoid_by_name, py::arg("name"));
  m.def("od_geodetic_to_ecef", &geodetic_to_ecef, py::arg("lat_rad"), py::arg("lon_rad"),
        py::arg("height_km"), py::arg("ellipsoid") = ellipsoids::wgs84);
  m.def("od_rot_z", &rot_z, py::arg("theta"));
  m.def("od_implied_rotation_rate", &implied_rotation_rate, py::arg("station_state"));

  py::class_<Station>(m, "Station")
      .def(py::init<>())
      .def_readwrite("r0", &Station::r0)
      .def_readwrite("omega", &Station::omega)
      .def_static("from_geodetic", &Station::from_geodetic, py::arg("lat_deg"), py::arg("lon_deg"),
                  py::arg("height_km"), py::arg("jd_utc"), py::arg("ut1_minus_utc_s") = 0.0,
                  py::arg("ellipsoid") = ellipsoids::wgs84, py::arg("omega") = dynamics::earth::omega)
      .def_static("from_ecef", &Station::from_ecef, py::arg("ecef"), py::arg("theta0_rad"),
                  py::arg("omega") = dynamics::earth::omega)
      .def_static("from_inertial", &Station::from_inertial, py::arg("r0"),
                  py::arg("omega") = dynamics::earth::omega)
      .def("validate", &Station::validate)
      .def("state", &Station::state, py::arg("t"))
      .def("__repr__", [](const Station& s) {
        return "Station(r0=[" + std::to_string(s.r0(0)) + ", " + std::to_string(s.r0(1)) + ", " +
               std::to_string(s.r0(2)) + "] km, omega=" + std::to_string(s.omega) + " rad/s)";
      });

  py::enum_<MeasurementType>(m, "MeasurementType")
      .value("range", MeasurementType::range)
      .value("range_rate", MeasurementType::range_rate);
  m.def("od_parse_measurement_type", &parse_measurement_type, py::arg("text"));
  py::class_<Measurement>(m, "Measurement")
      .def(py::init([](double t, MeasurementType type, double value, double sigma, int station) {
             return Measurement{t, type, value, sigma, station};
           }),
           py::arg("t"), py::arg("type"), py::arg("value"), py::arg("sigma"), py::arg("station") = 0)
      .def_readwrite("t", &Measurement::t)
      .def_readwrite("type", &Measurement::type)
      .def_readwrite("value", &Measurement::value)
      .def_readwrite("sigma", &Measurement::sigma)
      .def_readwrite("station", &Measurement::station);
  m.def("od_validate_measurements", &validate_measurements, py::arg("measurements"), py::arg("n_stations"));
  m.def(
      "od_predict_measurement",
      [](MeasurementType type, const Vec6& x, const Vec6& station_state, double min_range) {
        double v = 0.0;
        Row6 g;
        if (!predict_measurement(type, x, station_state, v, &g, min_range))
          throw std::invalid_argument(
              "station_state: the satellite is at the station (zero range); range-rate and partials are "
              "undefined");
        return py::make_tuple(v, Eigen::Matrix<double, 6, 1>(g.transpose()));
      },
      py::arg("type"), py::arg("x"), py::arg("station_state"), py::arg("min_range") = 1e-6);
}

// The two-satellite model and the discrete-model interface (blocks moved from
// py_guidance_nonlinear.cpp, issue 12).
void init_two_satellite(py::module_& m) {
  using namespace satgnc::dynamics;

  py::enum_<ControlFrame>(m, "ControlFrame")
      .value("inertial", ControlFrame::inertial)
      .value("target_cw", ControlFrame::target_cw);
  py::enum_<AtmosphereRotation>(m, "AtmosphereRotation")
      .value("co_rotating", AtmosphereRotation::co_rotating)
      .value("published", AtmosphereRotation::published);

  py::class_<TwoSatelliteParams>(m, "TwoSatelliteParams")
      .def(py::init<>())
      .def_readwrite("mu", &TwoSatelliteParams::mu)
      .def_readwrite("j2_on", &TwoSatelliteParams::j2_on)
      .def_readwrite("j2", &TwoSatelliteParams::j2)
      .def_readwrite("j2_radius", &TwoSatelliteParams::j2_radius)
      .def_readwrite("drag_on", &TwoSatelliteParams::drag_on)
      .def_readwrite("rho0", &TwoSatelliteParams::rho0)
      .def_readwrite("density_decay", &TwoSatelliteParams::density_decay)
      .def_readwrite("density_radius", &TwoSatelliteParams::density_radius)
      .def_readwrite("omega", &TwoSatelliteParams::omega)
      .def_readwrite("atmosphere", &TwoSatelliteParams::atmosphere)
      .def_readwrite("mass_chaser", &TwoSatelliteParams::mass_chaser)
      .def_readwrite("mass_target", &TwoSatelliteParams::mass_target)
      .def_readwrite("cd_chaser", &TwoSatelliteParams::cd_chaser)
      .def_readwrite("cd_target", &TwoSatelliteParams::cd_target)
      .def_readwrite("area_chaser", &TwoSatelliteParams::area_chaser)
      .def_readwrite("area_target", &TwoSatelliteParams::area_target)
      .def_readwrite("control_frame", &TwoSatelliteParams::control_frame)
      .def("validate", &TwoSatelliteParams::validate);

  py::class_<TwoSatelliteModel>(m, "TwoSatelliteModel")
      .def(py::init<const TwoSatelliteParams&>(), py::arg("params") = TwoSatelliteParams())
      .def_property_readonly("params", &TwoSatelliteModel::params)
      .def(
          "rhs",
          [](const TwoSatelliteModel& s, const Vec12& x, const Vec3& u) {
            Vec12 f;
            if (!s.rhs(x, u, f))
              throw std::runtime_error("rhs: model evaluation failed (zero radius or non-finite)");
            return f;
          },
          py::arg("x"), py::arg("u"))
      .def(
          "rhs_jacobians",
          [](const TwoSatelliteModel& s, const Vec12& x, const Vec3& u) {
            Vec12 f;
            Mat12 A;
            Mat12x3 B;
            if (!s.rhs_jacobians(x, u, f, A, B))
              throw std::runtime_error("rhs_jacobians: model evaluation failed (zero radius or non-finite)");
            return py::make_tuple(f, A, B);
          },
          py::arg("x"), py::arg("u"))
      .def(
          "rk_step",
          [](const TwoSatelliteModel& s, int scheme, double h, const Vec12& x, const Vec3& u,
             bool jacobians) {
            if (scheme != 3 && scheme != 4) throw py::value_error("scheme: must be 3 or 4");
            Vec12 xn;
            Mat12 A;
            Mat12x3 B;
            const bool ok =
                jacobians ? s.rk_step(scheme, h, x, u, xn, &A, &B) : s.rk_step(scheme, h, x, u, xn);
            if (!ok) throw std::runtime_error("rk_step: model evaluation failed");
            if (jacobians) return py::object(py::make_tuple(xn, A, B));
            return py::object(py::cast(xn));
          },
          py::arg("scheme"), py::arg("h"), py::arg("x"), py::arg("u"), py::arg("jacobians") = false)
      .def(
          "propagate",
          [](const TwoSatelliteModel& s, int scheme, const Vec12& x0, double duration, int steps) {
            if (steps < 1) throw py::value_error("steps: must be >= 1");
            Vec12 x = x0, xn;
            for (int i = 0; i < steps; ++i) {
              if (!s.rk_step(scheme, duration / steps, x, Vec3::Zero(), xn))
                throw std::runtime_error("propagate: model failed at step " + std::to_string(i));
              x = xn;
            }
            return x;
          },
          py::arg("scheme"), py::arg("x0"), py::arg("duration"), py::arg("steps"));

  m.def("cw_relative_state", &cw_relative_state, py::arg("x"));
  m.def("cw_relative_state_published", &cw_relative_state_published, py::arg("x"), py::arg("mu"));
  m.def("two_satellite_state", &two_satellite_state, py::arg("r_t"), py::arg("v_t"), py::arg("cw"));

  py::class_<DiscreteModel>(m, "DiscreteModel")
      .def_property_readonly("state_dim", &DiscreteModel::state_dim)
      .def_property_readonly("control_dim", &DiscreteModel::control_dim)
      .def(
          "step",
          [](const DiscreteModel& d, int k, const Eigen::VectorXd& x, const Eigen::VectorXd& u) {
            if (x.size() != d.state_dim()) throw py::value_error("x: must have state_dim entries");
            if (u.size() != d.control_dim()) throw py::value_error("u: must have control_dim entries");
            Eigen::VectorXd xn(d.state_dim());
            Eigen::MatrixXd A(d.state_dim(), d.state_dim()), B(d.state_dim(), d.control_dim());
            bool ok;
            {
              py::gil_scoped_release release;  // a propagated map integrates over the interval
              ok = d.step(k, x.data(), u.data(), xn.data(), A.data(), B.data());
            }
            if (!ok) throw std::runtime_error("step: the model failed on interval " + std::to_string(k));
            return py::make_tuple(xn, A, B);
          },
          py::arg("k"), py::arg("x"), py::arg("u"));

  py::class_<LinearDiscreteModel, DiscreteModel>(m, "LinearDiscreteModel")
      .def(py::init<std::vector<Eigen::MatrixXd>, std::vector<Eigen::MatrixXd>,
                    std::vector<Eigen::VectorXd>>(),
           py::arg("A"), py::arg("B"), py::arg("c"));
}
}  // namespace

void init_dynamics(py::module_& m) {
  using namespace satgnc::dynamics;

  py::class_<J2Gravity>(m, "J2Gravity", "Zonal J2 term: mu km^3/s^2, j2, radius km.")
      .def(py::init([](double mu, double j2, double radius) {
             // Checked here, naming the argument: J2Gravity(mu=nan) was accepted until a propagation.
             core::require_positive(mu, "mu");
             core::require_finite(j2, "j2");
             core::require_positive(radius, "radius");
             return J2Gravity{mu, j2, radius};
           }),
           py::arg("mu") = earth::mu, py::arg("j2") = earth::j2, py::arg("radius") = earth::radius)
      .def_readwrite("mu", &J2Gravity::mu)
      .def_readwrite("j2", &J2Gravity::j2)
      .def_readwrite("radius", &J2Gravity::radius)
      .def("__repr__", [](const J2Gravity& g) {
        std::ostringstream s;
        s.precision(12);
        s << "J2Gravity(mu=" << g.mu << ", j2=" << g.j2 << ", radius=" << g.radius << ")";
        return s.str();
      });

  py::class_<ExponentialDrag>(m, "ExponentialDrag",
                              "Exponential atmosphere rho0 exp(-(h - h0)/scale_height) with co-rotation.")
      .def(py::init([](double rho0, double h0, double scale_height, double cd, double area, double mass,
                       double body_radius, const Vec3& omega) {
             // The rules of ForceModel::validate, naming the argument (rho0=nan was accepted here).
             core::require_nonnegative(rho0, "rho0");
             core::require_finite(h0, "h0");
             core::require_positive(scale_height, "scale_height");
             core::require_nonnegative(cd, "cd");
             core::require_nonnegative(area, "area");
             core::require_positive(mass, "mass");
             core::require_positive(body_radius, "body_radius");
             core::require_finite(omega, "omega");
             ExponentialDrag d;
             d.rho0 = rho0;
             d.h0 = h0;
             d.scale_height = scale_height;
             d.cd = cd;
             d.area = area;
             d.mass = mass;
             d.body_radius = body_radius;
             d.omega = omega;
             return d;
           }),
           py::arg("rho0"), py::arg("h0"), py::arg("scale_height"), py::arg("cd") = 2.2,
           py::arg("area") = 1.0, py::arg("mass") = 1.0, py::arg("body_radius") = earth::radius,
           py::arg("omega") = Vec3(0.0, 0.0, earth::omega))
      .def_readwrite("rho0", &ExponentialDrag::rho0)
      .def_readwrite("h0", &ExponentialDrag::h0)
      .def_readwrite("scale_height", &ExponentialDrag::scale_height)
      .def_readwrite("cd", &ExponentialDrag::cd)
      .def_readwrite("area", &ExponentialDrag::area)
      .def_readwrite("mass", &ExponentialDrag::mass)
      .def_readwrite("body_radius", &ExponentialDrag::body_radius)
      .def_readwrite("omega", &ExponentialDrag::omega)
      .def(
          "density",
          [](const ExponentialDrag& d, py::handle radius) {
            const double rr = checks::real_arg(radius, "radius");
            validate_density_radius(d, rr, "radius");
            return exponential_density(d, rr);
          },
          py::arg("radius"),
          "Density (kg/m^3) at radius |r| km (>= body_radius; ValueError below the surface).")
      .def("__repr__", [](const ExponentialDrag& d) {
        std::ostringstream s;
        s.precision(12);
        s << "ExponentialDrag(rho0=" << d.rho0 << ", h0=" << d.h0 << ", scale_height=" << d.scale_height
          << ", cd=" << d.cd << ", area=" << d.area << ", mass=" << d.mass << ")";
        return s.str();
      });

  py::class_<ForceModel>(m, "ForceModel", "Point-mass gravity plus optional J2 and drag (km, km/s, s).")
      .def(py::init([](double mu, std::optional<J2Gravity> j2, std::optional<ExponentialDrag> drag,
                       std::optional<AtmosphereDrag> atmosphere_drag, double epoch_jd1, double epoch_jd2) {
             ForceModel f;
             f.mu = mu;
             f.j2 = j2;
             f.drag = drag;
             f.atmosphere_drag = atmosphere_drag;  // atmosphere drag (issue 14 item 4)
             f.epoch_jd1 = epoch_jd1;              // TT Julian date of t = 0: the Sun and Moon of every term
             f.epoch_jd2 = epoch_jd2;
             f.validate();
             return f;
           }),
           py::arg("mu") = earth::mu, py::arg("j2") = py::none(), py::arg("drag") = py::none(),
           py::arg("atmosphere_drag") = py::none(), py::arg("epoch_jd1") = 2451545.0,
           py::arg("epoch_jd2") = 0.0)
      .def_readwrite("mu", &ForceModel::mu)
      .def_readwrite("j2", &ForceModel::j2)
      .def_readwrite("drag", &ForceModel::drag)
      .def_readwrite("atmosphere_drag", &ForceModel::atmosphere_drag)  // atmosphere drag
      .def("validate", &ForceModel::validate)
      .def_property_readonly("conservative", &ForceModel::conservative)
      .def(
          "acceleration",
          [](const ForceModel& f, py::handle r, py::handle v, py::handle t) {
            const Vec3 rr = position_arg(f, r);
            const Vec3 a = f.acceleration(checks::real_arg(t, "t"), rr, checks::eigen_arg<Vec3>(v, "v"));
            return finite_result(a, rr);
          },
          py::arg("r"), py::arg("v"), py::arg("t") = 0.0,
          "Acceleration (km/s^2) at r km (|r| > 0, above the surface with drag), v km/s, t s.")
      .def(
          "acceleration_jacobians",
          [](const ForceModel& f, py::handle r, py::handle v, py::handle t) {
            const Vec3 rr = position_arg(f, r);
            const Vec3 vv = checks::eigen_arg<Vec3>(v, "v");
            const double tt = checks::real_arg(t, "t");
            Vec3 a;
            Mat3 gr, gv;
            f.acceleration_jacobians(tt, rr, vv, a, gr, gv);
            finite_result(a, rr);
            finite_result(gr, rr);
            return py::make_tuple(a, gr, gv);
          },
          py::arg("r"), py::arg("v"), py::arg("t") = 0.0, "(a km/s^2, da/dr 1/s^2, da/dv 1/s).")
      .def(
          "potential", [](const ForceModel& f, py::handle r) { return f.potential(position_arg(f, r)); },
          py::arg("r"), "Gravity potential energy, km^2/s^2 (|r| > 0).")
      .def(
          "energy",
          [](const ForceModel& f, py::handle r, py::handle v) {
            const Vec3 rr = position_arg(f, r);
            return f.energy(rr, checks::eigen_arg<Vec3>(v, "v"));
          },
          py::arg("r"), py::arg("v"), "|v|^2/2 + V(r), km^2/s^2 (|r| > 0).")
      .def("__repr__", [](const ForceModel& f) {
        std::ostringstream s;
        s.precision(12);
        s << "ForceModel(mu=" << f.mu << ", j2=" << (f.j2 ? "J2Gravity(...)" : "None")
          << ", drag=" << (f.drag ? "ExponentialDrag(...)" : "None")
          << (f.atmosphere_drag ? ", atmosphere_drag=AtmosphereDrag(...)" : "") << ")";
        return s.str();
      });

  init_cw(m);
  init_polar(m);
  init_tracking(m);
  init_two_satellite(m);
}

}  // namespace satgnc::bindings
