// pybind11 wrappers for the force-model TOML (dynamics/force_model_config.hpp). A
// ForceModelConfigError becomes satgnc.FileFormatError (path, line, reason, key).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include "satgnc/dynamics/force_model_config.hpp"

namespace py = pybind11;

namespace satgnc::bindings {

void init_force_model_config(py::module_& m) {
  namespace dy = dynamics;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const dy::ForceModelConfigError& e) {
      py::object cls = py::module_::import("satgnc._validate").attr("FileFormatError");
      py::object line = e.line() > 0 ? py::object(py::int_(e.line())) : py::object(py::none());
      const std::string reason = e.key().empty() ? e.rule() : e.key() + ": " + e.rule();
      py::object key = e.key().empty() ? py::object(py::none()) : py::object(py::str(e.key()));
      py::object err = cls(e.file(), line, reason, key);
      PyErr_SetObject(cls.ptr(), err.ptr());
    }
  });
  py::class_<dy::ForceModelConfig>(m, "ForceModelConfig",
                                   "A force-model TOML as read: the ForceModel and what it was built from.")
      .def_readonly("model", &dy::ForceModelConfig::model)
      .def_readonly("epoch", &dy::ForceModelConfig::epoch)
      .def_readonly("space_weather", &dy::ForceModelConfig::space_weather)
      .def_readonly("gravity_model", &dy::ForceModelConfig::gravity_model)
      .def_readonly("gravity_file", &dy::ForceModelConfig::gravity_file)
      .def_readonly("atmosphere", &dy::ForceModelConfig::atmosphere)
      .def_readonly("earth_orientation", &dy::ForceModelConfig::earth_orientation)
      .def_readonly("eop_file", &dy::ForceModelConfig::eop_file)
      .def_readonly("ephemeris_file", &dy::ForceModelConfig::ephemeris_file)
      .def_readonly("source", &dy::ForceModelConfig::source)
      .def_readonly("radius", &dy::ForceModelConfig::radius);
  m.def("two_satellite_params_from_config", &dy::two_satellite_params, py::arg("config"),
        py::arg("base") = dy::TwoSatelliteParams(),
        "TwoSatelliteParams (SI) of the guidance truth from a force-model TOML's config.");
  m.def("load_force_model_config", &dy::load_force_model_config, py::arg("path"),
        py::arg("egm2008_path") = "",
        "Read a force-model TOML (schema: docs/force_models.md); errors name the file, line, section, key.");
  m.def(
      "parse_force_model_config",
      [](const std::string& text, const std::string& source, const std::string& base_dir,
         const std::string& egm2008_path) {
        return dy::parse_force_model_config(text, source, base_dir, egm2008_path);
      },
      py::arg("text"), py::arg("source"), py::arg("base_dir") = ".", py::arg("egm2008_path") = "");
}

}  // namespace satgnc::bindings
