// pybind11 wrappers for the propagation room: Trajectory and the CVODES propagator.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <stdexcept>
#include <string>

#include "checks.hpp"
#include "satgnc/propagation/cvodes.hpp"
#include "satgnc/propagation/cvodes_ode.hpp"
#include "satgnc/propagation/propagated_map.hpp"
#include "satgnc/propagation/trajectory.hpp"
#include "satgnc/propagation/two_satellite_map.hpp"
#include "satgnc/propagation/two_satellite_truth.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {
using namespace satgnc::propagation;

CvodesSettings make_settings(const std::string& method, double rtol, py::object atol, bool with_stm,
                             long max_steps, int max_order, const std::string& corrector,
                             const std::string& vector, double initial_step, double max_step,
                             double surface_radius) {
  CvodesSettings s;
  if (method == "adams")
    s.method = CvodesMethod::adams;
  else if (method == "bdf")
    s.method = CvodesMethod::bdf;
  else
    throw std::invalid_argument("method: must be 'adams' or 'bdf' for CVODES, got '" + method + "'");
  if (corrector == "auto")
    s.corrector = CvodesCorrector::automatic;
  else if (corrector == "newton")
    s.corrector = CvodesCorrector::newton;
  else if (corrector == "fixed_point")
    s.corrector = CvodesCorrector::fixed_point;
  else
    throw std::invalid_argument("corrector: must be 'auto', 'newton' or 'fixed_point', got '" + corrector +
                                "'");
  if (vector == "satgnc")
    s.vector = CvodesVector::satgnc;
  else if (vector == "sundials_serial")
    s.vector = CvodesVector::sundials_serial;
  else
    throw std::invalid_argument("vector: must be 'satgnc' or 'sundials_serial', got '" + vector + "'");
  s.rtol = rtol;
  // atol is a number or a list: check it here (a complex list was "Unable to cast").
  if (py::isinstance<py::float_>(atol) || py::isinstance<py::int_>(atol) || py::isinstance<py::bool_>(atol)) {
    s.atol = checks::real_arg(atol, "atol");
  } else {
    s.atol_components = checks::vector_arg(atol, "atol");
  }
  s.with_stm = with_stm;
  s.max_steps = max_steps;
  s.max_order = max_order;
  s.initial_step = initial_step;
  s.max_step = max_step;
  s.surface_radius = surface_radius;
  return s;
}

