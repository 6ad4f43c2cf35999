#pragma once
/// @file nvector.hpp (private to the propagation room; not installed)
/// satgnc's own serial N_Vector: contiguous double storage, the SUNDIALS 6.4 N_Vector ops table,
/// compiled with satgnc's optimisation flags. Every operation reproduces the floating-point
/// operation order of SUNDIALS' NVECTOR_SERIAL (with its fused operations disabled, i.e. the generic
/// fall-backs), so CVODES takes the same steps and returns bitwise-identical results with either
/// vector, while not depending on how the system libsundials was compiled.
#include <sundials/sundials_context.h>
#include <sundials/sundials_nvector.h>

namespace satgnc::propagation {

/// New vector of length n owning its data (uninitialised); free with N_VDestroy. NULL on failure.
N_Vector nvector_new(sunindextype n, SUNContext ctx);
/// Data pointer of a satgnc vector (same as N_VGetArrayPointer).
double* nvector_data(N_Vector v);
/// True when v was created by nvector_new (or cloned from one).
bool nvector_is_satgnc(N_Vector v);

}  // namespace satgnc::propagation
