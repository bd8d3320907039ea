// Issue 17, part A: the energy_residual metric's scale, the eq. 3.14 damping cap, the chamber
// flow sign, the thesis's command stroke, and the summary metrics of the full system that
// settle with the tolerance (docs/thesis-deviations.md).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "core/contact.hpp"
#include "core/scenes/servo_actuator.hpp"
#include "core/scenes/slider_crank.hpp"
#include "fixture.hpp"
#include "sweep/metrics.hpp"
#include "sweep/runner.hpp"
#include "sweep/study.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

double metric(const CaseRecord& r, MetricId id) {
  return r.metrics[static_cast<std::size_t>(id)];
}

/// Runs the one case of a study document as `rodend run` would, and requires it to be ok.
CaseRecord run_one(Json doc, History* history = nullptr) {
  doc["name"] = "fidelity-test";
  const Study s = parse_study(doc, "fidelity-test.json", "/tmp/rodend-results");
  REQUIRE(s.cases.size() == 1);
  History h;
  const CaseRecord r = run_case(s.cases.at(0), history ? *history : h);
  INFO(r.message);
  REQUIRE(r.status == RunStatus::ok);
  return r;
}

Json impact_doc(const std::string& law, const Json& integrator) {
  return {{"scene", "impact-pair"},
          {"parameters",
           {{"contact", {{"law", law}, {"restitution", 0.8}}},
            {"impact", {{"approach_speed", 0.1}, {"outer_body", "free"}}}}},
          {"integrator", integrator},
          {"time", {{"end", 1e-3}, {"sample_interval", 1e-4}}},
          {"signals", Json::array({"energy_residual"})}};
}

}  // namespace

// --- energy_residual -----------------------------------------------------------------------------

TEST_CASE("energy_residual: lossless runs read their audit's round-off, not 1",
          "[metrics][energy]") {
  // A Hertz impact (chi = 0: no damping, no friction, no input) and a torque-free body lose
  // nothing: their input work and dissipation are 0 for the whole run, so a residual relative to
  // those flows (or to the mechanical-energy change, which is the residual itself) reads 1. The
  // scale is the kinetic energy they carry. measured (reference preset): Hertz impact 4.6e-9...
  // see the measured() lines; the bound is the brief's 1e-6.
  const CaseRecord hertz = run_one(impact_doc("hertz", {{"preset", "reference"}}));
  CHECK(metric(hertz, MetricId::input_work) == 0.0);
  CHECK(metric(hertz, MetricId::dissipated_energy) == 0.0);
  measured("energy_residual: Hertz impact, reference", metric(hertz, MetricId::energy_residual),
           1e-6);
  CHECK(metric(hertz, MetricId::energy_residual) < 1e-6);

  const Json body = {{"scene", "free-body"},
                     {"parameters",
                      {{"force", {{"amplitude", {0.0, 0.0, 0.0}}}},
                       {"moment", {{"amplitude", {0.0, 0.0, 0.0}}}},
                       {"body", {{"initial_angular_velocity", {1.0, 0.1, 0.5}}}}}},
                     {"integrator", {{"preset", "reference"}}},
                     {"time", {{"end", 10.0}, {"sample_interval", 0.01}}},
                     {"signals", Json::array({"energy_residual"})}};
  const CaseRecord free = run_one(body);
  CHECK(metric(free, MetricId::input_work) == 0.0);
  measured("energy_residual: torque-free body, reference", metric(free, MetricId::energy_residual),
           1e-6);
  CHECK(metric(free, MetricId::energy_residual) < 1e-6);
  CHECK(metric(free, MetricId::energy_residual) >= 0.0);
}

