#pragma once
// Memory set aside for a library that does not survive a failed allocation (HDF5 1.10).
//
// HDF5 dereferences some of its allocations unchecked (H5FL_blk_malloc, H5Eset_auto2): a
// malloc that returns NULL inside it is a SIGSEGV. Checking before the call that enough memory
// is free is not enough with -j 2: while one thread is inside HDF5, the other (integrating a
// case) may take that memory. So a MemoryReserve maps its bytes for the whole HDF5 session, and
// an allocation of the reserving thread that the system refuses is served from them instead
// (app/malloc_fallback.cpp, the rodend executable's allocator: every entry point glibc's rules
// for a replacement name, each glibc's first). The reserve's blocks are ordinary memory to their
// users; freeing the last one unmaps the reserve. Whoever else runs short gets NULL, which rodend's
// own code turns into the clean "out of memory" exit (sweep/runner.cpp).
//
// Without that malloc (the Python module, a sanitizer build) nothing draws on a reserve: it is
// only mapped and unmapped at once, a check that the memory is free at that moment.

#include <cstddef>

namespace rodend {

/// For its lifetime, `bytes` of memory that the calling thread's refused allocations are served
/// from. Throws std::bad_alloc if they cannot be mapped. Reserves nest (innermost drawn first).
class MemoryReserve {
 public:
  explicit MemoryReserve(std::size_t bytes);
  ~MemoryReserve();
  MemoryReserve(const MemoryReserve&) = delete;
  MemoryReserve& operator=(const MemoryReserve&) = delete;

  /// Bytes handed out from this reserve so far (0: the system served every allocation).
  std::size_t drawn() const;

 private:
  int slot_ = -1;  ///< index of the mapped region; -1: only checked (no fallback malloc)
};

}  // namespace rodend

// The interface of the fallback malloc (app/malloc_fallback.cpp); async-signal-unsafe, no
// allocation, no exception.
extern "C" {
/// Called once by the fallback malloc before main: reserves are kept mapped and drawn on.
void rodend_reserve_enable(void) noexcept;
/// A block of `size` bytes (16-byte aligned, zeroed) from the calling thread's innermost
/// reserve with room, or NULL.
void* rodend_reserve_alloc(std::size_t size) noexcept;
/// The same, aligned to `alignment` (a power of two; at least 16 is given); NULL if it is not one.
void* rodend_reserve_alloc_aligned(std::size_t alignment, std::size_t size) noexcept;
/// The usable size of `p` if a reserve's block (then `p` stays valid), else 0.
std::size_t rodend_reserve_block_size(const void* p) noexcept;
/// Frees `p` and returns 1 if it is a reserve's block; 0 (and nothing done) otherwise.
int rodend_reserve_free(void* p) noexcept;
}
