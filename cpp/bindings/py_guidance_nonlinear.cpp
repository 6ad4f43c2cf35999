// pybind11 wrappers for the guidance_nonlinear part.
#include <pybind11/pybind11.h>

namespace satgnc::bindings {
void init_guidance_nonlinear(pybind11::module_& m) { (void)m; }
}  // namespace satgnc::bindings
