// Servo-hydraulic actuator (thesis chapter 6; model-notes §6): scene servo-actuator (the
// actuator alone on its equivalent mass, the §6.2 calibration) and scene rod-end-actuator (the
// rod-end mechanism driven by the actuator, §6.3).
//
// Checks: the calibrated step response settles with micrometre error and physical chamber
// pressures; the hydraulic energy audit closes (it checks the chamber continuity equations
// 6.11-6.12 against the valve flows); the §6.3 comparisons (the actuator damps the first-contact
// oscillation; a constant opposing hinge moment keeps the contact closed through the reversal;
// a moment proportional to the angle moves the contact to the other half of the socket when the
// angle changes sign; a larger moment, a deeper penetration); bad input; the provenance of the
// equivalent mass.
//
// Runtime (Release, 2 cores shared with other builds): ~4 s of CPU, most of it the -20 N m
// constant-moment run (333k accepted steps, against 15k for the default cycle: the regularised
// friction's stick slope under a ~180 N normal force; with friction.law none it takes 30k).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>
#include <string>

#include "core/errors.hpp"
#include "core/scenes/slider_crank.hpp"
#include "fixture.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

/// End of one whole command cycle under `prefix` (motion.* or command.*) [s].
double cycle_end(const ParameterSet& p, const std::string& prefix) {
  return p.number(prefix + ".start_time") + p.number(prefix + ".extension_time") +
         p.number(prefix + ".retraction_time") + 2.0 * p.number(prefix + ".hold_time");
}

RunResult run(const std::string& scene, const ParameterSet& p, const IntegratorSettings& s,
              double end, RunObserver& obs, double sample_interval = 1e-3) {
  auto sc = make_scene(scene, p);
  const RunResult r = simulate(*sc, s, TimeSettings{end, sample_interval}, obs);
  INFO(scene << ": " << r.message);
  REQUIRE(r.status == RunStatus::ok);
  REQUIRE(r.stats.t_reached == Approx(end));
  return r;
}

/// The key path of the InputError that building `scene` from `p` throws ("" if none).
std::string rejected_key(const std::string& scene, const ParameterSet& p) {
  try {
    make_scene(scene, p);
  } catch (const InputError& e) {
    return e.key_path();
  }
  return "";
}

/// Prints a number the tests report but do not bound (RODEND_TEST_MEASURE set, as measured()).
void reported(const std::string& what, double value) {
  if (std::getenv("RODEND_TEST_MEASURE") != nullptr)
    std::printf("reported  %-60s %12.4e\n", what.c_str(), value);
}

/// Time of the first step frame in contact (contact force > 0); NAN if none.
double first_contact(const Track& st) {
  for (std::size_t i = 0; i < st.size(); ++i)
    if (st.get(i, SignalId::contact_force) > 0.0) return st.time(i);
  return NAN;
}

/// Peak-to-peak eccentricity over the step frames in [t0, t0 + window] [m].
double eccentricity_peak_to_peak(const Track& st, double t0, double window) {
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t i = 0; i < st.size(); ++i) {
    if (st.time(i) < t0 || st.time(i) > t0 + window) continue;
    lo = std::min(lo, st.get(i, SignalId::eccentricity));
    hi = std::max(hi, st.get(i, SignalId::eccentricity));
  }
  return hi - lo;
}

/// What the constant-hinge-moment tests need from one rod-end-actuator cycle.
struct ConstantMomentRun {
  double first_contact = NAN;     ///< first step frame in contact [s]
  double last_open_before = NAN;  ///< last step frame out of contact before the settling time [s]
  std::size_t frames_after = 0;   ///< step frames after the settling time
  std::size_t open_after = 0;     ///< of which out of contact (force or penetration <= 0)
  double first_open_after = NAN;  ///< first such frame [s]
  double min_force_after = INFINITY;         ///< smallest contact force after the settling time [N]
  double min_force_reversal = INFINITY;      ///< ... within 0.1 s either side of the reversal [N]
  double max_penetration = -INFINITY;        ///< over the whole run [m]
  double max_penetration_after = -INFINITY;  ///< after the settling time [m]
  double min_pressure = INFINITY, max_pressure = -INFINITY;  ///< both chambers [Pa]
};

