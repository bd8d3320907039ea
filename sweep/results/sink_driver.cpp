// The sink driver (sweep/results/sink_driver.hpp).
#include "sweep/results/sink_driver.hpp"

#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <functional>

#include "sweep/results/atomic_file.hpp"

namespace rodend::results_detail {

namespace {

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

}  // namespace

Handle sink_access(const Context& cx, SinkTarget& target) {
  static const hid_t driver = H5FDregister(&kSinkClass);
  if (driver < 0) cx.fail("cannot register rodend's HDF5 file driver");
  Handle fapl = cx.own(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "cannot create the file");
  SinkTarget* info = &target;
  cx.ok(H5Pset_driver(fapl.get(), driver, &info), "cannot create the file");
  // closing the file closes whatever of it is still open (an error path), so that HDF5 never
  // keeps it open past the life of `target`
  cx.ok(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG), "cannot create the file");
  // memory that does not grow with the file: a metadata cache of a fixed
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

}  // namespace rodend::results_detail
