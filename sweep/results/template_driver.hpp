// Files HDF5 builds for a case file's template (case_template.hpp): the template driver.
//
// A template needs HDF5's metadata, not the histories: each case writes its own into the raw
// regions. This virtual file driver keeps what HDF5 writes in pages of 4 kB, created on first
// write, and drops the histories' chunks and the arrays (the raw data written while a
// DroppingRawData is alive; reads of dropped bytes give zeros), so that a template costs no
// memory, copies nor page faults of the size of the histories (the core driver of
// memory_file.hpp clears and copies them: ~8 MB a bench-32 case). HDF5 writes its global heap
// as raw data (H5FD_MEM_DRAW) too: that is kept. Nothing of the driver is stored in the file.
#pragma once

#include <hdf5.h>

#include <functional>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "sweep/results/atomic_file.hpp"
#include "sweep/results/case_template.hpp"
#include "sweep/results/hdf5.hpp"

namespace rodend::results_detail {

/// What HDF5 wrote of a template file (driver addresses: the user block counts).
struct TemplateTarget {
  static constexpr haddr_t kPage = 4096;
  std::map<haddr_t, std::unique_ptr<unsigned char[]>> pages;  ///< by address / kPage
  std::vector<std::pair<haddr_t, haddr_t>> dropped;  ///< [begin, end) of each dropped write
  haddr_t eoa = 0;                                   ///< at close
  /// Memory ran out in a write: the write was dropped (HDF5 is never told: it does not
  /// survive a failed write), and build_template_file throws std::bad_alloc after the close.
  bool out_of_memory = false;
};

/// While alive (and `on`), the template driver drops the raw data HDF5 writes in this thread:
/// around the writes of a template's chunks and arrays.
class DroppingRawData {
 public:
  explicit DroppingRawData(bool on);
  ~DroppingRawData();
  DroppingRawData(const DroppingRawData&) = delete;
  DroppingRawData& operator=(const DroppingRawData&) = delete;

 private:
  bool on_;
};

/// Creates a file (with a user block of `user_block` bytes) written through the template
/// driver into `target`, runs build(file) and closes it. Call under Hdf5Lock.
void build_template_file(const Context& cx, TemplateTarget& target, hsize_t user_block,
                         const std::function<void(hid_t)>& build);

/// The image of a template file (without its user block of `user_block` bytes) in the calling
/// thread's ScratchSlot::image: its metadata where HDF5 wrote it, zeros between, the raw
/// regions of `built` left as they are (each case fills them). Empty when a dropped write is
/// not all inside a raw region (then it held something else).
ByteSpan template_image(const TemplateTarget& target, const CaseSlots& built, hsize_t user_block);

}  // namespace rodend::results_detail
