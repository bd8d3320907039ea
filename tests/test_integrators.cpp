// The integrator menu: every method, at a tight setting, reproduces the analytic checks of
// free-body and gravity-drop; presets resolve as documented; contact-onset location matters.
#include <catch2/catch.hpp>
#include <cmath>

#include "core/presets.hpp"
#include "fixture.hpp"
#include "sweep/study.hpp"

using namespace rodend;

namespace {

/// Tight settings per method: rk4 at a small step, the adaptive ones at 1e-10 on the scaled
/// state (1e-10 is two decades above what the controllers can still honour on O(1) states).
IntegratorSettings tight(const std::string& method) {
  IntegratorSettings s;
  s.method = test::method_named(method);
  s.abs_tol = s.rel_tol = 1e-10;
  s.step = method == "rk4" ? 1e-6 : 1e-5;
  s.max_step = 1e-3;
  return s;
}

struct Onset : RunObserver {
  double t1 = NAN, v1 = NAN;
  double exit_speed = NAN;   // approach speed latched at the first onset; rebound measured below
  double max_y = -INFINITY;  // highest ball position after the first contact
  bool in_contact_seen = false;
  void on_contact_onset(double t, int, double v) override {
    if (std::isnan(t1)) {
      t1 = t;
      v1 = v;
    }
  }
  void on_sample(const SignalFrame& f) override {
    if (!std::isnan(t1)) max_y = std::max(max_y, f.get(SignalId::ball_position, 1));
  }
};

}  // namespace

TEST_CASE("every method reproduces the free-body closed form", "[integrators]") {
  const auto method =
      GENERATE(as<std::string>{}, "rk4", "dopri5", "cash_karp54", "fehlberg78", "bulirsch_stoer",
               "rosenbrock4", "cvode_bdf", "cvode_bdf3", "cvode_adams");
  CAPTURE(method);
  ParameterSet p = ParameterSet::defaults_for("free-body");
  p.set("moment.amplitude", Json::array({0.0, 0.0, 0.0}));  // translation only: x = F t^2/(2m)
  const auto scene = make_scene("free-body", p);
  struct Last : RunObserver {
    Vec3 x;
    void on_sample(const SignalFrame& f) override { x = f.get3(SignalId::body_position); }
  } last;
  const RunResult r = simulate(*scene, tight(method), TimeSettings{1.0, 0.1}, last);
  REQUIRE(r.status == RunStatus::ok);
  // F = [3, 6, 9] N, m = 1 kg, t = 1 s: x = F/2. A quadratic is integrated exactly by every
  // method of order >= 2, so only round-off and (CVODE, BDF/Adams with variable order) the
  // tolerance remain: 1e-7 relative bounds the tolerance-driven methods at 1e-10 with margin.
  CHECK(last.x.x() == Approx(1.5).epsilon(1e-7));
  CHECK(last.x.y() == Approx(3.0).epsilon(1e-7));
  CHECK(last.x.z() == Approx(4.5).epsilon(1e-7));
}

TEST_CASE("cvode_bdf3 is BDF of order at most 3: more steps than cvode_bdf on a smooth motion",
          "[integrators]") {
  // A tumbling free body under its default moment (smooth, not a polynomial in t), 1e-10, steps
  // not capped: the step of a BDF of order q goes as tol^(1/(q+1)), so capping the order at 3
  // takes about tol^(1/4 - 1/6) ~ 7x the steps of order 5 here. Measured: 796 steps
  // (cvode_bdf) and 3,950 (cvode_bdf3); cvode_bdf3 without its cap took 742: 2x fails it.
  const auto scene = make_scene("free-body", ParameterSet::defaults_for("free-body"));
  auto steps = [&](const std::string& method) {
    IntegratorSettings s = tight(method);
    s.max_step = 1.0;
    RunObserver none;
    const RunResult r = simulate(*scene, s, TimeSettings{1.0, 0.1}, none);
    REQUIRE(r.status == RunStatus::ok);
    return r.stats.steps_accepted;
  };
  const long long bdf = steps("cvode_bdf"), bdf3 = steps("cvode_bdf3");
  CAPTURE(bdf, bdf3);
  CHECK(bdf3 > 2 * bdf);
}

