// Scene planar-slider-crank, the model forms of issue 36 item 4: a flexible connecting rod, the
// slider's guide with clearance and friction, the crank driven by a motor through a flywheel.
// Each option's limit reproduces today's model (a stiff rod, a tight stiff frictionless guide,
// a heavy flywheel: the error against the closed form, or against the option-off run, falls as
// the option's parameter goes to its limit), the energy audit closes with each, and a bad
// option names its key.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "fixture.hpp"
#include "sweep/metrics.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

// the rig, restated so that the test does not take it from the code it checks
constexpr double kCrank = 0.05;                                   // [m]
constexpr double kRod = 0.3;                                      // [m]
constexpr double kOmega = 500.0 * 2.0 * std::numbers::pi / 60.0;  // [rad/s]
constexpr double kTurn = 2.0 * std::numbers::pi / kOmega;         // [s] one revolution
constexpr double kScale = kCrank * kOmega * kOmega;               // r w^2 [m/s^2]

/// closed-form slider acceleration of the ideal in-line slider-crank at crank angle th, rate w,
/// angular acceleration al (x = r cos th + sqrt(L^2 - r^2 sin^2 th), differentiated twice)
double closed_form_acceleration(double th, double w, double al) {
  const double r = kCrank, L = kRod, s = std::sin(th), c = std::cos(th);
  const double S = std::sqrt(L * L - r * r * s * s);
  const double dx = -r * s - r * r * s * c / S;  // dx/dth
  const double ddx =
      -r * c - r * r * (c * c - s * s) / S - r * r * r * r * s * s * c * c / (S * S * S);
  return ddx * w * w + dx * al;
}

ParameterSet rig(const std::string& rod_slider, double clearance) {
  ParameterSet p = ParameterSet::defaults_for("planar-slider-crank");
  p.set("joints.rod_slider.model", rod_slider);
  p.set("joints.rod_slider.clearance", clearance);
  return p;
}

class Observer final : public RunObserver {
 public:
  explicit Observer(const Scene& scene)
      : metrics(scene, MetricsSettings{}),
        steps({SignalId::crank_angle, SignalId::surface_rate, SignalId::slider_position,
               SignalId::slider_acceleration, SignalId::energy_residual}) {}
  void on_step(const SignalFrame& f) override {
    metrics.on_step(f);
    steps.add(f);
  }
  bool wants_steps() const override { return true; }
  void on_contact_onset(double t, int, double v) override { metrics.on_contact_onset(t, v); }
  MetricsAccumulator metrics;
  Track steps;
};

struct Run {
  Track steps;
  MetricValues metrics{};
  double metric(MetricId id) const { return metrics[static_cast<std::size_t>(id)]; }
};

Run run(const ParameterSet& p, double revolutions) {
  const auto scene = make_scene("planar-slider-crank", p);
  Observer obs(*scene);
  const RunResult res =
      simulate(*scene, dopri5(1e-9, 1e-3), TimeSettings{revolutions * kTurn, 1e-3}, obs);
  REQUIRE(res.status == RunStatus::ok);
  return {obs.steps, obs.metrics.finish(res.stats)};
}

/// largest |a - closed form at the run's own theta, theta'| over the second revolution,
/// relative to r w^2 (theta'' from the rate's finite difference between steps)
double error_to_closed_form(const Run& r) {
  double worst = 0.0;
  for (std::size_t i = 1; i + 1 < r.steps.size(); ++i) {
    if (r.steps.time(i) < kTurn) continue;
    const double w = r.steps.get(i, SignalId::surface_rate);
    const double al =
        (r.steps.get(i + 1, SignalId::surface_rate) - r.steps.get(i - 1, SignalId::surface_rate)) /
        (r.steps.time(i + 1) - r.steps.time(i - 1));
    const double a = closed_form_acceleration(r.steps.get(i, SignalId::crank_angle), w, al);
    worst = std::max(worst, std::abs(r.steps.get(i, SignalId::slider_acceleration) - a) / kScale);
  }
  return worst;
}

double median_peak(const Run& r) {
  return r.metric(MetricId::median_revolution_peak_slider_acceleration);
}

}  // namespace