TEST_CASE("energy_residual: a damped impact's residual shrinks with the tolerance",
          "[metrics][energy]") {
  // Lankarani-Nikravesh, c_r = 0.8: the audit's residual is the integration error of the
  // dissipated-energy state and of the bodies; it must fall as the tolerance tightens (by at
  // least a decade over two decades of tolerance) and stay far below the 1 % health limit
  std::vector<double> r;
  for (double tol : {1e-6, 1e-8, 1e-10}) {
    const CaseRecord c = run_one(
        impact_doc("lankarani-nikravesh",
                   {{"method", "dopri5"}, {"abs_tol", tol}, {"rel_tol", tol}, {"max_step", 1e-3}}));
    CHECK(metric(c, MetricId::dissipated_energy) > 0.0);
    r.push_back(metric(c, MetricId::energy_residual));
    measured("energy_residual: damped impact at tol " + std::to_string(tol), r.back(), 1e-2);
  }
  CHECK(r[0] < 1e-2);
  CHECK(r[1] < r[0]);
  CHECK(r[2] < r[1]);
  CHECK(r[2] < 0.1 * r[0]);
}

// --- eq. 3.14 damping cap ------------------------------------------------------------------------

namespace {

ClearanceContactModel hertz_sphere(double chi, DampingCap cap) {
  ClearanceContactModel m;
  m.ball_radius = 0.01;
  m.clearance = 5e-4;
  m.stiffness = sphere_in_sphere_stiffness(0.01, 0.0105, 206e9, 0.3, 206e9, 0.3);
  m.hysteresis = chi;
  m.damping_cap = cap;
  return m;
}

BodyKinematics at_rest() {
  BodyKinematics k;
  k.p_W = k.v_W = k.w_B = k.w_W = Vec3::Zero();
  k.q_WB = Quat::Identity();
  k.R_WB = Mat3::Identity();
  return k;
}

/// Ball displaced along +x by clearance + delta, approaching at `rate` (socket at rest).
ContactEval press(const ClearanceContactModel& m, double delta, double rate, double latched) {
  BodyKinematics ball = at_rest(), socket = at_rest();
  ball.p_W = Vec3(m.clearance + delta, 0, 0);
  ball.v_W = Vec3(rate, 0, 0);
  return evaluate_contact(m, ball, socket, ContactLatch{true, latched});
}

}  // namespace

TEST_CASE("eq. 3.14 cap: the damping term never exceeds the elastic term", "[contact][cap]") {
  // the catalogue is the one list of allowed values: every scene with a contact offers it
  std::vector<std::string> names;
  for (std::string_view n : choice_names(DampingCap{})) names.emplace_back(n);
  REQUIRE(names == std::vector<std::string>{"none", "elastic"});
  for (const SceneEntry& s : scene_catalogue()) {
    const ParameterSet p = ParameterSet::defaults_for(s.name);
    if (!p.has("contact.law")) continue;
    CAPTURE(s.name);
    CHECK(p.leaves().at("contact.damping_cap").at("choices").get<std::vector<std::string>>() ==
          names);
    CHECK(p.text("contact.damping_cap") == "none");  // the default (docs/thesis-deviations.md)
  }
  // chi = 3.7 (Flores at c_r = 0.3): approaching at the latched speed, eq. 3.6 gives
  // F_el (1 + 3.7); the cap keeps the damping at F_el, so F = 2 F_el, whatever the rate
  const double delta = 1e-6, v = 0.1;
  const auto none = hertz_sphere(3.7, DampingCap::none);
  const auto cap = hertz_sphere(3.7, DampingCap::elastic);
  for (double rate : {0.01, 0.1, 1.0, 10.0}) {
    CAPTURE(rate);
    const ContactEval a = press(none, delta, rate, v), b = press(cap, delta, rate, v);
    CHECK(a.elastic_force == b.elastic_force);
    CHECK(b.normal_force - b.elastic_force <= b.elastic_force);
    CHECK(b.normal_force == std::min(a.normal_force, 2.0 * a.elastic_force));
    if (rate / v * 3.7 > 1.0) CHECK(b.normal_force == 2.0 * b.elastic_force);
    CHECK(b.damping_power == Approx((b.normal_force - b.elastic_force) * rate));
  }
  // restitution (rate < 0): the cap bounds only from above; the no-pull clamp still holds
  for (double rate : {-0.01, -0.1, -1.0}) {
    CAPTURE(rate);
    const ContactEval a = press(none, delta, rate, v), b = press(cap, delta, rate, v);
    // F_el (1 + r) against F_el + F_el r: equal to round-off
    CHECK(b.normal_force == Approx(a.normal_force).epsilon(1e-14));
    CHECK(b.normal_force >= 0.0);
  }
  // an elastic law (chi = 0) is untouched by the cap: the same force for every rate
  const auto el_none = hertz_sphere(0.0, DampingCap::none);
  const auto el_cap = hertz_sphere(0.0, DampingCap::elastic);
  for (double rate : {-1.0, -0.1, 0.0, 0.1, 1.0, 10.0})
    CHECK(press(el_cap, delta, rate, v).normal_force ==
          press(el_none, delta, rate, v).normal_force);
}

