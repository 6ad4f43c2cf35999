// pybind11 wrappers for the observation room: station ephemerides, light-time measurement models
// (vectorized over tags), the modifiers and a private timing loop for bench/observation.py. The
// Python package satgnc.observation builds its frozen results on top of these.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "checks.hpp"
#include "satgnc/dynamics/station.hpp"
#include "satgnc/frames/earth_orientation.hpp"
#include "satgnc/frames/earth_rotation.hpp"
#include "satgnc/frames/ground_station.hpp"
#include "satgnc/observation/light_time.hpp"
#include "satgnc/observation/measurement_model.hpp"
#include "satgnc/observation/modifiers.hpp"
#include "satgnc/observation/station_ephemeris.hpp"
#include "status.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {
using observation::Biases;
using observation::MeasurementModel;
using observation::MeasurementSettings;
using observation::Prediction;
using observation::StationEphemeris;

// Per-tag biases: a scalar for every tag or an (n,) array.
std::vector<double> per_tag(py::handle h, const std::string& name, std::size_t n) {
  std::vector<double> v = checks::vector_arg(h, name);
  if (v.size() == 1) v.assign(n, v[0]);
  if (v.size() != n)
    throw py::value_error(name + ": must be a number or have shape (" + std::to_string(n) + ",), got " +
                          std::to_string(v.size()) + " values");
  return v;
}

py::dict predict_many(const MeasurementModel& model, const StationEphemeris& station, py::handle t_,
                      py::handle states_, py::handle range_bias_, py::handle time_bias_) {
  const std::vector<double> t = checks::vector_arg(t_, "t");
  py::array sa = checks::real_array(states_, "states");
  if (sa.ndim() == 1) sa = py::module_::import("numpy").attr("atleast_2d")(sa);
  if (sa.ndim() != 2 || sa.shape(1) != 6)
    throw py::value_error("states: must have shape (n, 6) (km, km/s, GCRF), got " + checks::shape_text(sa));
  if (static_cast<std::size_t>(sa.shape(0)) != t.size())
    throw py::value_error("states: must have one row per tag in t (" + std::to_string(t.size()) + "), got " +
                          std::to_string(sa.shape(0)));
  const Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor> X =
      sa.cast<Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>>();
  if (!X.allFinite()) throw py::value_error("states: must be finite (no NaN or Inf)");
  const std::size_t n = t.size();
  const std::vector<double> rb = per_tag(range_bias_, "range_bias", n);
  const std::vector<double> tb = per_tag(time_bias_, "time_bias", n);
  const py::ssize_t N = static_cast<py::ssize_t>(n);
  py::array_t<double> value({N, py::ssize_t(2)}), dx({N, py::ssize_t(2), py::ssize_t(6)}),
      dbias({N, py::ssize_t(2), py::ssize_t(2)}), tau_d(N), tau_u(N), tropo(N), shapiro(N);
  py::array_t<int> status(N), iterations(N);
  {
    auto v = value.mutable_unchecked<2>();
    auto j = dx.mutable_unchecked<3>();
    auto b = dbias.mutable_unchecked<3>();
    auto td = tau_d.mutable_unchecked<1>();
    auto tu = tau_u.mutable_unchecked<1>();
    auto tr = tropo.mutable_unchecked<1>();
    auto sh = shapiro.mutable_unchecked<1>();
    auto st = status.mutable_unchecked<1>();
    auto it = iterations.mutable_unchecked<1>();
    py::gil_scoped_release release;
    Prediction p;
    for (py::ssize_t k = 0; k < N; ++k) {
      const Vec6 x = X.row(k).transpose();
      model.predict(station, t[k], x, Biases{rb[k], tb[k]}, p);
      for (int i = 0; i < 2; ++i) {
        v(k, i) = p.value(i);
        for (int c = 0; c < 6; ++c) j(k, i, c) = p.dx(i, c);
        for (int c = 0; c < 2; ++c) b(k, i, c) = p.dbias(i, c);
      }
      td(k) = p.tau_down;
      tu(k) = p.tau_up;
      tr(k) = p.troposphere;
      sh(k) = p.shapiro;
      st(k) = static_cast<int>(p.status);
      it(k) = p.iterations;
    }
  }
  py::dict d;
  d["value"] = value;
  d["dx"] = dx;
  d["dbias"] = dbias;
  d["tau_down"] = tau_d;
  d["tau_up"] = tau_u;
  d["troposphere"] = tropo;
  d["shapiro"] = shapiro;
  d["status"] = status;
  d["iterations"] = iterations;
  return d;
}
// Surface weather from Python numbers (hPa, K, hPa), each checked and named.
observation::Weather weather_arg(py::handle p_, py::handle t_, py::handle e_) {
  observation::Weather w;
  w.pressure = checks::real_arg(p_, "pressure");
  w.temperature = checks::real_arg(t_, "temperature");
  w.water_vapour = checks::real_arg(e_, "water_vapour");
  if (!(w.pressure >= 0.0)) throw py::value_error("pressure: must be >= 0 hPa");
  if (!(w.temperature > 0.0)) throw py::value_error("temperature: must be > 0 K");
  if (!(w.water_vapour >= 0.0)) throw py::value_error("water_vapour: must be >= 0 hPa");
  return w;
}

}  // namespace

