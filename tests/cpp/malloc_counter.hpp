#pragma once
// Allocation counter for the no-heap-in-solve tests. Include it in exactly one test file per binary:
// the binary interposes malloc (glibc forwards to __libc_malloc), which also sees operator new and
// Eigen's aligned allocations. Under AddressSanitizer malloc belongs to ASan (mixing in
// __libc_malloc crashes), so the interposer is compiled out there and the counts stay 0; the release
// build is where the proof runs.
#include <atomic>
#include <cstddef>

namespace {
std::atomic<long> g_mallocs{0};
std::atomic<bool> g_count{false};
}  // namespace
#if !defined(__SANITIZE_ADDRESS__)
extern "C" void* __libc_malloc(size_t);
extern "C" void* malloc(size_t n) {
  if (g_count.load(std::memory_order_relaxed)) g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(n);
}
#endif
