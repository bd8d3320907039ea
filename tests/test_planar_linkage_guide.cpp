// The planar linkage's prismatic guide with play (docs/planar-linkage.md): a free slider falls
// across its guide onto the wall at the analytic time (its actuator drives it along the guide
// only), and the guide tends to the ideal guide as its play and its walls' compliance vanish.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <numbers>
#include <regex>

#include "core/scene_parameters.hpp"
#include "fixture.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

constexpr double kG = 9.81;  // [m/s^2], the scenes' default gravity

Json leaf(const Json& v, const std::string& unit) {
  return {{"value", v}, {"unit", unit}, {"source", "assumed"}, {"note", "test"}};
}

/// The planar-linkage defaults as a tree, with `linkage` replaced: one slider (0.347 kg, the
/// rig's) on a guide along x with play `play` and walls of stiffness `k` [N/m], undamped,
/// its pin driven along x by the default motion (a 10 mm, 2 Hz sine).
ParameterSet free_slider(double play, double k) {
  Json tree = Json::object();
  const Json flat = ParameterSet::defaults_for("planar-linkage").leaves();
  for (auto it = flat.begin(); it != flat.end(); ++it)
    if (it.key().rfind("linkage.", 0) != 0)
      tree[Json::json_pointer("/" + std::regex_replace(it.key(), std::regex("\\."), "/"))] =
          it.value();
  const Json zero = {0.0, 0.0, 0.0};
  Json& l = tree["linkage"];
  l["ground"]["O"] = leaf(zero, "m");
  l["bodies"]["slider"] = {
      {"kind", leaf("rigid", "1")},          {"mass", leaf(0.347, "kg")},
      {"inertia", leaf(1.15e-4, "kg*m^2")},  {"center_of_mass", leaf(zero, "m")},
      {"origin", leaf(zero, "m")},           {"angle", leaf(0.0, "rad")},
      {"points", {{"pin", leaf(zero, "m")}}}};
  l["joints"]["guide"] = {{"type", leaf("prismatic", "1")},
                          {"a", leaf("slider.pin", "1")},
                          {"b", leaf("ground.O", "1")},
                          {"model", leaf("clearance", "1")},
                          {"clearance", leaf(play, "m")},
                          {"axis", leaf({1.0, 0.0, 0.0}, "1")},
                          {"stiffness", leaf(k, "N/m")},
                          {"damping_ratio", leaf(0.0, "1")},
                          {"friction_coefficient", leaf(0.2, "1")},
                          {"friction_speed", leaf(1e-3, "m/s")}};
  l["actuator"] = {{"kind", leaf("linear", "1")},
                   {"point", leaf("slider.pin", "1")},
                   {"rest", leaf("ground.O", "1")},
                   {"direction", leaf({1.0, 0.0, 0.0}, "1")}};
  l["output"] = leaf("slider.pin", "1");
  l["baumgarte_rate"] = leaf(100.0, "1/s");
  return ParameterSet::from_json(tree, "test");
}

/// The slider's y [m] at t_end (the state's second coordinate).
double slider_y(const ParameterSet& p, double t_end) {
  const auto scene = make_scene("planar-linkage", p);
  Recorder rec({SignalId::slider_position});
  const RunResult r = simulate(*scene, dopri5(1e-12, 1e-3), TimeSettings{t_end, t_end / 8}, rec);
  REQUIRE(r.status == RunStatus::ok);
  return r.final_state[1];
}

}  // namespace

TEST_CASE("planar linkage guide with play: a free slider falls onto the wall at the analytic time",
          "[planar-linkage][guide-play]") {
  // the slider starts on the guide's centre line at rest across it and falls freely, y = -g
  // t^2/2, until it meets the wall at y = -c: t_hit = sqrt(2 c / g). A time dt later the wall,
  // undamped, has pushed back by the double integral of k (v dt) / m: k v dt^3 / (6 m) with
  // v = g t_hit. The next terms: the wall's own push-back, -(w dt)^2/20 with w^2 = k/m
  // (-0.59 % at dt = 1 % of t_hit), and gravity still speeding the slider, +g dt/(4 v)
  // (+0.25 %): -0.34 % in all, as measured
  const double c = 2e-5, k = 1e8, m = 0.347;  // the rig guide's play and walls
  const double t_hit = std::sqrt(2.0 * c / kG);
  const ParameterSet p = free_slider(c, k);
  const double t1 = 0.99 * t_hit, t2 = 1.01 * t_hit, dt = t2 - t_hit;
  const double before = slider_y(p, t1) + 0.5 * kG * t1 * t1;
  const double after = slider_y(p, t2) + 0.5 * kG * t2 * t2;
  const double pushed = k * kG * t_hit * dt * dt * dt / (6.0 * m);  // 7.8e-9 m
  // before the wall: free fall, exact to the integration (a parabola: round-off of y ~ 2e-5)
  measured("free slider before the wall: y - free fall [m]", std::abs(before), 1e-15);
  measured("free slider after the wall: push-back / analytic - 1", after / pushed - 1.0, 0.01);
  CHECK(std::abs(before) < 1e-15);
  CHECK(after / pushed == Approx(1.0).margin(0.01));
}

