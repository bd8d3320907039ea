#include "core/integrator.hpp"

#include "core/stepper.hpp"

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <functional>
#include <memory>
#include <sstream>

namespace rodend {
namespace odeint = boost::numeric::odeint;
using detail::RunFailure;
using detail::ScaledSystem;
using detail::state_t;
using detail::Stepper;

std::vector<std::string_view> integrator_methods() {
  return {"rk4",         "dopri5",    "cash_karp54", "fehlberg78", "bulirsch_stoer",
          "rosenbrock4", "cvode_bdf", "cvode_adams"};
}

std::string_view to_string(RunStatus s) {
  switch (s) {
    case RunStatus::ok:
      return "ok";
    case RunStatus::step_budget_exhausted:
      return "step_budget_exhausted";
    case RunStatus::rhs_budget_exhausted:
      return "rhs_budget_exhausted";
    case RunStatus::step_size_underflow:
      return "step_size_underflow";
    case RunStatus::non_finite_state:
      return "non_finite_state";
    case RunStatus::penetration_limit:
      return "penetration_limit";
    case RunStatus::energy_residual_limit:
      return "energy_residual_limit";
    case RunStatus::actuator_saturation:
      return "actuator_saturation";
  }
  return "unknown";
}

void validate(const IntegratorSettings& s) {
  const auto methods = integrator_methods();
  if (std::find(methods.begin(), methods.end(), s.method) == methods.end()) {
    std::string list;
    for (auto m : methods) list += (list.empty() ? "" : ", ") + std::string(m);
    throw InputError("integrator.method",
                     "unknown method '" + s.method + "'; expected one of: " + list);
  }
  auto positive = [](double v, const char* key) {
    if (!(v > 0.0) || !std::isfinite(v)) throw InputError(key, "expected a finite number > 0");
  };
  positive(s.abs_tol, "integrator.abs_tol");
  positive(s.rel_tol, "integrator.rel_tol");
  positive(s.step, "integrator.step");
  positive(s.max_step, "integrator.max_step");
  positive(s.min_step, "integrator.min_step");
  if (s.max_steps <= 0) throw InputError("integrator.max_steps", "expected an integer > 0");
  if (s.max_rhs_calls <= 0) throw InputError("integrator.max_rhs_calls", "expected an integer > 0");
  if (s.contact_onset != "locate" && s.contact_onset != "step-end")
    throw InputError("integrator.contact_onset", "expected \"locate\" or \"step-end\"");
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
  if (s.end / s.sample_interval > 5e7)
    throw InputError("time.sample_interval",
                     "more than 5e7 samples requested; expected a larger sample interval");
}

void validate(const HealthLimits& h) {
  auto check = [](double v, bool zero_ok, const char* key, const char* what) {
    if (!std::isfinite(v) || (zero_ok ? !(v >= 0.0) : !(v > 0.0)))
      throw InputError(key, std::string("expected a finite ") + what);
  };
  check(h.max_penetration_fraction, false, "health.max_penetration_fraction", "fraction > 0");
  check(h.max_energy_residual, false, "health.max_energy_residual", "fraction > 0");
  check(h.energy_flow_floor, true, "health.energy_flow_floor", "energy >= 0 [J]");
  check(h.max_tracking_error, false, "health.max_tracking_error", "length > 0 [m]");
  check(h.tracking_window, true, "health.tracking_window", "time >= 0 [s]");
}

namespace {

bool all_finite(const state_t& z) {
  return std::all_of(z.begin(), z.end(), [](double v) { return std::isfinite(v); });
}

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
    scene.state_scale(scale_.data());
    // bookkeeping integrals: scaled so that they never limit the step size
    for (int o : scene.audit_offsets()) scale_[static_cast<std::size_t>(o)] *= 1e12;
    discrete_.contacts.assign(static_cast<std::size_t>(scene.contact_count()), ContactLatch{});
    const auto sig = scene.signals();
    auto provides = [&](SignalId id) { return std::find(sig.begin(), sig.end(), id) != sig.end(); };
    provides_force_ = provides(SignalId::contact_force);
    checks_energy_ = provides(SignalId::energy_residual) && provides(SignalId::input_work) &&
                     provides(SignalId::dissipated_energy);
    has_kinetic_ = provides(SignalId::kinetic_energy);
    checks_tracking_ =
        provides(SignalId::actuator_command) && provides(SignalId::actuator_position);
    signals_.assign(sig.begin(), sig.end());
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
      latch_time_ = 0.0;
      for (int c = 0; c < scene_.contact_count(); ++c) latch_if_touching(c, x_.data());
      stepper_ = detail::make_stepper(sys_, scene_, settings_);
      stepper_->reset(z0, 0.0, settings_.step);
      emit_sample(0, z0);
      next_sample_ = 1;
      loop();
    } catch (const RunFailure& f) {
      result.status = f.status;
      result.message = f.message;
    } catch (const odeint::step_adjustment_error& e) {
      result.status = RunStatus::step_size_underflow;
      result.message = std::string("step size underflow: ") + e.what();
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

  /// A frame with a non-finite value never reaches the observer: the run ends there.
  void check_frame_finite(double t) {
    for (SignalId id : signals_)
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
      max_energy_flow_ = std::max({max_energy_flow_, std::abs(frame_.get(SignalId::input_work)),
                                   std::abs(frame_.get(SignalId::dissipated_energy)),
                                   has_kinetic_ ? frame_.get(SignalId::kinetic_energy) : 0.0});
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

  double penetration_at(int c, const state_t& z) {
    unscale(z, x_);
    return scene_.contact_gap(c, x_.data()).penetration;
  }

  void latch_if_touching(int c, const double* x) {
    const ContactGap g = scene_.contact_gap(c, x);
    ContactLatch& l = discrete_.contacts[static_cast<std::size_t>(c)];
    if (g.penetration > 0.0 && !l.in_contact) {
      l.in_contact = true;
      l.impact_speed = std::max(g.penetration_rate, 0.0);
      ++stats_.contact_onsets;
      obs_.on_contact_onset(latch_time_, c, l.impact_speed);
    }
  }

  /// Earliest onset time in (t_prev, t_now] of a contact not yet latched, by bisection on the
  /// interpolant; returns t_now when nothing needs locating.
  double locate_onset() {
    double t_event = stepper_->t_now;
    for (int c = 0; c < scene_.contact_count(); ++c) {
      if (discrete_.contacts[static_cast<std::size_t>(c)].in_contact) continue;
      if (penetration_at(c, stepper_->z_now) <= 0.0) continue;
      if (penetration_at(c, stepper_->z_prev) > 0.0) continue;  // latched at the step end
      double lo = stepper_->t_prev, hi = t_event;
      // 60 halvings reach the resolution of double time for any step length
      for (int it = 0; it < 60 && hi - lo > 4e-16 * std::max(1.0, std::abs(hi)); ++it) {
        const double mid = 0.5 * (lo + hi);
        stepper_->interpolate(mid, z_tmp_);  // the method itself: consistent with the re-take
        if (penetration_at(c, z_tmp_) > 0.0)
          hi = mid;
        else
          lo = mid;
      }
      t_event = std::min(t_event, hi);
    }
    return t_event;
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
    unscale(z, x_);
    for (int c = 0; c < scene_.contact_count(); ++c) {
      const double clearance = scene_.contact_clearance(c);
      if (clearance <= 0.0) continue;
      const double frac = scene_.contact_gap(c, x_.data()).penetration / clearance;
      stats_.max_penetration_fraction = std::max(stats_.max_penetration_fraction, frac);
      if (frac > health_.max_penetration_fraction) {
        std::ostringstream m;
        m << "penetration " << frac << " x clearance exceeds the limit "
          << health_.max_penetration_fraction << " at t = " << stepper_->t_now << " s";
        throw RunFailure{RunStatus::penetration_limit, m.str()};
      }
    }
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
      // fixed-step methods renormalise every step; adaptive ones only when it matters, since
      // a restart costs a right-hand-side call
      if (err > (stepper_->dense() ? 1e-10 : 0.0)) {
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

  /// Frame at time t inside the last step, from the interpolant.
  void frame_at(double t) {
    stepper_->interpolate(t, z_tmp_);
    unscale(z_tmp_, x_);
    frame_.set(SignalId::time, t);
    scene_.outputs(t, x_.data(), discrete_, frame_);
  }

  /// Peaks of an impact fall between step ends: when a contact's approach speed turns from
  /// positive to negative within the step, the observer also gets the frames at the maximum
  /// penetration (root of the penetration rate, by bisection) and at the maximum contact force
  /// (golden-section search), both on the step's interpolant, in time order.
  void refine_impact_peaks() {
    const double t0 = stepper_->t_prev, t1 = stepper_->t_now;
    if (!(t1 > t0)) return;
    std::vector<double> times;
    for (int c = 0; c < scene_.contact_count(); ++c) {
      unscale(stepper_->z_prev, x_);
      const ContactGap g0 = scene_.contact_gap(c, x_.data());
      unscale(stepper_->z_now, x_);
      const ContactGap g1 = scene_.contact_gap(c, x_.data());
      if (!(g0.penetration_rate > 0.0 && g1.penetration_rate <= 0.0)) continue;
      if (!(std::max(g0.penetration, g1.penetration) > 0.0)) continue;
      double lo = t0, hi = t1;
      for (int it = 0; it < 40; ++it) {
        const double mid = 0.5 * (lo + hi);
        stepper_->interpolate(mid, z_tmp_);
        unscale(z_tmp_, x_);
        (scene_.contact_gap(c, x_.data()).penetration_rate > 0.0 ? lo : hi) = mid;
      }
      times.push_back(0.5 * (lo + hi));
      if (provides_force_) {
        // golden section for the force maximum (unimodal within one impact step)
        const double r = 0.5 * (std::sqrt(5.0) - 1.0);
        double a = t0, b = t1, x1 = b - r * (b - a), x2 = a + r * (b - a);
        frame_at(x1);
        double f1 = frame_.get(SignalId::contact_force);
        frame_at(x2);
        double f2 = frame_.get(SignalId::contact_force);
        for (int it = 0; it < 40 && b - a > 1e-12 * (t1 - t0); ++it) {
          if (f1 < f2) {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + r * (b - a);
            frame_at(x2);
            f2 = frame_.get(SignalId::contact_force);
          } else {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - r * (b - a);
            frame_at(x1);
            f1 = frame_.get(SignalId::contact_force);
          }
        }
        times.push_back(0.5 * (a + b));
      }
    }
    std::sort(times.begin(), times.end());
    for (double t : times) {
      if (!(t > t0 && t < t1)) continue;
      frame_at(t);
      check_frame_finite(t);
      obs_.on_step(frame_);
    }
  }

  void loop() {
    const double t_end = time_.end;
    while (stepper_->t_now < t_end) {
      const double t_limit = stepper_->dense() ? t_end : std::min(sample_time(next_sample_), t_end);
      stepper_->step(t_limit);
      check_health_after_step();

      // contact onset found by the method itself (CVODE's root finding): latch it there
      if (stepper_->finds_roots() && !stepper_->roots.empty()) {
        // re-take the step from its start up to the root, as for a located onset below: the
        // method's interpolant over the crossing step carries the contact force back to the
        // samples before the root and into the restart state
        const std::vector<int> found = stepper_->roots;
        const double t_root = stepper_->t_now;
        const state_t z_start = stepper_->z_prev;
        stepper_->reset(z_start, stepper_->t_prev, t_root - stepper_->t_prev);
        while (stepper_->t_now < t_root) {
          stepper_->step(t_root);
          check_health_after_step();
          emit_samples_until(stepper_->t_now);
          deposit_wear();
          // the re-take found the root a hair before t_root (a grazing approach): latch there;
          // stepping on from a root without re-initialising is CVODE's CV_ILL_INPUT ("root
          // found at and very near t")
          if (!stepper_->roots.empty()) break;
        }
        unscale(stepper_->z_now, x_);
        for (int c : found) {
          ContactLatch& l = discrete_.contacts[static_cast<std::size_t>(c)];
          if (l.in_contact) continue;
          l.in_contact = true;
          l.impact_speed = std::max(scene_.contact_gap(c, x_.data()).penetration_rate, 0.0);
          ++stats_.contact_onsets;
          obs_.on_contact_onset(stepper_->t_now, c, l.impact_speed);
        }
        stepper_->reset(stepper_->z_now, stepper_->t_now, stepper_->suggested_dt());
        stats_.t_reached = stepper_->t_now;
        continue;
      }
      // contact onset: locate it and restart there, so the step that crossed it is discarded
      // (after a relocation that ended short of contact, the next onset is latched at the step
      // end instead: the interpolant's onset can lie a little before the method's own, and
      // relocating again and again would creep towards it without ever getting there)
      const bool locate_now = !locate_suspended_;
      locate_suspended_ = false;
      if (settings_.contact_onset == "locate" && !stepper_->finds_roots() && locate_now) {
        const double t_event = locate_onset();
        if (t_event < stepper_->t_now) {
          const double dt_before = stepper_->suggested_dt();
          const long long onsets_before = stats_.contact_onsets;
          // re-take the step from its start up to the onset: the crossing step's later stages
          // felt the contact force, so its interpolant would leak that force into the samples
          // before the onset and into the restart state
          const state_t z_start = stepper_->z_prev;
          stepper_->reset(z_start, stepper_->t_prev, t_event - stepper_->t_prev);
          while (stepper_->t_now < t_event) {
            stepper_->step(t_event);
            check_health_after_step();
            emit_samples_until(stepper_->t_now);
            deposit_wear();
          }
          const state_t z_event = stepper_->z_now;
          unscale(z_event, x_);
          latch_time_ = stepper_->t_now;
          for (int c = 0; c < scene_.contact_count(); ++c) latch_if_touching(c, x_.data());
          if (stats_.contact_onsets == onsets_before) {
            // the re-taken step may end a hair short of the interpolant's onset: at the onset
            // within round-off and approaching, latch it here; otherwise fall back to step-end
            // latching for the next onset
            for (int c = 0; c < scene_.contact_count(); ++c) {
              ContactLatch& l = discrete_.contacts[static_cast<std::size_t>(c)];
              const ContactGap g = scene_.contact_gap(c, x_.data());
              if (!l.in_contact && g.penetration_rate > 0.0 &&
                  g.penetration > -1e-9 * std::max(scene_.contact_clearance(c), 1e-300)) {
                l.in_contact = true;
                l.impact_speed = g.penetration_rate;
                ++stats_.contact_onsets;
                obs_.on_contact_onset(latch_time_, c, l.impact_speed);
              }
            }
            if (stats_.contact_onsets == onsets_before) locate_suspended_ = true;
          }
          // restart with the step the controller had before the relocation, not the short one
          stepper_->reset(z_event, stepper_->t_now, dt_before);
          stats_.t_reached = stepper_->t_now;
          continue;
        }
      }
      emit_samples_until(stepper_->t_now);
      deposit_wear();
      stats_.t_reached = stepper_->t_now;

      // discrete updates at the end of the accepted step
      unscale(stepper_->z_now, x_);
      bool discrete_changed = false;
      for (int c = 0; c < scene_.contact_count(); ++c) {
        ContactLatch& l = discrete_.contacts[static_cast<std::size_t>(c)];
        const ContactGap g = scene_.contact_gap(c, x_.data());
        if (l.in_contact && g.penetration <= 0.0) {
          l = ContactLatch{};  // episode over
        } else if (!l.in_contact && g.penetration > 0.0) {
          latch_time_ = stepper_->t_now;
          latch_if_touching(c, x_.data());  // step-end latching (or onset at a restart point)
          discrete_changed = true;
        }
      }
      if (obs_.wants_steps()) {
        refine_impact_peaks();
        unscale(stepper_->z_now, x_);  // the refinement left an interior state in x_
        frame_.set(SignalId::time, stepper_->t_now);
        scene_.outputs(stepper_->t_now, x_.data(), discrete_, frame_);
        check_frame_finite(stepper_->t_now);
        obs_.on_step(frame_);
      }
      state_t& z = stepper_->z_now;
      const bool renormalised = renormalise(z);
      if ((renormalised || discrete_changed) && stepper_->dense())
        stepper_->reset(z, stepper_->t_now, stepper_->suggested_dt());
    }
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
  std::unique_ptr<Stepper> stepper_;
  SignalFrame frame_;
  state_t x_, z_tmp_;
  long long n_samples_ = 0, next_sample_ = 0;
  RunStats stats_;
  bool provides_force_ = false;
  bool checks_energy_ = false, checks_tracking_ = false, has_kinetic_ = false;
  bool wears_ = false;             ///< deposit wear (the scene models it and the observer wants it)
  std::vector<SignalId> signals_;  ///< the scene's signals (checked finite in every frame)
  double max_energy_flow_ = 0.0;   ///< largest |input work|, |dissipated|, kinetic at samples [J]
  double tracking_since_ = -1.0;   ///< first sample of the current tracking excess [s], or -1
  double latch_time_ = 0.0;
  bool locate_suspended_ = false;  ///< latch the next onset at the step end (see loop())  ///< time
                                   ///< at which latch_if_touching is evaluated
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
