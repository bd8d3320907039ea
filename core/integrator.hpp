// Integration driver: runs a Scene with a Boost.Odeint stepper, latches contact onsets between
// accepted steps, samples histories at a fixed interval, and enforces budgets.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "core/integrator_settings.hpp"
#include "core/scene.hpp"
#include "core/signals.hpp"

namespace rodend {

/// Time settings of a run.
struct TimeSettings {
  double end = 1.0;               ///< end time [s]
  double sample_interval = 1e-3;  ///< history sample interval [s]
};

/// Health limits (study key "health"). The penetration is checked on every accepted step; the
/// energy audit and the actuator tracking at every sample time, on the frame the driver computes
/// for the sample anyway (cheap; resolved to one sample interval).
struct HealthLimits {
  /// penetration / contact radius (the smaller of the two surfaces' radii) above which a run
  /// fails [-]: the elastic contact laws' validity. At delta = 0.05 R a sphere on a flat has a
  /// Hertz contact radius a = sqrt(R delta) = 0.22 R, the edge of the half-space assumption of
  /// Hertz theory (a << R); beyond it no law of the catalogue describes the contact
  double max_penetration_strain = 0.05;
  /// penetration / clearance above which a run fails [-]; 0 = no such limit (the default: the
  /// clearance is not a scale of the contact law's validity, a tight joint under load may
  /// legitimately penetrate more than its clearance; set it to stop runs that do)
  double max_penetration_fraction = 0.0;
  /// |energy-audit residual| relative to the largest energy flow so far (max of |input work|,
  /// |dissipated energy| and the kinetic energy, over the samples so far) above which a run
  /// fails [-] (scenes with an energy audit)
  double max_energy_residual = 0.01;
  /// the energy check starts once that largest flow exceeds this floor [J]: below it the
  /// relative residual measures the audit's absolute resolution, not an error (the actuator's
  /// net flows are the difference of watts of hydraulic power: ~1e-9 J of round-off)
  double energy_flow_floor = 1e-6;
  /// |command - position| of the actuator above which it is not following [m] (scenes with an
  /// actuator command) ...
  double max_tracking_error = 5e-3;
  /// ... and for longer than this window the run fails as actuator_saturation [s]
  double tracking_window = 0.1;
};

/// The energy scale of the audit at one instant: the largest of |input work|, |dissipated
/// energy| and the kinetic energy [J]. Its largest value over a run is what the health check
/// health.max_energy_residual and the energy_residual metric divide the residual by: the
/// kinetic energy keeps it finite for a lossless run (no input, no dissipation).
inline double energy_audit_scale(double input_work, double dissipated, double kinetic) {
  return std::max({std::abs(input_work), std::abs(dissipated), kinetic});
}

struct RunStats {
  long long steps_accepted = 0;
  long long steps_rejected = 0;
  long long rhs_calls = 0;
  long long contact_onsets = 0;
  long long friction_switches = 0;         ///< friction.mode stick-slip: branch switches latched
  double t_reached = 0.0;                  ///< [s]
  double max_quaternion_norm_error = 0.0;  ///< largest | |q| - 1 | seen before renormalising [-]
  double max_penetration_fraction = 0.0;   ///< largest penetration / clearance seen [-]
  double max_penetration_strain = 0.0;     ///< largest penetration / contact radius seen [-]
};

struct RunResult {
  RunStatus status = RunStatus::ok;
  std::string message;  ///< empty when ok
  RunStats stats;
  std::vector<double> final_state;  ///< state at the last accepted step (t_reached), unscaled
};

/// A maximum of a contact's normal force or penetration inside an accepted step, located on the
/// step's interpolant (RunObserver::on_contact_peak).
struct ContactPeak {
  enum class Kind { force, penetration };
  Kind kind = Kind::force;
  int contact = 0;
  double t = 0.0;      ///< where the maximum is [s]
  ContactSnapshot at;  ///< the contact there
};

/// Receives what the driver produces. Frames are valid only during the call.
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  /// At t = 0 and every sample interval (and never after a failure). Every value of a frame
  /// passed here or to on_step is finite: a non-finite output ends the run as non_finite_state
  /// before it reaches the observer.
  virtual void on_sample(const SignalFrame& /*frame*/) {}
  /// At the end of every accepted step, when wants_steps() is true (metrics that need peaks).
  /// The frame carries the signals of kStepSignals (Scene::step_outputs), not every signal.
  virtual void on_step(const SignalFrame& /*frame*/) {}
  virtual bool wants_steps() const { return false; }
  /// When wants_steps(): whether a maximum of a contact's force or penetration inside the step
  /// that starts at t0, known to be at most `bound` (the value where the tangents at the step's
  /// two ends meet: an upper bound of a concave maximum), could change what the observer
  /// collects. Only wanted maxima are located.
  virtual bool wants_peak(ContactPeak::Kind /*kind*/, int /*contact*/, double /*t0*/,
                          double /*bound*/) const {
    return true;
  }
  /// A located maximum, before the on_step of the step that contains it.
  virtual void on_contact_peak(const ContactPeak& /*peak*/) {}
  /// When a contact episode is latched: its onset time [s] and approach speed [m/s].
  virtual void on_contact_onset(double /*t*/, int /*contact*/, double /*impact_speed*/) {}
  /// Wear (scenes with a wear model, when wants_wear() is true): the sliding power and where
  /// it acts at one node of a 3-point Gauss-Legendre rule over every accepted step, on the
  /// step's interpolant, with the node's weight [s]. Steps that are discarded (the step that
  /// crossed a contact onset, re-taken up to it) deposit nothing.
  virtual void on_wear(const WearSource& /*source*/, double /*weight*/) {}
  virtual bool wants_wear() const { return false; }
};

/// Checks settings; throws InputError with a key path under "integrator." or "time.".
void validate(const IntegratorSettings& s);
void validate(const TimeSettings& s);
/// Why a run of `t.end` cannot finish within the step budget of `s` even at its largest step
/// (empty when it can): such a run ends at t = 0 as step_budget_exhausted, at once.
std::string budget_shortfall(const IntegratorSettings& s, const TimeSettings& t);
/// Checks health limits; throws InputError with a key path under "health.".
void validate(const HealthLimits& h);

/// Runs `scene` from its initial state to `time.end`. Never throws for numerical trouble: a
/// failed run returns its status, a message and the time reached. An exception thrown while it
/// runs (by the scene, the observer or a library) ends the run as internal_error, with the
/// exception's message and the time reached.
RunResult simulate(const Scene& scene, const IntegratorSettings& settings, const TimeSettings& time,
                   RunObserver& observer, const HealthLimits& health = {});

}  // namespace rodend