/// The time after which a constant hinge moment's contact counts as established [s]. The moment
/// is a step at t = 0: the ball is thrown across the clearance (first contact at ~4 ms) and
/// bounces (c_r = 0.8) before it rests on the socket; measured: first contact at 3.8 / 5.5 /
/// 7.9 ms and the last free step frame at 5.3 / 19.6 / 23.3 ms for -20 / -10 / -5 N m. 0.1 s
/// leaves 4x the slowest for the bounces to die out, and is still early in the extension
/// (the command has moved 0.5 mm of its 50 mm).
constexpr double kSettled = 0.1;

/// One default rod-end-actuator cycle with a constant hinge moment M0 from t = 0 (cached: the
/// -20 N m run serves two tests and is the longest here, ~2 s).
const ConstantMomentRun& constant_moment_run(double M0) {
  static std::map<double, ConstantMomentRun> cache;
  if (auto it = cache.find(M0); it != cache.end()) return it->second;
  ParameterSet p = ParameterSet::defaults_for("rod-end-actuator");
  p.set("hinge.kind", "constant");
  p.set("hinge.constant_moment", M0);
  p.set("hinge.step_time", 0.0);
  Recorder rec({SignalId::contact_force, SignalId::penetration, SignalId::chamber_pressures}, true);
  run("rod-end-actuator", p, dopri5(1e-6), cycle_end(p, "motion"), rec);
  const double t_rev = p.number("motion.start_time") + p.number("motion.extension_time") +
                       p.number("motion.hold_time");
  ConstantMomentRun r;
  const Track& st = rec.steps;
  r.first_contact = first_contact(st);
  for (std::size_t i = 0; i < st.size(); ++i) {
    const double t = st.time(i), F = st.get(i, SignalId::contact_force),
                 d = st.get(i, SignalId::penetration);
    const bool closed = F > 0.0 && d > 0.0;
    r.max_penetration = std::max(r.max_penetration, d);
    for (int k = 0; k < 2; ++k) {
      r.min_pressure = std::min(r.min_pressure, st.get(i, SignalId::chamber_pressures, k));
      r.max_pressure = std::max(r.max_pressure, st.get(i, SignalId::chamber_pressures, k));
    }
    if (t < kSettled) {
      if (!closed) r.last_open_before = t;
      continue;
    }
    ++r.frames_after;
    r.max_penetration_after = std::max(r.max_penetration_after, d);
    r.min_force_after = std::min(r.min_force_after, F);
    if (std::abs(t - t_rev) <= 0.1) r.min_force_reversal = std::min(r.min_force_reversal, F);
    if (!closed && r.open_after++ == 0) r.first_open_after = t;
  }
  return cache.emplace(M0, r).first->second;
}

}  // namespace

// --- 1. closed loop without the rod-end
// -----------------------------------------------------------

