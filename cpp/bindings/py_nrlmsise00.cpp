// pybind11 wrappers of dynamics/nrlmsise00.hpp: the NRLMSISE-00 AtmosphereModel (for AtmosphereDrag)
// and the model's direct evaluation. Units: km, deg, hours, s; number densities m^-3, mass density
// kg/m^3, temperatures K. Registered after init_atmosphere (the base class AtmosphereModel).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "satgnc/core/validate.hpp"
#include "satgnc/dynamics/nrlmsise00.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {
namespace dy = satgnc::dynamics;

// The model's switches 1..23 from a list of 23 numbers (None: all 1).
dy::Nrlmsise00Switches switches_arg(const std::optional<std::vector<double>>& s) {
  dy::Nrlmsise00Switches out = dy::nrlmsise00_default_switches();
  if (s) {
    core::require(s->size() == 23, "switches",
                  "must have 23 entries (switches 1..23), got " + std::to_string(s->size()));
    for (int i = 0; i < 23; ++i) out[i + 1] = (*s)[i];
  }
  return out;
}

// The 7-value Ap history from a list (None: not used).
std::optional<std::array<double, 7>> ap_history_arg(const std::optional<std::vector<double>>& a) {
  if (!a) return std::nullopt;
  core::require(a->size() == 7, "ap_history", "must have 7 entries, got " + std::to_string(a->size()));
  std::array<double, 7> out{};
  for (int i = 0; i < 7; ++i) out[i] = (*a)[i];
  return out;
}

py::dict output_dict(const dy::Nrlmsise00Output& o) {
  py::dict d;
  d["he"] = o.he;
  d["o"] = o.o;
  d["n2"] = o.n2;
  d["o2"] = o.o2;
  d["ar"] = o.ar;
  d["h"] = o.h;
  d["n"] = o.n;
  d["anomalous_o"] = o.anomalous_o;
  d["mass_density"] = o.mass_density;
  d["exospheric_temperature"] = o.exospheric_temperature;
  d["temperature"] = o.temperature;
  return d;
}
}  // namespace

void init_nrlmsise00(py::module_& m) {
  py::class_<dy::Nrlmsise00, dy::AtmosphereModel, std::shared_ptr<dy::Nrlmsise00>>(
      m, "Nrlmsise00",
      "NRLMSISE-00 (Picone et al. 2002) total mass density, kg/m^3, with the anomalous-oxygen drag density "
      "option; inputs from the ITRF position, the Sun direction and the epoch + t.")
      .def(
          py::init([](double epoch_jd1, double epoch_jd2, const dy::SpaceWeather& space_weather,
                      const std::optional<std::vector<double>>& ap_history_list, bool anomalous_oxygen,
                      const std::optional<std::vector<double>>& switches, double gradient_step) {
            const std::optional<std::array<double, 7>> ap_history = ap_history_arg(ap_history_list);
            dy::Nrlmsise00Settings s;
            s.epoch_jd1 = epoch_jd1;
            s.epoch_jd2 = epoch_jd2;
            s.space_weather = space_weather;
            if (ap_history) {
              s.ap_history = *ap_history;
              s.use_ap_history = true;
            }
            s.anomalous_oxygen = anomalous_oxygen;
            s.switches = switches_arg(switches);
            s.gradient_step = gradient_step;
            return std::make_shared<dy::Nrlmsise00>(s);
          }),
          py::kw_only(), py::arg("epoch_jd1") = 2451545.0, py::arg("epoch_jd2") = 0.0,
          py::arg("space_weather") = dy::SpaceWeather{}, py::arg("ap_history") = py::none(),
          py::arg("anomalous_oxygen") = true, py::arg("switches") = py::none(),
          py::arg("gradient_step") = 1.0e-2,
          "epoch of t = 0 as a two-part TT Julian date (days); space_weather: F10.7, F10.7a (sfu), daily Ap; "
          "ap_history: 7 Ap values (daily; 3-h now, -3 h, -6 h, -9 h; means of 12-33 h and 36-57 h before), "
          "given = switch 9 is -1; anomalous_oxygen: GTD7D drag density (True) or GTD7 mass density; "
          "switches: the model's 23 switches 1..23 (0, 1 or 2; switch 9 also -1); gradient_step km "
          "(central difference).")
      .def(
          "inputs",
          [](const dy::Nrlmsise00& a, const Vec3& r_itrf, const Vec3& sun_itrf, double t) {
            const dy::Nrlmsise00Input in = a.input(dy::atmosphere_point(t, r_itrf, sun_itrf));
            py::dict d;
            d["day_of_year"] = in.day_of_year;
            d["ut_seconds"] = in.ut_seconds;
            d["altitude"] = in.altitude;
            d["latitude"] = in.latitude;
            d["longitude"] = in.longitude;
            d["local_solar_time"] = in.local_solar_time;
            return d;
          },
          py::arg("r_itrf"), py::arg("sun_itrf"), py::arg("t") = 0.0,
          "The model's inputs at r_itrf (km) with the Sun along sun_itrf (ITRF) at t s: day_of_year, "
          "ut_seconds (s), altitude (km), latitude, longitude (deg), local_solar_time (h, apparent).")
      .def("__repr__", [](const dy::Nrlmsise00& a) {
        std::ostringstream s;
        s.precision(12);
        const auto& st = a.settings();
        s << "Nrlmsise00(epoch_jd1=" << st.epoch_jd1 << ", epoch_jd2=" << st.epoch_jd2
          << ", f107=" << st.space_weather.f107 << ", f107a=" << st.space_weather.f107a
          << ", ap=" << st.space_weather.ap
          << ", anomalous_oxygen=" << (st.anomalous_oxygen ? "True" : "False") << ")";
        return s.str();
      });

  m.def(
      "_nrlmsise00_evaluate",
      [](int day_of_year, double ut_seconds, double altitude, double latitude, double longitude,
         double local_solar_time, double f107a, double f107, double ap,
         const std::optional<std::vector<double>>& ap_history_list, bool anomalous_oxygen,
         const std::optional<std::vector<double>>& switches) {
        const std::optional<std::array<double, 7>> ap_history = ap_history_arg(ap_history_list);
        dy::Nrlmsise00Input in;
        in.day_of_year = day_of_year;
        in.ut_seconds = ut_seconds;
        in.altitude = altitude;
        in.latitude = latitude;
        in.longitude = longitude;
        in.local_solar_time = local_solar_time;
        in.f107a = f107a;
        in.f107 = f107;
        in.ap = ap;
        dy::Nrlmsise00Switches sw = switches_arg(switches);
        if (ap_history) {
          in.ap_history = *ap_history;
          sw[9] = -1.0;
        }
        in.validate("nrlmsise00");
        dy::nrlmsise00_validate_switches(sw, "switches");
        return output_dict(dy::nrlmsise00(in, sw, anomalous_oxygen));
      },
      py::arg("day_of_year"), py::arg("ut_seconds"), py::arg("altitude"), py::arg("latitude"),
      py::arg("longitude"), py::arg("local_solar_time"), py::arg("f107a"), py::arg("f107"), py::arg("ap"),
      py::arg("ap_history"), py::arg("anomalous_oxygen"), py::arg("switches"),
      "Private: one NRLMSISE-00 evaluation (satgnc.dynamics.nrlmsise00 wraps it in a result).");
}

}  // namespace satgnc::bindings
