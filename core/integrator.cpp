#include "core/integrator.hpp"

#include "core/stepper.hpp"

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <new>
#include <sstream>
#include <utility>

namespace rodend {
namespace odeint = boost::numeric::odeint;
using detail::all_finite;
using detail::RunFailure;
using detail::ScaledSystem;
using detail::state_t;
using detail::Stepper;

bool fixed_step(IntegratorMethod m) {
  static constexpr bool kFixed[] = {
#define RODEND_CHOICE(identifier, name, description, fixed_step) fixed_step,
#include "core/integrator_methods.def"
#undef RODEND_CHOICE
  };
  return kFixed[static_cast<std::size_t>(m)];
}

void validate(const IntegratorSettings& s) {
  // the method and the onset mode are enums: read from their names by the loader
  auto positive = [](double v, const char* key) {
    if (!(v > 0.0) || !std::isfinite(v)) throw InputError(key, "expected a finite number > 0");
  };
  positive(s.abs_tol, "integrator.abs_tol");
  positive(s.rel_tol, "integrator.rel_tol");
  positive(s.step, "integrator.step");
  positive(s.max_step, "integrator.max_step");
  positive(s.min_step, "integrator.min_step");
  if (s.min_step > s.max_step)
    throw InputError("integrator.min_step",
                     "larger than integrator.max_step; expected min_step <= max_step");
  if (s.max_steps <= 0) throw InputError("integrator.max_steps", "expected an integer > 0");
  if (s.max_rhs_calls <= 0) throw InputError("integrator.max_rhs_calls", "expected an integer > 0");
}

void validate(const TimeSettings& s) {
  auto got = [](double v) {
    std::ostringstream o;
    o << v;
    return o.str();
  };
  if (!(s.end > 0.0) || !std::isfinite(s.end))
    throw InputError("time.end", "expected an end time > 0 [s], got " + got(s.end));
  if (!(s.sample_interval > 0.0) || !std::isfinite(s.sample_interval))
    throw InputError("time.sample_interval",
                     "expected a sample interval > 0 [s], got " + got(s.sample_interval));
  if (s.sample_interval > s.end)
    throw InputError("time.sample_interval",
                     "longer than time.end (" + got(s.end) +
                         " s): only t = 0 would be recorded; expected a sample interval <= the "
                         "end time");
  if (s.end / s.sample_interval > 5e7)
    throw InputError("time.sample_interval",
                     "more than 5e7 samples requested; expected a larger sample interval");
}

std::string budget_shortfall(const IntegratorSettings& s, const TimeSettings& t) {
  // the fewest steps the run can take: a runaway end time ends at once, instead of running into
  // the step budget after minutes
  const bool fixed = fixed_step(s.method);
  const double largest = fixed ? s.step : s.max_step;
  const double fewest = t.end / largest;
  if (!(fewest > static_cast<double>(s.max_steps))) return {};
  std::ostringstream m;
  m << "step budget of " << s.max_steps << " steps exhausted at t = 0 s, before the first step: "
    << "reaching time.end = " << t.end << " s at "
    << (fixed ? "integrator.step" : "most integrator.max_step") << " = " << largest
    << " s takes at least " << fewest << " steps";
  return m.str();
}

void validate(const HealthLimits& h) {
  auto check = [](double v, bool zero_ok, const char* key, const char* what) {
    if (!std::isfinite(v) || (zero_ok ? !(v >= 0.0) : !(v > 0.0)))
      throw InputError(key, std::string("expected a finite ") + what);
  };
  check(h.max_penetration_strain, false, "health.max_penetration_strain", "fraction > 0");
  check(h.max_penetration_fraction, true, "health.max_penetration_fraction",
        "fraction >= 0 (0: no limit)");
  check(h.max_energy_residual, false, "health.max_energy_residual", "fraction > 0");
  check(h.energy_flow_floor, true, "health.energy_flow_floor", "energy >= 0 [J]");
  check(h.max_tracking_error, false, "health.max_tracking_error", "length > 0 [m]");
  check(h.tracking_window, true, "health.tracking_window", "time >= 0 [s]");
}

namespace {

/// The run: owns the stepper, the discrete state and the sampling clock.
class Driver {
 public:
  Driver(const Scene& scene, const IntegratorSettings& s, const TimeSettings& time,
         RunObserver& obs, const HealthLimits& health)
      : scene_(scene),
        settings_(s),
        time_(time),
        obs_(obs),
        health_(health),
        n_(static_cast<std::size_t>(scene.state_size())),
        scale_(n_),
        sys_(scene, discrete_, scale_, s.max_rhs_calls),
        x_(n_),
        z_tmp_(n_) {
    sys_.watch = &watch_;
    scene.state_scale(scale_.data());
    // bookkeeping integrals: scaled so that they never limit the step size
    for (int o : scene.audit_offsets()) scale_[static_cast<std::size_t>(o)] *= 1e12;
    discrete_.contacts.assign(static_cast<std::size_t>(scene.contact_count()), ContactLatch{});
    const auto sig = scene.signals();
    auto provides = [&](SignalId id) { return std::find(sig.begin(), sig.end(), id) != sig.end(); };
    const Features features = scene.features();
    provides_force_ = features.has(Feature::contact);
    checks_energy_ = features.has(Feature::energy_audit);
    has_kinetic_ = provides(SignalId::kinetic_energy);  // a term of the audit's scale, if written
    checks_tracking_ = features.has(Feature::actuator);
    signals_.assign(sig.begin(), sig.end());
    for (SignalId id : kStepSignals)
      if (provides(id)) step_signals_.push_back(id);
    signal_slots_ = slots_of(signals_);
    step_slots_ = slots_of(step_signals_);
    for (GapMemo& m : gap_memo_) {
      m.gaps.resize(static_cast<std::size_t>(scene.contact_count()));
      m.known.resize(m.gaps.size());
    }
    ends_.assign(static_cast<std::size_t>(scene.contact_count()), ContactEnd{});
    touched_.assign(ends_.size(), 0);
    wears_ = scene.wear_model() != nullptr && obs.wants_wear();
    n_samples_ = static_cast<long long>(std::floor(time.end / time.sample_interval + 1e-9)) + 1;
  }

