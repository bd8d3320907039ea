// The driver's observation stage: the full frames at the sample times (from the step's
// interpolant), the lean frame of every accepted step, and the check that a frame is finite
// before the observer sees it.
#include <cmath>
#include <sstream>

#include "core/driver/run.hpp"

namespace rodend::detail {

/// The frame of sample k at state z: checked finite, observed, then checked for health (the
/// energy audit, the actuator's tracking).
void emit_sample(Run& run, long long k, const state_t& z) {
  const RunModel& m = run.model;
  RunState& s = run.state;
  m.unscale(z, s.x);
  const double t = m.sample_time(k);
  s.frame.set(SignalId::time, t);
  m.scene.outputs(t, s.x.data(), s.discrete, s.frame);
  check_frame_finite(run, t, m.signals, m.signal_slots);
  run.obs.on_sample(s.frame);
  check_health_at_sample(run, t);
}

/// A frame with a non-finite value among `which` (the scene's signals, or those of a step
/// frame; `slots` their offsets) never reaches the observer: the run ends there. One pass over
/// those values first (no per-signal lookups, not the whole catalogue's width); only a frame
/// with a non-finite entry is looked at signal by signal.
void check_frame_finite(Run& run, double t, const std::vector<SignalId>& which,
                        const std::vector<int>& slots) {
  const SignalFrame& frame = run.state.frame;
  if (frame.all_finite(slots)) return;
  for (SignalId id : which)
    for (int k = 0; k < signal_spec(id).width; ++k)
      if (!std::isfinite(frame.get(id, k))) {
        std::ostringstream m;
        m << "non-finite signal " << signal_spec(id).name << " at t = " << t << " s";
        throw RunFailure{RunStatus::non_finite_state, m.str()};
      }
}

/// Emits every sample in (t_from, t_to] from the stepper's interpolant.
void emit_samples_until(Run& run, double t_to) {
  RunState& s = run.state;
  Stepper& stepper = run.stepper();
  while (s.next_sample < run.model.n_samples &&
         run.model.sample_time(s.next_sample) <= t_to * (1 + 1e-15)) {
    const double ts = run.model.sample_time(s.next_sample);
    if (ts >= stepper.t_now)
      s.z_tmp = stepper.z_now;
    else
      stepper.interpolate(ts, s.z_tmp);
    emit_sample(run, s.next_sample, s.z_tmp);
    ++s.next_sample;
  }
}

/// The lean frame the metrics read at every accepted step (kStepSignals); full frames only at
/// samples. Expects state.x to hold the step's end state.
void observe_step(Run& run) {
  RunState& s = run.state;
  const double t = run.stepper().t_now;
  s.frame.set(SignalId::time, t);
  run.model.scene.step_outputs(t, s.x.data(), s.discrete, s.frame);
  check_frame_finite(run, t, run.model.step_signals, run.model.step_slots);
  run.obs.on_step(s.frame);
}

}  // namespace rodend::detail
