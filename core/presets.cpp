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
const std::array<Entry, 12>& table() {
  static const std::array<Entry, 12> t{{
      // fast: dopri5 1e-7 is cheaper than 1e-6 in RHS calls and wall time and more accurate
      // (README "Speed and accuracy", 2-repeat run of this session)
      {"rod-end-kinematic", "fast", adaptive("dopri5", 1e-7)},
      {"rod-end-kinematic", "balanced", adaptive("dopri5", 1e-8)},
      {"rod-end-kinematic", "reference", adaptive("dopri5", 1e-10)},
      // measured: README "Speed and accuracy", rod-end-actuator table (plots/work_precision.py
      // --scene rod-end-actuator). balanced: the cheapest configuration in wall time with <= 1 %
      // error on every metric (max 2.7e-3); by RHS calls only cvode_adams 1e-8 is cheaper (3 %
      // fewer calls, 3.6x the wall time). fast = balanced: every looser dopri5 tolerance costs more
      // RHS calls and more wall time here, and the only other configuration with fewer RHS calls
      // (cvode_adams 1e-5, 1.01e-2) takes 5.2x the wall time. reference: dopri5 1e-10 (its measured
      // 5.4e-3 is the study's floor: the two references differ by 5.7e-3 on the first-impact peak).
      {"rod-end-actuator", "fast", adaptive("dopri5", 1e-8)},
      {"rod-end-actuator", "balanced", adaptive("dopri5", 1e-8)},
      {"rod-end-actuator", "reference", adaptive("dopri5", 1e-10)},
      // measured (issue 21; docs/planar-slider-crank.md "Integrator presets"): the rod-slider
      // clearance at 0.1, 0.3 and 0.5 mm, 10 revolutions, dopri5 at 1e-5 ... 1e-12; error of
      // peak_slider_acceleration and peak_contact_force against 1e-12, largest over the three.
      // fast: 1e-5, 0.49 % / 0.25 %, 2.0e5 RHS calls (the cheapest measured). balanced: 1e-7,
      // 0.11 % / 0.10 %, 4.1e5 (1e-6 is within 0.3 % too, 0.26 %, but with little margin: the
      // error of the 0.5 mm case, whose impacts come every few turns, is not monotonic in the
      // tolerance, 0.28 % at 1e-8). reference: 1e-10, 8.9e-5 / 2e-6, 1.5e6 (1e-12: 3.7e6).
      {"planar-slider-crank", "fast", adaptive("dopri5", 1e-5)},
      {"planar-slider-crank", "balanced", adaptive("dopri5", 1e-7)},
      {"planar-slider-crank", "reference", adaptive("dopri5", 1e-10)},
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