  RunResult run() {
    RunResult result;
    try {
      state_t z0(n_);
      scene_.initial_state(x_.data());
      for (std::size_t i = 0; i < n_; ++i) z0[i] = x_[i] / scale_[i];
      // an initial penetration starts latched, with its current approach speed
      for (int c = 0; c < scene_.contact_count(); ++c)
        if (const ContactGap g = scene_.contact_gap(c, x_.data()); g.penetration > 0.0)
          latch(c, g, 0.0);
      stepper_ = detail::make_stepper(sys_, scene_, settings_);
      stepper_->reset(z0, 0.0, settings_.step);
      emit_sample(0, z0);
      next_sample_ = 1;
      if (const std::string m = budget_shortfall(settings_, time_); !m.empty())
        throw RunFailure{RunStatus::step_budget_exhausted, m};
      loop();
    } catch (const RunFailure& f) {
      result.status = f.status;
      result.message = f.message;
    } catch (const odeint::step_adjustment_error& e) {
      result.status = RunStatus::step_size_underflow;
      result.message = std::string("step size underflow: ") + e.what();
    } catch (const std::bad_alloc&) {
      throw;  // out of memory: the environment's failure, not the case's (the runner stops)
    } catch (const std::exception& e) {
      // not a numerical failure: a bug
      std::ostringstream m;
      m << "internal error after t = " << stats_.t_reached << " s: " << e.what();
      result.status = RunStatus::internal_error;
      result.message = m.str();
    }
    stats_.rhs_calls = sys_.calls;
    if (stepper_) {
      stats_.steps_accepted = stepper_->accepted;
      stats_.steps_rejected = stepper_->rejected;
      if (all_finite(stepper_->z_now)) {
        result.final_state.resize(n_);
        for (std::size_t i = 0; i < n_; ++i) result.final_state[i] = stepper_->z_now[i] * scale_[i];
      }
    }
    result.stats = stats_;
    return result;
  }

 private:
  double sample_time(long long k) const {
    return std::min(static_cast<double>(k) * time_.sample_interval, time_.end);
  }

  void unscale(const state_t& z, state_t& x) const {
    for (std::size_t i = 0; i < n_; ++i) x[i] = z[i] * scale_[i];
  }

  void emit_sample(long long k, const state_t& z) {
    unscale(z, x_);
    const double t = sample_time(k);
    frame_.set(SignalId::time, t);
    scene_.outputs(t, x_.data(), discrete_, frame_);
    check_frame_finite(t);
    obs_.on_sample(frame_);
    check_health_at_sample(t);
  }

  /// The frame offsets of the components of `ids`.
  static std::vector<int> slots_of(const std::vector<SignalId>& ids) {
    std::vector<int> slots;
    for (SignalId id : ids)
      for (int k = 0; k < signal_spec(id).width; ++k) slots.push_back(signal_offset(id) + k);
    return slots;
  }

  /// A frame with a non-finite value among `which` (the scene's signals, or those of a step
  /// frame; `slots` their offsets) never reaches the observer: the run ends there. One pass over
  /// those values first (no per-signal lookups, not the whole catalogue's width); only a frame
  /// with a non-finite entry is looked at signal by signal.
  void check_frame_finite(double t) { check_frame_finite(t, signals_, signal_slots_); }
  void check_frame_finite(double t, const std::vector<SignalId>& which,
                          const std::vector<int>& slots) {
    if (frame_.all_finite(slots)) return;
    for (SignalId id : which)
      for (int k = 0; k < signal_spec(id).width; ++k)
        if (!std::isfinite(frame_.get(id, k))) {
          std::ostringstream m;
          m << "non-finite signal " << signal_spec(id).name << " at t = " << t << " s";
          throw RunFailure{RunStatus::non_finite_state, m.str()};
        }
  }

