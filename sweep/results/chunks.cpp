// The histories of a case file: chunks encoded off the lock (sweep/results/chunks.hpp) and the
// /signals datasets they are handed to.
#include "sweep/results/chunks.hpp"

#include <hdf5.h>
#include <libdeflate.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <map>
#include <new>
#include <stdexcept>

#include "sweep/results/memory_file.hpp"
#include "sweep/results/template_driver.hpp"

namespace rodend::results_detail {

namespace {

/// One libdeflate compressor per thread and level (they are not thread-safe, and cheap to keep).
libdeflate_compressor* thread_compressor(int level) {
  struct Owner {
    std::array<libdeflate_compressor*, 13> by_level{};
    ~Owner() {
      for (libdeflate_compressor* c : by_level) libdeflate_free_compressor(c);
    }
  };
  thread_local Owner owner;
  libdeflate_compressor*& c = owner.by_level[static_cast<std::size_t>(level)];
  if (!c) c = libdeflate_alloc_compressor(level);
  if (!c) throw std::bad_alloc();
  return c;
}

/// Rows per chunk of a signal with `rows` samples (at most 4096, at least 1).
hsize_t chunk_rows_for(hsize_t rows) {
  return std::clamp<hsize_t>(rows, 1, 4096);
}

}  // namespace

EncodedSignal encode_signal(const std::vector<double>& values, long long samples, int width,
                            const OutputSettings& out) {
  EncodedSignal e;
  e.rows = static_cast<hsize_t>(samples);
  e.width = static_cast<hsize_t>(width);
  e.chunk_rows = chunk_rows_for(e.rows);
  const bool f32 = out.history_precision == HistoryPrecision::float32;
  const std::size_t es = f32 ? 4 : 8;  // element size in the file [bytes]
  const std::size_t per_chunk = static_cast<std::size_t>(e.chunk_rows * e.width);  // elements
  const std::size_t chunk_bytes = per_chunk * es;
  libdeflate_compressor* compressor =
      out.compression_level > 0 ? thread_compressor(out.compression_level) : nullptr;
  const std::size_t bound =
      compressor ? libdeflate_zlib_compress_bound(compressor, chunk_bytes) : std::size_t{0};
  // scratch: the chunk as stored (element bytes, padded), its shuffle, its compression
  unsigned char* const raw = thread_scratch(ScratchSlot::encode, 2 * chunk_bytes + bound);
  unsigned char* const shuffled = raw + chunk_bytes;
  unsigned char* const z = shuffled + chunk_bytes;
  for (hsize_t r0 = 0; r0 < e.rows; r0 += e.chunk_rows) {
    const std::size_t n =
        static_cast<std::size_t>(std::min(e.chunk_rows, e.rows - r0) * e.width);  // filled
    const double* src = values.data() + static_cast<std::size_t>(r0 * e.width);
    if (!f32 && !compressor && n == per_chunk) {  // stored as it is held: no copy
      e.chunks.emplace_back(reinterpret_cast<const unsigned char*>(src), chunk_bytes);
      continue;
    }
    if (f32) {
      for (std::size_t i = 0; i < n; ++i) {
        const float v = static_cast<float>(src[i]);
        std::memcpy(raw + 4 * i, &v, 4);
      }
    } else {
      std::memcpy(raw, src, 8 * n);
    }
    std::fill(raw + n * es, raw + chunk_bytes, 0);  // the edge chunk's padding: the fill value 0
    const unsigned char* stored = raw;
    std::size_t size = chunk_bytes;
    if (compressor) {
      // HDF5's shuffle filter: byte b of element i goes to b * count + i
      for (std::size_t i = 0; i < per_chunk; ++i)
        for (std::size_t b = 0; b < es; ++b) shuffled[b * per_chunk + i] = raw[i * es + b];
      size = libdeflate_zlib_compress(compressor, shuffled, chunk_bytes, z, bound);
      if (size == 0) throw std::runtime_error("libdeflate could not compress a chunk");
      stored = z;
    }
    e.owned.emplace_back(stored, stored + size);
    e.chunks.emplace_back(e.owned.back().data(), size);
  }
  return e;
}

namespace {

void write_signal(const Context& cx, hid_t group, const SignalSpec& s, const EncodedSignal& e,
                  const OutputSettings& out, CaseSlots* raw) {
  const std::string what = "cannot write signal " + std::string(s.name);
  const int rank = s.width == 1 ? 1 : 2;
  const hsize_t dims[2] = {e.rows, e.width};
  // A chunked dataset needs maximum dimensions of at least one chunk: unlimited rows when empty.
  const hsize_t maxdims[2] = {e.rows == 0 ? H5S_UNLIMITED : e.rows, e.width};
  const hsize_t chunk[2] = {e.chunk_rows, e.width};

  const Handle space = cx.own(H5Screate_simple(rank, dims, maxdims), H5Sclose, what);
  const Handle dcpl = cx.own(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, what);
  cx.ok(H5Pset_chunk(dcpl.get(), rank, chunk), what);
  if (out.compression_level > 0) {
    // the pipeline the chunks were encoded with (HDF5's deflate takes levels up to 9; the
    // level is only a hint to writers, readers ignore it)
    cx.ok(H5Pset_shuffle(dcpl.get()), what);
    cx.ok(H5Pset_deflate(dcpl.get(), static_cast<unsigned>(std::min(out.compression_level, 9))),
          what);
  }
  const hid_t file_type =
      out.history_precision == HistoryPrecision::float32 ? H5T_IEEE_F32LE : H5T_IEEE_F64LE;
  Handle d = cx.own(H5Dcreate2(group, std::string(s.name).c_str(), file_type, space.get(),
                               H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                    H5Dclose, what);
  const DroppingRawData dropping(raw != nullptr);  // a template's: each case writes its own
  for (std::size_t k = 0; k < e.chunks.size(); ++k) {
    const hsize_t offset[2] = {static_cast<hsize_t>(k) * e.chunk_rows, 0};
    cx.ok(H5Dwrite_chunk(d.get(), H5P_DEFAULT, 0, offset, e.chunks[k].size(), e.chunks[k].data()),
          what);
    if (raw) {
      unsigned mask = 0;
      haddr_t addr = HADDR_UNDEF;
      hsize_t size = 0;
      cx.ok(H5Dget_chunk_info_by_coord(d.get(), offset, &mask, &addr, &size), what);
      raw->raw(addr, size);  // relative to the base address: an image offset
    }
  }
  attr_units(cx, d.get(), std::string(s.unit), std::string(s.description));
  cx.ok(d.close(), what);
}

/// netCDF dimensions of the histories: /signals/time is the dimension scale `time` of axis 0
/// of every signal; axis 1 of a signal of width w is the dimension `component<w>`, a
/// dimension without a variable in the root group (so /signals holds only signals).
void attach_signal_dimensions(const Context& cx, hid_t root, hid_t signals, const History& h) {
  const auto time_at = std::find(h.signals.begin(), h.signals.end(), SignalId::time);
  if (time_at == h.signals.end()) return;  // no time axis recorded: nothing to attach
  std::vector<Handle> open;
  std::vector<std::pair<hid_t, unsigned>> on_time;
  std::map<int, std::vector<std::pair<hid_t, unsigned>>> on_component;
  for (SignalId id : h.signals) {
    if (id == SignalId::time) continue;
    const SignalSpec& s = signal_spec(id);
    const std::string name(s.name);
    open.push_back(cx.own(H5Dopen2(signals, name.c_str(), H5P_DEFAULT), H5Dclose,
                          "cannot open signal " + name));
    on_time.emplace_back(open.back().get(), 0u);
    if (s.width > 1) on_component[s.width].emplace_back(open.back().get(), 1u);
  }
  const Handle time = cx.own(H5Dopen2(signals, "time", H5P_DEFAULT), H5Dclose, "no time signal");
  attach_scale(cx, time.get(), "time", on_time);
  for (const auto& [width, datasets] : on_component) {
    const std::string name = "component" + std::to_string(width);
    const Handle dim = dimension_without_variable(cx, root, name, static_cast<hsize_t>(width));
    attach_scale(cx, dim.get(), name.c_str(), datasets);
  }
}

}  // namespace

void write_case_signals(const Context& cx, hid_t root, const History& h,
                        const std::vector<EncodedSignal>& encoded, const OutputSettings& out,
                        CaseSlots* raw) {
  const Handle g = create_group(cx, root, "signals");
  for (std::size_t i = 0; i < h.signals.size(); ++i)
    write_signal(cx, g.get(), signal_spec(h.signals[i]), encoded[i], out, raw);
  attach_signal_dimensions(cx, root, g.get(), h);
}

}  // namespace rodend::results_detail
