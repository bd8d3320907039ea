// Issue 37 item 7: tests that pin what, before them, only the stored regression references
// caught (or nothing caught): one-line mutations of the physics must fail a test that needs no
// stored reference. Each test names the mutation it was proved against and what it did then.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "core/spring3d.hpp"
#include "fixture.hpp"
#include "sweep/metrics.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

/// Prothero-Robinson, as in test_stiff.cpp, started at a phase phi of its solution:
/// x' = -lambda (x - sin(t + phi)) + cos(t + phi), x(0) = sin(phi), exact x = sin(t + phi),
/// lambda = 1e4 s^-1. From the exact x(0) the error after the first accepted step is that step's
/// local error, nothing propagated; the phase moves where along the solution the step is taken.
class ProtheroRobinson final : public Scene {
 public:
  static constexpr double lambda = 1e4;  // [1/s]
  explicit ProtheroRobinson(double phi) : phi_(phi) {}
  double exact(double t) const { return std::sin(t + phi_); }
  std::string_view name() const override { return "prothero-robinson"; }
  Features features() const override { return {}; }
  int state_size() const override { return 1; }
  void initial_state(double* x) const override { x[0] = exact(0.0); }
  void state_scale(double* s) const override { s[0] = 1.0; }
  void derivatives(double t, const double* x, const DiscreteState&, double* dx) const override {
    dx[0] = -lambda * (x[0] - exact(t)) + std::cos(t + phi_);
  }
  std::span<const SignalId> signals() const override { return kSignals; }
  void outputs(double, const double* x, const DiscreteState&, SignalFrame& f) const override {
    f.set(SignalId::eccentricity, x[0]);
  }
  EnergyTerms energy(double, const double*, const DiscreteState&) const override { return {}; }

 private:
  static constexpr std::array<SignalId, 2> kSignals{SignalId::time, SignalId::eccentricity};
  double phi_;
};

/// The first accepted step of `method` on Prothero-Robinson at phase phi, tolerances tol, the
/// first trial step the whole run (end = 2 s): its local error relative to the tolerance it
/// was accepted against, abs + rel |x| (the error checkers' weight), and the run's rejections.
struct FirstStep {
  double error_over_tol = NAN;
  double t1 = NAN;
  long long rejected = 0;
};
FirstStep oversized_first_step(const std::string& method, double tol, double phi) {
  const ProtheroRobinson scene(phi);
  const double end = 2.0;
  IntegratorSettings s;
  s.method = test::method_named(method);
  s.abs_tol = s.rel_tol = tol;
  s.step = end;  // the first trial step: deliberately the whole run
  s.max_step = end;
  Recorder rec({SignalId::eccentricity}, true);
  // one sample interval over the whole run: the methods without dense output step to it
  const RunResult r = simulate(scene, s, TimeSettings{end, end}, rec);
  INFO(r.message);
  REQUIRE(r.status == RunStatus::ok);
  REQUIRE(!rec.steps.empty());
  FirstStep f;
  f.t1 = rec.steps.time(0);
  const double x1 = rec.steps.get(0, SignalId::eccentricity);
  f.error_over_tol = std::abs(x1 - scene.exact(f.t1)) / (tol + tol * std::abs(x1));
  f.rejected = r.stats.steps_rejected;
  return f;
}

}  // namespace

// --- 1. step-size control: an oversized first step is rejected ---------------------------------

