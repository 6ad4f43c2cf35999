// pybind11 wrappers for the parameter sensitivity dx/dp alongside the STM (propagation/sensitivity.hpp).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "checks.hpp"
#include "satgnc/propagation/sensitivity.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

using propagation::SensitivityTrajectory;

namespace {

std::vector<dynamics::ForceParameter> parameter_list(const std::vector<std::string>& names) {
  return propagation::force_parameters_from_names(names);
}

}  // namespace

void init_sensitivity(py::module_& m) {
  py::class_<SensitivityTrajectory>(m, "SensitivityTrajectory",
                                    "States (km, km/s), STMs and dx/dp (6 x k) at the requested times (s).")
      .def_readonly("trajectory", &SensitivityTrajectory::trajectory)
      .def_property_readonly("parameters",
                             [](const SensitivityTrajectory& s) {
                               std::vector<std::string> names;
                               for (auto p : s.parameters)
                                 names.emplace_back(propagation::force_parameter_name(p));
                               return names;
                             })
      .def_property_readonly("sensitivities", [](const SensitivityTrajectory& s) {
        const auto n = static_cast<py::ssize_t>(s.sensitivities.size());
        const auto k = static_cast<py::ssize_t>(s.parameters.size());
        py::array_t<double> a({n, py::ssize_t(6), k});
        auto r = a.mutable_unchecked<3>();
        for (py::ssize_t i = 0; i < n; ++i)
          for (py::ssize_t row = 0; row < 6; ++row)
            for (py::ssize_t j = 0; j < k; ++j)
              r(i, row, j) = s.sensitivities[static_cast<std::size_t>(i)](row, j);
        return a;
      });

  m.def(
      "propagate_dop853_sensitivity",
      [](py::handle x0, double t0, py::handle times, const dynamics::ForceModel& model,
         const std::vector<std::string>& parameters, double rtol, double atol, long max_steps,
         double surface_radius) {
        const Vec6 x = checks::eigen_arg<Vec6>(x0, "x0");
        const std::vector<double> ts = checks::vector_arg(times, "times");
        const auto ps = parameter_list(parameters);
        propagation::Dop853Settings s;
        s.rtol = rtol;
        s.atol = atol;
        s.max_steps = max_steps;
        // Copied with the GIL held: the model's caches (gravity workspace, ephemeris) are guarded by it.
        const dynamics::ForceModel own = model;
        py::gil_scoped_release release;
        return propagation::propagate_dop853_sensitivity(own, x, t0, ts, ps, s, surface_radius);
      },
      py::arg("x0"), py::arg("t0"), py::arg("times"), py::arg("force_model"), py::arg("parameters"),
      py::arg("rtol"), py::arg("atol"), py::arg("max_steps"), py::arg("surface_radius"));

  m.def(
      "propagate_cvodes_sensitivity",
      [](py::handle x0, double t0, py::handle times, const dynamics::ForceModel& model,
         const std::vector<std::string>& parameters, const std::string& method, double rtol, double atol,
         long max_steps, double surface_radius) {
        const Vec6 x = checks::eigen_arg<Vec6>(x0, "x0");
        const std::vector<double> ts = checks::vector_arg(times, "times");
        const auto ps = parameter_list(parameters);
        propagation::CvodesSettings s;
        if (method == "bdf")
          s.method = propagation::CvodesMethod::bdf;
        else if (method != "adams")
          throw std::invalid_argument("method: unknown '" + method + "'; use 'adams' or 'bdf'");
        s.rtol = rtol;
        s.atol = atol;
        s.max_steps = max_steps;
        s.surface_radius = surface_radius;
        s.with_stm = true;
        propagation::CvodesSensitivityPropagator p(model, ps, s);
        py::gil_scoped_release release;
        return p.propagate(x, t0, ts);
      },
      py::arg("x0"), py::arg("t0"), py::arg("times"), py::arg("force_model"), py::arg("parameters"),
      py::arg("method"), py::arg("rtol"), py::arg("atol"), py::arg("max_steps"), py::arg("surface_radius"));
}

}  // namespace satgnc::bindings
