// The integrator's settings and the statuses a run ends with: what the steppers
// (core/stepper.hpp) and the driver (core/integrator.hpp) share.
#pragma once

#include "core/choice.hpp"

namespace rodend {

/// The integration methods (README "The integrator menu"), from core/integrator_methods.def.
#define RODEND_CHOICE_ENUM IntegratorMethod
#define RODEND_CHOICE_FILE "core/integrator_methods.def"
#include "core/choice.hpp"
/// Whether the method takes integrator.step throughout (no error control).
bool fixed_step(IntegratorMethod m);

/// How contact onset is latched (integrator.contact_onset), from core/contact_onsets.def.
#define RODEND_CHOICE_ENUM ContactOnset
#define RODEND_CHOICE_FILE "core/contact_onsets.def"
#include "core/choice.hpp"

/// Integrator settings (a plain struct: one field per setting, with its unit).
struct IntegratorSettings {
  IntegratorMethod method = IntegratorMethod::dopri5;  ///< the integrator menu
  double abs_tol = 1e-6;                  ///< absolute tolerance on the scaled state [-]
  double rel_tol = 1e-6;                  ///< relative tolerance [-]
  double step = 1e-5;                     ///< fixed step (rk4) or first trial step (adaptive) [s]
  double max_step = 1e-3;                 ///< largest step of adaptive methods [s]
  double min_step = 1e-14;                ///< below this an adaptive step is an underflow [s]
  long long max_steps = 20'000'000;       ///< budget on accepted plus rejected steps [-]
  long long max_rhs_calls = 200'000'000;  ///< budget on right-hand-side calls [-]
  /// How contact onset is latched: "locate" finds the onset time on the step's interpolant by
  /// bisection and restarts there; "step-end" latches at the end of the step that crossed it.
  ContactOnset contact_onset = ContactOnset::locate;
};

/// How a run ended, from core/run_statuses.def (descriptions there).
#define RODEND_CHOICE_ENUM RunStatus
#define RODEND_CHOICE_FILE "core/run_statuses.def"
#include "core/choice.hpp"

}  // namespace rodend
