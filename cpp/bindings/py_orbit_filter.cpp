// pybind11 wrappers of the orbit filter (filter/orbit_*.hpp): one call runs the EKF (and, asked, the RTS
// smoother) and returns time-major arrays; the Python API satgnc.od.filter validates the arguments and
// builds its frozen result on top. Also the process model alone, for tests and the bench.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <vector>

#include "satgnc/filter/orbit_filter.hpp"
#include "satgnc/filter/orbit_measurement.hpp"
#include "satgnc/filter/orbit_process_model.hpp"
#include "satgnc/filter/status.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {
using filter::OrbitFilter;
using filter::OrbitFilterResult;
using filter::OrbitFilterSettings;
using filter::OrbitMeasurement;
using filter::OrbitMeasurementFunction;
using filter::OrbitMeasurementSettings;
using filter::OrbitProcessModel;
using filter::OrbitProcessSettings;

std::shared_ptr<const observation::StationEphemeris> station_copy(py::handle h, std::size_t i) {
  if (py::isinstance<observation::RotatingStationEphemeris>(h))
    return std::make_shared<observation::RotatingStationEphemeris>(
        h.cast<observation::RotatingStationEphemeris>());
  if (py::isinstance<observation::EarthFixedStationEphemeris>(h))
    return std::make_shared<observation::EarthFixedStationEphemeris>(
        h.cast<observation::EarthFixedStationEphemeris>());
  throw py::type_error("stations[" + std::to_string(i) +
                       "]: must be a RotatingStationEphemeris or EarthFixedStationEphemeris");
}

OrbitProcessSettings process_settings(const py::dict& d) {
  OrbitProcessSettings s;
  s.snc_psd_ric = d["snc_psd_ric"].cast<Vec3>();
  s.dmc = d["dmc"].cast<bool>();
  s.dmc_tau = d["dmc_tau"].cast<Vec3>();
  s.dmc_sigma = d["dmc_sigma"].cast<Vec3>();
  s.parameters = d["parameters"].cast<int>();
  s.noise_step = d["noise_step"].cast<double>();
  s.quadrature_nodes = d["quadrature_nodes"].cast<int>();
  s.integrator.rtol = d["rtol"].cast<double>();
  s.integrator.atol = d["atol"].cast<double>();
  if (d.contains("cd_state")) s.cd_state = d["cd_state"].cast<int>();
  if (d.contains("cr_state")) s.cr_state = d["cr_state"].cast<int>();
  return s;
}

