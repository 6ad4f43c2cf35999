// pybind11 wrappers for core::Epoch and core::TimeScale (the Python package is satgnc.time). A scale
// argument is a TimeScale or its name ("UTC", "tai", ...).
#include <pybind11/operators.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>

#include "satgnc/core/epoch.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {
using core::Epoch;
using core::TimeScale;

TimeScale scale_arg(const py::handle& h) {
  if (py::isinstance<py::str>(h)) return core::time_scale_from_name(h.cast<std::string>());
  if (py::isinstance<TimeScale>(h)) return h.cast<TimeScale>();
  throw py::type_error("scale: must be a TimeScale or a name (TAI, TT, UTC, GPS, TDB), got " +
                       std::string(py::str(py::type::of(h).attr("__name__"))));
}

std::string repr(const Epoch& e) { return "Epoch('" + e.to_iso(TimeScale::tai, 9) + "', 'TAI')"; }
}  // namespace

void init_time(py::module_& m) {
  py::enum_<TimeScale>(m, "TimeScale", "Time scales of an Epoch (UT1 needs EOP: satgnc.frames.EopTable).")
      .value("TAI", TimeScale::tai)
      .value("TT", TimeScale::tt)
      .value("UTC", TimeScale::utc)
      .value("GPS", TimeScale::gps)
      .value("TDB", TimeScale::tdb);
  m.def(
      "time_scale_from_name", [](const std::string& name) { return core::time_scale_from_name(name); },
      py::arg("name"), "The TimeScale named name (case-insensitive); ValueError naming the choices.");

  py::class_<Epoch>(m, "Epoch",
                    "An instant stored in TAI as whole seconds + fraction since J2000 TAI (no precision lost "
                    "over decades). Build with Epoch.parse / from_calendar / from_jd / from_mjd.")
      .def(py::init<>(), "J2000 TAI (2000-01-01T12:00:00 TAI).")
      .def_static(
          "parse",
          [](const std::string& text, const py::object& scale) {
            return Epoch::parse(text, scale_arg(scale));
          },
          py::arg("text"), py::arg("scale") = "UTC",
          "ISO-8601 'YYYY-MM-DDThh:mm:ss[.f]' or 'YYYY-DDDThh:mm:ss[.f]' in scale (23:59:60 on a UTC leap "
          "day).")
      .def_static(
          "from_calendar",
          [](int y, int mo, int d, int h, int mi, double s, const py::object& scale) {
            return Epoch::from_calendar(y, mo, d, h, mi, s, scale_arg(scale));
          },
          py::arg("year"), py::arg("month"), py::arg("day"), py::arg("hour") = 0, py::arg("minute") = 0,
          py::arg("second") = 0.0, py::arg("scale") = "UTC",
          "From a Gregorian calendar date and time in scale.")
      .def_static(
          "from_jd",
          [](double jd1, double jd2, const py::object& scale) {
            return Epoch::from_jd(jd1, jd2, scale_arg(scale));
          },
          py::arg("jd1"), py::arg("jd2") = 0.0, py::arg("scale") = "TT",
          "From a two-part Julian date (days).")
      .def_static(
          "from_mjd",
          [](double mjd, const py::object& scale) { return Epoch::from_mjd(mjd, scale_arg(scale)); },
          py::arg("mjd"), py::arg("scale") = "TT", "From a Modified Julian Date (days).")
      .def_static(
          "from_tai_seconds",
          [](std::int64_t whole, double fraction) { return Epoch::from_tai_seconds(whole, fraction); },
          py::arg("whole"), py::arg("fraction") = 0.0, "From TAI seconds since J2000 TAI (whole + fraction).")
      .def(
          "jd",
          [](const Epoch& e, const py::object& scale) {
            const core::JulianDate j = e.jd(scale_arg(scale));
            return py::make_tuple(j.jd1, j.jd2);
          },
          py::arg("scale") = "TT", "Two-part Julian date (jd1, jd2) in scale, days.")
      .def(
          "mjd", [](const Epoch& e, const py::object& scale) { return e.mjd(scale_arg(scale)); },
          py::arg("scale") = "TT", "Modified Julian Date in scale (days, one float).")
      .def(
          "to_iso",
          [](const Epoch& e, const py::object& scale, int decimals) {
            return e.to_iso(scale_arg(scale), decimals);
          },
          py::arg("scale") = "UTC", py::arg("decimals") = 3,
          "ISO-8601 text in scale with decimals (0..12) digits.")
      .def(
          "calendar",
          [](const Epoch& e, const py::object& scale, int decimals) {
            const core::CalendarTime c = e.calendar(scale_arg(scale), decimals);
            return py::make_tuple(c.year, c.month, c.day, c.hour, c.minute, c.second);
          },
          py::arg("scale") = "UTC", py::arg("decimals") = 9,
          "(year, month, day, hour, minute, second) in scale, second rounded to decimals.")
      .def(
          "offset_from_tai",
          [](const Epoch& e, const py::object& scale) { return e.offset_from_tai(scale_arg(scale)); },
          py::arg("scale"), "scale - TAI at this instant, s.")
      .def("tai_minus_utc", &Epoch::tai_minus_utc, "TAI - UTC at this instant, s.")
      .def_property_readonly("tai_whole", &Epoch::tai_whole, "Whole TAI seconds since J2000 TAI.")
      .def_property_readonly("tai_fraction", &Epoch::tai_fraction, "Fraction of the TAI second, [0, 1).")
      .def_property_readonly("tai_seconds", &Epoch::tai_seconds, "TAI seconds since J2000 TAI (one float).")
      .def(
          "__add__", [](const Epoch& e, double dt) { return e + dt; }, py::is_operator())
      .def(
          "__radd__", [](const Epoch& e, double dt) { return e + dt; }, py::is_operator())
      .def(
          "__sub__", [](const Epoch& e, const Epoch& o) { return e - o; }, py::is_operator())
      .def(
          "__sub__", [](const Epoch& e, double dt) { return e - dt; }, py::is_operator())
      .def(py::self == py::self)
      .def(py::self != py::self)
      .def(py::self < py::self)
      .def(py::self <= py::self)
      .def(py::self > py::self)
      .def(py::self >= py::self)
      .def("__hash__",
           [](const Epoch& e) { return py::hash(py::make_tuple(e.tai_whole(), e.tai_fraction())); })
      .def("__repr__", &repr)
      .def("__str__",
           [](const Epoch& e) {
             try {
               return e.to_iso(TimeScale::utc, 9) + " UTC";
             } catch (const std::invalid_argument&) {
               return e.to_iso(TimeScale::tai, 9) + " TAI";
             }
           })
      .def(py::pickle([](const Epoch& e) { return py::make_tuple(e.tai_whole(), e.tai_fraction()); },
                      [](const py::tuple& t) {
                        return Epoch::from_tai_seconds(t[0].cast<std::int64_t>(), t[1].cast<double>());
                      }));
}

}  // namespace satgnc::bindings
