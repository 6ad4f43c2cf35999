// pybind11 wrappers for the guidance_nonlinear part (two-satellite model, discrete maps, iLQR-ADMM).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <stdexcept>

#include "checks.hpp"
#include "satgnc/guidance/ilqr_admm.hpp"
#include "satgnc/guidance/nonlinear_model.hpp"
#include "satgnc/guidance/scp.hpp"
#include "status.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

void init_guidance_nonlinear(py::module_& m) {
  using namespace satgnc::dynamics;
  using namespace satgnc::guidance;

  py::enum_<ControlCost>(m, "ControlCost")
      .value("l1", ControlCost::l1)
      .value("l1_box", ControlCost::l1_box)
      .value("group_l2", ControlCost::group_l2);
  py::enum_<StopRule>(m, "StopRule").value("residuals", StopRule::residuals).value("paper", StopRule::paper);
  bind_status<IlqrAdmmStatus>(m, "IlqrAdmmStatus", {{"not_run", IlqrAdmmStatus::unsolved}});
  m.def("ilqr_admm_status_message", [](IlqrAdmmStatus s) { return std::string(status_message(s)); });

  py::class_<NonlinearL1Problem>(m, "NonlinearL1Problem")
      .def(py::init<>())
      .def_readwrite("horizon", &NonlinearL1Problem::horizon)
      .def_readwrite("x0", &NonlinearL1Problem::x0)
      .def_readwrite("x_target", &NonlinearL1Problem::x_target)
      .def_readwrite("Qf", &NonlinearL1Problem::Qf)
      .def_readwrite("alpha", &NonlinearL1Problem::alpha)
      .def_readwrite("stage_weight", &NonlinearL1Problem::stage_weight)
      .def_readwrite("cost", &NonlinearL1Problem::cost)
      .def_readwrite("u_min", &NonlinearL1Problem::u_min)
      .def_readwrite("u_max", &NonlinearL1Problem::u_max)
      .def_readwrite("terminal_equality", &NonlinearL1Problem::terminal_equality);

  py::class_<IlqrAdmmSettings>(m, "IlqrAdmmSettings")
      .def(py::init<>())
      .def("validate", &IlqrAdmmSettings::validate)  // field rules at assignment (satgnc._validate)
      .def_readwrite("rho", &IlqrAdmmSettings::rho)
      .def_readwrite("max_iter", &IlqrAdmmSettings::max_iter)
      .def_readwrite("ilqr_iters", &IlqrAdmmSettings::ilqr_iters)
      .def_readwrite("ilqr_tol", &IlqrAdmmSettings::ilqr_tol)
      .def_readwrite("stop", &IlqrAdmmSettings::stop)
      .def_readwrite("eps_paper", &IlqrAdmmSettings::eps_paper)
      .def_readwrite("eps_abs", &IlqrAdmmSettings::eps_abs)
      .def_readwrite("eps_rel", &IlqrAdmmSettings::eps_rel)
      .def_readwrite("paper_multiplier_rescale", &IlqrAdmmSettings::paper_multiplier_rescale)
      .def_readwrite("adaptive_rho", &IlqrAdmmSettings::adaptive_rho)
      .def_readwrite("rho_factor", &IlqrAdmmSettings::rho_factor)
      .def_readwrite("rho_balance", &IlqrAdmmSettings::rho_balance)
      .def_readwrite("rho_update_every", &IlqrAdmmSettings::rho_update_every)
      .def_readwrite("reg_init", &IlqrAdmmSettings::reg_init)
      .def_readwrite("reg_min", &IlqrAdmmSettings::reg_min)
      .def_readwrite("reg_max", &IlqrAdmmSettings::reg_max)
      .def_readwrite("reg_factor", &IlqrAdmmSettings::reg_factor)
      .def_readwrite("line_search_iters", &IlqrAdmmSettings::line_search_iters)
      .def_readwrite("ls_lower", &IlqrAdmmSettings::ls_lower)
      .def_readwrite("ls_upper", &IlqrAdmmSettings::ls_upper)
      .def_readwrite("return_best", &IlqrAdmmSettings::return_best)
      .def_readwrite("time_limit", &IlqrAdmmSettings::time_limit)
      .def_readwrite("inaccurate_factor", &IlqrAdmmSettings::inaccurate_factor)
      .def("validate", &IlqrAdmmSettings::validate);

  py::class_<IlqrAdmmInfo>(m, "IlqrAdmmInfo")
      .def_readonly("status", &IlqrAdmmInfo::status)
      .def_readonly("iterations", &IlqrAdmmInfo::iterations)
      .def_readonly("ilqr_iterations", &IlqrAdmmInfo::ilqr_iterations)
      .def_readonly("lqr_passes", &IlqrAdmmInfo::lqr_passes)
      .def_readonly("primal_residual", &IlqrAdmmInfo::primal_residual)
      .def_readonly("dual_residual", &IlqrAdmmInfo::dual_residual)
      .def_readonly("paper_criterion", &IlqrAdmmInfo::paper_criterion)
      .def_readonly("objective_u", &IlqrAdmmInfo::objective_u)
      .def_readonly("objective_y", &IlqrAdmmInfo::objective_y)
      .def_readonly("rho", &IlqrAdmmInfo::rho)
      .def_readonly("rho_updates", &IlqrAdmmInfo::rho_updates)
      .def_readonly("failed_interval", &IlqrAdmmInfo::failed_interval)
      .def_readonly("max_regularization", &IlqrAdmmInfo::max_regularization)
      .def_readonly("terminal_miss", &IlqrAdmmInfo::terminal_miss)
      .def_readonly("solve_time", &IlqrAdmmInfo::solve_time)
      .def_property_readonly("message",
                             [](const IlqrAdmmInfo& i) { return std::string(status_message(i.status)); });

  py::class_<IlqrAdmmSolver>(m, "IlqrAdmmSolver")
      .def(py::init<const DiscreteModel&, const NonlinearL1Problem&, const IlqrAdmmSettings&>(),
           py::arg("model"), py::arg("problem"), py::arg("settings") = IlqrAdmmSettings(),
           py::keep_alive<1, 2>(), py::call_guard<py::gil_scoped_release>())
      .def("set_initial_controls", &IlqrAdmmSolver::set_initial_controls, py::arg("U0"))
      .def("warm_start", &IlqrAdmmSolver::warm_start, py::arg("U"), py::arg("Y"), py::arg("Lambda"))
      .def("set_initial_state", &IlqrAdmmSolver::set_initial_state, py::arg("x0"))
      .def("set_rho", &IlqrAdmmSolver::set_rho, py::arg("rho"))
      .def("set_time_limit", &IlqrAdmmSolver::set_time_limit, py::arg("seconds"))
      .def("set_stage_bounds", &IlqrAdmmSolver::set_stage_bounds, py::arg("lo"), py::arg("hi"))
      .def("clear_stage_bounds", &IlqrAdmmSolver::clear_stage_bounds)
      .def(
          "solve", [](IlqrAdmmSolver& s) { return s.solve().info.status; },
          py::call_guard<py::gil_scoped_release>())
      .def("true_cost", &IlqrAdmmSolver::true_cost, py::arg("U"), py::call_guard<py::gil_scoped_release>())
      .def(
          "rollout",
          [](const IlqrAdmmSolver& s, const Eigen::MatrixXd& U) {
            const auto& r = s.result();
            if (U.rows() != r.U.rows() || U.cols() != r.U.cols()) throw py::value_error("U: must be nu x N");
            Eigen::MatrixXd X(r.X.rows(), r.X.cols());
            int k;
            {
              py::gil_scoped_release release;  // N model steps (propagated maps integrate)
              k = s.rollout(U, X);
            }
            if (k >= 0)
              throw std::runtime_error("rollout: the model failed on interval " + std::to_string(k));
            return X;
          },
          py::arg("U"))
      .def_property_readonly("X", [](const IlqrAdmmSolver& s) { return s.result().X; })
      .def_property_readonly("U", [](const IlqrAdmmSolver& s) { return s.result().U; })
      .def_property_readonly("Y", [](const IlqrAdmmSolver& s) { return s.result().Y; })
      .def_property_readonly("Lambda", [](const IlqrAdmmSolver& s) { return s.result().Lambda; })
      .def_property_readonly("info", [](const IlqrAdmmSolver& s) { return s.result().info; });
  bind_status<ScpStatus>(m, "ScpStatus", {{"not_run", ScpStatus::unsolved}});
  m.def("scp_status_message", [](ScpStatus s) { return std::string(status_message(s)); });
  py::enum_<ScpGlobalization>(m, "ScpGlobalization")
      .value("trust_region", ScpGlobalization::trust_region)
      .value("line_search", ScpGlobalization::line_search);
  py::enum_<ScpInner>(m, "ScpInner")
      .value("ilqr_admm", ScpInner::ilqr_admm)
      .value("linear_admm", ScpInner::linear_admm);
  py::class_<ScpSettings>(m, "ScpSettings")
      .def(py::init<>())
      .def("validate", &ScpSettings::validate)
      .def_readwrite("inner_solver", &ScpSettings::inner_solver)
      .def_readwrite("inner_ilqr", &ScpSettings::inner_ilqr)
      .def_readwrite("max_outer", &ScpSettings::max_outer)
      .def_readwrite("tol", &ScpSettings::tol)
      .def_readwrite("armijo", &ScpSettings::armijo)
      .def_readwrite("line_search_iters", &ScpSettings::line_search_iters)
      .def_readwrite("inner", &ScpSettings::inner)
      .def_readwrite("globalization", &ScpSettings::globalization)
      .def_readwrite("trust_radius", &ScpSettings::trust_radius)
      .def_readwrite("tr_accept", &ScpSettings::tr_accept)
      .def_readwrite("tr_grow_ratio", &ScpSettings::tr_grow_ratio)
      .def_readwrite("tr_shrink", &ScpSettings::tr_shrink)
      .def_readwrite("tr_grow", &ScpSettings::tr_grow)
      .def_readwrite("tr_min", &ScpSettings::tr_min)
      .def_readwrite("tol_inaccurate", &ScpSettings::tol_inaccurate)
      .def_readwrite("time_limit", &ScpSettings::time_limit)
      .def_readwrite("terminal_tol", &ScpSettings::terminal_tol)
      .def_readwrite("terminal_tol_inaccurate", &ScpSettings::terminal_tol_inaccurate)
      .def("validate", &ScpSettings::validate);
  py::class_<ScpInfo>(m, "ScpInfo")
      .def_readonly("status", &ScpInfo::status)
      .def_readonly("outer_iterations", &ScpInfo::outer_iterations)
      .def_readonly("inner_iterations", &ScpInfo::inner_iterations)
      .def_readonly("objective", &ScpInfo::objective)
      .def_readonly("predicted_decrease", &ScpInfo::predicted_decrease)
      .def_readonly("last_step", &ScpInfo::last_step)
      .def_readonly("failed_interval", &ScpInfo::failed_interval)
      .def_readonly("inner_status", &ScpInfo::inner_status)
      .def_readonly("inner_ilqr_status", &ScpInfo::inner_ilqr_status)
      .def_readonly("inner_solved", &ScpInfo::inner_solved)
      .def_readonly("terminal_miss", &ScpInfo::terminal_miss)
      .def_readonly("terminal_constraint_miss", &ScpInfo::terminal_constraint_miss)
      .def_readonly("terminal_reference", &ScpInfo::terminal_reference)
      .def_readonly("penalty", &ScpInfo::penalty)
      .def_readonly("penalty_updates", &ScpInfo::penalty_updates)
      .def_readonly("infeasibility_certificate", &ScpInfo::infeasibility_certificate)
      .def_readonly("infeasibility_margin", &ScpInfo::infeasibility_margin)
      .def_readonly("bound_violation", &ScpInfo::bound_violation)
      .def_readonly("rejected_steps", &ScpInfo::rejected_steps)
      .def_readonly("restoration_steps", &ScpInfo::restoration_steps)
      .def_readonly("trust_radius", &ScpInfo::trust_radius)
      .def_readonly("solve_time", &ScpInfo::solve_time)
      .def_readonly("merit_history", &ScpInfo::merit_history)
      .def_property_readonly("message",
                             [](const ScpInfo& i) { return std::string(status_message(i.status)); });
  py::class_<ScpSolver>(m, "ScpSolver")
      .def(py::init<const DiscreteModel&, const NonlinearL1Problem&, const ScpSettings&>(), py::arg("model"),
           py::arg("problem"), py::arg("settings") = ScpSettings(), py::keep_alive<1, 2>(),
           py::call_guard<py::gil_scoped_release>())
      .def("set_initial_controls", &ScpSolver::set_initial_controls, py::arg("U0"))
      .def("set_initial_state", &ScpSolver::set_initial_state, py::arg("x0"))
      .def(
          "solve", [](ScpSolver& s) { return s.solve().info.status; },
          py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("X", [](const ScpSolver& s) { return s.result().X; })
      .def_property_readonly("U", [](const ScpSolver& s) { return s.result().U; })
      .def_property_readonly("Lambda", [](const ScpSolver& s) { return s.result().Lambda; })
      .def_property_readonly("info", [](const ScpSolver& s) { return s.result().info; });
  checks::settings_from_kwargs<IlqrAdmmSettings>(m, "IlqrAdmmSettings");  // keyword constructors
  checks::settings_from_kwargs<ScpSettings>(m, "ScpSettings");
}

}  // namespace satgnc::bindings
