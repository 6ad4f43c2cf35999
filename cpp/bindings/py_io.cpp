// pybind11 wrappers for the io room (CCSDS TDM / OEM / OPM). The Python package satgnc.io holds the
// model as frozen dataclasses; these functions exchange it as plain dicts (strings, tuples, float64
// arrays), parse and format text, and turn io::FormatError into satgnc.FileFormatError (path, line,
// key, reason) so that Python callers get the same file / line / keyword as C++ ones.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "satgnc/io/oem.hpp"
#include "satgnc/io/opm.hpp"
#include "satgnc/io/tdm.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {

using io::TimeSystem;

TimeSystem time_system_of(const py::handle& h) {
  const std::string s = h.cast<std::string>();
  for (TimeSystem t : {TimeSystem::utc, TimeSystem::tai, TimeSystem::tt, TimeSystem::gps, TimeSystem::tdb})
    if (s == io::time_system_name(t)) return t;
  throw std::invalid_argument("time_system: unknown or unsupported time system '" + s +
                              "' (supported: UTC, TAI, TT, GPS, TDB)");
}

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// ------------------------------------------------------------------ C++ value <-> Python value
// to_py / from_py: one overload per field type of the io model; the structs of the model go through
// their field tables (fields_of) below, so that each field is named once for both directions.
py::object to_py(const std::string& v) { return py::str(v); }
void from_py(const py::handle& h, std::string& v) { v = h.cast<std::string>(); }
py::object to_py(double v) { return py::float_(v); }
void from_py(const py::handle& h, double& v) { v = h.cast<double>(); }
py::object to_py(int v) { return py::int_(v); }
void from_py(const py::handle& h, int& v) { v = h.cast<int>(); }
py::object to_py(TimeSystem v) { return py::str(std::string(io::time_system_name(v))); }
void from_py(const py::handle& h, TimeSystem& v) { v = time_system_of(h); }

py::object to_py(const std::vector<std::string>& v) {
  py::tuple t(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) t[i] = v[i];
  return std::move(t);
}
void from_py(const py::handle& h, std::vector<std::string>& v) { v = h.cast<std::vector<std::string>>(); }
py::object to_py(const std::vector<int>& v) { return py::tuple(py::cast(v)); }
void from_py(const py::handle& h, std::vector<int>& v) { v = h.cast<std::vector<int>>(); }

py::object to_py(const std::vector<io::KeyValue>& v) {
  py::tuple t(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) t[i] = py::make_tuple(v[i].first, v[i].second);
  return std::move(t);
}
void from_py(const py::handle& h, std::vector<io::KeyValue>& v) {
  v.clear();
  for (const py::handle& p : h) {
    const auto t = p.cast<py::tuple>();
    v.emplace_back(t[0].cast<std::string>(), t[1].cast<std::string>());
  }
}

py::object to_py(const Mat6& m) {
  py::array_t<double> a({6, 6});
  auto w = a.mutable_unchecked<2>();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) w(i, j) = m(i, j);
  return std::move(a);
}
void from_py(const py::handle& h, Mat6& m) {
  const Array a = Array::ensure(h);
  const auto r = a.unchecked<2>();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) m(i, j) = r(i, j);
}
py::object to_py(const Vec6& v) {
  py::array_t<double> a(6);
  auto w = a.mutable_unchecked<1>();
  for (int i = 0; i < 6; ++i) w(i) = v(i);
  return std::move(a);
}
void from_py(const py::handle& h, Vec6& v) {
  const Array a = Array::ensure(h);
  const auto r = a.unchecked<1>();
  for (int i = 0; i < 6; ++i) v(i) = r(i);
}
py::object to_py(const Vec3& v) { return py::make_tuple(v(0), v(1), v(2)); }
void from_py(const py::handle& h, Vec3& v) {
  const auto d = h.cast<std::vector<double>>();
  v = Vec3(d.at(0), d.at(1), d.at(2));
}

