// CvodeStepper's callbacks: the right-hand side, the Jacobian and the root functions CVODE
// calls. Nothing may unwind through CVODE (C): a callback keeps a failure and returns -1
// (unrecoverable), CVODE stops, and step() throws it again (rethrow_pending).
#include <algorithm>
#include <new>
#include <utility>

#include "core/cvode/cvode_stepper.hpp"

namespace rodend::detail {

int CvodeStepper::rhs(double t, N_Vector y, N_Vector ydot, void* user) {
  auto* self = static_cast<CvodeStepper*>(user);
  const double* yy = N_VGetArrayPointer(y);
  self->z_buf_.assign(yy, yy + self->n_);
  try {
    self->sys_(self->z_buf_, self->dz_buf_, t);
  } catch (const RunFailure& f) {
    self->pending_ = f;
    return -1;
  } catch (...) {
    self->pending_error_ = std::current_exception();
    return -1;
  }
  std::copy(self->dz_buf_.begin(), self->dz_buf_.end(), N_VGetArrayPointer(ydot));
  return 0;
}

/// The scene's exact Jacobian in the scaled variables (ScaledSystem::jacobian), written into
/// CVODE's dense matrix (column-major).
int CvodeStepper::jac(double t, N_Vector y, N_Vector, SUNMatrix J, void* user, N_Vector, N_Vector,
                      N_Vector) {
  auto* self = static_cast<CvodeStepper*>(user);
  const double* yy = N_VGetArrayPointer(y);
  self->z_buf_.assign(yy, yy + self->n_);
  try {
    self->sys_.jacobian(self->z_buf_, t, self->jz_);
  } catch (...) {
    self->pending_error_ = std::current_exception();
    return -1;
  }
  const auto n = static_cast<std::size_t>(self->n_);
  double* a = SUNDenseMatrix_Data(J);
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t i = 0; i < n; ++i) a[j * n + i] = self->jz_[i * n + j];
  return 0;
}

/// The penetration of every contact (CVODE finds where one crosses zero upwards).
int CvodeStepper::roots_fn(double, N_Vector y, double* g, void* user) {
  auto* self = static_cast<CvodeStepper*>(user);
  const double* yy = N_VGetArrayPointer(y);
  state_t& x = self->sys_.x;
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = yy[i] * self->sys_.scale[i];
  try {
    for (int c = 0; c < self->scene_.contact_count(); ++c)
      g[c] = self->scene_.contact_gap(c, x.data()).penetration;
  } catch (...) {
    self->pending_error_ = std::current_exception();
    return -1;
  }
  return 0;
}

/// Throws what a callback kept (a RunFailure, or another exception), if anything.
void CvodeStepper::rethrow_pending() {
  if (pending_error_) std::rethrow_exception(std::exchange(pending_error_, nullptr));
  if (pending_.status != RunStatus::ok)
    throw std::exchange(pending_, RunFailure{RunStatus::ok, {}});
}

/// A CVODE call's flag: a callback's failure first, an allocation failure as std::bad_alloc
/// (the environment's, not the case's), else a RunFailure naming the call.
void CvodeStepper::check(int flag, const char* what) {
  if (flag < 0) {
    rethrow_pending();
    if (flag == CV_MEM_FAIL) throw std::bad_alloc();
    fail(std::string(what) + " failed: " + CVodeGetReturnFlagName(flag));
  }
}

void CvodeStepper::fail(const std::string& m) {
  throw RunFailure{RunStatus::non_finite_state, "CVODE: " + m};
}

}  // namespace rodend::detail