// Mutation: rosenbrock4 accepts a step when its error norm is <= 100 instead of <= 1
// (core/steppers_odeint.cpp, `if (e <= 1.0)` -> `if (e <= 100.0)`). Seen then: at tol 1e-6 the
// 2 s first trial step is accepted at once (0 rejections) with a local error of 9-20 x tol (the
// three phases); at tol 1e-8 the first accepted steps carry 6.9-72 x tol; 9 checks fail. Without
// the mutation: <= 1.44 x tol. Before this test nothing failed on it (test_stiff.cpp asks only
// for a global error < 10 x tol at the end).
TEST_CASE("pins: every adaptive method rejects an oversized first step on a stiff problem",
          "[pins][stiff]") {
  // bulirsch_stoer is left out: odeint runs its step-size control, so its rejections are not
  // counted, and its first accepted step's error is not bounded by its tolerance on this problem
  // (the [!shouldfail] test below)
  const std::string method = GENERATE(as<std::string>{}, "dopri5", "cash_karp54", "fehlberg78",
                                      "rosenbrock4", "cvode_bdf", "cvode_adams");
  for (const double tol : {1e-6, 1e-8})
    for (const double phi : {0.0, 1.0, 2.0}) {
      const FirstStep f = oversized_first_step(method, tol, phi);
      CAPTURE(method, tol, phi, f.t1, f.rejected, f.error_over_tol);
      // a 2 s step across a 1e4 s^-1 eigenvalue is far outside every method's accuracy (the
      // explicit ones' stability too): the controller must reject it at least once
      CHECK(f.rejected > 0);
      // and the step it accepts has a local error of the order of the tolerance: its error
      // estimate (of the embedded lower-order solution, which is not the one kept) passed <= 1,
      // which bounds the kept solution's error only up to the estimate's own error. measured
      // max over tol and phase: dopri5 0.44, cash_karp54 1.19, fehlberg78 0.26, rosenbrock4
      // 1.44, cvode_bdf 0.32, cvode_adams 0.029 (x tol). The bound 3 is 2x the worst and 2.3x
      // below the smallest error a controller accepting 100 x tol let through (6.9 x tol)
      measured("oversized first step: local error / tol, " + method, f.error_over_tol, 3.0);
      CHECK(f.error_over_tol <= 3.0);
    }
}

// A limit of the method, not a pin: bulirsch_stoer (odeint's bulirsch_stoer_dense_out, which
// runs its own step-size control) accepts first steps whose local error is far above its
// tolerance on this stiff problem: measured 12.4 x tol (and over a 2 s run at tol 1e-6, global
// errors up to 1.1e4 x tol, where the other methods stay within 14 x tol). Why: its controller
// settles on h lambda ~ 10, where the explicit modified midpoint rule it extrapolates is near
// its stability limit, and the difference of the last two extrapolations (its error estimate)
// no longer bounds the error. Boost.Odeint alone does the same (measured 2026-11-26 with a
// stand-alone program on this problem: bulirsch_stoer_dense_out 12.44 x tol on the first step
// at tol 1e-8, phase 1, with the derivative term of the error weight at 1 or 0; the plain
// bulirsch_stoer 20-21 x tol; over the run 90-6000 x tol), so neither rodend's state scaling
// (1 here) nor its driver is the cause. docs/studies.md ("The integrator menu") says so.
// Marked [!shouldfail]: it passes while the limit is there and fails once it is gone (then
// drop the tag and add the method to the test above).
TEST_CASE("pins: bulirsch_stoer's first step on a stiff problem", "[pins][stiff][!shouldfail]") {
  double worst = 0.0;
  for (const double tol : {1e-6, 1e-8})
    for (const double phi : {0.0, 1.0, 2.0})
      worst = std::max(worst, oversized_first_step("bulirsch_stoer", tol, phi).error_over_tol);
  measured("oversized first step: local error / tol, bulirsch_stoer", worst, 3.0);
  CHECK(worst <= 3.0);
}

// --- 2. the 3-D spring's restoring moment: the order of the quaternion product ------------------

namespace {

/// A body at rest at the origin with orientation q (w, x, y, z; normalised by from_state).
BodyKinematics body_with(const Quat& q) {
  const double x[13] = {0, 0, 0, 0, 0, 0, q.w(), q.x(), q.y(), q.z(), 0, 0, 0};
  return BodyKinematics::from_state(x);
}

}  // namespace

