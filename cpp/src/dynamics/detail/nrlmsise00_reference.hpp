#pragma once
// NRLMSISE-00 with every periodic term evaluated as the Fortran writes it, cos(w (x - p[k])) per term
// and per parameter row: the reference the library's phase-table form (cos / sin of w x once per
// evaluation, of w p[k] once per process) is tested and benchmarked against. Not installed.
#include "satgnc/dynamics/nrlmsise00.hpp"

namespace satgnc::dynamics::detail::msis {

/// nrlmsise00() with the direct trigonometric terms (about 10x more cos / sin calls).
Nrlmsise00Output nrlmsise00_direct(const Nrlmsise00Input& in, const Nrlmsise00Switches& switches,
                                   bool anomalous_oxygen) noexcept;

}  // namespace satgnc::dynamics::detail::msis