  /// Health checks on the sample frame just emitted (energy audit, actuator tracking).
  void check_health_at_sample(double t) {
    if (checks_energy_) {
      const double r = frame_.get(SignalId::energy_residual);
      // the energy scale: what crossed the boundary (input work, dissipation) and what moves
      // inside it (kinetic energy: a falling ball's or a conservative run's exchanges)
      max_energy_flow_ =
          std::max(max_energy_flow_,
                   energy_audit_scale(frame_.get(SignalId::input_work),
                                      frame_.get(SignalId::dissipated_energy),
                                      has_kinetic_ ? frame_.get(SignalId::kinetic_energy) : 0.0));
      if (max_energy_flow_ > health_.energy_flow_floor &&
          std::abs(r) > health_.max_energy_residual * max_energy_flow_) {
        std::ostringstream m;
        m << "energy-audit residual " << std::abs(r) / max_energy_flow_
          << " x the largest energy flow or kinetic energy (" << max_energy_flow_
          << " J) exceeds the limit " << health_.max_energy_residual << " at t = " << t << " s";
        stats_.t_reached = t;
        throw RunFailure{RunStatus::energy_residual_limit, m.str()};
      }
    }
    if (checks_tracking_) {
      const double e = std::abs(frame_.get(SignalId::actuator_command) -
                                frame_.get(SignalId::actuator_position));
      if (!(e > health_.max_tracking_error)) {
        tracking_since_ = -1.0;
      } else if (tracking_since_ < 0.0) {
        tracking_since_ = t;
      }
      if (tracking_since_ >= 0.0 && t - tracking_since_ > health_.tracking_window) {
        std::ostringstream m;
        m << "actuator cannot follow its command: |command - position| = " << e
          << " m, above max_tracking_error " << health_.max_tracking_error
          << " m since t = " << tracking_since_ << " s (longer than tracking_window "
          << health_.tracking_window << " s) at t = " << t << " s";
        stats_.t_reached = t;
        throw RunFailure{RunStatus::actuator_saturation, m.str()};
      }
    }
  }

  /// Emits every sample in (t_from, t_to] from the stepper's interpolant.
  void emit_samples_until(double t_to) {
    while (next_sample_ < n_samples_ && sample_time(next_sample_) <= t_to * (1 + 1e-15)) {
      const double ts = sample_time(next_sample_);
      if (ts >= stepper_->t_now)
        z_tmp_ = stepper_->z_now;
      else
        stepper_->interpolate(ts, z_tmp_);
      emit_sample(next_sample_, z_tmp_);
      ++next_sample_;
    }
  }

  ContactGap gap_at(int c, const state_t& z) {
    unscale(z, x_);
    return scene_.contact_gap(c, x_.data());
  }

  /// gap_at for a step end (z_now, or z_prev: the previous step's end), remembered for the two
  /// last such states: the health check, the event search and the latching read the gaps at a
  /// step's end, and the next step's event search at its start. A gap is a function of the
  /// state alone; a state is recognised by its bits (a renormalised or re-taken state is
  /// another). May leave x_ unchanged or holding z unscaled.
  ContactGap end_gap(int c, const state_t& z) {
    auto holds = [&](const GapMemo& e) {
      return e.valid && std::memcmp(e.z.data(), z.data(), n_ * sizeof(double)) == 0;
    };
    GapMemo* m = &gap_memo_[gap_memo_last_];  // the one used last first
    if (!holds(*m)) m = &gap_memo_[1 - gap_memo_last_];
    if (!holds(*m)) {  // the one used less recently takes the new state
      m->z = z;
      m->valid = true;
      std::fill(m->known.begin(), m->known.end(), 0);
    }
    gap_memo_last_ = static_cast<int>(m - gap_memo_);
    const auto i = static_cast<std::size_t>(c);
    if (!m->known[i]) {
      m->gaps[i] = gap_at(c, z);
      m->known[i] = 1;
    }
    return m->gaps[i];
  }

  bool latched(int c) const { return discrete_.contacts[static_cast<std::size_t>(c)].in_contact; }

  /// Latches contact c's episode at time t with the approach speed delta'^- of gap g.
  void latch(int c, const ContactGap& g, double t) {
    ContactLatch& l = discrete_.contacts[static_cast<std::size_t>(c)];
    l.in_contact = true;
    l.impact_speed = std::max(g.penetration_rate, 0.0);
    l.slipping = g.slipping == 1;  // friction.mode stick-slip: the branch its slip speed calls for
    ++stats_.contact_onsets;
    obs_.on_contact_onset(t, c, l.impact_speed);
    ends_[static_cast<std::size_t>(c)].valid = false;  // its force changes law
    touched_[static_cast<std::size_t>(c)] = 0;
  }

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

  /// Whether contact c, at t on the last step's interpolant, is in the other state than its
  /// latch: penetrating while unlatched, or out of contact while latched.
  bool changed_at(int c, double t) {
    stepper_->interpolate(t, z_tmp_);
    const double p = gap_at(c, z_tmp_).penetration;
    return latched(c) ? p <= 0.0 : p > 0.0;
  }