// Field tables: (dict key, member) pairs of each model struct, in the order of the dict.
template <class T, class F>
struct Field {
  const char* key;
  F T::* member;
};
template <class T, class F>
constexpr Field<T, F> field(const char* key, F T::* member) {
  return {key, member};
}

auto fields_of(const io::Header*) {
  using T = io::Header;
  return std::make_tuple(field("version", &T::version), field("comments", &T::comments),
                         field("classification", &T::classification),
                         field("creation_date", &T::creation_date), field("originator", &T::originator),
                         field("message_id", &T::message_id));
}
auto fields_of(const io::TdmMetadata*) {
  using T = io::TdmMetadata;
  return std::make_tuple(
      field("comments", &T::comments), field("time_system", &T::time_system),
      field("participants", &T::participants), field("mode", &T::mode), field("path", &T::path),
      field("start_time", &T::start_time), field("stop_time", &T::stop_time),
      field("integration_interval", &T::integration_interval), field("integration_ref", &T::integration_ref),
      field("range_units", &T::range_units), field("angle_type", &T::angle_type), field("other", &T::other));
}
auto fields_of(const io::OemMetadata*) {
  using T = io::OemMetadata;
  return std::make_tuple(field("comments", &T::comments), field("object_name", &T::object_name),
                         field("object_id", &T::object_id), field("center_name", &T::center_name),
                         field("ref_frame", &T::ref_frame), field("ref_frame_epoch", &T::ref_frame_epoch),
                         field("time_system", &T::time_system), field("start_time", &T::start_time),
                         field("useable_start_time", &T::useable_start_time),
                         field("useable_stop_time", &T::useable_stop_time), field("stop_time", &T::stop_time),
                         field("interpolation", &T::interpolation),
                         field("interpolation_degree", &T::interpolation_degree));
}
auto fields_of(const io::OemCovariance*) {
  using T = io::OemCovariance;
  return std::make_tuple(field("comments", &T::comments), field("epoch", &T::epoch),
                         field("cov_ref_frame", &T::cov_ref_frame), field("matrix", &T::matrix));
}
auto fields_of(const io::OpmKeplerian*) {
  using T = io::OpmKeplerian;
  return std::make_tuple(
      field("semi_major_axis", &T::semi_major_axis), field("eccentricity", &T::eccentricity),
      field("inclination", &T::inclination), field("ra_of_asc_node", &T::ra_of_asc_node),
      field("arg_of_pericenter", &T::arg_of_pericenter), field("true_anomaly", &T::true_anomaly),
      field("mean_anomaly", &T::mean_anomaly), field("gm", &T::gm));
}
auto fields_of(const io::OpmSpacecraft*) {
  using T = io::OpmSpacecraft;
  return std::make_tuple(field("mass", &T::mass), field("solar_rad_area", &T::solar_rad_area),
                         field("solar_rad_coeff", &T::solar_rad_coeff), field("drag_area", &T::drag_area),
                         field("drag_coeff", &T::drag_coeff));
}
auto fields_of(const io::OpmManeuver*) {
  using T = io::OpmManeuver;
  return std::make_tuple(field("comments", &T::comments), field("epoch_ignition", &T::epoch_ignition),
                         field("duration", &T::duration), field("delta_mass", &T::delta_mass),
                         field("ref_frame", &T::ref_frame), field("dv", &T::dv));
}
auto fields_of(const io::Opm*) {
  using T = io::Opm;
  return std::make_tuple(field("header", &T::header), field("metadata_comments", &T::metadata_comments),
                         field("object_name", &T::object_name), field("object_id", &T::object_id),
                         field("center_name", &T::center_name), field("ref_frame", &T::ref_frame),
                         field("ref_frame_epoch", &T::ref_frame_epoch), field("time_system", &T::time_system),
                         field("comments", &T::data_comments), field("epoch", &T::epoch),
                         field("state", &T::state), field("keplerian", &T::keplerian),
                         field("spacecraft", &T::spacecraft), field("cov_ref_frame", &T::cov_ref_frame),
                         field("covariance", &T::covariance), field("maneuvers", &T::maneuvers),
                         field("user_defined", &T::user_defined));
}