TEST_CASE("eq. 3.14 cap: an impact with a large chi dissipates less and still balances",
          "[contact][cap][impact]") {
  // Flores at c_r = 0.3 (chi = 3.73): at onset eq. 3.6 already exceeds twice the elastic force,
  // so the cap removes damping early in the compression and the impact restitutes more.
  // measured (reference preset): restitution 0.2562 without, 0.2650 with the cap (the cap binds
  // only while delta' > delta'^-/chi = 0.27 delta'^-, the first part of the compression, where
  // the penetration and so the elastic force are still small). Hertz is unchanged.
  auto run = [](const std::string& law, const std::string& cap) {
    Json doc = impact_doc(law, {{"preset", "reference"}});
    doc["parameters"]["contact"]["restitution"] = 0.3;
    doc["parameters"]["contact"]["damping_cap"] = cap;
    return run_one(doc);
  };
  const CaseRecord a = run("flores", "none"), b = run("flores", "elastic");
  const double ea = metric(a, MetricId::first_impact_restitution);
  const double eb = metric(b, MetricId::first_impact_restitution);
  measured("cap: Flores c_r 0.3 restitution gained with the cap", eb - ea, 0.0);
  CHECK(eb > ea + 0.005);
  CHECK(metric(b, MetricId::dissipated_energy) < metric(a, MetricId::dissipated_energy));
  CHECK(metric(b, MetricId::energy_residual) < 1e-6);
  const CaseRecord h1 = run("hertz", "none"), h2 = run("hertz", "elastic");
  CHECK(metric(h1, MetricId::first_impact_restitution) ==
        metric(h2, MetricId::first_impact_restitution));
  CHECK(metric(h1, MetricId::max_contact_force) == metric(h2, MetricId::max_contact_force));
}

// --- metrics that settle with the tolerance ------------------------------------------------------

namespace {

/// Each metric of `run` within `bound` (relative) of the same metric of `reference`; `label`
/// names the pair in the measured() lines.
void check_metrics_agree(const CaseRecord& run, const CaseRecord& reference,
                         std::initializer_list<MetricId> ids, double bound,
                         const std::string& label) {
  for (MetricId id : ids) {
    const std::string name(metric_catalogue()[static_cast<std::size_t>(id)].name);
    CAPTURE(label, name, metric(run, id), metric(reference, id));
    REQUIRE(std::isfinite(metric(reference, id)));
    REQUIRE(metric(reference, id) != 0.0);
    const double rel = std::abs(metric(run, id) / metric(reference, id) - 1.0);
    measured(label + ": " + name, rel, bound);
    CHECK(rel < bound);
  }
}

}  // namespace

