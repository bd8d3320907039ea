// The Boost.Odeint part of the integrator menu: rk4, dopri5, cash_karp54, fehlberg78,
// bulirsch_stoer, and rosenbrock4 (implicit, odeint's coefficients corrected, on Eigen).
#include <Eigen/Dense>
#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>

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
  if (watch && watch->armed) watch->see(scene, discrete, t, x.data());
  for (std::size_t i = 0; i < z.size(); ++i) dz[i] = dx[i] / scale[i];
}

void ScaledSystem::jacobian(const state_t& z, double t, state_t& Jz) {
  const std::size_t n = z.size();
  if (!scene.exact_jacobian()) {
    calls += scene.jacobian_cost();  // the default's forward differences
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

/// A trial step that left the state's domain (a contact pushed far past its law's range by too
/// long a step gives an infinite or NaN force) is not finite. odeint's error checker takes the
/// largest error with std::max, which passes over a NaN, so it accepts such a trial with an
/// error of zero (and lengthens the next step); the steppers below reject it and shrink the step
/// by kDivergedShrink instead, as odeint does for an error far above 1.
constexpr double kDivergedShrink = 0.2;

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
      if (res == odeint::success && !(all_finite(z_now) && all_finite(dz_now))) {
        t = t_prev;  // odeint took it (see kDivergedShrink): a rejection, shrunk hard
        dt = kDivergedShrink * dt;
      } else if (res == odeint::success) {
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
      if (res == odeint::success && !all_finite(z_now)) {
        t = t_prev;  // odeint took it (see kDivergedShrink): a rejection, shrunk hard
        dt = kDivergedShrink * dt;
      } else if (res == odeint::success) {
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

/// Rosenbrock 4 (L-stable, order 4 with an embedded order-3 error estimate and a third-order
/// dense output): Hairer and Wanner's RODAS coefficient set as odeint 1.74 ships it
/// (rosenbrock4.hpp, gamma = 0.25, c = 0.386, 0.21, 0.63), with the sign of d4 corrected, on
/// Eigen vectors and Eigen's LU (odeint's own runs on uBLAS, whose factorisations and solves took
/// 40 % of the instructions at 30 states). d_i is the coefficient of h df/dt in stage i; odeint
/// has d4 = +0.0362, Hairer's rodas.f -0.0362. With the wrong sign every right-hand side that
/// depends on t (every prescribed motion) makes the step first order: local error O(h^2) where
/// O(h^5) is due, and the embedded estimate O(h^2) too. That is why rosenbrock4 took 1.4 million
/// steps of ~2e-6 s on one thesis cycle. Measured on y'' = -y + cos 3t (one step from t = 0.3):
/// local error 8.0e-4, 2.0e-4, 5.0e-5, 1.3e-5 for h = 0.1 ... 0.0125 with +0.0362; 3.2e-8,
/// 1.1e-9, 3.8e-11, 1.2e-12 with -0.0362 (order 5). Test: "[rosenbrock4]".
///
/// The step-size control is ours, as for dopri5: the error is measured with odeint's error
/// checker (max norm, |err_i| / (abs + rel |z_i|)), rejections are counted, and the step grows
/// by 0.9 (1 / err)^(1/4) (the estimate is O(h^4)), within [0.2, 5]. The Jacobian (the scene's,
/// Scene::jacobian) and f are evaluated once per step start: a retry reuses them.
class Rosenbrock4Stepper final : public Stepper {
  struct Coefficients {
    static constexpr double gamma = 0.25;
    static constexpr double d1 = 0.25, d2 = -0.1043, d3 = 0.1035, d4 = -0.3620000000000023e-01;
    static constexpr double c2 = 0.386, c3 = 0.21, c4 = 0.63;
    static constexpr double c21 = -0.5668800000000000e+01;
    static constexpr double a21 = 0.1544000000000000e+01;
    static constexpr double c31 = -0.2430093356833875e+01, c32 = -0.2063599157091915e+00;
    static constexpr double a31 = 0.9466785280815826e+00, a32 = 0.2557011698983284e+00;
    static constexpr double c41 = -0.1073529058151375e+00, c42 = -0.9594562251023355e+01,
                            c43 = -0.2047028614809616e+02;
    static constexpr double a41 = 0.3314825187068521e+01, a42 = 0.2896124015972201e+01,
                            a43 = 0.9986419139977817e+00;
    static constexpr double c51 = 0.7496443313967647e+01, c52 = -0.1024680431464352e+02,
                            c53 = -0.3399990352819905e+02, c54 = 0.1170890893206160e+02;
    static constexpr double a51 = 0.1221224509226641e+01, a52 = 0.6019134481288629e+01,
                            a53 = 0.1253708332932087e+02, a54 = -0.6878860361058950e+00;
    static constexpr double c61 = 0.8083246795921522e+01, c62 = -0.7981132988064893e+01,
                            c63 = -0.3152159432874371e+02, c64 = 0.1631930543123136e+02,
                            c65 = -0.6058818238834054e+01;
    static constexpr double d21 = 0.1012623508344586e+02, d22 = -0.7487995877610167e+01,
                            d23 = -0.3480091861555747e+02, d24 = -0.7992771707568823e+01,
                            d25 = 0.1025137723295662e+01;
    static constexpr double d31 = -0.6762803392801253e+00, d32 = 0.6087714651680015e+01,
                            d33 = 0.1643084320892478e+02, d34 = 0.2476722511418386e+02,
                            d35 = -0.6594389125716872e+01;
  };
  using Vec = Eigen::VectorXd;

 public:
  Rosenbrock4Stepper(ScaledSystem& sys, const IntegratorSettings& s)
      : sys_(sys), abs_(s.abs_tol), rel_(s.rel_tol), max_dt_(s.max_step), min_dt_(s.min_step) {}
  void reset(const state_t& z, double t, double dt) override {
    z_now = z;
    t_now = t;
    dt_ = std::min(dt > 0.0 ? dt : max_dt_, max_dt_);
    last_rejected_ = false;
  }
  void step(double t_limit) override {
    z_prev = z_now;
    t_prev = t_now;
    prepare_step_start();
    while (true) {
      const double dt = std::min(dt_, t_limit - t_prev);
      const bool clipped = dt < dt_;
      try_step(dt);
      double e = 0.0;
      for (std::size_t i = 0; i < z_now.size(); ++i) {
        const double r =
            std::abs(err_[static_cast<Eigen::Index>(i)]) / (abs_ + rel_ * std::abs(z_now[i]));
        if (!(r <= e)) e = r;  // not std::max, which would pass over a NaN
      }
      if (!std::isfinite(e)) e = 1e10;  // a diverged trial: shrink hard and retry
      const double grow = std::clamp(0.9 * std::pow(std::max(e, 1e-30), -0.25), 0.2, 5.0);
      if (e <= 1.0) {
        ++accepted;
        using C = Coefficients;
        cont3_ = C::d21 * g_[0] + C::d22 * g_[1] + C::d23 * g_[2] + C::d24 * g_[3] + C::d25 * g_[4];
        cont4_ = C::d31 * g_[0] + C::d32 * g_[1] + C::d33 * g_[2] + C::d34 * g_[3] + C::d35 * g_[4];
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
    const double h = t_now - t_prev;
    const double s = h > 0.0 ? (t - t_prev) / h : 1.0, s1 = 1.0 - s;
    out.resize(z_now.size());
    for (std::size_t i = 0; i < z_now.size(); ++i) {
      const auto k = static_cast<Eigen::Index>(i);
      out[i] = z_prev[i] * s1 + s * (z_now[i] + s1 * (cont3_[k] + s * cont4_[k]));
    }
  }
  bool dense() const override { return true; }
  double suggested_dt() const override { return dt_; }

 private:
  /// f, the Jacobian and df/dt at the step's start (z_prev, t_prev), in Eigen form.
  void prepare_step_start() {
    const std::size_t n = z_prev.size();
    const auto m = static_cast<Eigen::Index>(n);
    f0_.resize(n);
    sys_(z_prev, f0_, t_prev);
    sys_.jacobian(z_prev, t_prev, jbuf_);
    sys_.time_derivative(z_prev, f0_, t_prev, dfdt_buf_);
    J_ = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        jbuf_.data(), m, m);
    x0_ = Eigen::Map<const Vec>(z_prev.data(), m);
    f0v_ = Eigen::Map<const Vec>(f0_.data(), m);
    dfdt_ = Eigen::Map<const Vec>(dfdt_buf_.data(), m);
    lu_dt_ = -1.0;
  }
  /// f at x (Eigen) and t, into fx_.
  void eval(const Vec& x, double t) {
    const auto m = x.size();
    zs_.assign(x.data(), x.data() + m);
    fs_.resize(static_cast<std::size_t>(m));
    sys_(zs_, fs_, t);
    fx_ = Eigen::Map<const Vec>(fs_.data(), m);
  }
  void try_step(double dt) {
    using C = Coefficients;
    const auto m = x0_.size();
    if (dt != lu_dt_) {
      M_ = -J_;
      M_.diagonal().array() += 1.0 / (C::gamma * dt);
      lu_.compute(M_);
      lu_dt_ = dt;
    }
    g_[0] = lu_.solve(f0v_ + dt * C::d1 * dfdt_);
    eval(x0_ + C::a21 * g_[0], t_prev + C::c2 * dt);
    g_[1] = lu_.solve(fx_ + dt * C::d2 * dfdt_ + (C::c21 / dt) * g_[0]);
    eval(x0_ + C::a31 * g_[0] + C::a32 * g_[1], t_prev + C::c3 * dt);
    g_[2] = lu_.solve(fx_ + dt * C::d3 * dfdt_ + (C::c31 * g_[0] + C::c32 * g_[1]) / dt);
    eval(x0_ + C::a41 * g_[0] + C::a42 * g_[1] + C::a43 * g_[2], t_prev + C::c4 * dt);
    g_[3] = lu_.solve(fx_ + dt * C::d4 * dfdt_ +
                      (C::c41 * g_[0] + C::c42 * g_[1] + C::c43 * g_[2]) / dt);
    xt_ = x0_ + C::a51 * g_[0] + C::a52 * g_[1] + C::a53 * g_[2] + C::a54 * g_[3];
    eval(xt_, t_prev + dt);
    g_[4] =
        lu_.solve(fx_ + (C::c51 * g_[0] + C::c52 * g_[1] + C::c53 * g_[2] + C::c54 * g_[3]) / dt);
    xt_ += g_[4];
    eval(xt_, t_prev + dt);
    err_ = lu_.solve(
        fx_ +
        (C::c61 * g_[0] + C::c62 * g_[1] + C::c63 * g_[2] + C::c64 * g_[3] + C::c65 * g_[4]) / dt);
    xt_ += err_;
    z_now.assign(xt_.data(), xt_.data() + m);
  }

  ScaledSystem& sys_;
  double abs_, rel_, max_dt_, min_dt_;
  double dt_ = 0.0, lu_dt_ = -1.0;
  bool last_rejected_ = false;
  state_t f0_, jbuf_, dfdt_buf_, zs_, fs_;
  Eigen::MatrixXd J_, M_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  Vec x0_, f0v_, dfdt_, fx_, xt_, err_, cont3_, cont4_;
  Vec g_[5];
};

}  // namespace

std::unique_ptr<Stepper> make_odeint_stepper(ScaledSystem& sys, const IntegratorSettings& s) {
  switch (s.method) {
    case IntegratorMethod::rk4:
      return std::make_unique<Rk4Stepper>(sys, s.step);
    case IntegratorMethod::dopri5:
      return std::make_unique<Dopri5Stepper>(sys, s);
    case IntegratorMethod::cash_karp54:
      return std::make_unique<ControlledStepper<odeint::runge_kutta_cash_karp54<state_t>>>(sys, s);
    case IntegratorMethod::fehlberg78:
      return std::make_unique<ControlledStepper<odeint::runge_kutta_fehlberg78<state_t>>>(sys, s);
    case IntegratorMethod::bulirsch_stoer: {
      using BS = odeint::bulirsch_stoer_dense_out<state_t>;
      BS bs(s.abs_tol, s.rel_tol, 1.0, 1.0, s.max_step);
      auto sysref = std::ref(sys);
      return std::make_unique<DenseOutputStepper<BS, state_t, decltype(sysref)>>(bs, sysref);
    }
    case IntegratorMethod::rosenbrock4:
      return std::make_unique<Rosenbrock4Stepper>(sys, s);
    case IntegratorMethod::cvode_bdf:
    case IntegratorMethod::cvode_bdf3:
    case IntegratorMethod::cvode_adams:
      return nullptr;  // make_cvode_stepper
  }
  return nullptr;
}

std::unique_ptr<Stepper> make_stepper(ScaledSystem& sys, const Scene& scene,
                                      const IntegratorSettings& s) {
  if (s.method == IntegratorMethod::cvode_bdf || s.method == IntegratorMethod::cvode_bdf3 ||
      s.method == IntegratorMethod::cvode_adams)
    return make_cvode_stepper(sys, scene, s);
  if (auto st = make_odeint_stepper(sys, s)) return st;
  throw InputError("integrator.method",
                   "unknown method '" + std::string(to_string(s.method)) + "'");
}

}  // namespace rodend::detail
