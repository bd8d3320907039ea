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
    case RunStatus::internal_error:
      return "internal_error";
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
  if (s.min_step > s.max_step)
    throw InputError("integrator.min_step",
                     "larger than integrator.max_step; expected min_step <= max_step");
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
  const bool fixed = s.method == "rk4";
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
    const Features features = scene.features();
    provides_force_ = features.has(Feature::contact);
    checks_energy_ = features.has(Feature::energy_audit);
    has_kinetic_ = provides(SignalId::kinetic_energy);  // a term of the audit's scale, if written
    checks_tracking_ = features.has(Feature::actuator);
    signals_.assign(sig.begin(), sig.end());
    for (SignalId id : kStepSignals)
      if (provides(id)) step_signals_.push_back(id);
    ends_.assign(static_cast<std::size_t>(scene.contact_count()), ContactEnd{});
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
      if (const std::string m = budget_shortfall(settings_, time_); !m.empty())
        throw RunFailure{RunStatus::step_budget_exhausted, m};
      loop();
    } catch (const RunFailure& f) {
      result.status = f.status;
      result.message = f.message;
    } catch (const odeint::step_adjustment_error& e) {
      result.status = RunStatus::step_size_underflow;
      result.message = std::string("step size underflow: ") + e.what();
    } catch (const std::exception& e) {
      // not a numerical failure: a bug, or a resource the run could not get
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

  /// A frame with a non-finite value never reaches the observer: the run ends there. Checks
  /// `which` signals (the scene's, or those of a step frame).
  void check_frame_finite(double t) { check_frame_finite(t, signals_); }
  void check_frame_finite(double t, const std::vector<SignalId>& which) {
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
    for (int c = 0; c < scene_.contact_count(); ++c) check_penetration(c);
  }

  /// The penetration of contact c at x_ against the contact laws' validity (the contact radius)
  /// and, if the study sets one, against the clearance.
  void check_penetration(int c) {
    const double delta = scene_.contact_gap(c, x_.data()).penetration;
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
      // peaks inside the step, with the discrete state the step was taken with
      if (obs_.wants_steps()) locate_contact_peaks();

      // discrete updates at the end of the accepted step
      unscale(stepper_->z_now, x_);
      bool discrete_changed = false;
      for (int c = 0; c < scene_.contact_count(); ++c) {
        ContactLatch& l = discrete_.contacts[static_cast<std::size_t>(c)];
        const ContactGap g = scene_.contact_gap(c, x_.data());
        if (l.in_contact && g.penetration <= 0.0) {
          l = ContactLatch{};                                // episode over
          ends_[static_cast<std::size_t>(c)].valid = false;  // its force changed law
        } else if (!l.in_contact && g.penetration > 0.0) {
          latch_time_ = stepper_->t_now;
          latch_if_touching(c, x_.data());  // step-end latching (or onset at a restart point)
          discrete_changed = true;
          ends_[static_cast<std::size_t>(c)].valid = false;
        }
      }
      if (obs_.wants_steps()) {
        // the lean frame the metrics read (kStepSignals); full frames only at samples
        frame_.set(SignalId::time, stepper_->t_now);
        scene_.step_outputs(stepper_->t_now, x_.data(), discrete_, frame_);
        check_frame_finite(stepper_->t_now, step_signals_);
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
  std::vector<SignalId> step_signals_;  ///< those of kStepSignals (checked in step frames)
  /// A contact at the end of the last accepted step (locate_contact_peaks)
  struct ContactEnd {
    double t = 0.0;
    bool valid = false;
    ContactSnapshot at;
    double force_slope = 0.0;  ///< d F_n / dt there [N/s] (one-sided difference)
    bool force_slope_known = false;
  };
  std::vector<ContactEnd> ends_;
  double max_energy_flow_ = 0.0;   ///< largest |input work|, |dissipated|, kinetic at samples [J]
  double tracking_since_ = -1.0;   ///< first sample of the current tracking excess [s], or -1
  double latch_time_ = 0.0;        ///< time at which latch_if_touching is evaluated
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
