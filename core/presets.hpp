// Accuracy presets: named integrator settings per scene, chosen from the work-precision study
// (README "Speed and accuracy", plots/work_precision.py). A study selects one with
// "integrator": {"preset": "balanced"}; keys given next to it override the preset's.
#pragma once

#include <optional>
#include <span>
#include <string_view>

#include "core/choice.hpp"
#include "core/integrator.hpp"

namespace rodend {

/// The presets, the menu core/integrator_presets.def:
/// fast: about 1 % error on the impact-peak metrics, the cheapest setting measured;
/// balanced: <= 0.3 % on every metric of the work-precision study (default);
/// reference: dopri5 at 1e-10, for regression references and checks.
/// (README "Speed and accuracy" gives the measurement behind each.)
#define RODEND_CHOICE_ENUM IntegratorPreset
#define RODEND_CHOICE_FILE "core/integrator_presets.def"
#include "core/choice.hpp"
std::span<const std::string_view> preset_names();

/// The settings of `preset` for `scene`; nullopt for an unknown preset.
std::optional<IntegratorSettings> preset_settings(std::string_view scene, std::string_view name);

/// The preset a study uses when it gives no integrator settings.
inline constexpr IntegratorPreset kDefaultPreset = IntegratorPreset::balanced;

}  // namespace rodend
