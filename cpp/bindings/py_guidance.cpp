// pybind11 wrappers for the guidance room (CW model, Riccati step, ADMM solver). No algorithm here.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <stdexcept>
#include <string>

#include "checks.hpp"
#include "guidance_result.hpp"
#include "satgnc/guidance/admm.hpp"
#include "status.hpp"

namespace py = pybind11;

namespace satgnc::bindings {
namespace {
/// A fresh numpy copy of m in one array (Fortran order for matrices, as pybind11's Eigen copy),
/// which makes a view and then copies it: two arrays. The L1 call path returns six of them.
py::array fresh_array(const Eigen::MatrixXd& m) {
  py::array_t<double, py::array::f_style> a({m.rows(), m.cols()});
  if (m.size() > 0) std::memcpy(a.mutable_data(), m.data(), sizeof(double) * static_cast<size_t>(m.size()));
  return std::move(a);
}
py::array fresh_array(const Eigen::VectorXd& v) {
  py::array_t<double> a(v.size());
  if (v.size() > 0) std::memcpy(a.mutable_data(), v.data(), sizeof(double) * static_cast<size_t>(v.size()));
  return std::move(a);
}
}  // namespace

py::dict admm_result_to_dict(const guidance::AdmmResult& r) {
  py::dict d;
  d["X"] = fresh_array(r.X);
  d["U"] = fresh_array(r.U);
  d["Y"] = fresh_array(r.Y);
  d["Lambda"] = fresh_array(r.Lambda);
  d["X_flown"] = fresh_array(r.X_flown);
  d["terminal_multiplier"] = fresh_array(r.terminal_multiplier);
  const auto& i = r.info;
  d["status"] = static_cast<int>(i.status);
  d["status_name"] = std::string(guidance::status_message(i.status));
  d["iterations"] = i.iterations;
  d["primal_residual"] = i.primal_residual;
  d["dual_residual"] = i.dual_residual;
  d["eps_primal"] = i.eps_primal;
  d["eps_dual"] = i.eps_dual;
  d["paper_criterion"] = i.paper_criterion;
  d["objective"] = i.objective;
  d["objective_u"] = i.objective_u;
  d["terminal_miss"] = i.terminal_miss;
  d["rho"] = i.rho;
  d["factorizations"] = i.factorizations;
  d["rho_updates"] = i.rho_updates;
  d["polished"] = i.polished;
  d["polish_attempts"] = i.polish_attempts;
  d["condensed"] = i.condensed;
  d["solve_time"] = i.solve_time;
  d["primal_objective"] = i.primal_objective;
  d["dual_objective"] = i.dual_objective;
  d["duality_gap"] = i.duality_gap;
  d["certified"] = i.certified;
  d["workspace_bytes"] = i.workspace_bytes;
  d["ipm_iterations"] = i.ipm_iterations;
  d["ipm_solved"] = i.ipm_solved;
  d["dual_recoveries"] = i.dual_recoveries;
  d["infeasibility_certificate"] = fresh_array(r.infeasibility_certificate);
  return d;
}

namespace {
using guidance::AdmmSettings;
using guidance::AdmmSolver;
using guidance::AdmmStatus;
using guidance::LtvProblem;

/// Keyword API: `AdmmSettings(eps_abs=...)`, `LtvProblem(A=..., B=..., x0=..., ...)` and
/// `AdmmSolver(problem, settings)` beside the 16-positional constructor.
void bind_keyword_api(py::module_& m) {
  checks::settings_from_kwargs<AdmmSettings>(m, "AdmmSettings");
  using Vec = Eigen::VectorXd;
  using Mat = Eigen::MatrixXd;
  py::class_<LtvProblem>(
      m, "LtvProblem",
      "Discrete LTV L1 problem (guidance/admm.hpp), in the caller's units. A, B, c hold 1 or "
      "horizon matrices (nx x nx, nx x nu, nx); x0, xf (nx); Qf, Q (nx x nx), R (nu x nu), "
      "l1_weights, u_lower, u_upper (nu); empty = none.")
      .def(py::init([](std::vector<Mat> A, std::vector<Mat> B, std::vector<Vec> c, int horizon, Vec x0,
                       Vec xf, Mat Qf, Mat Q, Mat R, Vec l1_weights, double group_l2_weight, Vec u_lower,
                       Vec u_upper, double u_norm_max, bool terminal_equality) {
             LtvProblem p;
             p.dynamics.A = std::move(A);
             p.dynamics.B = std::move(B);
             p.dynamics.c = std::move(c);
             p.dynamics.horizon = horizon;
             p.x0 = std::move(x0);
             p.xf = std::move(xf);
             p.Qf = std::move(Qf);
             p.Q = std::move(Q);
             p.R = std::move(R);
             p.l1_weights = std::move(l1_weights);
             p.group_l2_weight = group_l2_weight;
             p.u_lower = std::move(u_lower);
             p.u_upper = std::move(u_upper);
             p.u_norm_max = u_norm_max;
             p.terminal_equality = terminal_equality;
             return p;
           }),
           py::kw_only(), py::arg("A"), py::arg("B"), py::arg("c") = std::vector<Vec>{}, py::arg("horizon"),
           py::arg("x0"), py::arg("xf") = Vec(), py::arg("Qf") = Mat(), py::arg("Q") = Mat(),
           py::arg("R") = Mat(), py::arg("l1_weights") = Vec(), py::arg("group_l2_weight") = 0.0,
           py::arg("u_lower") = Vec(), py::arg("u_upper") = Vec(), py::arg("u_norm_max") = 0.0,
           py::arg("terminal_equality") = false)
      .def_property_readonly("A", [](const LtvProblem& p) { return p.dynamics.A; })
      .def_property_readonly("B", [](const LtvProblem& p) { return p.dynamics.B; })
      .def_property_readonly("c", [](const LtvProblem& p) { return p.dynamics.c; })
      .def_property_readonly("horizon", [](const LtvProblem& p) { return p.dynamics.horizon; })
      .def_property_readonly("nx", [](const LtvProblem& p) { return p.dynamics.nx(); })
      .def_property_readonly("nu", [](const LtvProblem& p) { return p.dynamics.nu(); })
      .def_readonly("x0", &LtvProblem::x0)
      .def_readonly("xf", &LtvProblem::xf)
      .def_readonly("Qf", &LtvProblem::Qf)
      .def_readonly("Q", &LtvProblem::Q)
      .def_readonly("R", &LtvProblem::R)
      .def_readonly("l1_weights", &LtvProblem::l1_weights)
      .def_readonly("group_l2_weight", &LtvProblem::group_l2_weight)
      .def_readonly("u_lower", &LtvProblem::u_lower)
      .def_readonly("u_upper", &LtvProblem::u_upper)
      .def_readonly("u_norm_max", &LtvProblem::u_norm_max)
      .def_readonly("terminal_equality", &LtvProblem::terminal_equality);
  py::class_<AdmmSolver> solver(m.attr("AdmmSolver"));
  solver.def(py::init([](const LtvProblem& problem, const AdmmSettings& settings) {
               return new AdmmSolver(problem, settings);  // GIL released by the call guard below
             }),
             py::arg("problem"), py::arg("settings") = AdmmSettings(),
             py::call_guard<py::gil_scoped_release>());
}
}  // namespace

void init_guidance(py::module_& m) {
  py::enum_<guidance::StoppingRule>(m, "StoppingRule")
      .value("residuals", guidance::StoppingRule::kResiduals)
      .value("paper", guidance::StoppingRule::kPaper);
  py::enum_<guidance::AdmmMethod>(m, "AdmmMethod")
      .value("admm", guidance::AdmmMethod::kAdmm)
      .value("admm_ipm", guidance::AdmmMethod::kAdmmIpm)
      .value("ipm", guidance::AdmmMethod::kIpm);
  bind_status<AdmmStatus>(m, "AdmmStatus");
  m.def("admm_status_message",
        [](int s) { return std::string(guidance::status_message(static_cast<AdmmStatus>(s))); });

  py::class_<AdmmSettings>(m, "AdmmSettings")
      .def(py::init<>())
      .def("validate", &AdmmSettings::validate)  // field rules at assignment (satgnc._validate)
      .def_readwrite("rho", &AdmmSettings::rho)
      .def_readwrite("max_iterations", &AdmmSettings::max_iterations)
      .def_readwrite("stopping", &AdmmSettings::stopping)
      .def_readwrite("eps_abs", &AdmmSettings::eps_abs)
      .def_readwrite("eps_rel", &AdmmSettings::eps_rel)
      .def_readwrite("paper_eps", &AdmmSettings::paper_eps)
      .def_readwrite("relaxation", &AdmmSettings::relaxation)
      .def_readwrite("adaptive_rho", &AdmmSettings::adaptive_rho)
      .def_readwrite("adaptive_rho_interval", &AdmmSettings::adaptive_rho_interval)
      .def_readwrite("adaptive_rho_tolerance", &AdmmSettings::adaptive_rho_tolerance)
      .def_readwrite("rho_min", &AdmmSettings::rho_min)
      .def_readwrite("rho_max", &AdmmSettings::rho_max)
      .def_readwrite("cache_gains", &AdmmSettings::cache_gains)
      .def_readwrite("condensed", &AdmmSettings::condensed)
      .def_readwrite("paper_multiplier_rescale", &AdmmSettings::paper_multiplier_rescale)
      .def_readwrite("paper_global_rescale_iterations", &AdmmSettings::paper_global_rescale_iterations)
      .def_readwrite("track_best", &AdmmSettings::track_best)
      .def_readwrite("polish", &AdmmSettings::polish)
      .def_readwrite("polish_interval", &AdmmSettings::polish_interval)
      .def_readwrite("polish_max_free", &AdmmSettings::polish_max_free)
      .def_readwrite("polish_tolerance", &AdmmSettings::polish_tolerance)
      .def_readwrite("polish_dual", &AdmmSettings::polish_dual)
      .def_readwrite("polish_swaps", &AdmmSettings::polish_swaps)
      .def_readwrite("eps_gap", &AdmmSettings::eps_gap)
      .def_readwrite("gap_floor", &AdmmSettings::gap_floor)
      .def_readwrite("terminal_tolerance", &AdmmSettings::terminal_tolerance)
      .def_readwrite("gap_check_interval", &AdmmSettings::gap_check_interval)
      .def_readwrite("inaccurate_factor", &AdmmSettings::inaccurate_factor)
      .def_readwrite("time_limit", &AdmmSettings::time_limit)
      .def_readwrite("max_workspace_bytes", &AdmmSettings::max_workspace_bytes)
      .def_readwrite("infeasibility_check_interval", &AdmmSettings::infeasibility_check_interval)
      .def_readwrite("equilibrate", &AdmmSettings::equilibrate)
      .def_readwrite("method", &AdmmSettings::method)
      .def_readwrite("ipm_after", &AdmmSettings::ipm_after)
      .def_readwrite("ipm_max_iterations", &AdmmSettings::ipm_max_iterations)
      .def_readwrite("ipm_tolerance", &AdmmSettings::ipm_tolerance);

  py::class_<AdmmSolver>(m, "AdmmSolver")
      .def(py::init([](std::vector<Eigen::MatrixXd> A, std::vector<Eigen::MatrixXd> B,
                       std::vector<Eigen::VectorXd> c, int horizon, Eigen::VectorXd x0, Eigen::VectorXd xf,
                       Eigen::MatrixXd Qf, Eigen::MatrixXd Q, Eigen::MatrixXd R, Eigen::VectorXd l1_weights,
                       double group_l2_weight, Eigen::VectorXd u_lower, Eigen::VectorXd u_upper,
                       double u_norm_max, bool terminal_equality, const AdmmSettings& settings) {
             LtvProblem p;
             p.dynamics.A = std::move(A);
             p.dynamics.B = std::move(B);
             p.dynamics.c = std::move(c);
             p.dynamics.horizon = horizon;
             p.x0 = x0;
             p.xf = xf;
             p.Qf = Qf;
             p.Q = Q;
             p.R = R;
             p.l1_weights = l1_weights;
             p.group_l2_weight = group_l2_weight;
             p.u_lower = u_lower;
             p.u_upper = u_upper;
             p.u_norm_max = u_norm_max;
             p.terminal_equality = terminal_equality;
             return new AdmmSolver(p, settings);  // GIL released by the call guard below
           }),
           py::arg("A"), py::arg("B"), py::arg("c"), py::arg("horizon"), py::arg("x0"), py::arg("xf"),
           py::arg("Qf"), py::arg("Q"), py::arg("R"), py::arg("l1_weights"), py::arg("group_l2_weight"),
           py::arg("u_lower"), py::arg("u_upper"), py::arg("u_norm_max"), py::arg("terminal_equality"),
           py::arg("settings"), py::call_guard<py::gil_scoped_release>())  // setup: long for long horizons
      .def("solve",
           [](AdmmSolver& s) {
             const guidance::AdmmResult* r;
             {
               py::gil_scoped_release release;
               r = &s.solve();
             }
             return admm_result_to_dict(*r);
           })
      .def("solve_time_only",
           [](AdmmSolver& s, int repeats) {
             py::gil_scoped_release release;
             for (int i = 0; i < repeats; ++i) s.solve();
             return s.result().info.solve_time;
           })
      .def("warm_start", &AdmmSolver::warm_start, py::arg("Y"), py::arg("Lambda"))
      .def("cold_start", &AdmmSolver::cold_start)
      .def("set_x0", &AdmmSolver::set_x0, py::arg("x0"))
      .def("set_xf", &AdmmSolver::set_xf, py::arg("xf"))
      .def("update_settings", &AdmmSolver::update_settings, py::arg("settings"))
      .def("update_dynamics", &AdmmSolver::update_dynamics, py::arg("A"), py::arg("B"), py::arg("c"),
           py::call_guard<py::gil_scoped_release>())
      .def("objective_of", &AdmmSolver::objective_of, py::arg("U"))
      .def_property_readonly("nx", &AdmmSolver::nx)
      .def_property_readonly("nu", &AdmmSolver::nu)
      .def_property_readonly("horizon", &AdmmSolver::horizon);
  bind_keyword_api(m);
}

}  // namespace satgnc::bindings