TEST_CASE("full-system summary metrics agree to 1 % between the balanced and reference presets",
          "[metrics][actuator][convergence]") {
  // One thesis cycle (+60 / -60 mm) on rod-end-actuator at 0.5 mm clearance. The first-impact
  // metrics do not settle (the first impact's timing and speed are sensitive to every step
  // before it); these whole-run metrics do. measured: see the measured() lines.
  auto run = [](const std::string& preset) {
    return run_one({{"scene", "rod-end-actuator"},
                    {"integrator", {{"preset", preset}}},
                    {"time", {{"end", 2.4}, {"sample_interval", 1e-2}}},
                    {"signals", Json::array({"surface_angle"})}});
  };
  const CaseRecord b = run("balanced"), r = run("reference");
  check_metrics_agree(
      b, r,
      {MetricId::max_contact_force, MetricId::max_eccentricity, MetricId::wear_integral,
       MetricId::max_rear_chamber_pressure, MetricId::max_front_chamber_pressure,
       MetricId::surface_angle_error_extended, MetricId::surface_angle_error_retracted,
       MetricId::max_surface_angle, MetricId::min_surface_angle, MetricId::dissipated_energy},
      1e-2, "balanced vs reference");
  // the stroke-end errors are the lost motion of the clearance and the compliances: a fraction
  // of the clearance over the crank, c / s = 4.5 mrad, not more than a few of it
  for (MetricId id :
       {MetricId::surface_angle_error_extended, MetricId::surface_angle_error_retracted})
    CHECK(std::abs(metric(r, id)) < 3.0 * 5e-4 / 0.11);
}

TEST_CASE("the kinematic scene's presets run the thesis clearance study to its smallest clearance",
          "[metrics][presets][convergence]") {
  // The work-precision study's cases (plots/work_precision.py: +50 mm out, back to 0, clearance
  // 0.1 and 0.5 mm). Every preset must end ok (cvode_bdf 1e-5 failed the energy audit at
  // 0.1 mm on 2026-11-25: residual 1.045 % of the energy flow at t = 0.0698 s; it is the fast
  // preset since issue 34 and ends ok), and fast and balanced must meet the accuracy their names
  // promise against the reference on the whole-run metrics: 10 % and 1 % (measured: largest
  // 7.6e-3 and 7.7e-6 over five clearances, docs/performance.md).
  for (double clearance : {1e-4, 5e-4}) {
    auto run = [&](const std::string& preset) {
      return run_one({{"scene", "rod-end-kinematic"},
                      {"parameters",
                       {{"contact.clearance", clearance},
                        {"motion.extension", 0.05},
                        {"motion.retraction", 0.0}}},
                      {"integrator", {{"preset", preset}}},
                      {"time", {{"end", 2.4}, {"sample_interval", 1e-2}}},
                      {"signals", Json::array({"surface_angle"})}});
    };
    // run_one requires status ok: a preset the health checks refuse fails here
    const CaseRecord r = run("reference");
    for (const auto& [preset, bound] : {std::pair{"fast", 0.1}, std::pair{"balanced", 1e-2}}) {
      CAPTURE(clearance);
      check_metrics_agree(run(preset), r,
                          {MetricId::max_contact_force, MetricId::max_eccentricity,
                           MetricId::wear_integral, MetricId::first_impact_speed},
                          bound, std::string(preset) + " vs reference");
    }
  }
}

// --- command stroke and surface angle
// -------------------------------------------------------------

TEST_CASE("the thesis stroke +-60 mm is the default and gives +33.4 / -32.7 deg of surface",
          "[slider-crank][fidelity]") {
  for (const char* scene : {"rod-end-kinematic", "rod-end-actuator"}) {
    const ParameterSet p = ParameterSet::defaults_for(scene);
    CAPTURE(scene);
    CHECK(p.number("motion.extension") == 0.06);
    CHECK(p.number("motion.retraction") == 0.06);
  }
  // law of cosines by hand (thesis eq. 4.1), s = 0.11, t = 0.38, l0 = 0.37 m
  const double s = 0.11, t = 0.38, l0 = 0.37, deg = 180.0 / std::acos(-1.0);
  auto gamma = [&](double l) { return std::acos((t * t + s * s - l * l) / (2.0 * s * t)); };
  const SliderCrank sc(s, t, l0);
  CHECK(sc.ideal_crank_angle(l0 + 0.06) == Approx(gamma(l0 + 0.06) - gamma(l0)).epsilon(1e-12));
  CHECK(sc.ideal_crank_angle(l0 + 0.06) * deg == Approx(33.42).margin(0.01));
  CHECK(sc.ideal_crank_angle(l0 - 0.06) * deg == Approx(-32.70).margin(0.01));
  // +-35 deg would take +62.5 / -63.7 mm of stroke with the thesis's lengths
  CHECK(sc.ideal_crank_angle(l0 + 0.0625) * deg == Approx(35.0).margin(0.01));
  CHECK(sc.ideal_crank_angle(l0 - 0.0637) * deg == Approx(-35.0).margin(0.02));
  // the kinematic scene's surface follows the command to within the lost motion of the clearance
  const CaseRecord r = run_one({{"scene", "rod-end-kinematic"},
                                {"integrator", {{"preset", "fast"}}},
                                {"time", {{"end", 2.4}, {"sample_interval", 1e-2}}},
                                {"signals", Json::array({"surface_angle"})}});
  CHECK(metric(r, MetricId::max_surface_angle) * deg == Approx(33.4).margin(0.5));
  CHECK(metric(r, MetricId::min_surface_angle) * deg == Approx(-32.7).margin(0.5));
}

