// pybind11 wrappers for the propagation_analytic part.
#include <pybind11/pybind11.h>

namespace satgnc::bindings {
void init_propagation_analytic(pybind11::module_& m) { (void)m; }
}  // namespace satgnc::bindings
