#include "core/integrator.hpp"

#include "core/driver/run.hpp"

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <new>
#include <sstream>

namespace rodend {
namespace odeint = boost::numeric::odeint;
using detail::RunFailure;

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

/// The stages of a run, in order: start, then until the end time each step of the method is
/// taken and checked; a step with an event inside it (a contact's change of state) is re-taken
/// up to the event, otherwise it is accepted (samples, wear, peaks, latches, observation).
void run_stages(detail::Run& run) {
  detail::start(run);
  while (run.stepper().t_now < run.model.time.end) {
    detail::take_step(run);
    const detail::Event ev = detail::find_event(run);
    if (ev.any())
      detail::retake_to(run, ev);
    else
      detail::accept_step(run);
  }
}

}  // namespace

RunResult simulate(const Scene& scene, const IntegratorSettings& settings, const TimeSettings& time,
                   RunObserver& observer, const HealthLimits& health) {
  validate(settings);
  validate(time);
  validate(health);
  const detail::RunModel model(scene, settings, time, health, observer.wants_wear());
  detail::Run run(model, observer);
  RunResult result;
  try {
    run_stages(run);
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
    m << "internal error after t = " << run.state.stats.t_reached << " s: " << e.what();
    result.status = RunStatus::internal_error;
    result.message = m.str();
  }
  detail::assemble_result(run, result);
  return result;
}

}  // namespace rodend
