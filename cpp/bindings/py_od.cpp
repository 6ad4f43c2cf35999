// pybind11 wrappers for the od room (no algorithm here).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "checks.hpp"
#include "satgnc/od/measurement.hpp"
#include "satgnc/od/propagator.hpp"
#include "satgnc/od/solver.hpp"
#include "satgnc/od/station.hpp"
#include "satgnc/od/time.hpp"
#include "status.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {
using namespace satgnc::od;

// History rows 0..iterations as numpy-friendly matrices.
Eigen::MatrixXd rows_of(const Eigen::MatrixXd& m, int n) { return m.topRows(n); }
}  // namespace

void init_od(py::module_& m) {
  m.def("od_julian_date", &julian_date, py::arg("year"), py::arg("month"), py::arg("day"), py::arg("hour"),
        py::arg("minute"), py::arg("second"));
  m.def("od_gmst_iau1982", &gmst_iau1982, py::arg("jd_ut1"));
  m.def("od_gmst_from_utc", &gmst_from_utc, py::arg("jd_utc"), py::arg("ut1_minus_utc_s") = 0.0);
  py::class_<StmPropagator, std::shared_ptr<StmPropagator>>(m, "StmPropagator")
      .def(
          "propagate",
          [](StmPropagator& p, const Vec6& x0, const std::vector<double>& times) {
            const int n = static_cast<int>(times.size());
            std::vector<Vec6> xs(times.size());
            std::vector<Mat6> ph(times.size());
            bool ok;
            {
              py::gil_scoped_release release;
              ok = p.propagate(x0, times.data(), n, xs.data(), ph.data());
            }
            if (!ok) throw std::invalid_argument("x0: propagation failed");
            return py::make_tuple(xs, ph);
          },
          py::arg("x0"), py::arg("times"));
  py::class_<KeplerStmPropagator, StmPropagator, std::shared_ptr<KeplerStmPropagator>>(m,
                                                                                       "KeplerStmPropagator")
      .def(py::init<double>(), py::arg("mu") = dynamics::earth::mu)
      .def_property_readonly("mu", &KeplerStmPropagator::mu);
  py::class_<CvodesStmPropagator, StmPropagator, std::shared_ptr<CvodesStmPropagator>>(m,
                                                                                       "CvodesStmPropagator")
      .def(py::init([](double mu, bool j2, double rtol, double atol) {
             dynamics::ForceModel fm;
             fm.mu = mu;
             if (j2) {
               dynamics::J2Gravity g;
               g.mu = mu;
               fm.j2 = g;
             }
             propagation::CvodesSettings s;
             s.rtol = rtol;
             s.atol = atol;
             return std::make_shared<CvodesStmPropagator>(fm, s);
           }),
           py::arg("mu") = dynamics::earth::mu, py::arg("j2") = false, py::arg("rtol") = 1e-11,
           py::arg("atol") = 1e-12)
      // Any force model (point mass + optional J2 + optional ExponentialDrag; km, km/s, s): the STM
      // integrates the drag's analytic Jacobians too. The model is checked here (ForceModel::validate).
      .def(py::init([](const dynamics::ForceModel& force_model, double rtol, double atol) {
             force_model.validate();
             propagation::CvodesSettings s;
             s.rtol = rtol;
             s.atol = atol;
             return std::make_shared<CvodesStmPropagator>(force_model, s);
           }),
           py::arg("force_model"), py::arg("rtol") = 1e-11, py::arg("atol") = 1e-12,
           "STM propagator on a satgnc.ForceModel (km, km/s, s; J2 and ExponentialDrag optional).");
  py::class_<ShortArcStmPropagator, StmPropagator, std::shared_ptr<ShortArcStmPropagator>>(
      m, "ShortArcStmPropagator")
      .def(py::init<std::shared_ptr<StmPropagator>>(), py::arg("inner"));

  py::enum_<OdMethod>(m, "OdMethod")
      .value("newton", OdMethod::newton)
      .value("gauss_newton", OdMethod::gauss_newton)
      .value("levenberg_marquardt", OdMethod::levenberg_marquardt);
  bind_status<OdStatus>(m, "OdStatus");
  m.def(
      "od_status_message", [](OdStatus s) { return std::string(core::status_message(s)); },
      py::arg("status"));
  py::enum_<ConditionType>(m, "ConditionType")
      .value("range", ConditionType::range)
      .value("doppler", ConditionType::doppler);
  py::class_<BoundaryCondition>(m, "BoundaryCondition")
      .def(py::init(
               [](double t, ConditionType type, double range, double range_rate, double sr, double srr,
                  int station) { return BoundaryCondition{t, type, range, range_rate, sr, srr, station}; }),
           py::arg("t"), py::arg("type"), py::arg("range"), py::arg("range_rate") = 0.0,
           py::arg("sigma_range") = 1e-3, py::arg("sigma_range_rate") = 1e-6, py::arg("station") = 0)
      .def_readwrite("t", &BoundaryCondition::t)
      .def_readwrite("type", &BoundaryCondition::type)
      .def_readwrite("range", &BoundaryCondition::range)
      .def_readwrite("range_rate", &BoundaryCondition::range_rate)
      .def_readwrite("sigma_range", &BoundaryCondition::sigma_range)
      .def_readwrite("sigma_range_rate", &BoundaryCondition::sigma_range_rate)
      .def_readwrite("station", &BoundaryCondition::station);

  py::class_<OdSettings>(m, "OdSettings")
      .def(py::init<>())
      .def_readwrite("method", &OdSettings::method)
      .def_readwrite("max_iterations", &OdSettings::max_iterations)
      .def_readwrite("step_tol", &OdSettings::step_tol)
      .def_readwrite("step_sigma_tol", &OdSettings::step_sigma_tol)
      .def_readwrite("residual_tol", &OdSettings::residual_tol)
      .def_readwrite("cost_tol", &OdSettings::cost_tol)
      .def_readwrite("rank_tol", &OdSettings::rank_tol)
      .def_readwrite("min_radius", &OdSettings::min_radius)
      .def_readwrite("mu", &OdSettings::mu)
      .def_readwrite("fit_sigma", &OdSettings::fit_sigma)
      .def_readwrite("min_range", &OdSettings::min_range)
      .def_readwrite("gn_max_halvings", &OdSettings::gn_max_halvings)
      .def_readwrite("geodesic", &OdSettings::geodesic)
      .def_readwrite("valley_corrections", &OdSettings::valley_corrections)
      .def_readwrite("extrapolate", &OdSettings::extrapolate)
      .def_readwrite("lm_lambda0", &OdSettings::lm_lambda0)
      .def_readwrite("lm_increase", &OdSettings::lm_increase)
      .def_readwrite("lm_decrease", &OdSettings::lm_decrease)
      .def_readwrite("lm_max_rejections", &OdSettings::lm_max_rejections)
      .def_readwrite("lm_stall_tol", &OdSettings::lm_stall_tol)
      .def_readwrite("lm_polish_iterations", &OdSettings::lm_polish_iterations)
      .def("validate", &OdSettings::validate);

  py::class_<OdInfo>(m, "OdInfo",
                     "Run record of OdSolver.solve (core::InfoBase): status, iterations (accepted steps), "
                     "primal_residual (RMS of the normalized residuals at x0), dual_residual (|dx0| of the "
                     "last accepted step, km and km/s mixed; 0 without a step), solve_time (s). Read-only.")
      .def_readonly("status", &OdInfo::status)
      .def_property_readonly("message",
                             [](const OdInfo& i) { return std::string(core::status_message(i.status)); })
      .def_readonly("iterations", &OdInfo::iterations)
      .def_readonly("primal_residual", &OdInfo::primal_residual)
      .def_readonly("dual_residual", &OdInfo::dual_residual)
      .def_readonly("solve_time", &OdInfo::solve_time);

  py::class_<OdResult>(m, "OdResult")
      .def_readonly("info", &OdResult::info)
      .def_readonly("status", &OdResult::status)
      .def_property_readonly("message",
                             [](const OdResult& r) { return std::string(core::status_message(r.status)); })
      .def_readonly("iterations", &OdResult::iterations)
      .def_readonly("evaluations", &OdResult::evaluations)
      .def_readonly("x0", &OdResult::x0)
      .def_readonly("covariance", &OdResult::covariance)
      .def_readonly("correlation", &OdResult::correlation)
      .def_readonly("singular_values", &OdResult::singular_values)
      .def_readonly("rank", &OdResult::rank)
      .def_readonly("condition_number", &OdResult::condition_number)
      .def_readonly("cost", &OdResult::cost)
      .def_readonly("max_abs_normalized", &OdResult::max_abs_normalized)
      .def_readonly("fits", &OdResult::fits)
      .def_readonly("residuals", &OdResult::residuals)
      .def_readonly("normalized", &OdResult::normalized)
      .def_readonly("range_residuals", &OdResult::range_residuals)
      .def_readonly("range_rate_residuals", &OdResult::range_rate_residuals)
      .def_property_readonly("history_x0",
                             [](const OdResult& r) { return rows_of(r.history_x0, r.iterations + 1); })
      .def_property_readonly("history_residuals",
                             [](const OdResult& r) { return rows_of(r.history_residuals, r.iterations + 1); })
      .def_property_readonly(
          "history_range_residuals",
          [](const OdResult& r) { return rows_of(r.history_range_residuals, r.iterations + 1); })
      .def_property_readonly(
          "history_range_rate_residuals",
          [](const OdResult& r) { return rows_of(r.history_range_rate_residuals, r.iterations + 1); })
      .def_property_readonly(
          "history_cost",
          [](const OdResult& r) { return Eigen::VectorXd(r.history_cost.head(r.iterations + 1)); })
      .def_property_readonly("history_lambda", [](const OdResult& r) {
        return Eigen::VectorXd(r.history_lambda.head(r.iterations + 1));
      });

  py::class_<OdSolver>(m, "OdSolver")
      .def_static("from_measurements", &OdSolver::from_measurements, py::arg("stations"),
                  py::arg("measurements"), py::arg("propagator"), py::arg("settings") = OdSettings{})
      .def_static("from_conditions", &OdSolver::from_conditions, py::arg("stations"), py::arg("conditions"),
                  py::arg("propagator"), py::arg("settings") = OdSettings{})
      .def(
          "solve", [](OdSolver& s, const Vec6& x0) { return OdResult(s.solve(x0)); }, py::arg("x0"),
          py::call_guard<py::gil_scoped_release>())
      .def(
          "evaluate",
          [](OdSolver& s, const Vec6& x0) {
            Eigen::VectorXd r;
            Eigen::MatrixXd J;
            OdStatus st;
            {
              py::gil_scoped_release release;  // propagates the whole arc
              st = s.evaluate(x0, r, &J);
            }
            return py::make_tuple(st, r, J);
          },
          py::arg("x0"))
      .def_property_readonly("rows", &OdSolver::rows)
      .def_property_readonly("row_sigmas", &OdSolver::row_sigmas)
      .def_property("settings", &OdSolver::settings, &OdSolver::set_settings);

  py::class_<RootSearchSettings>(m, "RootSearchSettings")
      .def(py::init<>())
      .def_readwrite("distinct_position_km", &RootSearchSettings::distinct_position_km)
      .def_readwrite("distinct_velocity_kms", &RootSearchSettings::distinct_velocity_kms)
      .def_readwrite("distinct_sigma", &RootSearchSettings::distinct_sigma);
  py::class_<Root>(m, "Root")
      .def_readonly("x0", &Root::x0)
      .def_readonly("covariance", &Root::covariance)
      .def_readonly("residuals", &Root::residuals)
      .def_readonly("normalized", &Root::normalized)
      .def_readonly("max_abs_normalized", &Root::max_abs_normalized)
      .def_readonly("condition_number", &Root::condition_number)
      .def_readonly("fits", &Root::fits)
      .def_readonly("converged", &Root::converged)
      .def_readonly("hits", &Root::hits)
      .def_readonly("first_guess", &Root::first_guess);
  py::class_<RootSearchResult>(m, "RootSearchResult")
      .def_readonly("roots", &RootSearchResult::roots)
      .def_readonly("guess_root", &RootSearchResult::guess_root)
      .def_readonly("guess_status", &RootSearchResult::guess_status)
      .def_readonly("guess_iterations", &RootSearchResult::guess_iterations)
      .def_readonly("fitting_roots", &RootSearchResult::fitting_roots)
      .def_readonly("ambiguous", &RootSearchResult::ambiguous);
  m.def(
      "od_root_search",
      [](OdSolver& solver, const Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>& guesses,
         const RootSearchSettings& s) {
        std::vector<Vec6> g(static_cast<std::size_t>(guesses.rows()));
        for (Eigen::Index i = 0; i < guesses.rows(); ++i)
          g[static_cast<std::size_t>(i)] = guesses.row(i).transpose();
        py::gil_scoped_release release;
        return root_search(solver, g, s);
      },
      py::arg("solver"), py::arg("guesses"), py::arg("settings") = RootSearchSettings{});
  m.def(
      "od_box_guesses",
      [](const Vec6& c, const Vec6& hw, int n, std::uint64_t seed) {
        const auto g = box_guesses(c, hw, n, seed);
        Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor> out(n, 6);
        for (int i = 0; i < n; ++i) out.row(i) = g[static_cast<std::size_t>(i)].transpose();
        return out;
      },
      py::arg("center"), py::arg("half_width"), py::arg("n"), py::arg("seed"));
  checks::settings_from_kwargs<OdSettings>(m, "OdSettings");  // OdSettings(method=..., ...)
}

}  // namespace satgnc::bindings
