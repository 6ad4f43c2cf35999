// pybind11 wrappers for the guidance room.
#include <pybind11/pybind11.h>

namespace satgnc::bindings {
void init_guidance(pybind11::module_& m) { (void)m; }
}  // namespace satgnc::bindings
