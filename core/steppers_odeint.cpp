// The Boost.Odeint part of the integrator menu: rk4, dopri5, cash_karp54, fehlberg78,
// bulirsch_stoer and rosenbrock4 (implicit, Jacobian by finite differences).
#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

#include "core/rosenbrock4_core.hpp"
#include "core/stepper.hpp"

namespace rodend::detail {
namespace odeint = boost::numeric::odeint;

void ScaledSystem::operator()(const state_t& z, state_t& dz, double t) {
  if (++calls > max_calls) {
    std::ostringstream m;
    m << "right-hand-side budget of " << max_calls << " calls exhausted at t = " << t << " s";
    throw RunFailure{RunStatus::rhs_budget_exhausted, m.str()};
  }
  for (std::size_t i = 0; i < z.size(); ++i) x[i] = z[i] * scale[i];
  scene.derivatives(t, x.data(), discrete, dx.data());
  for (std::size_t i = 0; i < z.size(); ++i) dz[i] = dx[i] / scale[i];
}

void ScaledSystem::jacobian(const state_t& z, double t, state_t& Jz) {
  const std::size_t n = z.size();
  if (!scene.exact_jacobian()) {
    calls += 2 * static_cast<long long>(n);  // the default's central differences
    if (calls > max_calls) {
      std::ostringstream m;
      m << "right-hand-side budget of " << max_calls << " calls exhausted at t = " << t << " s";
      throw RunFailure{RunStatus::rhs_budget_exhausted, m.str()};
    }
  }
  ++jacobians;
  for (std::size_t i = 0; i < n; ++i) x[i] = z[i] * scale[i];
  jx_.resize(n * n);
  scene.jacobian(t, x.data(), discrete, jx_.data());
  Jz.resize(n * n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) Jz[i * n + j] = jx_[i * n + j] * scale[j] / scale[i];
}

void ScaledSystem::time_derivative(const state_t& z, const state_t& dz, double t, state_t& dfdt) {
  const double ht = std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::abs(t));
  const double t1 = t + ht;
  dz2_.resize(z.size());
  (*this)(z, dz2_, t1);
  dfdt.resize(z.size());
  for (std::size_t i = 0; i < z.size(); ++i) dfdt[i] = (dz2_[i] - dz[i]) / (t1 - t);
}

namespace {

[[noreturn]] void underflow(double dt, double min_dt, double t) {
  std::ostringstream m;
  m << "step size underflow: step " << dt << " s < min_step " << min_dt << " s at t = " << t
    << " s";
  throw RunFailure{RunStatus::step_size_underflow, m.str()};
}

/// Classical fourth-order Runge-Kutta, fixed step. Its interpolant re-takes the step from the
/// previous state with the shorter step: exactly what the method would have done.
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
    const double h = std::min(dt_, t_limit - t_now);
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

/// Dormand-Prince 5(4) with step-size control and its free fourth-order dense output. The
/// control loop is ours (try_step of the FSAL controlled stepper) so rejections are counted.
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
        if (!clipped) dt_ = dt;  // keep the suggestion unless the step was only clipped
        break;
      }
      ++rejected;
      dt_ = dt;
      if (dt_ < min_dt_) underflow(dt_, min_dt_, t_prev);
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

