// pybind11 wrappers for the filter room (issue 15, generic engine): one run of the KalmanFilter on
// the generic models (linear process; linear or beacon-range measurements), the RTS smoother, the
// chi-square quantile and a private timing loop of one EKF update for bench/filter_update.py.
// The orbit filter's public API is satgnc.od (KF15B); python/satgnc/filter wraps these for tests.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "satgnc/filter/gating.hpp"
#include "satgnc/filter/kalman_filter.hpp"
#include "satgnc/filter/linear_models.hpp"
#include "satgnc/filter/rts.hpp"
#include "status.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {

using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

filter::FilterSettings make_settings(const py::dict& s) {
  filter::FilterSettings out;
  for (auto item : s) {
    const auto key = item.first.cast<std::string>();
    const py::handle v = item.second;
    if (key == "algorithm") {
      const auto a = v.cast<std::string>();
      if (a != "ekf" && a != "ukf")
        throw std::invalid_argument("algorithm: must be 'ekf' or 'ukf', got '" + a + "'");
      out.algorithm = a == "ekf" ? filter::FilterAlgorithm::ekf : filter::FilterAlgorithm::ukf;
    } else if (key == "form") {
      const auto f = v.cast<std::string>();
      if (f == "joseph") {
        out.form = filter::CovarianceForm::joseph;
      } else if (f == "ud") {
        out.form = filter::CovarianceForm::ud;
      } else if (f == "conventional") {
        out.form = filter::CovarianceForm::conventional;
      } else {
        throw std::invalid_argument("form: must be 'joseph', 'ud' or 'conventional', got '" + f + "'");
      }
    } else if (key == "sequential") {
      out.sequential = v.cast<bool>();
    } else if (key == "iterated") {
      out.iterated = v.cast<bool>();
    } else if (key == "max_iterations") {
      out.max_iterations = v.cast<int>();
    } else if (key == "iteration_tolerance") {
      out.iteration_tolerance = v.cast<double>();
    } else if (key == "ukf_alpha") {
      out.ukf_alpha = v.cast<double>();
    } else if (key == "ukf_beta") {
      out.ukf_beta = v.cast<double>();
    } else if (key == "ukf_kappa") {
      out.ukf_kappa = v.cast<double>();
    } else if (key == "consider_count") {
      out.consider_count = v.cast<int>();
    } else if (key == "gating") {
      out.gating = v.cast<bool>();
    } else if (key == "gate_probability") {
      out.gate_probability = v.cast<double>();
    } else if (key == "warm_up") {
      out.warm_up = v.cast<double>();
    } else if (key == "check_covariance") {
      out.check_covariance = v.cast<bool>();
    } else {
      throw std::invalid_argument("settings: unknown key '" + key + "'");
    }
  }
  out.validate();
  return out;
}

// (N, n, n) array from an n x (n N) block matrix (block k = matrix k).
py::array_t<double> blocks(const Eigen::MatrixXd& m, int n, int steps) {
  py::array_t<double> out({steps, n, n});
  auto a = out.mutable_unchecked<3>();
  for (int k = 0; k < steps; ++k)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) a(k, i, j) = m(i, static_cast<Eigen::Index>(k) * n + j);
  return out;
}

