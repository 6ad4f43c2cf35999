// pybind11 wrappers for the state-constrained L1 ADMM (guidance/state_constraints.hpp). No algorithm here.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <string>
#include <tuple>
#include <vector>

#include "guidance_result.hpp"
#include "satgnc/guidance/state_constraints.hpp"

namespace py = pybind11;

namespace satgnc::bindings {
namespace {
using guidance::StateAdmmResult;
using guidance::StateConstrainedAdmm;
using Vec = Eigen::VectorXd;
using Idx = std::array<int, 3>;

py::dict state_result_to_dict(const StateAdmmResult& r) {
  py::dict d = admm_result_to_dict(r);
  d["state_multipliers"] = r.state_multipliers;
  d["state_consensus"] = r.state_consensus;
  d["max_violation"] = r.max_violation;
  d["violation_tolerance"] = r.violation_tolerance;
  d["ipm_plan"] = r.ipm_plan;
  return d;
}
}  // namespace

void init_guidance_state(py::module_& m) {
  py::class_<StateConstrainedAdmm>(
      m, "StateConstrainedAdmm",
      "L1 ADMM with state constraints (guidance/state_constraints.hpp). half_spaces: [(node, a, b)]; "
      "boxes: [(nodes, lower, upper)]; cones: [(nodes, axis, half_angle_rad, apex_offset, position_index)]; "
      "closing_velocity: [(nodes, axis, intercept, slope, position_index, velocity_index)].")
      .def(py::init([](const guidance::LtvProblem& problem, const py::list& hs_in, const py::list& boxes_in,
                       const py::list& cones_in, const py::list& cv_in,
                       const guidance::AdmmSettings& settings) {
             // py::list (not typed vectors): the tuples hold arrays, and the module's argument
             // checker would read a typed list of tuples as one numeric array
             const auto hs = hs_in.cast<std::vector<std::tuple<int, Vec, double>>>();
             const auto boxes = boxes_in.cast<std::vector<std::tuple<std::vector<int>, Vec, Vec>>>();
             const auto cones =
                 cones_in
                     .cast<std::vector<std::tuple<std::vector<int>, Eigen::Vector3d, double, double, Idx>>>();
             const auto cv =
                 cv_in.cast<std::vector<std::tuple<std::vector<int>, Eigen::Vector3d, Vec, Vec, Idx, Idx>>>();
             guidance::StateConstraints c;
             for (const auto& [node, a, b] : hs) c.half_spaces.push_back({node, a, b});
             for (const auto& [nodes, lo, hi] : boxes) c.boxes.push_back({nodes, lo, hi});
             for (const auto& [nodes, axis, ang, off, pi] : cones)
               c.cones.push_back({nodes, axis, ang, off, pi});
             for (const auto& [nodes, axis, ic, sl, pi, vi] : cv)
               c.closing_velocity.push_back({nodes, axis, ic, sl, pi, vi});
             py::gil_scoped_release release;
             return new StateConstrainedAdmm(problem, c, settings);
           }),
           py::arg("problem"), py::arg("half_spaces"), py::arg("boxes"), py::arg("cones"),
           py::arg("closing_velocity"), py::arg("settings"))
      .def("solve",
           [](StateConstrainedAdmm& s) {
             const StateAdmmResult* r;
             {
               py::gil_scoped_release release;
               r = &s.solve();
             }
             return state_result_to_dict(*r);
           })
      .def(
          "solve_time_only",
          [](StateConstrainedAdmm& s, int repeats) {
            py::gil_scoped_release release;
            double best = 1e300;
            for (int i = 0; i < repeats; ++i) {
              s.cold_start();
              best = std::min(best, s.solve().info.solve_time);
            }
            return best;
          },
          py::arg("repeats"))
      .def("set_half_space", &StateConstrainedAdmm::set_half_space, py::arg("i"), py::arg("node"),
           py::arg("a"), py::arg("b"))
      .def("set_x0", &StateConstrainedAdmm::set_x0, py::arg("x0"))
      .def("cold_start", &StateConstrainedAdmm::cold_start)
      .def("violation", &StateConstrainedAdmm::violation, py::arg("X"))
      .def_property_readonly("rows", &StateConstrainedAdmm::rows)
      .def_property_readonly("row_nodes", &StateConstrainedAdmm::row_nodes)
      .def_property_readonly("nx", &StateConstrainedAdmm::nx)
      .def_property_readonly("nu", &StateConstrainedAdmm::nu)
      .def_property_readonly("horizon", &StateConstrainedAdmm::horizon);
}

}  // namespace satgnc::bindings
