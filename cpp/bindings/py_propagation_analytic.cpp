// pybind11 wrappers for the analytic (universal-variable Kepler) and fixed-size DOP853 propagators.
// The Trajectory and ForceModel classes are registered by py_propagation.cpp / py_dynamics.cpp.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/propagation/dop853.hpp"
#include "satgnc/propagation/kepler.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

void init_propagation_analytic(py::module_& m) {
  using propagation::KeplerStatus;

  m.def(
      "propagate_kepler",
      [](const Vec6& x0, double t0, const std::vector<double>& times, double mu, bool with_stm) {
        py::gil_scoped_release release;
        return propagation::propagate_kepler(x0, t0, times, mu, with_stm);
      },
      py::arg("x0"), py::arg("t0"), py::arg("times"), py::arg("mu"), py::arg("with_stm") = true,
      "Two-body propagation in universal variables with the analytic STM (km, km/s, s, km^3/s^2).");

  m.def(
      "propagate_dop853",
      [](const Vec6& x0, double t0, const std::vector<double>& times, const dynamics::ForceModel& force_model,
         double rtol, double atol, bool with_stm, long max_steps) {
        propagation::Dop853Settings s;
        s.rtol = rtol;
        s.atol = atol;
        s.max_steps = max_steps;
        py::gil_scoped_release release;
        return propagation::propagate_dop853(force_model, x0, t0, times, s, with_stm);
      },
      py::arg("x0"), py::arg("t0"), py::arg("times"), py::arg("force_model"), py::arg("rtol") = 1e-10,
      py::arg("atol") = 1e-12, py::arg("with_stm") = true, py::arg("max_steps") = 100000,
      "Fixed-size Dormand-Prince 8(5,3) propagation with the variational equations (km, km/s, s).");

  m.def(
      "kepler_step",
      [](const Vec6& x0, double dt, double mu) {
        Vec6 x;
        Mat6 stm;
        const KeplerStatus st = propagation::kepler_step(x0, dt, mu, x, &stm);
        if (st == KeplerStatus::invalid_input) {
          // Name the offending argument, as the rest of the API does.
          if (!(std::isfinite(mu) && mu > 0.0)) throw py::value_error("mu: must be finite and > 0");
          if (!std::isfinite(dt)) throw py::value_error("dt: must be finite (no NaN or Inf)");
          if (!x0.allFinite()) throw py::value_error("x0: must be finite (no NaN or Inf)");
          throw py::value_error("x0: position must be non-zero (|r0| = 0)");
        }
        if (st != KeplerStatus::success)
          throw std::runtime_error(std::string("kepler_step: ") + propagation::kepler_status_message(st));
        return py::make_tuple(x, stm);
      },
      py::arg("x0"), py::arg("dt"), py::arg("mu"),
      "One universal-variable Kepler step: returns (x (6,), stm (6, 6)) after dt seconds.");
}

}  // namespace satgnc::bindings
