// pybind11 wrappers of dynamics/atmosphere.hpp: density models (Harris-Priester), Sun directions and
// the AtmosphereDrag term (co-rotating atmosphere). Units: km, km/s, s; densities kg/m^3; area m^2,
// mass kg. Registered before init_dynamics so that ForceModel's signature names AtmosphereDrag.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <sstream>

#include "checks.hpp"
#include "satgnc/core/validate.hpp"
#include "satgnc/dynamics/atmosphere.hpp"
#include "satgnc/dynamics/space_weather.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {
namespace dy = satgnc::dynamics;

// Position (km) and Sun direction arguments of the density calls: finite; r non-zero; sun non-zero.
dy::AtmospherePoint point_arg(py::handle r, py::handle sun, py::handle t) {
  const Vec3 rr = checks::eigen_arg<Vec3>(r, "r_itrf");
  core::require(rr.norm() > 0.0, "r_itrf", "must be non-zero (the Earth's centre has no height)");
  const Vec3 ss = checks::eigen_arg<Vec3>(sun, "sun_itrf");
  core::require(ss.norm() > 0.0, "sun_itrf", "must be non-zero (a direction towards the Sun)");
  return dy::atmosphere_point(checks::real_arg(t, "t"), rr, ss);
}

void check_drag(const dy::AtmosphereDrag& d) { d.validate("AtmosphereDrag"); }
}  // namespace

