// pybind11 wrappers for the dynamics room.
#include <pybind11/pybind11.h>

namespace satgnc::bindings {
void init_dynamics(pybind11::module_& m) { (void)m; }
}  // namespace satgnc::bindings