template <class T>
py::array_t<T> arr(const std::vector<T>& v, std::vector<py::ssize_t> shape) {
  py::array_t<T> a(shape);
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

py::dict run_filter(const dynamics::ForceModel& fm, const py::list& stations, const py::list& models,
                    const py::dict& process, const py::dict& stn, const py::dict& fset, double t0,
                    const Eigen::VectorXd& x0, const Eigen::MatrixXd& p0, const std::vector<double>& t,
                    const std::vector<int>& station, const std::vector<int>& observable,
                    const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>& value, bool smooth) {
  OrbitProcessModel pm(fm, process_settings(process));
  const int n = pm.dimension();
  OrbitMeasurementSettings ms;
  for (py::handle h : models)
    ms.observables.push_back(h.cast<const observation::MeasurementModel&>().settings());
  const auto sigma =
      stn["sigma"].cast<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>();
  const auto rbs = stn["range_bias_state"].cast<std::vector<int>>();
  const auto tbs = stn["time_bias_state"].cast<std::vector<int>>();
  const auto rb = stn["range_bias"].cast<std::vector<double>>();
  const auto tb = stn["time_bias"].cast<std::vector<double>>();
  for (std::size_t i = 0; i < stations.size(); ++i) {
    filter::OrbitStation s;
    s.ephemeris = station_copy(stations[i], i);
    for (Eigen::Index k = 0; k < sigma.cols(); ++k) s.sigma.push_back(sigma(static_cast<Eigen::Index>(i), k));
    s.range_bias_state = rbs.at(i);
    s.time_bias_state = tbs.at(i);
    s.range_bias = rb.at(i);
    s.time_bias = tb.at(i);
    ms.stations.push_back(std::move(s));
  }
  OrbitMeasurementFunction mf(ms, n);
  OrbitFilterSettings fs;
  fs.gating = fset["gating"].cast<bool>();
  fs.gate_probability = fset["gate_probability"].cast<double>();
  fs.warmup = fset["warmup"].cast<int>();
  fs.consider = fset["consider"].cast<std::vector<int>>();
  fs.method = fset["method"].cast<std::string>() == "ukf" ? filter::OrbitFilterMethod::ukf
                                                          : filter::OrbitFilterMethod::ekf;
  OrbitFilter f(std::move(pm), std::move(mf), fs);
  std::vector<OrbitMeasurement> meas(t.size());
  for (std::size_t k = 0; k < t.size(); ++k)
    meas[k] = {t[k], station.at(k), observable.at(k), value.row(static_cast<Eigen::Index>(k)).transpose()};
  OrbitFilterResult r;
  filter::OrbitSmootherResult s;
  {
    py::gil_scoped_release release;
    r = f.run(t0, x0, p0, meas);
    if (smooth && r.steps_run > 0) s = OrbitFilter::smooth(r);
  }
  const py::ssize_t K = static_cast<py::ssize_t>(t.size()), N = n;
  py::dict out;
  out["t"] = arr(r.t, {K});
  out["station"] = arr(r.station, {K});
  out["observable"] = arr(r.observable, {K});
  out["size"] = arr(r.size, {K});
  std::vector<int> st(r.status.size());
  for (std::size_t k = 0; k < st.size(); ++k) st[k] = static_cast<int>(r.status[k]);
  out["status"] = arr(st, {K});
  out["state"] = arr(r.state, {K, N});
  out["covariance"] = arr(r.covariance, {K, N, N});
  out["prefit"] = arr(r.prefit, {K, 2});
  out["postfit"] = arr(r.postfit, {K, 2});
  out["sigma"] = arr(r.sigma, {K, 2});
  out["nis"] = arr(r.nis, {K});
  out["normalized_residual"] = arr(r.normalized_residual, {K});
  out["gate"] = arr(r.gate, {K});
  out["steps_run"] = r.steps_run;
  out["rejected"] = r.rejected;
  out["propagation_steps"] = r.propagation_steps;
  out["solve_time"] = r.solve_time;
  if (smooth && r.steps_run > 0) {
    const py::ssize_t Ks = static_cast<py::ssize_t>(s.t.size());
    out["smoothed_t"] = arr(s.t, {Ks});
    out["smoothed_state"] = arr(s.state, {Ks, N});
    out["smoothed_covariance"] = arr(s.covariance, {Ks, N, N});
    out["smoothed_initial_state"] = s.initial_state;
    out["smoothed_initial_covariance"] = s.initial_covariance;
  }
  return out;
}

py::tuple propagate_process(const dynamics::ForceModel& fm, const py::dict& process, double t0, double t1,
                            const Eigen::VectorXd& x) {
  OrbitProcessModel pm(fm, process_settings(process));
  const int n = pm.dimension();
  if (x.size() != n) throw py::value_error("x: must have " + std::to_string(n) + " entries");
  Eigen::VectorXd y = x;
  Eigen::MatrixXd phi(n, n), q(n, n);
  const auto info = pm.propagate(t0, t1, y, phi, q);
  return py::make_tuple(y, phi, q, std::string(core::status_name(info.status)), info.steps);
}
}  // namespace

void init_orbit_filter(py::module_& m) {
  m.def("filter_orbit_run", &run_filter, py::arg("force_model"), py::arg("stations"), py::arg("models"),
        py::arg("process"), py::arg("station_setup"), py::arg("filter_settings"), py::arg("t0"),
        py::arg("x0"), py::arg("P0"), py::arg("t"), py::arg("station"), py::arg("observable"),
        py::arg("value"), py::arg("smooth") = false,
        "Private: the orbit EKF (filter/orbit_filter.hpp) over K measurements; dict of time-major arrays "
        "(use satgnc.od.filter).");
  m.def("filter_orbit_propagate", &propagate_process, py::arg("force_model"), py::arg("process"),
        py::arg("t0"), py::arg("t1"), py::arg("x"),
        "Private: OrbitProcessModel.propagate -> (x, Phi, Q, status, steps) (use satgnc.od.filter).");
  // Step status names by value, from the table (filter/status.hpp): an appended status is listed too.
  const auto table = core::status_table<filter::OrbitStepStatus>();
  py::list names(table.size());
  for (const core::StatusEntry& row : table) names[static_cast<std::size_t>(row.value)] = row.name;
  m.attr("FILTER_STEP_STATUS") = names;
}

}  // namespace satgnc::bindings