TEST_CASE("servo-actuator: the calibrated step response settles with micrometre error",
          "[actuator]") {
  const ParameterSet p = ParameterSet::defaults_for("servo-actuator");
  REQUIRE(p.text("command.shape") == "step");
  const double t0 = p.number("command.start_time");  // 0.01 s
  const double A = p.number("command.extension");    // 0.01 m
  const double t_hold_end = t0 + p.number("command.extension_time") +
                            p.number("command.hold_time");  // 0.51 s: the step back
  const double Ps = p.number("actuator.supply_pressure"), Pr = p.number("actuator.return_pressure");

  // dopri5 at 1e-8: ~3.9k accepted steps, a few ms. The response metrics are converged: the
  // end-of-hold error is -2.5492e-6 m at every tolerance from 1e-6 to 1e-9.
  Recorder rec(
      {SignalId::actuator_command, SignalId::actuator_position, SignalId::chamber_pressures}, true);
  run("servo-actuator", p, dopri5(1e-8), cycle_end(p, "command"), rec);
  const Track& st = rec.steps;
  REQUIRE(st.size() > 1000);

  double peak = -INFINITY, t10 = NAN, t90 = NAN, t_settle = t0, x_end = NAN, t_end = NAN;
  std::size_t held = 0, outside = 0, off_command = 0;
  double first_outside = NAN;
  for (std::size_t i = 0; i < st.size(); ++i) {
    const double t = st.time(i), x = st.get(i, SignalId::actuator_position);
    if (t <= t0 || t >= t_hold_end) continue;
    if (st.get(i, SignalId::actuator_command) != A) ++off_command;
    peak = std::max(peak, x);
    if (std::isnan(t10) && x >= 0.1 * A) t10 = t;
    if (std::isnan(t90) && x >= 0.9 * A) t90 = t;
    if (std::abs(x - A) > 0.02 * A) t_settle = t;
    x_end = x, t_end = t;
    if (t >= t0 + 0.2) {
      ++held;
      if (std::abs(x - A) > 0.02 * A && outside++ == 0) first_outside = t;
    }
  }
  const double overshoot = (peak - A) / A, rise = t90 - t10, settling = t_settle - t0;
  const double err_end = A - x_end;
  CAPTURE(overshoot, t10, t90, rise, settling, err_end, t_end);
  REQUIRE(off_command == 0);  // the command is the step for the whole hold
  // the closing note's numbers (default gains kp = 2 A/m, ki = 0.02 A/(m s)):
  // measured overshoot 0.026 % (peak at 0.234 s: a creep, not a ring), rise (10-90 %) 42.3 ms,
  // 2 % settling 68.9 ms after the step
  reported("servo-actuator: overshoot [%]", 100.0 * overshoot);
  reported("servo-actuator: rise time 10-90 % [s]", rise);
  measured("servo-actuator: 2 % settling time after the step [s]", settling, 0.2);

  // Within 2 % of the command from 0.2 s after the step to the end of the hold (the brief's
  // requirement; measured settling 68.9 ms, so 0.2 s is 3x that). Halving kp makes it 126 ms,
  // an unstable or undamped loop would not settle at all.
  CHECK(held > 100);
  CAPTURE(first_outside);
  CHECK(outside == 0);
  CHECK(settling <= 0.2);

  // Steady-state error at the end of the hold. measured -2.549e-6 m (the piston creeps 2.5 um
  // past the command): the integrator stores the step's error area (~2.3e-4 m s) and a type-1
  // plant (valve flow -> piston rate) must pay it back by an overshoot area, which at the
  // integral time kp/ki = 100 s is a 2.5 um offset (with ki = 0: 0.19 um; ki x 10: 23 um).
  // Bound 5 um, 2x the measured value: kp halved gives 7.7 um, an external 1 kN load 16 um.
  constexpr double kSteadyErrorAbs = 5e-6;  // [m]
  measured("servo-actuator: |cmd - x| at the end of the hold [m]", std::abs(err_end),
           kSteadyErrorAbs);
  CHECK(std::abs(err_end) < kSteadyErrorAbs);
  CHECK(t_hold_end - t_end < 1e-3);  // the error is read at the end of the hold

  // Chamber pressures within [P_r, P_s]: each chamber is fed only through orifices from the
  // supply and to the return, and the equivalent mass is too light to pump it past them.
  // Margin 1 % of each bound (the brief's). measured 6.62-14.52 MPa over the whole run (both
  // steps); a sign error in a chamber equation drives them to +-1.5e9 Pa.
  double pmin = INFINITY, pmax = -INFINITY;
  for (std::size_t i = 0; i < st.size(); ++i)
    for (int k = 0; k < 2; ++k) {
      pmin = std::min(pmin, st.get(i, SignalId::chamber_pressures, k));
      pmax = std::max(pmax, st.get(i, SignalId::chamber_pressures, k));
    }
  CAPTURE(pmin, pmax);
  measured("servo-actuator: lowest chamber pressure [Pa]", pmin, 0.99 * Pr);
  measured("servo-actuator: highest chamber pressure [Pa]", pmax, 1.01 * Ps);
  CHECK(pmin >= 0.99 * Pr);
  CHECK(pmax <= 1.01 * Ps);
  // and the step back to 0 at 0.51 s is followed too (measured x(1.01 s) = -1.2e-8 m)
  CHECK(std::abs(st.back(SignalId::actuator_position)) < 0.02 * A);
}

