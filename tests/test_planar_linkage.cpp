// Scene planar-linkage (docs/planar-linkage.md) with the flap actuation linkage: the ideal
// linkage against the closed-form kinematics of its geometry, restated here so that the test
// does not take it from the part file it checks.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <regex>

#include "fixture.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

// the flap linkage's geometry (core/scenes/parts/flap-linkage.part.json) [m]
constexpr double kA1 = 0.06;                // joint 3 (pivot) to joint 1 on the auxiliary lever arm
constexpr double kA2 = 0.04;                // joint 3 to joint 2
constexpr double kRod = 0.2;                // actuating rod
constexpr double kAux = 0.25;               // auxiliary rod, joint 2 to joint 4
constexpr double kLever = 0.075;            // lever arm, shaft to joint 4
constexpr double kAmp = 0.01, kFreq = 2.0;  // actuator [m], [Hz]
const Eigen::Vector2d kShaft(0.25, -0.115), kRest(-0.2, 0.06);

/// The intersection of the circles (c1, r1) and (c2, r2) nearer to `near`.
Eigen::Vector2d meet(const Eigen::Vector2d& c1, double r1, const Eigen::Vector2d& c2, double r2,
                     const Eigen::Vector2d& near) {
  const Eigen::Vector2d u = (c2 - c1).normalized();
  const double d = (c2 - c1).norm(), a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
  const double h = std::sqrt(r1 * r1 - a * a);
  const Eigen::Vector2d m = c1 + a * u, n(-u.y(), u.x());
  const Eigen::Vector2d p = m + h * n, q = m - h * n;
  return (p - near).norm() < (q - near).norm() ? p : q;
}

/// The shaft angle (lever arm from the shaft to joint 4, from the +y axis) at actuator
/// displacement d: joint 1 where the actuating rod from the actuator's end meets the arm's
/// circle about joint 3, joint 2 opposite it, joint 4 where the auxiliary rod meets the lever's
/// circle about the shaft.
double shaft_angle(double d) {
  const Eigen::Vector2d E = kRest + Eigen::Vector2d(d, 0.0);
  const Eigen::Vector2d J1 = meet(Eigen::Vector2d::Zero(), kA1, E, kRod, {0.0, kA1});
  const Eigen::Vector2d J2 = -(kA2 / kA1) * J1;
  const Eigen::Vector2d J4 = meet(kShaft, kLever, J2, kAux, {0.25, -kA2});
  const Eigen::Vector2d r = J4 - kShaft;
  return std::atan2(-r.x(), r.y());
}
double shaft_angle_at(double t) {
  return shaft_angle(kAmp * std::sin(2.0 * std::numbers::pi * kFreq * t)) - shaft_angle(0.0);
}

ParameterSet flap(const std::string& joint_1 = "ideal") {
  ParameterSet p = ParameterSet::defaults_for("planar-linkage");
  p.set("linkage.joints.joint_1.model", joint_1);
  return p;
}

const std::initializer_list<SignalId> kSignals = {
    SignalId::surface_angle,      SignalId::surface_angle_command, SignalId::surface_rate,
    SignalId::ideal_surface_rate, SignalId::surface_acceleration,  SignalId::constraint_drift,
    SignalId::energy_residual,    SignalId::kinetic_energy,        SignalId::input_work};

Recorder run(const ParameterSet& p, double periods, double tol = 1e-10) {
  const auto scene = make_scene("planar-linkage", p);
  Recorder rec(kSignals, true);
  const RunResult r = simulate(*scene, dopri5(tol, 1e-3), TimeSettings{periods / kFreq, 1e-3}, rec);
  REQUIRE(r.status == RunStatus::ok);
  return rec;
}

}  // namespace

