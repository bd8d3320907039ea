// A case file's HDF5 image built once and patched per case (sweep/results/case_template.hpp).
//
// The HDF5 structures this file reads and writes (HDF5 file format specification 3.0, as HDF5
// 1.10 writes them by default):
// - superblock version 0 at image offset 0: signature (8 bytes), version (1: 0), ..., size of
//   offsets (byte 13) and of lengths (byte 14), base address (8 bytes at 24), end-of-file
//   address (8 bytes at 40; absolute: the base address plus the image's size). No checksum.
//   Addresses elsewhere are relative to the base address, that is image offsets.
// - a variable-length string attribute's value: its length (4 bytes), the address of the
//   global heap collection that holds it (8) and its object index there (4).
// - a global heap collection: "GCOL", version 1, 3 reserved bytes, its size (8; at least
//   4096), then objects: index (2), reference count (2), reserved (4), size (8), the bytes
//   padded with zeros to a multiple of 8; last the free space, object 0, whose size counts its
//   own 16-byte header.
#include "sweep/results/case_template.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string_view>

namespace rodend {
namespace {

/// The high 32 bits of a number slot's sentinel (as a double, a signalling NaN, which no
/// computed value is); the low 32 bits are the slot.
constexpr std::uint64_t kSentinelTag = 0x7FF5D0C1u;
constexpr std::string_view kPlaceholderPrefix = "@rodend-slot:";
constexpr std::size_t kPlaceholderSize = kPlaceholderPrefix.size() + 8;
constexpr std::size_t kHeapHeader = 16;       ///< a collection's header, and an object's
constexpr std::size_t kMinCollection = 4096;  ///< HDF5 reads at least this much of one
constexpr std::size_t kSuperblockBase = 24;   ///< image offset of the base address
constexpr std::size_t kSuperblockEof = 40;    ///< image offset of the end-of-file address
constexpr unsigned char kSignature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

std::string placeholder(std::size_t slot) {
  char hex[9];
  std::snprintf(hex, sizeof hex, "%08zx", slot);
  return std::string(kPlaceholderPrefix) + hex;
}

template <class T>
T load(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);  // little-endian host and file (static_assert in case_file.cpp)
  return v;
}
template <class T>
void store(unsigned char* p, T v) {
  std::memcpy(p, &v, sizeof v);
}

std::size_t align8(std::size_t n) {
  return (n + 7) & ~std::size_t{7};
}

/// Image offsets of every occurrence of `needle` in the parts of the image listed in `gaps`.
std::vector<std::size_t> find_all(std::span<const unsigned char> image,
                                  const std::vector<std::pair<std::size_t, std::size_t>>& gaps,
                                  const void* needle, std::size_t n) {
  std::vector<std::size_t> hits;
  for (const auto& [begin, end] : gaps) {
    const unsigned char* p = image.data() + begin;
    const unsigned char* const stop = image.data() + end;
    while (p < stop) {
      const void* q = memmem(p, static_cast<std::size_t>(stop - p), needle, n);
      if (!q) break;
      const auto* h = static_cast<const unsigned char*>(q);
      hits.push_back(static_cast<std::size_t>(h - image.data()));
      p = h + 1;
    }
  }
  return hits;
}

/// `what` as a token of a key: its length first, so that no two sequences of tokens give one key.
std::string token(char kind, const std::string& what) {
  return kind + std::to_string(what.size()) + ":" + what;
}

}  // namespace

std::string CaseSlots::text(const std::string& name, const std::string& value) {
  key_ += token('t', name);
  slots_.push_back({true, value, 0});
  return collecting() ? value : placeholder(slots_.size() - 1);
}

std::uint64_t CaseSlots::number(const std::string& name, std::uint64_t bits) {
  key_ += token('n', name);
  slots_.push_back({false, {}, bits});
  return collecting() ? bits : (kSentinelTag << 32) | (slots_.size() - 1);
}

void CaseSlots::fixed(const std::string& what) {
  key_ += token('f', what);
}