TEST_CASE("every method reproduces the gravity-drop analytic checks", "[integrators]") {
  const auto method =
      GENERATE(as<std::string>{}, "rk4", "dopri5", "cash_karp54", "fehlberg78", "bulirsch_stoer",
               "rosenbrock4", "cvode_bdf", "cvode_bdf3", "cvode_adams");
  CAPTURE(method);
  ParameterSet p = ParameterSet::defaults_for("gravity-drop");
  p.set("contact.law", "hertz");  // elastic: the ball rebounds to where it started
  p.set("friction.law", "none");
  const auto scene = make_scene("gravity-drop", p);
  Onset o;
  const RunResult r = simulate(*scene, tight(method), TimeSettings{0.03, 1e-5}, o);
  REQUIRE(r.status == RunStatus::ok);
  const double g = 9.81, c = p.number("contact.clearance");
  // free fall through the clearance: t1 = sqrt(2 c / g), v1 = sqrt(2 g c). The onset is located
  // to ~1e-15 s on each method's interpolant; 1e-6 relative covers the tolerance-driven error.
  CHECK(o.t1 == Approx(std::sqrt(2 * c / g)).epsilon(1e-6));
  CHECK(o.v1 == Approx(std::sqrt(2 * g * c)).epsilon(1e-6));
  // an elastic rebound returns the ball to its release height (y = 0) within the sampling:
  // the apex is sampled every 10 us at speeds ~0 there, so the sampled apex is below the true
  // one by at most g (5e-6 s)^2 / 2 ~ 1e-10 m; 1e-3 of the clearance allows the method error
  CHECK(o.max_y == Approx(0.0).margin(1e-3 * c));
}

TEST_CASE("locating contact onset beats latching at the end of the step", "[integrators]") {
  // coarse rk4 steps (50 us) over a 10 ms fall: with "step-end" the impact speed is latched up
  // to one step after the onset, where gravity and the contact force have already changed it;
  // "locate" latches it at the onset itself
  ParameterSet p = ParameterSet::defaults_for("gravity-drop");
  const auto scene = make_scene("gravity-drop", p);
  const double v_exact = std::sqrt(2 * 9.81 * p.number("contact.clearance"));
  double err[2];
  int k = 0;
  for (const char* mode : {"locate", "step-end"}) {
    IntegratorSettings s;
    s.method = IntegratorMethod::rk4;
    s.step = 5e-5;
    s.contact_onset = *choice_from_name<ContactOnset>(mode);
    Onset o;
    // the coarse step is deliberate: the energy-audit health limit would stop the run
    HealthLimits lax;
    lax.max_energy_residual = 1e9;
    REQUIRE(simulate(*scene, s, TimeSettings{0.02, 1e-4}, o, lax).status == RunStatus::ok);
    err[k++] = std::abs(o.v1 - v_exact) / v_exact;
  }
  INFO("relative impact-speed error: locate " << err[0] << ", step-end " << err[1]);
  CHECK(err[0] < 1e-9);  // rk4 is exact on a parabola; bisection to ~1e-15 s
  CHECK(err[1] > 100 * err[0]);
}

TEST_CASE("presets resolve as documented", "[integrators]") {
  const auto bal = preset_settings("rod-end-kinematic", "balanced");
  REQUIRE(bal);
  const auto fast = preset_settings("rod-end-kinematic", "fast");
  const auto ref = preset_settings("rod-end-kinematic", "reference");
  REQUIRE(fast);
  REQUIRE(ref);
  // fast is no tighter than balanced, reference is tighter
  CHECK(fast->rel_tol >= bal->rel_tol);
  CHECK(ref->rel_tol < bal->rel_tol);
  CHECK_FALSE(preset_settings("rod-end-kinematic", "quick"));
  // every scene has every preset (its own row or the generic one)
  for (const SceneEntry& e : scene_catalogue())
    for (std::string_view name : preset_names()) CHECK(preset_settings(e.name, name));

  // a study: the default is the balanced preset; a preset with an override; a preset axis
  Json doc = Json::parse(
      R"({"scene": "rod-end-kinematic", "time": {"end": 0.1, "sample_interval": 1e-3}})");
  const Study plain = parse_study(doc, "p.json");
  CHECK(plain.cases[0].integrator.method == bal->method);
  CHECK(plain.cases[0].integrator.rel_tol == bal->rel_tol);
  doc["integrator"] = {{"preset", "reference"}, {"max_step", 1e-4}};
  const Study over = parse_study(doc, "p.json");
  CHECK(over.cases[0].integrator.method == ref->method);
  CHECK(over.cases[0].integrator.rel_tol == ref->rel_tol);
  CHECK(over.cases[0].integrator.max_step == 1e-4);
  doc.erase("integrator");
  doc["grid"] =
      Json::parse(R"([{"key": "integrator.preset", "values": ["fast", "balanced", "reference"]}])");
  const Study axis = parse_study(doc, "p.json");
  REQUIRE(axis.cases.size() == 3);
  CHECK(axis.cases[2].integrator.method == ref->method);
  doc["grid"] = Json::parse(R"([{"key": "integrator.preset", "values": ["quick"]}])");
  CHECK_THROWS_WITH(parse_study(doc, "p.json"),
                    Catch::Contains("integrator.preset") && Catch::Contains("unknown preset"));
}
