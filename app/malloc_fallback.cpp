// The rodend executable's allocator: glibc's, and when glibc refuses an allocation, a block of
// the calling thread's MemoryReserve if it holds one (sweep/memory_reserve.hpp: HDF5 1.10 crashes
// on a refused allocation, so its sessions run with memory set aside).
//
// glibc's rules for a replacement (its manual, "Replacing malloc"): defining malloc, free, calloc
// and realloc in the executable replaces them for every library, and a replacement defines
// aligned_alloc, malloc_usable_size, memalign, posix_memalign, pvalloc and valloc too (and
// reallocarray), so that none of glibc's versions meets a block it did not make. Every one is
// defined here. glibc's own definitions are reached through dlsym(RTLD_NEXT) (the documented
// way to call the definition one interposes; no private __libc_* symbol), resolved
// before the first library constructor runs (.preinit_array); the few allocations the dynamic
// linker makes before that come from a static bootstrap area and are never given back. The
// reserve's thread-local state is initial-exec (reaching it allocates nothing).
// tests/malloc/test_malloc_fallback.cpp checks each entry point, with glibc's blocks and with a
// reserve's under an address-space limit.
//
// Not in a sanitizer build (its runtime owns malloc). A fault injector preloaded by the tests
// (tests/faults/failalloc.c) is reached through the weak symbol rodend_fault_inject_alloc: the
// executable's definitions take precedence over a preloaded library's, so they ask the injector.
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
#include <dlfcn.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "sweep/memory_reserve.hpp"

extern "C" {
/// Defined by the test suite's fault injector when it is preloaded; nonzero: fail this one.
int rodend_fault_inject_alloc(const void* caller) __attribute__((weak));
}

namespace {

using std::size_t;

/// glibc's definitions of what this file defines.
struct Libc {
  void* (*malloc)(size_t);
  void* (*calloc)(size_t, size_t);
  void* (*realloc)(void*, size_t);
  void (*free)(void*);
  void* (*memalign)(size_t, size_t);  // also posix_memalign's, valloc's and pvalloc's
  void* (*aligned_alloc)(size_t, size_t);
  size_t (*malloc_usable_size)(void*);
};
Libc g_libc;
std::atomic<bool> g_resolved{false};

// Allocations before g_libc is resolved (the dynamic linker's, and dlsym's own while it resolves).
constexpr size_t kBootBytes = 256 * 1024;
constexpr size_t kHeader = 16;  // a bootstrap block's size, before it
alignas(64) unsigned char g_boot[kBootBytes];
std::atomic<size_t> g_boot_used{0};

bool in_boot(const void* p) {
  const auto* c = static_cast<const unsigned char*>(p);
  return c >= g_boot && c < g_boot + kBootBytes;
}

void* boot_alloc(size_t alignment, size_t size) {
  if (alignment < kHeader) alignment = kHeader;
  size_t used = g_boot_used.load();
  for (;;) {
    const size_t at = (used + kHeader + alignment - 1) & ~(alignment - 1);
    const size_t end = at + ((size + 15) & ~size_t{15});
    if (size > kBootBytes || end > kBootBytes) {
      errno = ENOMEM;
      return nullptr;
    }
    if (g_boot_used.compare_exchange_weak(used, end)) {
      std::memcpy(g_boot + at - kHeader, &size, sizeof size);  // never reused: the rest is zero
      return g_boot + at;
    }
  }
}

size_t boot_size(const void* p) {
  size_t size = 0;
  std::memcpy(&size, static_cast<const unsigned char*>(p) - kHeader, sizeof size);
  return size;
}

template <class F>
void resolve_one(void* libc, const char* name, F& f) {
  f = reinterpret_cast<F>(::dlsym(libc, name));
  if (f != nullptr) return;
  static const char msg[] = "rodend: cannot find glibc's allocator functions\n";
  const ssize_t w = ::write(2, msg, sizeof msg - 1);
  (void)w;
  std::abort();
}

/// Resolves g_libc (once; its own allocations come from the bootstrap area). RTLD_NEXT: the
/// next definition after the executable's, glibc's (or a preloaded allocator's). Not dlopen:
/// before libc's initialiser has run, dlopen would run it with an empty environment.
void resolve_libc() {
  if (g_resolved.load(std::memory_order_acquire)) return;
  resolve_one(RTLD_NEXT, "malloc", g_libc.malloc);
  resolve_one(RTLD_NEXT, "calloc", g_libc.calloc);
  resolve_one(RTLD_NEXT, "realloc", g_libc.realloc);
  resolve_one(RTLD_NEXT, "free", g_libc.free);
  resolve_one(RTLD_NEXT, "memalign", g_libc.memalign);
  resolve_one(RTLD_NEXT, "aligned_alloc", g_libc.aligned_alloc);
  resolve_one(RTLD_NEXT, "malloc_usable_size", g_libc.malloc_usable_size);
  g_resolved.store(true, std::memory_order_release);
}

/// First of all the program's initialisers, before any library's constructor.
void preinit(int, char**, char**) {
  resolve_libc();
  rodend_reserve_enable();
}
__attribute__((section(".preinit_array"), used)) void (*g_preinit)(int, char**, char**) = preinit;

inline bool resolved() {
  return g_resolved.load(std::memory_order_acquire);
}

inline bool injected_failure(const void* caller) {
  if (rodend_fault_inject_alloc == nullptr || rodend_fault_inject_alloc(caller) == 0) return false;
  errno = ENOMEM;
  return true;
}

/// The usable size of a block of this file's (bootstrap, reserve or glibc's).
size_t usable_size(void* p) {
  if (p == nullptr) return 0;
  if (in_boot(p)) return boot_size(p);
  if (const size_t n = rodend_reserve_block_size(p); n != 0) return n;
  return g_libc.malloc_usable_size(p);
}

/// An aligned block: glibc's, else the reserve's (only when glibc ran out of memory).
void* aligned(void* (*glibc)(size_t, size_t), size_t alignment, size_t size) {
  if (!resolved()) return boot_alloc(alignment, size);
  void* p = glibc(alignment, size);
  if (p != nullptr || errno != ENOMEM) return p;
  return rodend_reserve_alloc_aligned(alignment, size);
}

size_t page_size() {
  static const size_t page = static_cast<size_t>(::sysconf(_SC_PAGESIZE));
  return page;
}

}  // namespace

