// HDF5 inside rodend's results code: the one process-wide lock (lock.cpp) and the RAII handles,
// error reporting and attribute helpers (hdf5_handles.cpp) that the rooms of sweep/results/ share.
//
// - Thread safety: Debian's HDF5 1.10.8 is built thread-safe (H5_HAVE_THREADSAFE 1), but its
//   thread safety is one global lock around every API call, so HDF5 work never runs in
//   parallel. The results code keeps its own process-wide std::mutex (Hdf5Lock) around every
//   HDF5 call, held for the whole open-write-close (or open-read-close) of a file, so that a
//   file is never seen half-built by another thread's calls. What is expensive stays outside it:
//   the histories' chunks are shuffled and deflated (libdeflate, chunks.cpp) by the thread that
//   ran the case, before it takes the lock, and handed to HDF5 finished (H5Dwrite_chunk); HDF5
//   builds a case file in memory (memory_file.hpp) and the thread writes the image to the disk
//   after it has released the lock. Uncompressed case files enter HDF5 once per shape of case
//   only: the others are patched from that one, a template, outside the lock
//   (case_template.hpp). Nothing outside sweep/results/ calls HDF5.
// - Quiet: HDF5's automatic error printing is switched off in every thread that calls HDF5
//   (H5Eset_auto2; the error stacks are per thread); HDF5 failures become std::runtime_error
//   naming the file (read_case_record returns nullopt instead). HDF5 never sees a failed write,
//   so a full disk is one message from AtomicFile (atomic_file.hpp), never a half-closed HDF5
//   file: case files are images written by write_file_atomically; summary.h5, which grows with
//   the number of cases, is written by HDF5 through the sink driver (sink_driver.hpp), which
//   latches a failure instead of reporting it to HDF5.
#pragma once

#include <hdf5.h>
#include <time.h>

#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "sweep/clock.hpp"
#include "sweep/memory_reserve.hpp"
#include "sweep/results.hpp"
#include "sweep/results/case_template.hpp"

namespace rodend::results_detail {

namespace fs = std::filesystem;

/// HDF5 does not survive running out of memory: it dereferences unchecked allocations (a
/// thread's error stack in H5Eset_auto2, a free list's node in H5FL_blk_malloc, datatypes closed
/// in H5Awrite) and then crashes at exit. So every HDF5 session holds this much memory in
/// reserve (and build_image the in-memory image's share more), which the rodend executable
/// serves HDF5's allocations from once the system refuses them (sweep/memory_reserve.hpp); the
/// session throws std::bad_alloc instead of entering HDF5 if it cannot be had.
constexpr std::size_t kHdf5Headroom = std::size_t{16} << 20;

/// Holds g_hdf5_mutex and kHdf5Headroom in reserve; the first one in each thread also silences
/// HDF5's automatic error printing. Throws std::bad_alloc rather than enter HDF5 short of memory.
class Hdf5Lock {
 public:
  Hdf5Lock();
  ~Hdf5Lock();
  Hdf5Lock(const Hdf5Lock&) = delete;
  Hdf5Lock& operator=(const Hdf5Lock&) = delete;

 private:
  std::lock_guard<std::mutex> lock_;
  MemoryReserve reserve_;  // after lock_: released before it
  long long t0_ = 0, cpu0_ = 0;
};

/// Owns one hid_t and closes it with the matching H5?close function.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), closer_(o.closer_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      close();
      id_ = std::exchange(o.id_, H5I_INVALID_HID);
      closer_ = o.closer_;
    }
    return *this;
  }
  ~Handle() { close(); }

  hid_t get() const { return id_; }
  /// Closes now; returns the closer's status (negative on failure).
  herr_t close() noexcept {
    herr_t r = 0;
    if (id_ >= 0 && closer_) r = closer_(id_);
    id_ = H5I_INVALID_HID;
    return r;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer closer_ = nullptr;
};

/// Memory HDF5 allocated for a variable-length string read.
struct Hdf5Free {
  void operator()(char* p) const noexcept { H5free_memory(p); }
};
using Hdf5String = std::unique_ptr<char, Hdf5Free>;

/// The current HDF5 error stack, shortened to "API call: innermost description".
std::string hdf5_error_text();
/// True when the current HDF5 error is an allocation that failed (memory, not the file).
bool hdf5_out_of_memory();