// --- 2. hydraulic energy consistency
// --------------------------------------------------------------

TEST_CASE("servo-actuator: the hydraulic energy audit closes", "[actuator]") {
  // The input work is the hydraulic power by the long route: net supply power less orifice,
  // leakage and compression losses, with the compression power taken from dP/dt of eq.
  // 6.11-6.12. It equals (P1 - P2) A_c x' only if the chamber equations balance the valve flows,
  // leakages and piston displacement, so the residual checks them.
  // At tol 1e-6 the residual is the quadrature error, measured 4.4e-7 of the work (it scales
  // with the tolerance: 3.7e-8 at 1e-7, 3.1e-9 at 1e-8); run at 1e-8 (a few ms) so the brief's
  // bound 1e-6 has a 300x margin. Sign errors measured (servo_actuator.cpp mutated): A_c x' in
  // 6.11 -> residual 1.5e4 of the work; Q_2 in 6.12 -> 1e3; the internal leak's sign in 6.11
  // (step response unchanged to 0.1 %) -> 2.4e-2.
  constexpr double kHydraulicResidualRel = 1e-6;
  const ParameterSet p = ParameterSet::defaults_for("servo-actuator");
  Recorder rec({SignalId::energy_residual, SignalId::input_work, SignalId::dissipated_energy},
               true);
  run("servo-actuator", p, dopri5(1e-8), cycle_end(p, "command"), rec);
  double res = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < rec.steps.size(); ++i) {
    res = std::max(res, std::abs(rec.steps.get(i, SignalId::energy_residual)));
    scale = std::max({scale, std::abs(rec.steps.get(i, SignalId::input_work)),
                      std::abs(rec.steps.get(i, SignalId::dissipated_energy))});
  }
  CAPTURE(res, scale);
  // the run does real work: measured 7.71 J delivered and dissipated by the piston friction
  CHECK(scale > 1.0);
  measured("servo-actuator: max |energy residual| / max(|W|, |D|)", res / scale,
           kHydraulicResidualRel);
  CHECK(res / scale < kHydraulicResidualRel);
}

TEST_CASE("rod-end-actuator: the energy audit closes", "[actuator]") {
  // Mechanism plus actuator with the defaults at dopri5 1e-6 (what a user runs). measured max
  // |residual| 1.2e-8 J against 8.84 J of input work: 1.4e-9. The bound 1e-6 (not the brief's
  // 1 %, which the coupling errors below would pass only narrowly) is 700x the quadrature error.
  // Measured with rod_end_actuator.cpp mutated: the slider-spring reaction on the piston with
  // the wrong sign -> 0.28 of the work; left out -> 0.14.
  constexpr double kCoupledResidualRel = 1e-6;
  const ParameterSet p = ParameterSet::defaults_for("rod-end-actuator");
  Recorder rec({SignalId::energy_residual, SignalId::input_work, SignalId::dissipated_energy,
                SignalId::chamber_pressures},
               true);
  run("rod-end-actuator", p, dopri5(1e-6), cycle_end(p, "motion"), rec);
  double res = 0.0, work = 0.0, pmin = INFINITY, pmax = -INFINITY;
  for (std::size_t i = 0; i < rec.steps.size(); ++i) {
    res = std::max(res, std::abs(rec.steps.get(i, SignalId::energy_residual)));
    work = std::max(work, std::abs(rec.steps.get(i, SignalId::input_work)));
    for (int k = 0; k < 2; ++k) {
      pmin = std::min(pmin, rec.steps.get(i, SignalId::chamber_pressures, k));
      pmax = std::max(pmax, rec.steps.get(i, SignalId::chamber_pressures, k));
    }
  }
  CAPTURE(res, work, pmin, pmax);
  CHECK(work > 1.0);
  measured("rod-end-actuator: max |energy residual| / max |input work|", res / work,
           kCoupledResidualRel);
  CHECK(res / work < kCoupledResidualRel);
  // the chamber pressures stay physical here too (1 % margin as above)
  const double Ps = p.number("actuator.supply_pressure"), Pr = p.number("actuator.return_pressure");
  measured("rod-end-actuator: lowest chamber pressure [Pa]", pmin, 0.99 * Pr);
  measured("rod-end-actuator: highest chamber pressure [Pa]", pmax, 1.01 * Ps);
  CHECK(pmin >= 0.99 * Pr);
  CHECK(pmax <= 1.01 * Ps);
}

