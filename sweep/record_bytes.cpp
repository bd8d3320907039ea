#include "sweep/record_bytes.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace rodend {

void pack_record(std::size_t slot, const CaseRecord& rec, std::string& out) {
  const auto slot64 = static_cast<std::uint64_t>(slot);
  out.append(reinterpret_cast<const char*>(&slot64), sizeof slot64);
  out += encode_record(rec);  // led by its size
}

std::size_t unpack_record(std::string_view& in, CaseRecord& rec) {
  std::uint64_t slot = 0;
  std::uint32_t size = 0;
  if (in.size() < sizeof slot + sizeof size)
    throw std::runtime_error("a case record message is truncated");
  std::memcpy(&slot, in.data(), sizeof slot);
  in.remove_prefix(sizeof slot);
  std::memcpy(&size, in.data(), sizeof size);
  if (in.size() < size) throw std::runtime_error("a case record message is truncated");
  rec = decode_record(in.data(), size);
  in.remove_prefix(size);
  return static_cast<std::size_t>(slot);
}

}  // namespace rodend