py::dict run(const Eigen::MatrixXd& phi, const Eigen::MatrixXd& qd, const std::string& kind,
             const std::vector<Eigen::MatrixXd>& h_by_type, const Eigen::MatrixXd& beacons,
             const Eigen::VectorXd& x0, const Eigen::MatrixXd& p0, double t0, const Eigen::VectorXd& t,
             const Eigen::VectorXi& type, const Eigen::VectorXi& station, const RowMat& value,
             const RowMat& sigma, const py::dict& settings, bool smooth) {
  const filter::FilterSettings s = make_settings(settings);
  filter::LinearProcessModel proc(phi, qd);
  std::unique_ptr<filter::MeasurementFunction> meas;
  if (kind == "linear") {
    meas = std::make_unique<filter::LinearMeasurementFunction>(h_by_type);
  } else if (kind == "beacon") {
    meas = std::make_unique<filter::BeaconRangeFunction>(beacons, static_cast<int>(phi.rows()));
  } else {
    throw std::invalid_argument("measurement: must be 'linear' or 'beacon', got '" + kind + "'");
  }
  const Eigen::Index N = t.size();
  if (type.size() != N || station.size() != N || value.rows() != N || sigma.rows() != N) {
    throw std::invalid_argument("records: t, type, station, value and sigma must have the same length");
  }
  if (value.cols() > filter::kMaxMeasurementDim || sigma.cols() != value.cols()) {
    throw std::invalid_argument("value: must have at most 3 columns, and sigma the same shape");
  }
  filter::FilterProblem p;
  p.x0 = x0;
  p.p0 = p0;
  p.t0 = t0;
  p.records.resize(static_cast<std::size_t>(N));
  for (Eigen::Index k = 0; k < N; ++k) {
    auto& r = p.records[static_cast<std::size_t>(k)];
    r.t = t(k);
    r.type = type(k);
    r.station = station(k);
    for (Eigen::Index j = 0; j < value.cols(); ++j) {
      r.value[static_cast<std::size_t>(j)] = value(k, j);
      r.sigma[static_cast<std::size_t>(j)] = sigma(k, j);
    }
  }
  filter::KalmanFilter kf(proc, *meas, p, s);
  const int n = static_cast<int>(x0.size());
  const int steps = static_cast<int>(N);
  {
    py::gil_scoped_release release;
    kf.solve();
  }
  const filter::FilterResult& r = kf.result();
  py::dict out;
  out["times"] = r.times;
  out["states"] = RowMat(r.states.transpose());
  out["covariances"] = blocks(r.covariances, n, steps);
  out["predicted_states"] = RowMat(r.predicted_states.transpose());
  out["predicted_covariances"] = blocks(r.predicted_covariances, n, steps);
  const int M = filter::kMaxMeasurementDim;
  RowMat prefit(steps, M), postfit(steps, M), isig(steps, M), norm(steps, M);
  Eigen::VectorXd nis(steps), gate(steps);
  Eigen::VectorXi flag(steps), status(steps), iterations(steps), dim(steps);
  for (int k = 0; k < steps; ++k) {
    const auto& rec = r.records[static_cast<std::size_t>(k)];
    for (int j = 0; j < M; ++j) {
      const auto ju = static_cast<std::size_t>(j);
      prefit(k, j) = rec.prefit[ju];
      postfit(k, j) = rec.postfit[ju];
      isig(k, j) = rec.innovation_sigma[ju];
      norm(k, j) = rec.normalized[ju];
    }
    nis(k) = rec.nis;
    gate(k) = rec.gate;
    flag(k) = static_cast<int>(rec.flag);
    status(k) = static_cast<int>(rec.status);
    iterations(k) = rec.iterations;
    dim(k) = rec.dim;
  }
  out["prefit"] = prefit;
  out["postfit"] = postfit;
  out["innovation_sigma"] = isig;
  out["normalized"] = norm;
  out["nis"] = nis;
  out["gate"] = gate;
  out["flag"] = flag;
  out["step_status"] = status;
  out["iterations"] = iterations;
  out["dim"] = dim;
  out["status"] = static_cast<int>(r.info.status);
  out["accepted"] = r.info.accepted;
  out["rejected"] = r.info.rejected;
  out["failed"] = r.info.failed;
  out["first_failure"] = r.info.first_failure;
  out["residual_rms"] = r.info.primal_residual;
  out["solve_time"] = r.info.solve_time;
  if (smooth) {
    filter::RtsSmoother sm(n, steps);
    const filter::SmootherResult& sr = sm.smooth(r);
    out["smoother_status"] = static_cast<int>(sr.status);
    out["smoother_factored"] = sr.factored;
    out["smoothed_initial_state"] = sr.initial_state;
    out["smoothed_initial_covariance"] = sr.initial_covariance;
    out["smoothed_states"] = RowMat(sr.states.transpose());
    out["smoothed_covariances"] = blocks(sr.covariances, n, steps);
  }
  return out;
}

// Private timing loop: one EKF update (n states, one scalar linear measurement, Joseph form, no
// gate, no PD check), `repeats` updates at the same epoch per sample, best of `samples`; ns per update.
double bench_update(const Eigen::MatrixXd& p0, const Eigen::RowVectorXd& h, double sigma, double z,
                    int repeats, int samples, const std::string& form) {
  const int n = static_cast<int>(p0.rows());
  filter::LinearProcessModel proc(Eigen::MatrixXd::Identity(n, n), Eigen::MatrixXd::Zero(n, n));
  filter::LinearMeasurementFunction meas({Eigen::MatrixXd(h)});
  filter::FilterProblem p;
  p.x0 = Eigen::VectorXd::Zero(n);
  p.p0 = p0;
  filter::FilterSettings s;
  s.gating = false;
  s.check_covariance = false;
  s.form = form == "ud" ? filter::CovarianceForm::ud : filter::CovarianceForm::joseph;
  filter::KalmanFilter kf(proc, meas, p, s);
  filter::MeasurementRecord rec;
  rec.t = 0.0;
  rec.value[0] = z;
  rec.sigma[0] = sigma;
  double best = std::numeric_limits<double>::infinity();
  py::gil_scoped_release release;
  for (int smp = 0; smp < samples; ++smp) {
    kf.initialize();
    const auto a = std::chrono::steady_clock::now();
    for (int i = 0; i < repeats; ++i) kf.update(rec);  // same epoch: no propagation, P shrinks ~1/i
    const auto b = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(b - a).count() / repeats);
  }
  return best;
}

}  // namespace

void init_filter(py::module_& m) {
  bind_status<filter::FilterStatus>(m, "FilterStatus");
  bind_status<filter::EditFlag>(m, "FilterEditFlag");
  m.def("_filter_run", &run, py::arg("phi"), py::arg("qd"), py::arg("measurement"), py::arg("h_by_type"),
        py::arg("beacons"), py::arg("x0"), py::arg("p0"), py::arg("t0"), py::arg("t"), py::arg("type"),
        py::arg("station"), py::arg("value"), py::arg("sigma"), py::arg("settings"), py::arg("smooth"),
        "Private: one KalmanFilter run on the generic models (satgnc.filter.run_filter).");
  m.def(
      "_chi_square_quantile", [](double dof, double p) { return filter::chi_square_quantile(dof, p); },
      py::arg("dof"), py::arg("probability"),
      "Private: chi-square quantile (satgnc.filter.chi_square_quantile).");
  m.def("_filter_bench_update", &bench_update, py::arg("p0"), py::arg("h"), py::arg("sigma"), py::arg("z"),
        py::arg("repeats"), py::arg("samples"), py::arg("form"),
        "Private: ns per EKF update, best of samples (bench/filter_update.py).");
}

}  // namespace satgnc::bindings
