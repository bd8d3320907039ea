// The calling thread's scratch buffers (sweep/results/memory_file.hpp).
#include "sweep/results/memory_file.hpp"

#include <array>
#include <memory>

namespace rodend::results_detail {

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

}  // namespace rodend::results_detail
