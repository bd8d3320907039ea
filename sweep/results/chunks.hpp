// Signal chunks, encoded off the lock.
//
// HDF5's own filter pipeline would shuffle and deflate each chunk inside H5Dwrite, that is
// under the HDF5 lock, where it serialises the threads of a sweep. The thread that ran the case
// does it here instead (the same shuffle filter and zlib-format deflate stream, written by
// libdeflate), and the lock then only hands the finished chunks to H5Dwrite_chunk: every stock
// HDF5 reader (h5py, h5dump) decodes them with its built-in filters, no plugin.
#pragma once

#include <vector>

#include "sweep/results/atomic_file.hpp"
#include "sweep/results/hdf5.hpp"

namespace rodend::results_detail {

/// Row-major chunks of one signal, each padded to the full chunk shape (HDF5 stores edge chunks
/// at full size) and encoded with the dataset's filter pipeline.
struct EncodedSignal {
  hsize_t rows = 0, width = 1, chunk_rows = 1;
  /// The chunks in row order: views of the history itself (uncompressed float64 chunks that
  /// are whole) or of `owned` (the rest). The history must outlive the write.
  std::vector<ByteSpan> chunks;
  std::vector<std::vector<unsigned char>> owned;  ///< the bytes of chunks not in the history
};

/// The chunks of one signal of `samples` rows of `width` values, as the case file stores them
/// (output.history_precision, output.compression_level). Runs in the calling thread, no lock.
EncodedSignal encode_signal(const std::vector<double>& values, long long samples, int width,
                            const OutputSettings& out);
/// Writes /signals of a case file: the encoded signals of `h` and their netCDF dimensions.
/// Call under Hdf5Lock.
/// The group /signals of a case file; `raw`: where HDF5 put each chunk is recorded there (a
/// template: the chunks are then not kept, template_driver.hpp).
void write_case_signals(const Context& cx, hid_t root, const History& h,
                        const std::vector<EncodedSignal>& encoded, const OutputSettings& out,
                        CaseSlots* raw = nullptr);

}  // namespace rodend::results_detail
