// pybind11 wrappers of the thruster layout (guidance/thruster_layout.hpp). No algorithm here.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "satgnc/guidance/thruster_layout.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

void init_thrusters(py::module_& m) {
  using guidance::Thruster;
  using guidance::ThrusterLayout;
  using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  py::class_<ThrusterLayout>(m, "ThrusterLayout",
                             "Thruster layout (directions in the target's CW frame, positions m, thrust N, "
                             "minimum impulse bit N s); see satgnc.guidance.ThrusterLayout")
      .def(py::init([](const RowMat& directions, const RowMat& positions, const Eigen::VectorXd& max_thrust,
                       const Eigen::VectorXd& min_impulse_bit, const std::vector<std::string>& names) {
             const Eigen::Index m = directions.rows();
             if (directions.cols() != 3 || positions.rows() != m || positions.cols() != 3 ||
                 max_thrust.size() != m || min_impulse_bit.size() != m ||
                 static_cast<Eigen::Index>(names.size()) != m)
               throw std::invalid_argument(
                   "thrusters: directions (m, 3), positions (m, 3), max_thrust (m), "
                   "min_impulse_bit (m) and names (m) must agree");
             std::vector<Thruster> t(static_cast<std::size_t>(m));
             for (Eigen::Index i = 0; i < m; ++i) {
               auto& ti = t[static_cast<std::size_t>(i)];
               ti.direction = directions.row(i).transpose();
               ti.position = positions.row(i).transpose();
               ti.max_thrust = max_thrust(i);
               ti.min_impulse_bit = min_impulse_bit(i);
               ti.name = names[static_cast<std::size_t>(i)];
             }
             return ThrusterLayout(std::move(t));
           }),
           py::arg("directions"), py::arg("positions"), py::arg("max_thrust"), py::arg("min_impulse_bit"),
           py::arg("names"))
      .def_property_readonly("size", &ThrusterLayout::size)
      .def("allocation", &ThrusterLayout::allocation)
      .def("torque_allocation", &ThrusterLayout::torque_allocation)
      .def("input_matrix", &ThrusterLayout::input_matrix, py::arg("B_force"))
      .def("max_thrust", &ThrusterLayout::max_thrust)
      .def("min_impulse_bit", &ThrusterLayout::min_impulse_bit)
      .def("names", &ThrusterLayout::names)
      .def("positions",
           [](const ThrusterLayout& l) {
             Eigen::MatrixXd P(l.size(), 3);
             for (int i = 0; i < l.size(); ++i)
               P.row(i) = l.thrusters()[static_cast<std::size_t>(i)].position;
             return P;
           })
      .def("survivors", &ThrusterLayout::survivors, py::arg("failed"))
      .def("without", &ThrusterLayout::without, py::arg("failed"));
}

}  // namespace satgnc::bindings
