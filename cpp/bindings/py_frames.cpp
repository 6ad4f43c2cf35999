// pybind11 wrappers for the frames room: EOP tables, the IAU 2006/2000A GCRS <-> ITRS chain, the
// EME2000 frame bias, IauEarthRotation and ground stations (the Python package is satgnc.frames).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "satgnc/frames/earth_orientation.hpp"
#include "satgnc/frames/eop.hpp"
#include "satgnc/frames/ground_station.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

void init_earth_rotation_models(py::module_& m);  // py_force_models.cpp

namespace {
namespace fr = satgnc::frames;

fr::OutOfRangePolicy policy_arg(const std::string& name) { return fr::out_of_range_policy_from_name(name); }

// A 3-vector (position) or a 6-vector (state), finite. Typed parameters (not py::handle) so that the
// hardened wrapper's diagnosis of a bad call names the right argument.
Eigen::VectorXd vec36(const Eigen::VectorXd& v, const std::string& name) {
  if (v.size() != 3 && v.size() != 6)
    throw py::value_error(name + ": must have shape (3,) (position, km) or (6,) (state, km and km/s), got (" +
                          std::to_string(v.size()) + ",)");
  if (!v.allFinite()) throw py::value_error(name + ": must be finite (no NaN or Inf)");
  return v;
}

Vec6 state6(const Vec6& v, const std::string& name) {
  if (!v.allFinite()) throw py::value_error(name + ": must be finite (no NaN or Inf)");
  return v;
}

// A column, finite, of length n (or zeros of length n when absent).
std::vector<double> column_arg(const std::optional<std::vector<double>>& c, const std::string& name,
                               std::size_t n) {
  if (!c) return std::vector<double>(n, 0.0);
  if (c->size() != n)
    throw py::value_error(name + ": must have the length of mjd (" + std::to_string(n) + "), got " +
                          std::to_string(c->size()));
  for (double v : *c)
    if (!std::isfinite(v)) throw py::value_error(name + ": must be finite (no NaN or Inf)");
  return *c;
}

py::array_t<double> column(const fr::EopTable& t, double fr::EopRow::* f) {
  py::array_t<double> out(static_cast<py::ssize_t>(t.rows().size()));
  auto o = out.mutable_unchecked<1>();
  for (std::size_t i = 0; i < t.rows().size(); ++i) o(static_cast<py::ssize_t>(i)) = t.rows()[i].*f;
  return out;
}
}  // namespace

