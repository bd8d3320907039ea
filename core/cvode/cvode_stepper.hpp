// Internal to core: SUNDIALS CVODE in the integrator menu, BDF (stiff, Newton with a dense LU,
// ours; of order up to 5, or up to 3 as cvode_bdf3) and Adams (non-stiff, fixed-point
// iteration), on the same scaled right-hand side, one
// internal step at a time (CV_ONE_STEP), with CVODE's dense output and its own root finding
// for contact onset (the penetration of each contact, crossing zero upwards). In stages:
//   core/cvode/setup.cpp      CVODE's objects, its tolerances and limits, the BDF's linear
//                             solver or the Adams' fixed point, the root functions
//   core/steppers_cvode.cpp   reset, step (its failures, its roots, its counts), interpolate
//   core/cvode/callbacks.cpp  the right-hand side, the Jacobian and the root functions CVODE
//                             calls, and the errors they keep for step() to throw
#pragma once

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <exception>
#include <string>
#include <vector>

#include "core/stepper.hpp"

namespace rodend::detail {

/// CVODE's objects, owned: freed together, in the order CVODE needs (its memory first).
struct CvodeHandles {
  CvodeHandles() = default;
  CvodeHandles(const CvodeHandles&) = delete;
  CvodeHandles& operator=(const CvodeHandles&) = delete;
  ~CvodeHandles();
  SUNContext ctx = nullptr;
  N_Vector y = nullptr, tmp = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver ls = nullptr;
  SUNNonlinearSolver nls = nullptr;
  void* mem = nullptr;
};

class CvodeStepper final : public Stepper {
 public:
  CvodeStepper(ScaledSystem& sys, const Scene& scene, const IntegratorSettings& s);
  void reset(const state_t& z, double t, double dt) override;
  void step(double t_limit) override;
  void interpolate(double t, state_t& out) override;
  bool dense() const override { return true; }
  bool finds_roots() const override { return true; }
  double suggested_dt() const override;

 private:
  // setup (core/cvode/setup.cpp)
  void create();
  void set_tolerances_and_limits();
  void attach_newton_lu();
  void attach_fixed_point();
  void init_roots();
  // step (core/steppers_cvode.cpp)
  [[noreturn]] void throw_failure(int flag) const;
  void collect_roots();
  void count_steps();
  // callbacks (core/cvode/callbacks.cpp)
  static int rhs(double t, N_Vector y, N_Vector ydot, void* user);
  static int jac(double t, N_Vector y, N_Vector, SUNMatrix J, void* user, N_Vector, N_Vector,
                 N_Vector);
  static int roots_fn(double, N_Vector y, double* g, void* user);
  void rethrow_pending();
  void check(int flag, const char* what);
  [[noreturn]] void fail(const std::string& m);

  // the model: read only
  ScaledSystem& sys_;
  const Scene& scene_;
  IntegratorSettings s_;
  sunindextype n_;
  // CVODE's state
  CvodeHandles h_;
  // scratch, the counts taken from CVODE, and a failure a callback kept
  state_t z_buf_, dz_buf_, jz_;
  std::vector<int> found_;
  long counted_steps_ = 0, counted_fails_ = 0;
  RunFailure pending_{RunStatus::ok, {}};
  std::exception_ptr pending_error_;
};

}  // namespace rodend::detail