void CaseSlots::raw(std::uint64_t offset, std::uint64_t size) {
  raw_.push_back({offset, size});
}

std::vector<std::pair<std::uint64_t, std::uint64_t>> CaseSlots::raw_regions() const {
  std::vector<std::pair<std::uint64_t, std::uint64_t>> r;
  for (const Region& x : raw_) r.emplace_back(x.offset, x.size);
  return r;
}

std::unique_ptr<const CaseTemplate> CaseTemplate::analyse(Bytes image, const CaseSlots& built) {
  if (image.size() < 64 || std::memcmp(image.data(), kSignature, 8) != 0 || image[8] != 0 ||
      image[13] != 8 || image[14] != 8 || built.slots_.size() >= (std::size_t{1} << 16) ||
      load<std::uint64_t>(image.data() + kSuperblockEof) !=
          load<std::uint64_t>(image.data() + kSuperblockBase) + image.size())
    return nullptr;
  std::unique_ptr<CaseTemplate> t(new CaseTemplate());
  t->size_ = image.size();
  t->slots_ = built.slots_.size();
  t->key_ = built.key_;
  // the raw regions, and the gaps between them
  std::vector<std::size_t> order(built.raw_.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return built.raw_[a].offset < built.raw_[b].offset;
  });
  std::vector<std::pair<std::size_t, std::size_t>> gaps;
  std::size_t at = 0;
  t->raw_order_.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const CaseSlots::Region r = built.raw_[order[k]];
    if (r.offset < at || r.offset + r.size > image.size()) return nullptr;
    gaps.emplace_back(at, r.offset);
    at = r.offset + r.size;
    t->raw_.push_back(r);
    t->raw_order_[order[k]] = k;
  }
  gaps.emplace_back(at, image.size());
  for (const auto& [begin, end] : gaps)
    t->metadata_.insert(t->metadata_.end(), image.begin() + static_cast<std::ptrdiff_t>(begin),
                        image.begin() + static_cast<std::ptrdiff_t>(end));
  return t->find_slots(image, built, gaps) ? std::move(t) : nullptr;
}

bool CaseTemplate::find_slots(Bytes image, const CaseSlots& built, const Gaps& gaps) {
  std::vector<bool> found(built.slots_.size(), false);
  const auto tag = static_cast<std::uint32_t>(kSentinelTag);
  for (const std::size_t q : find_all(image, gaps, &tag, 4)) {
    if (q < 4) continue;
    const std::size_t slot = load<std::uint32_t>(image.data() + q - 4);
    if (slot >= built.slots_.size() || built.slots_[slot].text) continue;
    numbers_.push_back({slot, q - 4});
    found[slot] = true;
  }
  // the placeholders in the global heap: (collection, object index) -> slot
  const std::vector<std::size_t> collections = find_all(image, gaps, "GCOL", 4);
  std::map<std::pair<std::uint64_t, std::uint32_t>, std::size_t> objects;
  for (const std::size_t q :
       find_all(image, gaps, kPlaceholderPrefix.data(), kPlaceholderPrefix.size())) {
    if (q < kHeapHeader || q + kPlaceholderSize > image.size()) continue;
    const std::string text(reinterpret_cast<const char*>(image.data() + q), kPlaceholderSize);
    const std::size_t slot = std::strtoul(text.c_str() + kPlaceholderPrefix.size(), nullptr, 16);
    if (slot >= built.slots_.size() || !built.slots_[slot].text || text != placeholder(slot) ||
        load<std::uint64_t>(image.data() + q - 8) != kPlaceholderSize)
      continue;
    const auto in = std::lower_bound(collections.begin(), collections.end(), q);
    if (in != collections.begin())
      objects[{*(in - 1), load<std::uint16_t>(image.data() + q - kHeapHeader)}] = slot;
  }
  // their references in the attributes: length (4 bytes), collection (8), object index (4)
  for (const std::size_t c : collections) {
    const auto address = static_cast<std::uint64_t>(c);
    for (const std::size_t q : find_all(image, gaps, &address, 8)) {
      if (q < 4 || q + 12 > image.size() ||
          load<std::uint32_t>(image.data() + q - 4) != kPlaceholderSize)
        continue;
      const auto it = objects.find({address, load<std::uint32_t>(image.data() + q + 8)});
      if (it == objects.end()) continue;
      references_.push_back({it->second, q - 4});
      found[it->second] = true;
    }
  }
  return std::all_of(found.begin(), found.end(), [](bool f) { return f; });
}