// Mutation: the relative rotation taken as q_ref^-1 q_body instead of q_body q_ref^-1
// (core/spring3d.hpp, `b.q_WB * a.q_ref.conjugate()` -> `a.q_ref.conjugate() * b.q_WB`). Seen
// then: all four moment checks fail, each moment off by sqrt(2) k_r theta (14.1 N m at 0.1
// rad, 70.7 at 0.5): the swapped order gives +k_r theta y where -k_r theta x is due. The
// issue's audit found this caught only by cli.regression's stored references: the two orders
// agree whenever the reference and the deflection turn about the same axis.
TEST_CASE("pins: 3-D spring moment for a reference rotated 90 deg about z", "[pins][spring]") {
  // By hand, unit quaternions (w, x, y, z), a = 1/sqrt(2), c = cos(theta/2), s = sin(theta/2):
  //   q_ref = 90 deg about z = (a, 0, 0, a)
  //   tilted about the world x axis by theta: q_b = R_x(theta) q_ref = (c, s, 0, 0)(a, 0, 0, a)
  //     = (c a - 0, c (0, 0, a) + a (s, 0, 0) + (s, 0, 0) x (0, 0, a)) = a (c, s, -s, c)
  //   so q_b q_ref^-1 = R_x(theta): r = theta x, M = -k_r theta x (the world axis it was tilted
  //   about); the swapped order gives q_ref^-1 R_x(theta) q_ref, theta about R_z(-90 deg) x = -y:
  //   M = +k_r theta y.
  //   tilted about the body's own x axis: q_b = q_ref R_x(theta) = a (c, s, s, c), whose world
  //   axis is R_z(90 deg) x = y: M = -k_r theta y (the swapped order: -k_r theta x).
  Spring3DParams sp;
  sp.stiffness = 1e6;  // no linear deflection: the anchor sits at the body
  sp.damping = 200.0;
  sp.rotational_stiffness = 100.0;  // [N m/rad]
  sp.rotational_damping = 0.02;     // at rest: no damping moment
  SpringAnchor anchor;
  const double a = 1.0 / std::sqrt(2.0);
  anchor.q_ref = Quat(a, 0.0, 0.0, a);
  // 0.1 rad: the series branch of rotation_vector_of_unit (below 14 deg); 0.5 rad: atan2
  for (const double theta : {0.1, 0.5}) {
    CAPTURE(theta);
    const double c = std::cos(0.5 * theta), s = std::sin(0.5 * theta);
    const double kr = sp.rotational_stiffness;
    // the moment is k_r |r| with |r| recovered from a quaternion built from cos and sin of
    // theta/2: round-off only, ~1e-16 relative; 1e-12 of k_r theta allows it many times
    const double tol = 1e-12 * kr * theta;
    const BodyKinematics turned = body_with(Quat(a * c, a * s, -a * s, a * c));
    const SpringEval world = evaluate_spring(sp, anchor, turned);
    CHECK((world.moment_on_body - Vec3(-kr * theta, 0.0, 0.0)).norm() <= tol);
    CHECK(world.force_on_body.norm() == 0.0);
    CHECK(spring_potential(sp, anchor, turned) == Approx(0.5 * kr * theta * theta).epsilon(1e-12));
    const SpringEval own = evaluate_spring(sp, anchor, body_with(Quat(a * c, a * s, a * s, a * c)));
    CHECK((own.moment_on_body - Vec3(0.0, -kr * theta, 0.0)).norm() <= tol);
  }
}

// --- 3. the control surface's inertia about the hinge -----------------------------------------

