#include "core/signals.hpp"

namespace rodend {
namespace {

constexpr std::array<SignalSpec, signal_count> kCatalogue{{
#define RODEND_SIGNAL(id, unit, width, doc) SignalSpec{#id, unit, width, doc},
#include "core/signals.def"
#undef RODEND_SIGNAL
}};

constexpr std::array<int, signal_count + 1> make_offsets() {
  std::array<int, signal_count + 1> o{};
  for (int i = 0; i < signal_count; ++i) o[i + 1] = o[i] + kCatalogue[i].width;
  return o;
}
constexpr auto kOffsets = make_offsets();

}  // namespace

std::span<const SignalSpec> signal_catalogue() {
  return kCatalogue;
}
const SignalSpec& signal_spec(SignalId id) {
  return kCatalogue[static_cast<int>(id)];
}
int signal_offset(SignalId id) {
  return kOffsets[static_cast<int>(id)];
}
int signal_frame_width() {
  return kOffsets[signal_count];
}

std::optional<SignalId> signal_by_name(std::string_view name) {
  for (int i = 0; i < signal_count; ++i)
    if (kCatalogue[i].name == name) return static_cast<SignalId>(i);
  return std::nullopt;
}

}  // namespace rodend