// --- chamber flow sign ---------------------------------------------------------------------------

TEST_CASE("chamber flows are positive into each chamber (thesis fig. 6.20-6.21)",
          "[actuator][fidelity]") {
  History h;
  run_one({{"scene", "rod-end-actuator"},
           {"integrator", {{"preset", "balanced"}}},
           {"time", {{"end", 2.4}, {"sample_interval", 1e-2}}},
           {"signals", Json::array({"actuator_velocity", "chamber_flows"})}},
          &h);
  auto column = [&](SignalId id) {
    for (std::size_t i = 0; i < h.signals.size(); ++i)
      if (h.signals[i] == id) return h.values[i];
    FAIL("signal not recorded");
    return std::vector<double>{};
  };
  const auto v = column(SignalId::actuator_velocity);
  const auto q = column(SignalId::chamber_flows);  // interleaved: q1, q2 per sample
  REQUIRE(q.size() == 2 * v.size());
  int extending = 0, retracting = 0;
  const double A = 5e-4;  // piston area [m^2] (parameter file)
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (std::abs(v[k]) < 0.05) continue;  // fast strokes only: the flows then carry A v
    const double q1 = q[2 * k], q2 = q[2 * k + 1];
    // extension fills chamber 1 and empties chamber 2; retraction the reverse (fig. 6.21:
    // positive into the front chamber while retracting)
    CHECK(q1 * v[k] > 0.0);
    CHECK(q2 * v[k] < 0.0);
    // each within 10 % of A |x'| (compressibility and leakage take the rest)
    CHECK(std::abs(q1) == Approx(A * std::abs(v[k])).epsilon(0.1));
    CHECK(std::abs(q2) == Approx(A * std::abs(v[k])).epsilon(0.1));
    (v[k] > 0 ? extending : retracting)++;
  }
  CHECK(extending > 10);
  CHECK(retracting > 10);
}

// --- torque motor (eq. 6.1) ----------------------------------------------------------------------

TEST_CASE("torque motor: the solenoid law of eq. 6.1 against the linear one",
          "[actuator][fidelity]") {
  std::vector<std::string> names;
  for (std::string_view n : choice_names(TorqueMotor{})) names.emplace_back(n);
  REQUIRE(names == std::vector<std::string>{"linear", "solenoid"});
  for (const char* scene : {"servo-actuator", "rod-end-actuator"}) {
    const ParameterSet p = ParameterSet::defaults_for(scene);
    CAPTURE(scene);
    CHECK(p.leaves().at("actuator.torque_motor").at("choices").get<std::vector<std::string>>() ==
          names);
    CHECK(p.text("actuator.torque_motor") == "linear");
  }
  ParameterSet p = ParameterSet::defaults_for("servo-actuator");
  ServoActuatorParams a = read_servo_actuator(p, "actuator");
  const ServoActuator lin(a);
  a.torque_motor = TorqueMotor::solenoid;
  const ServoActuator sol(a);
  const double Ir = a.current_limit;
  // the same force at the rated current, either sign; B^2 ~ i^2 below it: a quarter at half
  for (double sgn : {-1.0, 1.0}) {
    CHECK(sol.motor_force(sgn * Ir) == Approx(lin.motor_force(sgn * Ir)).epsilon(1e-15));
    CHECK(sol.motor_force(sgn * 0.5 * Ir) ==
          Approx(0.5 * lin.motor_force(sgn * 0.5 * Ir)).epsilon(1e-15));
  }
  CHECK(sol.motor_force(0.0) == 0.0);
  CHECK(lin.motor_force(0.3 * Ir) == Approx(a.motor_gain * 0.3 * Ir).epsilon(1e-15));
}