// --- 3. thesis §6.3 comparisons
// ---------------------------------------------------------------------

TEST_CASE("rod-end-actuator: the actuator damps the first-contact oscillation (thesis §6.3)",
          "[actuator]") {
  // The same command (motion.* defaults, shared by both scenes) prescribed in rod-end-kinematic
  // and followed by the actuator in rod-end-actuator. Thesis fig. 6.12: with the actuator the
  // eccentricity oscillates less. Window: 50 ms from the first step frame in contact.
  const ParameterSet pk = ParameterSet::defaults_for("rod-end-kinematic");
  const ParameterSet pa = ParameterSet::defaults_for("rod-end-actuator");
  for (const char* k :
       {"motion.shape", "motion.extension", "motion.retraction", "motion.extension_time",
        "motion.retraction_time", "motion.hold_time", "motion.start_time", "motion.cycles"}) {
    INFO(k);
    if (std::string(k) == "motion.shape")
      REQUIRE(pk.text(k) == pa.text(k));
    else
      REQUIRE(pk.number(k) == pa.number(k));
  }
  const double window = 0.05;
  double pp[2], t1[2];
  int n = 0;
  for (const auto* scene : {"rod-end-kinematic", "rod-end-actuator"}) {
    const ParameterSet& p = n == 0 ? pk : pa;
    Recorder rec({SignalId::eccentricity, SignalId::contact_force}, true);
    run(scene, p, dopri5(1e-6), cycle_end(p, "motion"), rec);
    t1[n] = first_contact(rec.steps);
    REQUIRE(std::isfinite(t1[n]));
    pp[n] = eccentricity_peak_to_peak(rec.steps, t1[n], window);
    ++n;
  }
  // measured: kinematic first contact 0.1107 s, p-p 1.4417e-5 m; actuator (the piston lags the
  // command) 0.1235 s, p-p 1.3868e-5 m: 3.8 % smaller. Converged: at tol 1e-7 and 1e-8 the
  // values are 1.4427e-5 / 1.3876e-5 and 1.4430e-5 / 1.3875e-5, so the ordering is the model's,
  // not the integrator's. The effect is small (the piston, held by a hydraulic stiffness of
  // ~2e7 N/m, is nearly rigid behind the 1e6 N/m slider spring) but it is there.
  CAPTURE(t1[0], t1[1], pp[0], pp[1]);
  measured("§6.3 eccentricity p-p, 50 ms after first contact, kinematic [m]", pp[0], pp[0]);
  measured("§6.3 eccentricity p-p, 50 ms after first contact, actuator [m]", pp[1], pp[0]);
  CHECK(pp[0] > 0.0);
  CHECK(pp[1] < pp[0]);
}