  /// The cubic Hermite model of a penetration over a step, from its values p0, p1 and scaled
  /// rates m0 = h p'0, m1 = h p'1 at the two ends (exact for a free flight: a quadratic):
  /// p(s) = (2s^3 - 3s^2 + 1) p0 + (s^3 - 2s^2 + s) m0 + (3s^2 - 2s^3) p1 + (s^3 - s^2) m1,
  /// s in [0, 1]. Returns where inside the step it is largest (onset: `above` true; positive
  /// there) or smallest (separation; <= 0 there), or -1 when it does not get there.
  static double hermite_crossing(double p0, double m0, double p1, double m1, bool above) {
    auto p = [&](double s) {
      const double s2 = s * s, s3 = s2 * s;
      return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (3 * s2 - 2 * s3) * p1 +
             (s3 - s2) * m1;
    };
    // p'(s) = a s^2 + b s + c
    const double a = 6 * p0 + 3 * m0 - 6 * p1 + 3 * m1, b = -6 * p0 - 4 * m0 + 6 * p1 - 2 * m1;
    const double c = m0;
    double roots[2] = {-1.0, -1.0};
    if (std::abs(a) < 1e-14 * (std::abs(b) + std::abs(c))) {
      if (b != 0.0) roots[0] = -c / b;
    } else if (const double d = b * b - 4 * a * c; d >= 0.0) {
      const double q = -0.5 * (b + std::copysign(std::sqrt(d), b));  // no cancellation
      roots[0] = q / a;
      if (q != 0.0) roots[1] = c / q;
    }
    double best = -1.0;
    for (double s : roots)
      if (s > 0.0 && s < 1.0 && (above ? p(s) > 0.0 : p(s) <= 0.0) &&
          (best < 0.0 || (above ? p(s) > p(best) : p(s) < p(best))))
        best = s;
    return best;
  }

  /// The earliest time in (t_prev, t_now] at which contact c changes state on the step's
  /// interpolant, or +inf. A change at the step end is bracketed by the step; a change inside
  /// it with neither end changed (an impact stepped over, or a separation followed by a new
  /// onset) by the Hermite model's extremum, confirmed on the interpolant; then bisection.
  double change_time(int c) {
    const bool in = latched(c);
    const ContactGap g0 = end_gap(c, stepper_->z_prev), g1 = end_gap(c, stepper_->z_now);
    if (in && !touched_[static_cast<std::size_t>(c)] && g1.penetration_rate < 0.0)
      return deepest_time(c);
    auto changed = [in](double p) { return in ? p <= 0.0 : p > 0.0; };
    constexpr double none = std::numeric_limits<double>::infinity();
    if (changed(g0.penetration)) return none;  // at a restart point: latched at the step end
    const double t0 = stepper_->t_prev, h = stepper_->t_now - t0;
    double hi = stepper_->t_now;
    if (changed(g1.penetration)) {
      if (in) return none;  // a separation at the step end is latched there (accept_step)
    } else {
      // candidates: the Hermite model's extremum, and (onsets) the earliest stage that felt one
      const double s = hermite_crossing(g0.penetration, h * g0.penetration_rate, g1.penetration,
                                        h * g1.penetration_rate, !in);
      const double t_stage = in ? none : watch_.earliest;
      hi = none;
      for (double t : {s >= 0.0 ? t0 + s * h : none, t_stage})
        if (hi == none && t > t0 && t < stepper_->t_now && changed_at(c, t)) hi = t;
      if (hi == none) return none;  // the method's own solution does not change
    }
    double lo = t0;
    // 60 halvings reach the resolution of double time for any step length
    for (int it = 0; it < 60 && hi - lo > 4e-16 * std::max(1.0, std::abs(hi)); ++it) {
      const double mid = 0.5 * (lo + hi);
      (changed_at(c, mid) ? hi : lo) = mid;  // the method itself: consistent with the re-take
    }
    return hi;
  }

  /// Where contact c penetrates deepest in the last step, on its interpolant (+inf if it does
  /// not penetrate): the first step of an episode that went past its deepest point (or through
  /// the whole episode) is split there, so that every impact has a step end at its peak. An
  /// error estimate from nodes at the step ends alone (Fehlberg 7(8): err ~ k1 + k11 - k12 -
  /// k13, nodes at 0, 1, 0, 1) does not see an impact between them.
  double deepest_time(int c) {
    const double t0 = stepper_->t_prev, t1 = stepper_->t_now;
    double p_max = 0.0;
    const double t = argmax(
        t0, t1, 1e-3 * (t1 - t0),
        [&](double tt) {
          stepper_->interpolate(tt, z_tmp_);
          return gap_at(c, z_tmp_).penetration;
        },
        p_max);
    return p_max > 0.0 && t < t1 ? t : std::numeric_limits<double>::infinity();
  }

  /// The event of the last step: the roots the method found itself (CVODE), else the earliest
  /// contact change located on the step (integrator.contact_onset "locate"); t = t_now if none.
  Event find_event() {
    Event ev;
    ev.t = stepper_->t_now;
    if (stepper_->finds_roots() && !stepper_->roots.empty()) {
      ev.contacts = stepper_->roots;
      ev.from_method = true;
      return ev;
    }
    if (settings_.contact_onset != ContactOnset::locate || std::exchange(locate_suspended_, false))
      return ev;
    for (int c = 0; c < scene_.contact_count(); ++c) {
      const double t = change_time(c);
      if (t < ev.t) ev.contacts.clear();
      if (t <= ev.t && t < stepper_->t_now) {
        ev.t = t;
        ev.contacts.push_back(c);
      }
    }
    if (ev.contacts.empty() && watch_.earliest > stepper_->t_prev &&
        watch_.earliest < stepper_->t_now) {
      ev.t = watch_.earliest;
      ev.stage_only = true;
    }
    return ev;
  }

