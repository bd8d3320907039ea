// Results on disk: one HDF5 file per case, a summary table (HDF5 and CSV) per study.
//
// Rules of this file:
// - Thread safety: Debian's HDF5 1.10.8 is built thread-safe (H5_HAVE_THREADSAFE 1), but its
//   thread safety is one global lock around every API call, so HDF5 work never runs in
//   parallel. This file keeps its own process-wide std::mutex (g_hdf5_mutex) around every HDF5
//   call, held for the whole open-write-close (or open-read-close) of a file, so that a file is
//   never seen half-built by another thread's calls. What is expensive stays outside it: the
//   histories' chunks are shuffled and deflated (libdeflate) by the thread that ran the case,
//   before it takes the lock, and handed to HDF5 finished (H5Dwrite_chunk); HDF5 builds a case
//   file in memory (core driver, no backing store) and the thread writes the image to the disk
//   after it has released the lock. Nothing outside this file calls HDF5.
// - Quiet: HDF5's automatic error printing is switched off in every thread that calls HDF5
//   (H5Eset_auto2; the error stacks are per thread); HDF5 failures become std::runtime_error
//   naming the file (read_case_record returns nullopt instead). HDF5 never sees a failed write,
//   so a full disk is one message from AtomicFile, never a half-closed HDF5 file: case files
//   are images written by write_file_atomically; summary.h5, which grows with the number of
//   cases, is written by HDF5 through the sink driver (below), which latches a failure instead
//   of reporting it to HDF5.
// - Crash safety: a file is written under a hidden temporary name in its final directory
//   (.<name>.tmp.<host>.<pid>.<random>, created with O_EXCL|O_NOFOLLOW: never an existing
//   file, never through a link, a name nobody can plant beforehand), closed, then renamed to
//   its final name (atomic on POSIX; a link under the final name is replaced, not followed). A
//   failed write removes the temporary file and throws; a partially written file never appears
//   under the final name. Case files are not fsync'd: one torn by an OS crash fails its checksum
//   (below) and resume reruns it; summary.h5, summary.csv and their directory are.
// - Integrity: a case file and summary.h5 start with a 512-byte HDF5 user block holding the
//   checksum header, "RODEND-CHECKSUM 1\ncrc32 <8 hex>\nbytes <file size>\n" padded with NUL
//   bytes: the CRC-32 (zlib.crc32) of every byte after the user block and the file's size.
//   verify_case_file and verify_summary_file check it (every byte of the block too) before any
//   reader here opens the file with HDF5 (resume, merge, compare, report); HDF5 readers skip
//   the user block.
//
// Case file layout (stable interface, schema_version 2; 1 is still read, see below):
//   user block   512 bytes: the checksum header (Integrity, above)
//   /            attributes: schema_version (int), case_id, case_index (int64), scene, status,
//                message, t_reached_s, wall_time_s (double), steps_accepted, steps_rejected,
//                rhs_calls (int64), started_utc, finished_utc, rodend_version, git_revision,
//                host, study_file, coordinates_json, parameters_json, case_json (strings)
//   /parameters  one attribute per resolved parameter (dotted path): double, string, int8 0/1
//                for booleans, 1-D double for arrays; units_json = {"path": "unit"}
//   /signals     one dataset per recorded signal (catalogue name): float64 (or float32 with
//                output.history_precision), (samples,) or (samples, width), chunked (4096 rows),
//                shuffle + deflate at output.compression_level (no filters at level 0; the
//                standard filters, read by any HDF5 reader); attributes units, long_name;
//                /signals/time is the dimension scale "time" of axis 0 of every signal; axis
//                1 of a width-w signal is the dimension /component<w> (netCDF dimension
//                without a variable), so netCDF tools read the file as it is
//   /metrics     one scalar double attribute per metric (catalogue name), NaN when not
//                applicable; units_json = {"name": "unit"}
// Summary: summary.h5 (the checksum user block, group /summary, one 1-D dataset per column with
// units (not for text) and long_name, case_index the dimension scale of the others, attribute
// columns = JSON array of the names in order; root attribute summary_csv_crc32 (int64): the CRC-32
// of the summary.csv written with it) and summary.csv (one header line, one line per case, numbers
// as the shortest decimal that reads back as the same double). Schema 1 (before issue 22) named the
// attributes unit and description and had no dimension scales; readers accept both. All string
// attributes and string datasets are variable-length UTF-8.
#include "sweep/results.hpp"
#include "sweep/case_template.hpp"
#include "sweep/results_dir.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <hdf5_hl.h>
#include <libdeflate.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <set>
#include <span>
#include <stdexcept>
#include <utility>

#ifndef RODEND_VERSION
#define RODEND_VERSION "unknown"
#endif
#ifndef RODEND_GIT_REVISION
#define RODEND_GIT_REVISION "unknown"
#endif

namespace rodend {
namespace {

namespace fs = std::filesystem;
// histories are copied into the file's little-endian types byte for byte
static_assert(std::endian::native == std::endian::little, "rodend writes HDF5 chunks on LE hosts");

// ---------------------------------------------------------------------------------------------
// Locking

/// The one process-wide mutex around every HDF5 call.
std::mutex g_hdf5_mutex;

/// Diagnostics (RODEND_LOCK_STATS=1 in the environment): how long g_hdf5_mutex is held, summed
/// over the run, printed on stderr at exit: the serial section of a sweep (bench/README.md);
/// RODEND_LOCK_STATS=2 also prints each time it is released.
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

long long clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<long long>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

/// HDF5 does not survive running out of memory: it dereferences unchecked allocations (a
/// thread's error stack in H5Eset_auto2, datatypes closed in H5Awrite) and then crashes at exit.
/// So every HDF5 session first makes sure this much memory could be had (and `extra` more:
/// the in-memory image of a file), and throws std::bad_alloc instead of entering HDF5 if not.
constexpr std::size_t kHdf5Headroom = std::size_t{16} << 20;
void ensure_memory_for_hdf5(std::size_t extra = 0) {
  void* probe = std::malloc(kHdf5Headroom + extra);  // address space only: never touched
  if (probe == nullptr) throw std::bad_alloc();
  std::free(probe);
}

/// Holds g_hdf5_mutex; the first one in each thread also silences HDF5's automatic error
/// printing. Throws std::bad_alloc (ensure_memory_for_hdf5) rather than enter HDF5 short of
/// memory.
class Hdf5Lock {
 public:
  Hdf5Lock() : lock_(g_hdf5_mutex) {
    ensure_memory_for_hdf5();
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
  ~Hdf5Lock() {
    ++g_lock_stats.count;
    if (!g_lock_stats.enabled) return;
    g_lock_stats.held_ns += clock_ns(CLOCK_MONOTONIC) - t0_;
    g_lock_stats.held_cpu_ns += clock_ns(CLOCK_THREAD_CPUTIME_ID) - cpu0_;
    if (g_lock_stats.each)
      std::fprintf(stderr, "rodend: HDF5 lock held %.3f ms wall, %.3f ms CPU\n",
                   1e-6 * static_cast<double>(clock_ns(CLOCK_MONOTONIC) - t0_),
                   1e-6 * static_cast<double>(clock_ns(CLOCK_THREAD_CPUTIME_ID) - cpu0_));
  }
  Hdf5Lock(const Hdf5Lock&) = delete;
  Hdf5Lock& operator=(const Hdf5Lock&) = delete;

 private:
  std::lock_guard<std::mutex> lock_;
  long long t0_ = 0, cpu0_ = 0;
};

// ---------------------------------------------------------------------------------------------
// RAII handles and error reporting

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

herr_t collect_error(unsigned n, const H5E_error2_t* e, void* data) {
  auto* out = static_cast<std::pair<std::string, std::string>*>(data);
  if (n == 0 && e->func_name) out->first = e->func_name;  // the API call
  if (e->desc) out->second = e->desc;                     // the innermost cause, last
  return 0;
}

/// The current HDF5 error stack, shortened to "API call: innermost description".
std::string hdf5_error_text() {
  std::pair<std::string, std::string> parts;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, collect_error, &parts);
  if (parts.first.empty() && parts.second.empty()) return {};
  return parts.first.empty() ? parts.second : parts.first + ": " + parts.second;
}

herr_t find_allocation_failure(unsigned, const H5E_error2_t* e, void* data) {
  if (e->maj_num == H5E_RESOURCE && (e->min_num == H5E_CANTALLOC || e->min_num == H5E_NOSPACE))
    *static_cast<bool*>(data) = true;
  return 0;
}

/// True when the current HDF5 error is an allocation that failed (memory, not the file).
bool hdf5_out_of_memory() {
  bool found = false;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, find_allocation_failure, &found);
  return found;
}

/// Names the file (and the action) in error messages; checks HDF5 return values. An HDF5
/// failure to allocate is std::bad_alloc: the environment's failure, not the file's.
class Context {
 public:
  /// `slots`: the writers of attributes record their values there (sweep/case_template.hpp);
  /// when it is collecting, they make no HDF5 call at all.
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

// ---------------------------------------------------------------------------------------------
// Writing helpers

Handle utf8_string_type(const Context& cx) {
  Handle t = cx.own(H5Tcopy(H5T_C_S1), H5Tclose, "cannot create a string type");
  cx.ok(H5Tset_size(t.get(), H5T_VARIABLE), "cannot create a string type");
  cx.ok(H5Tset_cset(t.get(), H5T_CSET_UTF8), "cannot create a string type");
  return t;
}

Handle scalar_space(const Context& cx) {
  return cx.own(H5Screate(H5S_SCALAR), H5Sclose, "cannot create a dataspace");
}

Handle vector_space(const Context& cx, hsize_t n) {
  return cx.own(H5Screate_simple(1, &n, nullptr), H5Sclose, "cannot create a dataspace");
}

void write_attribute(const Context& cx, hid_t obj, const std::string& name, hid_t file_type,
                     hid_t mem_type, hid_t space, const void* data) {
  const std::string what = "cannot write attribute " + name;
  Handle a = cx.own(H5Acreate2(obj, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT),
                    H5Aclose, what);
  cx.ok(H5Awrite(a.get(), mem_type, data), what);
  cx.ok(a.close(), what);
}

// With a CaseSlots in the Context (a case file's template, sweep/case_template.hpp), text and
// number attributes are slots: their values are recorded, and placeholders written in their
// stead; the values of int and int8 attributes are part of the template's key.

void attr_string(const Context& cx, hid_t obj, const std::string& name, const std::string& v) {
  const std::string value = cx.slots() ? cx.slots()->text(name, v) : v;
  if (cx.collecting()) return;
  const Handle t = utf8_string_type(cx);
  const Handle s = scalar_space(cx);
  const char* p = value.c_str();
  write_attribute(cx, obj, name, t.get(), t.get(), s.get(), &p);
}

/// A scalar 8-byte number attribute (a slot with a CaseSlots), `v` its bytes in memory.
template <class T>
void attr_number(const Context& cx, hid_t obj, const std::string& name, hid_t file_type,
                 hid_t mem_type, T v) {
  static_assert(sizeof(T) == 8);
  std::uint64_t bits = std::bit_cast<std::uint64_t>(v);
  if (cx.slots()) bits = cx.slots()->number(name, bits);
  if (cx.collecting()) return;
  const Handle s = scalar_space(cx);
  write_attribute(cx, obj, name, file_type, mem_type, s.get(), &bits);
}

void attr_double(const Context& cx, hid_t obj, const std::string& name, double v) {
  attr_number(cx, obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v);
}

void attr_int64(const Context& cx, hid_t obj, const std::string& name, long long v) {
  attr_number(cx, obj, name, H5T_STD_I64LE, H5T_NATIVE_LLONG, v);
}

void attr_int(const Context& cx, hid_t obj, const std::string& name, int v) {
  if (cx.slots()) cx.slots()->fixed("int " + name + "=" + std::to_string(v));
  if (cx.collecting()) return;
  const Handle s = scalar_space(cx);
  write_attribute(cx, obj, name, H5T_STD_I32LE, H5T_NATIVE_INT, s.get(), &v);
}

void attr_int8(const Context& cx, hid_t obj, const std::string& name, signed char v) {
  if (cx.slots()) cx.slots()->fixed("int8 " + name + "=" + std::to_string(v));
  if (cx.collecting()) return;
  const Handle s = scalar_space(cx);
  write_attribute(cx, obj, name, H5T_STD_I8LE, H5T_NATIVE_SCHAR, s.get(), &v);
}

void attr_doubles(const Context& cx, hid_t obj, const std::string& name,
                  const std::vector<double>& v) {
  std::vector<std::uint64_t> bits(v.size());
  std::transform(v.begin(), v.end(), bits.begin(),
                 [](double x) { return std::bit_cast<std::uint64_t>(x); });
  if (cx.slots()) {
    cx.slots()->fixed("doubles " + name + "[" + std::to_string(v.size()) + "]");
    for (std::uint64_t& b : bits) b = cx.slots()->number(name, b);
  }
  if (cx.collecting()) return;
  const Handle s = vector_space(cx, v.size());
  write_attribute(cx, obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, s.get(), bits.data());
}

/// CF-style description of a dataset: `units` (UDUNITS spelling as the catalogues give it; none
/// for text) and `long_name`, the attributes netCDF tools (xarray, ParaView, Panoply) read.
void attr_units(const Context& cx, hid_t dataset, const std::string& units,
                const std::string& long_name, bool text = false) {
  if (!text) attr_string(cx, dataset, "units", units);
  attr_string(cx, dataset, "long_name", long_name);
}

/// Makes `scale` the netCDF dimension `name` (a dimension scale, hdf5_hl) and attaches it as
/// axis `axis` of every dataset in `datasets`.
void attach_scale(const Context& cx, hid_t scale, const char* name,
                  const std::vector<std::pair<hid_t, unsigned>>& datasets) {
  const std::string what = std::string("cannot attach dimension scale ") + name;
  if (!cx.yes(H5DSis_scale(scale), what)) cx.ok(H5DSset_scale(scale, name), what);
  for (const auto& [d, axis] : datasets) cx.ok(H5DSattach_scale(d, scale, axis), what);
}

/// A netCDF dimension without a coordinate variable (`name`, `size` entries): an uninitialised
/// float dataset marked as netCDF-C marks one, so that xarray and netCDF tools name the axis.
Handle dimension_without_variable(const Context& cx, hid_t group, const std::string& name,
                                  hsize_t size) {
  const std::string what = "cannot create dimension " + name;
  const Handle space = cx.own(H5Screate_simple(1, &size, nullptr), H5Sclose, what);
  Handle d = cx.own(H5Dcreate2(group, name.c_str(), H5T_IEEE_F32BE, space.get(), H5P_DEFAULT,
                               H5P_DEFAULT, H5P_DEFAULT),
                    H5Dclose, what);
  char label[96];
  std::snprintf(label, sizeof label, "This is a netCDF dimension but not a netCDF variable.%10d",
                static_cast<int>(size));
  cx.ok(H5DSset_scale(d.get(), label), what);
  return d;
}

Handle create_group(const Context& cx, hid_t parent, const std::string& name,
                    bool track_link_order = false) {
  if (cx.slots()) cx.slots()->fixed("group " + name);
  if (cx.collecting()) return Handle();
  const std::string what = "cannot create group " + name;
  Handle gcpl;
  if (track_link_order) {
    // so that tools iterating the group (h5py) list its members in creation order
    gcpl = cx.own(H5Pcreate(H5P_GROUP_CREATE), H5Pclose, what);
    cx.ok(H5Pset_link_creation_order(gcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED),
          what);
  }
  return cx.own(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT,
                           track_link_order ? gcpl.get() : H5P_DEFAULT, H5P_DEFAULT),
                H5Gclose, what);
}

/// A string value of the provenance object ("" if absent).
std::string prov_text(const Json& prov, const char* key) {
  if (!prov.is_object()) return {};
  const auto it = prov.find(key);
  return it != prov.end() && it->is_string() ? it->get<std::string>() : std::string();
}

// ---------------------------------------------------------------------------------------------
// Atomic file replacement

/// `.<name>.tmp.<host>.<pid>.<random>` beside `path`: the host and pid tell a later run whether
/// its writer is gone (sweep/results_dir.hpp); the random part (64 bits from getrandom(2), in
/// decimal) makes the name unpredictable, so that nobody can plant a link under it beforehand.
fs::path temp_path_for(const fs::path& path) {
  static const std::string host = host_name();
  std::uint64_t r = 0;
  if (::getrandom(&r, sizeof r, 0) != static_cast<ssize_t>(sizeof r)) {
    // no entropy source (very old kernels): the clock and a counter (O_EXCL still holds)
    static std::atomic<std::uint64_t> counter{0};
    r = static_cast<std::uint64_t>(clock_ns(CLOCK_REALTIME)) * 1000003u + counter.fetch_add(1);
  }
  const std::string name = "." + path.filename().string() + ".tmp." + host + "." +
                           std::to_string(static_cast<long long>(::getpid())) + "." +
                           std::to_string(r);
  return path.parent_path() / name;
}

/// Bytes a WriteFailureInjection still lets through (negative: no injection in place).
std::atomic<long long> g_write_budget{-1};

/// write(2) of all of `bytes` to `fd` (pwrite(2) at `offset` when it is not negative), with the
/// injected failure of WriteFailureInjection. Returns 0 or the errno of the failure.
int write_all(int fd, const unsigned char* bytes, std::size_t size, off_t offset = -1) {
  while (size > 0) {
    std::size_t n = std::min<std::size_t>(size, std::size_t{1} << 30);
    const long long budget = g_write_budget.load();
    if (budget >= 0) {
      if (budget == 0) return ENOSPC;
      n = std::min<std::size_t>(n, static_cast<std::size_t>(budget));
      g_write_budget.fetch_sub(static_cast<long long>(n));
    }
    const ssize_t w = offset < 0 ? ::write(fd, bytes, n) : ::pwrite(fd, bytes, n, offset);
    if (w < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    if (offset >= 0) offset += w;
    bytes += w;
    size -= static_cast<std::size_t>(w);
  }
  return 0;
}

using ByteSpan = std::span<const unsigned char>;

/// A file replaced atomically: written under a hidden temporary name in the same directory with
/// write(2) (every failure, a full disk included, is this class's error message naming the
/// final path, never HDF5's), optionally flushed to the disk, then renamed over the final path.
/// On any failure, and when destroyed before commit(), the temporary file is removed and the
/// final path is left as it was. Writing in pieces keeps a large file (summary.csv) from being
/// held whole in memory.
class AtomicFile {
 public:
  AtomicFile(fs::path path, std::string what) : path_(std::move(path)), what_(std::move(what)) {
    if (path_.filename().empty())
      throw std::runtime_error("cannot write " + path_.string() + ": not a file name");
    std::error_code ec;
    const fs::path dir = path_.parent_path();
    if (!dir.empty()) {
      fs::create_directories(dir, ec);
      if (ec)
        throw std::runtime_error("cannot write " + what_ + " " + path_.string() +
                                 ": cannot create directory " + dir.string() + ": " + ec.message());
    }
    // the directory, opened once: the temporary file is created, renamed and removed in it
    // (*at calls), whatever happens to the path to it meanwhile
    dir_fd_ = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir_fd_ < 0)
      throw std::runtime_error("cannot write " + what_ + " " + path_.string() +
                               ": cannot open directory " + dir.string() + ": " +
                               std::strerror(errno));
    // created fresh (O_EXCL: never an existing file, never through a link) under a name
    // nobody can guess; read-write: the summary's HDF5 driver reads back what it wrote
    for (int attempt = 0; fd_ < 0; ++attempt) {
      temp_ = temp_path_for(path_);
      fd_ = ::openat(dir_fd_, temp_.filename().c_str(),
                     O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
      const int err = errno;
      if (fd_ < 0 && (err != EEXIST || attempt == 16)) {
        ::close(dir_fd_);
        throw std::runtime_error("cannot write " + what_ + " " + path_.string() +
                                 ": cannot create " + temp_.string() + ": " + std::strerror(err));
      }
    }
  }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) ::unlinkat(dir_fd_, temp_.filename().c_str(), 0);
    ::close(dir_fd_);
  }

