#pragma once
/// @file no_malloc.hpp
/// No-allocation guard of the solver contract (core/solver.hpp): `SATGNC_NO_MALLOC_SCOPE;` as the
/// first line of an allocation-free solve() forbids Eigen heap allocation until the end of the
/// enclosing scope, as proxsuite does.
///
/// Active only where the translation unit is compiled with EIGEN_RUNTIME_NO_MALLOC (the
/// `satgnc_core_guarded` library that the gtest binaries link); empty otherwise (the installed
/// library, the Python module and the examples). Eigen reports an allocation inside the scope
/// through eigen_assert, so it aborts in builds with assertions (Debug, the sanitizer build); with
/// NDEBUG the switch is still set and readable (core::malloc_allowed()). Eigen's switch is one
/// process-wide flag, not thread-local: never enable the guard in a library used from several
/// threads (the Python module releases the GIL around solves).
/// It sees Eigen allocations only; tests/cpp/malloc_counter.hpp also sees std::vector, CVODES and
/// operator new.
#include <Eigen/Core>

namespace satgnc::core {

#if defined(EIGEN_RUNTIME_NO_MALLOC)
/// RAII: forbids Eigen heap allocation for its lifetime, then restores the previous state.
class NoMallocScope {
 public:
  NoMallocScope() noexcept : previous_(Eigen::internal::is_malloc_allowed()) {
    Eigen::internal::set_is_malloc_allowed(false);
  }
  ~NoMallocScope() { Eigen::internal::set_is_malloc_allowed(previous_); }
  NoMallocScope(const NoMallocScope&) = delete;
  NoMallocScope& operator=(const NoMallocScope&) = delete;

 private:
  bool previous_;
};
/// True when the guard is compiled in (EIGEN_RUNTIME_NO_MALLOC).
inline constexpr bool kNoMallocGuard = true;
/// Whether Eigen may allocate now (false inside a SATGNC_NO_MALLOC_SCOPE of a guarded build).
inline bool malloc_allowed() noexcept { return Eigen::internal::is_malloc_allowed(); }
#define SATGNC_NO_MALLOC_SCOPE const ::satgnc::core::NoMallocScope satgnc_no_malloc_scope_
#else
inline constexpr bool kNoMallocGuard = false;
inline bool malloc_allowed() noexcept { return true; }
#define SATGNC_NO_MALLOC_SCOPE static_cast<void>(0)
#endif

}  // namespace satgnc::core