// The two-satellite discrete maps and the CVODES truth flight (blocks moved from
// py_guidance_nonlinear.cpp, issue 12).
void init_two_satellite_maps(py::module_& m) {
  using namespace satgnc::dynamics;

  py::class_<TwoSatelliteMapSettings>(m, "TwoSatelliteMapSettings")
      .def(py::init<>())
      .def_readwrite("dt", &TwoSatelliteMapSettings::dt)
      .def_readwrite("scheme", &TwoSatelliteMapSettings::scheme)
      .def_readwrite("substeps", &TwoSatelliteMapSettings::substeps)
      .def_readwrite("state_scale", &TwoSatelliteMapSettings::state_scale)
      .def_readwrite("control_scale", &TwoSatelliteMapSettings::control_scale);

  py::class_<TwoSatelliteMap, DiscreteModel>(m, "TwoSatelliteMap")
      .def(py::init<const TwoSatelliteModel&, const TwoSatelliteMapSettings&>(), py::arg("model"),
           py::arg("settings"))
      .def_property_readonly("state_scale", &TwoSatelliteMap::state_scale)
      .def_property_readonly("control_scale", &TwoSatelliteMap::control_scale);

  py::class_<PropagatedMapSettings>(m, "PropagatedMapSettings")
      .def(py::init<>())
      .def_readwrite("dt", &PropagatedMapSettings::dt)
      .def_readwrite("rtol", &PropagatedMapSettings::rtol)
      .def_readwrite("atol", &PropagatedMapSettings::atol)
      .def_readwrite("max_steps", &PropagatedMapSettings::max_steps)
      .def_readwrite("min_radius", &PropagatedMapSettings::min_radius)
      .def_readwrite("state_scale", &PropagatedMapSettings::state_scale)
      .def_readwrite("control_scale", &PropagatedMapSettings::control_scale);
  py::class_<PropagatedMapInfo>(m, "PropagatedMapInfo")
      .def_readonly("ok", &PropagatedMapInfo::ok)
      .def_readonly("interval", &PropagatedMapInfo::interval)
      .def_readonly("status", &PropagatedMapInfo::status)
      .def_readonly("steps", &PropagatedMapInfo::steps)
      .def_readonly("rejected", &PropagatedMapInfo::rejected)
      .def_readonly("rhs_evals", &PropagatedMapInfo::rhs_evals)
      .def_readonly("t_reached", &PropagatedMapInfo::t_reached);
  py::class_<PropagatedTwoSatelliteMap, DiscreteModel>(m, "PropagatedTwoSatelliteMap")
      .def(py::init<const TwoSatelliteModel&, const PropagatedMapSettings&>(), py::arg("model"),
           py::arg("settings"))
      .def_property_readonly("state_scale", &PropagatedTwoSatelliteMap::state_scale)
      .def_property_readonly("control_scale", &PropagatedTwoSatelliteMap::control_scale)
      .def_property_readonly("last_info", &PropagatedTwoSatelliteMap::last_info);

  py::class_<propagation::CvodesOdeSettings>(m, "CvodesOdeSettings")
      .def(py::init<>())
      .def_readwrite("rtol", &propagation::CvodesOdeSettings::rtol)
      .def_readwrite("atol", &propagation::CvodesOdeSettings::atol)
      .def_readwrite("atol_components", &propagation::CvodesOdeSettings::atol_components)
      .def_readwrite("max_steps", &propagation::CvodesOdeSettings::max_steps)
      .def_readwrite("max_order", &propagation::CvodesOdeSettings::max_order)
      .def_readwrite("max_step", &propagation::CvodesOdeSettings::max_step);
  m.def("default_truth_settings", &default_truth_settings);
  py::class_<TwoSatelliteTruth>(m, "TwoSatelliteTruth")
      .def(py::init<const TwoSatelliteModel&, const propagation::CvodesOdeSettings&>(), py::arg("model"),
           py::arg("settings") = default_truth_settings())
      .def(
          "step",
          [](TwoSatelliteTruth& t, const Eigen::VectorXd& x, const Eigen::VectorXd& u, double dt) {
            if (x.size() != 12) throw py::value_error("x: must have 12 entries [d, r_t, w, v_t] (m, m/s)");
            if (u.size() != 3) throw py::value_error("u: must have 3 entries (N)");
            if (!(dt > 0.0)) throw py::value_error("dt: must be > 0 (s)");
            Eigen::VectorXd y = x;
            if (t.step(y, u, dt) != propagation::PropagationStatus::success)
              throw std::runtime_error("TwoSatelliteTruth.step: " + t.message());
            return y;
          },
          py::arg("x"), py::arg("u"), py::arg("dt"))
      .def(
          "fly",
          [](TwoSatelliteTruth& t, const Eigen::VectorXd& x0, const Eigen::MatrixXd& U, double dt) {
            TruthFlight f;
            {
              py::gil_scoped_release rel;
              f = t.fly(x0, U, dt);
            }
            py::dict d;
            d["X"] = f.X;
            d["ok"] = f.status == propagation::PropagationStatus::success;
            d["failed_interval"] = f.failed_interval;
            d["message"] = f.message;
            d["impact"] = f.status == propagation::PropagationStatus::impact;
            d["t_reached"] = f.t_reached;
            d["steps"] = f.steps;
            d["rhs_evals"] = f.rhs_evals;
            return d;
          },
          py::arg("x0"), py::arg("U"), py::arg("dt"));

  py::class_<ReferenceScaling>(m, "ReferenceScaling")
      .def_readonly("state_scale", &ReferenceScaling::state_scale)
      .def_readonly("control_scale", &ReferenceScaling::control_scale)
      .def_readonly("time_scale", &ReferenceScaling::time_scale);
  m.def("published_scaling", &published_scaling, py::arg("x0"), py::arg("mu"), py::arg("mass_chaser"));
}
}  // namespace

