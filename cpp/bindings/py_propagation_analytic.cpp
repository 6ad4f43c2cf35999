// pybind11 wrappers for the analytic (universal-variable Kepler) and fixed-size DOP853 propagators.
// The Trajectory and ForceModel classes are registered by py_propagation.cpp / py_dynamics.cpp.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "checks.hpp"
#include "satgnc/dynamics/force_model.hpp"
#include "satgnc/propagation/dop853.hpp"
#include "satgnc/propagation/kepler.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

void init_propagation_analytic(py::module_& m) {
  using propagation::KeplerStatus;

  m.def(
      "propagate_kepler",
      [](py::handle x0, py::handle t0, py::handle times, py::handle mu, py::handle with_stm,
         py::handle surface_radius) {
        const Vec6 x = checks::eigen_arg<Vec6>(x0, "x0");
        const double t = checks::real_arg(t0, "t0");
        const std::vector<double> ts = checks::vector_arg(times, "times");
        const double m = checks::real_arg(mu, "mu");
        const bool stm = checks::bool_arg(with_stm, "with_stm");
        const double R = checks::real_arg(surface_radius, "surface_radius");
        py::gil_scoped_release release;
        return propagation::propagate_kepler(x, t, ts, m, stm, R);
      },
      py::arg("x0"), py::arg("t0"), py::arg("times"), py::arg("mu"), py::arg("with_stm") = true,
      py::arg("surface_radius") = 0.0,
      "Two-body propagation in universal variables with the analytic STM (km, km/s, s, km^3/s^2).\n"
      "An arc reaching |r| = surface_radius km (or r = 0) stops with status 'impact', t_reached = its time.");

  m.def(
      "propagate_dop853",
      [](py::handle x0, py::handle t0, py::handle times, const dynamics::ForceModel& force_model,
         py::handle rtol, py::handle atol, py::handle with_stm, py::handle max_steps,
         py::handle surface_radius) {
        const Vec6 x = checks::eigen_arg<Vec6>(x0, "x0");
        const double t = checks::real_arg(t0, "t0");
        const std::vector<double> ts = checks::vector_arg(times, "times");
        propagation::Dop853Settings s;
        s.rtol = checks::real_arg(rtol, "rtol");
        s.atol = checks::real_arg(atol, "atol");
        s.max_steps = static_cast<long>(checks::int_arg(max_steps, "max_steps", 1, 1LL << 62));
        const bool stm = checks::bool_arg(with_stm, "with_stm");
        const double R = checks::real_arg(surface_radius, "surface_radius");
        py::gil_scoped_release release;
        return propagation::propagate_dop853(force_model, x, t, ts, s, stm, R);
      },
      py::arg("x0"), py::arg("t0"), py::arg("times"), py::arg("force_model"),
      py::arg("rtol") = propagation::kDefaultOrbitRtol, py::arg("atol") = propagation::kDefaultOrbitAtol,
      py::arg("with_stm") = true, py::arg("max_steps") = 100000, py::arg("surface_radius") = 0.0,
      "Fixed-size Dormand-Prince 8(5,3) propagation with the variational equations (km, km/s, s).\n"
      "An arc reaching |r| = surface_radius km stops with status 'impact', t_reached = its time.");

  m.def(
      "kepler_step",
      [](py::handle x0_, py::handle dt_, py::handle mu_) {
        const Vec6 x0 = checks::eigen_arg<Vec6>(x0_, "x0");
        const double dt = checks::real_arg(dt_, "dt");
        const double mu = checks::real_arg(mu_, "mu");
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
        if (st != KeplerStatus::success) {
          const double alpha = 2.0 / x0.head<3>().norm() - x0.tail<3>().squaredNorm() / mu;
          throw std::runtime_error(std::string("kepler_step: ") +
                                   propagation::kepler_failure_message(st, alpha, dt));
        }
        // The universal-variable solution runs straight through r = 0 on a collision orbit.
        const double s_hit = propagation::kepler_time_to_radius(x0, dt, mu, 0.0);
        if (s_hit >= 0.0 && s_hit < std::abs(dt))
          throw py::value_error("x0: a collision orbit: it reaches r = 0 after " + std::to_string(s_hit) +
                                " s, before |dt| = " + std::to_string(std::abs(dt)) +
                                " s (the two-body solution is singular there)");
        return py::make_tuple(x, stm);
      },
      py::arg("x0"), py::arg("dt"), py::arg("mu"),
      "One universal-variable Kepler step: returns (x (6,), stm (6, 6)) after dt seconds.");
}

}  // namespace satgnc::bindings
