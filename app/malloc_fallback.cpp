// The rodend executable's malloc: glibc's, and when glibc refuses an allocation, a block of the
// calling thread's MemoryReserve if it holds one (sweep/memory_reserve.hpp: HDF5 1.10 crashes on
// a refused allocation, so its sessions run with memory set aside). Defining malloc, calloc,
// realloc and free in the executable replaces them for every library (glibc's documented way,
// "Replacing malloc"); memalign and its kin stay glibc's, their blocks are freed here as any.
// malloc_usable_size stays glibc's too: nothing rodend links asks it about a reserve's block.
//
// Not in a sanitizer build (its runtime owns malloc). A fault injector preloaded by the tests
// (tests/faults/failalloc.c) is reached through the weak symbol rodend_fault_inject_alloc:
// the executable's malloc takes precedence over a preloaded one, so it asks the injector.
#if defined(__SANITIZE_ADDRESS__)
#define RODEND_MALLOC_FALLBACK 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer)
#define RODEND_MALLOC_FALLBACK 0
#endif
#endif
#ifndef RODEND_MALLOC_FALLBACK
#define RODEND_MALLOC_FALLBACK 1
#endif

#if RODEND_MALLOC_FALLBACK
#include <cerrno>
#include <cstddef>
#include <cstring>

#include <malloc.h>

#include "sweep/memory_reserve.hpp"

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void __libc_free(void*);
/// Defined by the test suite's fault injector when it is preloaded; nonzero: fail this one.
int rodend_fault_inject_alloc(const void* caller) __attribute__((weak));
}

namespace {

inline bool injected_failure(const void* caller) {
  if (rodend_fault_inject_alloc == nullptr || rodend_fault_inject_alloc(caller) == 0) return false;
  errno = ENOMEM;
  return true;
}

__attribute__((constructor(101))) void enable_reserves() {
  rodend_reserve_enable();
}

}  // namespace

extern "C" {

void* malloc(std::size_t size) {
  if (injected_failure(__builtin_return_address(0))) return nullptr;
  void* p = __libc_malloc(size);
  return p != nullptr ? p : rodend_reserve_alloc(size);
}

void* calloc(std::size_t n, std::size_t size) {
  if (injected_failure(__builtin_return_address(0))) return nullptr;
  void* p = __libc_calloc(n, size);
  if (p != nullptr || (size != 0 && n > static_cast<std::size_t>(-1) / size)) return p;
  return rodend_reserve_alloc(n * size);  // a reserve's blocks are zero already
}

void free(void* p) {
  if (rodend_reserve_free(p) == 0) __libc_free(p);
}

void* realloc(void* p, std::size_t size) {
  if (injected_failure(__builtin_return_address(0))) return nullptr;
  const std::size_t old = rodend_reserve_block_size(p);
  if (old == 0) {  // glibc's block (or none)
    void* q = __libc_realloc(p, size);
    if (q != nullptr || size == 0) return q;
    q = rodend_reserve_alloc(size);
    if (q != nullptr && p != nullptr) {
      const std::size_t had = malloc_usable_size(p);  // glibc's (not replaced here)
      std::memcpy(q, p, had < size ? had : size);
      __libc_free(p);
    }
    return q;
  }
  if (size == 0) {
    rodend_reserve_free(p);
    return nullptr;
  }
  void* q = __libc_malloc(size);
  if (q == nullptr) q = rodend_reserve_alloc(size);
  if (q == nullptr) return nullptr;
  std::memcpy(q, p, old < size ? old : size);
  rodend_reserve_free(p);
  return q;
}

}  // extern "C"
#endif
