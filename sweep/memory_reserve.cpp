// MemoryReserve (sweep/memory_reserve.hpp says why): regions mapped for one thread's HDF5
// session, handed out by a bump allocator (never reused: a region is unmapped when its last
// block is freed after its reserve ended). Everything here may run inside malloc or free: no
// allocation, no lock, no exception outside the constructor.
#include "sweep/memory_reserve.hpp"

#include <sys/mman.h>

#include <atomic>
#include <cstdint>
#include <new>

namespace rodend {
namespace {

enum State : int { kFree, kBusy, kActive, kRetired };

struct Region {
  std::atomic<std::uintptr_t> base{0};
  std::atomic<std::size_t> size{0};
  std::atomic<std::size_t> used{0};  // written by the reserving thread only
  std::atomic<long> live{0};         // blocks handed out and not yet freed
  std::atomic<int> state{kFree};
};

constexpr int kSlots = 16;           // regions mapped at once (a session, and those still in use)
constexpr int kMaxDepth = 4;         // reserves nested in one thread
constexpr std::size_t kHeader = 16;  // a block's size, before it; keeps 16-byte alignment

Region g_regions[kSlots];
std::atomic<int> g_mapped{0};  // regions mapped: 0 lets free() skip the search
std::atomic<bool> g_enabled{false};
// initial-exec: reaching them allocates nothing (this code runs inside malloc)
[[gnu::tls_model("initial-exec")]] thread_local int t_stack[kMaxDepth];
[[gnu::tls_model("initial-exec")]] thread_local int t_depth = 0;

int find_region(const void* p) {
  if (g_mapped.load(std::memory_order_acquire) == 0) return -1;
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  for (int i = 0; i < kSlots; ++i) {
    const std::uintptr_t b = g_regions[i].base.load(std::memory_order_acquire);
    if (b != 0 && a >= b && a < b + g_regions[i].size.load(std::memory_order_acquire)) return i;
  }
  return -1;
}

/// Unmaps a retired region without live blocks (once, whoever gets here first).
void unmap_if_done(int slot) {
  Region& r = g_regions[slot];
  int retired = kRetired;
  if (r.live.load() != 0 || !r.state.compare_exchange_strong(retired, kBusy)) return;
  const std::uintptr_t b = r.base.exchange(0);
  g_mapped.fetch_sub(1);
  ::munmap(reinterpret_cast<void*>(b), r.size.load());
  r.state.store(kFree);
}

/// A free slot, marked busy; -1 if none.
int claim_slot() {
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (g_regions[i].state.compare_exchange_strong(expected, kBusy)) return i;
  }
  return -1;
}

}  // namespace

MemoryReserve::MemoryReserve(std::size_t bytes) {
  const int prot = PROT_READ | PROT_WRITE, flags = MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE;
  if (!g_enabled.load()) {  // nothing would draw on it: only check that it could be had
    void* probe = ::mmap(nullptr, bytes, prot, flags, -1, 0);
    if (probe == MAP_FAILED) throw std::bad_alloc();
    ::munmap(probe, bytes);
    return;
  }
  if (t_depth == kMaxDepth) throw std::bad_alloc();
  const int slot = claim_slot();
  if (slot < 0) throw std::bad_alloc();  // regions still held by blocks of earlier sessions
  void* base = ::mmap(nullptr, bytes, prot, flags, -1, 0);
  Region& r = g_regions[slot];
  if (base == MAP_FAILED) {
    r.state.store(kFree);
    throw std::bad_alloc();
  }
  r.size.store(bytes);
  r.used.store(0);
  r.live.store(0);
  r.base.store(reinterpret_cast<std::uintptr_t>(base));
  g_mapped.fetch_add(1);
  r.state.store(kActive);
  t_stack[t_depth++] = slot;
  slot_ = slot;
}

MemoryReserve::~MemoryReserve() {
  if (slot_ < 0) return;
  --t_depth;
  g_regions[slot_].state.store(kRetired);
  unmap_if_done(slot_);
}

std::size_t MemoryReserve::drawn() const {
  return slot_ < 0 ? 0 : g_regions[slot_].used.load();
}

}  // namespace rodend

using rodend::g_regions;
using rodend::kHeader;

extern "C" void rodend_reserve_enable(void) noexcept {
  rodend::g_enabled.store(true);
}

extern "C" void* rodend_reserve_alloc_aligned(std::size_t alignment, std::size_t size) noexcept {
  if (size > (std::size_t{1} << 40) || alignment > (std::size_t{1} << 30) ||
      (alignment & (alignment - 1)) != 0)
    return nullptr;
  if (alignment < kHeader) alignment = kHeader;
  if (size == 0) size = 1;  // a block's size is never 0 (rodend_reserve_block_size)
  for (int d = rodend::t_depth - 1; d >= 0; --d) {
    rodend::Region& r = g_regions[rodend::t_stack[d]];
    const std::uintptr_t base = r.base.load();
    const std::uintptr_t at = (base + r.used.load() + kHeader + alignment - 1) & ~(alignment - 1);
    const std::size_t end = at - base + ((size + 15) & ~std::size_t{15});
    if (end > r.size.load()) continue;
    r.used.store(end);
    r.live.fetch_add(1);
    *reinterpret_cast<std::size_t*>(at - kHeader) = size;  // fresh pages: the rest is zero
    return reinterpret_cast<void*>(at);
  }
  return nullptr;
}

extern "C" void* rodend_reserve_alloc(std::size_t size) noexcept {
  return rodend_reserve_alloc_aligned(kHeader, size);
}

extern "C" std::size_t rodend_reserve_block_size(const void* p) noexcept {
  if (p == nullptr || rodend::find_region(p) < 0) return 0;
  return *reinterpret_cast<const std::size_t*>(static_cast<const unsigned char*>(p) - kHeader);
}

extern "C" int rodend_reserve_free(void* p) noexcept {
  const int slot = p == nullptr ? -1 : rodend::find_region(p);
  if (slot < 0) return 0;
  if (g_regions[slot].live.fetch_sub(1) == 1) rodend::unmap_if_done(slot);
  return 1;
}
