// Named extremes (issue 9): runs at the edges of the parameter space end ok, or with the specific
// failure they were built to trigger, and never hand a non-finite frame to an observer.
//
//  - resting contact, delta'^- -> 0: gravity-drop starting on the wall at zero speed settles at
//    the static Hertz penetration with a bounded force (the min_impact_speed guard);
//  - a 1 um clearance: rod-end-kinematic runs ok;
//  - misalignment = 1.1 x clearance: the socket starts against the ball (no initial penetration)
//    and the contact force stays at the slider spring's preload, not the Hertz force of the
//    overlap (README "Modelling decisions");
//  - c_r = 0.05 with every law: finite, never pulling, settles (the damping laws);
//  - each failure status of the health checks, from a case built to trigger it; a non-finite
//    state or output ends the run before the frame reaches the observer.
//
// Runtime (Release, 2 cores shared with other builds): ~4 s wall, 0.8 s of CPU.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/contact.hpp"
#include "core/errors.hpp"
#include "fixture.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

/// Keeps every frame it is given (samples and steps) and checks each for finite values.
class FiniteObserver final : public RunObserver {
 public:
  explicit FiniteObserver(std::vector<SignalId> ids) : ids_(std::move(ids)) {}
  void on_sample(const SignalFrame& f) override {
    check(f);
    sample_times.push_back(f.get(SignalId::time));
    samples.push_back(values(f));
  }
  void on_step(const SignalFrame& f) override {
    check(f);
    steps.push_back(values(f));
  }
  bool wants_steps() const override { return true; }

  std::vector<double> sample_times;
  std::vector<std::vector<double>> samples, steps;  ///< the ids' first components, in order
  bool all_finite = true;

 private:
  void check(const SignalFrame& f) {
    for (SignalId id : ids_)
      for (int k = 0; k < signal_spec(id).width; ++k)
        if (!std::isfinite(f.get(id, k))) all_finite = false;
    if (!std::isfinite(f.get(SignalId::time))) all_finite = false;
  }
  std::vector<double> values(const SignalFrame& f) const {
    std::vector<double> v;
    for (SignalId id : ids_) v.push_back(f.get(id));
    return v;
  }
  std::vector<SignalId> ids_;
};

/// Every signal a scene provides, for the finiteness check.
std::vector<SignalId> all_signals(const Scene& s) {
  const auto sig = s.signals();
  return {sig.begin(), sig.end()};
}

// gravity-drop defaults, restated (as in test_gravity_drop.cpp)
constexpr double kMass = 0.2, kG = 9.81, kClearance = 0.5e-3, kBallRadius = 0.01;
constexpr double kE = 206e9, kNu = 0.3;

double hertz_stiffness(double clearance) {
  const double Rs = kBallRadius + clearance;
  const double R_star = kBallRadius * Rs / (Rs - kBallRadius);
  const double E_star = 1.0 / (2.0 * (1.0 - kNu * kNu) / kE);
  return 4.0 / 3.0 * E_star * std::sqrt(R_star);
}

/// A one-state scene that blows up: x' = x^2, x(0) = 1, so x = 1/(1 - t) is infinite at t = 1.
/// With `bad_output_from` >= 0 the state stays harmless (x' = 0) and the output signal turns
/// non-finite from that time on instead.
class BlowUpScene final : public Scene {
 public:
  explicit BlowUpScene(double bad_output_from = -1.0) : bad_from_(bad_output_from) {}
  std::string_view name() const override { return "blow-up"; }
  Features features() const override { return {}; }  // no contact, no energy audit
  int state_size() const override { return 1; }
  void initial_state(double* x) const override { x[0] = 1.0; }
  void state_scale(double* s) const override { s[0] = 1.0; }
  void derivatives(double, const double* x, const DiscreteState&, double* dx) const override {
    dx[0] = bad_from_ >= 0.0 ? 0.0 : x[0] * x[0];
  }
  std::span<const SignalId> signals() const override { return kSignals; }
  void outputs(double t, const double* x, const DiscreteState&, SignalFrame& f) const override {
    const bool bad = bad_from_ >= 0.0 && t >= bad_from_;
    f.set(SignalId::eccentricity, bad ? std::numeric_limits<double>::infinity() : x[0]);
  }
  EnergyTerms energy(double, const double*, const DiscreteState&) const override { return {}; }

 private:
  static constexpr std::array<SignalId, 2> kSignals{SignalId::time, SignalId::eccentricity};
  double bad_from_;
};

}  // namespace

