// SUNDIALS CVODE in the integrator menu: BDF (stiff, Newton with a dense LU, ours) and
// Adams (non-stiff, fixed-point iteration), on the same scaled right-hand side, one internal
// step at a time (CV_ONE_STEP), with CVODE's dense output and its own root finding for
// contact onset (the penetration of each contact, crossing zero upwards).
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <cmath>
#include <exception>
#include <new>
#include <sstream>
#include <utility>

#include "core/stepper.hpp"
#include "core/sundials_kernels.hpp"

namespace rodend::detail {
namespace {

class CvodeStepper final : public Stepper {
 public:
  CvodeStepper(ScaledSystem& sys, const Scene& scene, const IntegratorSettings& s)
      : sys_(sys), scene_(scene), s_(s), n_(static_cast<sunindextype>(sys.scale.size())) {
    if (SUNContext_Create(nullptr, &ctx_) != 0) fail("cannot create a SUNDIALS context");
    y_ = N_VNew_Serial(n_, ctx_);
    tmp_ = N_VNew_Serial(n_, ctx_);
    const bool bdf = s.method == IntegratorMethod::cvode_bdf;
    mem_ = CVodeCreate(bdf ? CV_BDF : CV_ADAMS, ctx_);
    if (!y_ || !tmp_ || !mem_) throw std::bad_alloc();  // only an allocation fails here
    use_fast_ops(y_);  // before CVodeInit: CVODE's vectors are clones of y_
    use_fast_ops(tmp_);
    z_buf_.resize(static_cast<std::size_t>(n_));
    dz_buf_.resize(static_cast<std::size_t>(n_));
    N_VConst(0.0, y_);
    check(CVodeInit(mem_, &CvodeStepper::rhs, 0.0, y_), "CVodeInit");
    check(CVodeSetUserData(mem_, this), "CVodeSetUserData");
    // scalar tolerances on the scaled state, as for every method of the menu
    check(CVodeSStolerances(mem_, s.rel_tol, s.abs_tol), "CVodeSStolerances");
    check(CVodeSetMaxStep(mem_, s.max_step), "CVodeSetMaxStep");
    check(CVodeSetMinStep(mem_, 0.0), "CVodeSetMinStep");
    check(CVodeSetMaxNumSteps(mem_, -1), "CVodeSetMaxNumSteps");  // the driver keeps the budget
    check(CVodeSetMaxHnilWarns(mem_, -1), "CVodeSetMaxHnilWarns");
    if (bdf) {
      A_ = SUNDenseMatrix(n_, n_, ctx_);
      ls_ = make_dense_lu(ctx_);
      if (!A_ || !ls_) throw std::bad_alloc();
      use_fast_ops(A_);  // before CVodeSetLinearSolver: the saved Jacobian is a clone of A_
      check(CVodeSetLinearSolver(mem_, ls_, A_), "CVodeSetLinearSolver");
      // a scene's exact Jacobian instead of CVODE's difference quotients (n + 1 calls each)
      if (scene.exact_jacobian()) check(CVodeSetJacFn(mem_, &CvodeStepper::jac), "CVodeSetJacFn");
      // BDF of order 3-5 is unstable for eigenvalues near the imaginary axis (the rod-end
      // contact mode, ~3 kHz, lightly damped): CVODE's stability-limit detection lowers the
      // order there instead of cutting the step. Measured on the thesis cycle (issue 34; steps
      // without -> with, one per tolerance 1e-5..1e-8): kinematic 4372, 5702, 12454, 13960 ->
      // 4578, 5355, 7139, 9251; actuator 5905, 5641, 8679, 17914 -> 5064, 5663, 7189, 11087,
      // errors of the same order. Without it the step count jumped with round-off (the
      // kinematic 1e-7 took 7121 or 12454 steps depending on the LU's rounding).
      check(CVodeSetStabLimDet(mem_, SUNTRUE), "CVodeSetStabLimDet");
    } else {
      nls_ = SUNNonlinSol_FixedPoint(y_, 0, ctx_);
      check(CVodeSetNonlinearSolver(mem_, nls_), "CVodeSetNonlinearSolver");
    }
    const int nc = scene.contact_count();
    if (nc > 0) {
      check(CVodeRootInit(mem_, nc, &CvodeStepper::roots_fn), "CVodeRootInit");
      std::vector<int> dir(static_cast<std::size_t>(nc), 1);  // onsets only: upward crossings
      check(CVodeSetRootDirection(mem_, dir.data()), "CVodeSetRootDirection");
      check(CVodeSetNoInactiveRootWarn(mem_), "CVodeSetNoInactiveRootWarn");
      found_.resize(static_cast<std::size_t>(nc));
    }
  }
  ~CvodeStepper() override {
    if (mem_) CVodeFree(&mem_);
    if (ls_) SUNLinSolFree(ls_);
    if (A_) SUNMatDestroy(A_);
    if (nls_) SUNNonlinSolFree(nls_);
    if (y_) N_VDestroy(y_);
    if (tmp_) N_VDestroy(tmp_);
    if (ctx_) SUNContext_Free(&ctx_);
  }

