// A case file's HDF5 image built once and patched per case (the serial section).
//
// HDF5 builds case files under one process-wide lock (sweep/results/), and building one
// (datasets, attributes, dimension scales, the chunks copied in) took 12-16 ms a case, a fifth
// of a one-thread sweep. The cases of a study share their file's structure, so HDF5 builds it
// once, with placeholders where a case's values go, and every case's image is that template
// with its values written in, by the thread that ran the case, without HDF5 and without the
// lock. What a placeholder is:
// - a number attribute (double, int64; each element of a double array): the 8-byte sentinel
//   kSentinelTag << 32 | slot, found in the image and overwritten with the case's value;
// - a text attribute (variable-length string): the placeholder "@rodend-slot:<8 hex>", which
//   HDF5 stores in a global heap collection; each case's strings go to a new collection
//   appended to the image, the attributes' references (length, collection, index) are pointed
//   at it and the superblock's end-of-file address moved past it (the template's collection is
//   left in place, unreferenced but for what is not a slot: DIMENSION_LIST);
// - raw data (the histories' chunks, the per-case arrays): HDF5 tells where it put them
//   (H5Dget_chunk_info_by_coord, H5Dget_offset), and the case's bytes are copied there.
// What is not a slot is part of the template's key: the names, kinds and order of the slots,
// the groups, the values of int32 and int8 attributes, the histories' shape (signals, samples,
// precision) and the arrays' shapes, units and descriptions. A case whose key differs gets a
// template of its own. Only for fixed-size chunks (output.compression_level 0): compressed
// chunks vary in size from case to case, and those files are built by HDF5 as before.
//
// This file only handles bytes: it never calls HDF5.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace rodend {

/// The values a case file's attributes take, in the order they are written (the slots), and
/// the file's shape (the key). Filled by the writers of sweep/results/: `collect` records a
/// case's values without HDF5; `placeholders` records them while HDF5 writes the placeholders,
/// and where HDF5 put the raw data.
class CaseSlots {
 public:
  enum class Mode { collect, placeholders };
  explicit CaseSlots(Mode mode) : mode_(mode) {}

  bool collecting() const { return mode_ == Mode::collect; }
  /// A text attribute `name` of value `value`: returns what to write (the placeholder or, when
  /// collecting, `value`).
  std::string text(const std::string& name, const std::string& value);
  /// A number attribute (or one element of a double array) whose 8 bytes are `bits`: returns
  /// the bits to write (the sentinel, or `bits` when collecting).
  std::uint64_t number(const std::string& name, std::uint64_t bits);
  /// Something that is the same in every case of a template: a group, an int attribute's value.
  void fixed(const std::string& what);
  /// Raw data HDF5 placed at image offset `offset` (`size` bytes): a chunk or an array.
  void raw(std::uint64_t offset, std::uint64_t size);

  const std::string& key() const { return key_; }
  std::size_t size() const { return slots_.size(); }
  /// The raw regions, (image offset, size) in the order they were recorded.
  std::vector<std::pair<std::uint64_t, std::uint64_t>> raw_regions() const;

 private:
  friend class CaseTemplate;
  struct Slot {
    bool text = false;
    std::string value;       ///< text slots
    std::uint64_t bits = 0;  ///< number slots
  };
  struct Region {
    std::uint64_t offset, size;
  };
  Mode mode_;
  std::string key_;
  std::vector<Slot> slots_;
  std::vector<Region> raw_;
};

/// A template image and where its slots are; shared read-only by the threads of a sweep.
class CaseTemplate {
 public:
  using Bytes = std::span<const unsigned char>;
  /// Analyses `image` (without its user block), built by HDF5 with the placeholders of
  /// `built`; its raw regions are not read. nullptr when a slot cannot be found (then HDF5
  /// builds the case files as before).
  static std::unique_ptr<const CaseTemplate> analyse(Bytes image, const CaseSlots& built);

  /// Size [bytes] of the image of a case with the slot values of `values`.
  std::size_t image_size(const CaseSlots& values) const;
  /// Writes the image of a case into `out` (image_size bytes): the template with the slot
  /// values of `values` (collected with this template's key) and `raw` copied into the raw
  /// regions (one span per region, of its size). Throws std::logic_error on a mismatch.
  void patch(const CaseSlots& values, const std::vector<Bytes>& raw, unsigned char* out) const;

 private:
  CaseTemplate() = default;
  struct Reference {  ///< a variable-length string reference of a text slot: image offset
    std::size_t slot, offset;
  };
  struct Number {  ///< the 8 bytes of a number slot
    std::size_t slot, offset;
  };
  std::size_t size_ = 0;                 ///< of the template image
  std::vector<unsigned char> metadata_;  ///< the template image but the raw regions
  std::vector<CaseSlots::Region> raw_;   ///< sorted by offset, as in CaseSlots order
  std::vector<std::size_t> raw_order_;   ///< raw_ index of the i-th raw span of a case
  std::vector<Number> numbers_;
  std::vector<Reference> references_;
  std::size_t slots_ = 0;
  std::string key_;

  using Gaps = std::vector<std::pair<std::size_t, std::size_t>>;  ///< [begin, end) offsets
  bool find_slots(Bytes image, const CaseSlots& built, const Gaps& gaps);
  std::size_t collection_size(const CaseSlots& values) const;
  void write_collection(const CaseSlots& values, unsigned char* out) const;
};

}  // namespace rodend