// Mutation: the centre of mass put at half the crank instead of a third (core/scenes/
// rod_end_mechanism.cpp, `m * (s / 3.0) * (s / 3.0) + I` -> `m * (s / 2.0) * (s / 2.0) + I`).
// Seen then: both scenes fail, 569.4 rad/s^2 where M / J = 748.4 rad/s^2. The audit
// found this caught only by cli.regression's stored references (test_actuator.cpp recomputes
// J from the parameters, not from the scene).
TEST_CASE("pins: the surface's initial angular acceleration under a constant hinge moment",
          "[pins][hinge]") {
  // Thesis eq. 4.16 (the typo of 4.15 fixed; docs/model.md "Mechanism"): the crank and surface
  // turn about the hinge with J theta'' = tau - c theta' + M_hinge, J = m (s/3)^2 + I: the
  // surface a triangular plate of mass m whose centre of mass is at a third of the crank
  // length s from the hinge, I its own inertia. At t = 0 everything is at rest (theta' = 0)
  // and the crank torque tau is the same with or without the hinge moment, so the difference of
  // two initial accelerations, with M and without, is M / J alone.
  // The defaults (control-surface.part.json, rod-end-mechanism.part.json), restated:
  constexpr double m = 5.0, I = 0.02, s = 0.11;        // [kg], [kg m^2], [m]
  constexpr double J = m * (s / 3.0) * (s / 3.0) + I;  // 0.0267222 kg m^2
  constexpr double M = 20.0;  // [N m] the constant moment of test_actuator.cpp's runs
  const std::string scene_name =
      GENERATE(as<std::string>{}, "rod-end-kinematic", "rod-end-actuator");
  CAPTURE(scene_name);
  const ParameterSet defaults = ParameterSet::defaults_for(scene_name);
  REQUIRE(defaults.number("surface.mass") == m);
  REQUIRE(defaults.number("surface.inertia") == I);
  REQUIRE(defaults.number("geometry.crank") == s);
  auto initial_acceleration = [&](double moment) {
    ParameterSet p = defaults;
    p.set("hinge.kind", "constant");
    p.set("hinge.constant_moment", moment);
    p.set("hinge.step_time", 0.0);
    const auto scene = make_scene(scene_name, p);
    Recorder rec({SignalId::surface_acceleration, SignalId::hinge_moment});
    const RunResult r = simulate(*scene, IntegratorSettings{}, TimeSettings{1e-3, 1e-3}, rec);
    INFO(r.message);
    REQUIRE(r.status == RunStatus::ok);
    REQUIRE(rec.samples.time(0) == 0.0);
    CHECK(rec.samples.get(0, SignalId::hinge_moment) == moment);
    return rec.samples.get(0, SignalId::surface_acceleration);
  };
  const double free = initial_acceleration(0.0), loaded = initial_acceleration(M);
  // the sample at t = 0 is the right-hand side at the initial state: round-off only (measured
  // 0 in both scenes), so 1e-9 relative; an inertia off by 1e-6 of itself would show
  measured("surface: initial acceleration without a hinge moment [rad/s^2]", std::abs(free),
           1e-9 * M / J);
  measured("surface: (loaded - free) acceleration vs M / J (rel)",
           std::abs((loaded - free) / (M / J) - 1.0), 1e-9);
  CHECK(loaded - free == Approx(M / J).epsilon(1e-9));
  // and the mechanism at rest has no crank torque at t = 0: the ball sits at the crank end
  CHECK(std::abs(free) <= 1e-9 * M / J);
}

// --- 4. the first step after a located contact onset --------------------------------------------

namespace {

/// The accepted steps' end times and the contact onsets of a run.
class StepsAndOnsets final : public RunObserver {
 public:
  void on_step(const SignalFrame& f) override { steps.push_back(f.get(SignalId::time)); }
  bool wants_steps() const override { return true; }
  void on_contact_onset(double t, int, double) override { onsets.push_back(t); }
  std::vector<double> steps, onsets;
};

}  // namespace

// Mutation: the cap removed (core/integrator.cpp, retake_to: `if (stats_.contact_onsets >
// onsets_before) dt = std::min(dt, settings_.step);` -> `(void)onsets_before;`), so the method
// restarts with the step it had before the re-take. Seen then: every method fails, its longest
// first step after an onset 1.7x (cvode_adams), 2.4x (cvode_bdf), 4.4x (rosenbrock4), 57x
// (cash_karp54), 66x (dopri5), 351x (bulirsch_stoer), 950x (fehlberg78) integrator.step.
TEST_CASE("pins: the first step after a located contact onset is at most integrator.step",
          "[pins][events]") {
  // The driver restarts the method at a located onset with at most the first trial step
  // integrator.step, as at t = 0: the force law is not smooth there (delta^1.5), and a long
  // first step through the impact's rise is not seen by every error estimate (integrator.cpp,
  // retake_to). The re-take up to the onset is not an observed step, so the first step frame
  // after an onset ends the first step taken from it.
  const std::string method = GENERATE(as<std::string>{}, "dopri5", "cash_karp54", "fehlberg78",
                                      "bulirsch_stoer", "rosenbrock4", "cvode_bdf", "cvode_adams");
  CAPTURE(method);
  const auto scene = make_scene("gravity-drop", ParameterSet::defaults_for("gravity-drop"));
  IntegratorSettings s;
  s.method = test::method_named(method);
  s.step = 1e-7;  // [s] far below the steps of the free fall before each impact (up to 1e-3 s)
  StepsAndOnsets obs;
  const RunResult r = simulate(*scene, s, TimeSettings{0.05, 1e-3}, obs);
  INFO(r.message);
  REQUIRE(r.status == RunStatus::ok);
  REQUIRE(obs.onsets.size() >= 2);  // measured: 3 impacts in 50 ms, every method
  double longest = 0.0;
  for (const double t_on : obs.onsets) {
    const auto next = std::upper_bound(obs.steps.begin(), obs.steps.end(), t_on);
    REQUIRE(next != obs.steps.end());
    longest = std::max(longest, *next - t_on);
  }
  // a step of exactly integrator.step lands at t_on + step, rounded: 1e-9 of it is round-off
  measured("first step after an onset / integrator.step, " + method, longest / s.step, 1.0);
  CHECK(longest <= s.step * (1.0 + 1e-9));
}

