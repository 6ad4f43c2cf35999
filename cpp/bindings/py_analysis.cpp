// pybind11 wrappers for the analysis room (and the polar model it owns). Wrap only; no algorithm.
#include <pybind11/complex.h>
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "checks.hpp"
#include "satgnc/analysis/gramian.hpp"
#include "satgnc/analysis/linearize.hpp"
#include "satgnc/analysis/od_gramian.hpp"
#include "satgnc/analysis/rank.hpp"
#include "satgnc/dynamics/polar.hpp"

namespace py = pybind11;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace satgnc::bindings {
namespace {
namespace an = satgnc::analysis;
namespace dy = satgnc::dynamics;

an::Property property(const std::string& p) {
  if (p == "controllability") return an::Property::controllability;
  if (p == "observability") return an::Property::observability;
  throw std::invalid_argument("property: must be 'controllability' or 'observability', got '" + p + "'");
}

an::Units units_from(const py::dict& d) {
  an::Units u;
  u.time = d["time"].cast<double>();
  u.state = d["state"].cast<VectorXd>();
  if (d.contains("input") && !d["input"].is_none()) u.input = d["input"].cast<VectorXd>();
  if (d.contains("output") && !d["output"].is_none()) u.output = d["output"].cast<VectorXd>();
  return u;
}

py::dict units_to(const an::Units& u) {
  py::dict d;
  d["time"] = u.time;
  d["state"] = u.state;
  d["input"] = u.input;
  d["output"] = u.output;
  return d;
}

an::RankSettings settings(double rtol, double fuzz, const std::string& stair, double cluster_rtol,
                          const std::optional<py::dict>& units) {
  an::RankSettings s;
  s.rtol = rtol;
  s.fuzz = fuzz;
  if (stair == "svd")
    s.stair = an::StairMethod::svd;
  else if (stair == "qrcp")
    s.stair = an::StairMethod::qrcp;
  else
    throw std::invalid_argument("stair: must be 'svd' or 'qrcp', got '" + stair + "'");
  s.cluster_rtol = cluster_rtol;
  if (units) s.units = units_from(*units);
  return s;
}

py::dict report(const an::RankReport& r) {
  py::dict d;
  d["property"] = r.property == an::Property::controllability ? "controllability" : "observability";
  d["n"] = r.n;
  d["rank"] = r.rank;
  d["rtol"] = r.rtol;
  d["sigma_r"] = r.sigma_r;
  d["sigma_next"] = r.sigma_next;
  d["margin"] = r.margin;
  d["gap"] = r.gap;
  d["method"] = r.method;
  d["verdict"] = core::status_message(r.verdict);
  d["verdict_text"] = an::verdict_text(r.verdict, r.property);
  d["reason"] = r.reason;
  return d;
}

py::dict gramian(const an::GramianReport& g) {
  py::dict d;
  d["W"] = g.W;
  d["eigenvalues"] = g.eigenvalues;
  d["condition"] = g.condition;
  d["weakest"] = g.weakest;
  d["strongest"] = g.strongest;
  d["rounding_floor"] = g.rounding_floor;
  d["resolved"] = g.resolved;
  return d;
}

#define SATGNC_RANK_ARGS                                                                       \
  py::arg("A"), py::arg("BC"), py::arg("property") = "controllability", py::arg("rtol") = 0.0, \
                               py::arg("fuzz") = 100.0, py::arg("stair") = "svd",              \
                               py::arg("cluster_rtol") = 1e-6, py::arg("units") = py::none()

}  // namespace

void init_analysis(py::module_& m) {
  m.def(
      "_polar_units", [](double s, double w, int p) { return units_to(an::polar_units(s, w, p)); },
      py::arg("sigma"), py::arg("omega"), py::arg("n_outputs") = 0);
  m.def(
      "_cw_units", [](double n, double L, int p) { return units_to(an::cw_units(n, L, p)); },
      py::arg("mean_motion"), py::arg("length"), py::arg("n_outputs") = 0);
  m.def(
      "_nondimensionalize",
      [](const MatrixXd& A, const MatrixXd& B, const MatrixXd& C, const py::dict& u) {
        an::LinearModel lm{A, B, C};
        const an::LinearModel s = an::nondimensionalize(lm, units_from(u));
        return py::make_tuple(s.A, s.B, s.C);
      },
      py::arg("A"), py::arg("B"), py::arg("C"), py::arg("units"));
  m.def(
      "_cw_model",
      [](double n, const std::vector<int>& measured) {
        const an::LinearModel lm = an::cw_model(n, measured);
        return py::make_tuple(lm.A, lm.B, lm.C);
      },
      py::arg("mean_motion"), py::arg("measured") = std::vector<int>{0, 1, 2});
  m.def(
      "_fd_jacobian",
      [](const an::ModelFn& f, double t, const VectorXd& x, const VectorXd& u, double rel_step,
         const VectorXd& xs, const VectorXd& us) {
        an::FdSettings fd;
        fd.rel_step = rel_step;
        fd.x_scale = xs;
        fd.u_scale = us;
        MatrixXd A, B;
        an::fd_jacobian(f, t, x, u, A, B, fd);
        return py::make_tuple(A, B);
      },
      py::arg("f"), py::arg("t"), py::arg("x"), py::arg("u"), py::arg("rel_step"), py::arg("x_scale"),
      py::arg("u_scale"));
  m.def("_two_body_jacobian", &an::two_body_jacobian, py::arg("r"), py::arg("mu"));
  m.def(
      "_range_partial",
      [](const Eigen::Vector3d& r, const Eigen::Vector3d& R) {
        Eigen::Matrix<double, 1, 6> H;
        const double rho = an::range_partial(r, R, H);
        return py::make_tuple(rho, MatrixXd(H));
      },
      py::arg("r"), py::arg("R"));
  m.def(
      "_range_rate_partial",
      [](const Eigen::Vector3d& r, const Eigen::Vector3d& v, const Eigen::Vector3d& R,
         const Eigen::Vector3d& V) {
        Eigen::Matrix<double, 1, 6> H;
        const double rd = an::range_rate_partial(r, v, R, V, H);
        return py::make_tuple(rd, MatrixXd(H));
      },
      py::arg("r"), py::arg("v"), py::arg("R"), py::arg("V"));

  m.def(
      "_staircase",
      [](const MatrixXd& A, const MatrixXd& BC, const std::string& p, double rtol, double fuzz,
         const std::string& stair, double crt, const std::optional<py::dict>& units) {
        const an::RankSettings st = settings(rtol, fuzz, stair, crt, units);
        const an::Property pp = property(p);
        an::StaircaseReport r;
        {
          py::gil_scoped_release release;  // O(n^3) per stair: let other Python threads run
          r = an::staircase(A, BC, pp, st);
        }
        py::dict d = report(r.summary);
        d["stairs"] = r.stairs;
        d["indices"] = r.indices;
        d["Q"] = r.Q;
        d["A_staircase"] = r.A_staircase;
        d["B_staircase"] = r.B_staircase;
        d["A_uncontrollable"] = r.A_uncontrollable;
        d["uncontrollable_modes"] = r.uncontrollable_modes;
        return d;
      },
      SATGNC_RANK_ARGS);
  m.def(
      "_pbh",
      [](const MatrixXd& A, const MatrixXd& BC, const std::string& p, double rtol, double fuzz,
         const std::string& stair, double crt, const std::optional<py::dict>& units) {
        const an::RankSettings st = settings(rtol, fuzz, stair, crt, units);
        const an::Property pp = property(p);
        an::PbhReport r;
        {
          py::gil_scoped_release release;  // one SVD per eigenvalue cluster: seconds for large n
          r = an::pbh(A, BC, pp, st);
        }
        py::dict d = report(r.summary);
        py::list modes;
        for (const an::PbhMode& md : r.modes) {
          py::dict x;
          x["lambda"] = md.lambda;
          x["multiplicity"] = md.multiplicity;
          x["sigma_min"] = md.sigma_min;
          x["deficiency"] = md.deficiency;
          x["controllable"] = md.controllable;
          x["ct_stable"] = md.ct_stable;
          x["dt_stable"] = md.dt_stable;
          x["verdict"] = core::status_message(md.verdict);
          modes.append(x);
        }
        d["modes"] = modes;
        d["stabilizable_ct"] = r.stabilizable_ct;
        d["stabilizable_dt"] = r.stabilizable_dt;
        d["distance_upper_bound"] = r.distance_upper_bound;
        return d;
      },
      SATGNC_RANK_ARGS);
  m.def(
      "_kalman_rank",
      [](const MatrixXd& A, const MatrixXd& BC, const std::string& p, double rtol, double fuzz,
         const std::string& stair, double crt, const std::optional<py::dict>& units) {
        const an::RankSettings st = settings(rtol, fuzz, stair, crt, units);
        const an::Property pp = property(p);
        an::RankReport r;
        {
          py::gil_scoped_release release;
          r = an::kalman_rank(A, BC, pp, st);
        }
        return report(r);
      },
      SATGNC_RANK_ARGS);
  m.def("_kalman_controllability_matrix", &an::kalman_controllability_matrix, py::arg("A"), py::arg("B"),
        py::call_guard<py::gil_scoped_release>());
  m.def("_kalman_observability_matrix", &an::kalman_observability_matrix, py::arg("A"), py::arg("C"),
        py::call_guard<py::gil_scoped_release>());
  m.def(
      "_distance_to_uncontrollability",
      [](const MatrixXd& A, const MatrixXd& BC, const std::string& p, double rtol, double fuzz,
         const std::string& stair, double crt, const std::optional<py::dict>& units, int max_iter) {
        const an::RankSettings st = settings(rtol, fuzz, stair, crt, units);
        const an::Property pp = property(p);
        an::DistanceReport r;
        {
          py::gil_scoped_release release;  // Nelder-Mead over SVDs
          r = an::distance_to_uncontrollability(A, BC, pp, st, max_iter);
        }
        py::dict d;
        d["upper_bound"] = r.upper_bound;
        d["lambda_upper"] = r.lambda_upper;
        d["refined"] = r.refined;
        d["lambda_refined"] = r.lambda_refined;
        d["relative"] = r.relative;
        d["evaluations"] = r.evaluations;
        d["method"] = r.method;
        return d;
      },
      SATGNC_RANK_ARGS, py::arg("max_iter") = 200);
  m.def(
      "_loss_table",
      [](const MatrixXd& A, const MatrixXd& BC, const std::string& p, double rtol, double fuzz,
         const std::string& stair, double crt, const std::optional<py::dict>& units) {
        const an::Property pp = property(p);
        const an::RankSettings st = settings(rtol, fuzz, stair, crt, units);
        std::vector<an::LossRow> table;
        {
          py::gil_scoped_release release;  // 2^m - 1 staircases
          table = an::loss_table(A, BC, pp, st);
        }
        py::list rows;
        for (const an::LossRow& r : table) {
          py::dict x;
          x["channels"] = r.channels;
          x["rank"] = r.rank;
          x["verdict"] = core::status_message(r.verdict);
          x["verdict_text"] = an::verdict_text(r.verdict, pp);
          x["margin"] = r.margin;
          x["kalman_rank"] = r.kalman_rank;
          x["kalman_ratio"] = r.kalman_ratio;
          rows.append(x);
        }
        return rows;
      },
      SATGNC_RANK_ARGS);

  m.def("_expm", &an::expm, py::arg("M"), py::call_guard<py::gil_scoped_release>());
  m.def(
      "_controllability_gramian",
      [](const MatrixXd& A, const MatrixXd& B, double T) {
        an::GramianReport g;
        {
          py::gil_scoped_release release;
          g = an::controllability_gramian(A, B, T);
        }
        return gramian(g);
      },
      py::arg("A"), py::arg("B"), py::arg("T"));
  m.def(
      "_observability_gramian",
      [](const MatrixXd& A, const MatrixXd& C, double T) {
        an::GramianReport g;
        {
          py::gil_scoped_release release;
          g = an::observability_gramian(A, C, T);
        }
        return gramian(g);
      },
      py::arg("A"), py::arg("C"), py::arg("T"));
  m.def(
      "_ltv_observability_gramian",
      [](const std::vector<MatrixXd>& stms, const std::vector<MatrixXd>& H, const std::vector<double>& w) {
        an::GramianReport g;
        {
          py::gil_scoped_release release;
          g = an::ltv_observability_gramian(stms, H, w);
        }
        return gramian(g);
      },
      py::arg("stms"), py::arg("H"), py::arg("weights") = std::vector<double>{});
  m.def(
      "_analyze_gramian",
      [](const MatrixXd& W) {
        an::GramianReport g;
        {
          py::gil_scoped_release release;
          g = an::analyze_gramian(W);
        }
        return gramian(g);
      },
      py::arg("W"));
  m.def(
      "_minimum_energy",
      [](const MatrixXd& W, const VectorXd& xf) { return an::minimum_energy(an::analyze_gramian(W), xf); },
      py::arg("W"), py::arg("x_f"), py::call_guard<py::gil_scoped_release>());
  m.def(
      "_od_observability_gramian",
      [](const Eigen::Matrix<double, 6, 1>& x0, const Eigen::Vector3d& r0, double rate,
         const std::vector<double>& times, const std::string& kind, double mu) {
        an::OdMeasurement k;
        if (kind == "range")
          k = an::OdMeasurement::range;
        else if (kind == "range_rate")
          k = an::OdMeasurement::range_rate;
        else if (kind == "both")
          k = an::OdMeasurement::both;
        else
          throw std::invalid_argument("kind: must be 'range', 'range_rate' or 'both', got '" + kind + "'");
        an::OdGramianReport r;
        {
          py::gil_scoped_release release;
          r = an::od_observability_gramian(x0, dy::Station{r0, rate}, times, k, mu);
        }
        py::dict d = gramian(r.gramian);
        d["jacobi_condition"] = r.jacobi_condition;
        d["singular_values"] = r.singular_values;
        d["sensitivity_condition"] = r.sensitivity_condition;
        d["jacobi_sensitivity_condition"] = r.jacobi_sensitivity_condition;
        d["times"] = r.times;
        return d;
      },
      py::arg("x0"), py::arg("station_r0"), py::arg("rate"), py::arg("times"), py::arg("kind"),
      py::arg("mu"));
  m.def(
      "_visibility_pass",
      [](const Eigen::Matrix<double, 6, 1>& x0, const Eigen::Vector3d& r0, double rate, double mu,
         double t_max, double dt) { return an::visibility_pass(x0, dy::Station{r0, rate}, mu, t_max, dt); },
      py::arg("x0"), py::arg("station_r0"), py::arg("rate"), py::arg("mu"), py::arg("t_max") = 3600.0,
      py::arg("dt") = 10.0, py::call_guard<py::gil_scoped_release>());
}

}  // namespace satgnc::bindings