  void write(ByteSpan bytes) {
    if (const int err = write_all(fd_, bytes.data(), bytes.size()); err != 0) fail_write(err);
  }
  /// The temporary file, for a writer of its own (the summary's HDF5 driver, the sink driver).
  int fd() const { return fd_; }
  /// That writer's failure (`err`: its errno): throws this class's message, as write() does.
  [[noreturn]] void fail_write(int err) { fail("write error on " + temp_.string(), err); }
  /// Everything is written: flushes it to the disk (durable) and closes the temporary file.
  void finish(bool durable) {
    int err = 0;
    if (durable && ::fsync(fd_) != 0) err = errno;
    if (::close(fd_) != 0 && err == 0) err = errno;
    fd_ = -1;
    if (err != 0) fail("write error on " + temp_.string(), err);
  }
  /// Renames the finished file over the final path, in the same directory (a link under the
  /// final name is replaced, not followed), and, durable, flushes the directory, so that the
  /// rename is there after an OS crash.
  void commit(bool durable) {
    if (::renameat(dir_fd_, temp_.filename().c_str(), dir_fd_, path_.filename().c_str()) != 0)
      fail("cannot rename " + temp_.string(), errno);
    committed_ = true;
    if (durable) (void)::fsync(dir_fd_);  // best effort: not every file system syncs a directory
  }

 private:
  [[noreturn]] void fail(const std::string& step, int err) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    if (!committed_) ::unlinkat(dir_fd_, temp_.filename().c_str(), 0);
    committed_ = true;  // nothing left to remove
    throw std::runtime_error("cannot write " + what_ + " " + path_.string() + ": " + step + ": " +
                             std::strerror(err));
  }

  fs::path path_, temp_;
  std::string what_;
  int dir_fd_ = -1;
  int fd_ = -1;
  bool committed_ = false;
};

/// Writes `parts` (in order) to `path` atomically (AtomicFile), optionally flushed to the disk
/// (`durable`). Throws std::runtime_error naming `path`; `path` is then left as it was.
void write_file_atomically(const fs::path& path, const std::string& what,
                           std::initializer_list<ByteSpan> parts, bool durable) {
  AtomicFile file(path, what);
  for (const ByteSpan part : parts) file.write(part);
  file.finish(durable);
  file.commit(durable);
}

}  // namespace

void write_text_file_atomically(const fs::path& path, const std::string& what,
                                const std::string& text, bool durable) {
  write_file_atomically(
      path, what, {ByteSpan(reinterpret_cast<const unsigned char*>(text.data()), text.size())},
      durable);
}

namespace {

// ---------------------------------------------------------------------------------------------
// In-memory HDF5 files
//
// Every case file is built by HDF5 in memory (the core driver without a backing store) and its
// finished image written by write_file_atomically: a full disk, a quota or an I/O error is one
// clear message, never a half-closed HDF5 file (which HDF5 1.10 cannot close again: it crashed
// at exit), and the write of the bytes (the file system's share of the cost) runs outside
// g_hdf5_mutex. (summary.h5 is written as a stream instead: the sink driver, below.)

/// Size of the user block of a case file: the checksum header (case_checksum_header).
constexpr hsize_t kUserBlock = 512;
constexpr std::string_view kChecksumMagic = "RODEND-CHECKSUM 1\n";
constexpr unsigned char kHdf5Signature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

/// Scratch of the calling thread: a buffer of at least `size` bytes, not zeroed, that the next
/// call with the same `slot` reuses (its pages stay mapped: no fresh page faults per file).
/// Only for bytes that are all written before they are read.
enum class ScratchSlot { encode, image, count_ };
unsigned char* thread_scratch(ScratchSlot slot, std::size_t size) {
  struct Buffer {
    std::unique_ptr<unsigned char[]> bytes;
    std::size_t capacity = 0;
  };
  thread_local std::array<Buffer, static_cast<std::size_t>(ScratchSlot::count_)> buffers;
  Buffer& b = buffers[static_cast<std::size_t>(slot)];
  if (b.capacity < size) {
    b.bytes = std::make_unique_for_overwrite<unsigned char[]>(size);
    b.capacity = size;
  }
  return b.bytes.get();
}

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

/// The user block of a case file, written before its HDF5 image (H5Fget_file_image leaves it
/// out): the checksum header "RODEND-CHECKSUM 1", then "crc32 <8 hex digits>" (CRC-32, as
/// zlib.crc32, of every byte after the user block, the image) and "bytes <file size>", one per
/// line, padded with NUL bytes to kUserBlock bytes.
std::array<unsigned char, kUserBlock> checksum_header(std::uint32_t crc, std::size_t file_size) {
  std::array<unsigned char, kUserBlock> header{};
  std::snprintf(reinterpret_cast<char*>(header.data()), header.size(), "%scrc32 %08x\nbytes %zu\n",
                std::string(kChecksumMagic).c_str(), static_cast<unsigned>(crc), file_size);
  return header;
}
std::array<unsigned char, kUserBlock> checksum_header(ByteSpan image) {
  if (image.size() < sizeof kHdf5Signature ||
      std::memcmp(image.data(), kHdf5Signature, sizeof kHdf5Signature) != 0)
    throw std::logic_error("the HDF5 image of a case file does not start with its superblock");
  return checksum_header(libdeflate_crc32(0, image.data(), image.size()),
                         static_cast<std::size_t>(kUserBlock) + image.size());
}

// ---------------------------------------------------------------------------------------------
// Files HDF5 writes to the disk: the sink driver
//
// summary.h5 grows with the number of cases, so it is not built in memory (issue 16 item 6):
// HDF5 writes it, block of rows by block of rows, through this minimal virtual file driver
// straight into the temporary file of an AtomicFile. The driver never reports a failed write to
// HDF5 (HDF5 1.10 cannot close a file whose writes failed, and crashed at exit on it): the
// first failure (a full disk) is latched in its SinkTarget and later writes are dropped; the
// writer reports the latched error once HDF5 has closed the file, through the AtomicFile, which
// removes the temporary file. HDF5 reads back metadata it has evicted from its cache: reads
// come from the temporary file (after a failure, what was dropped reads as zeros; an HDF5 error
// that follows from it gives way to the latched one). Nothing of the driver is stored in the
// file: any HDF5 reader opens it with its default driver.

/// Where a sink file goes (its driver info): an open file descriptor, and the first failure.
struct SinkTarget {
  int fd = -1;
  int error = 0;  ///< errno of the first failed write, read or truncation; 0: none
};

struct SinkFile {
  H5FD_t pub;  // first: HDF5 holds an H5FD_t*
  SinkTarget* target;
  haddr_t eoa, eof;
};

SinkFile* sink_file(H5FD_t* f) {
  return reinterpret_cast<SinkFile*>(f);
}
const SinkFile* sink_file(const H5FD_t* f) {
  return reinterpret_cast<const SinkFile*>(f);
}

H5FD_t* sink_open(const char*, unsigned, hid_t fapl, haddr_t) {
  const auto* info = static_cast<SinkTarget* const*>(H5Pget_driver_info(fapl));
  if (!info || !*info) return nullptr;
  auto* f = static_cast<SinkFile*>(std::calloc(1, sizeof(SinkFile)));
  if (!f) return nullptr;
  f->target = *info;
  return &f->pub;
}
herr_t sink_close(H5FD_t* f) {
  std::free(sink_file(f));
  return 0;
}
int sink_cmp(const H5FD_t* a, const H5FD_t* b) {
  return std::less<const H5FD_t*>{}(a, b) ? -1 : a == b ? 0 : 1;
}
herr_t sink_query(const H5FD_t*, unsigned long* flags) {
  // as the default (sec2) driver, metadata and small raw data aggregated; but no sieve buffer
  // (HDF5 keeps one per open dataset, up to 64 kB each, a summary's memory growing with its
  // columns; the writes are whole blocks of rows anyway)
  *flags =
      H5FD_FEAT_AGGREGATE_METADATA | H5FD_FEAT_ACCUMULATE_METADATA | H5FD_FEAT_AGGREGATE_SMALLDATA;
  return 0;
}
haddr_t sink_get_eoa(const H5FD_t* f, H5FD_mem_t) {
  return sink_file(f)->eoa;
}
herr_t sink_set_eoa(H5FD_t* f, H5FD_mem_t, haddr_t addr) {
  sink_file(f)->eoa = addr;
  return 0;
}
haddr_t sink_get_eof(const H5FD_t* f, H5FD_mem_t) {
  return sink_file(f)->eof;
}
herr_t sink_read(H5FD_t* f, H5FD_mem_t, hid_t, haddr_t addr, size_t size, void* buffer) {
  auto* out = static_cast<unsigned char*>(buffer);
  const int fd = sink_file(f)->target->fd;
  while (size > 0) {
    const ssize_t r = ::pread(fd, out, size, static_cast<off_t>(addr));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0 && sink_file(f)->target->error == 0) sink_file(f)->target->error = errno;
    if (r <= 0) break;  // past the end (or dropped, or a read error): zeros below
    out += r;
    addr += static_cast<haddr_t>(r);
    size -= static_cast<size_t>(r);
  }
  std::memset(out, 0, size);
  return 0;
}
herr_t sink_write(H5FD_t* f, H5FD_mem_t, hid_t, haddr_t addr, size_t size, const void* buffer) {
  SinkFile* s = sink_file(f);
  if (s->target->error == 0)
    s->target->error = write_all(s->target->fd, static_cast<const unsigned char*>(buffer), size,
                                 static_cast<off_t>(addr));
  s->eof = std::max(s->eof, addr + size);
  return 0;
}
herr_t sink_truncate(H5FD_t* f, hid_t, hbool_t) {
  SinkFile* s = sink_file(f);
  if (s->eoa != s->eof && s->target->error == 0 &&
      ::ftruncate(s->target->fd, static_cast<off_t>(s->eoa)) != 0)
    s->target->error = errno;
  s->eof = s->eoa;
  return 0;
}