// --- 5. contact_time of a single impact ----------------------------------------------------------

namespace {

/// The summary metrics of a run, accumulated as the runner does, and the step end times.
class MetricsAndSteps final : public RunObserver {
 public:
  explicit MetricsAndSteps(const Scene& scene) : metrics(scene, MetricsSettings{}) {}
  void on_step(const SignalFrame& f) override {
    metrics.on_step(f);
    steps.push_back(f.get(SignalId::time));
  }
  bool wants_steps() const override { return true; }
  void on_contact_onset(double t, int, double v) override { metrics.on_contact_onset(t, v); }
  bool wants_peak(ContactPeak::Kind k, int, double t0, double bound) const override {
    return metrics.wants_peak(k, t0, bound);
  }
  void on_contact_peak(const ContactPeak& p) override { metrics.on_contact_peak(p); }
  MetricsAccumulator metrics;
  std::vector<double> steps;
};

/// The duration of a Hertz impact without damping (F = K delta^(3/2)) of a mass m at speed v.
/// The energy m delta'^2 / 2 + (2/5) K delta^(5/2) = m v^2 / 2 gives
///   delta_max = (5 m v^2 / (4 K))^(2/5),  delta' = v sqrt(1 - (delta / delta_max)^(5/2)),
/// and the time to delta_max
///   (delta_max / v) int_0^1 du / sqrt(1 - u^(5/2))  (u = w^(2/5), du = (2/5) w^(-3/5) dw)
///   = (delta_max / v) (2/5) B(2/5, 1/2).
/// The rebound is its mirror image (no damping), so the contact lasts
///   T = 2 (2/5) B(2/5, 1/2) delta_max / v = 2.9433 delta_max / v   (the classical 2.94).
double hertz_duration(double m, double v, double K) {
  const double d_max = std::pow(5.0 * m * v * v / (4.0 * K), 0.4);
  const double beta = std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
  CHECK(2.0 * 0.4 * beta == Approx(2.94).margin(5e-3));  // the literature's three digits
  return 2.0 * 0.4 * beta * d_max / v;
}

/// The longest of the steps (given by their end times, the run starting at 0) that overlap
/// [t0, t1].
double longest_step_over(const std::vector<double>& ends, double t0, double t1) {
  double h = 0.0, prev = 0.0;
  for (const double t : ends) {
    if (t > t0 && prev < t1) h = std::max(h, t - prev);
    prev = t;
  }
  return h;
}

}  // namespace

