// pybind11 entry point: each room registers its own wrappers (no algorithm lives here).
#include <pybind11/pybind11.h>

namespace satgnc::bindings {
void init_core(pybind11::module_& m);
void init_time(pybind11::module_& m);
void init_frames(pybind11::module_& m);
void init_atmosphere(pybind11::module_& m);
void init_dynamics(pybind11::module_& m);
void init_force_models(pybind11::module_& m);
void init_propagation(pybind11::module_& m);
void init_propagation_analytic(pybind11::module_& m);
void init_ensemble(pybind11::module_& m);
void init_od(pybind11::module_& m);
void init_guidance(pybind11::module_& m);
void init_guidance_nonlinear(pybind11::module_& m);
void init_guidance_state(pybind11::module_& m);
void init_analysis(pybind11::module_& m);
void init_io(pybind11::module_& m);
void init_observation(pybind11::module_& m);
void init_thrusters(pybind11::module_& m);
}  // namespace satgnc::bindings

PYBIND11_MODULE(_satgnc, m) {
  m.doc() = "satgnc C++ engine (use the satgnc package, not this module directly)";
  m.attr("__version__") = SATGNC_VERSION_STRING;
  namespace b = satgnc::bindings;
  b::init_core(m);
  b::init_time(m);
  b::init_frames(m);
  b::init_atmosphere(m);  // before init_dynamics: ForceModel names AtmosphereDrag
  b::init_dynamics(m);
  b::init_force_models(m);
  b::init_propagation(m);
  b::init_propagation_analytic(m);
  b::init_ensemble(m);
  b::init_od(m);
  b::init_guidance(m);
  b::init_guidance_nonlinear(m);
  b::init_guidance_state(m);
  b::init_analysis(m);
  b::init_io(m);
  b::init_observation(m);
  b::init_thrusters(m);
}