const H5FD_class_t kSinkClass = {
    .name = "rodend_sink",
    .maxaddr = (haddr_t{1} << 62) - 1,
    .fc_degree = H5F_CLOSE_STRONG,
    .terminate = nullptr,
    .sb_size = nullptr,
    .sb_encode = nullptr,
    .sb_decode = nullptr,
    .fapl_size = sizeof(SinkTarget*),
    .fapl_get = nullptr,
    .fapl_copy = nullptr,
    .fapl_free = nullptr,
    .dxpl_size = 0,
    .dxpl_copy = nullptr,
    .dxpl_free = nullptr,
    .open = sink_open,
    .close = sink_close,
    .cmp = sink_cmp,
    .query = sink_query,
    .get_type_map = nullptr,
    .alloc = nullptr,
    .free = nullptr,
    .get_eoa = sink_get_eoa,
    .set_eoa = sink_set_eoa,
    .get_eof = sink_get_eof,
    .get_handle = nullptr,
    .read = sink_read,
    .write = sink_write,
    .flush = nullptr,
    .truncate = sink_truncate,
    .lock = nullptr,
    .unlock = nullptr,
    .fl_map = H5FD_FLMAP_DICHOTOMY,
};

/// A file access property list that writes through the sink driver into `target` (which must
/// outlive the file). Call under Hdf5Lock.
Handle sink_access(const Context& cx, SinkTarget& target) {
  static const hid_t driver = H5FDregister(&kSinkClass);
  if (driver < 0) cx.fail("cannot register rodend's HDF5 file driver");
  Handle fapl = cx.own(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "cannot create the file");
  SinkTarget* info = &target;
  cx.ok(H5Pset_driver(fapl.get(), driver, &info), "cannot create the file");
  // closing the file closes whatever of it is still open (an error path), so that HDF5 never
  // keeps it open past the life of `target`
  cx.ok(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG), "cannot create the file");
  // memory that does not grow with the file (issue 16 item 6): a metadata cache of a fixed
  // 1 MiB (its adaptive default grows with the global heap's collections, which hold a
  // summary's strings)
  H5AC_cache_config_t mdc{};
  mdc.version = H5AC__CURR_CACHE_CONFIG_VERSION;
  cx.ok(H5Pget_mdc_config(fapl.get(), &mdc), "cannot create the file");
  mdc.set_initial_size = true;
  mdc.initial_size = mdc.min_size = mdc.max_size = std::size_t{1} << 20;
  mdc.incr_mode = H5C_incr__off;
  mdc.flash_incr_mode = H5C_flash_incr__off;
  mdc.decr_mode = H5C_decr__off;
  cx.ok(H5Pset_mdc_config(fapl.get(), &mdc), "cannot create the file");
  return fapl;
}

// ---------------------------------------------------------------------------------------------
// Files HDF5 builds for a template: the template driver
//
// A case file's template (sweep/case_template.hpp) needs HDF5's metadata, not the histories:
// each case writes its own into the raw regions. This driver keeps what HDF5 writes of the
// metadata in pages of 4 kB, created on first write, and drops the histories' chunks and the
// arrays (the raw data written while t_dropping_raw_data is set; reads of dropped bytes give
// zeros), so that a template costs no memory, copies nor page faults of the size of the
// histories (the core driver clears and copies them, ~8 MB a bench-32 case). HDF5 writes its
// global heap as raw data (H5FD_MEM_DRAW) too: that is kept.

/// Set while a template's chunks or arrays are handed to HDF5 (DroppingRawData).
thread_local bool t_dropping_raw_data = false;
/// Sets t_dropping_raw_data for its lifetime when `on`.
class DroppingRawData {
 public:
  explicit DroppingRawData(bool on) : on_(on) { t_dropping_raw_data = t_dropping_raw_data || on; }
  ~DroppingRawData() {
    if (on_) t_dropping_raw_data = false;
  }
  DroppingRawData(const DroppingRawData&) = delete;
  DroppingRawData& operator=(const DroppingRawData&) = delete;

 private:
  bool on_;
};

/// What HDF5 wrote of a template file (driver addresses: the user block counts).
struct TemplateTarget {
  static constexpr haddr_t kPage = 4096;
  std::map<haddr_t, std::unique_ptr<unsigned char[]>> pages;  ///< by address / kPage
  std::vector<std::pair<haddr_t, haddr_t>> dropped;  ///< [begin, end) of each dropped write
  haddr_t eoa = 0;                                   ///< at close
};

struct TemplateFile {
  H5FD_t pub;  // first: HDF5 holds an H5FD_t*
  TemplateTarget* target;
  haddr_t eoa, eof;
};

TemplateFile* template_file(H5FD_t* f) {
  return reinterpret_cast<TemplateFile*>(f);
}

H5FD_t* template_open(const char*, unsigned, hid_t fapl, haddr_t) {
  const auto* info = static_cast<TemplateTarget* const*>(H5Pget_driver_info(fapl));
  if (!info || !*info) return nullptr;
  auto* f = static_cast<TemplateFile*>(std::calloc(1, sizeof(TemplateFile)));
  if (!f) return nullptr;
  f->target = *info;
  return &f->pub;
}
herr_t template_close(H5FD_t* f) {
  template_file(f)->target->eoa = template_file(f)->eoa;
  std::free(template_file(f));
  return 0;
}
herr_t template_query(const H5FD_t*, unsigned long* flags) {
  // the core driver's, for the same allocation of the file's space
  *flags = H5FD_FEAT_AGGREGATE_METADATA | H5FD_FEAT_ACCUMULATE_METADATA | H5FD_FEAT_DATA_SIEVE |
           H5FD_FEAT_AGGREGATE_SMALLDATA;
  return 0;
}
haddr_t template_get_eoa(const H5FD_t* f, H5FD_mem_t) {
  return reinterpret_cast<const TemplateFile*>(f)->eoa;
}
herr_t template_set_eoa(H5FD_t* f, H5FD_mem_t, haddr_t addr) {
  template_file(f)->eoa = addr;
  return 0;
}
haddr_t template_get_eof(const H5FD_t* f, H5FD_mem_t) {
  return reinterpret_cast<const TemplateFile*>(f)->eof;
}
/// Copies between `buffer` and the pages (`write`: into them, creating them; else out of
/// them, zeros where none).
void template_copy(TemplateTarget& t, haddr_t addr, size_t size, unsigned char* buffer,
                   bool write) {
  while (size > 0) {
    const haddr_t page = addr / TemplateTarget::kPage, at = addr % TemplateTarget::kPage;
    const size_t n = std::min<size_t>(size, static_cast<size_t>(TemplateTarget::kPage - at));
    auto it = t.pages.find(page);
    if (write && it == t.pages.end())
      it = t.pages.emplace(page, std::make_unique<unsigned char[]>(TemplateTarget::kPage)).first;
    if (write)
      std::memcpy(it->second.get() + at, buffer, n);
    else if (it == t.pages.end())
      std::memset(buffer, 0, n);
    else
      std::memcpy(buffer, it->second.get() + at, n);
    addr += n;
    buffer += n;
    size -= n;
  }
}
herr_t template_read(H5FD_t* f, H5FD_mem_t type, hid_t, haddr_t addr, size_t size, void* buffer) {
  if (type == H5FD_MEM_DRAW)
    std::memset(buffer, 0, size);
  else
    template_copy(*template_file(f)->target, addr, size, static_cast<unsigned char*>(buffer),
                  false);
  return 0;
}
herr_t template_write(H5FD_t* f, H5FD_mem_t type, hid_t, haddr_t addr, size_t size,
                      const void* buffer) {
  TemplateFile* t = template_file(f);
  if (type == H5FD_MEM_DRAW && t_dropping_raw_data)
    t->target->dropped.emplace_back(addr, addr + size);
  else
    template_copy(*t->target, addr, size,
                  const_cast<unsigned char*>(static_cast<const unsigned char*>(buffer)), true);
  t->eof = std::max(t->eof, addr + size);
  return 0;
}
herr_t template_truncate(H5FD_t* f, hid_t, hbool_t) {
  template_file(f)->eof = template_file(f)->eoa;
  return 0;
}

const H5FD_class_t kTemplateClass = {
    .name = "rodend_template",
    .maxaddr = (haddr_t{1} << 62) - 1,
    .fc_degree = H5F_CLOSE_STRONG,
    .terminate = nullptr,
    .sb_size = nullptr,
    .sb_encode = nullptr,
    .sb_decode = nullptr,
    .fapl_size = sizeof(TemplateTarget*),
    .fapl_get = nullptr,
    .fapl_copy = nullptr,
    .fapl_free = nullptr,
    .dxpl_size = 0,
    .dxpl_copy = nullptr,
    .dxpl_free = nullptr,
    .open = template_open,
    .close = template_close,
    .cmp = sink_cmp,
    .query = template_query,
    .get_type_map = nullptr,
    .alloc = nullptr,
    .free = nullptr,
    .get_eoa = template_get_eoa,
    .set_eoa = template_set_eoa,
    .get_eof = template_get_eof,
    .get_handle = nullptr,
    .read = template_read,
    .write = template_write,
    .flush = nullptr,
    .truncate = template_truncate,
    .lock = nullptr,
    .unlock = nullptr,
    .fl_map = H5FD_FLMAP_DICHOTOMY,
};

/// Creates a template file written through the template driver into `target`, runs
/// build(file) and closes it. Call under Hdf5Lock.
template <class Build>
void build_template_file(const Context& cx, TemplateTarget& target, Build&& build) {
  static const hid_t driver = H5FDregister(&kTemplateClass);
  if (driver < 0) cx.fail("cannot register rodend's HDF5 template driver");
  const Handle fapl = cx.own(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "cannot create the file");
  TemplateTarget* info = &target;
  cx.ok(H5Pset_driver(fapl.get(), driver, &info), "cannot create the file");
  cx.ok(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG), "cannot create the file");
  const Handle fcpl = cx.own(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "cannot create the file");
  cx.ok(H5Pset_userblock(fcpl.get(), kUserBlock), "cannot create the file");
  Handle file = cx.own(H5Fcreate("rodend-template.h5", H5F_ACC_TRUNC, fcpl.get(), fapl.get()),
                       H5Fclose, "cannot create the file");
  build(file.get());
  cx.ok(file.close(), "cannot close the file");
}

// ---------------------------------------------------------------------------------------------
// Case file

