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

py::tuple strings(const std::vector<std::string>& v) {
  py::tuple t(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) t[i] = v[i];
  return t;
}
std::vector<std::string> strings_of(const py::handle& h) { return h.cast<std::vector<std::string>>(); }

py::tuple pairs(const std::vector<io::KeyValue>& v) {
  py::tuple t(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) t[i] = py::make_tuple(v[i].first, v[i].second);
  return t;
}
std::vector<io::KeyValue> pairs_of(const py::handle& h) {
  std::vector<io::KeyValue> out;
  for (const py::handle& p : h) {
    const auto t = p.cast<py::tuple>();
    out.emplace_back(t[0].cast<std::string>(), t[1].cast<std::string>());
  }
  return out;
}

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

py::array matrix(const Mat6& m) {
  py::array_t<double> a({6, 6});
  auto w = a.mutable_unchecked<2>();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) w(i, j) = m(i, j);
  return std::move(a);
}
Mat6 matrix_of(const py::handle& h) {
  const Array a = Array::ensure(h);
  const auto r = a.unchecked<2>();
  Mat6 m;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) m(i, j) = r(i, j);
  return m;
}
py::array vector6(const Vec6& v) {
  py::array_t<double> a(6);
  auto w = a.mutable_unchecked<1>();
  for (int i = 0; i < 6; ++i) w(i) = v(i);
  return std::move(a);
}
Vec6 vector6_of(const py::handle& h) {
  const Array a = Array::ensure(h);
  const auto r = a.unchecked<1>();
  Vec6 v;
  for (int i = 0; i < 6; ++i) v(i) = r(i);
  return v;
}
py::object opt(const std::optional<double>& v) {
  return v ? py::object(py::float_(*v)) : py::object(py::none());
}
std::optional<double> opt_of(const py::handle& h) {
  if (h.is_none()) return std::nullopt;
  return h.cast<double>();
}

py::dict header_dict(const io::Header& h) {
  py::dict d;
  d["version"] = h.version;
  d["comments"] = strings(h.comments);
  d["classification"] = h.classification;
  d["creation_date"] = h.creation_date;
  d["originator"] = h.originator;
  d["message_id"] = h.message_id;
  return d;
}
io::Header header_of(const py::dict& d) {
  io::Header h;
  h.version = d["version"].cast<std::string>();
  h.comments = strings_of(d["comments"]);
  h.classification = d["classification"].cast<std::string>();
  h.creation_date = d["creation_date"].cast<std::string>();
  h.originator = d["originator"].cast<std::string>();
  h.message_id = d["message_id"].cast<std::string>();
  return h;
}

// ------------------------------------------------------------------------------------------ TDM
py::dict tdm_dict(const io::Tdm& t) {
  py::list segs;
  for (const io::TdmSegment& s : t.segments) {
    const io::TdmMetadata& m = s.metadata;
    py::dict md;
    md["comments"] = strings(m.comments);
    md["time_system"] = std::string(io::time_system_name(m.time_system));
    md["participants"] = strings(m.participants);
    md["mode"] = m.mode;
    md["path"] = py::tuple(py::cast(m.path));
    md["start_time"] = m.start_time;
    md["stop_time"] = m.stop_time;
    md["integration_interval"] = opt(m.integration_interval);
    md["integration_ref"] = m.integration_ref;
    md["range_units"] = m.range_units;
    md["angle_type"] = m.angle_type;
    md["other"] = pairs(m.other);
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
    sd["metadata"] = md;
    sd["comments"] = strings(s.data_comments);
    sd["keywords"] = kw;
    sd["epochs"] = ep;
    sd["values"] = val;
    sd["units"] = un;
    segs.append(sd);
  }
  py::dict d;
  d["header"] = header_dict(t.header);
  d["segments"] = segs;
  return d;
}

