// pybind11 wrappers for the propagation room.
#include <pybind11/pybind11.h>

namespace satgnc::bindings {
void init_propagation(pybind11::module_& m) { (void)m; }
}  // namespace satgnc::bindings
