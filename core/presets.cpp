#include "core/presets.hpp"

#include <array>
#include <string>

namespace rodend {
namespace {

IntegratorSettings adaptive(IntegratorMethod method, double tol, double max_step = 1e-3) {
  IntegratorSettings s;
  s.method = method;
  s.abs_tol = s.rel_tol = tol;
  s.max_step = max_step;
  return s;
}

struct Entry {
  std::string_view scene;  ///< "*" for any scene without its own entry
  IntegratorPreset preset;
  IntegratorSettings settings;
};

/// Measured with plots/work_precision.py (README "Speed and accuracy"): each row's error is
/// documented there. Scenes without a row of their own use the "*" rows.
const std::array<Entry, 12>& table() {
  static const std::array<Entry, 12> t{{
      // Chosen again on 2026-11-28 from docs/performance.md "Speed and accuracy" (the figures
      // are there, not here). fast: the least wall time within 1 % (cvode_bdf 1e-5: 0.60 %
      // kinematic, 0.98 % actuator). balanced: the fewest RHS calls within 0.3 % that also ends
      // ok where the energy flows are tiny: kinematic cvode_bdf 1e-6 (6.8e-4, 3.27e4 calls; 1e-5
      // is 0.60 %); actuator cvode_bdf 1e-7 (5.4e-5, 4.16e4 calls), since at 1e-6 (2.8e-4,
      // 3.29e4) an actuator held still with a 1 um clearance fails the energy audit (residual
      // 1.06 % of flows of 6.4 uJ; cli.plots_inputs). The free-flight agreement between
      // clearances of cli.thesis_trends_scenes no longer decides it: since the error norm
      // measures positions on a fixed length (core/scenes/contact_length_scale.hpp), the free
      // flight is the same to the last bit at any tolerance (until then it needed 1e-8
      // kinematic, 1e-9 actuator). Stiff, so that a sustained hinge moment does not hold it to
      // dopri5's microsecond steps. Checked by the [presets] test.
      {"rod-end-kinematic", IntegratorPreset::fast, adaptive(IntegratorMethod::cvode_bdf, 1e-5)},
      {"rod-end-kinematic", IntegratorPreset::balanced,
       adaptive(IntegratorMethod::cvode_bdf, 1e-6)},
      {"rod-end-kinematic", IntegratorPreset::reference, adaptive(IntegratorMethod::dopri5, 1e-10)},
      {"rod-end-actuator", IntegratorPreset::fast, adaptive(IntegratorMethod::cvode_bdf, 1e-5)},
      {"rod-end-actuator", IntegratorPreset::balanced, adaptive(IntegratorMethod::cvode_bdf, 1e-7)},
      {"rod-end-actuator", IntegratorPreset::reference, adaptive(IntegratorMethod::dopri5, 1e-10)},
      // measured (docs/planar-slider-crank.md "Integrator presets"): the rod-slider
      // clearance at 0.1, 0.3 and 0.5 mm, 10 revolutions, dopri5 at 1e-5 ... 1e-12; error of
      // peak_slider_acceleration and peak_contact_force against 1e-12, largest over the three.
      // fast: 1e-5, 0.49 % / 0.25 %, 2.0e5 RHS calls (the cheapest measured). balanced: 1e-7,
      // 0.11 % / 0.10 %, 4.1e5 (1e-6 is within 0.3 % too, 0.26 %, but with little margin: the
      // error of the 0.5 mm case, whose impacts come every few turns, is not monotonic in the
      // tolerance, 0.28 % at 1e-8). reference: 1e-10, 8.9e-5 / 2e-6, 1.5e6 (1e-12: 3.7e6).
      {"planar-slider-crank", IntegratorPreset::fast, adaptive(IntegratorMethod::dopri5, 1e-5)},
      {"planar-slider-crank", IntegratorPreset::balanced, adaptive(IntegratorMethod::dopri5, 1e-7)},
      {"planar-slider-crank", IntegratorPreset::reference,
       adaptive(IntegratorMethod::dopri5, 1e-10)},
      {"*", IntegratorPreset::fast, adaptive(IntegratorMethod::dopri5, 1e-6)},
      {"*", IntegratorPreset::balanced, adaptive(IntegratorMethod::dopri5, 1e-8)},
      {"*", IntegratorPreset::reference, adaptive(IntegratorMethod::dopri5, 1e-11)},
  }};
  return t;
}

}  // namespace

std::span<const std::string_view> preset_names() {
  return choice_names(IntegratorPreset{});
}

std::optional<IntegratorSettings> preset_settings(std::string_view scene, std::string_view name) {
  const std::optional<IntegratorPreset> named = choice_from_name<IntegratorPreset>(name);
  if (!named) return std::nullopt;
  const IntegratorPreset preset = *named;
  for (const Entry& e : table())
    if (e.scene == scene && e.preset == preset) return e.settings;
  for (const Entry& e : table())
    if (e.scene == "*" && e.preset == preset) return e.settings;
  return std::nullopt;
}

}  // namespace rodend
