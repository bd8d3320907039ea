// The driver's re-take stage: a step with an event inside it is taken again from its start up
// to the event, the latches change there, and the method restarts.
#include <algorithm>

#include "core/driver/run.hpp"

namespace rodend::detail {

/// Re-takes the last step from its start up to the event and changes the latches there: the
/// discarded step's later stages felt the far side of the event (the contact force, or its
/// absence), and its interpolant would carry that into the samples before the event and into
/// the restart state. The impact speed is latched at the event, the exact onset.
void retake_to(Run& run, const Event& ev) {
  Stepper& stepper = run.stepper();
  RunState& s = run.state;
  const double dt_before = stepper.suggested_dt();
  const state_t z_start = stepper.z_prev;
  const double t_start = stepper.t_prev;
  stepper.reset(z_start, t_start, ev.t - t_start);
  std::vector<int> found = ev.contacts;
  while (stepper.t_now < ev.t) {
    stepper.step(ev.t);
    check_health_after_step(run);
    emit_samples_until(run, stepper.t_now);
    deposit_wear(run);
    // the method found a root a hair before ev.t (a grazing approach): latch there; stepping
    // on from a root without re-initialising is CVODE's CV_ILL_INPUT ("root found at and
    // very near t")
    if (stepper.finds_roots() && !stepper.roots.empty()) {
      found.insert(found.end(), stepper.roots.begin(), stepper.roots.end());
      break;
    }
  }
  const long long onsets_before = s.stats.contact_onsets;
  if (!latch_at_event(run, found, ev.from_method) && !ev.from_method && !ev.stage_only)
    s.locate_suspended = true;
  // restart with the step the controller had before the re-take, not the short one (CVODE,
  // at its root: with its own suggestion); after an onset at most with the first trial step
  // integrator.step, as at t = 0: the force law is not smooth there (delta^n, n = 1.5), and
  // a long first step through the impact's rise is not seen by every error estimate
  double dt = ev.from_method ? stepper.suggested_dt() : dt_before;
  if (s.stats.contact_onsets > onsets_before) dt = std::min(dt, run.model.settings.step);
  if (ev.stage_only) dt = std::min(dt, ev.t - t_start);  // what its stages stood
  stepper.reset(stepper.z_now, stepper.t_now, dt);
  s.stats.t_reached = stepper.t_now;
}

}  // namespace rodend::detail