TEST_CASE(
    "rod-end-actuator: a constant opposing hinge moment keeps the contact closed "
    "through the reversal (thesis §6.3.2)",
    "[actuator]") {
  // -20 N m (clockwise, opposing extension) as a step at t = 0. Thesis fig. 6.24: contact from
  // the start to the end, reversal included, because the moment outweighs the inertia that
  // would separate the spheres when the motion reverses (at 1.2 s).
  const ConstantMomentRun& r = constant_moment_run(-20.0);
  CAPTURE(r.first_contact, r.last_open_before, r.first_open_after, r.min_force_after,
          r.min_force_reversal);
  // established within the settling allowance (measured first contact 3.8 ms, last free frame
  // 5.3 ms; see kSettled)
  CHECK(r.first_contact < kSettled);
  CHECK(r.frames_after > 10000);  // measured ~3.3e5 accepted steps, almost all after 0.1 s
  // then closed at every accepted step (force > 0 and penetration > 0), with no tolerance:
  // measured 0 open frames; smallest force within 0.1 s of the reversal 180.6 N (the static
  // rod load of 20 N m on the 0.11 m crank, ~180 N: the inertia is small beside it)
  measured("§6.3.2 -20 N m: open step frames after 0.1 s", static_cast<double>(r.open_after), 0);
  measured("§6.3.2 -20 N m: min contact force after 0.1 s [N]", r.min_force_after, 0.0);
  measured("§6.3.2 -20 N m: min contact force at the reversal +-0.1 s [N]", r.min_force_reversal,
           0.0);
  CHECK(r.open_after == 0);
  CHECK(r.min_force_reversal > 0.0);
}

TEST_CASE("rod-end-actuator: a larger constant moment, a deeper penetration (thesis §6.3.2)",
          "[actuator]") {
  // Thesis fig. 6.24 and 6.26: at higher moments the contact force and the eccentricity (the
  // penetration) are larger. Two maxima, both must grow with |M0| (-5, -10, -20 N m):
  //  - over the whole cycle: the first impact, when the step moment throws the ball across the
  //    clearance (measured 3.64e-6, 5.02e-6, 6.81e-6 m at t = 8.0, 5.5, 3.9 ms);
  //  - over the established contact after kSettled: the sustained load (measured 9.47e-7,
  //    1.36e-6, 2.04e-6 m, all at ~0.52 s, mid-extension; ratios 1.43 and 1.50 against Hertz's
  //    static 2^(2/3) = 1.59, the rest being the stroke's own load, the same for every moment).
  const ParameterSet d = ParameterSet::defaults_for("rod-end-actuator");
  const double Ps = d.number("actuator.supply_pressure"), Pr = d.number("actuator.return_pressure");
  double last = -INFINITY, last_after = -INFINITY;
  for (double M0 : {-5.0, -10.0, -20.0}) {
    const ConstantMomentRun& r = constant_moment_run(M0);
    INFO("M0 = " << M0 << " N m: max penetration " << r.max_penetration << " m (previous " << last
                 << "), after " << kSettled << " s " << r.max_penetration_after << " m (previous "
                 << last_after << ")");
    measured("§6.3.2 max penetration, whole cycle, M0 = " + std::to_string(M0) + " N m [m]",
             r.max_penetration, last);
    measured("§6.3.2 max penetration, after 0.1 s,  M0 = " + std::to_string(M0) + " N m [m]",
             r.max_penetration_after, last_after);
    CHECK(r.max_penetration > last);
    CHECK(r.max_penetration_after > last_after);
    // the contact is closed after the settling at every moment (measured: 0 open frames)
    CHECK(r.open_after == 0);
    // and the chamber pressures stay within [P_r, P_s] (1 % margin) under the load (measured
    // 9.84-10.77, 9.80-10.88, 9.72-11.06 MPa)
    CHECK(r.min_pressure >= 0.99 * Pr);
    CHECK(r.max_pressure <= 1.01 * Ps);
    last = r.max_penetration;
    last_after = r.max_penetration_after;
  }
  CHECK(last_after > 0.0);
}