namespace {
/// The slider-crank through the linkage, every joint ideal, its guide ideal or with play
/// `play` [m] and walls of stiffness `k` [N/m], frictionless (the ideal guide's law).
ParameterSet rig_with_guide(double play, double k) {
  const std::string file =
      std::string(RODEND_SOURCE_DIR) + "/tests/linkage/slider-crank.scene.json";
  std::ifstream in(file);
  REQUIRE(in.good());
  ParameterSet p = ParameterSet::from_json(compose_scene_parameters(Json::parse(in), file), file);
  p.set("linkage.joints.rod_slider.model", "ideal");
  if (play > 0.0) {
    p.set("linkage.joints.guide.model", "clearance");
    p.set("linkage.joints.guide.clearance", play);
    p.set("linkage.joints.guide.stiffness", k);
    p.set("linkage.joints.guide.friction_coefficient", 0.0);
  }
  return p;
}
Track rig_run(const ParameterSet& p) {
  const auto scene = make_scene("planar-linkage", p);
  Recorder rec({SignalId::slider_position});
  const double turn = 2.0 * std::numbers::pi / (500.0 * 2.0 * std::numbers::pi / 60.0);
  REQUIRE(simulate(*scene, dopri5(1e-10, 1e-3), TimeSettings{turn, 1e-4}, rec).status ==
          RunStatus::ok);
  return rec.samples;
}
}  // namespace

TEST_CASE("planar linkage guide with play: zero play and rigid walls give the ideal guide",
          "[planar-linkage][guide-play]") {
  // with play c and walls of stiffness k the pin is off the guide's line by at most
  // |y| <= c + F/k, F the guide's largest load: at most the rod's mass times the crank pin's
  // acceleration r w^2 plus the rod's and the slider's weights, 1.072 x 137 + 1.419 x 9.81 =
  // 161 N (rig values). Off the line by y, the loop closes with the slider at most
  // |dx/dy| = r / sqrt(L^2 - r^2) = 0.169 further along it; so |dx| <= 0.169 (c + 161 N / k)
  const Track ideal = rig_run(rig_with_guide(0.0, 0.0));
  double previous = 0.0;
  for (const auto& [c, k] : {std::pair{1e-6, 1e8}, std::pair{1e-7, 1e9}, std::pair{1e-8, 1e10}}) {
    const Track play = rig_run(rig_with_guide(c, k));
    REQUIRE(play.size() == ideal.size());
    double dx = 0.0;
    for (std::size_t i = 0; i < ideal.size(); ++i)
      dx = std::max(dx, std::abs(play.get(i, SignalId::slider_position) -
                                 ideal.get(i, SignalId::slider_position)));
    const double bound = 0.169 * (c + 161.0 / k);
    char what[96];
    std::snprintf(what, sizeof what, "guide play %g m, walls %g N/m: slider off the ideal [m]", c,
                  k);
    measured(what, dx, bound);
    CHECK(dx < bound);
    if (previous > 0.0) CHECK(dx < 0.2 * previous);
    previous = dx;
  }
}

TEST_CASE("planar linkage guide with play: the energy audit closes with the walls and friction",
          "[planar-linkage][guide-play]") {
  // the slider-crank through the linkage with its guide's default play (20 um, 100 N/um walls
  // damped at 0.1, friction 0.2): the walls' elastic energy is mechanical energy, their damping
  // and the friction dissipation; the residual against the input work is the quadrature error
  // of the audit integrals (fixture.hpp, kEnergyResidualRel)
  ParameterSet p = rig_with_guide(0.0, 0.0);
  p.set("linkage.joints.guide.model", "clearance");
  const auto scene = make_scene("planar-linkage", p);
  Recorder rec({SignalId::energy_residual, SignalId::input_work, SignalId::dissipated_energy},
               true);
  const double turn = 2.0 * std::numbers::pi / (500.0 * 2.0 * std::numbers::pi / 60.0);
  REQUIRE(simulate(*scene, dopri5(1e-10, 1e-3), TimeSettings{turn, 1e-4}, rec).status ==
          RunStatus::ok);
  double worst = 0.0, work = 0.0;
  for (std::size_t i = 0; i < rec.steps.size(); ++i) {
    worst = std::max(worst, std::abs(rec.steps.get(i, SignalId::energy_residual)));
    work = std::max(work, std::abs(rec.steps.get(i, SignalId::input_work)));
  }
  const double lost = rec.steps.get(rec.steps.size() - 1, SignalId::dissipated_energy);
  REQUIRE(work > 0.0);
  measured("guide with play: energy residual / input work", worst / work, kEnergyResidualRel);
  measured("guide with play: dissipated energy [J]", lost, 0.0);
  CHECK(lost > 0.0);  // the walls and the friction do dissipate
  CHECK(worst / work < kEnergyResidualRel);
}