  void reset(const state_t& z, double t, double dt) override {
    std::copy(z.begin(), z.end(), N_VGetArrayPointer(y_));
    check(CVodeReInit(mem_, t, y_), "CVodeReInit");
    check(CVodeSetInitStep(mem_, dt > 0.0 ? std::min(dt, s_.max_step) : 0.0), "CVodeSetInitStep");
    z_now = z;
    t_now = t;
    counted_steps_ = counted_fails_ = 0;
  }
  void step(double t_limit) override {
    z_prev = z_now;
    t_prev = t_now;
    roots.clear();
    // never past the end of the run (tstop), but free to step over sample times (dense)
    check(CVodeSetStopTime(mem_, t_limit), "CVodeSetStopTime");
    double t = t_prev;
    const int flag = CVode(mem_, t_limit, y_, &t, CV_ONE_STEP);
    rethrow_pending();
    if (flag < 0) {
      std::ostringstream m;
      m << "CVODE failed at t = " << t_prev << " s: " << CVodeGetReturnFlagName(flag);
      const auto status =
          (flag == CV_TOO_CLOSE || flag == CV_ERR_FAILURE || flag == CV_CONV_FAILURE)
              ? RunStatus::step_size_underflow
              : RunStatus::non_finite_state;
      throw RunFailure{status, m.str()};
    }
    if (flag == CV_ROOT_RETURN) {
      check(CVodeGetRootInfo(mem_, found_.data()), "CVodeGetRootInfo");
      for (std::size_t i = 0; i < found_.size(); ++i)
        if (found_[i] > 0) roots.push_back(static_cast<int>(i));
    }
    t_now = t;
    const double* y = N_VGetArrayPointer(y_);
    z_now.assign(y, y + n_);
    // CVODE's own counts (cumulative since the last re-initialisation)
    long nst = 0, netf = 0, nni_fail = 0;
    CVodeGetNumSteps(mem_, &nst);
    CVodeGetNumErrTestFails(mem_, &netf);
    CVodeGetNumNonlinSolvConvFails(mem_, &nni_fail);
    accepted += nst - counted_steps_;
    rejected += (netf + nni_fail) - counted_fails_;
    counted_steps_ = nst;
    counted_fails_ = netf + nni_fail;
  }
  void interpolate(double t, state_t& out) override {
    check(CVodeGetDky(mem_, t, 0, tmp_), "CVodeGetDky");
    const double* y = N_VGetArrayPointer(tmp_);
    out.assign(y, y + n_);
  }
  bool dense() const override { return true; }
  bool finds_roots() const override { return true; }
  double suggested_dt() const override {
    double h = 0.0;
    CVodeGetCurrentStep(mem_, &h);
    return h;
  }

 private:
  static int rhs(double t, N_Vector y, N_Vector ydot, void* user) {
    auto* self = static_cast<CvodeStepper*>(user);
    const double* yy = N_VGetArrayPointer(y);
    self->z_buf_.assign(yy, yy + self->n_);
    // nothing may unwind through CVODE (C): a failure is kept, CVODE stops (-1: unrecoverable)
    // and step() throws it again
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
  static int jac(double t, N_Vector y, N_Vector, SUNMatrix J, void* user, N_Vector, N_Vector,
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
  static int roots_fn(double, N_Vector y, double* g, void* user) {
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
  void rethrow_pending() {
    if (pending_error_) std::rethrow_exception(std::exchange(pending_error_, nullptr));
    if (pending_.status != RunStatus::ok)
      throw std::exchange(pending_, RunFailure{RunStatus::ok, {}});
  }
  void check(int flag, const char* what) {
    if (flag < 0) {
      rethrow_pending();
      if (flag == CV_MEM_FAIL) throw std::bad_alloc();  // the environment's, not the case's
      fail(std::string(what) + " failed: " + CVodeGetReturnFlagName(flag));
    }
  }
  [[noreturn]] void fail(const std::string& m) {
    throw RunFailure{RunStatus::non_finite_state, "CVODE: " + m};
  }

  ScaledSystem& sys_;
  const Scene& scene_;
  IntegratorSettings s_;
  sunindextype n_;
  SUNContext ctx_ = nullptr;
  N_Vector y_ = nullptr, tmp_ = nullptr;
  SUNMatrix A_ = nullptr;
  SUNLinearSolver ls_ = nullptr;
  SUNNonlinearSolver nls_ = nullptr;
  void* mem_ = nullptr;
  state_t z_buf_, dz_buf_, jz_;
  std::vector<int> found_;
  long counted_steps_ = 0, counted_fails_ = 0;
  RunFailure pending_{RunStatus::ok, {}};
  std::exception_ptr pending_error_;
};

}  // namespace

std::unique_ptr<Stepper> make_cvode_stepper(ScaledSystem& sys, const Scene& scene,
                                            const IntegratorSettings& s) {
  return std::make_unique<CvodeStepper>(sys, scene, s);
}

}  // namespace rodend::detail