std::size_t CaseTemplate::collection_size(const CaseSlots& values) const {
  std::size_t total = kHeapHeader;
  for (const CaseSlots::Slot& s : values.slots_)
    if (s.text) total += kHeapHeader + align8(s.value.size());
  return std::max(kMinCollection, total + kHeapHeader);  // the free space: a header at least
}

std::size_t CaseTemplate::image_size(const CaseSlots& values) const {
  return size_ + collection_size(values);
}

void CaseTemplate::patch(const CaseSlots& values, const std::vector<Bytes>& raw,
                         unsigned char* out) const {
  if (values.key_ != key_ || values.slots_.size() != slots_ || raw.size() != raw_.size())
    throw std::logic_error("a case does not fit the template of its case file");
  // the template, its raw regions filled with the case's bytes
  const unsigned char* meta = metadata_.data();
  std::size_t at = 0;
  std::vector<std::size_t> by_offset(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) by_offset[raw_order_[i]] = i;
  for (std::size_t k = 0; k <= raw_.size(); ++k) {
    const std::size_t end = k < raw_.size() ? raw_[k].offset : size_;
    std::memcpy(out + at, meta, end - at);
    meta += end - at;
    if (k == raw_.size()) break;
    const Bytes bytes = raw[by_offset[k]];
    if (bytes.size() != raw_[k].size)
      throw std::logic_error("a chunk does not fit the template of its case file");
    std::memcpy(out + end, bytes.data(), bytes.size());
    at = end + bytes.size();
  }
  for (const Number& n : numbers_) store(out + n.offset, values.slots_[n.slot].bits);
  write_collection(values, out);
}

void CaseTemplate::write_collection(const CaseSlots& values, unsigned char* out) const {
  // the case's strings: a global heap collection appended to the image
  const std::size_t size = collection_size(values);
  unsigned char* const c = out + size_;
  std::memcpy(c, "GCOL\x01\0\0\0", 8);
  store<std::uint64_t>(c + 8, size);
  std::vector<std::uint32_t> index(values.slots_.size(), 0);
  std::size_t at = kHeapHeader;
  std::uint32_t next = 1;
  for (std::size_t i = 0; i < values.slots_.size(); ++i) {
    const CaseSlots::Slot& s = values.slots_[i];
    if (!s.text) continue;
    index[i] = next;
    std::memset(c + at, 0, kHeapHeader + align8(s.value.size()));
    store<std::uint16_t>(c + at, static_cast<std::uint16_t>(next++));
    store<std::uint64_t>(c + at + 8, s.value.size());
    std::memcpy(c + at + kHeapHeader, s.value.data(), s.value.size());
    at += kHeapHeader + align8(s.value.size());
  }
  std::memset(c + at, 0, size - at);  // the free space: object 0, its size counting its header
  store<std::uint64_t>(c + at + 8, size - at);
  for (const Reference& r : references_) {
    store<std::uint32_t>(out + r.offset,
                         static_cast<std::uint32_t>(values.slots_[r.slot].value.size()));
    store<std::uint64_t>(out + r.offset + 4, size_);
    store<std::uint32_t>(out + r.offset + 12, index[r.slot]);
  }
  const std::uint64_t base = load<std::uint64_t>(out + kSuperblockBase);
  store<std::uint64_t>(out + kSuperblockEof, base + size_ + size);
}

}  // namespace rodend
