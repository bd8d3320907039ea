// Internal to core: the integration driver's model, state and stages. `simulate`
// (core/integrator.cpp) runs them in this order, one file each under core/driver/:
//   setup.cpp     the RunModel (state scaling, the signals to check, what the scene has), the
//                 RunState; start: initial state and latches, the stepper, the first sample
//   step.cpp      take_step: one step of the method; the checks after every step (finite
//                 state, step budget, penetration)
//   events.cpp    find_event: the earliest contact change inside the step (the method's roots,
//                 or located on its interpolant), if any ...
//   retake.cpp    ... then retake_to: the step re-taken up to the event, the latches changed
//   accept.cpp    otherwise accept_step, in order:
//     sampling.cpp      the samples inside the step (full frames), each checked by
//     audit.cpp         the energy audit and the actuator's tracking,
//     wear_deposit.cpp  the wear sources of the step,
//     peaks.cpp         the contacts' force and penetration maxima inside the step,
//     latches.cpp       contact onset and separation at the step end (also at an event),
//                       then the step's lean frame and quaternion renormalisation
//   setup.cpp     assemble_result: status, message, counts and the final state
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "core/integrator.hpp"
#include "core/stepper.hpp"

namespace rodend::detail {

/// What a run is given and what follows from it once (setup): only read while it runs.
struct RunModel {
  RunModel(const Scene& scene, const IntegratorSettings& s, const TimeSettings& time,
           const HealthLimits& health, bool observer_wants_wear);
  const Scene& scene;
  const IntegratorSettings& settings;
  const TimeSettings& time;
  const HealthLimits& health;
  std::size_t n;  ///< state size
  state_t scale;  ///< x = z * scale
  bool provides_force = false;
  bool checks_energy = false, checks_tracking = false, has_kinetic = false;
  bool wears = false;             ///< deposit wear (the scene models it and the observer wants it)
  std::vector<SignalId> signals;  ///< the scene's signals (checked finite in every frame)
  std::vector<SignalId> step_signals;         ///< those of kStepSignals (checked in step frames)
  std::vector<int> signal_slots, step_slots;  ///< their frame offsets (check_frame_finite)
  long long n_samples = 0;

  double sample_time(long long k) const {
    return std::min(static_cast<double>(k) * time.sample_interval, time.end);
  }
  void unscale(const state_t& z, state_t& x) const {
    for (std::size_t i = 0; i < n; ++i) x[i] = z[i] * scale[i];
  }
};

/// Contact gaps at the last two step-end states (end_gap).
struct GapMemo {
  state_t z;  ///< the scaled state
  std::vector<ContactGap> gaps;
  std::vector<char> known;  ///< per contact: gaps[c] is computed
  bool valid = false;
};

/// A contact at the end of the last accepted step (locate_contact_peaks).
struct ContactEnd {
  double t = 0.0;
  bool valid = false;
  ContactSnapshot at;
  double force_slope = 0.0;  ///< d F_n / dt there [N/s] (one-sided difference)
  bool force_slope_known = false;
};

/// What changes while a run runs: the discrete state, the stepper, the counts, the memories of
/// the stages and their scratch. Holds references into itself (sys): neither copied nor moved.
struct RunState {
  explicit RunState(const RunModel& m);
  RunState(const RunState&) = delete;
  RunState& operator=(const RunState&) = delete;

  DiscreteState discrete;
  ScaledSystem sys;
  StageWatch watch;  ///< the stages' earliest onset in the step (sys.watch)
  std::unique_ptr<Stepper> stepper;
  SignalFrame frame;
  state_t x, z_tmp;  ///< scratch: an unscaled state, a scaled one
  long long next_sample = 0;
  RunStats stats;
  GapMemo gap_memo[2];
  int gap_memo_last = 0;  ///< the entry used last
  std::vector<ContactEnd> ends;
  double max_energy_flow = 0.0;  ///< largest |input work|, |dissipated|, kinetic at samples [J]
  double tracking_since = -1.0;  ///< first sample of the current tracking excess [s], or -1
  /// per contact: its episode has been in contact at a step end after the one that latched it
  /// (until then, it is not over while it approaches: it may be latched a hair before touching)
  std::vector<char> touched;
  bool locate_suspended = false;  ///< latch the next onset at the step end (see retake_to)
};

/// A run: its model, its state and the observer it reports to.
struct Run {
  Run(const RunModel& m, RunObserver& o) : model(m), obs(o), state(m) {}
  const RunModel& model;
  RunObserver& obs;
  RunState state;
  Stepper& stepper() { return *state.stepper; }
};

/// An event of the last step: the earliest time in (t_prev, t_now] at which a contact changes
/// state (onset of an unlatched one, separation of a latched one), and which (none: no event).
struct Event {
  double t = 0.0;
  std::vector<int> contacts;
  bool from_method = false;  ///< found by the method's own root finding (CVODE)
  /// a stage of the method felt an onset at t that its solution does not show: the step was
  /// too long for the contact's stiffness (its stages left the solution), re-taken up to t
  bool stage_only = false;
  bool any() const { return !contacts.empty() || stage_only; }
};

// setup (core/driver/setup.cpp)
void start(Run& run);
void assemble_result(Run& run, RunResult& result);

// step (core/driver/step.cpp) and the checks at every sample (core/driver/audit.cpp)
void take_step(Run& run);
void check_health_after_step(Run& run);
void check_health_at_sample(Run& run, double t);

// events (core/driver/events.cpp, core/driver/retake.cpp)
Event find_event(Run& run);
void retake_to(Run& run, const Event& ev);

// accept (core/driver/accept.cpp)
void accept_step(Run& run);

// sampling (core/driver/sampling.cpp)
void emit_sample(Run& run, long long k, const state_t& z);
void emit_samples_until(Run& run, double t_to);
void check_frame_finite(Run& run, double t, const std::vector<SignalId>& which,
                        const std::vector<int>& slots);
void observe_step(Run& run);

// latches (core/driver/latches.cpp)
ContactGap gap_at(Run& run, int c, const state_t& z);
ContactGap end_gap(Run& run, int c, const state_t& z);
inline bool latched(const Run& run, int c) {
  return run.state.discrete.contacts[static_cast<std::size_t>(c)].in_contact;
}
void latch(Run& run, int c, const ContactGap& g, double t);
bool latch_at_step_end(Run& run);
bool latch_at_event(Run& run, const std::vector<int>& event_contacts, bool from_method);

// wear (core/driver/wear_deposit.cpp)
void deposit_wear(Run& run);

// contact peaks (core/driver/peaks.cpp)
void locate_contact_peaks(Run& run);

}  // namespace rodend::detail
