#pragma once
// The L1 ADMM result dict, shared by AdmmSolver.solve() (py_guidance.cpp) and
// StateConstrainedAdmm.solve() (py_guidance_state.cpp, which adds its state-constraint fields).
#include <pybind11/pybind11.h>

#include "satgnc/guidance/admm.hpp"

namespace satgnc::bindings {

/// Every field of an AdmmResult and of its AdmmInfo as a dict (arrays nu x N / nx x (N+1), the
/// solver's units); `status` is the enum's value and `status_name` its message.
pybind11::dict admm_result_to_dict(const guidance::AdmmResult& r);

}  // namespace satgnc::bindings
