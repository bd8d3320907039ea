// Files HDF5 writes to the disk: the sink driver.
//
// summary.h5 grows with the number of cases, so it is not built in memory:
// HDF5 writes it, block of rows by block of rows, through a minimal virtual file driver
// straight into the temporary file of an AtomicFile. The driver never reports a failed write to
// HDF5 (HDF5 1.10 cannot close a file whose writes failed, and crashed at exit on it): the
// first failure (a full disk) is latched in its SinkTarget and later writes are dropped; the
// writer reports the latched error once HDF5 has closed the file, through the AtomicFile, which
// removes the temporary file. HDF5 reads back metadata it has evicted from its cache: reads
// come from the temporary file (after a failure, what was dropped reads as zeros; an HDF5 error
// that follows from it gives way to the latched one). Nothing of the driver is stored in the
// file: any HDF5 reader opens it with its default driver.
#pragma once

#include "sweep/results/hdf5.hpp"

namespace rodend::results_detail {

/// Where a sink file goes (its driver info): an open file descriptor, and the first failure.
struct SinkTarget {
  int fd = -1;
  int error = 0;  ///< errno of the first failed write, read or truncation; 0: none
};

/// A file access property list that writes through the sink driver into `target` (which must
/// outlive the file). Call under Hdf5Lock.
Handle sink_access(const Context& cx, SinkTarget& target);

}  // namespace rodend::results_detail