void init_propagation(py::module_& m) {
  py::class_<PropagationStats>(m, "PropagationStats")
      .def_readonly("steps", &PropagationStats::steps)
      .def_readonly("rhs_evals", &PropagationStats::rhs_evals)
      .def_readonly("error_test_fails", &PropagationStats::error_test_fails)
      .def_readonly("nonlin_iters", &PropagationStats::nonlin_iters)
      .def_readonly("nonlin_conv_fails", &PropagationStats::nonlin_conv_fails)
      .def_readonly("lin_setups", &PropagationStats::lin_setups)
      .def_readonly("last_step", &PropagationStats::last_step);

  py::class_<Trajectory>(m, "Trajectory",
                         "States (km, km/s) and STMs at the requested times (s), statistics, status.")
      .def_property_readonly("times",
                             [](const Trajectory& t) {
                               py::array_t<double> a(static_cast<py::ssize_t>(t.times.size()));
                               std::copy(t.times.begin(), t.times.end(), a.mutable_data());
                               return a;
                             })
      .def_property_readonly("states",
                             [](const Trajectory& t) {
                               const auto n = static_cast<py::ssize_t>(t.states.size());
                               py::array_t<double> a({n, py::ssize_t(6)});
                               auto r = a.mutable_unchecked<2>();
                               for (py::ssize_t k = 0; k < n; ++k)
                                 for (int i = 0; i < 6; ++i) r(k, i) = t.states[k][i];
                               return a;
                             })
      .def_property_readonly("stms",
                             [](const Trajectory& t) -> py::object {
                               if (t.stms.empty() && !t.states.empty()) return py::none();
                               const auto n = static_cast<py::ssize_t>(t.stms.size());
                               py::array_t<double> a({n, py::ssize_t(6), py::ssize_t(6)});
                               auto r = a.mutable_unchecked<3>();
                               for (py::ssize_t k = 0; k < n; ++k)
                                 for (int i = 0; i < 6; ++i)
                                   for (int j = 0; j < 6; ++j) r(k, i, j) = t.stms[k](i, j);
                               return std::move(a);
                             })
      .def_property_readonly("stats",
                             [](const Trajectory& t) {
                               py::dict d;
                               d["steps"] = t.stats.steps;
                               d["rhs_evals"] = t.stats.rhs_evals;
                               d["error_test_fails"] = t.stats.error_test_fails;
                               d["nonlin_iters"] = t.stats.nonlin_iters;
                               d["nonlin_conv_fails"] = t.stats.nonlin_conv_fails;
                               d["lin_setups"] = t.stats.lin_setups;
                               d["last_step"] = t.stats.last_step;
                               return d;
                             })
      .def_property_readonly("status", [](const Trajectory& t) { return status_name(t.status); })
      .def_property_readonly("success",
                             [](const Trajectory& t) { return t.status == PropagationStatus::success; })
      .def_readonly("t_reached", &Trajectory::t_reached)
      .def_readonly("message", &Trajectory::message)
      .def("__len__", [](const Trajectory& t) { return t.times.size(); })
      .def("__repr__", [](const Trajectory& t) {
        return "Trajectory(n=" + std::to_string(t.times.size()) + ", status='" + status_name(t.status) +
               "', steps=" + std::to_string(t.stats.steps) + ")";
      });

  m.def("status_message", [](const std::string& name) {
    for (const core::StatusEntry& row : core::status_table<PropagationStatus>())
      if (name == row.name) return std::string(row.message);
    throw std::invalid_argument("status: unknown status '" + name + "'");
  });

  py::class_<CvodesPropagator>(m, "CvodesPropagator",
                               "CVODES propagator whose workspace is allocated once for a force model.")
      .def(py::init([](const dynamics::ForceModel& f, const std::string& method, double rtol, py::object atol,
                       bool with_stm, long max_steps, int max_order, const std::string& corrector,
                       const std::string& vector, double initial_step, double max_step,
                       double surface_radius) {
             return new CvodesPropagator(
                 f, make_settings(method, rtol, atol, with_stm, max_steps, max_order, corrector, vector,
                                  initial_step, max_step, surface_radius));
           }),
           py::arg("force_model"), py::arg("method") = "adams", py::arg("rtol") = 1e-10,
           py::arg("atol") = 1e-12, py::arg("with_stm") = true, py::arg("max_steps") = 500000,
           py::arg("max_order") = 0, py::arg("corrector") = "auto", py::arg("vector") = "satgnc",
           py::arg("initial_step") = 0.0, py::arg("max_step") = 0.0, py::arg("surface_radius") = 0.0)
      .def(
          "propagate",
          [](CvodesPropagator& p, py::handle x0, py::handle t0, py::handle times) {
            const Vec6 x = checks::eigen_arg<Vec6>(x0, "x0");
            const double t = checks::real_arg(t0, "t0");
            const std::vector<double> ts = checks::vector_arg(times, "times");
            py::gil_scoped_release release;
            return p.propagate(x, t, ts);
          },
          py::arg("x0"), py::arg("t0"), py::arg("times"));

  init_two_satellite_maps(m);
}

}  // namespace satgnc::bindings
