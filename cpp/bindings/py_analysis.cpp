// pybind11 wrappers for the analysis room.
#include <pybind11/pybind11.h>

namespace satgnc::bindings {
void init_analysis(pybind11::module_& m) { (void)m; }
}  // namespace satgnc::bindings