void init_frames(py::module_& m) {
  py::class_<fr::EopValues>(m, "EopValues", "EOP interpolated at an epoch (arcsec, s).")
      .def_readonly("xp", &fr::EopValues::xp, "polar motion x, arcsec")
      .def_readonly("yp", &fr::EopValues::yp, "polar motion y, arcsec")
      .def_readonly("ut1_utc", &fr::EopValues::ut1_utc, "UT1-UTC, s")
      .def_readonly("ut1_tai", &fr::EopValues::ut1_tai, "UT1-TAI, s")
      .def_readonly("lod", &fr::EopValues::lod, "excess length of day, s")
      .def_readonly("dx", &fr::EopValues::dx, "celestial pole offset dX, arcsec")
      .def_readonly("dy", &fr::EopValues::dy, "celestial pole offset dY, arcsec")
      .def("__repr__", [](const fr::EopValues& v) {
        return "EopValues(xp=" + std::to_string(v.xp) + ", yp=" + std::to_string(v.yp) +
               ", ut1_utc=" + std::to_string(v.ut1_utc) + ", lod=" + std::to_string(v.lod) + ")";
      });

  py::class_<fr::EopTable>(m, "EopTable",
                           "Daily Earth orientation parameters with 4-point Lagrange interpolation (UT1 as "
                           "UT1-TAI across leap seconds). Read with EopTable.read(path).")
      .def(py::init([](const std::vector<double>& mjd, const std::vector<double>& xp,
                       const std::vector<double>& yp, const std::vector<double>& ut1_utc,
                       const std::optional<std::vector<double>>& lod,
                       const std::optional<std::vector<double>>& dx,
                       const std::optional<std::vector<double>>& dy, const std::string& policy) {
             const std::size_t n = mjd.size();
             const std::vector<double> c0 = column_arg(mjd, "mjd", n);
             const std::vector<std::vector<double>> cols = {
                 column_arg(xp, "xp", n),   column_arg(yp, "yp", n), column_arg(ut1_utc, "ut1_utc", n),
                 column_arg(lod, "lod", n), column_arg(dx, "dx", n), column_arg(dy, "dy", n)};
             std::vector<fr::EopRow> rows(n);
             for (std::size_t i = 0; i < n; ++i)
               rows[i] = {c0[i],      cols[0][i], cols[1][i], cols[2][i],
                          cols[3][i], cols[4][i], cols[5][i], fr::EopSource::user};
             return fr::EopTable(std::move(rows), policy_arg(policy));
           }),
           py::arg("mjd"), py::arg("xp"), py::arg("yp"), py::arg("ut1_utc"), py::arg("lod") = py::none(),
           py::arg("dx") = py::none(), py::arg("dy") = py::none(), py::arg("policy") = "error",
           "From columns: mjd (UTC days, whole, increasing), xp, yp (arcsec), ut1_utc, lod (s), dx, dy "
           "(arcsec); "
           "lod, dx, dy default to zeros.")
      .def_static(
          "read",
          [](const std::string& path, const std::string& policy) {
            return fr::EopTable::read(path, policy_arg(policy));
          },
          py::arg("path"), py::arg("policy") = "error",
          "Read an IERS finals2000A or EOP 20 C04 file (format detected).")
      .def_static(
          "read_finals2000a",
          [](const std::string& path, const std::string& policy) {
            return fr::EopTable::read_finals2000a(path, policy_arg(policy));
          },
          py::arg("path"), py::arg("policy") = "error",
          "Read an IERS finals2000A file (Bulletin B where present).")
      .def_static(
          "read_c04",
          [](const std::string& path, const std::string& policy) {
            return fr::EopTable::read_c04(path, policy_arg(policy));
          },
          py::arg("path"), py::arg("policy") = "error", "Read an IERS EOP 20 C04 file.")
      .def(
          "with_policy",
          [](const fr::EopTable& t, const std::string& policy) { return t.with_policy(policy_arg(policy)); },
          py::arg("policy"),
          "The same rows with another out-of-range policy: 'error', 'hold_last' or 'zero'.")
      .def("at", &fr::EopTable::at, py::arg("epoch"),
           "EOP interpolated at epoch (the policy applies outside).")
      .def("ut1_minus_utc", &fr::EopTable::ut1_minus_utc, py::arg("epoch"), "UT1-UTC at epoch, s.")
      .def(
          "ut1_jd",
          [](const fr::EopTable& t, const core::Epoch& e) {
            const core::JulianDate j = t.ut1_jd(e);
            return py::make_tuple(j.jd1, j.jd2);
          },
          py::arg("epoch"), "UT1 at epoch as a two-part Julian date (days).")
      .def("covers", &fr::EopTable::covers, py::arg("epoch"), "True when epoch is within the table.")
      .def_property_readonly(
          "policy",
          [](const fr::EopTable& t) { return std::string(fr::out_of_range_policy_name(t.policy())); })
      .def_property_readonly("first_epoch", &fr::EopTable::first_epoch, "0h UTC of the first row")
      .def_property_readonly("last_epoch", &fr::EopTable::last_epoch, "0h UTC of the last row")
      .def_property_readonly(
          "mjd", [](const fr::EopTable& t) { return column(t, &fr::EopRow::mjd); }, "MJD (UTC), days")
      .def_property_readonly(
          "xp", [](const fr::EopTable& t) { return column(t, &fr::EopRow::xp); }, "arcsec")
      .def_property_readonly(
          "yp", [](const fr::EopTable& t) { return column(t, &fr::EopRow::yp); }, "arcsec")
      .def_property_readonly(
          "ut1_utc", [](const fr::EopTable& t) { return column(t, &fr::EopRow::ut1_utc); }, "s")
      .def_property_readonly(
          "lod", [](const fr::EopTable& t) { return column(t, &fr::EopRow::lod); }, "s")
      .def_property_readonly(
          "dx", [](const fr::EopTable& t) { return column(t, &fr::EopRow::dx); }, "arcsec")
      .def_property_readonly(
          "dy", [](const fr::EopTable& t) { return column(t, &fr::EopRow::dy); }, "arcsec")
      .def_property_readonly(
          "sources",
          [](const fr::EopTable& t) {
            std::vector<std::string> s;
            for (const fr::EopRow& r : t.rows()) s.emplace_back(fr::eop_source_name(r.source));
            return s;
          },
          "per row: 'bulletin_b', 'bulletin_a', 'bulletin_a_prediction', 'c04' or 'user'")
      .def("__len__", [](const fr::EopTable& t) { return t.rows().size(); })
      .def("__repr__", [](const fr::EopTable& t) {
        return "<EopTable " + std::to_string(t.rows().size()) + " rows, MJD " +
               std::to_string(static_cast<long long>(t.rows().front().mjd)) + " .. " +
               std::to_string(static_cast<long long>(t.rows().back().mjd)) + ", policy " +
               fr::out_of_range_policy_name(t.policy()) + ">";
      });

  py::class_<fr::EarthOrientation>(m, "EarthOrientation",
                                   "GCRS -> ITRS factors: r_itrs = w R3(era) q r_gcrs.")
      .def_readonly("q", &fr::EarthOrientation::q, "GCRS -> CIRS matrix")
      .def_readonly("era", &fr::EarthOrientation::era, "Earth rotation angle, rad")
      .def_readonly("w", &fr::EarthOrientation::w, "TIRS -> ITRS (polar motion) matrix")
      .def_readonly("gcrs_to_itrs", &fr::EarthOrientation::gcrs_to_itrs, "GCRS -> ITRS matrix")
      .def_readonly("omega", &fr::EarthOrientation::omega, "Earth rotation rate with LOD, rad/s");

  m.def(
      "earth_orientation",
      [](const core::Epoch& e, const fr::EopTable& t) { return fr::earth_orientation(e, t); },
      py::arg("epoch"), py::arg("eop"), "The IAU 2006/2000A GCRS -> ITRS factors at epoch (full series).");
  m.def("gcrs_to_itrs_matrix", &fr::gcrs_to_itrs_matrix, py::arg("epoch"), py::arg("eop"),
        "GCRS -> ITRS rotation matrix at epoch.");
  m.def(
      "gcrs_to_itrs",
      [](const Eigen::VectorXd& x, const core::Epoch& e, const fr::EopTable& t) -> Eigen::VectorXd {
        const Eigen::VectorXd v = vec36(x, "x");
        if (v.size() == 3) return fr::gcrs_to_itrs(Vec3(v), e, t);
        return fr::gcrs_to_itrs(Vec6(v), e, t);
      },
      py::arg("x"), py::arg("epoch"), py::arg("eop"),
      "Position (3,) km or state (6,) km, km/s from GCRS to ITRS at epoch (velocity with the Earth-rotation "
      "term).");
  m.def(
      "itrs_to_gcrs",
      [](const Eigen::VectorXd& x, const core::Epoch& e, const fr::EopTable& t) -> Eigen::VectorXd {
        const Eigen::VectorXd v = vec36(x, "x");
        if (v.size() == 3) return fr::itrs_to_gcrs(Vec3(v), e, t);
        return fr::itrs_to_gcrs(Vec6(v), e, t);
      },
      py::arg("x"), py::arg("epoch"), py::arg("eop"),
      "Position (3,) or state (6,) from ITRS to GCRS at epoch.");
  m.def("gcrs_to_eme2000_matrix", &fr::gcrs_to_eme2000_matrix,
        "Frame bias B (eraBp06): r_EME2000 = B r_GCRS.");
  m.def(
      "gcrs_to_eme2000",
      [](const Eigen::VectorXd& x) -> Eigen::VectorXd {
        Eigen::VectorXd v = vec36(x, "x");
        for (Eigen::Index k = 0; k < v.size(); k += 3)
          v.segment<3>(k) = fr::gcrs_to_eme2000(Vec3(v.segment<3>(k)));
        return v;
      },
      py::arg("x"), "Vector (3,) or state (6,) from GCRS to EME2000 (constant rotation).");
  m.def(
      "eme2000_to_gcrs",
      [](const Eigen::VectorXd& x) -> Eigen::VectorXd {
        Eigen::VectorXd v = vec36(x, "x");
        for (Eigen::Index k = 0; k < v.size(); k += 3)
          v.segment<3>(k) = fr::eme2000_to_gcrs(Vec3(v.segment<3>(k)));
        return v;
      },
      py::arg("x"), "Vector (3,) or state (6,) from EME2000 to GCRS.");

  // The EarthRotationModel interface first (py_force_models.cpp): a GravityField takes any model.
  init_earth_rotation_models(m);
  py::class_<fr::IauEarthRotation, fr::EarthRotationModel, std::shared_ptr<fr::IauEarthRotation>>(
      m, "IauEarthRotation",
      "IAU 2006/2000A Earth orientation for a propagation: slowly varying parts on a "
      "grid, exact ERA (max error 2.9e-12 rad at the default 3600 s step).")
      .def(py::init<const core::Epoch&, const fr::EopTable&, double, double, double>(), py::arg("epoch"),
           py::arg("eop"), py::arg("t_begin"), py::arg("t_end"), py::arg("step") = 3600.0)
      .def(
          "rotation",
          [](const fr::IauEarthRotation& r, double t) {
            Mat3 R;
            Vec3 w;
            r.rotation(t, R, w);
            return py::make_tuple(R, w);
          },
          py::arg("t"), "(gcrf_to_itrf (3, 3), omega_gcrf (3,) rad/s) at t seconds after the epoch.")
      .def_property_readonly("t_begin", &fr::IauEarthRotation::t_begin)
      .def_property_readonly("t_end", &fr::IauEarthRotation::t_end)
      .def_property_readonly("step", &fr::IauEarthRotation::step);

  py::class_<fr::LookAngles>(m, "LookAngles",
                             "Topocentric azimuth (from north, east positive), elevation, range.")
      .def_readonly("azimuth", &fr::LookAngles::azimuth, "rad, [0, 2 pi)")
      .def_readonly("elevation", &fr::LookAngles::elevation, "rad")
      .def_readonly("range", &fr::LookAngles::range, "km")
      .def_readonly("azimuth_rate", &fr::LookAngles::azimuth_rate, "rad/s")
      .def_readonly("elevation_rate", &fr::LookAngles::elevation_rate, "rad/s")
      .def_readonly("range_rate", &fr::LookAngles::range_rate, "km/s");

  py::class_<fr::GroundStation>(m, "GroundStation",
                                "A station fixed in the ITRF at WGS-84 geodetic coordinates.")
      .def(py::init<double, double, double, double, std::string>(), py::arg("latitude_deg"),
           py::arg("longitude_deg"), py::arg("height_km"), py::arg("elevation_mask_deg") = 0.0,
           py::arg("name") = "")
      .def_property_readonly("name", &fr::GroundStation::name)
      .def_property_readonly("latitude_deg", &fr::GroundStation::latitude_deg)
      .def_property_readonly("longitude_deg", &fr::GroundStation::longitude_deg)
      .def_property_readonly("height_km", &fr::GroundStation::height_km)
      .def_property_readonly("elevation_mask_deg", &fr::GroundStation::elevation_mask_deg)
      .def_property_readonly(
          "position_itrf", [](const fr::GroundStation& s) { return Vec3(s.position_itrf()); }, "km")
      .def_property_readonly("itrf_to_enu", [](const fr::GroundStation& s) { return Mat3(s.itrf_to_enu()); })
      .def(
          "state_gcrf",
          [](const fr::GroundStation& s, const core::Epoch& e, const fr::EopTable& t) {
            return s.state_gcrf(e, t);
          },
          py::arg("epoch"), py::arg("eop"), "Station state [r km, v km/s] in the GCRF at epoch.")
      .def(
          "look",
          [](const fr::GroundStation& s, const Vec6& x, const core::Epoch& e, const fr::EopTable& t) {
            return s.look(state6(x, "satellite_gcrf"), e, t);
          },
          py::arg("satellite_gcrf"), py::arg("epoch"), py::arg("eop"),
          "Look angles of a satellite GCRF state.")
      .def(
          "look_itrf",
          [](const fr::GroundStation& s, const Vec6& x) { return s.look_itrf(state6(x, "satellite_itrf")); },
          py::arg("satellite_itrf"), "Look angles of a satellite ITRF state.")
      .def("visible", &fr::GroundStation::visible, py::arg("elevation"), "elevation (rad) >= the mask.");
}

}  // namespace satgnc::bindings
