// pybind11 wrappers for the core room: the Earth constants (EARTH_*, defined once in
// satgnc/core/constants.hpp) and the status tables (read by tests and tools; each status enum itself
// is bound in its room through bind_status).
#include <pybind11/pybind11.h>

#include <string>

#include "satgnc/core/constants.hpp"
#include "satgnc/core/status.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

namespace {
template <class E>
py::list table_rows() {
  py::list rows;
  for (const core::StatusEntry& row : core::status_table<E>())
    rows.append(py::make_tuple(row.value, std::string(row.name), std::string(row.message)));
  return rows;
}
}  // namespace

void init_core(py::module_& m) {
  m.attr("EARTH_MU") = core::earth::mu;          // km^3/s^2
  m.attr("EARTH_RADIUS") = core::earth::radius;  // km
  m.attr("EARTH_J2") = core::earth::j2;          // dimensionless
  m.attr("EARTH_OMEGA") = core::earth::omega;    // rad/s
  m.def(
      "status_tables",
      []() {
        py::dict d;
        d["AdmmStatus"] = table_rows<core::AdmmStatus>();
        d["RiccatiStatus"] = table_rows<core::RiccatiStatus>();
        d["IlqrAdmmStatus"] = table_rows<core::IlqrAdmmStatus>();
        d["ScpStatus"] = table_rows<core::ScpStatus>();
        d["OdStatus"] = table_rows<core::OdStatus>();
        d["PropagationStatus"] = table_rows<core::PropagationStatus>();
        d["Dop853Status"] = table_rows<core::Dop853Status>();
        d["KeplerStatus"] = table_rows<core::KeplerStatus>();
        d["Verdict"] = table_rows<core::Verdict>();
        d["ObservationStatus"] = table_rows<core::ObservationStatus>();
        return d;
      },
      "Every C++ status table (satgnc/core/status.hpp): {enum name: [(value, name, message), ...]} "
      "in declaration order.");
}

}  // namespace satgnc::bindings