TEST_CASE("planar linkage: every joint ideal follows the closed-form kinematics",
          "[planar-linkage]") {
  const Recorder rec = run(flap("ideal"), 2.0);
  const Track& s = rec.steps;
  REQUIRE(s.size() > 50);
  // the shaft's amplitude is the chosen 5.1 deg (the lever ratio's derivation)
  CHECK(shaft_angle(kAmp) - shaft_angle(0.0) == Approx(0.0889).margin(0.002));
  const double w = 2.0 * std::numbers::pi * kFreq,
               amp = std::abs(shaft_angle(kAmp) - shaft_angle(0.0));
  double e_angle = 0.0, e_cmd = 0.0, e_rate = 0.0, e_acc = 0.0, drift = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double t = s.time(i), h = 1e-5, h2 = 1e-4;
    const double cf = shaft_angle_at(t);
    const double rate = (shaft_angle_at(t + h) - shaft_angle_at(t - h)) / (2.0 * h);
    const double acc = (shaft_angle_at(t + h2) - 2.0 * cf + shaft_angle_at(t - h2)) / (h2 * h2);
    e_angle = std::max(e_angle, std::abs(s.get(i, SignalId::surface_angle) - cf) / amp);
    e_cmd = std::max(e_cmd, std::abs(s.get(i, SignalId::surface_angle_command) - cf) / amp);
    e_rate = std::max(e_rate, std::abs(s.get(i, SignalId::surface_rate) - rate) / (amp * w));
    e_acc =
        std::max(e_acc, std::abs(s.get(i, SignalId::surface_acceleration) - acc) / (amp * w * w));
    drift = std::max(drift, s.get(i, SignalId::constraint_drift));
  }
  // the integration at tolerance 1e-10 on the scaled state (measured 5.7e-12, 2.7e-9 and
  // 5.7e-14 m); the acceleration against second differences of the closed form, whose
  // truncation is ~1e-7 of the scale (measured 1.5e-7)
  measured("ideal linkage: shaft angle (rel to amplitude)", e_angle, 1e-8);
  measured("ideal solve: shaft angle (rel)", e_cmd, 1e-10);
  measured("ideal linkage: shaft rate (rel to amplitude x w)", e_rate, 1e-7);
  measured("ideal linkage: shaft acceleration (rel to amplitude x w^2)", e_acc, 1e-5);
  measured("ideal linkage: constraint drift [m]", drift, 1e-9);
  CHECK(e_angle < 1e-8);
  CHECK(e_cmd < 1e-10);
  CHECK(e_rate < 1e-7);
  CHECK(e_acc < 1e-5);
  CHECK(drift < 1e-9);
}

namespace {
/// Largest |surface_angle - surface_angle_command| over the steps, relative to the amplitude.
double largest_angle_error(const Track& s) {
  const double amp = std::abs(shaft_angle(kAmp) - shaft_angle(0.0));
  double e = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i)
    e = std::max(
        e, std::abs(s.get(i, SignalId::surface_angle) - s.get(i, SignalId::surface_angle_command)) /
               amp);
  return e;
}
}  // namespace

TEST_CASE("planar linkage: a clearance joint tends to the ideal joint as its clearance vanishes",
          "[planar-linkage]") {
  // joint 1 with clearance c: the shaft can be off the ideal linkage's by about the lost motion
  // c over the arm (60 mm) times the lever ratio, plus the contact's deflection; both vanish
  // with c (the contact's force is the same, its Hertz deflection shrinks with the gap's
  // curvature term (2 (c + delta))^-1/2)
  double previous = 0.0;
  for (const double c : {1e-5, 1e-6, 1e-7}) {
    ParameterSet p = flap("clearance");
    p.set("linkage.joints.joint_1.clearance", c);
    const double e = largest_angle_error(run(p, 0.5, 1e-8).steps);
    // lost motion bound: c / a1 x a2 / b over the amplitude, with 20 % for the deflection
    const double bound =
        1.2 * (c / kA1) * (kA2 / kLever) / std::abs(shaft_angle(kAmp) - shaft_angle(0.0));
    measured("clearance " + std::to_string(c) + " m: shaft angle error (rel)", e, bound);
    CHECK(e < bound);
    if (previous > 0.0) CHECK(e < 0.5 * previous);
    previous = e;
  }
}

