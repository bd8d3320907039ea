// In-memory HDF5 files.
//
// Every case file is built by HDF5 in memory (the core driver without a backing store) and its
// finished image written by write_file_atomically: a full disk, a quota or an I/O error is one
// clear message, never a half-closed HDF5 file (which HDF5 1.10 cannot close again: it crashed
// at exit), and the write of the bytes (the file system's share of the cost) runs outside
// the HDF5 lock. (summary.h5 is written as a stream instead: the sink driver, sink_driver.hpp.)
#pragma once

#include <hdf5.h>

#include <algorithm>
#include <cstddef>

#include "sweep/results/atomic_file.hpp"
#include "sweep/results/hdf5.hpp"

namespace rodend::results_detail {

/// Scratch of the calling thread: a buffer of at least `size` bytes, not zeroed, that the next
/// call with the same `slot` reuses (its pages stay mapped: no fresh page faults per file).
/// Only for bytes that are all written before they are read.
enum class ScratchSlot { encode, image, count_ };
unsigned char* thread_scratch(ScratchSlot slot, std::size_t size);

/// Creates the in-memory file, runs build(file), and returns the file's image (without its
/// user block), in the calling thread's ScratchSlot::image (valid until its next call). `estimate`:
/// the expected size [bytes] (the core driver's allocation step). Call under Hdf5Lock.
template <class Build>
ByteSpan build_image(const Context& cx, hsize_t user_block, std::size_t estimate, Build&& build) {
  ensure_memory_for_hdf5(2 * estimate);  // the estimate at once, and a case growing meanwhile
  const Handle fapl = cx.own(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "cannot create the file");
  cx.ok(H5Pset_fapl_core(fapl.get(), std::max<std::size_t>(estimate, 1 << 16), /*backing=*/0),
        "cannot create the file");
  const Handle fcpl = cx.own(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "cannot create the file");
  if (user_block > 0) cx.ok(H5Pset_userblock(fcpl.get(), user_block), "cannot create the file");
  // the name only identifies the in-memory file to HDF5 (two threads never build at once)
  Handle file = cx.own(H5Fcreate("rodend-in-memory.h5", H5F_ACC_TRUNC, fcpl.get(), fapl.get()),
                       H5Fclose, "cannot create the file");
  build(file.get());
  cx.ok(H5Fflush(file.get(), H5F_SCOPE_LOCAL), "cannot flush the file");
  const ssize_t size = H5Fget_file_image(file.get(), nullptr, 0);
  if (size <= 0) cx.fail("cannot take the file's image");
  unsigned char* const buffer = thread_scratch(ScratchSlot::image, static_cast<std::size_t>(size));
  if (H5Fget_file_image(file.get(), buffer, static_cast<std::size_t>(size)) != size)
    cx.fail("cannot take the file's image");
  cx.ok(file.close(), "cannot close the file");
  return ByteSpan(buffer, static_cast<std::size_t>(size));
}

}  // namespace rodend::results_detail
