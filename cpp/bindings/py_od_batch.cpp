// od room: TrackingData and the batch least-squares estimator (od/tracking_data.hpp, od/batch.hpp).
// Thin wrappers; the Python API with its argument checks is python/satgnc/od/batch.py.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "checks.hpp"
#include "satgnc/io/tdm.hpp"
#include "satgnc/od/batch.hpp"
#include "satgnc/od/tracking_data.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {

using od::TrackingData;
using od::TrackingMeasurement;

// The batch problem of od_batch_estimate / od_batch_evaluate: the data and one BatchStation per station
// ephemeris, biases at zero. The Python objects outlive the call (they are its arguments): the
// ephemerides are held by non-owning pointers.
od::BatchProblem batch_problem(const TrackingData& data, const core::Epoch& epoch, const py::list& stations,
                               const std::vector<bool>& est_range, const std::vector<bool>& est_time) {
  od::BatchProblem p;
  p.epoch = epoch;
  p.data = data;
  for (std::size_t k = 0; k < stations.size(); ++k) {
    const auto& eph = stations[k].cast<const observation::StationEphemeris&>();
    od::BatchStation s;
    s.ephemeris = std::shared_ptr<const observation::StationEphemeris>(&eph, [](const auto*) {});
    s.estimate_range_bias = est_range.at(k);
    s.estimate_time_bias = est_time.at(k);
    p.stations.push_back(std::move(s));
  }
  return p;
}

// TrackingData from arrays: t (s after epoch), types (ints of ObservableType), stations, values (n, 2),
// sigmas (n, 2), corrections (n,).
TrackingData data_from_arrays(const core::Epoch& epoch, const Eigen::VectorXd& t,
                              const Eigen::VectorXi& types, const Eigen::VectorXi& stations,
                              const Eigen::MatrixXd& values, const Eigen::MatrixXd& sigmas,
                              const Eigen::VectorXi& corrections, int n_stations, bool require_sorted) {
  const Eigen::Index n = t.size();
  std::vector<TrackingMeasurement> m(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    TrackingMeasurement& x = m[static_cast<std::size_t>(i)];
    x.epoch = epoch + t[i];
    x.type = static_cast<observation::ObservableType>(types[i]);
    x.station = stations[i];
    x.value = values.row(i).transpose();
    x.sigma = sigmas.row(i).transpose();
    x.corrections = static_cast<std::uint8_t>(corrections[i]);
  }
  return TrackingData(std::move(m), n_stations,
                      require_sorted ? od::TrackingOrder::require_sorted : od::TrackingOrder::sort);
}

py::dict result_dict(const od::BatchResult& r) {
  py::dict d;
  d["status"] = std::string(core::status_name(r.status));
  d["message"] = std::string(core::status_message(r.status));
  d["iterations"] = r.iterations;
  d["evaluations"] = r.info.evaluations;
  d["x0"] = Eigen::VectorXd(r.x0);
  d["range_bias"] = r.range_bias;
  d["time_bias"] = r.time_bias;
  d["parameters"] = r.parameters;
  d["parameter_names"] = r.parameter_names;
  d["covariance"] = r.covariance;
  d["correlation"] = r.correlation;
  d["sigma"] = r.sigma;
  d["rank"] = r.rank;
  d["condition_number"] = r.condition_number;
  d["cost"] = r.cost;
  d["rms"] = r.rms;
  d["residuals"] = r.residuals;
  d["normalized"] = r.normalized;
  d["measurement_status"] = r.measurement_status;
  d["history_cost"] = r.history_cost.head(r.iterations + 1).eval();
  d["step_sigma"] = r.info.dual_residual;
  d["solve_time"] = r.info.solve_time;
  return d;
}

}  // namespace