void init_atmosphere(py::module_& m) {
  py::class_<dy::SpaceWeather>(m, "SpaceWeather",
                               "Solar and geomagnetic activity: f107, f107a (sfu, 0-400) and ap (0-400).")
      .def(py::init([](double f107, double f107a, double ap) {
             dy::SpaceWeather w;
             w.f107 = f107;
             w.f107a = f107a;
             w.ap = ap;
             w.validate("SpaceWeather");
             return w;
           }),
           py::arg("f107") = 150.0, py::arg("f107a") = 150.0, py::arg("ap") = 4.0,
           "F10.7 of the previous day and its 81-day mean (sfu), daily Ap; defaults: the NRLMSISE-00 "
           "reference cases' moderate activity.")
      .def_readonly("f107", &dy::SpaceWeather::f107)
      .def_readonly("f107a", &dy::SpaceWeather::f107a)
      .def_readonly("ap", &dy::SpaceWeather::ap)
      .def("__repr__", [](const dy::SpaceWeather& w) {
        std::ostringstream s;
        s.precision(12);
        s << "SpaceWeather(f107=" << w.f107 << ", f107a=" << w.f107a << ", ap=" << w.ap << ")";
        return s.str();
      });

  py::class_<dy::AtmosphereModel, std::shared_ptr<dy::AtmosphereModel>>(
      m, "AtmosphereModel", "Density model interface: density (kg/m^3) at an ITRF position (km).")
      .def(
          "density",
          [](const dy::AtmosphereModel& a, py::handle r_itrf, py::handle sun_itrf, py::handle t) {
            return a.density(point_arg(r_itrf, sun_itrf, t));
          },
          py::arg("r_itrf"), py::arg("sun_itrf"), py::arg("t") = 0.0,
          "Density, kg/m^3, at r_itrf (km, ITRF) with the Sun along sun_itrf (ITRF, any length), t s.")
      .def(
          "density_gradient",
          [](const dy::AtmosphereModel& a, py::handle r_itrf, py::handle sun_itrf, py::handle t) {
            Vec3 g;
            const double rho = a.density_gradient(point_arg(r_itrf, sun_itrf, t), g);
            return py::make_tuple(rho, g);
          },
          py::arg("r_itrf"), py::arg("sun_itrf"), py::arg("t") = 0.0,
          "(density kg/m^3, gradient d rho / d r_itrf in kg/m^3 per km, ITRF).")
      .def_static(
          "geodetic",
          [](py::handle r_itrf) {
            const Vec3 rr = checks::eigen_arg<Vec3>(r_itrf, "r_itrf");
            core::require(rr.norm() > 0.0, "r_itrf", "must be non-zero");
            const dy::AtmospherePoint p = dy::atmosphere_point(0.0, rr, Vec3::UnitX());
            return py::make_tuple(p.latitude, p.longitude, p.height);
          },
          py::arg("r_itrf"), "(geodetic latitude rad, east longitude rad, height km) on WGS-84 (ERFA).");

  py::class_<dy::HarrisPriester, dy::AtmosphereModel, std::shared_ptr<dy::HarrisPriester>>(
      m, "HarrisPriester",
      "Harris-Priester density (Montenbruck & Gill 2000, 3.5.2, Table 3.8; 100-1000 km, 0 above).")
      .def(py::init([](double n, double lag) { return std::make_shared<dy::HarrisPriester>(n, lag); }),
           py::arg("n") = 2.0, py::arg("lag") = 0.523599,
           "n in [2, 6] (2 low inclination, 6 polar); lag of the bulge behind the Sun, rad, in [0, pi].")
      .def_property_readonly("n", &dy::HarrisPriester::n)
      .def_property_readonly("lag", &dy::HarrisPriester::lag)
      .def("__repr__", [](const dy::HarrisPriester& h) {
        std::ostringstream s;
        s.precision(12);
        s << "HarrisPriester(n=" << h.n() << ", lag=" << h.lag() << ")";
        return s.str();
      });

  py::class_<dy::SunDirectionModel, std::shared_ptr<dy::SunDirectionModel>>(
      m, "SunDirectionModel", "Direction of the Sun (GCRF unit vector) at t s after the epoch.")
      .def(
          "direction",
          [](const dy::SunDirectionModel& s, py::handle t) { return s.direction(checks::real_arg(t, "t")); },
          py::arg("t"), "Unit vector towards the Sun, GCRF, at t (s after the epoch).");
  py::class_<dy::FixedSun, dy::SunDirectionModel, std::shared_ptr<dy::FixedSun>>(
      m, "FixedSun", "A fixed Sun direction (GCRF).")
      .def(py::init([](py::handle direction) {
             return std::make_shared<dy::FixedSun>(checks::eigen_arg<Vec3>(direction, "direction"));
           }),
           py::arg("direction"));
  py::class_<dy::ErfaSun, dy::SunDirectionModel, std::shared_ptr<dy::ErfaSun>>(
      m, "ErfaSun", "Geocentric Sun from ERFA eraEpv00, tabulated every node_spacing s (cubic Hermite).")
      .def(py::init([](double jd1, double jd2, double t_begin, double t_end, double spacing) {
             return std::make_shared<dy::ErfaSun>(jd1, jd2, t_begin, t_end, spacing);
           }),
           py::arg("epoch_jd1") = 2451545.0, py::arg("epoch_jd2") = 0.0, py::arg("t_begin") = -86400.0,
           py::arg("t_end") = 31.0 * 86400.0, py::arg("node_spacing") = 21600.0,
           "Epoch: TT Julian date epoch_jd1 + epoch_jd2 (days); table over [t_begin, t_end] s.")
      .def_property_readonly("epoch_jd1", &dy::ErfaSun::epoch_jd1)
      .def_property_readonly("epoch_jd2", &dy::ErfaSun::epoch_jd2);

  py::class_<dy::AtmosphereDrag>(m, "AtmosphereDrag",
                                 "Drag through an AtmosphereModel with a co-rotating atmosphere (GCRF; "
                                 "km, km/s, s; area m^2, mass kg).")
      .def(py::init([](std::shared_ptr<dy::AtmosphereModel> atmosphere,
                       std::optional<std::shared_ptr<dy::SunDirectionModel>> sun, double cd, double area,
                       double mass,
                       std::optional<std::shared_ptr<frames::EarthRotationModel>> earth_rotation) {
             dy::AtmosphereDrag d;
             d.atmosphere = std::move(atmosphere);
             if (sun && *sun) d.sun = std::move(*sun);  // None: the force model's Sun
             if (earth_rotation && *earth_rotation) d.earth_rotation = std::move(*earth_rotation);
             d.cd = cd;
             d.area = area;
             d.mass = mass;
             d.validate("AtmosphereDrag");
             return d;
           }),
           py::arg("atmosphere"), py::arg("sun") = py::none(), py::arg("cd") = 2.2, py::arg("area") = 1.0,
           py::arg("mass") = 1.0, py::arg("earth_rotation") = py::none(),
           "atmosphere: e.g. HarrisPriester(); sun: a SunDirectionModel or None (the force model's Sun: "
           "its cached ERFA Sun at its epoch; alone, ERFA at t s after J2000 TT); cd >= 0; area m^2 >= 0; "
           "mass kg > 0; earth_rotation: an EarthRotationModel (UniformRotation, IauEarthRotation) or None "
           "(UniformRotation(0): uniform about GCRF z from t = 0).")
      .def_property_readonly("earth_rotation",
                             [](const dy::AtmosphereDrag& d) {
                               return std::const_pointer_cast<frames::EarthRotationModel>(d.earth_rotation);
                             })
      .def_property_readonly("atmosphere",
                             [](const dy::AtmosphereDrag& d) {
                               return std::const_pointer_cast<dy::AtmosphereModel>(d.atmosphere);
                             })
      .def_property_readonly(
          "sun",
          [](const dy::AtmosphereDrag& d) { return std::const_pointer_cast<dy::SunDirectionModel>(d.sun); })
      .def_readonly("cd", &dy::AtmosphereDrag::cd)
      .def_readonly("area", &dy::AtmosphereDrag::area)
      .def_readonly("mass", &dy::AtmosphereDrag::mass)
      .def(
          "density",
          [](const dy::AtmosphereDrag& d, py::handle r, py::handle t) {
            check_drag(d);
            const Vec3 rr = checks::eigen_arg<Vec3>(r, "r");
            core::require(rr.norm() > 0.0, "r", "must be non-zero");
            return dy::atmosphere_drag_density(d, checks::real_arg(t, "t"), rr);
          },
          py::arg("r"), py::arg("t") = 0.0, "Density (kg/m^3) at GCRF r (km) and t (s).")
      .def(
          "acceleration",
          [](const dy::AtmosphereDrag& d, py::handle r, py::handle v, py::handle t) {
            const Vec3 rr = checks::eigen_arg<Vec3>(r, "r");
            core::require(rr.norm() > 0.0, "r", "must be non-zero");
            return dy::atmosphere_drag_acceleration(d, checks::real_arg(t, "t"), rr,
                                                    checks::eigen_arg<Vec3>(v, "v"));
          },
          py::arg("r"), py::arg("v"), py::arg("t") = 0.0,
          "Drag acceleration, km/s^2 (r km, v km/s, t s; GCRF).")
      .def(
          "acceleration_jacobians",
          [](const dy::AtmosphereDrag& d, py::handle r, py::handle v, py::handle t) {
            const Vec3 rr = checks::eigen_arg<Vec3>(r, "r");
            core::require(rr.norm() > 0.0, "r", "must be non-zero");
            Vec3 a;
            Mat3 gr, gv;
            dy::atmosphere_drag_jacobians(d, checks::real_arg(t, "t"), rr, checks::eigen_arg<Vec3>(v, "v"), a,
                                          gr, gv);
            return py::make_tuple(a, gr, gv);
          },
          py::arg("r"), py::arg("v"), py::arg("t") = 0.0, "(a km/s^2, da/dr 1/s^2, da/dv 1/s).")
      .def(
          "cd_partial",
          [](const dy::AtmosphereDrag& d, py::handle r, py::handle v, py::handle t) {
            const Vec3 rr = checks::eigen_arg<Vec3>(r, "r");
            core::require(rr.norm() > 0.0, "r", "must be non-zero");
            return dy::atmosphere_drag_cd_partial(d, checks::real_arg(t, "t"), rr,
                                                  checks::eigen_arg<Vec3>(v, "v"));
          },
          py::arg("r"), py::arg("v"), py::arg("t") = 0.0, "d a / d Cd, km/s^2 per unit Cd.")
      .def("__repr__", [](const dy::AtmosphereDrag& d) {
        std::ostringstream s;
        s.precision(12);
        s << "AtmosphereDrag(cd=" << d.cd << ", area=" << d.area << ", mass=" << d.mass << ")";
        return s.str();
      });
}

}  // namespace satgnc::bindings