io::Tdm tdm_of(const py::dict& d) {
  io::Tdm t;
  t.header = header_of(d["header"].cast<py::dict>());
  for (const py::handle& sh : d["segments"]) {
    const py::dict sd = sh.cast<py::dict>();
    const py::dict md = sd["metadata"].cast<py::dict>();
    io::TdmSegment s;
    io::TdmMetadata& m = s.metadata;
    m.comments = strings_of(md["comments"]);
    m.time_system = time_system_of(md["time_system"]);
    m.participants = strings_of(md["participants"]);
    m.mode = md["mode"].cast<std::string>();
    m.path = md["path"].cast<std::vector<int>>();
    m.start_time = md["start_time"].cast<std::string>();
    m.stop_time = md["stop_time"].cast<std::string>();
    m.integration_interval = opt_of(md["integration_interval"]);
    m.integration_ref = md["integration_ref"].cast<std::string>();
    m.range_units = md["range_units"].cast<std::string>();
    m.angle_type = md["angle_type"].cast<std::string>();
    m.other = pairs_of(md["other"]);
    s.data_comments = strings_of(sd["comments"]);
    const auto kw = strings_of(sd["keywords"]);
    const auto ep = strings_of(sd["epochs"]);
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
    const io::OemMetadata& m = s.metadata;
    py::dict md;
    md["comments"] = strings(m.comments);
    md["object_name"] = m.object_name;
    md["object_id"] = m.object_id;
    md["center_name"] = m.center_name;
    md["ref_frame"] = m.ref_frame;
    md["ref_frame_epoch"] = m.ref_frame_epoch;
    md["time_system"] = std::string(io::time_system_name(m.time_system));
    md["start_time"] = m.start_time;
    md["useable_start_time"] = m.useable_start_time;
    md["useable_stop_time"] = m.useable_stop_time;
    md["stop_time"] = m.stop_time;
    md["interpolation"] = m.interpolation;
    md["interpolation_degree"] =
        m.interpolation_degree ? py::object(py::int_(*m.interpolation_degree)) : py::object(py::none());
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
    py::list covs;
    for (const io::OemCovariance& c : s.covariances) {
      py::dict cd;
      cd["comments"] = strings(c.comments);
      cd["epoch"] = c.epoch;
      cd["cov_ref_frame"] = c.cov_ref_frame;
      cd["matrix"] = matrix(c.matrix);
      covs.append(cd);
    }
    py::dict sd;
    sd["metadata"] = md;
    sd["comments"] = strings(s.data_comments);
    sd["epochs"] = ep;
    sd["states"] = st;
    sd["accelerations"] = any_acc ? py::object(acc) : py::object(py::none());
    sd["covariances"] = covs;
    segs.append(sd);
  }
  py::dict d;
  d["header"] = header_dict(o.header);
  d["segments"] = segs;
  return d;
}

io::Oem oem_of(const py::dict& d) {
  io::Oem o;
  o.header = header_of(d["header"].cast<py::dict>());
  for (const py::handle& sh : d["segments"]) {
    const py::dict sd = sh.cast<py::dict>();
    const py::dict md = sd["metadata"].cast<py::dict>();
    io::OemSegment s;
    io::OemMetadata& m = s.metadata;
    m.comments = strings_of(md["comments"]);
    m.object_name = md["object_name"].cast<std::string>();
    m.object_id = md["object_id"].cast<std::string>();
    m.center_name = md["center_name"].cast<std::string>();
    m.ref_frame = md["ref_frame"].cast<std::string>();
    m.ref_frame_epoch = md["ref_frame_epoch"].cast<std::string>();
    m.time_system = time_system_of(md["time_system"]);
    m.start_time = md["start_time"].cast<std::string>();
    m.useable_start_time = md["useable_start_time"].cast<std::string>();
    m.useable_stop_time = md["useable_stop_time"].cast<std::string>();
    m.stop_time = md["stop_time"].cast<std::string>();
    m.interpolation = md["interpolation"].cast<std::string>();
    if (!md["interpolation_degree"].is_none())
      m.interpolation_degree = md["interpolation_degree"].cast<int>();
    s.data_comments = strings_of(sd["comments"]);
    const auto ep = strings_of(sd["epochs"]);
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
    for (const py::handle& ch : sd["covariances"]) {
      const py::dict cd = ch.cast<py::dict>();
      io::OemCovariance c;
      c.comments = strings_of(cd["comments"]);
      c.epoch = cd["epoch"].cast<std::string>();
      c.cov_ref_frame = cd["cov_ref_frame"].cast<std::string>();
      c.matrix = matrix_of(cd["matrix"]);
      s.covariances.push_back(std::move(c));
    }
    o.segments.push_back(std::move(s));
  }
  return o;
}