/// Names the file (and the action) in error messages; checks HDF5 return values. An HDF5
/// failure to allocate is std::bad_alloc: the environment's failure, not the file's.
class Context {
 public:
  /// `slots`: the writers of attributes record their values there (case_template.hpp); when it
  /// is collecting, they make no HDF5 call at all.
  Context(const fs::path& file, std::string action, CaseSlots* slots = nullptr)
      : file_(file.string()), action_(std::move(action)), slots_(slots) {}

  CaseSlots* slots() const { return slots_; }
  bool collecting() const { return slots_ && slots_->collecting(); }

  [[noreturn]] void fail(const std::string& what) const {
    if (!collecting() && hdf5_out_of_memory()) throw std::bad_alloc();
    const std::string detail = collecting() ? std::string() : hdf5_error_text();
    throw std::runtime_error(action_ + " " + file_ + ": " + what +
                             (detail.empty() ? "" : " (HDF5: " + detail + ")"));
  }
  /// Takes ownership of a new identifier; throws if it is invalid.
  Handle own(hid_t id, Handle::Closer closer, const std::string& what) const {
    if (id < 0) fail(what);
    return Handle(id, closer);
  }
  void ok(herr_t status, const std::string& what) const {
    if (status < 0) fail(what);
  }
  /// For htri_t results: true, false, or throws.
  bool yes(htri_t result, const std::string& what) const {
    if (result < 0) fail(what);
    return result > 0;
  }

 private:
  std::string file_, action_;
  CaseSlots* slots_;
};

// Writing helpers. With a CaseSlots in the Context (a case file's template, case_template.hpp),
// text and number attributes are slots: their values are recorded, and placeholders written in
// their stead; the values of int and int8 attributes and the groups are the template's key.

Handle utf8_string_type(const Context& cx);
Handle scalar_space(const Context& cx);
Handle vector_space(const Context& cx, hsize_t n);
void attr_string(const Context& cx, hid_t obj, const std::string& name, const std::string& v);
void attr_double(const Context& cx, hid_t obj, const std::string& name, double v);
void attr_int64(const Context& cx, hid_t obj, const std::string& name, long long v);
void attr_int(const Context& cx, hid_t obj, const std::string& name, int v);
void attr_int8(const Context& cx, hid_t obj, const std::string& name, signed char v);
void attr_doubles(const Context& cx, hid_t obj, const std::string& name,
                  const std::vector<double>& v);
/// CF-style description of a dataset: `units` (UDUNITS spelling as the catalogues give it; none
/// for text) and `long_name`, the attributes netCDF tools (xarray, ParaView, Panoply) read.
void attr_units(const Context& cx, hid_t dataset, const std::string& units,
                const std::string& long_name, bool text = false);
/// Makes `scale` the netCDF dimension `name` (a dimension scale, hdf5_hl) and attaches it as
/// axis `axis` of every dataset in `datasets`.
void attach_scale(const Context& cx, hid_t scale, const char* name,
                  const std::vector<std::pair<hid_t, unsigned>>& datasets);
/// A netCDF dimension without a coordinate variable (`name`, `size` entries): an uninitialised
/// float dataset marked as netCDF-C marks one, so that xarray and netCDF tools name the axis.
Handle dimension_without_variable(const Context& cx, hid_t group, const std::string& name,
                                  hsize_t size);
/// A new group `name` in `parent`; `track_link_order`: tools iterating it (h5py) list its
/// members in creation order.
Handle create_group(const Context& cx, hid_t parent, const std::string& name,
                    bool track_link_order = false);
/// A string value of the provenance object ("" if absent).
std::string prov_text(const Json& prov, const char* key);

// Reading helpers (throw; read_case_record turns that into nullopt)

std::string read_attr_string(const Context& cx, hid_t obj, const char* name);
double read_attr_double(const Context& cx, hid_t obj, const char* name);
long long read_attr_int64(const Context& cx, hid_t obj, const char* name);
/// The names of the members of `group`, in name order.
std::vector<std::string> group_members(const Context& cx, hid_t group);
/// The unit of dataset `d`: its `units` (CF, schema 2) or `unit` (schema 1) attribute, "" if none.
std::string read_dataset_unit(const Context& cx, hid_t d);

}  // namespace rodend::results_detail
