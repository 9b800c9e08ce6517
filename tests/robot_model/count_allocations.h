// Counting heap allocations in a test binary: this header replaces malloc and its relatives
// (through glibc's __libc_ entry points), so every heap allocation made while counting is seen
// (operator new, Eigen, MuJoCo's shared library). Include it in exactly one source file of a
// test binary of its own. OHRP_CAN_COUNT is defined when counting works (glibc, and not under
// the sanitizers: AddressSanitizer owns malloc and would not see these).
//
//   EXPECT_EQ(ohrp::testing::Allocations([&] { controller.update(s, &c); }), 0);
#pragma once

#include <malloc.h>

#include <atomic>
#include <cstddef>
#include <cstdlib>
// the system's declarations before the replacements (Eigen includes this one later)
#if __has_include(<mm_malloc.h>)
#include <mm_malloc.h>
#endif

#if defined(__GLIBC__) && !defined(OHRP_SANITIZE)
extern "C" {
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t n, size_t size);
void* __libc_realloc(void* p, size_t size);
void* __libc_memalign(size_t alignment, size_t size);
void __libc_free(void* p);
}

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
void Count() {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace

// the replacements: count, then hand over to glibc's own allocator
extern "C" {
void* malloc(size_t size) {
  Count();
  return __libc_malloc(size);
}
void* calloc(size_t n, size_t size) {
  Count();
  return __libc_calloc(n, size);
}
void* realloc(void* p, size_t size) {
  Count();
  return __libc_realloc(p, size);
}
void* memalign(size_t alignment, size_t size) {
  Count();
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(size_t alignment, size_t size) {
  Count();
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** p, size_t alignment, size_t size) {
  Count();
  *p = __libc_memalign(alignment, size);
  return *p ? 0 : 12;  // ENOMEM
}
void free(void* p) { __libc_free(p); }
}
#define OHRP_CAN_COUNT 1
#endif

#if defined(OHRP_CAN_COUNT)
namespace ohrp::testing {

// counts the heap allocations made by `f`
template <typename F>
long Allocations(F&& f) {
  g_allocations = 0;
  g_counting = true;
  f();
  g_counting = false;
  return g_allocations.load();
}

}  // namespace ohrp::testing
#endif