// A struct with a field table <-> a dict with its keys; optional -> None; vector of structs -> list.
template <class T, class = decltype(fields_of(static_cast<const T*>(nullptr)))>
py::object to_py(const T& v);
template <class T, class = decltype(fields_of(static_cast<const T*>(nullptr)))>
void from_py(const py::handle& h, T& v);
template <class T>
py::object to_py(const std::optional<T>& v) {
  return v ? to_py(*v) : py::object(py::none());
}
template <class T>
void from_py(const py::handle& h, std::optional<T>& v) {
  if (h.is_none()) {
    v.reset();
    return;
  }
  T t{};
  from_py(h, t);
  v = std::move(t);
}
template <class T, class = decltype(fields_of(static_cast<const T*>(nullptr)))>
py::object to_py(const std::vector<T>& v) {
  py::list l;
  for (const T& e : v) l.append(to_py(e));
  return std::move(l);
}
template <class T, class = decltype(fields_of(static_cast<const T*>(nullptr)))>
void from_py(const py::handle& h, std::vector<T>& v) {
  v.clear();
  for (const py::handle& e : h) {
    T t{};
    from_py(e, t);
    v.push_back(std::move(t));
  }
}
template <class T, class>
py::object to_py(const T& v) {
  py::dict d;
  std::apply([&](const auto&... f) { ((d[f.key] = to_py(v.*(f.member))), ...); },
             fields_of(static_cast<const T*>(nullptr)));
  return std::move(d);
}
template <class T, class>
void from_py(const py::handle& h, T& v) {
  const py::dict d = h.cast<py::dict>();
  std::apply([&](const auto&... f) { (from_py(d[f.key], v.*(f.member)), ...); },
             fields_of(static_cast<const T*>(nullptr)));
}

// ------------------------------------------------------------------------------------------ TDM
py::dict tdm_dict(const io::Tdm& t) {
  py::list segs;
  for (const io::TdmSegment& s : t.segments) {
    const std::size_t n = s.observations.size();
    py::tuple kw(n), ep(n), un(n);
    py::array_t<double> val(static_cast<py::ssize_t>(n));
    auto w = val.mutable_unchecked<1>();
    for (std::size_t i = 0; i < n; ++i) {
      kw[i] = s.observations[i].keyword;
      ep[i] = s.observations[i].epoch;
      un[i] = s.observations[i].unit;
      w(static_cast<py::ssize_t>(i)) = s.observations[i].value;
    }
    py::dict sd;
    sd["metadata"] = to_py(s.metadata);
    sd["comments"] = to_py(s.data_comments);
    sd["keywords"] = kw;
    sd["epochs"] = ep;
    sd["values"] = val;
    sd["units"] = un;
    segs.append(sd);
  }
  py::dict d;
  d["header"] = to_py(t.header);
  d["segments"] = segs;
  return d;
}

io::Tdm tdm_of(const py::dict& d) {
  io::Tdm t;
  from_py(d["header"], t.header);
  for (const py::handle& sh : d["segments"]) {
    const py::dict sd = sh.cast<py::dict>();
    io::TdmSegment s;
    from_py(sd["metadata"], s.metadata);
    from_py(sd["comments"], s.data_comments);
    std::vector<std::string> kw, ep;
    from_py(sd["keywords"], kw);
    from_py(sd["epochs"], ep);
    const Array val = Array::ensure(sd["values"]);
    const auto v = val.unchecked<1>();
    for (std::size_t i = 0; i < kw.size(); ++i) {
      const char* unit = io::tdm_unit(kw[i]);
      s.observations.push_back({kw[i], ep[i], v(static_cast<py::ssize_t>(i)), unit ? unit : ""});
    }
    t.segments.push_back(std::move(s));
  }
  return t;
}