TEST_CASE("extremes: resting contact (delta'- -> 0) settles at the static Hertz penetration",
          "[extremes]") {
  for (const double c : {kClearance, 1e-6}) {
    ParameterSet p = ParameterSet::defaults_for("gravity-drop");
    p.set("contact.clearance", c);
    p.set("ball.initial_offset", Json::array({0.0, -c, 0.0}));  // on the wall, at rest
    auto scene = make_scene("gravity-drop", p);
    FiniteObserver obs({SignalId::penetration, SignalId::contact_force, SignalId::impact_speed,
                        SignalId::ball_velocity});
    const double end = 0.3;
    const RunResult r = simulate(*scene, dopri5(1e-10), TimeSettings{end, 1e-3}, obs);
    INFO("clearance " << c << ": " << r.message);
    REQUIRE(r.status == RunStatus::ok);
    CHECK(obs.all_finite);
    const double weight = kMass * kG;
    const double delta_static = std::pow(weight / hertz_stiffness(c), 2.0 / 3.0);
    // released on the wall the ball sinks in and rings down; undamped it would reach the
    // penetration where the Hertz energy equals the weight's work, F = 2.5 m g: the bound
    double peak = 0.0;
    for (const auto& v : obs.steps) peak = std::max(peak, v[1]);
    measured("resting contact: peak force / weight", peak / weight, 2.5);
    CHECK(peak <= 2.5 * weight);
    // the latched approach speed is ~0, so the guard min_impact_speed (1 mm/s) sets the damping
    CHECK(obs.samples.back()[2] < 1e-3);
    const double pen = obs.samples.back()[0];
    measured("resting contact: static penetration rel error", std::abs(pen / delta_static - 1),
             kStaticPenetrationRel);
    CHECK(pen == Approx(delta_static).epsilon(kStaticPenetrationRel));
    CHECK(obs.samples.back()[1] == Approx(weight).epsilon(kStaticForceRel));
  }
}

TEST_CASE("extremes: a 1 um clearance runs ok in rod-end-kinematic", "[extremes]") {
  ParameterSet p = ParameterSet::defaults_for("rod-end-kinematic");
  p.set("contact.clearance", 1e-6);
  auto scene = make_scene("rod-end-kinematic", p);
  FiniteObserver obs(all_signals(*scene));
  const double end = 1.2;  // the extension and its hold
  const RunResult r = simulate(*scene, dopri5(1e-6), TimeSettings{end, 1e-3}, obs);
  INFO(r.message);
  REQUIRE(r.status == RunStatus::ok);
  CHECK(r.stats.t_reached == Approx(end));
  CHECK(obs.all_finite);
  CHECK(r.stats.max_penetration_fraction < 0.2);
  CHECK(r.stats.contact_onsets >= 1);
}

TEST_CASE("extremes: misalignment 1.1 x clearance starts against the ball, preloaded",
          "[extremes]") {
  for (const std::string scene_name : {"rod-end-kinematic", "rod-end-actuator"}) {
    ParameterSet p = ParameterSet::defaults_for(scene_name);
    const double c = p.number("contact.clearance");
    const double m = 1.1 * c;
    p.set("socket.misalignment_z", m);
    auto scene = make_scene(scene_name, p);
    // the start: socket at z = c, exactly touching, not overlapping by 0.1 c
    std::vector<double> x0(static_cast<std::size_t>(scene->state_size()));
    scene->initial_state(x0.data());
    const ContactGap g0 = scene->contact_gap(0, x0.data());
    INFO(scene_name);
    CHECK(std::abs(g0.penetration) <= 1e-15);
    FiniteObserver obs({SignalId::contact_force, SignalId::penetration, SignalId::socket_position});
    const RunResult r = simulate(*scene, dopri5(1e-6), TimeSettings{0.2, 1e-3}, obs);
    INFO(r.message);
    REQUIRE(r.status == RunStatus::ok);
    CHECK(obs.all_finite);
    CHECK(obs.sample_times.front() == 0.0);
    // the contact carries the slider spring's preload k (m - c) = 50 N (twice that at most,
    // released suddenly), not the Hertz force of a 0.1 c overlap, K (0.1 c)^1.5 = 24 kN
    const double preload = p.number("slider_spring.stiffness") * (m - c);
    const double hertz_overlap = hertz_stiffness(c) * std::pow(0.1 * c, 1.5);
    double peak = 0.0;
    for (const auto& v : obs.steps) peak = std::max(peak, v[0]);
    measured(scene_name + ": misalignment 1.1 c, peak force / preload", peak / preload, 2.0);
    CHECK(hertz_overlap > 2e4);
    CHECK(peak <= 2.0 * preload);
    CHECK(r.stats.max_penetration_fraction < 0.01);
  }
}

