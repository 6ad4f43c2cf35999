// pybind11 wrapper of the ensemble propagator (propagation/ensemble.hpp): K initial states in one call,
// the GIL released while the thread pool runs. satgnc.propagation.propagate_ensemble checks the
// arguments and wraps the dict this returns into its frozen result.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "checks.hpp"
#include "satgnc/propagation/ensemble.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {
using propagation::EnsemblePropagator;
using propagation::EnsembleResult;
using propagation::EnsembleSettings;

py::dict to_dict(const EnsembleResult& r) {
  const auto K = static_cast<py::ssize_t>(r.members);
  const auto n = static_cast<py::ssize_t>(r.times.size());
  py::array_t<double> states({K, n, py::ssize_t(6)});
  if (!r.states.empty())
    std::memcpy(states.mutable_data(), r.states.data(), r.states.size() * 6 * sizeof(double));
  py::object stms = py::none();
  if (!r.stms.empty()) {
    py::array_t<double> a({K, n, py::ssize_t(6), py::ssize_t(6)});
    double* d = a.mutable_data();
    for (const Mat6& m : r.stms) {  // Eigen column-major -> numpy row-major
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) *d++ = m(i, j);
    }
    stms = std::move(a);
  }
  py::array_t<double> times(n);
  if (n > 0) std::memcpy(times.mutable_data(), r.times.data(), r.times.size() * sizeof(double));
  py::list status, messages;
  py::array_t<long long> outputs(K), steps(K), rhs_evals(K), rejected(K);
  py::array_t<double> t_reached(K);
  for (py::ssize_t k = 0; k < K; ++k) {
    status.append(std::string(status_name(r.status[k])));
    messages.append(r.messages[k]);
    outputs.mutable_at(k) = static_cast<long long>(r.outputs[k]);
    steps.mutable_at(k) = r.stats[k].steps;
    rhs_evals.mutable_at(k) = r.stats[k].rhs_evals;
    rejected.mutable_at(k) = r.stats[k].error_test_fails;
    t_reached.mutable_at(k) = r.t_reached[k];
  }
  py::dict d;
  d["times"] = times;
  d["states"] = states;
  d["stms"] = stms;
  d["status"] = status;
  d["messages"] = messages;
  d["outputs"] = outputs;
  d["t_reached"] = t_reached;
  d["steps"] = steps;
  d["rhs_evals"] = rhs_evals;
  d["rejected"] = rejected;
  return d;
}

}  // namespace

void init_ensemble(py::module_& m) {
  py::class_<EnsemblePropagator>(m, "EnsemblePropagator",
                                 "DOP853 ensemble propagator (km, km/s, s): a fixed pool of threads started "
                                 "once; per-member step control and status.")
      .def(py::init([](const dynamics::ForceModel& f, py::handle rtol, py::handle atol, py::handle with_stm,
                       py::handle max_steps, py::handle surface_radius, py::handle threads, py::handle simd,
                       py::handle simd_portable) {
             EnsembleSettings s;
             s.integrator.rtol = checks::real_arg(rtol, "rtol");
             s.integrator.atol = checks::real_arg(atol, "atol");
             s.integrator.max_steps =
                 static_cast<long>(checks::int_arg(max_steps, "max_steps", 1, 1LL << 62));
             s.with_stm = checks::bool_arg(with_stm, "with_stm");
             s.surface_radius = checks::real_arg(surface_radius, "surface_radius");
             s.threads = static_cast<int>(checks::int_arg(threads, "threads", 1, 256));
             s.simd = checks::bool_arg(simd, "simd");
             s.simd_portable = checks::bool_arg(simd_portable, "simd_portable");
             return new EnsemblePropagator(f, s);
           }),
           py::arg("force_model"), py::arg("rtol") = propagation::kDefaultOrbitRtol,
           py::arg("atol") = propagation::kDefaultOrbitAtol, py::arg("with_stm") = true,
           py::arg("max_steps") = 100000, py::arg("surface_radius") = 0.0, py::arg("threads") = 1,
           py::arg("simd") = true, py::arg("simd_portable") = false)
      .def_property_readonly("threads", &EnsemblePropagator::threads)
      .def(
          "propagate",
          [](EnsemblePropagator& p, const py::array_t<double, py::array::c_style | py::array::forcecast>& x0,
             py::handle t0, py::handle times) {
            if (x0.ndim() != 2 || x0.shape(1) != 6)
              throw py::value_error("x0: must have shape (K, 6) = K states [r km, v km/s]");
            const auto K = static_cast<std::size_t>(x0.shape(0));
            std::vector<Vec6> xs(K);  // copy: numpy rows need not meet Eigen's alignment
            if (K > 0) std::memcpy(static_cast<void*>(xs.data()), x0.data(), K * 6 * sizeof(double));
            const double t = checks::real_arg(t0, "t0");
            const std::vector<double> ts = checks::vector_arg(times, "times", false);
            EnsembleResult r;
            {
              py::gil_scoped_release release;
              p.propagate(xs.data(), K, t, ts, r);
            }
            return to_dict(r);
          },
          py::arg("x0"), py::arg("t0"), py::arg("times"),
          "Propagate K states x0 (K, 6) from t0 (s) to `times` (s); returns a dict of (K, ...) arrays "
          "and per-member status names and messages.");
}

}  // namespace satgnc::bindings
