#pragma once
// Allocation counter for the no-heap-in-solve tests. Include it in exactly one test file per binary:
// the binary interposes malloc, calloc, realloc, posix_memalign and aligned_alloc (glibc forwards to
// __libc_*), which also sees operator new / new[] and Eigen's aligned allocations. Count with
// `g_mallocs = 0; g_count = true; ...; g_count = false;`. Under AddressSanitizer malloc belongs to
// ASan (mixing in __libc_malloc crashes), so the interposer is compiled out there and the counts stay
// 0; the release build is where the proof runs.
#include <atomic>
#include <cstddef>
#include <cstdlib>  // glibc declares the allocators noexcept: the definitions below match

namespace {
std::atomic<long> g_mallocs{0};
std::atomic<bool> g_count{false};
}  // namespace
#if !defined(__SANITIZE_ADDRESS__)
namespace {
inline void count_one() {
  if (g_count.load(std::memory_order_relaxed)) g_mallocs.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace
extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void* __libc_memalign(size_t, size_t);
void* malloc(size_t n) noexcept {
  count_one();
  return __libc_malloc(n);
}
void* calloc(size_t a, size_t b) noexcept {
  count_one();
  return __libc_calloc(a, b);
}
void* realloc(void* p, size_t n) noexcept {
  count_one();
  return __libc_realloc(p, n);
}
int posix_memalign(void** p, size_t al, size_t n) noexcept {
  count_one();
  *p = __libc_memalign(al, n);
  return *p ? 0 : 12;  // ENOMEM
}
void* aligned_alloc(size_t al, size_t n) noexcept {
  count_one();
  return __libc_memalign(al, n);
}
}
#endif