  /// Re-takes the last step from its start up to the event and changes the latches there: the
  /// discarded step's later stages felt the far side of the event (the contact force, or its
  /// absence), and its interpolant would carry that into the samples before the event and into
  /// the restart state. The impact speed is latched at the event, the exact onset.
  void retake_to(const Event& ev) {
    const double dt_before = stepper_->suggested_dt();
    const state_t z_start = stepper_->z_prev;
    const double t_start = stepper_->t_prev;
    stepper_->reset(z_start, t_start, ev.t - t_start);
    std::vector<int> found = ev.contacts;
    while (stepper_->t_now < ev.t) {
      stepper_->step(ev.t);
      check_health_after_step();
      emit_samples_until(stepper_->t_now);
      deposit_wear();
      // the method found a root a hair before ev.t (a grazing approach): latch there; stepping
      // on from a root without re-initialising is CVODE's CV_ILL_INPUT ("root found at and
      // very near t")
      if (stepper_->finds_roots() && !stepper_->roots.empty()) {
        found.insert(found.end(), stepper_->roots.begin(), stepper_->roots.end());
        break;
      }
    }
    const long long onsets_before = stats_.contact_onsets;
    if (!latch_at_event(found, ev.from_method) && !ev.from_method && !ev.stage_only)
      locate_suspended_ = true;
    // restart with the step the controller had before the re-take, not the short one (CVODE,
    // at its root: with its own suggestion); after an onset at most with the first trial step
    // integrator.step, as at t = 0: the force law is not smooth there (delta^n, n = 1.5), and
    // a long first step through the impact's rise is not seen by every error estimate
    double dt = ev.from_method ? stepper_->suggested_dt() : dt_before;
    if (stats_.contact_onsets > onsets_before) dt = std::min(dt, settings_.step);
    if (ev.stage_only) dt = std::min(dt, ev.t - t_start);  // what its stages stood
    stepper_->reset(stepper_->z_now, stepper_->t_now, dt);
    stats_.t_reached = stepper_->t_now;
  }

  /// The latches at the end of a re-take: every contact penetrating there starts its episode;
  /// an event's contact that is still approaching starts it too (the re-taken state may end a
  /// hair short of the interpolant's onset), and one that is out of contact ends it. Returns
  /// whether a latch changed (if not, the next step latches at its end instead: relocating
  /// again and again could creep towards an onset without ever getting there).
  bool latch_at_event(const std::vector<int>& event_contacts, bool from_method) {
    bool changed = false;
    for (int c = 0; c < scene_.contact_count(); ++c) {
      const ContactGap g = end_gap(c, stepper_->z_now);
      const bool event =
          std::find(event_contacts.begin(), event_contacts.end(), c) != event_contacts.end();
      if (!latched(c) &&
          (g.penetration > 0.0 || (event && (from_method || g.penetration_rate > 0.0)))) {
        latch(c, g, stepper_->t_now);
        changed = true;
      } else if (latched(c) && event) {
        char& touched = touched_[static_cast<std::size_t>(c)];
        if (g.penetration <= 0.0) {
          discrete_.contacts[static_cast<std::size_t>(c)] = ContactLatch{};  // episode over
          ends_[static_cast<std::size_t>(c)].valid = false;
          changed = true;
        } else if (!touched) {
          changed = true;  // an episode split at its deepest point
        }
        // else: a separation the re-taken step does not reproduce (a grazing contact, a
        // rounding error above zero) is no change, so the next step is accepted without
        // locating (locate_suspended_). Reporting one re-took the same event 2.6e-15 s later,
        // 2e7 times (gravity-drop at rest on the wall, restitution 0.136: tests/test_events.cpp)
        touched = 1;
      }
    }
    return changed;
  }

  void check_health_after_step() {
    const state_t& z = stepper_->z_now;
    if (!all_finite(z)) {
      std::ostringstream m;
      m << "non-finite state at t = " << stepper_->t_now
        << " s (last finite t = " << stepper_->t_prev << " s)";
      stats_.t_reached = stepper_->t_prev;
      throw RunFailure{RunStatus::non_finite_state, m.str()};
    }
    stats_.t_reached = stepper_->t_now;  // an accepted, finite step
    if (stepper_->accepted + stepper_->rejected > settings_.max_steps) {
      std::ostringstream m;
      m << "step budget of " << settings_.max_steps << " steps exhausted at t = " << stepper_->t_now
        << " s";
      throw RunFailure{RunStatus::step_budget_exhausted, m.str()};
    }
    for (int c = 0; c < scene_.contact_count(); ++c) check_penetration(c);
  }

  /// The penetration of contact c at the step's end against the contact laws' validity (the
  /// contact radius) and, if the study sets one, against the clearance.
  void check_penetration(int c) {
    const double delta = end_gap(c, stepper_->z_now).penetration;
    auto limit = [&](double scale, double max_ratio, double& seen, const char* what,
                     const char* key) {
      if (!(scale > 0.0)) return;
      const double ratio = delta / scale;
      seen = std::max(seen, ratio);
      if (max_ratio > 0.0 && ratio > max_ratio) {
        std::ostringstream m;
        m << "penetration " << delta << " m = " << ratio << " x the " << what
          << " exceeds the limit " << key << " = " << max_ratio << " at t = " << stepper_->t_now
          << " s";
        throw RunFailure{RunStatus::penetration_limit, m.str()};
      }
    };
    limit(scene_.contact_radius(c), health_.max_penetration_strain, stats_.max_penetration_strain,
          "contact radius", "health.max_penetration_strain");
    limit(scene_.contact_clearance(c), health_.max_penetration_fraction,
          stats_.max_penetration_fraction, "clearance", "health.max_penetration_fraction");
  }

