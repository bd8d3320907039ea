// One reading of a POSIX clock, in nanoseconds: the timings of the HDF5 lock's and the MPI
// dispatcher's statistics (RODEND_LOCK_STATS, RODEND_MPI_STATS).
#pragma once

#include <ctime>

namespace rodend {

/// The clock `clock` (CLOCK_MONOTONIC, CLOCK_REALTIME, CLOCK_THREAD_CPUTIME_ID) [ns].
inline long long clock_ns(clockid_t clock = CLOCK_MONOTONIC) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<long long>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

}  // namespace rodend