TEST_CASE("extremes: c_r = 0.05 with every law: finite, never pulling, settles", "[extremes]") {
  const double weight = kMass * kG;
  const double delta_static = std::pow(weight / hertz_stiffness(kClearance), 2.0 / 3.0);
  int laws = 0;
  for (const NormalLaw* law : normal_laws()) {
    ParameterSet p = ParameterSet::defaults_for("gravity-drop");
    p.set("contact.law", std::string(law->name()));
    p.set("contact.restitution", 0.05);
    std::unique_ptr<Scene> scene;
    try {
      scene = make_scene("gravity-drop", p);
    } catch (const InputError&) {
      continue;  // a law that does not accept c_r = 0.05
    }
    ++laws;
    FiniteObserver obs({SignalId::contact_force, SignalId::penetration, SignalId::ball_velocity});
    const RunResult r = simulate(*scene, dopri5(1e-10), TimeSettings{0.3, 1e-3}, obs);
    INFO(law->name() << ": " << r.message);
    REQUIRE(r.status == RunStatus::ok);
    CHECK(obs.all_finite);
    // no pull: the normal force is >= 0 in every frame, and zero across a gap
    bool pulls = false, force_across_gap = false;
    for (const auto& v : obs.steps) {
      pulls = pulls || v[0] < 0.0;
      force_across_gap = force_across_gap || (v[1] <= 0.0 && v[0] != 0.0);
    }
    CHECK_FALSE(pulls);
    CHECK_FALSE(force_across_gap);
    // a law that damps settles at the static penetration; hertz ignores c_r (chi = 0) and
    // keeps bouncing, elastically
    if (law->hysteresis_factor(0.05) > 0.0)
      CHECK(obs.samples.back()[1] == Approx(delta_static).epsilon(kStaticPenetrationRel));
  }
  CHECK(laws >= 5);
}

TEST_CASE("extremes: a coarse rk4 step fails the energy audit (energy_residual_limit)",
          "[extremes]") {
  ParameterSet p = ParameterSet::defaults_for("gravity-drop");
  auto scene = make_scene("gravity-drop", p);
  FiniteObserver obs({SignalId::energy_residual});
  HealthLimits h;
  h.max_energy_residual = 1e-6;
  const TimeSettings time{0.3, 1e-4};
  const RunResult r = simulate(*scene, rk4(2e-5), time, obs, h);
  INFO(r.message);
  REQUIRE(r.status == RunStatus::energy_residual_limit);
  CHECK(r.message.find("energy-audit residual") != std::string::npos);
  CHECK(r.message.find("at t = ") != std::string::npos);
  CHECK(r.stats.t_reached < time.end);
  CHECK(obs.all_finite);
  CHECK(obs.sample_times.back() == Approx(r.stats.t_reached));
  // the same run at the default bound (1 %) and a fine step is ok
  FiniteObserver fine({SignalId::energy_residual});
  CHECK(simulate(*scene, dopri5(1e-10), time, fine).status == RunStatus::ok);
}