  /// Renormalises quaternions when they have drifted; returns true if the state changed.
  bool renormalise(state_t& z) {
    bool changed = false;
    for (int o : scene_.quaternion_offsets()) {
      const auto i = static_cast<std::size_t>(o);
      double n2 = 0.0;
      for (std::size_t k = 0; k < 4; ++k) n2 += z[i + k] * z[i + k] * scale_[i + k] * scale_[i + k];
      const double err = std::abs(std::sqrt(n2) - 1.0);
      stats_.max_quaternion_norm_error = std::max(stats_.max_quaternion_norm_error, err);
      // fixed-step methods renormalise every step; adaptive ones only when the drift exceeds
      // 1e-6: the right-hand side reads only the normalised quaternion (BodyKinematics), so the
      // drift changes no dynamics, and a restart is not free. For dopri5 it costs a call; for
      // cvode_bdf it throws away the BDF history (back to order 1, a new Jacobian): at 1e-10,
      // crossed on nearly every step, rod-end-kinematic's thesis cycle took 845,082 calls at
      // cvode_bdf 1e-7, 15,491 at 1e-6 (issue 20; dopri5 never reached 1e-10 there)
      if (err > (stepper_->dense() ? 1e-6 : 0.0)) {
        const double inv = 1.0 / std::sqrt(n2);
        for (std::size_t k = 0; k < 4; ++k) z[i + k] *= inv;
        changed = true;
      }
    }
    return changed;
  }

