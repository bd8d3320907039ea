// The driver's checks at every sample, on the frame just emitted: the energy audit (scenes
// with one) and the actuator's tracking of its command (scenes with an actuator).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/driver/run.hpp"

namespace rodend::detail {
namespace {

/// The audit's residual against the largest energy flow so far (health.max_energy_residual).
void audit_energy(Run& run, double t) {
  const HealthLimits& health = run.model.health;
  RunState& s = run.state;
  const SignalFrame& frame = s.frame;
  const double r = frame.get(SignalId::energy_residual);
  // the energy scale: what crossed the boundary (input work, dissipation) and what moves
  // inside it (kinetic energy: a falling ball's or a conservative run's exchanges)
  s.max_energy_flow = std::max(
      s.max_energy_flow,
      energy_audit_scale(frame.get(SignalId::input_work), frame.get(SignalId::dissipated_energy),
                         run.model.has_kinetic ? frame.get(SignalId::kinetic_energy) : 0.0));
  if (s.max_energy_flow > health.energy_flow_floor &&
      std::abs(r) > health.max_energy_residual * s.max_energy_flow) {
    std::ostringstream m;
    m << "energy-audit residual " << std::abs(r) / s.max_energy_flow
      << " x the largest energy flow or kinetic energy (" << s.max_energy_flow
      << " J) exceeds the limit " << health.max_energy_residual << " at t = " << t << " s";
    s.stats.t_reached = t;
    throw RunFailure{RunStatus::energy_residual_limit, m.str()};
  }
}

/// |command - position| of the actuator above health.max_tracking_error for longer than
/// health.tracking_window ends the run as actuator_saturation.
void check_tracking(Run& run, double t) {
  const HealthLimits& health = run.model.health;
  RunState& s = run.state;
  const double e =
      std::abs(s.frame.get(SignalId::actuator_command) - s.frame.get(SignalId::actuator_position));
  if (!(e > health.max_tracking_error)) {
    s.tracking_since = -1.0;
  } else if (s.tracking_since < 0.0) {
    s.tracking_since = t;
  }
  if (s.tracking_since >= 0.0 && t - s.tracking_since > health.tracking_window) {
    std::ostringstream m;
    m << "actuator cannot follow its command: |command - position| = " << e
      << " m, above max_tracking_error " << health.max_tracking_error
      << " m since t = " << s.tracking_since << " s (longer than tracking_window "
      << health.tracking_window << " s) at t = " << t << " s";
    s.stats.t_reached = t;
    throw RunFailure{RunStatus::actuator_saturation, m.str()};
  }
}

}  // namespace

/// Health checks on the sample frame just emitted (energy audit, actuator tracking).
void check_health_at_sample(Run& run, double t) {
  if (run.model.checks_energy) audit_energy(run, t);
  if (run.model.checks_tracking) check_tracking(run, t);
}

}  // namespace rodend::detail
