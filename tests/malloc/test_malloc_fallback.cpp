// Every allocator entry point of app/malloc_fallback.cpp (linked into this program as into rodend):
// malloc, calloc, realloc, reallocarray, free, memalign, posix_memalign, aligned_alloc, valloc,
// pvalloc, malloc_usable_size. First with glibc's blocks; then, inside a MemoryReserve with the
// address space limited to what is mapped (setrlimit RLIMIT_AS, as `ulimit -v` does) so that
// glibc refuses every large allocation, with the reserve's blocks: each entry point must return
// one, aligned as asked, of the usable size malloc_usable_size reports, zeroed by calloc, its
// contents kept by realloc and reallocarray across glibc's blocks and the reserve's, and freed by
// free. Exit 0 when every check holds; each failed check is printed.
#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "sweep/memory_reserve.hpp"

namespace {

int g_failures = 0;

void check(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "FAIL: %s\n", what);
  ++g_failures;
}

bool aligned_to(const void* p, std::size_t a) {
  return reinterpret_cast<std::uintptr_t>(p) % a == 0;
}

bool filled(const void* p, std::size_t n, unsigned char c) {
  const auto* b = static_cast<const unsigned char*>(p);
  for (std::size_t i = 0; i < n; ++i)
    if (b[i] != c) return false;
  return true;
}

/// `p` is a reserve's block of at least `n` usable bytes, which malloc_usable_size reports.
void check_reserve_block(void* p, std::size_t n, const char* what) {
  char msg[160];
  std::snprintf(msg, sizeof msg, "%s: a reserve's block of %zu bytes", what, n);
  check(p != nullptr && rodend_reserve_block_size(p) >= n, msg);
  if (p == nullptr) return;
  std::snprintf(msg, sizeof msg, "%s: malloc_usable_size of the reserve's block", what);
  check(malloc_usable_size(p) == rodend_reserve_block_size(p), msg);
}

/// Every entry point on glibc's blocks (no limit).
void glibc_blocks(std::size_t page) {
  void* a = malloc(100);
  check(a != nullptr && malloc_usable_size(a) >= 100 && rodend_reserve_block_size(a) == 0,
        "malloc: glibc's block");
  void* b = calloc(10, 10);
  check(b != nullptr && filled(b, 100, 0), "calloc: zeroed");
  std::memset(a, 7, 100);
  a = realloc(a, 5000);
  check(a != nullptr && filled(a, 100, 7), "realloc: contents kept");
  a = reallocarray(a, 100, 100);
  check(a != nullptr && filled(a, 100, 7), "reallocarray: contents kept");
  errno = 0;
  volatile std::size_t huge = SIZE_MAX / 2;  // volatile: no compile-time size warning
  void* volatile same = a;                   // (a refused reallocarray leaves `a` as it was)
  check(reallocarray(same, huge, 3) == nullptr && errno == ENOMEM,
        "reallocarray: overflow refused with ENOMEM");
  void* c = memalign(256, 1000);
  void* d = aligned_alloc(4096, 4096);
  void* e = nullptr;
  check(posix_memalign(&e, 64, 1000) == 0 && aligned_to(e, 64), "posix_memalign: aligned");
  check(posix_memalign(&e, 3, 1000) == EINVAL, "posix_memalign: alignment 3 refused");
  void* f = valloc(10);
  void* g = pvalloc(10);
  check(c != nullptr && aligned_to(c, 256), "memalign: aligned");
  check(d != nullptr && aligned_to(d, 4096), "aligned_alloc: aligned");
  check(f != nullptr && aligned_to(f, page), "valloc: page-aligned");
  check(g != nullptr && aligned_to(g, page) && malloc_usable_size(g) >= page,
        "pvalloc: a whole page");
  for (void* p : {a, b, c, d, e, f, g}) free(p);
  free(nullptr);
}

/// The address space in use now (bytes).
std::size_t mapped_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages = 0;
  statm >> pages;
  return pages * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

/// Every entry point on a reserve's blocks: glibc gets no more address space meanwhile.
void reserve_blocks(std::size_t page) {
  constexpr std::size_t kBig = 8 << 20;  // more than the limit leaves glibc
  void* glibc_block = malloc(64 << 10);  // before the limit
  std::memset(glibc_block, 5, 64 << 10);
  rodend::MemoryReserve reserve(256 << 20);
  rlimit old{};
  getrlimit(RLIMIT_AS, &old);
  rlimit lim = old;
  lim.rlim_cur = mapped_bytes() + (2 << 20);  // a little for the stack and small blocks
  check(setrlimit(RLIMIT_AS, &lim) == 0, "setrlimit");
  void* a = malloc(kBig);
  check_reserve_block(a, kBig, "malloc");
  void* b = calloc(kBig / 8, 8);
  check_reserve_block(b, kBig, "calloc");
  check(b != nullptr && filled(b, kBig, 0), "calloc: the reserve's block is zeroed");
  void* moved = realloc(glibc_block, kBig);  // glibc's block to the reserve
  check_reserve_block(moved, kBig, "realloc of glibc's block");
  check(moved != nullptr && filled(moved, 64 << 10, 5), "realloc of glibc's block: contents kept");
  if (a != nullptr) std::memset(a, 9, kBig);
  a = realloc(a, 2 * kBig);  // the reserve's block to a larger one
  check_reserve_block(a, 2 * kBig, "realloc of the reserve's block");
  check(a != nullptr && filled(a, kBig, 9), "realloc of the reserve's block: contents kept");
  a = reallocarray(a, 3, kBig);
  check_reserve_block(a, 3 * kBig, "reallocarray");
  check(a != nullptr && filled(a, kBig, 9), "reallocarray: contents kept");
  void* c = memalign(4096, kBig);
  check_reserve_block(c, kBig, "memalign");
  check(aligned_to(c, 4096), "memalign: the reserve's block aligned");
  void* d = aligned_alloc(1 << 16, kBig);
  check_reserve_block(d, kBig, "aligned_alloc");
  check(aligned_to(d, 1 << 16), "aligned_alloc: the reserve's block aligned");
  void* e = nullptr;
  check(posix_memalign(&e, 128, kBig) == 0, "posix_memalign: served");
  check_reserve_block(e, kBig, "posix_memalign");
  check(aligned_to(e, 128), "posix_memalign: the reserve's block aligned");
  void* f = valloc(kBig);
  check_reserve_block(f, kBig, "valloc");
  check(aligned_to(f, page), "valloc: the reserve's block page-aligned");
  void* g = pvalloc(kBig + 1);
  check_reserve_block(g, kBig + page, "pvalloc");
  check(aligned_to(g, page), "pvalloc: the reserve's block page-aligned");
  check(reserve.drawn() >= 9 * kBig, "the reserve served every block");
  for (void* p : {a, b, moved, c, d, e, f, g}) free(p);
  setrlimit(RLIMIT_AS, &old);
}

}  // namespace

int main() {
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  glibc_blocks(page);
  reserve_blocks(page);
  if (g_failures > 0) {
    std::fprintf(stderr, "malloc_fallback: %d check(s) failed\n", g_failures);
    return 1;
  }
  std::printf("malloc_fallback: every entry point checked, glibc's blocks and a reserve's\n");
  return 0;
}
