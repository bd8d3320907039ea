// Accuracy presets: named integrator settings per scene, chosen from the work-precision study
// (README "Speed and accuracy", plots/work_precision.py). A study selects one with
// "integrator": {"preset": "balanced"}; keys given next to it override the preset's.
#pragma once

#include <optional>
#include <span>
#include <string_view>

#include "core/integrator.hpp"

namespace rodend {

/// fast: about 10 % error on the impact metrics, for screening sweeps;
/// balanced: <= 1 % on every metric of the work-precision study, the cheapest measured (default);
/// reference: the most accurate setting measured, for regression references and checks.
std::span<const std::string_view> preset_names();

/// The settings of `preset` for `scene`; nullopt for an unknown preset.
std::optional<IntegratorSettings> preset_settings(std::string_view scene, std::string_view preset);

/// The preset a study uses when it gives no integrator settings.
inline constexpr std::string_view kDefaultPreset = "balanced";

}  // namespace rodend
