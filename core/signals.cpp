#include "core/signals.hpp"

namespace rodend {

std::optional<SignalId> signal_by_name(std::string_view name) {
  const auto catalogue = signal_catalogue();
  for (std::size_t i = 0; i < catalogue.size(); ++i)
    if (catalogue[i].name == name) return static_cast<SignalId>(i);
  return std::nullopt;
}

}  // namespace rodend