void init_observation(py::module_& m) {
  bind_status<core::ObservationStatus>(m, "ObservationStatus");
  m.attr("SPEED_OF_LIGHT") = observation::speed_of_light;  // km/s

  py::class_<StationEphemeris>(m, "StationEphemeris",
                               "GCRF ephemeris of a tracking station (km, km/s; t in s after its epoch).")
      .def(
          "state",
          [](const StationEphemeris& s, py::handle t_) {
            const double t = checks::real_arg(t_, "t");
            observation::StationState out;
            s.state(t, out);
            return py::make_tuple(out.r, out.v, out.a, out.enu);
          },
          py::arg("t"), "(r km, v km/s, a km/s^2, enu 3x3 rows east/north/up) in GCRF at t (s).")
      .def_property_readonly("latitude", &StationEphemeris::latitude, "geodetic latitude, rad")
      .def_property_readonly("height", &StationEphemeris::height, "height above the ellipsoid, km");

  py::class_<observation::RotatingStationEphemeris, StationEphemeris>(
      m, "RotatingStationEphemeris",
      "The paper's rotating station (Station: inertial r0 at t = 0 turning about +z) as a StationEphemeris.")
      .def(py::init([](const dynamics::Station& station, const std::string& ellipsoid) {
             return observation::RotatingStationEphemeris(station, dynamics::ellipsoid_by_name(ellipsoid));
           }),
           py::arg("station"), py::arg("ellipsoid") = "WGS-84")
      .def_property_readonly("station", &observation::RotatingStationEphemeris::station);

  py::class_<observation::EarthFixedStationEphemeris, StationEphemeris>(
      m, "EarthFixedStationEphemeris",
      "Station fixed in the ITRF at WGS-84 geodetic coordinates, carried to GCRF by an Earth rotation model "
      "(here: uniform rotation by theta0 + omega t about +z).")
      .def(py::init(
               [](py::handle lat_, py::handle lon_, py::handle h_, py::handle theta0_, py::handle omega_) {
                 const double lat = checks::real_arg(lat_, "latitude_deg");
                 const double lon = checks::real_arg(lon_, "longitude_deg");
                 const double h = checks::real_arg(h_, "height_km");
                 const double theta0 = checks::real_arg(theta0_, "theta0");
                 const double omega = checks::real_arg(omega_, "omega");
                 constexpr double kDeg = 3.14159265358979323846 / 180.0;
                 if (std::abs(lat) > 90.0) throw py::value_error("latitude_deg: must be within [-90, 90]");
                 return observation::EarthFixedStationEphemeris(
                     lat * kDeg, lon * kDeg, h, std::make_shared<frames::UniformRotation>(theta0, omega));
               }),
           py::arg("latitude_deg"), py::arg("longitude_deg"), py::arg("height_km"), py::arg("theta0") = 0.0,
           py::arg("omega") = core::earth::omega)
      .def_static(
          "from_ground_station",
          [](const frames::GroundStation& station, const frames::IauEarthRotation& rotation) {
            return observation::EarthFixedStationEphemeris::from_ground_station(
                station, std::make_shared<frames::IauEarthRotation>(rotation));
          },
          py::arg("station"), py::arg("rotation"),
          "The GroundStation carried to GCRF by the IAU 2006/2000A chain with EOP (t = s after "
          "rotation.epoch).")
      .def_property_readonly("longitude", &observation::EarthFixedStationEphemeris::longitude, "rad (east)")
      .def_property_readonly("position_itrf", &observation::EarthFixedStationEphemeris::position_itrf, "km");

  py::class_<MeasurementModel>(m, "MeasurementModel",
                               "Light-time measurement model (observation/measurement_model.hpp).")
      .def(
          py::init([](const std::string& type, py::handle troposphere, py::handle shapiro,
                      py::handle relative_humidity, py::handle tolerance, py::handle max_iterations,
                      py::handle mu, py::handle min_range, py::handle time_bias_partials,
                      py::handle wavelength_um) {
            MeasurementSettings s;
            s.type = observation::parse_observable(type);
            if (py::isinstance<py::str>(troposphere)) {  // the model's name turns it on
              const std::string name = troposphere.cast<std::string>();
              if (name == "saastamoinen")
                s.troposphere_model = observation::TroposphereModel::saastamoinen;
              else if (name == "mendes_pavlis")
                s.troposphere_model = observation::TroposphereModel::mendes_pavlis;
              else if (name == "marini_murray")
                s.troposphere_model = observation::TroposphereModel::marini_murray;
              else
                throw py::value_error(
                    "troposphere: must be a bool, 'saastamoinen', 'mendes_pavlis' or 'marini_murray', got '" +
                    name + "'");
              s.troposphere = true;
            } else {
              s.troposphere = checks::bool_arg(troposphere, "troposphere");
            }
            s.wavelength_um = checks::real_arg(wavelength_um, "wavelength_um");
            s.shapiro = checks::bool_arg(shapiro, "shapiro");
            s.relative_humidity = checks::real_arg(relative_humidity, "relative_humidity");
            s.light_time.tolerance = checks::real_arg(tolerance, "tolerance");
            s.light_time.max_iterations =
                static_cast<int>(checks::int_arg(max_iterations, "max_iterations", 1, 100));
            s.mu = checks::real_arg(mu, "mu");
            s.min_range = checks::real_arg(min_range, "min_range");
            s.time_bias_partials = checks::bool_arg(time_bias_partials, "time_bias_partials");
            return MeasurementModel(s);
          }),
          py::arg("type"), py::arg("troposphere") = false, py::arg("shapiro") = false,
          py::arg("relative_humidity") = 0.5, py::arg("tolerance") = 1e-14, py::arg("max_iterations") = 10,
          py::arg("mu") = core::earth::mu, py::arg("min_range") = 1e-3, py::arg("time_bias_partials") = true,
          py::arg("wavelength_um") = 0.532)
      .def_property_readonly("type",
                             [](const MeasurementModel& mm) {
                               return std::string(observation::observable_name(mm.settings().type));
                             })
      .def_property_readonly(
          "size", [](const MeasurementModel& mm) { return observation::observable_size(mm.settings().type); })
      .def_property_readonly("troposphere",
                             [](const MeasurementModel& mm) { return mm.settings().troposphere; })
      .def_property_readonly("shapiro", [](const MeasurementModel& mm) { return mm.settings().shapiro; })
      .def_property_readonly(
          "troposphere_model",
          [](const MeasurementModel& mm) {
            return std::string(observation::troposphere_model_name(mm.settings().troposphere_model));
          },
          "'saastamoinen' (radio), 'mendes_pavlis' or 'marini_murray' (laser ranging at wavelength_um); "
          "applies when "
          "troposphere is True")
      .def("predict_many", &predict_many, py::arg("station"), py::arg("t"), py::arg("states"),
           py::arg("range_bias") = 0.0, py::arg("time_bias") = 0.0,
           "Arrays of one predict() per tag: value (n, 2), dx (n, 2, 6), dbias (n, 2, 2), tau_down, tau_up, "
           "troposphere, shapiro (n,), status, iterations (n,) ints.");

  m.def(
      "shift_state",
      [](py::handle x_, py::handle dt_, py::handle mu_) {
        const Vec6 x = checks::eigen_arg<Vec6>(x_, "x");
        const double dt = checks::real_arg(dt_, "dt");
        const double mu = checks::real_arg(mu_, "mu");
        if (!(mu > 0.0)) throw py::value_error("mu: must be finite and > 0");
        if (!(x.head<3>().norm() > 0.0)) throw py::value_error("x: position must be non-zero");
        Vec6 out;
        Mat6 J;
        observation::shift_state(x, dt, mu, out, &J);
        return py::make_tuple(out, J);
      },
      py::arg("x"), py::arg("dt"), py::arg("mu") = core::earth::mu,
      "Third-order two-body Taylor shift of x (km, km/s) by dt (s): (x', d x' / d x).");
  m.def(
      "standard_atmosphere",
      [](py::handle h_, py::handle rh_) {
        const double h = checks::real_arg(h_, "height");
        const double rh = checks::real_arg(rh_, "relative_humidity");
        if (rh < 0.0 || rh > 1.0) throw py::value_error("relative_humidity: must be in [0, 1]");
        const observation::Weather w = observation::standard_atmosphere(h, rh);
        return py::make_tuple(w.pressure, w.temperature, w.water_vapour);
      },
      py::arg("height"), py::arg("relative_humidity") = 0.5,
      "(pressure hPa, temperature K, water vapour hPa) of the standard atmosphere at height km.");
  m.def(
      "saastamoinen_zenith_delay",
      [](py::handle p_, py::handle t_, py::handle e_, py::handle lat_, py::handle h_) {
        const observation::Weather w = weather_arg(p_, t_, e_);
        return observation::saastamoinen_zenith_delay(w, checks::real_arg(lat_, "latitude"),
                                                      checks::real_arg(h_, "height"));
      },
      py::arg("pressure"), py::arg("temperature"), py::arg("water_vapour"), py::arg("latitude"),
      py::arg("height"), "Saastamoinen zenith delay (km): hPa, K, hPa, latitude rad, height km.");
  m.def(
      "marini_murray_delay",
      [](py::handle p_, py::handle t_, py::handle e_, py::handle lat_, py::handle h_, py::handle wl_,
         py::handle el_) {
        const observation::Weather w = weather_arg(p_, t_, e_);
        const double wl = checks::real_arg(wl_, "wavelength_um");
        if (!(wl >= 0.3 && wl <= 1.7))
          throw py::value_error("wavelength_um: must be in [0.3, 1.7] micrometres");
        double d = 0.0;
        const double v = observation::marini_murray_delay(w, checks::real_arg(lat_, "latitude"),
                                                          checks::real_arg(h_, "height"), wl,
                                                          checks::real_arg(el_, "elevation"), &d);
        return py::make_tuple(v, d);
      },
      py::arg("pressure"), py::arg("temperature"), py::arg("water_vapour"), py::arg("latitude"),
      py::arg("height"), py::arg("wavelength_um"), py::arg("elevation"),
      "Marini-Murray range delay (km) and its derivative (km/rad): hPa, K, hPa, latitude rad, height km, "
      "wavelength um, elevation rad.");
  m.def(
      "tropo_mapping",
      [](py::handle el_) { return observation::tropo_mapping(checks::real_arg(el_, "elevation")); },
      py::arg("elevation"), "Black-Eisner mapping function at elevation (rad).");
  m.def(
      "shapiro_delay",
      [](py::handle r1_, py::handle r2_, py::handle rho_, py::handle mu_) {
        return observation::shapiro_delay(checks::real_arg(r1_, "r1"), checks::real_arg(r2_, "r2"),
                                          checks::real_arg(rho_, "rho"), checks::real_arg(mu_, "mu"));
      },
      py::arg("r1"), py::arg("r2"), py::arg("rho"), py::arg("mu") = core::earth::mu,
      "One-way Shapiro delay (km) between geocentric distances r1, r2 (km) separated by rho (km).");

  m.def(
      "_bench_two_way_range",
      [](const StationEphemeris& station, py::handle x_, py::handle calls_, py::handle repeats_) {
        const Vec6 x = checks::eigen_arg<Vec6>(x_, "x");
        const long long calls = checks::int_arg(calls_, "calls", 1, 100000000);
        const long long repeats = checks::int_arg(repeats_, "repeats", 1, 1000);
        MeasurementSettings s;
        s.type = observation::ObservableType::two_way_range;
        const MeasurementModel model(s);
        double best = 1e300, sink = 0.0;
        {
          py::gil_scoped_release release;  // re-acquired before the tuple is built
          Prediction p;
          for (long long r = 0; r < repeats; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            for (long long k = 0; k < calls; ++k) {
              model.predict(station, 1e-3 * static_cast<double>(k % 1000), x, Biases{}, p);
              sink += p.value(0) + p.dx(0, 0);
            }
            const auto t1 = std::chrono::steady_clock::now();
            best =
                std::min(best, std::chrono::duration<double>(t1 - t0).count() / static_cast<double>(calls));
          }
        }
        return py::make_tuple(best, sink);
      },
      py::arg("station"), py::arg("x"), py::arg("calls"), py::arg("repeats") = 5,
      "Private: best-of-repeats seconds per two-way range predict() with partials (and a checksum).");
}

}  // namespace satgnc::bindings