// Mutation: the trapezoid's weights swapped (sweep/metrics.cpp, MetricsAccumulator::on_step:
// `(F > 0.0 && force_prev_ > 0.0) ? dt : 0.5 * dt` -> `? 0.5 * dt : dt`), every step inside the
// contact counted half. Seen then: every method fails, contact_time ~T/2, 30-62 steps off (rk4
// 62). A mutation that moves contact_time by less than a step (e.g. the exit's half step
// dropped) is below this metric's resolution and is not caught. (The audit found a
// contact_time mutation caught only by cli.regression's stored references.)
TEST_CASE("pins: a single impact's contact_time is the closed-form Hertz duration",
          "[pins][impact]") {
  // Scene impact-pair, fixed outer body, no gravity, no friction, law "hertz" (no damping): the
  // ball of mass m meets the wall at v and m delta'' = -K delta^(3/2) while delta > 0, for the
  // time T of hertz_duration (2.94 delta_max / v). K = 4/3 E* sqrt(R*) of a ball in a conformal
  // socket, E* = E / (2 (1 - nu^2)) (the same steel on both sides), R* = R_b R_s / (R_s - R_b), R_s
  // = R_b + c (model-notes §1), restated from the parameter files as test_impact_pair.cpp does:
  constexpr double m = 0.2, v = 0.1, c = 0.5e-3, Rb = 0.01;  // [kg], [m/s], [m], [m]
  constexpr double E = 206e9, nu = 0.3;                      // [Pa], [-]
  const double K = 4.0 / 3.0 * (E / (2.0 * (1.0 - nu * nu))) * std::sqrt(Rb * (Rb + c) / c);
  const double T = hertz_duration(m, v, K);  // 1.2361e-4 s
  ParameterSet p = ParameterSet::defaults_for("impact-pair");
  REQUIRE(p.number("ball.mass") == m);
  REQUIRE(p.number("impact.approach_speed") == v);
  REQUIRE(p.number("contact.clearance") == c);
  REQUIRE(p.number("contact.ball_radius") == Rb);
  REQUIRE(p.text("impact.outer_body") == "fixed");
  p.set("contact.law", "hertz");
  p.set("contact.restitution", 1.0);
  const auto scene = make_scene("impact-pair", p);
  // every method, at tol 1e-8 with steps of at most 2 us (~60 per impact; rk4: 1 us), so that
  // "within a step" is a bound of 1-2 % of T
  const std::string method =
      GENERATE(as<std::string>{}, "rk4", "dopri5", "cash_karp54", "fehlberg78", "bulirsch_stoer",
               "rosenbrock4", "cvode_bdf", "cvode_adams");
  CAPTURE(method);
  IntegratorSettings s;
  s.method = test::method_named(method);
  s.abs_tol = s.rel_tol = 1e-8;
  s.step = 1e-6;
  s.max_step = 2e-6;
  MetricsAndSteps obs(*scene);
  const RunResult r = simulate(*scene, s, TimeSettings{1e-3, 1e-4}, obs);
  INFO(r.message);
  REQUIRE(r.status == RunStatus::ok);
  REQUIRE(r.stats.contact_onsets == 1);
  const MetricValues metrics = obs.metrics.finish(r.stats);
  const double contact_time = metrics[static_cast<std::size_t>(MetricId::contact_time)];
  const double t_on = metrics[static_cast<std::size_t>(MetricId::first_contact_time)];
  // contact_time sums the accepted steps while the force is > 0 (trapezoids of the indicator
  // F > 0 over step ends): a step with both ends in contact counts whole, the step that crosses
  // the exit (not located) counts half, so the exit is resolved to half a step. The onset is
  // located (to ~1e-16 s) and the method restarts there; the impact starts 5e-12 s after
  // t = 0, so the first step after the onset is the run's first observed step, counted from
  // t = 0 with its end's force held back over it (the test below). Hence |contact_time - T| <=
  // 1.5 h, h the longest step that overlaps the contact [t_on, t_on + T]. (Measured before
  // the first step was counted, in h: rk4 1.11, fehlberg78 0.81, dopri5 0.55, the others <=
  // 0.33; printed by `measured` below.)
  const double h = longest_step_over(obs.steps, t_on, t_on + T);
  CAPTURE(contact_time, T, h, t_on);
  measured("impact contact_time vs closed form, in steps, " + method,
           std::abs(contact_time - T) / h, 1.5);
  CHECK(std::abs(contact_time - T) <= 1.5 * h);
  // which is a fine resolution: the steps are short beside the impact
  CHECK(h <= 0.02 * T);
}

// contact_time and wear_integral count the run's first step (from t = 0 to its end, the first
// frame): a contact under way from the start, constant force F and wear indicator w over ten
// steps of 0.1 s ending at 1 s, lasts 1 s and integrates w to w x 1 s. Before: the first step
// was left out (0.9 s and 0.9 w).
TEST_CASE("pins: contact_time and wear_integral count the run's first step", "[pins][metrics]") {
  const auto scene = make_scene("impact-pair", ParameterSet::defaults_for("impact-pair"));
  MetricsAccumulator acc(*scene, MetricsSettings{});
  const double w = 2.0;
  for (int i = 1; i <= 10; ++i) {
    SignalFrame f;
    f.set(SignalId::time, 0.1 * i);
    f.set(SignalId::contact_force, 5.0);
    f.set(SignalId::penetration, 1e-6);
    f.set(SignalId::wear_indicator, w);
    acc.on_step(f);
  }
  const MetricValues v = acc.finish(RunStats{});
  CHECK(v[static_cast<std::size_t>(MetricId::contact_time)] == Approx(1.0).epsilon(1e-12));
  CHECK(v[static_cast<std::size_t>(MetricId::wear_integral)] == Approx(w).epsilon(1e-12));
}
