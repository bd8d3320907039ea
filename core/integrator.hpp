// Integration driver: runs a Scene with a Boost.Odeint stepper, latches contact onsets between
// accepted steps, samples histories at a fixed interval, and enforces budgets.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/scene.hpp"
#include "core/signals.hpp"

namespace rodend {

/// Integrator settings (a plain struct: one field per setting, with its unit).
struct IntegratorSettings {
  std::string method = "dopri5";     ///< rk4 (fixed step) | dopri5 (adaptive, dense output)
  double abs_tol = 1e-6;             ///< absolute tolerance on the scaled state [-]
  double rel_tol = 1e-6;             ///< relative tolerance [-]
  double step = 1e-5;                ///< fixed step (rk4) or first trial step (adaptive) [s]
  double max_step = 1e-3;            ///< largest step of adaptive methods [s]
  double min_step = 1e-14;           ///< below this an adaptive step is an underflow [s]
  long long max_steps = 20'000'000;  ///< budget on accepted plus rejected steps [-]
  long long max_rhs_calls = 200'000'000;  ///< budget on right-hand-side calls [-]
  /// How contact onset is latched: "locate" finds the onset time on the step's interpolant by
  /// bisection and restarts there; "step-end" latches at the end of the step that crossed it.
  std::string contact_onset = "locate";
};

/// Time settings of a run.
struct TimeSettings {
  double end = 1.0;               ///< end time [s]
  double sample_interval = 1e-3;  ///< history sample interval [s]
};

/// Health limits checked on every accepted step.
struct HealthLimits {
  double max_penetration_fraction = 0.2;  ///< penetration / clearance above which a run fails [-]
};

std::vector<std::string_view> integrator_methods();

enum class RunStatus {
  ok,
  step_budget_exhausted,
  rhs_budget_exhausted,
  step_size_underflow,
  non_finite_state,
  penetration_limit,
};
std::string_view to_string(RunStatus s);

struct RunStats {
  long long steps_accepted = 0;
  long long steps_rejected = 0;
  long long rhs_calls = 0;
  long long contact_onsets = 0;
  double t_reached = 0.0;                 ///< [s]
  double max_quaternion_norm_error = 0.0; ///< largest | |q| - 1 | seen before renormalising [-]
  double max_penetration_fraction = 0.0;  ///< largest penetration / clearance seen [-]
};

struct RunResult {
  RunStatus status = RunStatus::ok;
  std::string message;  ///< empty when ok
  RunStats stats;
};

/// Receives what the driver produces. Frames are valid only during the call.
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  /// At t = 0 and every sample interval (and never after a failure).
  virtual void on_sample(const SignalFrame& /*frame*/) {}
  /// At the end of every accepted step, when wants_steps() is true (metrics that need peaks).
  virtual void on_step(const SignalFrame& /*frame*/) {}
  virtual bool wants_steps() const { return false; }
  /// When a contact episode is latched: its onset time [s] and approach speed [m/s].
  virtual void on_contact_onset(double /*t*/, int /*contact*/, double /*impact_speed*/) {}
};

/// Checks settings; throws InputError with a key path under "integrator." or "time.".
void validate(const IntegratorSettings& s);
void validate(const TimeSettings& s);

/// Runs `scene` from its initial state to `time.end`. Never throws for numerical trouble: a
/// failed run returns its status, a message and the time reached.
RunResult simulate(const Scene& scene, const IntegratorSettings& settings,
                   const TimeSettings& time, RunObserver& observer,
                   const HealthLimits& health = {});

}  // namespace rodend
