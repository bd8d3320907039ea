// The driver's contact-onset stage: the contacts' gaps at step ends (remembered), and the
// latches of the discrete state, changed only between steps: at the end of an accepted step,
// or at an event a step was re-taken up to.
#include <algorithm>
#include <cstring>

#include "core/driver/run.hpp"

namespace rodend::detail {

ContactGap gap_at(Run& run, int c, const state_t& z) {
  run.model.unscale(z, run.state.x);
  return run.model.scene.contact_gap(c, run.state.x.data());
}

/// gap_at for a step end (z_now, or z_prev: the previous step's end), remembered for the two
/// last such states: the health check, the event search and the latching read the gaps at a
/// step's end, and the next step's event search at its start. A gap is a function of the
/// state alone; a state is recognised by its bits (a renormalised or re-taken state is
/// another). May leave state.x unchanged or holding z unscaled.
ContactGap end_gap(Run& run, int c, const state_t& z) {
  RunState& s = run.state;
  const std::size_t n = run.model.n;
  auto holds = [&](const GapMemo& e) {
    return e.valid && std::memcmp(e.z.data(), z.data(), n * sizeof(double)) == 0;
  };
  GapMemo* m = &s.gap_memo[s.gap_memo_last];  // the one used last first
  if (!holds(*m)) m = &s.gap_memo[1 - s.gap_memo_last];
  if (!holds(*m)) {  // the one used less recently takes the new state
    m->z = z;
    m->valid = true;
    std::fill(m->known.begin(), m->known.end(), 0);
  }
  s.gap_memo_last = static_cast<int>(m - s.gap_memo);
  const auto i = static_cast<std::size_t>(c);
  if (!m->known[i]) {
    m->gaps[i] = gap_at(run, c, z);
    m->known[i] = 1;
  }
  return m->gaps[i];
}

/// Latches contact c's episode at time t with the approach speed delta'^- of gap g.
void latch(Run& run, int c, const ContactGap& g, double t) {
  RunState& s = run.state;
  ContactLatch& l = s.discrete.contacts[static_cast<std::size_t>(c)];
  l.in_contact = true;
  l.impact_speed = std::max(g.penetration_rate, 0.0);
  l.slipping = g.slipping == 1;  // friction.mode stick-slip: the branch its slip speed calls for
  ++s.stats.contact_onsets;
  run.obs.on_contact_onset(t, c, l.impact_speed);
  s.ends[static_cast<std::size_t>(c)].valid = false;  // its force changes law
  s.touched[static_cast<std::size_t>(c)] = 0;
}

namespace {

/// Ends contact c's episode (its force changes law).
void unlatch(RunState& s, int c) {
  s.discrete.contacts[static_cast<std::size_t>(c)] = ContactLatch{};  // episode over
  s.ends[static_cast<std::size_t>(c)].valid = false;
}

/// The branch a latched contact in contact takes at a step end: the one its slip speed calls
/// for (g.slipping); in friction.mode switch, a slipping contact sticks only if the force that
/// holds it is within the static limit too (Scene::stick_demand, evaluated only then).
bool slips(Run& run, int c, const ContactGap& g, const ContactLatch& l) {
  if (!g.stick || !l.slipping || g.slipping == 1) return g.slipping == 1;
  run.model.unscale(run.stepper().z_now, run.state.x);
  return run.model.scene.stick_demand(c, run.stepper().t_now, run.state.x.data(),
                                      run.state.discrete) > 1.0;
}

}  // namespace

/// Discrete updates at the end of an accepted step: an episode ends once its contact is out
/// of contact (unless latched a hair before touching and still approaching), a contact that
/// penetrates unlatched starts one (step-end latching, or an onset at a restart point), and a
/// contact in friction.mode stick-slip takes the branch its slip speed calls for (stuck to
/// slipping above the switch speed, back below it; in switch, back only if the force that holds
/// it is within the static limit). Returns whether an onset was latched or a
/// branch switched (the method restarts with the new force law).
bool latch_at_step_end(Run& run) {
  RunState& s = run.state;
  bool onset = false;
  for (int c = 0; c < run.model.scene.contact_count(); ++c) {
    const ContactGap g = end_gap(run, c, run.stepper().z_now);
    char& touched = s.touched[static_cast<std::size_t>(c)];
    if (latched(run, c) && g.penetration <= 0.0 && (touched || !(g.penetration_rate > 0.0))) {
      unlatch(s, c);
    } else if (!latched(run, c) && g.penetration > 0.0) {
      latch(run, c, g, run.stepper().t_now);
      onset = true;
    } else if (latched(run, c) && g.penetration > 0.0) {
      touched = 1;
      ContactLatch& l = s.discrete.contacts[static_cast<std::size_t>(c)];
      if (g.slipping >= 0 && slips(run, c, g, l) != l.slipping) {
        l.slipping = !l.slipping;
        ++s.stats.friction_switches;
        onset = true;
      }
    }
  }
  run.model.unscale(run.stepper().z_now, s.x);  // for observe_step
  return onset;
}

/// The latches at the end of a re-take: every contact penetrating there starts its episode;
/// an event's contact that is still approaching starts it too (the re-taken state may end a
/// hair short of the interpolant's onset), and one that is out of contact ends it. Returns
/// whether a latch changed (if not, the next step latches at its end instead: relocating
/// again and again could creep towards an onset without ever getting there).
bool latch_at_event(Run& run, const std::vector<int>& event_contacts, bool from_method) {
  RunState& s = run.state;
  bool changed = false;
  for (int c = 0; c < run.model.scene.contact_count(); ++c) {
    const ContactGap g = end_gap(run, c, run.stepper().z_now);
    const bool event =
        std::find(event_contacts.begin(), event_contacts.end(), c) != event_contacts.end();
    if (!latched(run, c) &&
        (g.penetration > 0.0 || (event && (from_method || g.penetration_rate > 0.0)))) {
      latch(run, c, g, run.stepper().t_now);
      changed = true;
    } else if (latched(run, c) && event) {
      char& touched = s.touched[static_cast<std::size_t>(c)];
      if (g.penetration <= 0.0) {
        unlatch(s, c);
        changed = true;
      } else if (!touched) {
        changed = true;  // an episode split at its deepest point
      }
      // else: a separation the re-taken step does not reproduce (a grazing contact, a
      // rounding error above zero) is no change, so the next step is accepted without
      // locating (locate_suspended). Reporting one re-took the same event 2.6e-15 s later,
      // 2e7 times (gravity-drop at rest on the wall, restitution 0.136: tests/test_events.cpp)
      touched = 1;
    }
  }
  return changed;
}

}  // namespace rodend::detail