// ------------------------------------------------------------------------------------------ OEM
py::dict oem_dict(const io::Oem& o) {
  py::list segs;
  for (const io::OemSegment& s : o.segments) {
    const auto n = static_cast<py::ssize_t>(s.states.size());
    py::tuple ep(s.states.size());
    py::array_t<double> st({n, py::ssize_t(6)});
    py::array_t<double> acc({n, py::ssize_t(3)});
    auto ws = st.mutable_unchecked<2>();
    auto wa = acc.mutable_unchecked<2>();
    bool any_acc = false;
    for (py::ssize_t i = 0; i < n; ++i) {
      const io::OemState& e = s.states[static_cast<std::size_t>(i)];
      ep[static_cast<std::size_t>(i)] = e.epoch;
      for (int j = 0; j < 6; ++j) ws(i, j) = e.state(j);
      for (int j = 0; j < 3; ++j)
        wa(i, j) = e.acceleration ? (*e.acceleration)(j) : std::numeric_limits<double>::quiet_NaN();
      any_acc = any_acc || e.acceleration.has_value();
    }
    py::dict sd;
    sd["metadata"] = to_py(s.metadata);
    sd["comments"] = to_py(s.data_comments);
    sd["epochs"] = ep;
    sd["states"] = st;
    sd["accelerations"] = any_acc ? py::object(acc) : py::object(py::none());
    sd["covariances"] = to_py(s.covariances);
    segs.append(sd);
  }
  py::dict d;
  d["header"] = to_py(o.header);
  d["segments"] = segs;
  return d;
}

io::Oem oem_of(const py::dict& d) {
  io::Oem o;
  from_py(d["header"], o.header);
  for (const py::handle& sh : d["segments"]) {
    const py::dict sd = sh.cast<py::dict>();
    io::OemSegment s;
    from_py(sd["metadata"], s.metadata);
    from_py(sd["comments"], s.data_comments);
    std::vector<std::string> ep;
    from_py(sd["epochs"], ep);
    const Array st = Array::ensure(sd["states"]);
    const auto rs = st.unchecked<2>();
    const bool has_acc = !sd["accelerations"].is_none();
    Array acc;
    if (has_acc) acc = Array::ensure(sd["accelerations"]);
    for (std::size_t i = 0; i < ep.size(); ++i) {
      io::OemState e;
      e.epoch = ep[i];
      const auto ii = static_cast<py::ssize_t>(i);
      for (int j = 0; j < 6; ++j) e.state(j) = rs(ii, j);
      if (has_acc) {
        const auto ra = acc.unchecked<2>();
        if (!std::isnan(ra(ii, 0))) e.acceleration = Vec3(ra(ii, 0), ra(ii, 1), ra(ii, 2));
      }
      s.states.push_back(std::move(e));
    }
    from_py(sd["covariances"], s.covariances);
    o.segments.push_back(std::move(s));
  }
  return o;
}

// ------------------------------------------------------------------------------------------ OPM
py::dict opm_dict(const io::Opm& o) { return to_py(o).cast<py::dict>(); }

io::Opm opm_of(const py::dict& d) {
  io::Opm o;
  from_py(d, o);
  return o;
}

// Seconds of each epoch text after origin (both in ts), exact to the double rounding of the result.
py::array epoch_seconds(const std::vector<std::string>& epochs, const std::string& origin,
                        const py::handle& ts_h) {
  const TimeSystem ts = time_system_of(ts_h);
  core::Epoch t0;
  try {
    t0 = core::Epoch::parse(origin, ts);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("origin: ") + e.what());
  }
  py::array_t<double> out(static_cast<py::ssize_t>(epochs.size()));
  auto w = out.mutable_unchecked<1>();
  for (std::size_t i = 0; i < epochs.size(); ++i) {
    try {
      w(static_cast<py::ssize_t>(i)) = core::Epoch::parse(epochs[i], ts) - t0;
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("epochs[" + std::to_string(i) + "]: " + e.what());
    }
  }
  return std::move(out);
}

