// The process-wide HDF5 lock (sweep/results/hdf5.hpp, "Thread safety").
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <new>
#include <string_view>

#include "sweep/results/hdf5.hpp"

namespace rodend::results_detail {

namespace {

/// The one process-wide mutex around every HDF5 call.
std::mutex g_hdf5_mutex;

/// Diagnostics (RODEND_LOCK_STATS=1 in the environment): how long g_hdf5_mutex is held, summed
/// over the run, printed on stderr at exit: the serial section of a sweep (bench/README.md);
/// RODEND_LOCK_STATS=2 also prints each time it is released. The count is always kept
/// (hdf5_lock_count).
struct LockStats {
  const bool enabled = std::getenv("RODEND_LOCK_STATS") != nullptr;
  const bool each = enabled && std::string_view(std::getenv("RODEND_LOCK_STATS")) == "2";
  std::atomic<long long> held_ns{0}, held_cpu_ns{0}, count{0};
  ~LockStats() {
    if (enabled)
      std::fprintf(stderr,
                   "rodend: HDF5 lock held %lld times, %.3f s wall, %.3f s CPU of the holder\n",
                   count.load(), 1e-9 * static_cast<double>(held_ns.load()),
                   1e-9 * static_cast<double>(held_cpu_ns.load()));
  }
};
LockStats g_lock_stats;

}  // namespace

Hdf5Lock::Hdf5Lock() : lock_(g_hdf5_mutex), reserve_(kHdf5Headroom) {
  // HDF5's error stacks (and so its automatic printing) are per thread in a thread-safe build:
  // each thread that calls HDF5 switches it off once
  thread_local bool silenced = false;
  if (!silenced) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    silenced = true;
  }
  // HDF5 keeps freed blocks on its own free lists, unbounded by default: after a large
  // summary they held 4.8 MB that no later call reused. Bounded here (per list 256 kB, in all
  // 1 MB per kind), so peak memory does not grow with the number of cases (bench/memory.sh).
  static const bool bounded =
      H5set_free_list_limits(1 << 20, 1 << 18, 1 << 20, 1 << 18, 1 << 20, 1 << 18) >= 0;
  (void)bounded;
  if (g_lock_stats.enabled) {
    t0_ = clock_ns(CLOCK_MONOTONIC);
    cpu0_ = clock_ns(CLOCK_THREAD_CPUTIME_ID);
  }
}

Hdf5Lock::~Hdf5Lock() {
  // blocks HDF5 keeps on its free lists would keep a drawn reserve mapped after the session
  if (reserve_.drawn() > 0) H5garbage_collect();
  ++g_lock_stats.count;
  if (!g_lock_stats.enabled) return;
  g_lock_stats.held_ns += clock_ns(CLOCK_MONOTONIC) - t0_;
  g_lock_stats.held_cpu_ns += clock_ns(CLOCK_THREAD_CPUTIME_ID) - cpu0_;
  if (g_lock_stats.each)
    std::fprintf(stderr, "rodend: HDF5 lock held %.3f ms wall, %.3f ms CPU\n",
                 1e-6 * static_cast<double>(clock_ns(CLOCK_MONOTONIC) - t0_),
                 1e-6 * static_cast<double>(clock_ns(CLOCK_THREAD_CPUTIME_ID) - cpu0_));
}

}  // namespace rodend::results_detail

namespace rodend {

long long hdf5_lock_count() {
  return results_detail::g_lock_stats.count.load();
}

void prepare_results_io() {
  const results_detail::Hdf5Lock lock;  // H5open on first use, the free-list limits, this
                                        // thread's error stack
}

}  // namespace rodend