TEST_CASE(
    "rod-end-actuator: a moment proportional to the angle moves the contact to the other "
    "half of the socket when the angle changes sign (thesis §6.3.2)",
    "[actuator]") {
  // M = -k theta with k = 50 N m/rad, and a command retracting to -0.05 m so the surface swings
  // from about +27 deg to about -26 deg. While theta > 0 the moment is clockwise and the rod
  // pushes (compression): the ball sits on the far side of the socket from the actuator base;
  // while theta < 0 it pulls (tension) and the ball crosses to the other half (thesis fig. 6.26).
  ParameterSet p = ParameterSet::defaults_for("rod-end-actuator");
  p.set("hinge.kind", "proportional");
  p.set("hinge.stiffness", 50.0);
  p.set("motion.retraction", 0.05);
  Recorder rec({SignalId::contact_force, SignalId::contact_angle, SignalId::surface_angle}, true);
  run("rod-end-actuator", p, dopri5(1e-6), cycle_end(p, "motion"), rec);
  const Track& st = rec.steps;

  // circular mean of the contact angle over the in-contact step frames with theta beyond
  // +-5 deg (away from the sign change, where the ball is crossing the clearance)
  double S[2] = {0.0, 0.0}, C[2] = {0.0, 0.0}, th_lo = INFINITY, th_hi = -INFINITY;
  std::size_t N[2] = {0, 0};
  for (std::size_t i = 0; i < st.size(); ++i) {
    const double th = st.get(i, SignalId::surface_angle);
    th_lo = std::min(th_lo, th), th_hi = std::max(th_hi, th);
    if (st.get(i, SignalId::contact_force) <= 0.0) continue;
    const int k = th * kDeg > 5.0 ? 0 : th * kDeg < -5.0 ? 1 : -1;
    if (k < 0) continue;
    const double a = st.get(i, SignalId::contact_angle);
    S[k] += std::sin(a), C[k] += std::cos(a), ++N[k];
  }
  CAPTURE(th_lo * kDeg, th_hi * kDeg, N[0], N[1]);
  // the surface did change sign by more than the +-5 deg band (measured -26.3 to +26.9 deg)
  REQUIRE(th_hi * kDeg > 20.0);
  REQUIRE(th_lo * kDeg < -20.0);
  REQUIRE(N[0] > 1000);  // measured ~1.7e5 frames
  REQUIRE(N[1] > 1000);  // measured ~7.3e4 frames
  const double mean_pos = std::atan2(S[0], C[0]), mean_neg = std::atan2(S[1], C[1]);
  // mean resultant length: 1 when every frame has the same angle. measured 0.997 and 0.999:
  // each half is one localised contact patch, so its mean is meaningful. Bound 0.9.
  const double R_pos = std::hypot(S[0], C[0]) / N[0], R_neg = std::hypot(S[1], C[1]) / N[1];
  // separation on the circle, in [0, 180] deg
  const double sep = std::abs(std::remainder(mean_pos - mean_neg, 2.0 * std::numbers::pi));
  CAPTURE(mean_pos * kDeg, mean_neg * kDeg, R_pos, R_neg, sep * kDeg);
  // measured: theta > +5 deg -> -152.1 deg (ball on the -x, base side, tilted by the rod's
  // inclination); theta < -5 deg -> -21.2 deg; 130.9 deg apart. Not 180: the contact normal
  // follows the rod, whose inclination differs between the two ends of the stroke, and the
  // friction tilts it further. Bound 90 deg (the brief's: the opposite half of the socket).
  measured("§6.3.2 proportional: contact-angle separation [deg]", sep * kDeg, 90.0);
  CHECK(R_pos > 0.9);
  CHECK(R_neg > 0.9);
  CHECK(sep * kDeg > 90.0);
  // the halves are the expected ones: base side (|angle| > 90 deg) while pushing, far side
  // while pulling
  CHECK(std::abs(mean_pos) * kDeg > 90.0);
  CHECK(std::abs(mean_neg) * kDeg < 90.0);
}

// --- 4. bad input
// ----------------------------------------------------------------------------------

