/* Allocation-failure injection for the fault suite (issue 37 item 8;
 * tests/cli/test_alloc_failures.py), in the spirit of SQLite's malloc tests: preloaded (LD_PRELOAD)
 * into a rodend process, it makes the K-th allocation (any entry point of rodend's allocator,
 * app/malloc_fallback.cpp, counted over every thread) fail (NULL, errno ENOMEM), and with
 * RODEND_FAIL_ALLOC_PERSIST=1 every call after it too. Without RODEND_FAIL_ALLOC it only counts,
 * and prints the count to stderr at exit when RODEND_FAIL_ALLOC_COUNT=1 (how many allocations a run
 * makes, to choose the K's).
 *
 * Only the allocations that rodend's code makes are counted and failed: those called from the
 * executable itself, from libstdc++ (operator new on rodend's behalf), SUNDIALS and libdeflate.
 * HDF5 and libgomp are left alone: they do not survive a failed allocation whatever their caller
 * does (HDF5 1.10 dereferences one in H5SL_insert while initialising; libgomp prints "out of
 * memory" and exits 1), and neither do the GnuTLS constructors that run before main.
 *
 * RODEND_FAIL_ALLOC_SPARE="lo-hi,lo-hi,...": address ranges (offsets in the executable, from its
 * symbol table) of functions an allocation inside which is never failed: nlohmann::json's
 * destructor (json_value::destroy) allocates its work stack inside a noexcept destructor, so a
 * failure there ends any program in std::terminate whatever it does (a limit of the library, like
 * HDF5's above). When the K-th allocation is made inside one of them, the next one fails instead.
 *
 * Test code only: never linked into rodend. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <link.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <unwind.h>

static long fail_at = -2; /* -2: not read yet; -1: never */
/* the executable segments of the objects whose allocations are counted */
#define MAX_RANGES 64
static uintptr_t range_lo[MAX_RANGES], range_hi[MAX_RANGES];
static int ranges = 0;

static int counted_object(const char* name) {
  return name[0] == '\0' || strstr(name, "libstdc++") || strstr(name, "libsundials") ||
         strstr(name, "libdeflate");
}

static int collect(struct dl_phdr_info* info, size_t size, void* data) {
  (void)size;
  (void)data;
  if (!counted_object(info->dlpi_name)) return 0;
  for (int i = 0; i < info->dlpi_phnum && ranges < MAX_RANGES; ++i) {
    const ElfW(Phdr)* ph = &info->dlpi_phdr[i];
    if (ph->p_type != PT_LOAD || !(ph->p_flags & PF_X)) continue;
    range_lo[ranges] = info->dlpi_addr + ph->p_vaddr;
    range_hi[ranges] = range_lo[ranges] + ph->p_memsz;
    ++ranges;
  }
  return 0;
}

static int from_counted(const void* caller) {
  const uintptr_t a = (uintptr_t)caller;
  for (int i = 0; i < ranges; ++i)
    if (a >= range_lo[i] && a < range_hi[i]) return 1;
  return 0;
}
/* RODEND_FAIL_ALLOC_SPARE, as absolute addresses */
#define MAX_SPARE 64
static uintptr_t spare_lo[MAX_SPARE], spare_hi[MAX_SPARE];
static int spares = 0;

static int exe_base(struct dl_phdr_info* info, size_t size, void* data) {
  (void)size;
  if (info->dlpi_name[0] != '\0') return 0;
  *(uintptr_t*)data = info->dlpi_addr;
  return 1;
}

static void read_spares(void) {
  const char* s = getenv("RODEND_FAIL_ALLOC_SPARE");
  if (!s) return;
  uintptr_t base = 0;
  dl_iterate_phdr(exe_base, &base);
  while (*s && spares < MAX_SPARE) {
    char* end;
    const unsigned long lo = strtoul(s, &end, 16);
    if (*end != '-') break;
    const unsigned long hi = strtoul(end + 1, &end, 16);
    spare_lo[spares] = base + lo;
    spare_hi[spares] = base + hi;
    ++spares;
    s = *end == ',' ? end + 1 : end;
  }
}

/* _Unwind_Backtrace does not allocate once libgcc_s is loaded (it is: C++ exceptions) */
static _Unwind_Reason_Code spare_frame(struct _Unwind_Context* cx, void* found) {
  const uintptr_t ip = (uintptr_t)_Unwind_GetIP(cx);
  for (int i = 0; i < spares; ++i)
    if (ip > spare_lo[i] && ip <= spare_hi[i]) {
      *(int*)found = 1;
      return _URC_END_OF_STACK;
    }
  return _URC_NO_REASON;
}

static int in_spared_function(void) {
  int found = 0;
  if (spares > 0) _Unwind_Backtrace(spare_frame, &found);
  return found;
}

static int persist = 0;
static long calls = 0;

static void report_count(void) {
  char buf[64];
  int n = snprintf(buf, sizeof buf, "failalloc: %ld allocations\n", calls);
  if (n > 0) (void)!write(2, buf, (size_t)n);
}

/* counting starts in main: a failure in a static constructor before it is out of every
 * program's reach */
static int in_main = 0;
typedef int (*main_fn)(int, char**, char**);
static main_fn real_main;
static int marked_main(int argc, char** argv, char** envp) {
  __atomic_store_n(&in_main, 1, __ATOMIC_RELEASE);
  return real_main(argc, argv, envp);
}
int __libc_start_main(main_fn main, int argc, char** argv, void (*init)(void), void (*fini)(void),
                      void (*rtld_fini)(void), void* stack_end) {
  typedef int (*start_fn)(main_fn, int, char**, void (*)(void), void (*)(void), void (*)(void),
                          void*);
  start_fn real = (start_fn)dlsym(RTLD_NEXT, "__libc_start_main");
  real_main = main;
  return real(marked_main, argc, argv, init, fini, rtld_fini, stack_end);
}

static int fail_now(const void* caller) {
  if (__atomic_load_n(&fail_at, __ATOMIC_ACQUIRE) == -2) {
    dl_iterate_phdr(collect, NULL);
    const char* at = getenv("RODEND_FAIL_ALLOC");
    const char* p = getenv("RODEND_FAIL_ALLOC_PERSIST");
    const char* count = getenv("RODEND_FAIL_ALLOC_COUNT");
    persist = p && strcmp(p, "1") == 0;
    read_spares();
    __atomic_store_n(&fail_at, at ? atol(at) : -1, __ATOMIC_RELEASE);
    /* after fail_at is set: atexit may allocate, which comes back here */
    if (count && strcmp(count, "1") == 0) atexit(report_count);
  }
  if (!__atomic_load_n(&in_main, __ATOMIC_ACQUIRE) || !from_counted(caller)) return 0;
  const long n = __atomic_add_fetch(&calls, 1, __ATOMIC_RELAXED);
  if (fail_at < 0) return 0;
  if (n == fail_at && !persist && in_spared_function()) {
    __atomic_add_fetch(&fail_at, 1, __ATOMIC_RELAXED); /* the next one fails instead */
    return 0;
  }
  if (n == fail_at || (persist && n > fail_at)) {
    errno = ENOMEM;
    return 1;
  }
  return 0;
}

/* The rodend executable defines every allocator entry point itself (app/malloc_fallback.cpp:
 * HDF5's sessions draw on a reserve) and asks here, naming its caller. This library defines none
 * (the executable's would reach them through dlsym(RTLD_NEXT) and count every call twice). */
int rodend_fault_inject_alloc(const void* caller) {
  return fail_now(caller);
}