// ------------------------------------------------------------------------------------------ OPM
py::dict opm_dict(const io::Opm& o) {
  py::dict d;
  d["header"] = header_dict(o.header);
  d["metadata_comments"] = strings(o.metadata_comments);
  d["object_name"] = o.object_name;
  d["object_id"] = o.object_id;
  d["center_name"] = o.center_name;
  d["ref_frame"] = o.ref_frame;
  d["ref_frame_epoch"] = o.ref_frame_epoch;
  d["time_system"] = std::string(io::time_system_name(o.time_system));
  d["comments"] = strings(o.data_comments);
  d["epoch"] = o.epoch;
  d["state"] = vector6(o.state);
  if (o.keplerian) {
    py::dict k;
    k["semi_major_axis"] = o.keplerian->semi_major_axis;
    k["eccentricity"] = o.keplerian->eccentricity;
    k["inclination"] = o.keplerian->inclination;
    k["ra_of_asc_node"] = o.keplerian->ra_of_asc_node;
    k["arg_of_pericenter"] = o.keplerian->arg_of_pericenter;
    k["true_anomaly"] = opt(o.keplerian->true_anomaly);
    k["mean_anomaly"] = opt(o.keplerian->mean_anomaly);
    k["gm"] = o.keplerian->gm;
    d["keplerian"] = k;
  } else {
    d["keplerian"] = py::none();
  }
  if (o.spacecraft) {
    py::dict p;
    p["mass"] = opt(o.spacecraft->mass);
    p["solar_rad_area"] = opt(o.spacecraft->solar_rad_area);
    p["solar_rad_coeff"] = opt(o.spacecraft->solar_rad_coeff);
    p["drag_area"] = opt(o.spacecraft->drag_area);
    p["drag_coeff"] = opt(o.spacecraft->drag_coeff);
    d["spacecraft"] = p;
  } else {
    d["spacecraft"] = py::none();
  }
  d["cov_ref_frame"] = o.cov_ref_frame;
  d["covariance"] = o.covariance ? py::object(matrix(*o.covariance)) : py::object(py::none());
  py::list mans;
  for (const io::OpmManeuver& m : o.maneuvers) {
    py::dict md;
    md["comments"] = strings(m.comments);
    md["epoch_ignition"] = m.epoch_ignition;
    md["duration"] = m.duration;
    md["delta_mass"] = m.delta_mass;
    md["ref_frame"] = m.ref_frame;
    md["dv"] = py::make_tuple(m.dv(0), m.dv(1), m.dv(2));
    mans.append(md);
  }
  d["maneuvers"] = mans;
  d["user_defined"] = pairs(o.user_defined);
  return d;
}

io::Opm opm_of(const py::dict& d) {
  io::Opm o;
  o.header = header_of(d["header"].cast<py::dict>());
  o.metadata_comments = strings_of(d["metadata_comments"]);
  o.object_name = d["object_name"].cast<std::string>();
  o.object_id = d["object_id"].cast<std::string>();
  o.center_name = d["center_name"].cast<std::string>();
  o.ref_frame = d["ref_frame"].cast<std::string>();
  o.ref_frame_epoch = d["ref_frame_epoch"].cast<std::string>();
  o.time_system = time_system_of(d["time_system"]);
  o.data_comments = strings_of(d["comments"]);
  o.epoch = d["epoch"].cast<std::string>();
  o.state = vector6_of(d["state"]);
  if (!d["keplerian"].is_none()) {
    const py::dict k = d["keplerian"].cast<py::dict>();
    io::OpmKeplerian e;
    e.semi_major_axis = k["semi_major_axis"].cast<double>();
    e.eccentricity = k["eccentricity"].cast<double>();
    e.inclination = k["inclination"].cast<double>();
    e.ra_of_asc_node = k["ra_of_asc_node"].cast<double>();
    e.arg_of_pericenter = k["arg_of_pericenter"].cast<double>();
    e.true_anomaly = opt_of(k["true_anomaly"]);
    e.mean_anomaly = opt_of(k["mean_anomaly"]);
    e.gm = k["gm"].cast<double>();
    o.keplerian = e;
  }
  if (!d["spacecraft"].is_none()) {
    const py::dict p = d["spacecraft"].cast<py::dict>();
    io::OpmSpacecraft s;
    s.mass = opt_of(p["mass"]);
    s.solar_rad_area = opt_of(p["solar_rad_area"]);
    s.solar_rad_coeff = opt_of(p["solar_rad_coeff"]);
    s.drag_area = opt_of(p["drag_area"]);
    s.drag_coeff = opt_of(p["drag_coeff"]);
    o.spacecraft = s;
  }
  o.cov_ref_frame = d["cov_ref_frame"].cast<std::string>();
  if (!d["covariance"].is_none()) o.covariance = matrix_of(d["covariance"]);
  for (const py::handle& mh : d["maneuvers"]) {
    const py::dict md = mh.cast<py::dict>();
    io::OpmManeuver m;
    m.comments = strings_of(md["comments"]);
    m.epoch_ignition = md["epoch_ignition"].cast<std::string>();
    m.duration = md["duration"].cast<double>();
    m.delta_mass = md["delta_mass"].cast<double>();
    m.ref_frame = md["ref_frame"].cast<std::string>();
    const auto dv = md["dv"].cast<std::vector<double>>();
    m.dv = Vec3(dv.at(0), dv.at(1), dv.at(2));
    o.maneuvers.push_back(std::move(m));
  }
  o.user_defined = pairs_of(d["user_defined"]);
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
}

}  // namespace satgnc::bindings