TEST_CASE("planar slider-crank options: a stiff rod converges to the rigid one",
          "[planar-slider-crank][options]") {
  // ideal joints at a prescribed speed: the slider's motion is kinematic, and the mode, pinned at
  // both bores (no foreshortening), changes the pin forces only: the slider follows the rigid
  // closed form to round-off (measured 4e-16)
  ParameterSet p = rig("ideal", 0.0);
  p.set("rod_flexibility.model", "first_mode");
  const double e = error_to_closed_form(run(p, 2.0));
  measured("flexible rod, ideal joints, error to rigid (rel to r w^2)", e, 1e-12);
  CHECK(e < 1e-12);
  // at the rig's 0.3 mm (its periodic response) the mode loads the clearance joint: the peak
  // moves, and comes back to the rigid rod's as the section stiffens (the rigid value is the
  // option-off run of the same length; the stiff rod's residue measured 5.6e-4 at 100 x E I)
  ParameterSet q = rig("clearance", 3e-4);
  const Run rigid = run(q, 6.0);
  q.set("rod_flexibility.model", "first_mode");
  const double soft = std::abs(median_peak(run(q, 6.0)) / median_peak(rigid) - 1.0);
  q.set("rod_flexibility.section_second_moment", 3.375e-6);
  const double stiff = std::abs(median_peak(run(q, 6.0)) / median_peak(rigid) - 1.0);
  measured("flexible rod at 0.3 mm, median peak against rigid (rel)", soft, 1.0);
  measured("100 x stiffer rod at 0.3 mm, median peak against rigid (rel)", stiff, 2e-3);
  CHECK(stiff < soft);
  CHECK(stiff < 2e-3);
}

TEST_CASE("planar slider-crank options: a tight stiff frictionless guide is the ideal guide",
          "[planar-slider-crank][options]") {
  // ideal joints: the guide's play and the walls' give turn the rod; the slider's position
  // converges to the closed form's as the play shrinks and the walls stiffen (its acceleration
  // does not in the largest value: the walls ring at sqrt(k/m) with an amplitude ~ the play,
  // so the ringing's acceleration, ~ (k/m) c, stays of one size: 2.7e-2 and 1.4e-2 r w^2 here)
  ParameterSet p = rig("ideal", 0.0);
  p.set("guide.model", "clearance");
  p.set("guide.friction_coefficient", 0.0);
  double before = 1.0;
  for (double k : {1e8, 1e10}) {
    p.set("guide.clearance", 1e-6 * 1e8 / k);
    p.set("guide.stiffness", k);
    const Run r = run(p, 2.0);
    double dev = 0.0;
    for (std::size_t i = 0; i < r.steps.size(); ++i) {
      const double th = r.steps.get(i, SignalId::crank_angle), sn = std::sin(th);
      const double x = kCrank * std::cos(th) + std::sqrt(kRod * kRod - kCrank * kCrank * sn * sn);
      dev = std::max(dev, std::abs(r.steps.get(i, SignalId::slider_position) - x));
    }
    measured("guide, ideal joints, stiffness " + std::to_string(k) + ", position error [m]", dev,
             before / 30.0);
    CHECK(dev < before / 30.0);  // the play and the walls' give shrink 100x
    before = dev;
  }
  // at 0.3 mm the guide's y couples to the journal on its bearing wall; the peak converges to
  // the ideal guide's as the play goes to 0 and the wall's stiffness up (measured 198.2, 184.3,
  // 183.65 m/s^2 at 1 um and 1e8, 0.1 um and 1e9, 0.01 um and 1e10 N/m, 10 revolutions)
  ParameterSet q = rig("clearance", 3e-4);
  const Run ideal = run(q, 6.0);
  q.set("guide.model", "clearance");
  q.set("guide.friction_coefficient", 0.0);
  double previous = 1.0;
  for (double k : {1e8, 1e10}) {
    q.set("guide.clearance", 1e-6 * 1e8 / k);
    q.set("guide.stiffness", k);
    const double rel = std::abs(median_peak(run(q, 6.0)) / median_peak(ideal) - 1.0);
    measured("guide at 0.3 mm, stiffness " + std::to_string(k) + ", median peak (rel)", rel,
             previous);
    CHECK(rel < previous);
    previous = rel;
  }
  CHECK(previous < 2e-3);  // measured 5.5e-4 at 0.01 um and 1e10 N/m
}