/// An embedded Runge-Kutta pair without dense output (Cash-Karp 5(4), Fehlberg 7(8)) under
/// odeint's step-size controller. Steps land on sample times; for contact onsets the driver
/// bisects on the method's own re-take of the step to a trial time (interpolate), the state it
/// then restarts from at the located time.
template <class ErrorStepper>
class ControlledStepper final : public Stepper {
 public:
  ControlledStepper(ScaledSystem& sys, const IntegratorSettings& s)
      : sys_(sys),
        min_dt_(s.min_step),
        ctrl_(odeint::make_controlled(s.abs_tol, s.rel_tol, s.max_step, ErrorStepper())) {}
  void reset(const state_t& z, double t, double dt) override {
    z_now = z;
    t_now = t;
    dz_now.resize(z.size());
    sys_(z_now, dz_now, t_now);
    dt_ = dt;
  }
  void step(double t_limit) override {
    z_prev = z_now;
    dz_prev = dz_now;
    t_prev = t_now;
    double t = t_prev;
    while (true) {
      double dt = std::min(dt_, t_limit - t_prev);
      const bool clipped = dt < dt_;
      const auto res = ctrl_.try_step(std::ref(sys_), z_prev, dz_prev, t, z_now, dt);
      if (res == odeint::success) {
        ++accepted;
        if (!clipped) dt_ = dt;
        break;
      }
      ++rejected;
      dt_ = dt;
      if (dt_ < min_dt_) underflow(dt_, min_dt_, t_prev);
    }
    // land exactly on t_limit when the step was clipped to reach it
    t_now = (std::abs(t - t_limit) <= 1e-12 * std::max(1.0, std::abs(t_limit))) ? t_limit : t;
    sys_(z_now, dz_now, t_now);
  }
  void interpolate(double t, state_t& out) override {
    out = z_prev;
    if (t > t_prev) ctrl_.stepper().do_step(std::ref(sys_), out, dz_prev, t_prev, t - t_prev);
  }
  bool dense() const override { return false; }
  double suggested_dt() const override { return dt_; }

 private:
  ScaledSystem& sys_;
  double min_dt_;
  double dt_ = 0.0;
  state_t dz_prev, dz_now;
  odeint::controlled_runge_kutta<ErrorStepper> ctrl_;
};

/// An odeint dense-output stepper (Bulirsch-Stoer, Rosenbrock 4): odeint runs the step-size
/// control (rejections are not visible), we read the interpolant.
template <class Dense, class State, class System>
class DenseOutputStepper final : public Stepper {
 public:
  DenseOutputStepper(Dense dense, System system) : dense_(std::move(dense)), system_(system) {}
  void reset(const state_t& z, double t, double dt) override {
    to_state(z, buf_);
    dense_.initialize(buf_, t, dt);
    z_now = z;
    t_now = t;
  }
  void step(double t_limit) override {
    z_prev = z_now;
    t_prev = t_now;
    // do not step past the limit (the driver re-integrates up to a located contact onset)
    if (t_now + dense_.current_time_step() > t_limit) {
      to_state(z_now, buf_);
      dense_.initialize(buf_, t_now, t_limit - t_now);
    }
    const auto [t0, t1] = dense_.do_step(system_);
    (void)t0;
    t_now = t1;
    from_state(dense_.current_state(), z_now);
    ++accepted;
  }
  void interpolate(double t, state_t& out) override {
    dense_.calc_state(t, buf_);
    from_state(buf_, out);
  }
  bool dense() const override { return true; }
  double suggested_dt() const override { return dense_.current_time_step(); }

 private:
  static void to_state(const state_t& z, State& s) {
    s.resize(z.size());
    for (std::size_t i = 0; i < z.size(); ++i) s[i] = z[i];
  }
  static void from_state(const State& s, state_t& z) {
    z.resize(s.size());
    for (std::size_t i = 0; i < z.size(); ++i) z[i] = s[i];
  }
  Dense dense_;
  System system_;
  State buf_;
};