void init_od_batch(py::module_& m) {
  py::class_<TrackingData>(
      m, "TrackingData",
      "Tracking measurements sorted by reception epoch (od/tracking_data.hpp). Build with "
      "satgnc.od.tracking_data(...) or TrackingData.from_tdm(...).")
      .def_static("from_arrays", &data_from_arrays, py::arg("epoch"), py::arg("t"), py::arg("types"),
                  py::arg("stations"), py::arg("values"), py::arg("sigmas"), py::arg("corrections"),
                  py::arg("n_stations"), py::arg("require_sorted") = false,
                  "From arrays (t: s after epoch; types: observable ints; values, sigmas: (n, 2)).")
      .def_static(
          "from_tdm",
          [](const std::string& path, const std::vector<std::string>& names, const std::vector<int>& indices,
             int n_stations, double s_range, double s_rr, double s_angle) {
            // (names, indices) rather than a dict: the stub-driven argument check reads a Mapping[str, int]
            // annotation as an int.
            if (names.size() != indices.size())
              throw py::value_error("indices: must have one entry per name");
            std::map<std::string, int> stations;
            for (std::size_t i = 0; i < names.size(); ++i) stations[names[i]] = indices[i];
            od::TdmSigmas s;
            s.range = s_range;
            s.range_rate = s_rr;
            s.angle = s_angle;
            return od::tracking_data_from_tdm(io::read_tdm(path), stations, n_stations, s);
          },
          py::arg("path"), py::arg("names"), py::arg("indices"), py::arg("n_stations"),
          py::arg("sigma_range") = 1e-3, py::arg("sigma_range_rate") = 1e-6, py::arg("sigma_angle") = 1e-4,
          "Read a CCSDS TDM (KVN or XML); receiving participant names[i] is station indices[i].")
      .def_property_readonly("size", &TrackingData::size, "number of measurements")
      .def_property_readonly("rows", &TrackingData::rows, "scalar rows (angle pairs count 2)")
      .def_property_readonly("n_stations", &TrackingData::n_stations, "stations the indices refer to")
      .def_property_readonly("input_index", &TrackingData::input_index,
                             "input index of each (sorted) measurement")
      .def("__len__", &TrackingData::size)
      .def(
          "arrays",
          [](const TrackingData& d, const core::Epoch& epoch) {
            const Eigen::Index n = d.size();
            Eigen::VectorXd t(n);
            Eigen::VectorXi types(n), stations(n), corr(n);
            Eigen::MatrixXd values(n, 2), sigmas(n, 2);
            for (Eigen::Index i = 0; i < n; ++i) {
              const TrackingMeasurement& x = d[static_cast<int>(i)];
              t[i] = x.epoch - epoch;
              types[i] = static_cast<int>(x.type);
              stations[i] = x.station;
              values.row(i) = x.value.transpose();
              sigmas.row(i) = x.sigma.transpose();
              corr[i] = x.corrections;
            }
            py::dict out;
            out["t"] = t;
            out["types"] = types;
            out["stations"] = stations;
            out["values"] = values;
            out["sigmas"] = sigmas;
            out["corrections"] = corr;
            return out;
          },
          py::arg("epoch"),
          "Dict of arrays: t (s after epoch), types, stations, values (n, 2), sigmas, corrections.");

  const auto tropo_model = [](const std::string& name) {
    if (name == "saastamoinen") return observation::TroposphereModel::saastamoinen;
    if (name == "mendes_pavlis") return observation::TroposphereModel::mendes_pavlis;
    if (name == "marini_murray") return observation::TroposphereModel::marini_murray;
    throw py::value_error("troposphere: must be 'saastamoinen', 'mendes_pavlis' or 'marini_murray', got '" +
                          name + "'");
  };
  m.def(
      "od_batch_estimate",
      [tropo_model](const TrackingData& data, const core::Epoch& epoch, const py::list& stations,
                    const Eigen::VectorXd& guess, const dynamics::ForceModel& force_model,
                    const std::vector<bool>& est_range, const std::vector<bool>& est_time,
                    const std::vector<double>& range_bias, const std::vector<double>& time_bias,
                    const std::vector<std::string>& names, int max_iterations, double sigma_tol,
                    bool light_time, bool troposphere, bool shapiro, double relative_humidity, double rtol,
                    double atol, const std::string& method, const std::string& troposphere_model,
                    double wavelength_um) {
        od::BatchProblem p = batch_problem(data, epoch, stations, est_range, est_time);
        for (std::size_t k = 0; k < p.stations.size(); ++k) {
          p.stations[k].range_bias = range_bias.at(k);
          p.stations[k].time_bias = time_bias.at(k);
          p.stations[k].name = names.at(k);
        }
        od::BatchSettings s;
        s.max_iterations = max_iterations;
        s.sigma_tol = sigma_tol;
        s.light_time = light_time;
        s.troposphere = troposphere;
        s.shapiro = shapiro;
        s.relative_humidity = relative_humidity;
        s.troposphere_model = tropo_model(troposphere_model);
        s.wavelength_um = wavelength_um;
        if (method == "levenberg_marquardt")
          s.method = od::BatchMethod::levenberg_marquardt;
        else if (method != "gauss_newton")
          throw py::value_error("method: must be 'gauss_newton' or 'levenberg_marquardt', got '" + method +
                                "'");
        propagation::Dop853Settings ds;
        ds.rtol = rtol;
        ds.atol = atol;
        od::BatchEstimator est(std::move(p), std::make_shared<od::Dop853StmPropagator>(force_model, ds), s);
        est.set_initial_guess(Vec6(guess));
        {
          py::gil_scoped_release release;
          est.solve();
        }
        return result_dict(est.result());
      },
      py::arg("data"), py::arg("epoch"), py::arg("stations"), py::arg("x0_guess"), py::arg("force_model"),
      py::arg("estimate_range_bias"), py::arg("estimate_time_bias"), py::arg("range_bias"),
      py::arg("time_bias"), py::arg("names"), py::arg("max_iterations"), py::arg("sigma_tol"),
      py::arg("light_time"), py::arg("troposphere"), py::arg("shapiro"), py::arg("relative_humidity"),
      py::arg("rtol"), py::arg("atol"), py::arg("method") = "gauss_newton",
      py::arg("troposphere_model") = "saastamoinen", py::arg("wavelength_um") = 0.532,
      "Batch least squares (od/batch.hpp) on DOP853 with the force model; returns a dict (see "
      "satgnc.od.batch_estimate).");

  m.def(
      "od_batch_evaluate",
      [tropo_model](const TrackingData& data, const core::Epoch& epoch, const py::list& stations,
                    const Eigen::VectorXd& p_, const dynamics::ForceModel& force_model,
                    const std::vector<bool>& est_range, const std::vector<bool>& est_time, bool light_time,
                    bool troposphere, bool shapiro, double rtol, double atol,
                    const std::string& troposphere_model, double wavelength_um) {
        od::BatchProblem p = batch_problem(data, epoch, stations, est_range, est_time);
        od::BatchSettings s;
        s.light_time = light_time;
        s.troposphere = troposphere;
        s.shapiro = shapiro;
        s.troposphere_model = tropo_model(troposphere_model);
        s.wavelength_um = wavelength_um;
        propagation::Dop853Settings ds;
        ds.rtol = rtol;
        ds.atol = atol;
        od::BatchEstimator est(std::move(p), std::make_shared<od::Dop853StmPropagator>(force_model, ds), s);
        Eigen::VectorXd r;
        Eigen::MatrixXd J;
        const bool ok = est.evaluate(p_, r, J);
        return py::make_tuple(ok, r, J);
      },
      py::arg("data"), py::arg("epoch"), py::arg("stations"), py::arg("parameters"), py::arg("force_model"),
      py::arg("estimate_range_bias"), py::arg("estimate_time_bias"), py::arg("light_time"),
      py::arg("troposphere"), py::arg("shapiro"), py::arg("rtol"), py::arg("atol"),
      py::arg("troposphere_model") = "saastamoinen", py::arg("wavelength_um") = 0.532,
      "(ok, whitened residuals (O - C)/sigma, whitened Jacobian d predicted/sigma / dp) at parameters.");
}

}  // namespace satgnc::bindings
