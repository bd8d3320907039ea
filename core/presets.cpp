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
      // measured (issue 20, bench/stiff-work-precision.py --callgrind; README "Speed and
      // accuracy"): one thesis cycle, error on max contact force, max eccentricity, wear
      // integral, first-impact peak force and stroke-end surface-angle errors against dopri5
      // 1e-11, cost in instructions (callgrind, whole run). dopri5's steps are held at ~1.3e-4 s
      // by the contact mode's eigenvalues (1.5e4 ... 7e4 1/s, rodend-eigen); cvode_bdf's are
      // 3-4x longer. fast: cvode_bdf 1e-6 since 2026-11-25 (was 1e-5, which fails the energy
      // audit at clearance 0.1 mm of the thesis clearance study, plots/work_precision.py; 1e-6:
      // largest error 5e-4 over its five clearances, the least wall time of every method with
      // <= 1 %; one 0.5 mm cycle 1.7e-4 at 525 M instructions). balanced:
      // dopri5 1e-7 since 2026-11-25 (was 1e-8; remeasured with contact events, samples every
      // 1 ms: 1e-7 has 2.5e-6 largest error at 674.8 M, 18,343 steps; 1e-8 8.5e-7 at 831.6 M,
      // 25,674 steps; 1e-5 and 1e-6 cost more, 692.6 M and 701.2 M, rejecting a third of their
      // steps). cvode_bdf 1e-6 (1.7e-4, 557 M) is within 1 % on these metrics, but its free
      // flight is less accurate than the thesis-trend check allows (the socket's speed before
      // any contact differs by 3e-5 between clearances, cli.thesis_trends_scenes asks 1e-6;
      // dopri5 1e-7 gives 3.5e-7).
      {"rod-end-kinematic", "fast", adaptive("cvode_bdf", 1e-6)},
      {"rod-end-kinematic", "balanced", adaptive("dopri5", 1e-7)},
      {"rod-end-kinematic", "reference", adaptive("dopri5", 1e-10)},
      // measured (issue 20, as above): fast: cvode_bdf 1e-5, largest error 3.0e-3, 765 M
      // instructions (dopri5 1e-8: 7.9e-7, 1027 M; 1e-6 and 1e-7 cost as much, 1018 M and
      // 1010 M). Its cost is not monotonic in the tolerance here (cvode_bdf 1e-6: 1398 M, twice
      // the steps of 1e-5; 1e-7: 950 M). balanced stays dopri5 1e-8, the cheapest in wall time
      // with <= 1 % error in issue 17's study (plots/work_precision.py), for the same reason as
      // above (cvode_bdf 1e-5's socket speed before contact differs by 2e-3 between clearances).
      // reference: dopri5 1e-10 (its measured 5.4e-3 is that study's floor: the two references
      // differ by 5.7e-3 on the first-impact peak).
      {"rod-end-actuator", "fast", adaptive("cvode_bdf", 1e-5)},
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