TEST_CASE("actuator scenes reject non-physical hydraulics and out-of-stroke commands by name",
          "[actuator]") {
  for (const char* scene : {"servo-actuator", "rod-end-actuator"}) {
    INFO(scene);
    const ParameterSet d = ParameterSet::defaults_for(scene);
    REQUIRE(rejected_key(scene, d).empty());  // the defaults build
    const double Pr = d.number("actuator.return_pressure");
    SECTION("supply pressure <= return pressure") {
      for (double Ps : {Pr, 0.5 * Pr}) {
        ParameterSet p = d;
        p.set("actuator.supply_pressure", Ps);
        CHECK(rejected_key(scene, p) == "actuator.supply_pressure");
      }
    }
    SECTION("dead volume <= 0") {
      for (double v : {0.0, -1e-5}) {
        ParameterSet p = d;
        p.set("actuator.dead_volume", v);
        CHECK(rejected_key(scene, p) == "actuator.dead_volume");
      }
    }
    SECTION("bulk modulus <= 0") {
      for (double b : {0.0, -1e9}) {
        ParameterSet p = d;
        p.set("actuator.bulk_modulus", b);
        CHECK(rejected_key(scene, p) == "actuator.bulk_modulus");
      }
    }
    SECTION("a command outside the piston stroke (+-half_stroke = 0.065 m)") {
      REQUIRE(d.number("actuator.half_stroke") == 0.065);
      const std::string m = std::string(scene) == "servo-actuator" ? "command" : "motion";
      ParameterSet p = d;
      p.set(m + ".extension", 0.07);
      CHECK(rejected_key(scene, p) == m + ".extension");
      ParameterSet q = d;
      q.set(m + ".retraction", 0.07);
      CHECK(rejected_key(scene, q) == m + ".retraction");
      // inside the stroke is accepted (0.06 m, the thesis's working stroke)
      ParameterSet ok = d;
      ok.set(m + ".extension", 0.06);
      CHECK(rejected_key(scene, ok).empty());
    }
  }
}

// --- 5. equivalent mass provenance
// ----------------------------------------------------------------

TEST_CASE("servo-actuator: the equivalent mass is the mechanism's, referred to the rod",
          "[actuator]") {
  // Thesis §6.2: the surface inertia about the hinge, m (s/3)^2 + I (eq. 4.16), over the squared
  // mean transmission ratio dl/dtheta over +-60 mm (fig. 6.9), plus the two rod-end spheres,
  // recomputed from the rod-end-kinematic defaults.
  const ParameterSet k = ParameterSet::defaults_for("rod-end-kinematic");
  const double s = k.number("geometry.crank");
  const SliderCrank g(s, k.number("geometry.frame"), k.number("geometry.rod"));
  const double l0 = g.rod_zero();
  const double rbar = 0.12 / (g.ideal_crank_angle(l0 + 0.06) - g.ideal_crank_angle(l0 - 0.06));
  const double J = k.number("surface.mass") * (s / 3.0) * (s / 3.0) + k.number("surface.inertia");
  const double expected = J / (rbar * rbar) + k.number("ball.mass") + k.number("socket.mass");
  const double stored = ParameterSet::defaults_for("servo-actuator").number("load.equivalent_mass");
  CAPTURE(rbar, J, expected, stored);
  // measured: rbar 0.103986 m/rad, J 0.026722 kg m^2, expected 2.971304 kg, stored 2.9713 kg
  // (rounded to 4 decimals: at most 5e-5 kg, 1.7e-5 relative); 1e-3 is the brief's bound, and a
  // transmission ratio off by 0.1 % already moves the mass by 1.7e-3.
  measured("equivalent mass: |stored - recomputed| / recomputed",
           std::abs(stored - expected) / expected, 1e-3);
  CHECK(stored == Approx(expected).epsilon(1e-3));
  // the mechanism parameters behind it are those of rod-end-actuator too
  const ParameterSet a = ParameterSet::defaults_for("rod-end-actuator");
  for (const char* key : {"geometry.crank", "geometry.frame", "geometry.rod", "surface.mass",
                          "surface.inertia", "ball.mass", "socket.mass"}) {
    INFO(key);
    CHECK(a.number(key) == k.number(key));
  }
}
