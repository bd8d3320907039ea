#include "core/signals.hpp"

namespace rodend {

std::optional<SignalId> signal_by_name(std::string_view name) {
  for (int i = 0; i < signal_count; ++i)
    if (detail::kSignalCatalogue[static_cast<std::size_t>(i)].name == name)
      return static_cast<SignalId>(i);
  return std::nullopt;
}

}  // namespace rodend