void check_history(const fs::path& path, const History& h) {
  auto bad = [&](const std::string& what) {
    throw std::runtime_error("cannot write results file " + path.string() + ": " + what);
  };
  if (h.samples < 0) bad("negative sample count");
  if (h.values.size() != h.signals.size())
    bad("history has a different count of signals and value arrays");
  for (std::size_t i = 0; i < h.signals.size(); ++i) {
    const SignalSpec& s = signal_spec(h.signals[i]);
    const auto expected = static_cast<std::size_t>(h.samples) * static_cast<std::size_t>(s.width);
    if (h.values[i].size() != expected)
      bad("signal " + std::string(s.name) + " has " + std::to_string(h.values[i].size()) +
          " values, expected " + std::to_string(expected));
  }
}

void write_case_root(const Context& cx, hid_t root, const CaseSpec& spec, const CaseRecord& r,
                     const Json& prov) {
  attr_int(cx, root, "schema_version", kResultsSchemaVersion);
  attr_string(cx, root, "case_id", r.id);
  attr_int64(cx, root, "case_index", r.index);
  attr_string(cx, root, "scene", spec.scene);
  attr_string(cx, root, "features_json", Json(r.features.names()).dump());
  attr_string(cx, root, "status", r.status);
  attr_string(cx, root, "message", r.message);
  attr_double(cx, root, "t_reached_s", r.t_reached);
  attr_double(cx, root, "wall_time_s", r.wall_time);
  attr_int64(cx, root, "steps_accepted", r.steps_accepted);
  attr_int64(cx, root, "steps_rejected", r.steps_rejected);
  attr_int64(cx, root, "rhs_calls", r.rhs_calls);
  attr_string(cx, root, "started_utc", r.started_utc);
  attr_string(cx, root, "finished_utc", r.finished_utc);
  for (const char* key : {"rodend_version", "git_revision", "host", "study_file"})
    attr_string(cx, root, key, prov_text(prov, key));
  attr_string(cx, root, "coordinates_json", r.coordinates.dump());
  attr_string(cx, root, "parameters_json", spec.parameters.leaves().dump());
  attr_string(cx, root, "case_json", spec.canonical().dump());
}

void write_case_parameters(const Context& cx, hid_t root, const ParameterSet& params) {
  const Handle g = create_group(cx, root, "parameters");
  const Json values = params.values();
  Json units = Json::object();
  for (const auto& [path, v] : values.items()) {
    if (v.is_boolean()) {
      attr_int8(cx, g.get(), path, v.get<bool>() ? 1 : 0);
    } else if (v.is_number()) {
      attr_double(cx, g.get(), path, v.get<double>());
    } else if (v.is_string()) {
      attr_string(cx, g.get(), path, v.get<std::string>());
    } else if (v.is_array() &&
               std::all_of(v.begin(), v.end(), [](const Json& e) { return e.is_number(); })) {
      attr_doubles(cx, g.get(), path, v.get<std::vector<double>>());
    } else {
      cx.fail("parameter " + path + " has a value of unsupported type: " + v.dump());
    }
    units[path] = params.unit(path);
  }
  attr_string(cx, g.get(), "units_json", units.dump());
}

// ---------------------------------------------------------------------------------------------
// Signal chunks, encoded off the lock
//
// HDF5's own filter pipeline would shuffle and deflate each chunk inside H5Dwrite, that is
// under g_hdf5_mutex, where it serialises the threads of a sweep. The thread that ran the case
// does it here instead (the same shuffle filter and zlib-format deflate stream, written by
// libdeflate), and the lock then only hands the finished chunks to H5Dwrite_chunk: every stock
// HDF5 reader (h5py, h5dump) decodes them with its built-in filters, no plugin.

/// Row-major chunks of one signal, each padded to the full chunk shape (HDF5 stores edge chunks
/// at full size) and encoded with the dataset's filter pipeline.
struct EncodedSignal {
  hsize_t rows = 0, width = 1, chunk_rows = 1;
  /// The chunks in row order: views of the history itself (uncompressed float64 chunks that
  /// are whole) or of `owned` (the rest). The history must outlive the write.
  std::vector<ByteSpan> chunks;
  std::vector<std::vector<unsigned char>> owned;  ///< the bytes of chunks not in the history
};

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

/// `raw`: where HDF5 put each chunk is recorded there (a template, sweep/case_template.hpp).
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

void write_case_signals(const Context& cx, hid_t root, const History& h,
                        const std::vector<EncodedSignal>& encoded, const OutputSettings& out,
                        CaseSlots* raw = nullptr) {
  const Handle g = create_group(cx, root, "signals");
  for (std::size_t i = 0; i < h.signals.size(); ++i)
    write_signal(cx, g.get(), signal_spec(h.signals[i]), encoded[i], out, raw);
  attach_signal_dimensions(cx, root, g.get(), h);
}

/// The netCDF dimensions of the per-case arrays (CaseArray::dim_names): a dimension named
/// after a 1-D array of the group is that array (a coordinate), else one without a variable.
void attach_array_dimensions(const Context& cx, const History& h,
                             const std::map<std::string, Handle>& groups) {
  // group -> dimension -> (dataset, axis) to attach
  std::map<std::string, std::map<std::string, std::vector<std::pair<std::string, unsigned>>>> uses;
  std::map<std::string, std::map<std::string, hsize_t>> sizes;
  for (const CaseArray& a : h.arrays)
    for (std::size_t k = 0; k < a.dim_names.size() && k < a.dims.size(); ++k) {
      const std::string& dim = a.dim_names[k];
      if (!(a.dims.size() == 1 && a.name == dim))
        uses[a.group][dim].emplace_back(a.name, static_cast<unsigned>(k));
      sizes[a.group][dim] = static_cast<hsize_t>(a.dims[k]);
    }
  for (const auto& [group, dims] : sizes) {
    const hid_t g = groups.at(group).get();
    for (const auto& [dim, size] : dims) {
      const bool has_variable = std::any_of(h.arrays.begin(), h.arrays.end(), [&](const auto& a) {
        return a.group == group && a.name == dim && a.dims.size() == 1;
      });
      const std::string what = "cannot attach dimension " + group + "/" + dim;
      const Handle scale = has_variable
                               ? cx.own(H5Dopen2(g, dim.c_str(), H5P_DEFAULT), H5Dclose, what)
                               : dimension_without_variable(cx, g, dim, size);
      std::vector<Handle> open;
      std::vector<std::pair<hid_t, unsigned>> targets;
      for (const auto& [name, axis] : uses[group][dim]) {
        open.push_back(cx.own(H5Dopen2(g, name.c_str(), H5P_DEFAULT), H5Dclose, what));
        targets.emplace_back(open.back().get(), axis);
      }
      attach_scale(cx, scale.get(), dim.c_str(), targets);
    }
  }
}

/// Throws (cx.fail) when a per-case array cannot be written: a bad shape, a value not finite.
void check_case_array(const Context& cx, const CaseArray& a) {
  const std::string what = "cannot write " + a.group + "/" + a.name;
  std::size_t n = 1;
  for (std::size_t d : a.dims) n *= d;
  if (a.dims.empty() || a.dims.size() > 2 || n != a.values.size()) cx.fail(what + ": bad shape");
  for (double v : a.values)
    if (!std::isfinite(v)) cx.fail(what + ": a value is not finite");
}

/// `raw`: where HDF5 put each array is recorded there (a template, sweep/case_template.hpp).
void write_case_arrays(const Context& cx, hid_t root, const History& h, CaseSlots* raw = nullptr) {
  std::map<std::string, Handle> groups;
  for (const CaseArray& a : h.arrays) {
    const std::string what = "cannot write " + a.group + "/" + a.name;
    check_case_array(cx, a);
    const std::size_t n = a.values.size();
    auto it = groups.find(a.group);
    if (it == groups.end()) it = groups.emplace(a.group, create_group(cx, root, a.group)).first;
    hsize_t dims[2] = {0, 0};
    for (std::size_t k = 0; k < a.dims.size(); ++k) dims[k] = static_cast<hsize_t>(a.dims[k]);
    const Handle space =
        cx.own(H5Screate_simple(static_cast<int>(a.dims.size()), dims, nullptr), H5Sclose, what);
    Handle d = cx.own(H5Dcreate2(it->second.get(), a.name.c_str(), H5T_IEEE_F64LE, space.get(),
                                 H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                      H5Dclose, what);
    if (n > 0) {
      const DroppingRawData dropping(raw != nullptr);  // a template's: each case writes its own
      cx.ok(H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, a.values.data()),
            what);
    }
    if (raw && n > 0) {  // H5Dget_offset counts the user block, image offsets do not
      const haddr_t addr = H5Dget_offset(d.get());
      if (addr == HADDR_UNDEF || addr < kUserBlock) cx.fail(what + ": no address");
      raw->raw(addr - kUserBlock, 8 * n);
    }
    attr_units(cx, d.get(), a.unit, a.description);
    cx.ok(d.close(), what);
  }
  attach_array_dimensions(cx, h, groups);
}

void write_case_metrics(const Context& cx, hid_t root, const MetricValues& m) {
  const Handle g = create_group(cx, root, "metrics");
  Json units = Json::object();
  const auto cat = metric_catalogue();
  for (std::size_t i = 0; i < cat.size() && i < m.size(); ++i) {
    const std::string name(cat[i].name);
    attr_double(cx, g.get(), name, m[i]);
    units[name] = std::string(cat[i].unit);
  }
  attr_string(cx, g.get(), "units_json", units.dump());
}

// ---------------------------------------------------------------------------------------------
// Reading helpers (throw; read_case_record turns that into nullopt)

Handle open_attribute(const Context& cx, hid_t obj, const char* name) {
  const std::string what = std::string("cannot read attribute ") + name;
  Handle a = cx.own(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, what);
  const Handle s = cx.own(H5Aget_space(a.get()), H5Sclose, what);
  if (H5Sget_simple_extent_npoints(s.get()) != 1) cx.fail(what + ": not a single value");
  return a;
}

std::string read_attr_string(const Context& cx, hid_t obj, const char* name) {
  const std::string what = std::string("cannot read attribute ") + name;
  const Handle a = open_attribute(cx, obj, name);
  const Handle ft = cx.own(H5Aget_type(a.get()), H5Tclose, what);
  if (H5Tget_class(ft.get()) != H5T_STRING || !cx.yes(H5Tis_variable_str(ft.get()), what))
    cx.fail(what + ": not a variable-length string");
  const Handle mt = utf8_string_type(cx);
  char* raw = nullptr;
  cx.ok(H5Aread(a.get(), mt.get(), &raw), what);
  const Hdf5String owned(raw);
  return raw ? std::string(raw) : std::string();
}

template <class T>
T read_attr_number(const Context& cx, hid_t obj, const char* name, hid_t mem_type) {
  const std::string what = std::string("cannot read attribute ") + name;
  const Handle a = open_attribute(cx, obj, name);
  const Handle ft = cx.own(H5Aget_type(a.get()), H5Tclose, what);
  const H5T_class_t c = H5Tget_class(ft.get());
  if (c != H5T_INTEGER && c != H5T_FLOAT) cx.fail(what + ": not a number");
  T v{};
  cx.ok(H5Aread(a.get(), mem_type, &v), what);
  return v;
}

double read_attr_double(const Context& cx, hid_t obj, const char* name) {
  return read_attr_number<double>(cx, obj, name, H5T_NATIVE_DOUBLE);
}
long long read_attr_int64(const Context& cx, hid_t obj, const char* name) {
  return read_attr_number<long long>(cx, obj, name, H5T_NATIVE_LLONG);
}

/// A readable file of a layout this rodend does not read: not damage.
struct UnreadableVersion : std::runtime_error {
  using std::runtime_error::runtime_error;
};

CaseRecord read_case_locked(const fs::path& path) {
  const Context cx(path, "cannot read results file");
  Handle file =
      cx.own(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "cannot open the file");
  CaseRecord r;
  {
    const Handle root = cx.own(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, "no root");
    const hid_t g = root.get();
    if (const long long v = read_attr_int64(cx, g, "schema_version");
        v < kOldestReadableSchemaVersion || v > kResultsSchemaVersion)
      throw UnreadableVersion("cannot read results file " + path.string() + ": " +
                              "schema_version " + std::to_string(v) +
                              " is not readable by this rodend (it reads " +
                              std::to_string(kOldestReadableSchemaVersion) + " to " +
                              std::to_string(kResultsSchemaVersion) + ")");
    r.id = read_attr_string(cx, g, "case_id");
    r.index = static_cast<long>(read_attr_int64(cx, g, "case_index"));
    r.scene = read_attr_string(cx, g, "scene");
    r.coordinates = Json::parse(read_attr_string(cx, g, "coordinates_json"));
    r.status = read_attr_string(cx, g, "status");
    r.message = read_attr_string(cx, g, "message");
    r.t_reached = read_attr_double(cx, g, "t_reached_s");
    r.wall_time = read_attr_double(cx, g, "wall_time_s");
    r.steps_accepted = read_attr_int64(cx, g, "steps_accepted");
    r.steps_rejected = read_attr_int64(cx, g, "steps_rejected");
    r.rhs_calls = read_attr_int64(cx, g, "rhs_calls");
    r.started_utc = read_attr_string(cx, g, "started_utc");
    r.finished_utc = read_attr_string(cx, g, "finished_utc");

    r.metrics.fill(std::numeric_limits<double>::quiet_NaN());
    if (cx.yes(H5Lexists(g, "metrics", H5P_DEFAULT), "cannot look up /metrics")) {
      const Handle m =
          cx.own(H5Gopen2(g, "metrics", H5P_DEFAULT), H5Gclose, "cannot open /metrics");
      const auto cat = metric_catalogue();
      for (std::size_t i = 0; i < cat.size() && i < r.metrics.size(); ++i) {
        const std::string name(cat[i].name);
        if (cx.yes(H5Aexists(m.get(), name.c_str()), "cannot look up metric " + name))
          r.metrics[i] = read_attr_double(cx, m.get(), name.c_str());
      }
    }
  }
  cx.ok(file.close(), "cannot close the file");
  return r;
}

