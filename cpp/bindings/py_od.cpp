// pybind11 wrappers for the od room.
#include <pybind11/pybind11.h>

namespace satgnc::bindings {
void init_od(pybind11::module_& m) { (void)m; }
}  // namespace satgnc::bindings