// --- figs. 6.27-6.29: spring-force signs and where the wear peaks, under a constant moment
// --------

TEST_CASE(
    "constant clockwise hinge moment: outer spring compressed, inner spring on the ball "
    "pushed back, and the wear peak away from the force peak (thesis figs. 6.27-6.29)",
    "[actuator][fidelity][hinge]") {
  // M0 = -30 N m from t = 0 (clockwise, opposing extension), the thesis cycle +-60 mm. The
  // moment exceeds the surface's dynamic load (hinge damping c theta' <= 2 N m s x 2.3 rad/s =
  // 4.6 N m at the retraction's peak rate), so the rod pushes for the whole cycle (fig. 6.27);
  // at -3 N m it does not (docs/thesis-deviations.md#fig-6-27-6-28-outer-spring-signs).
  // dopri5 1e-7: ~4e5 steps. measured: slider F_x on the socket 215..302 N, crank F_x on the ball
  // -299..-215 N; on the retraction the force peaks at its start (274 N, t = 1.200 s) and the
  // wear indicator mid-stroke (t = 1.50 s), where the force is 0.88 of its peak.
  History h;
  const CaseRecord r =
      run_one({{"scene", "rod-end-actuator"},
               {"parameters", {{"hinge", {{"kind", "constant"}, {"constant_moment", -30.0}}}}},
               {"integrator",
                {{"method", "dopri5"}, {"abs_tol", 1e-7}, {"rel_tol", 1e-7}, {"max_step", 1e-3}}},
               {"time", {{"end", 2.4}, {"sample_interval", 1e-3}}},
               {"signals", Json::array({"slider_spring_force", "crank_spring_force",
                                        "contact_force", "wear_indicator"})}},
              &h);
  auto column = [&](SignalId id) {
    for (std::size_t i = 0; i < h.signals.size(); ++i)
      if (h.signals[i] == id) return h.values[i];
    FAIL("signal not recorded");
    return std::vector<double>{};
  };
  const auto t = column(SignalId::time);
  const auto fs = column(SignalId::slider_spring_force);  // x, y, z per sample
  const auto fc = column(SignalId::crank_spring_force);
  const auto f = column(SignalId::contact_force);
  const auto w = column(SignalId::wear_indicator);
  REQUIRE(fs.size() == 3 * t.size());
  std::size_t checked = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] < 0.05) continue;  // the step of the moment at t = 0 rings first
    CHECK(fs[3 * k] > 0.0);     // fig. 6.27: the outer spring pushes the socket: compressed
    CHECK(fc[3 * k] < 0.0);     // fig. 6.28: the inner spring pushes the ball back (compressed)
    CHECK(f[k] > 0.0);          // fig. 6.24: in contact throughout
    ++checked;
  }
  CHECK(checked > 2000);
  // fig. 6.29: on the retraction (1.2-2.2 s) the wear indicator F_n v_slip peaks where the
  // slip is fast (mid-stroke), not where the force peaks (the reversal)
  std::size_t kf = 0, kw = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] < 1.2 || t[k] > 2.2) continue;
    if (kf == 0 || f[k] > f[kf]) kf = k;
    if (kw == 0 || w[k] > w[kw]) kw = k;
  }
  CAPTURE(t[kf], t[kw], f[kf], f[kw]);
  CHECK(std::abs(t[kw] - t[kf]) > 0.1);
  CHECK(f[kw] < 0.95 * f[kf]);
  CHECK(metric(r, MetricId::impact_count) >= 1.0);
}
