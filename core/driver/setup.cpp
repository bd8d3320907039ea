// The driver's first and last stages: the run's model (state scaling, the signals to check,
// what the scene has), its state, the start (initial state, latches, stepper, first sample),
// and the result assembled at the end.
#include <algorithm>
#include <cmath>

#include "core/driver/run.hpp"

namespace rodend::detail {
namespace {

/// The frame offsets of the components of `ids`.
std::vector<int> slots_of(const std::vector<SignalId>& ids) {
  std::vector<int> slots;
  for (SignalId id : ids)
    for (int k = 0; k < signal_spec(id).width; ++k) slots.push_back(signal_offset(id) + k);
  return slots;
}

}  // namespace

RunModel::RunModel(const Scene& sc, const IntegratorSettings& s, const TimeSettings& t,
                   const HealthLimits& h, bool observer_wants_wear)
    : scene(sc),
      settings(s),
      time(t),
      health(h),
      n(static_cast<std::size_t>(sc.state_size())),
      scale(n) {
  scene.state_scale(scale.data());
  // bookkeeping integrals: scaled so that they never limit the step size
  for (int o : scene.audit_offsets()) scale[static_cast<std::size_t>(o)] *= 1e12;
  const auto sig = scene.signals();
  auto provides = [&](SignalId id) { return std::find(sig.begin(), sig.end(), id) != sig.end(); };
  const Features features = scene.features();
  provides_force = features.has(Feature::contact);
  checks_energy = features.has(Feature::energy_audit);
  has_kinetic = provides(SignalId::kinetic_energy);  // a term of the audit's scale, if written
  checks_tracking = features.has(Feature::actuator);
  signals.assign(sig.begin(), sig.end());
  for (SignalId id : kStepSignals)
    if (provides(id)) step_signals.push_back(id);
  signal_slots = slots_of(signals);
  step_slots = slots_of(step_signals);
  wears = scene.wear_model() != nullptr && observer_wants_wear;
  n_samples = static_cast<long long>(std::floor(time.end / time.sample_interval + 1e-9)) + 1;
}

RunState::RunState(const RunModel& m)
    : sys(m.scene, discrete, m.scale, m.settings.max_rhs_calls), x(m.n), z_tmp(m.n) {
  sys.watch = &watch;
  const auto contacts = static_cast<std::size_t>(m.scene.contact_count());
  discrete.contacts.assign(contacts, ContactLatch{});
  for (GapMemo& g : gap_memo) {
    g.gaps.resize(contacts);
    g.known.resize(contacts);
  }
  ends.assign(contacts, ContactEnd{});
  touched.assign(contacts, 0);
}

/// The initial state (an initial penetration starts latched, with its current approach speed),
/// the stepper, the sample at t = 0, and the check that the step budget can reach the end.
void start(Run& run) {
  const RunModel& m = run.model;
  RunState& s = run.state;
  state_t z0(m.n);
  m.scene.initial_state(s.x.data());
  for (std::size_t i = 0; i < m.n; ++i) z0[i] = s.x[i] / m.scale[i];
  for (int c = 0; c < m.scene.contact_count(); ++c)
    if (const ContactGap g = m.scene.contact_gap(c, s.x.data()); g.penetration > 0.0)
      latch(run, c, g, 0.0);
  s.stepper = make_stepper(s.sys, m.scene, m.settings);
  s.stepper->reset(z0, 0.0, m.settings.step);
  emit_sample(run, 0, z0);
  s.next_sample = 1;
  if (const std::string msg = budget_shortfall(m.settings, m.time); !msg.empty())
    throw RunFailure{RunStatus::step_budget_exhausted, msg};
}

/// The counts and the final state (unscaled) of a run that ended, whatever its status.
void assemble_result(Run& run, RunResult& result) {
  RunState& s = run.state;
  s.stats.rhs_calls = s.sys.calls;
  if (s.stepper) {
    s.stats.steps_accepted = s.stepper->accepted;
    s.stats.steps_rejected = s.stepper->rejected;
    if (all_finite(s.stepper->z_now)) {
      result.final_state.resize(run.model.n);
      for (std::size_t i = 0; i < run.model.n; ++i)
        result.final_state[i] = s.stepper->z_now[i] * run.model.scale[i];
    }
  }
  result.stats = s.stats;
}

}  // namespace rodend::detail
