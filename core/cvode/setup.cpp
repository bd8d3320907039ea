// CvodeStepper's setup: CVODE's objects, its tolerances and limits, the nonlinear solver of
// the method (BDF: Newton with a dense LU; Adams: fixed point), and the root functions.
#include <new>

#include "core/cvode/cvode_stepper.hpp"
#include "core/sundials_kernels.hpp"

namespace rodend::detail {

CvodeHandles::~CvodeHandles() {
  if (mem) CVodeFree(&mem);
  if (ls) SUNLinSolFree(ls);
  if (A) SUNMatDestroy(A);
  if (nls) SUNNonlinSolFree(nls);
  if (y) N_VDestroy(y);
  if (tmp) N_VDestroy(tmp);
  if (ctx) SUNContext_Free(&ctx);
}

CvodeStepper::CvodeStepper(ScaledSystem& sys, const Scene& scene, const IntegratorSettings& s)
    : sys_(sys), scene_(scene), s_(s), n_(static_cast<sunindextype>(sys.scale.size())) {
  create();
  set_tolerances_and_limits();
  if (s.method != IntegratorMethod::cvode_adams)
    attach_newton_lu();
  else
    attach_fixed_point();
  init_roots();
}

/// The context, the state vectors and CVODE's memory, initialised on this right-hand side.
void CvodeStepper::create() {
  if (SUNContext_Create(nullptr, &h_.ctx) != 0) fail("cannot create a SUNDIALS context");
  h_.y = N_VNew_Serial(n_, h_.ctx);
  h_.tmp = N_VNew_Serial(n_, h_.ctx);
  const bool bdf = s_.method != IntegratorMethod::cvode_adams;
  h_.mem = CVodeCreate(bdf ? CV_BDF : CV_ADAMS, h_.ctx);
  if (!h_.y || !h_.tmp || !h_.mem) throw std::bad_alloc();  // only an allocation fails here
  use_fast_ops(h_.y);  // before CVodeInit: CVODE's vectors are clones of y
  use_fast_ops(h_.tmp);
  z_buf_.resize(static_cast<std::size_t>(n_));
  dz_buf_.resize(static_cast<std::size_t>(n_));
  N_VConst(0.0, h_.y);
  check(CVodeInit(h_.mem, &CvodeStepper::rhs, 0.0, h_.y), "CVodeInit");
  check(CVodeSetUserData(h_.mem, this), "CVodeSetUserData");
}

void CvodeStepper::set_tolerances_and_limits() {
  // scalar tolerances on the scaled state, as for every method of the menu
  check(CVodeSStolerances(h_.mem, s_.rel_tol, s_.abs_tol), "CVodeSStolerances");
  check(CVodeSetMaxStep(h_.mem, s_.max_step), "CVodeSetMaxStep");
  check(CVodeSetMinStep(h_.mem, 0.0), "CVodeSetMinStep");
  check(CVodeSetMaxNumSteps(h_.mem, -1), "CVodeSetMaxNumSteps");  // the driver keeps the budget
  check(CVodeSetMaxHnilWarns(h_.mem, -1), "CVodeSetMaxHnilWarns");
}

/// BDF: Newton iteration with a dense LU (core/sundials_kernels.hpp), on the scene's exact
/// Jacobian when it has one.
void CvodeStepper::attach_newton_lu() {
  h_.A = SUNDenseMatrix(n_, n_, h_.ctx);
  h_.ls = make_dense_lu(h_.ctx);
  if (!h_.A || !h_.ls) throw std::bad_alloc();
  use_fast_ops(h_.A);  // before CVodeSetLinearSolver: the saved Jacobian is a clone of A
  check(CVodeSetLinearSolver(h_.mem, h_.ls, h_.A), "CVodeSetLinearSolver");
  // a scene's exact Jacobian instead of CVODE's difference quotients (n + 1 calls each)
  if (scene_.exact_jacobian()) check(CVodeSetJacFn(h_.mem, &CvodeStepper::jac), "CVodeSetJacFn");
  // BDF of order 3-5 is unstable for eigenvalues near the imaginary axis (the rod-end
  // contact mode, ~3 kHz, lightly damped): CVODE's stability-limit detection lowers the
  // order there instead of cutting the step. Measured on the thesis cycle (issue 34; steps
  // without -> with, one per tolerance 1e-5..1e-8): kinematic 4372, 5702, 12454, 13960 ->
  // 4578, 5355, 7139, 9251; actuator 5905, 5641, 8679, 17914 -> 5064, 5663, 7189, 11087,
  // errors of the same order. Without it the step count jumped with round-off (the
  // kinematic 1e-7 took 7121 or 12454 steps depending on the LU's rounding).
  if (s_.method == IntegratorMethod::cvode_bdf) {
    check(CVodeSetStabLimDet(h_.mem, SUNTRUE), "CVodeSetStabLimDet");
    return;
  }
  // cvode_bdf3: orders 1-3 only, where the detection never acted on the thesis cycle (runs with
  // and without it bit-identical at order 3) and cost 6 % of the case (Debian's library is
  // built without optimisation). Kinematic thesis cycle at 1e-6 (docs/performance.md, "CVODE's
  // own settings"): 222.4 M -> 190.4 M instructions, work-precision error 6.8e-4 -> 1.0e-3.
  check(CVodeSetMaxOrd(h_.mem, 3), "CVodeSetMaxOrd");
}

/// Adams: fixed-point iteration (no Jacobian).
void CvodeStepper::attach_fixed_point() {
  h_.nls = SUNNonlinSol_FixedPoint(h_.y, 0, h_.ctx);
  check(CVodeSetNonlinearSolver(h_.mem, h_.nls), "CVodeSetNonlinearSolver");
}

/// One root function per contact, its penetration: onsets only (upward crossings).
void CvodeStepper::init_roots() {
  const int nc = scene_.contact_count();
  if (nc == 0) return;
  check(CVodeRootInit(h_.mem, nc, &CvodeStepper::roots_fn), "CVodeRootInit");
  std::vector<int> dir(static_cast<std::size_t>(nc), 1);
  check(CVodeSetRootDirection(h_.mem, dir.data()), "CVodeSetRootDirection");
  check(CVodeSetNoInactiveRootWarn(h_.mem), "CVodeSetNoInactiveRootWarn");
  found_.resize(static_cast<std::size_t>(nc));
}

}  // namespace rodend::detail
