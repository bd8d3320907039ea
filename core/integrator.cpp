#include "core/integrator.hpp"

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <functional>
#include <memory>
#include <sstream>

namespace rodend {
namespace odeint = boost::numeric::odeint;
using state_t = std::vector<double>;

std::vector<std::string_view> integrator_methods() { return {"rk4", "dopri5"}; }

std::string_view to_string(RunStatus s) {
  switch (s) {
    case RunStatus::ok: return "ok";
    case RunStatus::step_budget_exhausted: return "step_budget_exhausted";
    case RunStatus::rhs_budget_exhausted: return "rhs_budget_exhausted";
    case RunStatus::step_size_underflow: return "step_size_underflow";
    case RunStatus::non_finite_state: return "non_finite_state";
    case RunStatus::penetration_limit: return "penetration_limit";
  }
  return "unknown";
}

void validate(const IntegratorSettings& s) {
  const auto methods = integrator_methods();
  if (std::find(methods.begin(), methods.end(), s.method) == methods.end()) {
    std::string list;
    for (auto m : methods) list += (list.empty() ? "" : ", ") + std::string(m);
    throw InputError("integrator.method", "unknown method '" + s.method + "'; expected one of: " + list);
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
  if (!(s.end > 0.0) || !std::isfinite(s.end))
    throw InputError("time.end", "expected an end time > 0 [s]");
  if (!(s.sample_interval > 0.0) || !std::isfinite(s.sample_interval))
    throw InputError("time.sample_interval", "expected a sample interval > 0 [s]");
  if (s.end / s.sample_interval > 5e7)
    throw InputError("time.sample_interval",
                     "more than 5e7 samples requested; expected a larger sample interval");
}

namespace {

/// Thrown inside the step loop; turned into a RunResult.
struct RunFailure {
  RunStatus status;
  std::string message;
};

/// The right-hand side in scaled variables z = x / scale, as odeint wants it.
/// Holds references to the model and the discrete state, plus scratch of its own.
struct ScaledSystem {
  const Scene& scene;
  const DiscreteState& discrete;
  const state_t& scale;
  state_t x, dx;
  long long calls = 0;
  long long max_calls = 0;

  ScaledSystem(const Scene& s, const DiscreteState& d, const state_t& sc, long long budget)
      : scene(s), discrete(d), scale(sc), x(sc.size()), dx(sc.size()), max_calls(budget) {}

  void operator()(const state_t& z, state_t& dz, double t) {
    if (++calls > max_calls) {
      std::ostringstream m;
      m << "right-hand-side budget of " << max_calls << " calls exhausted at t = " << t << " s";
      throw RunFailure{RunStatus::rhs_budget_exhausted, m.str()};
    }
    for (std::size_t i = 0; i < z.size(); ++i) x[i] = z[i] * scale[i];
    scene.derivatives(t, x.data(), discrete, dx.data());
    for (std::size_t i = 0; i < z.size(); ++i) dz[i] = dx[i] / scale[i];
  }
};

/// One accepted step at a time, with an interpolant over the last step.
class Stepper {
 public:
  virtual ~Stepper() = default;
  /// (Re)starts at (t, z) with a first trial step dt.
  virtual void reset(const state_t& z, double t, double dt) = 0;
  /// Advances one accepted step, not past t_limit.
  virtual void step(double t_limit) = 0;
  /// State at t in [t_prev, t_now] on the method's interpolant.
  virtual void interpolate(double t, state_t& out) = 0;
  /// Whether the interpolant is cheap and accurate everywhere in the step (dense output):
  /// then steps need not land on sample times.
  virtual bool dense() const = 0;
  virtual double suggested_dt() const = 0;

  double t_prev = 0.0, t_now = 0.0;
  state_t z_prev, z_now;
  long long accepted = 0, rejected = 0;
};

/// Classical fourth-order Runge-Kutta, fixed step. Its "interpolant" re-takes the step from the
/// previous state with the shorter step, which is exactly what the method would have done.
class Rk4Stepper final : public Stepper {
 public:
  Rk4Stepper(ScaledSystem& sys, double dt) : sys_(sys), dt_(dt) {}
  void reset(const state_t& z, double t, double) override {
    z_now = z;
    t_now = t;
  }
  void step(double t_limit) override {
    z_prev = z_now;
    t_prev = t_now;
    double h = std::min(dt_, t_limit - t_now);
    stepper_.do_step(std::ref(sys_), z_now, t_now, h);
    // land exactly on t_limit when the step was shortened to reach it
    t_now = (h < dt_) ? t_limit : t_now + h;
    ++accepted;
  }
  void interpolate(double t, state_t& out) override {
    out = z_prev;
    if (t > t_prev) stepper_.do_step(std::ref(sys_), out, t_prev, t - t_prev);
  }
  bool dense() const override { return false; }
  double suggested_dt() const override { return dt_; }

 private:
  ScaledSystem& sys_;
  double dt_;
  odeint::runge_kutta4<state_t> stepper_;
};

/// Dormand-Prince 5(4) with step-size control and its free fourth-order dense output.
class Dopri5Stepper final : public Stepper {
 public:
  Dopri5Stepper(ScaledSystem& sys, const IntegratorSettings& s)
      : sys_(sys),
        min_dt_(s.min_step),
        ctrl_(odeint::make_controlled(s.abs_tol, s.rel_tol, s.max_step,
                                      odeint::runge_kutta_dopri5<state_t>())) {}
  void reset(const state_t& z, double t, double dt) override {
    z_now = z;
    t_now = t;
    dz_now.resize(z.size());
    sys_(z_now, dz_now, t_now);
    dt_ = dt;
  }
  void step(double t_limit) override {
    std::swap(z_prev, z_now);
    std::swap(dz_prev, dz_now);
    t_prev = t_now;
    z_now.resize(z_prev.size());
    dz_now.resize(z_prev.size());
    double t = t_prev;
    while (true) {
      double dt = std::min(dt_, t_limit - t_prev);
      const bool clipped = dt < dt_;
      const auto res = ctrl_.try_step(std::ref(sys_), z_prev, dz_prev, t, z_now, dz_now, dt);
      if (res == odeint::success) {
        ++accepted;
        // keep the controller's suggestion unless this step was only clipped to the limit
        if (!clipped) dt_ = dt;
        break;
      }
      ++rejected;
      dt_ = dt;
      if (dt_ < min_dt_) {
        std::ostringstream m;
        m << "step size underflow: step " << dt_ << " s < min_step " << min_dt_ << " s at t = "
          << t_prev << " s";
        throw RunFailure{RunStatus::step_size_underflow, m.str()};
      }
    }
    t_now = t;
  }
  void interpolate(double t, state_t& out) override {
    out.resize(z_now.size());
    ctrl_.stepper().calc_state(t, out, z_prev, dz_prev, t_prev, z_now, dz_now, t_now);
  }
  bool dense() const override { return true; }
  double suggested_dt() const override { return dt_; }

 private:
  ScaledSystem& sys_;
  double min_dt_;
  double dt_ = 0.0;
  state_t dz_prev, dz_now;
  odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<state_t>> ctrl_;
};

std::unique_ptr<Stepper> make_stepper(ScaledSystem& sys, const IntegratorSettings& s) {
  if (s.method == "rk4") return std::make_unique<Rk4Stepper>(sys, s.step);
  if (s.method == "dopri5") return std::make_unique<Dopri5Stepper>(sys, s);
  throw InputError("integrator.method", "unknown method '" + s.method + "'");
}

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
    n_samples_ = static_cast<long long>(std::floor(time.end / time.sample_interval + 1e-9)) + 1;
  }

  RunResult run() {
    RunResult result;
    try {
      state_t z0(n_);
      scene_.initial_state(x_.data());
      for (std::size_t i = 0; i < n_; ++i) z0[i] = x_[i] / scale_[i];
      // an initial penetration starts latched, with its current approach speed
      for (int c = 0; c < scene_.contact_count(); ++c) latch_if_touching(c, x_.data());
      stepper_ = make_stepper(sys_, settings_);
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
    frame_.set(SignalId::time, sample_time(k));
    scene_.outputs(sample_time(k), x_.data(), discrete_, frame_);
    obs_.on_sample(frame_);
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
        stepper_->interpolate(mid, z_tmp_);
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
      m << "non-finite state at t = " << stepper_->t_now << " s (last finite t = "
        << stepper_->t_prev << " s)";
      throw RunFailure{RunStatus::non_finite_state, m.str()};
    }
    if (stepper_->accepted + stepper_->rejected > settings_.max_steps) {
      std::ostringstream m;
      m << "step budget of " << settings_.max_steps << " steps exhausted at t = "
        << stepper_->t_now << " s";
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

  void loop() {
    const double t_end = time_.end;
    while (stepper_->t_now < t_end) {
      const double t_limit =
          stepper_->dense() ? t_end : std::min(sample_time(next_sample_), t_end);
      stepper_->step(t_limit);
      check_health_after_step();

      // contact onset: locate it and restart there, so the step that crossed it is discarded
      if (settings_.contact_onset == "locate") {
        const double t_event = locate_onset();
        if (t_event < stepper_->t_now) {
          // re-take the step from its start up to the onset: the crossing step's later stages
          // felt the contact force, so its interpolant would leak that force into the samples
          // before the onset and into the restart state
          const state_t z_start = stepper_->z_prev;
          stepper_->reset(z_start, stepper_->t_prev, t_event - stepper_->t_prev);
          while (stepper_->t_now < t_event) {
            stepper_->step(t_event);
            check_health_after_step();
            emit_samples_until(stepper_->t_now);
          }
          const state_t z_event = stepper_->z_now;
          unscale(z_event, x_);
          for (int c = 0; c < scene_.contact_count(); ++c) latch_if_touching(c, x_.data());
          stepper_->reset(z_event, stepper_->t_now, stepper_->suggested_dt());
          stats_.t_reached = stepper_->t_now;
          continue;
        }
      }
      emit_samples_until(stepper_->t_now);
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
          latch_if_touching(c, x_.data());  // step-end latching (or onset at a restart point)
          discrete_changed = true;
        }
      }
      if (obs_.wants_steps()) {
        frame_.set(SignalId::time, stepper_->t_now);
        scene_.outputs(stepper_->t_now, x_.data(), discrete_, frame_);
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
};

}  // namespace

RunResult simulate(const Scene& scene, const IntegratorSettings& settings,
                   const TimeSettings& time, RunObserver& observer, const HealthLimits& health) {
  validate(settings);
  validate(time);
  Driver d(scene, settings, time, observer, health);
  return d.run();
}

}  // namespace rodend