// ---------------------------------------------------------------------------------------------
// Summary
//
// Written as a stream (issue 16 item 6): the rows come from a RecordSpool on the disk, a block
// at a time, and each block goes to summary.csv and to the columns of
// summary.h5 (datasets of the final size, written by hyperslabs through the sink driver) before
// the next is read: the memory it takes does not grow with the number of cases.

/// A summary column: name, unit, description and how a case record gives its value.
struct Column {
  enum class Kind { text, integer, real };
  std::string name, unit, description;
  Kind kind = Kind::real;
  std::function<std::string(const CaseRecord&)> text;
  std::function<long long(const CaseRecord&)> integer;
  std::function<double(const CaseRecord&)> real;
};

/// The values of one column for a block of rows (or for a whole table read back).
struct ColumnValues {
  Column::Kind kind = Column::Kind::real;
  std::vector<std::string> texts;
  std::vector<long long> integers;
  std::vector<double> reals;
  std::size_t size() const {
    return kind == Column::Kind::text      ? texts.size()
           : kind == Column::Kind::integer ? integers.size()
                                           : reals.size();
  }
};

/// The columns of the summary, in table order; `text_coordinates`: the grid keys whose values
/// are not all numbers (a text column; the others are numeric).
std::vector<Column> summary_columns(const Study& study,
                                    const std::set<std::string>& text_coordinates) {
  std::vector<Column> cols;
  using Get = std::function<std::string(const CaseRecord&)>;
  auto text = [&](std::string name, std::string unit, std::string desc, Get get) {
    Column c{std::move(name), std::move(unit), std::move(desc), Column::Kind::text, {}, {}, {}};
    c.text = std::move(get);
    cols.push_back(std::move(c));
  };
  auto integer = [&](std::string name, std::string unit, std::string desc,
                     std::function<long long(const CaseRecord&)> get) {
    Column c{std::move(name), std::move(unit), std::move(desc), Column::Kind::integer, {}, {}, {}};
    c.integer = std::move(get);
    cols.push_back(std::move(c));
  };
  auto real = [&](std::string name, std::string unit, std::string desc,
                  std::function<double(const CaseRecord&)> get) {
    Column c{std::move(name), std::move(unit), std::move(desc), Column::Kind::real, {}, {}, {}};
    c.real = std::move(get);
    cols.push_back(std::move(c));
  };
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();

  text("case_id", "", "case id: FNV-1a 64 hash of the canonical case description",
       [](const CaseRecord& r) { return r.id; });
  integer("case_index", "1", "position of the case in the expanded grid, 0-based",
          [](const CaseRecord& r) { return static_cast<long long>(r.index); });
  text("scene", "", "the case's scene (a grid coordinate when the study's scene is a grid axis)",
       [](const CaseRecord& r) { return r.scene; });

  // grid coordinates: numeric columns when every value is a number, else text (strings as
  // they are, other values as compact JSON); a missing value is NaN or ""
  for (const std::string& key : study.axis_keys) {
    if (key == "scene") continue;  // the scene column above
    std::string unit;
    if (key.rfind("parameters.", 0) == 0 && !study.cases.empty()) {
      const std::string path = key.substr(11);
      for (const CaseSpec& c : study.cases)  // with a scene axis, not every scene has it
        if (c.parameters.has(path)) {
          unit = c.parameters.unit(path);
          break;
        }
    }
    const std::string desc = "grid coordinate " + key;
    auto value = [key](const CaseRecord& r) -> const Json* {
      if (!r.coordinates.is_object()) return nullptr;
      const auto it = r.coordinates.find(key);
      return it == r.coordinates.end() ? nullptr : &*it;
    };
    if (text_coordinates.count(key) == 0)
      real(key, unit, desc, [value](const CaseRecord& r) {
        const Json* v = value(r);
        return v && v->is_number() ? v->get<double>() : nan;
      });
    else
      text(key, unit, desc, [value](const CaseRecord& r) {
        const Json* v = value(r);
        return !v ? std::string() : v->is_string() ? v->get<std::string>() : v->dump();
      });
  }

  text("status", "", "\"ok\" or the reason the run stopped",
       [](const CaseRecord& r) { return r.status; });
  text("message", "", "details of a failed run (empty when ok)",
       [](const CaseRecord& r) { return r.message; });
  real("t_reached_s", "s", "simulation time reached",
       [](const CaseRecord& r) { return r.t_reached; });
  real("wall_time_s", "s", "wall-clock time of the run",
       [](const CaseRecord& r) { return r.wall_time; });
  integer("steps_accepted", "1", "accepted integration steps",
          [](const CaseRecord& r) { return r.steps_accepted; });
  integer("steps_rejected", "1", "rejected integration steps",
          [](const CaseRecord& r) { return r.steps_rejected; });
  integer("rhs_calls", "1", "right-hand-side evaluations",
          [](const CaseRecord& r) { return r.rhs_calls; });
  text("started_utc", "", "start of the run, UTC, ISO 8601",
       [](const CaseRecord& r) { return r.started_utc; });
  text("finished_utc", "", "end of the run, UTC, ISO 8601",
       [](const CaseRecord& r) { return r.finished_utc; });

  const auto cat = metric_catalogue();
  for (std::size_t i = 0; i < cat.size() && i < MetricValues{}.size(); ++i)
    real(std::string(cat[i].name), std::string(cat[i].unit), std::string(cat[i].description),
         [i](const CaseRecord& r) { return r.metrics[i]; });

  std::set<std::string> seen;
  for (const Column& c : cols) {
    if (c.name.empty() || c.name.find('/') != std::string::npos || c.name == ".")
      throw std::runtime_error("summary column name \"" + c.name + "\" is not usable");
    if (!seen.insert(c.name).second)
      throw std::runtime_error("summary column \"" + c.name + "\" appears twice");
  }
  return cols;
}

/// The values of column `c` for the records of `block`, into `out`.
void column_values(const Column& c, const std::vector<CaseRecord>& block, ColumnValues& out) {
  out.kind = c.kind;
  out.texts.clear();
  out.integers.clear();
  out.reals.clear();
  for (const CaseRecord& r : block) switch (c.kind) {
      case Column::Kind::text:
        out.texts.push_back(c.text(r));
        break;
      case Column::Kind::integer:
        out.integers.push_back(c.integer(r));
        break;
      case Column::Kind::real:
        out.reals.push_back(c.real(r));
        break;
    }
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (const char ch : s) {
    if (ch == '"') out += '"';
    out += ch;
  }
  return out + "\"";
}

/// The header line of summary.csv: the column names.
std::string summary_csv_header(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t j = 0; j < names.size(); ++j) {
    if (j) text += ',';
    text += csv_field(names[j]);
  }
  return text + '\n';
}

/// The first `rows` rows of `cols` as lines of summary.csv, appended to `text`: numbers as the
/// shortest decimal that reads back as the same double.
void append_summary_csv_rows(const std::vector<ColumnValues>& cols, std::size_t rows,
                             std::string& text) {
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t j = 0; j < cols.size(); ++j) {
      const ColumnValues& c = cols[j];
      if (j) text += ',';
      switch (c.kind) {
        case Column::Kind::text:
          text += csv_field(c.texts[i]);
          break;
        case Column::Kind::integer:
          text += std::to_string(c.integers[i]);
          break;
        case Column::Kind::real:
          text += shortest_decimal(c.reals[i]);
          break;
      }
    }
    text += '\n';
  }
}

/// A summary dataset: `rows` values of the column's type, contiguous (the default layout),
/// with its units and long_name.
Handle create_summary_column(const Context& cx, hid_t group, const Column& c, hsize_t rows) {
  const std::string what = "cannot write summary column " + c.name;
  const Handle space = vector_space(cx, rows);
  const Handle str = utf8_string_type(cx);
  const hid_t file_type = c.kind == Column::Kind::text      ? str.get()
                          : c.kind == Column::Kind::integer ? H5T_STD_I64LE
                                                            : H5T_IEEE_F64LE;
  // every row is written: no fill values written first (HDF5 requires them for strings)
  const Handle dcpl = cx.own(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, what);
  if (c.kind != Column::Kind::text) cx.ok(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), what);
  Handle d = cx.own(H5Dcreate2(group, c.name.c_str(), file_type, space.get(), H5P_DEFAULT,
                               dcpl.get(), H5P_DEFAULT),
                    H5Dclose, what);
  attr_units(cx, d.get(), c.unit, c.description, c.kind == Column::Kind::text);
  return d;
}

/// Writes `v` (a block of rows) into rows [begin, begin + its size) of dataset `d`.
void write_summary_block(const Context& cx, hid_t d, const std::string& name, const ColumnValues& v,
                         hsize_t begin) {
  const std::string what = "cannot write summary column " + name;
  const hsize_t n = v.size();
  if (n == 0) return;
  const Handle file_space = cx.own(H5Dget_space(d), H5Sclose, what);
  cx.ok(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &begin, nullptr, &n, nullptr), what);
  const Handle mem_space = vector_space(cx, n);
  const Handle str = utf8_string_type(cx);
  hid_t mem_type = H5T_NATIVE_DOUBLE;
  const void* data = v.reals.data();
  std::vector<const char*> ptrs;
  if (v.kind == Column::Kind::text) {
    for (const std::string& s : v.texts) ptrs.push_back(s.c_str());
    mem_type = str.get();
    data = ptrs.data();
  } else if (v.kind == Column::Kind::integer) {
    mem_type = H5T_NATIVE_LLONG;
    data = v.integers.data();
  }
  // type conversion buffers of a block's size, not HDF5's default 1 MiB each (two per write:
  // the strings' conversion and its background)
  const Handle dxpl = cx.own(H5Pcreate(H5P_DATASET_XFER), H5Pclose, what);
  cx.ok(H5Pset_buffer(dxpl.get(), std::max<std::size_t>(n * 16, 4096), nullptr, nullptr), what);
  cx.ok(H5Dwrite(d, mem_type, mem_space.get(), file_space.get(), dxpl.get(), data), what);
}

/// The kind of summary dataset `d` (from its HDF5 type) and its number of rows, into `v`.
hsize_t open_summary_column(const Context& cx, hid_t d, const std::string& what, ColumnValues& v) {
  const Handle space = cx.own(H5Dget_space(d), H5Sclose, what);
  const Handle type = cx.own(H5Dget_type(d), H5Tclose, what);
  const H5T_class_t cls = H5Tget_class(type.get());
  v.kind = cls == H5T_STRING    ? Column::Kind::text
           : cls == H5T_INTEGER ? Column::Kind::integer
                                : Column::Kind::real;
  return static_cast<hsize_t>(H5Sget_simple_extent_npoints(space.get()));
}

/// Rows [begin, begin + n) of summary dataset `d` into `v` (of the kind open_summary_column
/// gave), its old values replaced.
void read_summary_block(const Context& cx, hid_t d, const std::string& what, hsize_t begin,
                        hsize_t n, ColumnValues& v) {
  v.texts.clear();
  v.integers.assign(v.kind == Column::Kind::integer ? n : 0, 0);
  v.reals.assign(v.kind == Column::Kind::real ? n : 0, 0.0);
  if (n == 0) return;
  const Handle file_space = cx.own(H5Dget_space(d), H5Sclose, what);
  cx.ok(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &begin, nullptr, &n, nullptr), what);
  const Handle mem_space = vector_space(cx, n);
  if (v.kind == Column::Kind::text) {
    const Handle str = utf8_string_type(cx);
    std::vector<char*> raw(n, nullptr);
    cx.ok(H5Dread(d, str.get(), mem_space.get(), file_space.get(), H5P_DEFAULT, raw.data()), what);
    for (char* p : raw) {
      v.texts.emplace_back(p ? p : "");
      H5free_memory(p);
    }
  } else if (v.kind == Column::Kind::integer) {
    cx.ok(H5Dread(d, H5T_NATIVE_LLONG, mem_space.get(), file_space.get(), H5P_DEFAULT,
                  v.integers.data()),
          what);
  } else {
    cx.ok(H5Dread(d, H5T_NATIVE_DOUBLE, mem_space.get(), file_space.get(), H5P_DEFAULT,
                  v.reals.data()),
          what);
  }
}

/// Rows a summary is written in: the memory a summary takes is about this many case records.
constexpr std::size_t kSummaryRowsPerBlock = 256;

ByteSpan bytes_of(const std::string& text) {
  return ByteSpan(reinterpret_cast<const unsigned char*>(text.data()), text.size());
}

}  // namespace

// -------------------------------------------------------------------------------------------
// Public interface

std::string shortest_decimal(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[40];
  // the shortest digits that read back exactly, as d.ddde±XX
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::scientific);
  const std::string sci(buf, r.ptr);
  const auto e = sci.find('e');
  const int exp = std::stoi(sci.substr(e + 1));
  if (exp < -4 || exp >= 16) return sci;  // 1e-17, 1.5e+20
  const bool negative = sci[0] == '-';
  std::string digits;
  for (std::size_t i = negative ? 1 : 0; i < e; ++i)
    if (sci[i] != '.') digits += sci[i];
  std::string out = negative ? "-" : "";
  if (exp < 0) {
    out += "0." + std::string(static_cast<std::size_t>(-exp - 1), '0') + digits;  // 0.0005
  } else {
    const auto whole = static_cast<std::size_t>(exp + 1);
    if (digits.size() <= whole)
      out += digits + std::string(whole - digits.size(), '0');  // 12345678901
    else
      out += digits.substr(0, whole) + "." + digits.substr(whole);  // 1.25
  }
  return out;
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

