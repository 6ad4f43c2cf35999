// pybind11 wrappers for the dynamics room: force-model terms (Earth constants: py_core.cpp).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <sstream>

#include "checks.hpp"
#include "satgnc/core/validate.hpp"
#include "satgnc/dynamics/force_model.hpp"

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
          << ", drag=" << (f.drag ? "ExponentialDrag(...)" : "None") << ")";
        return s.str();
      });
}

}  // namespace satgnc::bindings
