// The driver's accept stage: what follows a step with no event inside it, in order.
#include <cmath>

#include "core/driver/run.hpp"

namespace rodend::detail {
namespace {

/// Renormalises quaternions when they have drifted; returns true if the state changed.
bool renormalise(Run& run, state_t& z) {
  const state_t& scale = run.model.scale;
  RunStats& stats = run.state.stats;
  bool changed = false;
  for (int o : run.model.scene.quaternion_offsets()) {
    const auto i = static_cast<std::size_t>(o);
    double n2 = 0.0;
    for (std::size_t k = 0; k < 4; ++k) n2 += z[i + k] * z[i + k] * scale[i + k] * scale[i + k];
    const double err = std::abs(std::sqrt(n2) - 1.0);
    stats.max_quaternion_norm_error = std::max(stats.max_quaternion_norm_error, err);
    // fixed-step methods renormalise every step; adaptive ones only when the drift exceeds
    // 1e-6: the right-hand side reads only the normalised quaternion (BodyKinematics), so the
    // drift changes no dynamics, and a restart is not free. For dopri5 it costs a call; for
    // cvode_bdf it throws away the BDF history (back to order 1, a new Jacobian): at 1e-10,
    // crossed on nearly every step, rod-end-kinematic's thesis cycle took 845,082 calls at
    // cvode_bdf 1e-7, 15,491 at 1e-6 (issue 20; dopri5 never reached 1e-10 there)
    if (err > (run.stepper().dense() ? 1e-6 : 0.0)) {
      const double inv = 1.0 / std::sqrt(n2);
      for (std::size_t k = 0; k < 4; ++k) z[i + k] *= inv;
      changed = true;
    }
  }
  return changed;
}

}  // namespace

/// An accepted step: samples, wear and peaks inside it (with the discrete state it was taken
/// with), then the discrete updates at its end, the step observation and renormalisation.
void accept_step(Run& run) {
  Stepper& stepper = run.stepper();
  emit_samples_until(run, stepper.t_now);
  deposit_wear(run);
  run.state.stats.t_reached = stepper.t_now;
  if (run.obs.wants_steps()) locate_contact_peaks(run);
  const bool discrete_changed = latch_at_step_end(run);
  if (run.obs.wants_steps()) observe_step(run);
  state_t& z = stepper.z_now;
  const bool renormalised = renormalise(run, z);
  if ((renormalised || discrete_changed) && stepper.dense())
    stepper.reset(z, stepper.t_now, stepper.suggested_dt());
}

}  // namespace rodend::detail