Json provenance(const Study& study) {
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
  Json p{{"rodend_version", RODEND_VERSION}, {"git_revision", RODEND_GIT_REVISION},
         {"host", std::string(host)},        {"study_file", study.file.string()},
         {"study_name", study.name},         {"created_utc", utc_now()}};
  if (!study.overrides.empty()) p["overrides"] = study.overrides;  // rodend run --set
  return p;
}

namespace {

// ---------------------------------------------------------------------------------------------
// Case files from templates (sweep/case_template.hpp): HDF5 builds a case file once per shape,
// under the lock, and every case of that shape is the template with its values written in,
// outside it

/// What a case file's key holds of its histories and arrays (the attributes' part: CaseSlots).
std::string history_shape(const History& h, const OutputSettings& out) {
  Json shape{{"samples", h.samples},
             {"precision", static_cast<int>(out.history_precision)},
             {"level", out.compression_level}};
  Json& signals = shape["signals"] = Json::array();
  for (SignalId id : h.signals) signals.push_back(std::string(signal_spec(id).name));
  Json& arrays = shape["arrays"] = Json::array();
  for (const CaseArray& a : h.arrays)
    arrays.push_back({a.group, a.name, a.unit, a.description, a.dims, a.dim_names});
  return shape.dump();
}

/// The case's raw data in the order the template's writers placed it: every chunk of every
/// signal, then every array that is not empty.
std::vector<CaseTemplate::Bytes> raw_data(const History& h,
                                          const std::vector<EncodedSignal>& encoded) {
  std::vector<CaseTemplate::Bytes> raw;
  for (const EncodedSignal& e : encoded) raw.insert(raw.end(), e.chunks.begin(), e.chunks.end());
  for (const CaseArray& a : h.arrays)
    if (!a.values.empty())
      raw.emplace_back(reinterpret_cast<const unsigned char*>(a.values.data()),
                       8 * a.values.size());
  return raw;
}

/// What a case file is made of.
struct CaseParts {
  const CaseSpec& spec;
  const CaseRecord& record;
  const History& history;
  const Json& prov;
  const std::vector<EncodedSignal>& encoded;
  std::size_t estimate;  ///< of the image [bytes]
};

/// The attributes of a case file, written through `cx` (values, placeholders or collected).
void write_case_attributes(const Context& cx, hid_t root, const CaseParts& c) {
  write_case_root(cx, root, c.spec, c.record, c.prov);
  write_case_parameters(cx, root, c.spec.parameters);
  write_case_metrics(cx, root, c.record.metrics);
}

/// The image of a template file (without its user block) in the calling thread's
/// ScratchSlot::image: its metadata where HDF5 wrote it, zeros between, the raw regions of
/// `built` left as they are (each case fills them). Empty when a dropped write is not all in
/// a raw region (then it held something else).
ByteSpan template_image(const TemplateTarget& target, const CaseSlots& built) {
  const haddr_t base = kUserBlock;
  if (target.eoa < base + 64) return {};
  const std::size_t size = static_cast<std::size_t>(target.eoa - base);
  std::vector<std::pair<haddr_t, haddr_t>> raw;  // image offsets, sorted
  for (const auto& [offset, bytes] : built.raw_regions()) raw.emplace_back(offset, offset + bytes);
  std::sort(raw.begin(), raw.end());
  for (const auto& [begin, end] : target.dropped) {
    if (begin < base) return {};
    const auto after =
        std::upper_bound(raw.begin(), raw.end(), std::pair{begin - base, ~haddr_t{0}});
    if (after == raw.begin() || std::prev(after)->second < end - base) return {};
  }
  unsigned char* const image = thread_scratch(ScratchSlot::image, size);
  haddr_t at = 0;
  auto& t = const_cast<TemplateTarget&>(target);  // template_copy out of it only reads
  for (std::size_t k = 0; k <= raw.size(); ++k) {
    const haddr_t end = k < raw.size() ? raw[k].first : size;
    if (end < at || end > size) return {};
    template_copy(t, base + at, static_cast<size_t>(end - at), image + at, false);
    if (k < raw.size()) at = raw[k].second;
  }
  return ByteSpan(image, size);
}

/// HDF5 builds the case file with placeholders (under the lock, without its histories: the
/// template driver), and the template is made of it (outside the lock). nullptr: the file
/// cannot be a template.
std::shared_ptr<const CaseTemplate> build_case_template(const fs::path& path, const CaseParts& c,
                                                        const CaseSlots& values) {
  CaseSlots built(CaseSlots::Mode::placeholders);
  TemplateTarget target;
  {
    Hdf5Lock lock;
    const Context plain(path, "cannot write results file");
    const Context cx(path, "cannot write results file", &built);
    build_template_file(plain, target, [&](hid_t file) {
      const Handle root = plain.own(H5Gopen2(file, "/", H5P_DEFAULT), H5Gclose, "no root");
      // in the order of write_case_file's build: the attributes' slots, the raw data
      write_case_root(cx, root.get(), c.spec, c.record, c.prov);
      write_case_parameters(cx, root.get(), c.spec.parameters);
      write_case_signals(plain, root.get(), c.history, c.encoded, c.spec.output, &built);
      write_case_arrays(plain, root.get(), c.history, &built);
      write_case_metrics(cx, root.get(), c.record.metrics);
    });
  }
  const ByteSpan image = template_image(target, built);
  if (image.empty() || built.key() != values.key()) return nullptr;
  return CaseTemplate::analyse(image, built);
}

/// The templates by key (a case's slots and history_shape), the most recently used last.
struct TemplateCache {
  std::mutex mutex;  ///< held while one is built: a case of the same key waits for it
  std::vector<std::pair<std::string, std::shared_ptr<const CaseTemplate>>> entries;
};
TemplateCache g_templates;
/// Templates kept: one per shape of the cases of a study (a failed case's histories are
/// shorter, a shape of its own); each holds its image but the raw data (~0.1 MB for bench-32).
constexpr std::size_t kTemplatesKept = 8;

/// The case file's image from its template (building the template first if there is none for
/// its key), in the calling thread's ScratchSlot::image. Empty: no template possible.
ByteSpan image_from_template(const fs::path& path, const CaseParts& c) {
  CaseSlots values(CaseSlots::Mode::collect);
  const Context cx(path, "cannot write results file", &values);
  write_case_attributes(cx, H5I_INVALID_HID, c);
  for (const CaseArray& a : c.history.arrays) check_case_array(cx, a);
  const std::vector<CaseTemplate::Bytes> raw = raw_data(c.history, c.encoded);
  const std::string key = values.key() + history_shape(c.history, c.spec.output);
  std::shared_ptr<const CaseTemplate> t;
  {
    std::lock_guard lock(g_templates.mutex);
    auto& e = g_templates.entries;
    auto it = std::find_if(e.begin(), e.end(), [&](const auto& x) { return x.first == key; });
    if (it == e.end()) {
      if (e.size() == kTemplatesKept) e.erase(e.begin());
      e.emplace_back(key, build_case_template(path, c, values));
      it = std::prev(e.end());
    }
    std::rotate(it, std::next(it), e.end());  // the most recently used last
    t = e.back().second;
  }
  if (!t) return {};
  const std::size_t size = t->image_size(values);
  unsigned char* const buffer = thread_scratch(ScratchSlot::image, size);
  t->patch(values, raw, buffer);
  return ByteSpan(buffer, size);
}

}  // namespace

void write_case_file(const fs::path& path, const CaseSpec& spec, const CaseRecord& record,
                     const History& history, const Json& prov) {
  check_history(path, history);
  // the expensive part, in the calling thread: every chunk shuffled and deflated
  std::vector<EncodedSignal> encoded;
  encoded.reserve(history.signals.size());
  std::size_t estimate = 1 << 16;  // [bytes] attributes and HDF5's own structures
  for (std::size_t i = 0; i < history.signals.size(); ++i) {
    encoded.push_back(encode_signal(history.values[i], history.samples,
                                    signal_spec(history.signals[i]).width, spec.output));
    for (const auto& chunk : encoded.back().chunks) estimate += chunk.size();
  }
  for (const CaseArray& a : history.arrays) estimate += 8 * a.values.size() + (1 << 14);
  // HDF5's own structures per dataset (object header, attributes, chunk index; measured:
  // 4-9 kB): an estimate too small makes the core driver grow its buffer by a whole estimate
  // (a copy and a clear of the file so far, under the lock)
  estimate += history.signals.size() * (1 << 14);
  // chunks of a fixed size (not compressed): the case's image from its template, no HDF5
  ByteSpan image;
  const char* const templates = std::getenv("RODEND_CASE_TEMPLATES");
  if (spec.output.compression_level == 0 && !(templates && std::string_view(templates) == "0"))
    image = image_from_template(path, {spec, record, history, prov, encoded, estimate});
  if (image.empty()) {
    Hdf5Lock lock;  // held for the in-memory build: cheap calls only, the chunks are ready
    const Context cx(path, "cannot write results file");
    image = build_image(cx, kUserBlock, estimate, [&](hid_t file) {
      const Handle root = cx.own(H5Gopen2(file, "/", H5P_DEFAULT), H5Gclose, "no root");
      write_case_root(cx, root.get(), spec, record, prov);
      write_case_parameters(cx, root.get(), spec.parameters);
      write_case_signals(cx, root.get(), history, encoded, spec.output);
      write_case_arrays(cx, root.get(), history);
      write_case_metrics(cx, root.get(), record.metrics);
    });
  }
  encoded.clear();
  const auto header = checksum_header(image);
  // Not flushed to the disk (no fsync): a case file torn by an OS crash or a power loss fails
  // its checksum, and resume moves it aside and reruns the case (docs/testing.md, Faults).
  write_file_atomically(path, "results file", {ByteSpan(header), image}, /*durable=*/false);
}

WriteFailureInjection::WriteFailureInjection(long long bytes) {
  g_write_budget.store(std::max(bytes, 0LL));
}
WriteFailureInjection::~WriteFailureInjection() {
  g_write_budget.store(-1);
}

namespace {

/// Reads `n` bytes at `offset` of `fd` into `buf`; throws naming `path` (CorruptFile `corrupt`
/// when the file ends before them).
void read_exactly(int fd, unsigned char* buf, std::size_t offset, std::size_t n,
                  const fs::path& path, const std::string& corrupt) {
  std::size_t got = 0;
  while (got < n) {
    const ssize_t r = ::pread(fd, buf + got, n - got, static_cast<off_t>(offset + got));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0)
      throw std::runtime_error("cannot read " + path.string() + ": " + std::strerror(errno));
    if (r == 0) throw CorruptFile(corrupt + "shorter than it was a moment ago");
    got += static_cast<std::size_t>(r);
  }
}

/// The checksum of a case file or summary.h5 (`kind`: "case file", "summary file"): its user
/// block must be exactly the header checksum_header writes (every byte of the 512, padding
/// included), its size the one stated, the CRC-32 of the rest the one stated. False for a
/// file without a user block (an HDF5 file written before checksums). Throws CorruptFile.
bool verify_checksum(const fs::path& path, const std::string& kind) {
  const std::string corrupt = "corrupt " + kind + " " + path.string() + ": ";
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0)
    throw std::runtime_error("cannot read " + kind + " " + path.string() + ": " +
                             std::strerror(errno));
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    throw std::runtime_error("cannot read " + kind + " " + path.string() + ": " +
                             std::strerror(errno));
  if (!S_ISREG(st.st_mode))
    throw std::runtime_error("cannot read " + kind + " " + path.string() + ": not a regular file");
  const auto size = static_cast<std::size_t>(st.st_size);
  std::vector<unsigned char> buf(std::size_t{1} << 20);
  const std::size_t head = std::min<std::size_t>(size, kUserBlock);
  read_exactly(fd, buf.data(), 0, head, path, corrupt);
  if (head >= sizeof kHdf5Signature &&
      std::memcmp(buf.data(), kHdf5Signature, sizeof kHdf5Signature) == 0)
    return false;  // no user block: written before checksums (HDF5 checks what it can)
  if (head < kChecksumMagic.size() ||
      std::memcmp(buf.data(), kChecksumMagic.data(), kChecksumMagic.size()) != 0)
    throw CorruptFile(corrupt + (size == 0 ? "empty file"
                                           : "no checksum header (\"RODEND-CHECKSUM\") and not an "
                                             "HDF5 file"));
  const std::string header(reinterpret_cast<const char*>(buf.data()), head);
  unsigned stored = 0;
  unsigned long long bytes = 0;
  if (head < kUserBlock ||
      std::sscanf(header.c_str() + kChecksumMagic.size(), "crc32 %8x\nbytes %llu", &stored,
                  &bytes) != 2 ||
      std::memcmp(buf.data(), checksum_header(stored, bytes).data(), kUserBlock) != 0)
    throw CorruptFile(corrupt + "damaged checksum header");
  if (bytes != size)
    throw CorruptFile(corrupt + std::to_string(size) + " bytes, its checksum header says " +
                      std::to_string(bytes) + " (truncated or extended)");
  std::uint32_t crc = 0;
  for (std::size_t offset = kUserBlock; offset < size;) {
    const std::size_t n = std::min(buf.size(), size - offset);
    read_exactly(fd, buf.data(), offset, n, path, corrupt);
    crc = libdeflate_crc32(crc, buf.data(), n);
    offset += n;
  }
  if (crc != stored) {
    char text[96];
    std::snprintf(text, sizeof text,
                  "content does not match its checksum (CRC-32 %08x, stored %08x)",
                  static_cast<unsigned>(crc), stored);
    throw CorruptFile(corrupt + text);
  }
  return true;
}

}  // namespace

