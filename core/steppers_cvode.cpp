// SUNDIALS CVODE in the integrator menu (core/cvode/cvode_stepper.hpp): the step stage, one
// internal step at a time (CV_ONE_STEP), and the factory.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/cvode/cvode_stepper.hpp"

namespace rodend::detail {

void CvodeStepper::reset(const state_t& z, double t, double dt) {
  std::copy(z.begin(), z.end(), N_VGetArrayPointer(h_.y));
  check(CVodeReInit(h_.mem, t, h_.y), "CVodeReInit");
  check(CVodeSetInitStep(h_.mem, dt > 0.0 ? std::min(dt, s_.max_step) : 0.0), "CVodeSetInitStep");
  z_now = z;
  t_now = t;
  counted_steps_ = counted_fails_ = 0;
}

void CvodeStepper::step(double t_limit) {
  z_prev = z_now;
  t_prev = t_now;
  roots.clear();
  // never past the end of the run (tstop), but free to step over sample times (dense)
  check(CVodeSetStopTime(h_.mem, t_limit), "CVodeSetStopTime");
  double t = t_prev;
  const int flag = CVode(h_.mem, t_limit, h_.y, &t, CV_ONE_STEP);
  rethrow_pending();
  if (flag < 0) throw_failure(flag);
  if (flag == CV_ROOT_RETURN) collect_roots();
  t_now = t;
  const double* y = N_VGetArrayPointer(h_.y);
  z_now.assign(y, y + n_);
  count_steps();
}

/// A failed CVode call: a step too small for its error test or its nonlinear solver is an
/// underflow; any other failure a non-finite state.
void CvodeStepper::throw_failure(int flag) const {
  std::ostringstream m;
  m << "CVODE failed at t = " << t_prev << " s: " << CVodeGetReturnFlagName(flag);
  const auto status = (flag == CV_TOO_CLOSE || flag == CV_ERR_FAILURE || flag == CV_CONV_FAILURE)
                          ? RunStatus::step_size_underflow
                          : RunStatus::non_finite_state;
  throw RunFailure{status, m.str()};
}

/// The contacts whose onset the step ended at.
void CvodeStepper::collect_roots() {
  check(CVodeGetRootInfo(h_.mem, found_.data()), "CVodeGetRootInfo");
  for (std::size_t i = 0; i < found_.size(); ++i)
    if (found_[i] > 0) roots.push_back(static_cast<int>(i));
}

/// CVODE's own counts (cumulative since the last re-initialisation) added to the stepper's.
void CvodeStepper::count_steps() {
  long nst = 0, netf = 0, nni_fail = 0;
  CVodeGetNumSteps(h_.mem, &nst);
  CVodeGetNumErrTestFails(h_.mem, &netf);
  CVodeGetNumNonlinSolvConvFails(h_.mem, &nni_fail);
  accepted += nst - counted_steps_;
  rejected += (netf + nni_fail) - counted_fails_;
  counted_steps_ = nst;
  counted_fails_ = netf + nni_fail;
}

void CvodeStepper::interpolate(double t, state_t& out) {
  check(CVodeGetDky(h_.mem, t, 0, h_.tmp), "CVodeGetDky");
  const double* y = N_VGetArrayPointer(h_.tmp);
  out.assign(y, y + n_);
}

double CvodeStepper::suggested_dt() const {
  double h = 0.0;
  CVodeGetCurrentStep(h_.mem, &h);
  return h;
}

std::unique_ptr<Stepper> make_cvode_stepper(ScaledSystem& sys, const Scene& scene,
                                            const IntegratorSettings& s) {
  return std::make_unique<CvodeStepper>(sys, scene, s);
}

}  // namespace rodend::detail