// The epoch texts origin + seconds[i] in ts (ISO-8601, up to 12 fraction digits, zeros dropped).
py::tuple epochs_at(const std::string& origin, const Array& seconds, const py::handle& ts_h) {
  const TimeSystem ts = time_system_of(ts_h);
  core::Epoch t0;
  try {
    t0 = core::Epoch::parse(origin, ts);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("origin: ") + e.what());
  }
  const auto r = seconds.unchecked<1>();
  py::tuple out(static_cast<std::size_t>(r.shape(0)));
  for (py::ssize_t i = 0; i < r.shape(0); ++i) {
    try {
      out[static_cast<std::size_t>(i)] = io::epoch_text(t0 + r(i), ts);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("seconds[" + std::to_string(i) + "]: " + e.what());
    }
  }
  return out;
}

}  // namespace

void init_io(py::module_& m) {
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const io::FormatError& e) {
      // satgnc.FileFormatError(path, line, reason, key): str() reads "<path>:<line>: <keyword>: <rule>"
      py::object cls = py::module_::import("satgnc._validate").attr("FileFormatError");
      py::object line = e.line() > 0 ? py::object(py::int_(e.line())) : py::object(py::none());
      py::object err = cls(e.file(), line, e.keyword() + ": " + e.rule(), e.keyword());
      PyErr_SetObject(cls.ptr(), err.ptr());
    }
  });
  m.def(
      "io_parse_tdm",
      [](const std::string& text, const std::string& source) {
        return tdm_dict(io::parse_tdm(text, source));
      },
      py::arg("text"), py::arg("source"),
      "Parse TDM text (KVN or XML, CCSDS 503.0-B-2) into the dict form of satgnc.io.Tdm; errors name source, "
      "line and keyword.");
  m.def(
      "io_format_tdm",
      [](const py::dict& model, bool xml) {
        const io::Tdm t = tdm_of(model);
        return xml ? io::format_tdm_xml(t) : io::format_tdm_kvn(t);
      },
      py::arg("model"), py::arg("xml"),
      "TDM text (KVN, or XML when xml is True) of the dict form of satgnc.io.Tdm.");
  m.def(
      "io_parse_oem",
      [](const std::string& text, const std::string& source) {
        return oem_dict(io::parse_oem(text, source));
      },
      py::arg("text"), py::arg("source"),
      "Parse OEM KVN text (CCSDS 502.0-B-3) into the dict form of satgnc.io.Oem.");
  m.def(
      "io_format_oem", [](const py::dict& model) { return io::format_oem(oem_of(model)); }, py::arg("model"),
      "OEM KVN text of the dict form of satgnc.io.Oem.");
  m.def(
      "io_parse_opm",
      [](const std::string& text, const std::string& source) {
        return opm_dict(io::parse_opm(text, source));
      },
      py::arg("text"), py::arg("source"),
      "Parse OPM KVN text (CCSDS 502.0-B-3) into the dict form of satgnc.io.Opm.");
  m.def("io_epoch_seconds", &epoch_seconds, py::arg("epochs"), py::arg("origin"), py::arg("time_system"),
        "Seconds (float64) of each epoch text after origin, both in time_system (core::Epoch: leap seconds "
        "counted, exact to the double rounding of each difference).");
  m.def("io_epochs_at", &epochs_at, py::arg("origin"), py::arg("seconds"), py::arg("time_system"),
        "Epoch texts origin + seconds[i] in time_system (ISO-8601, up to 12 fraction digits).");
  m.def(
      "io_format_opm", [](const py::dict& model) { return io::format_opm(opm_of(model)); }, py::arg("model"),
      "OPM KVN text of the dict form of satgnc.io.Opm.");
  m.def(
      "io_format_oem_xml", [](const py::dict& model) { return io::format_oem_xml(oem_of(model)); },
      py::arg("model"), "OEM XML text (NDM/XML 2.0) of the dict form of satgnc.io.Oem.");
  m.def(
      "io_format_opm_xml", [](const py::dict& model) { return io::format_opm_xml(opm_of(model)); },
      py::arg("model"), "OPM XML text (NDM/XML 2.0) of the dict form of satgnc.io.Opm.");
}

}  // namespace satgnc::bindings
