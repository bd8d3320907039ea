// The driver's step stage: one step of the method, and the checks every step passes (a finite
// state, the step budget, the penetration of every contact).
#include <algorithm>
#include <limits>
#include <sstream>

#include "core/driver/run.hpp"

namespace rodend::detail {
namespace {

/// Watches the stages of the next step for an onset of a contact not latched (locate only).
void arm_stage_watch(Run& run) {
  StageWatch& watch = run.state.watch;
  watch.earliest = std::numeric_limits<double>::infinity();
  watch.armed = false;
  if (run.model.settings.contact_onset != ContactOnset::locate) return;
  for (int c = 0; c < run.model.scene.contact_count(); ++c) watch.armed |= !latched(run, c);
}

/// The penetration of contact c at the step's end against the contact laws' validity (the
/// contact radius) and, if the study sets one, against the clearance.
void check_penetration(Run& run, int c) {
  const Scene& scene = run.model.scene;
  const HealthLimits& health = run.model.health;
  RunStats& stats = run.state.stats;
  const double t = run.stepper().t_now;
  const double delta = end_gap(run, c, run.stepper().z_now).penetration;
  auto limit = [&](double scale, double max_ratio, double& seen, const char* what,
                   const char* key) {
    if (!(scale > 0.0)) return;
    const double ratio = delta / scale;
    seen = std::max(seen, ratio);
    if (max_ratio > 0.0 && ratio > max_ratio) {
      std::ostringstream m;
      m << "penetration " << delta << " m = " << ratio << " x the " << what << " exceeds the limit "
        << key << " = " << max_ratio << " at t = " << t << " s";
      throw RunFailure{RunStatus::penetration_limit, m.str()};
    }
  };
  limit(scene.contact_radius(c), health.max_penetration_strain, stats.max_penetration_strain,
        "contact radius", "health.max_penetration_strain");
  limit(scene.contact_clearance(c), health.max_penetration_fraction, stats.max_penetration_fraction,
        "clearance", "health.max_penetration_fraction");
}

}  // namespace

/// One step of the method: to the end of the run (dense output), or to the next sample time
/// (no dense output: samples are step ends or re-takes of the step).
void take_step(Run& run) {
  const double t_end = run.model.time.end;
  const double t_limit =
      run.stepper().dense() ? t_end : std::min(run.model.sample_time(run.state.next_sample), t_end);
  arm_stage_watch(run);
  run.stepper().step(t_limit);
  check_health_after_step(run);
}

void check_health_after_step(Run& run) {
  const Stepper& stepper = run.stepper();
  RunStats& stats = run.state.stats;
  if (!all_finite(stepper.z_now)) {
    std::ostringstream m;
    m << "non-finite state at t = " << stepper.t_now << " s (last finite t = " << stepper.t_prev
      << " s)";
    stats.t_reached = stepper.t_prev;
    throw RunFailure{RunStatus::non_finite_state, m.str()};
  }
  stats.t_reached = stepper.t_now;  // an accepted, finite step
  const long long max_steps = run.model.settings.max_steps;
  if (stepper.accepted + stepper.rejected > max_steps) {
    std::ostringstream m;
    m << "step budget of " << max_steps << " steps exhausted at t = " << stepper.t_now << " s";
    throw RunFailure{RunStatus::step_budget_exhausted, m.str()};
  }
  for (int c = 0; c < run.model.scene.contact_count(); ++c) check_penetration(run, c);
}

}  // namespace rodend::detail
