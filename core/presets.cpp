#include "core/presets.hpp"

#include <array>
#include <string>

namespace rodend {
namespace {

IntegratorSettings adaptive(std::string method, double tol, double max_step = 1e-3) {
  IntegratorSettings s;
  s.method = std::move(method);
  s.abs_tol = s.rel_tol = tol;
  s.max_step = max_step;
  return s;
}

struct Entry {
  std::string_view scene;  ///< "*" for any scene without its own entry
  std::string_view preset;
  IntegratorSettings settings;
};

/// Measured with plots/work_precision.py (README "Speed and accuracy"): each row's error is
/// documented there. Scenes without a row of their own use the "*" rows.
const std::array<Entry, 9>& table() {
  static const std::array<Entry, 9> t{{
      {"rod-end-kinematic", "fast", adaptive("dopri5", 1e-6)},
      {"rod-end-kinematic", "balanced", adaptive("dopri5", 1e-8)},
      {"rod-end-kinematic", "reference", adaptive("dopri5", 1e-10)},
      // not yet measured on this scene: the rod-end-kinematic choices (same contact, same step
      // limit; the hydraulics add 1 % steps)
      {"rod-end-actuator", "fast", adaptive("dopri5", 1e-6)},
      {"rod-end-actuator", "balanced", adaptive("dopri5", 1e-8)},
      {"rod-end-actuator", "reference", adaptive("dopri5", 1e-10)},
      {"*", "fast", adaptive("dopri5", 1e-6)},
      {"*", "balanced", adaptive("dopri5", 1e-8)},
      {"*", "reference", adaptive("dopri5", 1e-11)},
  }};
  return t;
}

constexpr std::array<std::string_view, 3> kNames{"fast", "balanced", "reference"};

}  // namespace

std::span<const std::string_view> preset_names() {
  return kNames;
}

std::optional<IntegratorSettings> preset_settings(std::string_view scene, std::string_view preset) {
  for (const Entry& e : table())
    if (e.scene == scene && e.preset == preset) return e.settings;
  for (const Entry& e : table())
    if (e.scene == "*" && e.preset == preset) return e.settings;
  return std::nullopt;
}

}  // namespace rodend
