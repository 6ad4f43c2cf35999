// pybind11 wrappers for the dynamics room: force-model terms and Earth constants.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <sstream>

#include "satgnc/dynamics/force_model.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

void init_dynamics(py::module_& m) {
  using namespace satgnc::dynamics;
  m.attr("EARTH_MU") = earth::mu;
  m.attr("EARTH_RADIUS") = earth::radius;
  m.attr("EARTH_J2") = earth::j2;
  m.attr("EARTH_OMEGA") = earth::omega;

  py::class_<J2Gravity>(m, "J2Gravity", "Zonal J2 term: mu km^3/s^2, j2, radius km.")
      .def(py::init([](double mu, double j2, double radius) { return J2Gravity{mu, j2, radius}; }),
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
      .def("density", &exponential_density, py::arg("radius"), "Density (kg/m^3) at radius |r| km.")
      .def("__repr__", [](const ExponentialDrag& d) {
        std::ostringstream s;
        s.precision(12);
        s << "ExponentialDrag(rho0=" << d.rho0 << ", h0=" << d.h0 << ", scale_height=" << d.scale_height
          << ", cd=" << d.cd << ", area=" << d.area << ", mass=" << d.mass << ")";
        return s.str();
      });

  py::class_<ForceModel>(m, "ForceModel", "Point-mass gravity plus optional J2 and drag (km, km/s, s).")
      .def(py::init([](double mu, std::optional<J2Gravity> j2, std::optional<ExponentialDrag> drag) {
             ForceModel f;
             f.mu = mu;
             f.j2 = j2;
             f.drag = drag;
             f.validate();
             return f;
           }),
           py::arg("mu") = earth::mu, py::arg("j2") = py::none(), py::arg("drag") = py::none())
      .def_readwrite("mu", &ForceModel::mu)
      .def_readwrite("j2", &ForceModel::j2)
      .def_readwrite("drag", &ForceModel::drag)
      .def("validate", &ForceModel::validate)
      .def_property_readonly("conservative", &ForceModel::conservative)
      .def(
          "acceleration",
          [](const ForceModel& f, const Vec3& r, const Vec3& v, double t) { return f.acceleration(t, r, v); },
          py::arg("r"), py::arg("v"), py::arg("t") = 0.0, "Acceleration (km/s^2) at r km, v km/s.")
      .def(
          "acceleration_jacobians",
          [](const ForceModel& f, const Vec3& r, const Vec3& v, double t) {
            Vec3 a;
            Mat3 gr, gv;
            f.acceleration_jacobians(t, r, v, a, gr, gv);
            return py::make_tuple(a, gr, gv);
          },
          py::arg("r"), py::arg("v"), py::arg("t") = 0.0, "(a, da/dr 1/s^2, da/dv 1/s).")
      .def("potential", &ForceModel::potential, py::arg("r"), "Gravity potential energy, km^2/s^2.")
      .def("energy", &ForceModel::energy, py::arg("r"), py::arg("v"), "|v|^2/2 + V(r), km^2/s^2.")
      .def("__repr__", [](const ForceModel& f) {
        std::ostringstream s;
        s.precision(12);
        s << "ForceModel(mu=" << f.mu << ", j2=" << (f.j2 ? "J2Gravity(...)" : "None")
          << ", drag=" << (f.drag ? "ExponentialDrag(...)" : "None") << ")";
        return s.str();
      });
}

}  // namespace satgnc::bindings