TEST_CASE("planar linkage: energy is conserved with contact damping and friction off",
          "[planar-linkage]") {
  ParameterSet p = flap("clearance");
  p.set("contact.law", "hertz");
  p.set("friction.law", "none");
  const Recorder rec = run(p, 1.0, 1e-10);
  double worst = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < rec.steps.size(); ++i) {
    worst = std::max(worst, std::abs(rec.steps.get(i, SignalId::energy_residual)));
    scale = std::max({scale, std::abs(rec.steps.get(i, SignalId::input_work)),
                      rec.steps.get(i, SignalId::kinetic_energy)});
  }
  REQUIRE(scale > 0.0);
  measured("lossless linkage: energy residual (rel)", worst / scale, kEnergyResidualRel);
  CHECK(worst / scale < kEnergyResidualRel);
}

namespace {
Json leaf(const Json& v, const std::string& unit) {
  return {{"value", v}, {"unit", unit}, {"source", "assumed"}, {"note", "test"}};
}
/// A rigid bar body for the part-file tree: mass, inertia, mass centre, pose, two points.
Json bar(const Json& origin, const Json& p1, const Json& p2, const std::string& n1,
         const std::string& n2) {
  return {{"kind", leaf("rigid", "1")},
          {"mass", leaf(0.02, "kg")},
          {"inertia", leaf(1e-5, "kg*m^2")},
          {"center_of_mass", leaf(p2, "m")},
          {"origin", leaf(origin, "m")},
          {"angle", leaf(0.0, "rad")},
          {"points", {{n1, leaf(p1, "m")}, {n2, leaf(p2, "m")}}}};
}
Json revolute(const std::string& a, const std::string& b) {
  return {{"type", leaf("revolute", "1")},
          {"a", leaf(a, "1")},
          {"b", leaf(b, "1")},
          {"model", leaf("ideal", "1")},
          {"clearance", leaf(1e-4, "m")}};
}
}  // namespace

TEST_CASE("planar linkage: more bodies and joints are part-file groups only", "[planar-linkage]") {
  // the default linkage as a tree, plus a flap driven from a 50 mm horn under the shaft by a
  // 150 mm push rod to the flap's own 50 mm horn, the flap hinged 150 mm right of the shaft: a
  // parallelogram, so the flap turns exactly with the shaft
  Json tree = Json::object();
  const Json flat = flap("ideal").leaves();
  for (auto it = flat.begin(); it != flat.end(); ++it)
    tree[Json::json_pointer("/" + std::regex_replace(it.key(), std::regex("\\."), "/"))] =
        it.value();
  Json& k = tree["linkage"];
  k["ground"]["flap_hinge"] = leaf({0.40, -0.115, 0.0}, "m");
  k["bodies"]["lever_arm"]["points"]["horn"] = leaf({0.0, -0.05, 0.0}, "m");
  k["bodies"]["push_rod"] = bar({0.25, -0.165, 0.0}, {0.0, 0.0, 0.0}, {0.15, 0.0, 0.0}, "a", "b");
  k["bodies"]["flap"] =
      bar({0.40, -0.115, 0.0}, {0.0, 0.0, 0.0}, {0.0, -0.05, 0.0}, "hinge", "horn");
  k["joints"]["joint_5"] = revolute("lever_arm.horn", "push_rod.a");
  k["joints"]["joint_6"] = revolute("push_rod.b", "flap.horn");
  k["joints"]["flap_hinge"] = revolute("flap.hinge", "ground.flap_hinge");
  k["output"]["value"] = "flap.hinge";
  const ParameterSet p = ParameterSet::from_json(tree, "test");
  const auto scene = make_scene("planar-linkage", p);
  Recorder rec(kSignals, true);
  REQUIRE(simulate(*scene, dopri5(1e-10, 1e-3), TimeSettings{0.25, 1e-3}, rec).status ==
          RunStatus::ok);
  double e = 0.0;
  for (std::size_t i = 0; i < rec.steps.size(); ++i)
    e = std::max(
        e, std::abs(rec.steps.get(i, SignalId::surface_angle) - shaft_angle_at(rec.steps.time(i))));
  measured("six-body linkage: flap angle against the closed-form shaft angle [rad]", e, 1e-9);
  CHECK(e < 1e-9);
}
