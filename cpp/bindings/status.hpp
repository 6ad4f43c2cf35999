#pragma once
// bind_status<E>: the one way a status enum reaches Python. The members, their values and the
// `.message` property are read from core::status_table<E>() (satgnc/core/status.hpp); nothing here
// re-types a name or a message.
#include <pybind11/pybind11.h>

#include <initializer_list>
#include <string>
#include <utility>

#include "satgnc/core/status.hpp"

namespace satgnc::bindings {

/// Builds py::enum_<E>(m, name) from the status table (members in table order, `unsolved` first, each
/// with its message as doc) plus a read-only `.message`. `aliases` adds old Python member names
/// (e.g. {"not_run", E::unsolved}) after the table rows, so that `.name` gives the table name while
/// the old attribute keeps working and `{int(v): k for k, v in E.__members__.items()}` maps the
/// value to the old name as it did.
template <class E>
pybind11::enum_<E> bind_status(pybind11::module_& m, const char* name,
                               std::initializer_list<std::pair<const char*, E>> aliases = {}) {
  pybind11::enum_<E> e(m, name, "Status enum read from satgnc/core/status.hpp; .message gives the text.");
  for (const core::StatusEntry& row : core::status_table<E>())
    e.value(row.name, static_cast<E>(row.value), row.message);
  for (const auto& alias : aliases) e.value(alias.first, alias.second);
  e.def_property_readonly("message", [](E s) { return std::string(core::status_message(s)); });
  return e;
}

}  // namespace satgnc::bindings