bool verify_case_file(const fs::path& path) {
  try {
    return verify_checksum(path, "case file");
  } catch (const CorruptFile& e) {
    throw CorruptCaseFile(e.what());
  }
}

bool verify_summary_file(const fs::path& path) {
  return verify_checksum(path, "summary file");
}

long long hdf5_lock_count() {
  return g_lock_stats.count.load();
}

void prepare_results_io() {
  const Hdf5Lock lock;  // H5open on first use, the free-list limits, this thread's error stack
}

std::optional<CaseRecord> read_case_record(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return std::nullopt;
  try {
    verify_case_file(path);
    Hdf5Lock lock;  // held for the whole open-read-close
    return read_case_locked(path);
  } catch (const std::exception&) {
    // unreadable, corrupt, or of another schema version: the caller treats it as absent
    return std::nullopt;
  }
}

std::optional<CaseRecord> read_case_record_strict(const fs::path& path) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(path, ec);
  if (st.type() == fs::file_type::not_found) return std::nullopt;
  if (ec) throw std::runtime_error(path.string() + ": " + ec.message());
  if (!fs::is_regular_file(path, ec))
    throw std::runtime_error(path.string() + ": not a regular file");
  const bool verified = verify_case_file(path);  // outside the lock: reads the whole file
  Hdf5Lock lock;                                 // held for the whole open-read-close
  try {
    CaseRecord rec = read_case_locked(path);
    // an intact file of another case copied under this name: not this case's result
    if (rec.id != path.stem().string())
      throw std::runtime_error("cannot read results file " + path.string() + ": it holds case " +
                               rec.id + ", not " + path.stem().string() +
                               " (a case file copied or moved under another case's name)");
    return rec;
  } catch (const UnreadableVersion&) {
    throw;
  } catch (const std::exception& e) {
    // a file whose checksum holds is not damaged (opened elsewhere for writing, say); one
    // without a checksum (written before them) that HDF5 cannot read is
    if (!verified) throw CorruptCaseFile("corrupt case file " + path.string() + ": " + e.what());
    throw std::runtime_error(std::string(e.what()).rfind("cannot read", 0) == 0
                                 ? std::string(e.what())
                                 : "cannot read results file " + path.string() + ": " + e.what());
  }
}

bool summary_csv_matches(const fs::path& dir) {
  const fs::path h5 = dir / "summary.h5";
  std::error_code ec;
  if (!fs::is_regular_file(h5, ec)) return true;
  long long stored = -1;
  {
    try {
      verify_summary_file(h5);
    } catch (const std::exception&) {
      return true;  // damaged: left for read_summary (and repair_summary_csv) to report
    }
    Hdf5Lock lock;
    const Context cx(h5, "cannot read summary");
    try {
      Handle file = cx.own(H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                           "cannot open the file");
      const Handle root = cx.own(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, "no root");
      if (!cx.yes(H5Aexists(root.get(), "summary_csv_crc32"), "cannot look up summary_csv_crc32"))
        return true;  // written before the pair was tied: nothing to compare
      stored = read_attr_int64(cx, root.get(), "summary_csv_crc32");
    } catch (const std::exception&) {
      return true;  // not readable: left for read_summary to report
    }
  }
  // the CRC-32 of summary.csv, read in blocks (never whole in memory)
  std::ifstream in(dir / "summary.csv", std::ios::binary);
  if (!in) return false;
  std::uint32_t crc = 0;
  std::vector<char> block(1 << 16);
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    crc = libdeflate_crc32(crc, block.data(), static_cast<std::size_t>(in.gcount()));
  }
  return static_cast<long long>(crc) == stored;
}

namespace {

/// Writes the checksum header (checksum_header) into the user block of the summary.h5 HDF5 has
/// just written to `h5`'s temporary file: the CRC-32 of every byte after the block.
void seal_summary(AtomicFile& h5) {
  struct stat st {};
  if (::fstat(h5.fd(), &st) != 0) h5.fail_write(errno);
  const auto size = static_cast<std::size_t>(st.st_size);
  if (size < kUserBlock + sizeof kHdf5Signature)
    throw std::logic_error("summary.h5 is shorter than its user block");
  std::vector<unsigned char> buf(std::size_t{1} << 20);
  std::uint32_t crc = 0;
  for (std::size_t offset = kUserBlock; offset < size;) {
    const std::size_t n = std::min(buf.size(), size - offset);
    const ssize_t r = ::pread(h5.fd(), buf.data(), n, static_cast<off_t>(offset));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) h5.fail_write(r < 0 ? errno : EIO);
    crc = libdeflate_crc32(crc, buf.data(), static_cast<std::size_t>(r));
    offset += static_cast<std::size_t>(r);
  }
  const auto header = checksum_header(crc, size);
  if (const int err = write_all(h5.fd(), header.data(), header.size(), 0); err != 0)
    h5.fail_write(err);
}

}  // namespace

void write_summary(const fs::path& dir, const Study& study, const RecordSpool& rows,
                   const Json& prov) {
  const std::size_t row_count = rows.size();
  const std::vector<Column> cols = summary_columns(study, rows.text_coordinates());
  std::vector<std::string> names;
  for (const Column& c : cols) names.push_back(c.name);
  // summary.csv and summary.h5 go to their temporary files block of rows by block of rows;
  // summary.h5 carries the CRC-32 of summary.csv and is renamed first, and only then
  // summary.csv: a run stopped between the two renames leaves a summary.csv that does not
  // match, which the next run (or merge) rewrites from summary.h5 (repair_summary_csv)
  AtomicFile csv(dir / "summary.csv", "summary file");
  const fs::path h5_path = dir / "summary.h5";
  AtomicFile h5(h5_path, "summary file");
  SinkTarget sink;
  sink.fd = h5.fd();
  try {
    Hdf5Lock lock;  // held for the whole create-write-close
    const Context cx(h5_path, "cannot write summary file");
    const Handle fapl = sink_access(cx, sink);
    // the user block: the checksum header, written once HDF5 is done (seal_summary)
    const Handle fcpl = cx.own(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "cannot create the file");
    cx.ok(H5Pset_userblock(fcpl.get(), kUserBlock), "cannot create the file");
    Handle file = cx.own(H5Fcreate(h5_path.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()),
                         H5Fclose, "cannot create the file");
    Handle root = cx.own(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, "no root");
    const hid_t g = root.get();
    attr_int(cx, g, "schema_version", kResultsSchemaVersion);
    attr_string(cx, g, "study_name", study.name);
    const std::string study_file = prov_text(prov, "study_file");
    attr_string(cx, g, "study_file", study_file.empty() ? study.file.string() : study_file);
    for (const char* key : {"rodend_version", "git_revision", "host"})
      attr_string(cx, g, key, prov_text(prov, key));
    attr_int64(cx, g, "case_count", static_cast<long long>(row_count));
    attr_string(cx, g, "provenance_json", prov.dump());
    attr_string(cx, g, "study_json", study.source.dump());

    Handle summary = create_group(cx, g, "summary", /*track_link_order=*/true);
    std::vector<Handle> datasets;
    for (const Column& c : cols)
      datasets.push_back(create_summary_column(cx, summary.get(), c, row_count));

    std::vector<CaseRecord> block;
    std::vector<ColumnValues> values(cols.size());
    std::string text = summary_csv_header(names);
    std::uint32_t crc = 0;
    for (std::size_t begin = 0;; begin += kSummaryRowsPerBlock) {
      const std::size_t end = std::min(row_count, begin + kSummaryRowsPerBlock);
      if (end > begin) {
        rows.read(begin, end, block);
        if (block.size() != end - begin)
          throw std::logic_error("the summary's rows gave " + std::to_string(block.size()) +
                                 " records for " + std::to_string(end - begin) + " rows");
        for (std::size_t j = 0; j < cols.size(); ++j) {
          column_values(cols[j], block, values[j]);
          write_summary_block(cx, datasets[j].get(), cols[j].name, values[j], begin);
        }
        append_summary_csv_rows(values, end - begin, text);
        // a latched failure (a full disk): reported at once, not after the remaining rows
        if (sink.error != 0) throw std::runtime_error("the sink driver latched a failure");
      }
      crc = libdeflate_crc32(crc, text.data(), text.size());
      csv.write(bytes_of(text));
      text.clear();
      if (end >= row_count) break;
    }

    attr_string(cx, summary.get(), "columns", Json(names).dump());
    // case_index is the netCDF dimension of every column: the table is one call away,
    // xarray.open_dataset(path, engine="h5netcdf", group="summary").to_dataframe()
    std::vector<std::pair<hid_t, unsigned>> columns;
    hid_t index = H5I_INVALID_HID;
    for (std::size_t j = 0; j < cols.size(); ++j)
      if (cols[j].name == "case_index")
        index = datasets[j].get();
      else
        columns.emplace_back(datasets[j].get(), 0u);
    attach_scale(cx, index, "case_index", columns);
    // the summary.csv of the same run (summary_csv_matches, repair_summary_csv)
    attr_int64(cx, g, "summary_csv_crc32", static_cast<long long>(crc));
    for (Handle& d : datasets) cx.ok(d.close(), "cannot close a summary column");
    cx.ok(summary.close(), "cannot close the summary group");
    cx.ok(root.close(), "cannot close the root group");
    // nothing of the file is open now, so this is the real close (the last flush, the
    // superblock), whose result counts
    cx.ok(file.close(), "cannot close the file");
  } catch (const std::exception&) {
    if (sink.error != 0) h5.fail_write(sink.error);  // the cause of what HDF5 reported
    throw;
  }
  if (sink.error != 0) h5.fail_write(sink.error);
  seal_summary(h5);
  csv.finish(/*durable=*/true);
  h5.finish(/*durable=*/true);
  h5.commit(/*durable=*/true);
  csv.commit(/*durable=*/true);
}