  /// Wear of the accepted step just taken, by 3-point Gauss-Legendre on its interpolant (exact
  /// for polynomials of degree 5, the dense output's order; the sliding power is smooth within
  /// a step, whose ends the driver places at contact onsets).
  void deposit_wear() {
    if (!wears_) return;
    const double t0 = stepper_->t_prev, t1 = stepper_->t_now, h = t1 - t0;
    if (!(h > 0.0)) return;
    static const double r = std::sqrt(0.6);
    static constexpr double w[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    const double node[3] = {-r, 0.0, r};
    for (int k = 0; k < 3; ++k) {
      const double t = t0 + 0.5 * h * (1.0 + node[k]);
      stepper_->interpolate(t, z_tmp_);
      unscale(z_tmp_, x_);
      const WearSource src = scene_.wear_source(t, x_.data(), discrete_);
      if (!std::isfinite(src.sliding_power)) {
        std::ostringstream m;
        m << "non-finite sliding power at t = " << t << " s";
        throw RunFailure{RunStatus::non_finite_state, m.str()};
      }
      obs_.on_wear(src, 0.5 * h * w[k]);
    }
  }

  /// Contact c at time t of the last step, on its interpolant (at its end, the step's state).
  ContactSnapshot snapshot_at(int c, double t) {
    if (t >= stepper_->t_now)
      z_tmp_ = stepper_->z_now;
    else
      stepper_->interpolate(t, z_tmp_);
    unscale(z_tmp_, x_);
    return scene_.contact_snapshot(c, t, x_.data(), discrete_);
  }

  /// The maximum of f on [a, b] (Brent's method: golden section with parabolic steps), to the
  /// time resolution `tol` [s]; returns its time and writes its value.
  template <class F>
  static double argmax(double a, double b, double tol, F&& f, double& f_max) {
    const double golden = 0.5 * (3.0 - std::sqrt(5.0));
    double x = a + golden * (b - a), w = x, v = x;
    double fx = -f(x), fw = fx, fv = fx;  // minimising -f
    double d = 0.0, e = 0.0;
    for (int it = 0; it < 100; ++it) {
      const double m = 0.5 * (a + b);
      const double tol1 = tol + 4e-16 * std::abs(x), tol2 = 2.0 * tol1;
      if (std::abs(x - m) <= tol2 - 0.5 * (b - a)) break;
      bool golden_step = true;
      if (std::abs(e) > tol1) {  // try a parabola through x, w, v
        double r = (x - w) * (fx - fv), q = (x - v) * (fx - fw), p = (x - v) * q - (x - w) * r;
        q = 2.0 * (q - r);
        if (q > 0.0)
          p = -p;
        else
          q = -q;
        const double e_old = e;
        e = d;
        if (std::abs(p) < std::abs(0.5 * q * e_old) && p > q * (a - x) && p < q * (b - x)) {
          d = p / q;
          const double u = x + d;
          if (u - a < tol2 || b - u < tol2) d = m - x >= 0.0 ? tol1 : -tol1;
          golden_step = false;
        }
      }
      if (golden_step) {
        e = x >= m ? a - x : b - x;
        d = golden * e;
      }
      const double u = std::abs(d) >= tol1 ? x + d : x + (d >= 0.0 ? tol1 : -tol1);
      const double fu = -f(u);
      if (fu <= fx) {
        (u >= x ? a : b) = x;
        v = w, fv = fw, w = x, fw = fx, x = u, fx = fu;
      } else {
        (u < x ? a : b) = u;
        if (fu <= fw || w == x) {
          v = w, fv = fw, w = u, fw = fu;
        } else if (fu <= fv || v == x || v == w) {
          v = u, fv = fu;
        }
      }
    }
    f_max = -fx;
    return x;
  }

  /// Where the tangents at (t0, f0) with slope s0 > 0 and at (t1, f1) with slope s1 < 0 meet:
  /// an upper bound of the maximum in between when f is concave there.
  static double tangent_bound(double t0, double f0, double s0, double t1, double f1, double s1) {
    const double t = (f1 - f0 + s0 * t0 - s1 * t1) / (s0 - s1);
    return f0 + s0 * (std::clamp(t, t0, t1) - t0);
  }

  /// The peaks of an impact fall between step ends. For each contact, inside the accepted step
  /// just taken: a maximum of the normal force where its slope turns from rising to falling
  /// (with damping this is before the maximum penetration), and a maximum of the penetration
  /// where its rate turns from positive to negative, each located on the step's interpolant
  /// (Brent) when the observer says it could change what it collects, and reported to it.
  /// The slopes at the step ends come from the contact's state there: the penetration rate is
  /// the state's; the force's slope is a one-sided difference over 1e-4 of the step, carried
  /// from one step's end to the next step's start.
  void locate_contact_peaks() {
    const double t0 = stepper_->t_prev, t1 = stepper_->t_now, h = t1 - t0;
    if (!(h > 0.0)) return;
    const double eps = 1e-4 * h, tol = 1e-7 * h;
    for (int c = 0; c < scene_.contact_count(); ++c) {
      ContactEnd& last = ends_[static_cast<std::size_t>(c)];
      ContactEnd start;
      if (last.valid && last.t == t0) {
        start = last;
      } else {
        start.at = snapshot_at(c, t0);
        start.force_slope_known = false;
      }
      ContactEnd end;
      end.t = t1;
      end.valid = true;
      end.at = snapshot_at(c, t1);
      if (provides_force_ && (start.at.normal_force > 0.0 || end.at.normal_force > 0.0)) {
        end.force_slope = (end.at.normal_force - snapshot_at(c, t1 - eps).normal_force) / eps;
        end.force_slope_known = true;
        if (!start.force_slope_known) {
          start.force_slope = (snapshot_at(c, t0 + eps).normal_force - start.at.normal_force) / eps;
          start.force_slope_known = true;
        }
        if (start.force_slope > 0.0 && end.force_slope < 0.0) {
          const double bound = tangent_bound(t0, start.at.normal_force, start.force_slope, t1,
                                             end.at.normal_force, end.force_slope);
          if (obs_.wants_peak(ContactPeak::Kind::force, c, t0, bound)) {
            double f_max = 0.0;
            const double t = argmax(
                t0, t1, tol, [&](double tt) { return snapshot_at(c, tt).normal_force; }, f_max);
            report_peak(ContactPeak::Kind::force, c, t);
          }
        }
      }
      if (start.at.penetration_rate > 0.0 && end.at.penetration_rate <= 0.0 &&
          std::max(start.at.penetration, end.at.penetration) > 0.0) {
        const double bound =
            tangent_bound(t0, start.at.penetration, start.at.penetration_rate, t1,
                          end.at.penetration, std::min(end.at.penetration_rate, -1e-300));
        if (obs_.wants_peak(ContactPeak::Kind::penetration, c, t0, bound)) {
          double d_max = 0.0;
          const double t = argmax(
              t0, t1, tol, [&](double tt) { return snapshot_at(c, tt).penetration; }, d_max);
          report_peak(ContactPeak::Kind::penetration, c, t);
        }
      }
      last = end;
    }
  }

  void report_peak(ContactPeak::Kind kind, int c, double t) {
    ContactPeak p;
    p.kind = kind;
    p.contact = c;
    p.t = t;
    p.at = snapshot_at(c, t);
    for (double v : {p.at.penetration, p.at.penetration_rate, p.at.eccentricity, p.at.normal_force})
      if (!std::isfinite(v)) {
        std::ostringstream m;
        m << "non-finite contact state at t = " << t << " s";
        throw RunFailure{RunStatus::non_finite_state, m.str()};
      }
    obs_.on_contact_peak(p);
  }

  /// The run: the pipeline of an accepted step. A step whose event lies inside it is re-taken
  /// up to the event; otherwise it is accepted.
  void loop() {
    while (stepper_->t_now < time_.end) {
      take_step();
      const Event ev = find_event();
      if (ev.any())
        retake_to(ev);
      else
        accept_step();
    }
  }

  /// One step of the method: to the end of the run (dense output), or to the next sample time
  /// (no dense output: samples are step ends or re-takes of the step).
  void take_step() {
    const double t_end = time_.end;
    const double t_limit = stepper_->dense() ? t_end : std::min(sample_time(next_sample_), t_end);
    arm_stage_watch();
    stepper_->step(t_limit);
    check_health_after_step();
  }

  /// Watches the stages of the next step for an onset of a contact not latched (locate only).
  void arm_stage_watch() {
    watch_.earliest = std::numeric_limits<double>::infinity();
    watch_.armed = false;
    if (settings_.contact_onset != ContactOnset::locate) return;
    for (int c = 0; c < scene_.contact_count(); ++c) watch_.armed |= !latched(c);
  }

  /// An accepted step: samples, wear and peaks inside it (with the discrete state it was taken
  /// with), then the discrete updates at its end, the step observation and renormalisation.
  void accept_step() {
    emit_samples_until(stepper_->t_now);
    deposit_wear();
    stats_.t_reached = stepper_->t_now;
    if (obs_.wants_steps()) locate_contact_peaks();
    const bool discrete_changed = latch_at_step_end();
    if (obs_.wants_steps()) observe_step();
    state_t& z = stepper_->z_now;
    const bool renormalised = renormalise(z);
    if ((renormalised || discrete_changed) && stepper_->dense())
      stepper_->reset(z, stepper_->t_now, stepper_->suggested_dt());
  }

  /// Discrete updates at the end of an accepted step: an episode ends once its contact is out
  /// of contact (unless latched a hair before touching and still approaching), a contact that
  /// penetrates unlatched starts one (step-end latching, or an onset at a restart point), and a
  /// contact in friction.mode stick-slip takes the branch its slip speed calls for (stuck to
  /// slipping above the switch speed, back below it). Returns whether an onset was latched or a
  /// branch switched (the method restarts with the new force law).
  bool latch_at_step_end() {
    bool onset = false;
    for (int c = 0; c < scene_.contact_count(); ++c) {
      const ContactGap g = end_gap(c, stepper_->z_now);
      char& touched = touched_[static_cast<std::size_t>(c)];
      if (latched(c) && g.penetration <= 0.0 && (touched || !(g.penetration_rate > 0.0))) {
        discrete_.contacts[static_cast<std::size_t>(c)] = ContactLatch{};  // episode over
        ends_[static_cast<std::size_t>(c)].valid = false;                  // its force changed law
      } else if (!latched(c) && g.penetration > 0.0) {
        latch(c, g, stepper_->t_now);
        onset = true;
      } else if (latched(c) && g.penetration > 0.0) {
        touched = 1;
        ContactLatch& l = discrete_.contacts[static_cast<std::size_t>(c)];
        if (g.slipping >= 0 && (g.slipping == 1) != l.slipping) {
          l.slipping = g.slipping == 1;
          ++stats_.friction_switches;
          onset = true;
        }
      }
    }
    unscale(stepper_->z_now, x_);  // for observe_step
    return onset;
  }

  /// The lean frame the metrics read at every accepted step (kStepSignals); full frames only at
  /// samples. Expects x_ to hold the step's end state.
  void observe_step() {
    frame_.set(SignalId::time, stepper_->t_now);
    scene_.step_outputs(stepper_->t_now, x_.data(), discrete_, frame_);
    check_frame_finite(stepper_->t_now, step_signals_, step_slots_);
    obs_.on_step(frame_);
  }

  const Scene& scene_;
  const IntegratorSettings& settings_;
  const TimeSettings& time_;
  RunObserver& obs_;
  const HealthLimits& health_;
  std::size_t n_;
  state_t scale_;
  DiscreteState discrete_;
  ScaledSystem sys_;
  detail::StageWatch watch_;  ///< the stages' earliest onset in the step (sys_.watch)
  std::unique_ptr<Stepper> stepper_;
  SignalFrame frame_;
  state_t x_, z_tmp_;
  long long n_samples_ = 0, next_sample_ = 0;
  RunStats stats_;
  bool provides_force_ = false;
  bool checks_energy_ = false, checks_tracking_ = false, has_kinetic_ = false;
  bool wears_ = false;             ///< deposit wear (the scene models it and the observer wants it)
  std::vector<SignalId> signals_;  ///< the scene's signals (checked finite in every frame)
  std::vector<SignalId> step_signals_;          ///< those of kStepSignals (checked in step frames)
  std::vector<int> signal_slots_, step_slots_;  ///< their frame offsets (check_frame_finite)
  /// Contact gaps at the last two step-end states (end_gap)
  struct GapMemo {
    state_t z;  ///< the scaled state
    std::vector<ContactGap> gaps;
    std::vector<char> known;  ///< per contact: gaps[c] is computed
    bool valid = false;
  };
  GapMemo gap_memo_[2];
  int gap_memo_last_ = 0;  ///< the entry used last
  /// A contact at the end of the last accepted step (locate_contact_peaks)
  struct ContactEnd {
    double t = 0.0;
    bool valid = false;
    ContactSnapshot at;
    double force_slope = 0.0;  ///< d F_n / dt there [N/s] (one-sided difference)
    bool force_slope_known = false;
  };
  std::vector<ContactEnd> ends_;
  double max_energy_flow_ = 0.0;  ///< largest |input work|, |dissipated|, kinetic at samples [J]
  double tracking_since_ = -1.0;  ///< first sample of the current tracking excess [s], or -1
  /// per contact: its episode has been in contact at a step end after the one that latched it
  /// (until then, it is not over while it approaches: it may be latched a hair before touching)
  std::vector<char> touched_;
  bool locate_suspended_ = false;  ///< latch the next onset at the step end (see loop())
};

}  // namespace

RunResult simulate(const Scene& scene, const IntegratorSettings& settings, const TimeSettings& time,
                   RunObserver& observer, const HealthLimits& health) {
  validate(settings);
  validate(time);
  validate(health);
  Driver d(scene, settings, time, observer, health);
  return d.run();
}

}  // namespace rodend