extern "C" {

void* malloc(size_t size) {
  if (!resolved()) return boot_alloc(16, size);
  if (injected_failure(__builtin_return_address(0))) return nullptr;
  void* p = g_libc.malloc(size);
  return p != nullptr ? p : rodend_reserve_alloc(size);
}

void* calloc(size_t n, size_t size) {
  if (size != 0 && n > static_cast<size_t>(-1) / size) {
    errno = ENOMEM;
    return nullptr;
  }
  if (!resolved()) return boot_alloc(16, n * size);  // zero: never used before
  if (injected_failure(__builtin_return_address(0))) return nullptr;
  void* p = g_libc.calloc(n, size);
  return p != nullptr ? p : rodend_reserve_alloc(n * size);  // a reserve's blocks are zero
}

void free(void* p) {
  if (p == nullptr || in_boot(p) || rodend_reserve_free(p) != 0) return;
  g_libc.free(p);
}

void* realloc(void* p, size_t size) {
  if (p == nullptr) return malloc(size);
  if (size == 0) {
    free(p);
    return nullptr;
  }
  if (injected_failure(__builtin_return_address(0))) return nullptr;
  if (resolved() && !in_boot(p) && rodend_reserve_block_size(p) == 0) {  // glibc's block
    void* q = g_libc.realloc(p, size);
    if (q != nullptr) return q;
  }
  void* q = resolved() ? g_libc.malloc(size) : boot_alloc(16, size);
  if (q == nullptr) q = rodend_reserve_alloc(size);
  if (q == nullptr) return nullptr;  // p is left as it was
  const size_t had = usable_size(p);
  std::memcpy(q, p, had < size ? had : size);
  free(p);
  return q;
}

void* reallocarray(void* p, size_t n, size_t size) {
  if (size != 0 && n > static_cast<size_t>(-1) / size) {
    errno = ENOMEM;
    return nullptr;
  }
  return realloc(p, n * size);
}

size_t malloc_usable_size(void* p) {
  return usable_size(p);
}

void* memalign(size_t alignment, size_t size) {
  if (injected_failure(__builtin_return_address(0))) return nullptr;
  return aligned(resolved() ? g_libc.memalign : nullptr, alignment, size);
}

void* aligned_alloc(size_t alignment, size_t size) {
  if (injected_failure(__builtin_return_address(0))) return nullptr;
  return aligned(resolved() ? g_libc.aligned_alloc : nullptr, alignment, size);
}

int posix_memalign(void** out, size_t alignment, size_t size) {
  if (alignment < sizeof(void*) || (alignment & (alignment - 1)) != 0) return EINVAL;
  if (injected_failure(__builtin_return_address(0))) return ENOMEM;
  const int saved = errno;
  void* p = aligned(resolved() ? g_libc.memalign : nullptr, alignment, size);
  errno = saved;  // posix_memalign reports through its result only
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}

void* valloc(size_t size) {
  if (injected_failure(__builtin_return_address(0))) return nullptr;
  return aligned(resolved() ? g_libc.memalign : nullptr, page_size(), size);
}

void* pvalloc(size_t size) {
  if (injected_failure(__builtin_return_address(0))) return nullptr;
  const size_t page = page_size();
  if (size > static_cast<size_t>(-1) - page) {
    errno = ENOMEM;
    return nullptr;
  }
  const size_t rounded = size == 0 ? page : (size + page - 1) & ~(page - 1);
  return aligned(resolved() ? g_libc.memalign : nullptr, page, rounded);
}

}  // extern "C"
#endif