namespace {

/// The grid keys to which `r` gives a value that is not a number.
std::vector<std::string> text_coordinate_keys(const CaseRecord& r) {
  std::vector<std::string> keys;
  if (!r.coordinates.is_object()) return keys;
  for (const auto& [key, value] : r.coordinates.items())
    if (!value.is_number()) keys.push_back(key);
  return keys;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// RecordSpool
//
// A record on the spool: its size (uint32), then index, t_reached, wall_time, steps_accepted,
// steps_rejected, rhs_calls, the metric count and the metrics (8 bytes each, native), then the
// strings id, scene, status, message, started_utc, finished_utc and the coordinates as compact
// JSON, each as its size (uint32) and bytes. The file is private to the process (native byte
// order; nothing else reads it).

namespace {

template <class T>
void put_raw(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}
void put_text(std::string& out, const std::string& s) {
  put_raw(out, static_cast<std::uint32_t>(s.size()));
  out += s;
}

/// Reads what put_raw / put_text wrote; throws on a record shorter than it says.
class SpoolReader {
 public:
  SpoolReader(const char* p, std::size_t n) : p_(p), end_(p + n) {}
  template <class T>
  T raw() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  std::string text() {
    const auto n = raw<std::uint32_t>();
    if (static_cast<std::size_t>(end_ - p_) < n) throw std::runtime_error("truncated record");
    std::string s(p_, n);
    p_ += n;
    return s;
  }

 private:
  void take(void* v, std::size_t n) {
    if (static_cast<std::size_t>(end_ - p_) < n) throw std::runtime_error("truncated record");
    std::memcpy(v, p_, n);
    p_ += n;
  }
  const char* p_;
  const char* end_;
};

std::string encode_record(const CaseRecord& r) {
  std::string out;
  put_raw(out, std::uint32_t{0});  // the size, set below
  put_raw(out, static_cast<std::int64_t>(r.index));
  put_raw(out, r.t_reached);
  put_raw(out, r.wall_time);
  put_raw(out, static_cast<std::int64_t>(r.steps_accepted));
  put_raw(out, static_cast<std::int64_t>(r.steps_rejected));
  put_raw(out, static_cast<std::int64_t>(r.rhs_calls));
  put_raw(out, static_cast<std::uint32_t>(r.metrics.size()));
  out.append(reinterpret_cast<const char*>(r.metrics.data()), sizeof(double) * r.metrics.size());
  for (const std::string* s :
       {&r.id, &r.scene, &r.status, &r.message, &r.started_utc, &r.finished_utc})
    put_text(out, *s);
  put_text(out, r.coordinates.dump());
  const auto size = static_cast<std::uint32_t>(out.size());
  std::memcpy(out.data(), &size, sizeof size);
  return out;
}

CaseRecord decode_record(const char* p, std::size_t n) {
  SpoolReader in(p, n);
  (void)in.raw<std::uint32_t>();
  CaseRecord r;
  r.index = static_cast<long>(in.raw<std::int64_t>());
  r.t_reached = in.raw<double>();
  r.wall_time = in.raw<double>();
  r.steps_accepted = in.raw<std::int64_t>();
  r.steps_rejected = in.raw<std::int64_t>();
  r.rhs_calls = in.raw<std::int64_t>();
  if (in.raw<std::uint32_t>() != r.metrics.size()) throw std::runtime_error("metric count");
  for (double& m : r.metrics) m = in.raw<double>();
  for (std::string* s : {&r.id, &r.scene, &r.status, &r.message, &r.started_utc, &r.finished_utc})
    *s = in.text();
  r.coordinates = Json::parse(in.text());
  return r;
}

}  // namespace

struct RecordSpool::Impl {
  fs::path summary;  ///< dir/summary.h5, named in messages (the spool is the summary's rows)
  int fd = -1;
  mutable std::mutex mutex;
  std::vector<std::int64_t> offsets;  ///< per slot: the record's offset, -1 when none
  std::string buffer;                 ///< records not yet written, from offset `written`
  std::int64_t written = 0;           ///< bytes in the file
  /// grid key -> records (as they stand) that give it a value that is not a number
  std::map<std::string, std::size_t> text_keys;
  std::size_t count = 0, failed = 0;  ///< records; of them, not "ok"
  /// where read() is: `cursor_slot` is the slot of row `cursor_row` (reads in order walk the
  /// offsets once; reset by put)
  mutable std::size_t cursor_row = 0, cursor_slot = 0;

  static constexpr std::size_t kBufferBytes = 1 << 16;

  /// Writes the buffer out; call with `mutex` held.
  void flush() {
    if (buffer.empty()) return;
    if (const int err = write_all(fd, reinterpret_cast<const unsigned char*>(buffer.data()),
                                  buffer.size(), static_cast<off_t>(written));
        err != 0)
      throw std::runtime_error("cannot write summary file " + summary.string() +
                               ": write error on its rows' spool in " +
                               summary.parent_path().string() + ": " + std::strerror(err));
    written += static_cast<std::int64_t>(buffer.size());
    buffer.clear();
  }
  /// The record at `offset`; call with `mutex` held.
  CaseRecord load(std::int64_t offset) const {
    if (offset >= written) {  // still in the buffer
      const std::size_t at = static_cast<std::size_t>(offset - written);
      std::uint32_t size = 0;
      std::memcpy(&size, buffer.data() + at, sizeof size);
      return decode_record(buffer.data() + at, size);
    }
    std::uint32_t size = 0;
    std::string bytes(sizeof size, '\0');
    read_at(bytes.data(), sizeof size, offset);
    std::memcpy(&size, bytes.data(), sizeof size);
    bytes.resize(size);
    read_at(bytes.data(), size, offset);
    return decode_record(bytes.data(), size);
  }
  void read_at(char* out, std::size_t n, std::int64_t offset) const {
    while (n > 0) {
      const ssize_t r = ::pread(fd, out, n, static_cast<off_t>(offset));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0)
        throw std::runtime_error("cannot read the rows' spool of " + summary.string() + ": " +
                                 (r < 0 ? std::strerror(errno) : "unexpected end"));
      out += r;
      n -= static_cast<std::size_t>(r);
      offset += r;
    }
  }
};

RecordSpool::RecordSpool(const fs::path& dir, std::size_t slots) : impl_(std::make_unique<Impl>()) {
  impl_->summary = dir / "summary.h5";
  const fs::path path = temp_path_for(dir / "summary-rows");
  impl_->fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (impl_->fd < 0)
    throw std::runtime_error("cannot write summary file " + impl_->summary.string() +
                             ": cannot create its rows' spool " + path.string() + ": " +
                             std::strerror(errno));
  ::unlink(path.c_str());  // anonymous from now on (left behind, a later run removes it)
  impl_->offsets.assign(slots, -1);
}

RecordSpool::~RecordSpool() {
  if (impl_ && impl_->fd >= 0) ::close(impl_->fd);
}

void RecordSpool::put(std::size_t slot, const CaseRecord& record) {
  const std::string bytes = encode_record(record);
  std::lock_guard lock(impl_->mutex);
  if (slot >= impl_->offsets.size()) throw std::out_of_range("spool slot");
  if (impl_->offsets[slot] < 0) {
    ++impl_->count;
  } else {  // replaced: what the old record counted no longer holds
    const CaseRecord old = impl_->load(impl_->offsets[slot]);
    if (old.status != "ok") --impl_->failed;
    for (const std::string& k : text_coordinate_keys(old))
      if (--impl_->text_keys[k] == 0) impl_->text_keys.erase(k);
  }
  if (impl_->buffer.size() + bytes.size() > Impl::kBufferBytes) impl_->flush();
  impl_->offsets[slot] = impl_->written + static_cast<std::int64_t>(impl_->buffer.size());
  if (record.status != "ok") ++impl_->failed;
  impl_->buffer += bytes;
  for (const std::string& k : text_coordinate_keys(record)) ++impl_->text_keys[k];
  impl_->cursor_row = impl_->cursor_slot = 0;
}

std::size_t RecordSpool::failed() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->failed;
}

std::size_t RecordSpool::size() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->count;
}

void RecordSpool::read(std::size_t begin, std::size_t end, std::vector<CaseRecord>& out) const {
  std::lock_guard lock(impl_->mutex);
  if (begin > end || end > impl_->count) throw std::out_of_range("spool rows");
  Impl& m = *impl_;
  if (begin < m.cursor_row) m.cursor_row = m.cursor_slot = 0;
  out.clear();
  for (std::size_t row = begin; row < end; ++row) {
    // to the slot of `row`: the next slot with a record, `row - cursor_row` times over
    for (;; ++m.cursor_slot) {
      while (m.offsets[m.cursor_slot] < 0) ++m.cursor_slot;
      if (m.cursor_row == row) break;
      ++m.cursor_row;
    }
    out.push_back(m.load(m.offsets[m.cursor_slot]));
  }
}

std::set<std::string> RecordSpool::text_coordinates() const {
  std::lock_guard lock(impl_->mutex);
  std::set<std::string> keys;
  for (const auto& [key, n] : impl_->text_keys) keys.insert(key);
  return keys;
}

namespace {

herr_t collect_name(hid_t, const char* name, const H5L_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->push_back(name);
  return 0;
}

std::vector<std::string> group_members(const Context& cx, hid_t group) {
  std::vector<std::string> names;
  cx.ok(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_name, &names),
        "cannot list a group");
  return names;
}

std::string read_dataset_unit(const Context& cx, hid_t d) {
  // `units` (CF, schema 2); `unit` in schema 1 files
  for (const char* name : {"units", "unit"})
    if (cx.yes(H5Aexists(d, name), "cannot look up a unit")) return read_attr_string(cx, d, name);
  return {};
}

}  // namespace

SummaryTable read_summary(const fs::path& dir) {
  const fs::path path = dir / "summary.h5";
  if (!fs::exists(path))
    throw std::runtime_error(dir.string() + " is not a rodend study: no summary.h5");
  verify_summary_file(path);  // never hands a damaged file to HDF5
  Hdf5Lock lock;
  const Context cx(path, "cannot read summary");
  Handle file =
      cx.own(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "cannot open the file");
  SummaryTable t;
  {
    const Handle root = cx.own(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, "no root");
    if (cx.yes(H5Aexists(root.get(), "provenance_json"), "cannot look up provenance_json"))
      t.provenance = Json::parse(read_attr_string(cx, root.get(), "provenance_json"), nullptr,
                                 /*allow_exceptions=*/false);
    if (!t.provenance.is_object()) t.provenance = Json::object();
    const Handle g =
        cx.own(H5Gopen2(file.get(), "/summary", H5P_DEFAULT), H5Gclose, "no /summary group");
    const Json cols = Json::parse(read_attr_string(cx, g.get(), "columns"));
    for (const Json& c : cols) t.columns.push_back(c.get<std::string>());
    for (const std::string& name : t.columns) {
      const std::string what = "cannot read summary column " + name;
      const Handle d = cx.own(H5Dopen2(g.get(), name.c_str(), H5P_DEFAULT), H5Dclose, what);
      ColumnValues v;
      const hsize_t n = open_summary_column(cx, d.get(), what, v);
      t.rows = static_cast<std::size_t>(n);
      t.units[name] = read_dataset_unit(cx, d.get());
      read_summary_block(cx, d.get(), what, 0, n, v);
      if (v.kind == Column::Kind::text) {
        t.texts[name] = std::move(v.texts);
      } else if (v.kind == Column::Kind::integer) {
        t.integers.insert(name);
        t.numbers[name].assign(v.integers.begin(), v.integers.end());
      } else {
        t.numbers[name] = std::move(v.reals);
      }
    }
  }
  cx.ok(file.close(), "cannot close the file");
  return t;
}

bool repair_summary_csv(const fs::path& dir) {
  if (summary_csv_matches(dir)) return false;
  const fs::path h5 = dir / "summary.h5";
  if (!fs::exists(h5))
    throw std::runtime_error(dir.string() + " is not a rodend study: no summary.h5");
  // summary.csv again from summary.h5, a block of rows at a time (as write_summary wrote it),
  // kept only if its CRC-32 is the one summary.h5 was written with
  verify_summary_file(h5);
  AtomicFile csv(dir / "summary.csv", "summary file");
  std::uint32_t crc = 0;
  long long stored = -1;
  {
    Hdf5Lock lock;
    const Context cx(h5, "cannot read summary");
    Handle file =
        cx.own(H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "cannot open the file");
    {
      const Handle root = cx.own(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, "no root");
      stored = read_attr_int64(cx, root.get(), "summary_csv_crc32");
    }
    const Handle g =
        cx.own(H5Gopen2(file.get(), "/summary", H5P_DEFAULT), H5Gclose, "no /summary group");
    std::vector<std::string> names;
    for (const Json& c : Json::parse(read_attr_string(cx, g.get(), "columns")))
      names.push_back(c.get<std::string>());
    std::vector<Handle> datasets;
    std::vector<ColumnValues> values(names.size());
    hsize_t rows = 0;
    for (std::size_t j = 0; j < names.size(); ++j) {
      const std::string what = "cannot read summary column " + names[j];
      datasets.push_back(cx.own(H5Dopen2(g.get(), names[j].c_str(), H5P_DEFAULT), H5Dclose, what));
      rows = open_summary_column(cx, datasets[j].get(), what, values[j]);
    }
    std::string text = summary_csv_header(names);
    for (hsize_t begin = 0;; begin += kSummaryRowsPerBlock) {
      const hsize_t n = std::min<hsize_t>(kSummaryRowsPerBlock, rows - begin);
      for (std::size_t j = 0; j < names.size(); ++j)
        read_summary_block(cx, datasets[j].get(), "cannot read summary column " + names[j], begin,
                           n, values[j]);
      append_summary_csv_rows(values, n, text);
      crc = libdeflate_crc32(crc, text.data(), text.size());
      csv.write(bytes_of(text));
      text.clear();
      if (begin + n >= rows) break;
    }
  }
  if (static_cast<long long>(crc) != stored)
    throw std::runtime_error("cannot rewrite " + (dir / "summary.csv").string() + " from " +
                             h5.string() +
                             ": the table read back does not give the summary.csv "
                             "it was written with (summary_csv_crc32)");
  csv.finish(/*durable=*/true);
  csv.commit(/*durable=*/true);
  return true;
}

namespace {

/// verify_case_file, once per version of a file in this process: compare opens a case file
/// once per signal, and checks it the first time only. A file changed since (another inode,
/// size, modification or status-change time) is checked again.
void verify_case_file_once(const fs::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    verify_case_file(path);  // reports why it cannot be read
    return;
  }
  using Key = std::array<long long, 7>;
  const Key key{static_cast<long long>(st.st_dev),
                static_cast<long long>(st.st_ino),
                static_cast<long long>(st.st_size),
                st.st_mtim.tv_sec,
                st.st_mtim.tv_nsec,
                st.st_ctim.tv_sec,
                st.st_ctim.tv_nsec};
  static std::mutex mutex;
  static std::set<Key> verified;
  {
    const std::lock_guard lock(mutex);
    if (verified.count(key)) return;
  }
  verify_case_file(path);
  const std::lock_guard lock(mutex);
  if (verified.size() >= 4096) verified.clear();  // memory that does not grow with the cases
  verified.insert(key);
}

}  // namespace

std::vector<std::string> list_signals(const fs::path& case_file) {
  verify_case_file_once(case_file);  // never hands a damaged file to HDF5
  Hdf5Lock lock;
  const Context cx(case_file, "cannot read case file");
  Handle file = cx.own(H5Fopen(case_file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                       "cannot open the file");
  std::vector<std::string> names;
  {
    const Handle g =
        cx.own(H5Gopen2(file.get(), "/signals", H5P_DEFAULT), H5Gclose, "no /signals group");
    names = group_members(cx, g.get());
  }
  cx.ok(file.close(), "cannot close the file");
  std::sort(names.begin(), names.end());
  return names;
}

SignalData read_signal(const fs::path& case_file, const std::string& name) {
  verify_case_file_once(case_file);  // never hands a damaged file to HDF5
  Hdf5Lock lock;
  const Context cx(case_file, "cannot read case file");
  Handle file = cx.own(H5Fopen(case_file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                       "cannot open the file");
  SignalData s;
  {
    const std::string what = "cannot read signal " + name;
    const Handle d =
        cx.own(H5Dopen2(file.get(), ("/signals/" + name).c_str(), H5P_DEFAULT), H5Dclose, what);
    const Handle space = cx.own(H5Dget_space(d.get()), H5Sclose, what);
    const int rank = H5Sget_simple_extent_ndims(space.get());
    hsize_t dims[2] = {0, 1};
    if (rank < 1 || rank > 2 || H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0)
      cx.fail(what + ": not a 1-D or 2-D dataset");
    s.samples = static_cast<std::size_t>(dims[0]);
    s.width = rank == 2 ? static_cast<int>(dims[1]) : 1;
    s.values.resize(s.samples * static_cast<std::size_t>(s.width));
    if (!s.values.empty())
      cx.ok(H5Dread(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, s.values.data()),
            what);
    s.unit = read_dataset_unit(cx, d.get());
  }
  cx.ok(file.close(), "cannot close the file");
  return s;
}

}  // namespace rodend