TEST_CASE("extremes: an actuator that cannot follow fails (actuator_saturation)", "[extremes]") {
  SECTION("a 60 mm stroke commanded in 20 ms: faster than the valve can follow") {
    ParameterSet p = ParameterSet::defaults_for("servo-actuator");
    p.set("command.shape", "raised-cosine");
    p.set("command.extension", 0.06);
    p.set("command.extension_time", 0.02);
    auto scene = make_scene("servo-actuator", p);
    FiniteObserver obs(all_signals(*scene));
    const RunResult r = simulate(*scene, dopri5(1e-6), TimeSettings{1.0, 1e-4}, obs);
    INFO(r.message);
    REQUIRE(r.status == RunStatus::actuator_saturation);
    CHECK(r.message.find("cannot follow") != std::string::npos);
    CHECK(obs.all_finite);
    // the window: the error has been above 5 mm for just over 0.1 s when the run stops
    CHECK(r.stats.t_reached < 0.5);
    // a wider window lets the same run finish: the stroke is followed at the valve's rate
    HealthLimits h;
    h.tracking_window = 0.5;
    FiniteObserver obs2(all_signals(*scene));
    CHECK(simulate(*scene, dopri5(1e-6), TimeSettings{1.0, 1e-4}, obs2, h).status == RunStatus::ok);
  }
  SECTION("a load beyond the 10.5 kN stall force pushes the piston back") {
    ParameterSet p = ParameterSet::defaults_for("servo-actuator");
    p.set("load.external_force", -15000.0);
    auto scene = make_scene("servo-actuator", p);
    FiniteObserver obs(all_signals(*scene));
    const RunResult r = simulate(*scene, dopri5(1e-6), TimeSettings{1.0, 1e-4}, obs);
    INFO(r.message);
    REQUIRE(r.status == RunStatus::actuator_saturation);
    CHECK(obs.all_finite);
  }
  SECTION("a hinge moment beyond the stall moment in rod-end-actuator") {
    ParameterSet p = ParameterSet::defaults_for("rod-end-actuator");
    p.set("hinge.kind", "constant");
    p.set("hinge.constant_moment", -1500.0);
    auto scene = make_scene("rod-end-actuator", p);
    FiniteObserver obs(all_signals(*scene));
    IntegratorSettings s = dopri5(1e-6);
    s.method =
        IntegratorMethod::rosenbrock4;  // kN contact forces make the friction stiff for dopri5
    const RunResult r = simulate(*scene, s, TimeSettings{2.4, 1e-3}, obs);
    INFO(r.message);
    REQUIRE(r.status == RunStatus::actuator_saturation);
    CHECK(obs.all_finite);
  }
}

TEST_CASE("extremes: no frame after a non-finite state or output", "[extremes]") {
  SECTION("the state blows up (x' = x^2): rk4") {
    BlowUpScene scene;
    FiniteObserver obs({SignalId::eccentricity});
    const RunResult r = simulate(scene, rk4(1e-3), TimeSettings{2.0, 1e-3}, obs);
    INFO(r.message);
    REQUIRE(r.status == RunStatus::non_finite_state);
    CHECK(obs.all_finite);
    REQUIRE_FALSE(obs.samples.empty());
    CHECK(obs.sample_times.back() <= r.stats.t_reached + 1e-12);
    CHECK(r.message.find("non-finite state") != std::string::npos);
  }
  SECTION("the state blows up: dopri5 (fails one way or another, never with a bad frame)") {
    BlowUpScene scene;
    FiniteObserver obs({SignalId::eccentricity});
    IntegratorSettings s = dopri5(1e-8);
    s.max_steps = 100000;
    const RunResult r = simulate(scene, s, TimeSettings{2.0, 1e-3}, obs);
    INFO(r.message);
    CHECK(r.status != RunStatus::ok);
    CHECK(obs.all_finite);
    CHECK(obs.sample_times.back() < 1.01);
  }
  SECTION("a finite state whose output turns infinite at t = 0.25 s") {
    BlowUpScene scene(0.25);
    FiniteObserver obs({SignalId::eccentricity});
    const RunResult r = simulate(scene, dopri5(1e-8), TimeSettings{1.0, 1e-2}, obs);
    INFO(r.message);
    REQUIRE(r.status == RunStatus::non_finite_state);
    CHECK(r.message.find("non-finite signal eccentricity") != std::string::npos);
    CHECK(obs.all_finite);
    CHECK(obs.sample_times.back() < 0.25);
  }
}

TEST_CASE("extremes: health limits are validated by name", "[extremes]") {
  auto scene = make_scene("gravity-drop", ParameterSet::defaults_for("gravity-drop"));
  FiniteObserver obs({});
  const auto key_of = [&](HealthLimits h) -> std::string {
    try {
      simulate(*scene, dopri5(1e-6), TimeSettings{0.01, 1e-3}, obs, h);
    } catch (const InputError& e) {
      return e.key_path();
    }
    return "";
  };
  HealthLimits h;
  CHECK(key_of(h).empty());
  h.max_energy_residual = 0.0;
  CHECK(key_of(h) == "health.max_energy_residual");
  h = {};
  h.tracking_window = -1.0;
  CHECK(key_of(h) == "health.tracking_window");
  h = {};
  h.max_tracking_error = std::numeric_limits<double>::infinity();
  CHECK(key_of(h) == "health.max_tracking_error");
  h = {};
  h.energy_flow_floor = std::nan("");
  CHECK(key_of(h) == "health.energy_flow_floor");
}