TEST_CASE("planar slider-crank options: a heavy flywheel holds the crank's speed",
          "[planar-slider-crank][options]") {
  // ideal joints: the speed's fluctuation, and with it the slider's acceleration against the
  // prescribed-speed closed form, scale as 1/J: 100x the flywheel, ~1/100 of the error
  ParameterSet p = rig("ideal", 0.0);
  p.set("drive.model", "motor");
  p.set("drive.flywheel_inertia", 0.02);
  const Run light = run(p, 2.0);
  p.set("drive.flywheel_inertia", 2.0);
  const Run heavy = run(p, 2.0);
  auto speed_error = [](const Run& r) {  // largest |theta' - w| / w
    double worst = 0.0;
    for (std::size_t i = 0; i < r.steps.size(); ++i)
      worst = std::max(worst, std::abs(r.steps.get(i, SignalId::surface_rate) / kOmega - 1.0));
    return worst;
  };
  auto against_prescribed = [](const Run& r) {  // a at the run's theta, with w and 0 for the rest
    double worst = 0.0;
    for (std::size_t i = 0; i < r.steps.size(); ++i) {
      if (r.steps.time(i) < kTurn) continue;
      const double a = closed_form_acceleration(r.steps.get(i, SignalId::crank_angle), kOmega, 0.0);
      worst = std::max(worst, std::abs(r.steps.get(i, SignalId::slider_acceleration) - a) / kScale);
    }
    return worst;
  };
  measured("flywheel 0.02 kg m^2, speed fluctuation (rel)", speed_error(light), 0.2);
  measured("flywheel 2 kg m^2, speed fluctuation (rel)", speed_error(heavy), 0.2 / 30.0);
  CHECK(speed_error(light) > 1e-3);
  CHECK(speed_error(heavy) < speed_error(light) / 30.0);
  CHECK(against_prescribed(heavy) < against_prescribed(light) / 30.0);
  // the motor's own dynamics are the closed form at its theta, theta', theta'' (round-off and
  // the finite-difference theta'': ~1e-6)
  CHECK(error_to_closed_form(light) < 1e-4);
  // at 0.3 mm: a 100 kg m^2 flywheel gives the prescribed speed's peak (measured ~1e-5)
  ParameterSet q = rig("clearance", 3e-4);
  const Run prescribed = run(q, 6.0);
  q.set("drive.model", "motor");
  q.set("drive.flywheel_inertia", 100.0);
  const double rel = std::abs(median_peak(run(q, 6.0)) / median_peak(prescribed) - 1.0);
  measured("flywheel 100 kg m^2 at 0.3 mm, median peak against prescribed (rel)", rel, 1e-3);
  CHECK(rel < 1e-3);
}

TEST_CASE("planar slider-crank options: the energy audit closes with each option",
          "[planar-slider-crank][options]") {
  // the mode's strain energy and damping, the guide's walls and friction, the motor's work and
  // the flywheel's kinetic energy all enter the audit: its residual stays at the integrator's
  // level (the one-joint audit of the rigid model: ~4e-9)
  ParameterSet base = rig("clearance", 5e-4);
  const char* option[] = {"rod_flexibility.model", "guide.model", "drive.model"};
  const char* value[] = {"first_mode", "clearance", "motor"};
  for (int i = 0; i < 3; ++i) {
    ParameterSet p = base;
    p.set(option[i], std::string(value[i]));
    const Run r = run(p, 2.0);
    measured(std::string("energy residual with ") + value[i] + " (rel)",
             r.metric(MetricId::energy_residual), 1e-4);
    CHECK(r.metric(MetricId::energy_residual) < 1e-4);
    CHECK(r.metric(MetricId::dissipated_energy) > 0.0);
  }
}

TEST_CASE("planar slider-crank options: bad option parameters name their key",
          "[planar-slider-crank][options]") {
  auto key_of = [](ParameterSet p) {
    try {
      make_scene("planar-slider-crank", p);
    } catch (const InputError& e) {
      return e.key_path();
    }
    return std::string("(no error)");
  };
  ParameterSet p = rig("clearance", 5e-4);
  p.set("rod_flexibility.model", "first_mode");
  p.set("rod.inertia", 0.005);  // below a uniform bar's m L^2/12 = 0.00804
  CHECK(key_of(p) == "rod.inertia");
  p.set("rod.inertia", 0.034);
  p.set("rod.center_of_mass", 0.1);
  CHECK(key_of(p) == "rod.center_of_mass");
  p = rig("clearance", 5e-4);
  p.set("guide.model", "clearance");
  p.set("guide.clearance", 0.0);
  CHECK(key_of(p) == "guide.clearance");
  p = rig("clearance", 5e-4);
  p.set("drive.model", "motor");
  p.set("drive.flywheel_inertia", -1.0);
  CHECK(key_of(p) == "drive.flywheel_inertia");
  p = rig("clearance", 5e-4);
  p.set("guide.clearance", 0.0);  // read only with guide.model "clearance"
  p.set("drive.motor_slope", 0.0);
  CHECK(key_of(p) == "(no error)");
}