/// Rosenbrock 4 (Shampine's coefficients as in odeint; L-stable, order 4 with an embedded
/// order-3 error estimate and a third-order dense output) through the C++17 core, with the
/// scene's Jacobian. The step-size control is ours, as for dopri5: the error is measured with
/// odeint's error checker (max norm, |err_i| / (abs + rel |z_i|)), rejections are counted, and
/// the step grows by (1 / err)^(1/4) (the error estimate is of order 3, so O(h^4)), at most 5x.
class Rosenbrock4Stepper final : public Stepper {
 public:
  Rosenbrock4Stepper(ScaledSystem& sys, const IntegratorSettings& s)
      : sys_(sys),
        abs_(s.abs_tol),
        rel_(s.rel_tol),
        max_dt_(s.max_step),
        min_dt_(s.min_step),
        core_(make_rosenbrock4([&sys](const state_t& z, state_t& dz, double t) { sys(z, dz, t); },
                               [&sys, this](const state_t& z, double t, state_t& J, state_t& dfdt) {
                                 f0_.resize(z.size());
                                 sys(z, f0_, t);
                                 sys.jacobian(z, t, J);
                                 sys.time_derivative(z, f0_, t, dfdt);
                               })) {}
  void reset(const state_t& z, double t, double dt) override {
    z_now = z;
    t_now = t;
    dt_ = std::min(dt > 0.0 ? dt : max_dt_, max_dt_);
    core_->invalidate_jacobian();  // a reset may follow a change of the discrete state
  }
  void step(double t_limit) override {
    z_prev = z_now;
    t_prev = t_now;
    while (true) {
      const double dt = std::min(dt_, t_limit - t_prev);
      const bool clipped = dt < dt_;
      core_->try_step(z_prev, t_prev, dt, z_now, err_);
      double e = 0.0;
      for (std::size_t i = 0; i < err_.size(); ++i)
        e = std::max(e, std::abs(err_[i]) / (abs_ + rel_ * std::abs(z_now[i])));
      if (!std::isfinite(e)) e = 1e10;  // a diverged trial: shrink hard and retry
      // step factor: 0.9 (1/e)^(1/4), within [0.2, 5]
      const double grow = std::clamp(0.9 * std::pow(std::max(e, 1e-30), -0.25), 0.2, 5.0);
      if (e <= 1.0) {
        ++accepted;
        core_->accept();
        t_now = clipped ? t_limit : t_prev + dt;
        // after a clipped step keep the controller's step unless the error asks for less
        dt_ = std::min(max_dt_, clipped ? std::max(dt_, dt * grow) : dt * grow);
        if (last_rejected_) dt_ = std::min(dt_, dt);
        last_rejected_ = false;
        break;
      }
      ++rejected;
      last_rejected_ = true;
      dt_ = dt * grow;
      if (dt_ < min_dt_) underflow(dt_, min_dt_, t_prev);
    }
  }
  void interpolate(double t, state_t& out) override {
    core_->calc_state(t, out, z_prev, t_prev, z_now, t_now);
  }
  bool dense() const override { return true; }
  double suggested_dt() const override { return dt_; }

 private:
  ScaledSystem& sys_;
  double abs_, rel_, max_dt_, min_dt_;
  double dt_ = 0.0;
  bool last_rejected_ = false;
  state_t err_, f0_;
  std::unique_ptr<Rosenbrock4Core> core_;
};

}  // namespace

std::unique_ptr<Stepper> make_odeint_stepper(ScaledSystem& sys, const IntegratorSettings& s) {
  if (s.method == "rk4") return std::make_unique<Rk4Stepper>(sys, s.step);
  if (s.method == "dopri5") return std::make_unique<Dopri5Stepper>(sys, s);
  if (s.method == "cash_karp54")
    return std::make_unique<ControlledStepper<odeint::runge_kutta_cash_karp54<state_t>>>(sys, s);
  if (s.method == "fehlberg78")
    return std::make_unique<ControlledStepper<odeint::runge_kutta_fehlberg78<state_t>>>(sys, s);
  if (s.method == "bulirsch_stoer") {
    using BS = odeint::bulirsch_stoer_dense_out<state_t>;
    BS bs(s.abs_tol, s.rel_tol, 1.0, 1.0, s.max_step);
    auto sysref = std::ref(sys);
    return std::make_unique<DenseOutputStepper<BS, state_t, decltype(sysref)>>(bs, sysref);
  }
  if (s.method == "rosenbrock4") return std::make_unique<Rosenbrock4Stepper>(sys, s);
  return nullptr;
}

std::unique_ptr<Stepper> make_stepper(ScaledSystem& sys, const Scene& scene,
                                      const IntegratorSettings& s) {
  if (s.method.rfind("cvode", 0) == 0) return make_cvode_stepper(sys, scene, s);
  if (auto st = make_odeint_stepper(sys, s)) return st;
  throw InputError("integrator.method", "unknown method '" + s.method + "'");
}

}  // namespace rodend::detail
