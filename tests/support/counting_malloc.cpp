// SPDX-License-Identifier: MIT
#include "counting_malloc.hpp"

#include <atomic>
#include <cstddef>

#if defined(__SANITIZE_ADDRESS__)
#define EXCITE_NO_MALLOC_INTERPOSE 1
#endif
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define EXCITE_NO_MALLOC_INTERPOSE 1
#endif
#endif

namespace {
std::atomic<long> g_mallocs{0};
}  // namespace

namespace excite::test {
long mallocs() {
  return g_mallocs.load(std::memory_order_relaxed);
}
bool malloc_interposed() {
#ifdef EXCITE_NO_MALLOC_INTERPOSE
  return false;
#else
  return true;
#endif
}
}  // namespace excite::test

#ifndef EXCITE_NO_MALLOC_INTERPOSE
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);

void* malloc(std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
void* calloc(std::size_t n, std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, size);
}
void* memalign(std::size_t alignment, std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  void* p = __libc_memalign(alignment, size);
  if (p == nullptr) return 12;  // ENOMEM
  *out = p;
  return 0;
}
}
#endif
