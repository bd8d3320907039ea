// The template driver (sweep/results/template_driver.hpp).
#include "sweep/results/template_driver.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <new>

#include "sweep/results/memory_file.hpp"

namespace rodend::results_detail {
namespace {

/// Set while a template's chunks or arrays are handed to HDF5 (DroppingRawData).
thread_local bool t_dropping_raw_data = false;

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
int template_cmp(const H5FD_t* a, const H5FD_t* b) {
  return std::less<const H5FD_t*>{}(a, b) ? -1 : a == b ? 0 : 1;
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
  t->eof = std::max(t->eof, addr + size);
  try {  // no exception may cross HDF5's C frames
    if (type == H5FD_MEM_DRAW && t_dropping_raw_data)
      t->target->dropped.emplace_back(addr, addr + size);
    else
      template_copy(*t->target, addr, size,
                    const_cast<unsigned char*>(static_cast<const unsigned char*>(buffer)), true);
  } catch (const std::bad_alloc&) {
    t->target->out_of_memory = true;
  }
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
    .cmp = template_cmp,
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

}  // namespace

DroppingRawData::DroppingRawData(bool on) : on_(on && !t_dropping_raw_data) {
  if (on_) t_dropping_raw_data = true;
}
DroppingRawData::~DroppingRawData() {
  if (on_) t_dropping_raw_data = false;
}

void build_template_file(const Context& cx, TemplateTarget& target, hsize_t user_block,
                         const std::function<void(hid_t)>& build) {
  static const hid_t driver = H5FDregister(&kTemplateClass);
  if (driver < 0) cx.fail("cannot register rodend's HDF5 template driver");
  const Handle fapl = cx.own(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "cannot create the file");
  TemplateTarget* info = &target;
  cx.ok(H5Pset_driver(fapl.get(), driver, &info), "cannot create the file");
  cx.ok(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG), "cannot create the file");
  const Handle fcpl = cx.own(H5Pcreate(H5P_FILE_CREATE), H5Pclose, "cannot create the file");
  cx.ok(H5Pset_userblock(fcpl.get(), user_block), "cannot create the file");
  Handle file = cx.own(H5Fcreate("rodend-template.h5", H5F_ACC_TRUNC, fcpl.get(), fapl.get()),
                       H5Fclose, "cannot create the file");
  build(file.get());
  cx.ok(file.close(), "cannot close the file");
  if (target.out_of_memory) throw std::bad_alloc();
}

ByteSpan template_image(const TemplateTarget& target, const CaseSlots& built, hsize_t user_block) {
  const haddr_t base = user_block;
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

}  // namespace rodend::results_detail
