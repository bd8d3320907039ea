// Scene rod-end-kinematic (thesis §4-§5): the rod-end inside the slider-crank, the rod length
// following a prescribed raised-cosine extension (1 s) - hold (0.2 s) - retraction (1 s) - hold
// (0.2 s) profile. Checks: the stiff, tight mechanism follows the ideal slider-crank; the §5.1
// physics (contact only across the clearance, force and spring signs per stroke, a planar motion
// without misalignment); §5.3 misalignment; the energy audit; bad input; the §5.2 clearance trend.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>

#include "core/errors.hpp"
#include "core/scenes/drivers.hpp"
#include "core/scenes/slider_crank.hpp"
#include "fixture.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

/// End of the motion profile (every run here covers one whole cycle) [s].
double profile_end(const ParameterSet& p) {
  return p.number("motion.start_time") + p.number("motion.extension_time") +
         p.number("motion.retraction_time") + 2.0 * p.number("motion.hold_time");
}

/// Peak rate of the raised-cosine extension, 2 a / T (velocity a (1 - cos 2 pi u) / T) [m/s].
double peak_extension_rate(const ParameterSet& p) {
  return 2.0 * p.number("motion.extension") / p.number("motion.extension_time");
}

RunResult run(const ParameterSet& p, const IntegratorSettings& s, double end, RunObserver& obs,
              double sample_interval = 1e-3) {
  auto scene = make_scene("rod-end-kinematic", p);
  const RunResult r = simulate(*scene, s, TimeSettings{end, sample_interval}, obs);
  INFO(r.message);
  REQUIRE(r.status == RunStatus::ok);
  REQUIRE(r.stats.t_reached == Approx(end));
  return r;
}

/// The physics signals of §5.1-§5.3, every accepted step recorded.
Recorder physics_recorder() {
  return Recorder({SignalId::eccentricity, SignalId::penetration, SignalId::contact_force,
                   SignalId::contact_force_vector, SignalId::actuator_velocity,
                   SignalId::slider_spring_axial_force, SignalId::surface_angle,
                   SignalId::surface_rate, SignalId::ball_position, SignalId::relative_position},
                  true);
}

/// The default settings of the driver (dopri5, tolerances 1e-6, max step 1e-3 s): what a user
/// runs. The default scene takes ~15k accepted steps, ~0.1 s.
IntegratorSettings default_settings() {
  return IntegratorSettings{};
}

/// Time of the first contact onset (a step frame in contact after one out of contact) at or
/// after t0; INFINITY if none.
double first_onset_after(const Track& steps, double t0) {
  bool free = false;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (steps.time(i) < t0) continue;
    const bool in_contact = steps.get(i, SignalId::contact_force) > 0.0;
    if (free && in_contact) return steps.time(i);
    free = free || !in_contact;
  }
  return INFINITY;
}

/// Counts the frames of `track` where `window` holds and `ok` fails; keeps the first such time.
template <class Window, class Ok>
std::size_t count_violations(const Track& track, Window window, Ok ok, std::size_t& frames,
                             double& first_time) {
  std::size_t bad = 0;
  frames = 0;
  first_time = NAN;
  for (std::size_t i = 0; i < track.size(); ++i) {
    if (!window(i)) continue;
    ++frames;
    if (!ok(i)) {
      if (bad++ == 0) first_time = track.time(i);
    }
  }
  return bad;
}

/// Peak contact force of the first contact episode (first F > 0 until F returns to 0) [N].
double first_impact_peak(const Track& steps) {
  double peak = 0.0;
  bool started = false;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const double F = steps.get(i, SignalId::contact_force);
    if (F > 0.0) {
      started = true;
      peak = std::max(peak, F);
    } else if (started) {
      break;
    }
  }
  return peak;
}

}  // namespace

// --- a. static kinematics -----------------------------------------------------------------------

TEST_CASE("rod-end kinematic: stiff and tight, the surface follows the ideal slider-crank",
          "[rod-end-kinematic]") {
  ParameterSet p = ParameterSet::defaults_for("rod-end-kinematic");
  // springs 100x stiffer than the defaults; damping 10x (sqrt of 100) keeps the damping ratio
  // of the defaults, 2000 / (2 sqrt(1e8 * 0.2 kg)) = 0.22
  for (const char* spring : {"slider_spring", "crank_spring"}) {
    p.set(std::string(spring) + ".stiffness", 1e8);
    p.set(std::string(spring) + ".damping", 2000.0);
  }
  const double c = 1e-6;
  p.set("contact.clearance", c);
  // slow: 60 mm in 5 s out and 5 s back to zero (peak 24 mm/s), the +33.4 deg half of §4's
  // stroke
  p.set("motion.extension", 0.06);
  p.set("motion.retraction", 0.0);
  p.set("motion.extension_time", 5.0);
  p.set("motion.retraction_time", 5.0);
  const SliderCrank ideal(p.number("geometry.crank"), p.number("geometry.frame"),
                          p.number("geometry.rod"));

  // dopri5 at 1e-6 with 1 ms steps at most: ~187k accepted steps over 10.4 s, ~0.6 s (Release);
  // the springs' 0.28 ms period and dopri5's stability limit set the step, not the tolerance
  Recorder rec({SignalId::surface_angle, SignalId::actuator_position, SignalId::contact_force});
  const double end = profile_end(p);
  run(p, dopri5(1e-6, 1e-3), end, rec, 1e-2);

  // The error is the lag of the crank behind the rod end: at most the clearance c (the ball
  // sits anywhere inside the socket), plus the springs' and the contact's elastic deflections
  // (F/k <= 5e-8 m each with F <= 5 N, Hertz penetration <= 2.2e-8 m), over the crank s.
  // No transient needs excluding, the error is taken from t = 0: until the socket first touches
  // the ball the rod end has moved by less than c, so the ideal angle by less than c/s.
  // Bounds: the brief's 0.1 deg, and 2 c/s = 1.8e-5 rad (c/s plus room for the deflections,
  // which add ~1.1e-6 rad). measured 1.02e-5 rad = 5.9e-4 deg. A crank-angle law off by 0.1 %
  // would add 5e-4 rad at the 0.5 rad end of the stroke.
  const double s = p.number("geometry.crank");
  const double bound_physics = 2.0 * c / s;
  double worst = 0.0, worst_t = 0.0, top = 0.0;
  std::size_t contact_frames = 0;
  for (std::size_t i = 0; i < rec.samples.size(); ++i) {
    const double l = p.number("geometry.rod") + rec.samples.get(i, SignalId::actuator_position);
    const double theta = rec.samples.get(i, SignalId::surface_angle);
    const double err = std::abs(theta - ideal.ideal_crank_angle(l));
    if (err > worst) worst = err, worst_t = rec.samples.time(i);
    top = std::max(top, theta);
    if (rec.samples.get(i, SignalId::contact_force) > 0.0) ++contact_frames;
  }
  CAPTURE(worst, worst_t, top);
  measured("rod-end kinematic: stiff mechanism, |theta - ideal| [deg]", worst * kDeg, 0.1);
  measured("rod-end kinematic: stiff mechanism, |theta - ideal| [rad]", worst, bound_physics);
  CHECK(rec.samples.size() > 1000);
  CHECK(worst * kDeg <= 0.1);
  CHECK(worst <= bound_physics);
  // the run did swing the surface through the stroke (+33.4 deg at l0 + 0.06 m) and back
  CHECK(top * kDeg > 33.0);
  CHECK(std::abs(rec.samples.back(SignalId::surface_angle)) * kDeg < 0.1);
  // and the surface is driven through the contact (not by some other path)
  CHECK(contact_frames > rec.samples.size() / 2);
}

// --- b. §5.1 physics ---------------------------------------------------------------------------

TEST_CASE("rod-end kinematic: thesis §5.1 physics on the 0 -> +50 mm -> 0 profile",
          "[rod-end-kinematic]") {
  // the defaults but the command: the windows and measured values below were set on the profile
  // that was the default before the thesis's +-60 mm (docs/thesis-deviations.md), out to +50 mm
  // and back to zero, where the retraction starts from the extension's contact side
  ParameterSet p = ParameterSet::defaults_for("rod-end-kinematic");
  p.set("motion.extension", 0.05);
  p.set("motion.retraction", 0.0);
  REQUIRE(p.number("socket.misalignment_z") == 0.0);
  const double c = p.number("contact.clearance");
  Recorder rec = physics_recorder();
  run(p, default_settings(), profile_end(p), rec);
  const Track& st = rec.steps;
  REQUIRE(st.size() > 1000);

  const double v_peak = peak_extension_rate(p);  // 0.1 m/s
  const double t_ret = p.number("motion.extension_time") + p.number("motion.hold_time");
  // A step frame carries the step signals (kStepSignals), not the actuator's rate or the
  // springs' forces: the windows come from the prescribed motion at each frame's time, and the
  // spring's sign is checked on the samples, which carry every signal.
  const InputPtr motion = read_motion(p, "motion");
  const auto rate = [&](const Track& track, std::size_t i) {
    return motion->at(track.time(i)).rate;
  };
  const Track& sa = rec.samples;

  SECTION("contact force only across the clearance") {
    // The force is computed from the penetration |e| - c, so F > 0 implies |e| >= c exactly,
    // with no tolerance, at every accepted step.
    std::size_t in_contact = 0, violations = 0;
    for (std::size_t i = 0; i < st.size(); ++i) {
      if (st.get(i, SignalId::contact_force) <= 0.0) continue;
      ++in_contact;
      if (!(st.get(i, SignalId::eccentricity) >= c)) ++violations;
    }
    CAPTURE(in_contact);
    CHECK(in_contact > 100);  // the surface is driven through the contact for most of the run
    CHECK(violations == 0);
  }

  SECTION("extension: spring compressed, force up and right, surface turning up") {
    // Extension window: actuator rate above 20 % of its peak (t in 0.148-0.852 s). The socket
    // crosses the clearance c = 0.5 mm and hits the ball at ~0.12 s, before the window opens.
    // measured: min axial force 2.79 N, min F_x 2.83 N, min F_y 0.17 N in contact (the normal
    // starts ~3 deg above the x-axis, the crank's initial tangent), min rate 0.19 rad/s.
    const auto window = [&](std::size_t i) { return rate(st, i) > 0.2 * v_peak; };
    const auto in_contact = [&](std::size_t i) {
      return window(i) && st.get(i, SignalId::contact_force) > 0.0;
    };
    const auto sample_in_window = [&](std::size_t i) { return rate(sa, i) > 0.2 * v_peak; };
    const auto compressed = [&](std::size_t i) {
      return sa.get(i, SignalId::slider_spring_axial_force) > 0.0;
    };
    const auto turning_up = [&](std::size_t i) { return st.get(i, SignalId::surface_rate) > 0.0; };
    const auto force_up_right = [&](std::size_t i) {
      const Vec3 F = st.get3(i, SignalId::contact_force_vector);
      return F.x() > 0.0 && F.y() > 0.0;
    };
    std::size_t frames = 0, contact_frames = 0, sample_frames = 0;
    double t_bad = NAN;
    CHECK(count_violations(sa, sample_in_window, compressed, sample_frames, t_bad) == 0);
    CAPTURE(t_bad);
    CHECK(sample_frames > 600);  // 0.70 s of 1 ms samples
    CHECK(count_violations(st, window, turning_up, frames, t_bad) == 0);
    CHECK(count_violations(st, in_contact, force_up_right, contact_frames, t_bad) == 0);
    CAPTURE(frames, contact_frames);
    CHECK(frames > 100);
    CHECK(contact_frames > frames / 2);
    // the surface angle increases between successive samples in the window
    const auto sample_window = [&](std::size_t i) {
      return i > 0 && sa.get(i - 1, SignalId::actuator_velocity) > 0.2 * v_peak &&
             sa.get(i, SignalId::actuator_velocity) > 0.2 * v_peak;
    };
    const auto increasing = [&](std::size_t i) {
      return sa.get(i, SignalId::surface_angle) > sa.get(i - 1, SignalId::surface_angle);
    };
    CHECK(count_violations(sa, sample_window, increasing, sample_frames, t_bad) == 0);
    CHECK(sample_frames > 600);  // 0.70 s of 1 ms samples
  }

  SECTION("retraction: everything reversed once the socket is across the clearance") {
    // Retraction window: actuator rate below -20 % of its peak (t in 1.348-2.052 s).
    // Unlike the extension, the socket starts the retraction in contact on the far side, so it
    // must cross 2c = 1 mm before it meets the ball again: it does at t = 1.369 s (rate -26 %
    // of the peak), inside the window, and the impact rings (bounces, socket on its 1 MN/m
    // spring) until t = 1.398 s (rate -35 %). While crossing, the slider spring carries only the
    // socket's weight, whose component along the slightly inclined rod is +0.02 N; while ringing
    // the axial force swings up to +2.7 N. So the slider-spring sign is checked where the rate
    // is below -40 % of the peak (t > 1.418 s, 20 ms after the ringing ends), and the
    // crossing is checked to be the reason (the first retraction contact comes after the 20 %
    // threshold). The contact-force direction and the surface rate hold over the whole 20 %
    // window. measured: max axial force -5.72 N (rate below -40 %), max surface rate
    // -0.054 rad/s (the surface coasting while the socket crosses), max F_x -2.7e-14 N and
    // F_y -1.6e-14 N (at a located contact onset, where F itself is ~1e-13 N).
    const double t20 = t_ret + 0.1476;  // raised cosine: 1 - cos(2 pi u) = 0.4 at u = 0.1476
    const double t_contact = first_onset_after(st, t_ret);
    CAPTURE(t20, t_contact);
    CHECK(t_contact > t20);
    CHECK(t_contact < t_ret + 0.3);

    const auto window = [&](std::size_t i) { return rate(st, i) < -0.2 * v_peak; };
    const auto sample_window40 = [&](std::size_t i) { return rate(sa, i) < -0.4 * v_peak; };
    const auto in_contact = [&](std::size_t i) {
      return window(i) && st.get(i, SignalId::contact_force) > 0.0;
    };
    const auto stretched = [&](std::size_t i) {
      return sa.get(i, SignalId::slider_spring_axial_force) < 0.0;
    };
    const auto turning_down = [&](std::size_t i) {
      return st.get(i, SignalId::surface_rate) < 0.0;
    };
    const auto force_down_left = [&](std::size_t i) {
      const Vec3 F = st.get3(i, SignalId::contact_force_vector);
      return F.x() < 0.0 && F.y() < 0.0;
    };
    std::size_t frames = 0, frames40 = 0, contact_frames = 0;
    double t_bad = NAN;
    CHECK(count_violations(sa, sample_window40, stretched, frames40, t_bad) == 0);
    CAPTURE(t_bad);
    CHECK(count_violations(st, window, turning_down, frames, t_bad) == 0);
    CHECK(count_violations(st, in_contact, force_down_left, contact_frames, t_bad) == 0);
    CAPTURE(frames, frames40, contact_frames);
    CHECK(frames > 100);
    CHECK(frames40 > 500);  // the rate is below -40 % for 0.59 s: 590 samples
    CHECK(contact_frames > frames / 2);
    const auto sample_window = [&](std::size_t i) {
      return i > 0 && sa.get(i - 1, SignalId::actuator_velocity) < -0.2 * v_peak &&
             sa.get(i, SignalId::actuator_velocity) < -0.2 * v_peak;
    };
    const auto decreasing = [&](std::size_t i) {
      return sa.get(i, SignalId::surface_angle) < sa.get(i - 1, SignalId::surface_angle);
    };
    std::size_t sample_frames = 0;
    CHECK(count_violations(sa, sample_window, decreasing, sample_frames, t_bad) == 0);
    CHECK(sample_frames > 600);
  }

  SECTION("zero misalignment: the motion stays in the plane") {
    // Every force lies in the xy-plane (gravity along -y, anchors at z = 0, the normal along the
    // in-plane eccentricity), so z components vanish identically: |F_z| <= 1e-9 |F| (the
    // brief's bound) is measured as exactly 0, and so is the balls' z.
    double worst_fz = 0.0, worst_z = 0.0;
    for (std::size_t i = 0; i < st.size(); ++i) {
      const Vec3 F = st.get3(i, SignalId::contact_force_vector);
      const double Fn = st.get(i, SignalId::contact_force);
      CHECK(std::abs(F.z()) <= 1e-9 * Fn);
      if (Fn > 0.0) worst_fz = std::max(worst_fz, std::abs(F.z()) / Fn);
      worst_z = std::max({worst_z, std::abs(st.get(i, SignalId::ball_position, 2)),
                          std::abs(st.get(i, SignalId::relative_position, 2))});
    }
    measured("rod-end kinematic: no misalignment, max |F_z| / |F|", worst_fz, 1e-9);
    measured("rod-end kinematic: no misalignment, max |z| of ball and relative [m]", worst_z,
             1e-15);
    CHECK(worst_z <= 1e-15);
  }
}

// --- c. §5.3 misalignment ----------------------------------------------------------------------

TEST_CASE("rod-end kinematic: misalignment takes the motion out of the plane (thesis §5.3)",
          "[rod-end-kinematic]") {
  ParameterSet p = ParameterSet::defaults_for("rod-end-kinematic");
  const double dz = 1e-4;  // thesis §5.3: 0.1 mm with the 0.5 mm clearance
  p.set("socket.misalignment_z", dz);
  Recorder rec = physics_recorder();
  run(p, default_settings(), profile_end(p), rec);
  const Track& st = rec.steps;
  const double c = p.number("contact.clearance");

  // Before the first contact nothing pushes the ball along z (gravity along -y, the crank
  // spring's anchor at z = 0), so it stays at z = 0 exactly (thesis: "the trajectory of the inner
  // sphere remains at the same z-level until it comes into contact"); the tilted normal then
  // pushes it off the plane. Its z is bounded by the crank spring: |F_z| / k ~ 0.2 * 17 N / 1 MN/m
  // ~ 3.4e-6 m, measured max 3.40e-6 m; the brief's threshold 1e-6 m.
  const double t_contact = first_onset_after(st, 0.0);
  REQUIRE(std::isfinite(t_contact));
  double z_before = 0.0, z_after = 0.0, fz_rel = 0.0;
  double F_max = 0.0, pen_max = -INFINITY;
  for (std::size_t i = 0; i < st.size(); ++i) {
    const double z = std::abs(st.get(i, SignalId::ball_position, 2));
    if (st.time(i) < t_contact)
      z_before = std::max(z_before, z);
    else
      z_after = std::max(z_after, z);
    const double Fn = st.get(i, SignalId::contact_force);
    if (Fn > 0.0)
      fz_rel = std::max(fz_rel, std::abs(st.get(i, SignalId::contact_force_vector, 2)) / Fn);
    F_max = std::max(F_max, Fn);
    pen_max = std::max(pen_max, st.get(i, SignalId::penetration));
  }
  CAPTURE(t_contact, z_before, z_after, fz_rel);
  measured("rod-end kinematic: misalignment, max |F_z| / |F|", fz_rel, 0.3);
  measured("rod-end kinematic: misalignment, ball |z| before the first contact [m]", z_before, 0.0);
  measured("rod-end kinematic: misalignment, max ball |z| [m]", z_after, 1e-6);
  CHECK(z_before == 0.0);
  CHECK(z_after > 1e-6);
  // the relative position starts off the plane by the misalignment itself
  CHECK(rec.samples.time(0) == 0.0);
  CHECK(std::abs(rec.samples.get(0, SignalId::relative_position, 2) + dz) <= 1e-12);
  // the normal tilts out of the plane by about dz / c = 0.2 (measured max |F_z|/|F| 0.200);
  // the band 0.1-0.3 would catch a normal left in the plane or a z offset applied twice
  CHECK(fz_rel > 0.1);
  CHECK(fz_rel < 0.3);

  // Hertz bound, K from the materials independently (model-notes §1): the penetration is
  // deepest where delta' = 0, and there the force is exactly K delta^1.5 (the hysteresis term
  // vanishes), so max delta <= (F_max / K)^(2/3). Step frames can only miss the deepest
  // instant, which lowers the delta seen. Slack: the fixture's round-off slack.
  // measured: max delta 9.703e-7 m vs bound 9.87e-7 m (ratio 0.983).
  const double Rb = p.number("contact.ball_radius");
  const double Rs = Rb + c;
  const double Rstar = Rb * Rs / (Rs - Rb);
  const double Eb = p.number("contact.ball_youngs_modulus");
  const double nub = p.number("contact.ball_poisson_ratio");
  const double Es = p.number("contact.socket_youngs_modulus");
  const double nus = p.number("contact.socket_poisson_ratio");
  const double Estar = 1.0 / ((1.0 - nub * nub) / Eb + (1.0 - nus * nus) / Es);
  const double K = p.number("contact.stiffness_scale") * 4.0 / 3.0 * Estar * std::sqrt(Rstar);
  const double bound = std::pow(F_max / K, 2.0 / 3.0);
  CAPTURE(K, F_max, pen_max, bound);
  measured("rod-end kinematic: misalignment, max penetration / Hertz bound - 1",
           pen_max / bound - 1.0, kHertzBoundSlackRel);
  CHECK(F_max > 10.0);  // a real load: ~68 N at the impacts
  CHECK(pen_max <= bound * (1.0 + kHertzBoundSlackRel));
  // and the penetration stays a small fraction of the clearance (measured 0.2 %)
  CHECK(pen_max < 0.01 * c);
}

// --- d. energy audit ---------------------------------------------------------------------------

TEST_CASE("rod-end kinematic: the energy audit closes", "[rod-end-kinematic]") {
  ParameterSet p = ParameterSet::defaults_for("rod-end-kinematic");
  std::string variant =
      GENERATE(as<std::string>{}, "defaults", "friction none", "hinge proportional");
  if (variant == "friction none") p.set("friction.law", "none");
  if (variant == "hinge proportional") {
    p.set("hinge.kind", "proportional");
    p.set("hinge.stiffness", 50.0);
  }
  Recorder rec({SignalId::mechanical_energy, SignalId::input_work, SignalId::dissipated_energy,
                SignalId::energy_residual, SignalId::friction_force, SignalId::hinge_moment});
  run(p, default_settings(), profile_end(p), rec);
  const Track& sa = rec.samples;

  const double work = sa.back(SignalId::input_work);
  const double residual = sa.back(SignalId::energy_residual);
  // the residual is what the signal says it is: mechanical change - input + dissipated
  const double recomposed = sa.back(SignalId::mechanical_energy) -
                            sa.get(0, SignalId::mechanical_energy) - work +
                            sa.back(SignalId::dissipated_energy);
  CHECK(std::abs(recomposed - residual) <= 1e-12 * std::abs(work));

  // The brief's 1 % of the input work, and a tighter 1e-6: the audit integrals are
  // quadratures of the powers at the integrator's tolerance, measured 4.6e-9 (defaults),
  // 9.8e-9 (no friction), 6.7e-9 (hinge) relative. A missing or doubled dissipation term shows
  // above 1e-6: the crank damper dissipates nearly all of the ~1.37 J, and a single impact
  // (reduced mass 0.12 kg, latched approach speeds 0.012-0.023 m/s, c_r = 0.8) dissipates
  // ~(1 - c_r^2) m v^2 / 2 = 3e-6 to 1e-5 J, 2e-6 to 8e-6 of the work. (A conservative term can
  // cancel over the cycle: see the check over the whole run below.)
  const double rel = std::abs(residual) / std::abs(work);
  CAPTURE(variant, work, residual, rel);
  measured("rod-end kinematic: energy residual / input work, " + variant, rel, 1e-2);
  CHECK(work > 1.0);  // measured 1.37 J (1.43 J with the hinge): the run did work
  CHECK(rel <= 1e-2);
  CHECK(rel <= 1e-6);

  // The audit closes at every sample, not only at the end: a conservative term (the
  // proportional hinge's work returns to ~0 over the cycle) would cancel out at the end but show
  // mid-run. Relative to the largest |input work| seen; measured 8.2e-9 (defaults), 9.8e-9 (no
  // friction), 6.7e-9 (hinge). Dropping the hinge's work from the input power gives 0.87 here
  // (and only 1.04e-6 at the end of the run).
  double max_friction = 0.0, max_hinge = 0.0, max_work = 0.0, max_residual = 0.0;
  for (std::size_t i = 0; i < sa.size(); ++i) {
    max_friction = std::max(max_friction, sa.get(i, SignalId::friction_force));
    max_hinge = std::max(max_hinge, std::abs(sa.get(i, SignalId::hinge_moment)));
    max_work = std::max(max_work, std::abs(sa.get(i, SignalId::input_work)));
    max_residual = std::max(max_residual, std::abs(sa.get(i, SignalId::energy_residual)));
  }
  measured("rod-end kinematic: max |energy residual| / max |input work|, " + variant,
           max_residual / max_work, 1e-6);
  CHECK(max_residual <= 1e-6 * max_work);
  // the variants do exercise the terms they are meant to
  CAPTURE(max_friction, max_hinge);
  if (variant == "friction none")
    CHECK(max_friction == 0.0);
  else
    CHECK(max_friction > 0.0);
  if (variant == "hinge proportional")
    CHECK(max_hinge > 10.0);  // 50 N m/rad x ~0.47 rad
  else
    CHECK(max_hinge == 0.0);
}

// --- e. bad input ------------------------------------------------------------------------------

TEST_CASE("rod-end kinematic: a motion the mechanism cannot follow is rejected",
          "[rod-end-kinematic]") {
  ParameterSet p = ParameterSet::defaults_for("rod-end-kinematic");
  // l0 + 0.2 = 0.57 m > t + s = 0.49 m: the rod length leaves the closing range on extension
  p.set("motion.extension", 0.2);
  try {
    make_scene("rod-end-kinematic", p);
    FAIL("expected InputError");
  } catch (const InputError& e) {
    const std::string msg = e.what();
    CAPTURE(msg);
    CHECK(e.key_path() == "motion.extension");
    // the first offending time: 0.2 S(u) = 0.12 m (less the 1e-6 relative margin), S the
    // raised-cosine stroke u - sin(2 pi u)/(2 pi), solved here by bisection: u = 0.5504
    double lo = 0.0, hi = 1.0;
    for (int k = 0; k < 60; ++k) {
      const double u = 0.5 * (lo + hi);
      const double S = u - std::sin(2.0 * std::numbers::pi * u) / (2.0 * std::numbers::pi);
      (0.2 * S < 0.12 - 0.49e-6 ? lo : hi) = u;
    }
    const double t_expected = lo * p.number("motion.extension_time");
    const auto at = msg.find("t = ");
    REQUIRE(at != std::string::npos);
    const double t_reported = std::strtod(msg.c_str() + at + 4, nullptr);
    CAPTURE(t_expected, t_reported);
    // the check scans the profile at T/20000 = 1.2e-4 s: the first offending scan time is
    // within one scan step after the crossing
    CHECK(t_reported >= t_expected);
    CHECK(t_reported <= t_expected + 2.4 / 20000 + 1e-9);
    // and the rod length there, at the top of the range
    CHECK(msg.find("rod length 0.49") != std::string::npos);
  }
}

TEST_CASE("rod-end kinematic: a retraction the mechanism cannot follow names the retraction",
          "[rod-end-kinematic]") {
  ParameterSet p = ParameterSet::defaults_for("rod-end-kinematic");
  // l0 - 0.11 = 0.26 m < t - s = 0.27 m: the rod leaves the closing range on retraction, with
  // the extension untouched; the error must point at the value to change
  p.set("motion.retraction", 0.11);
  try {
    make_scene("rod-end-kinematic", p);
    FAIL("expected InputError");
  } catch (const InputError& e) {
    const std::string msg = e.what();
    CAPTURE(msg);
    CHECK(e.key_path() == "motion.retraction");
    CHECK(msg.find("t = ") != std::string::npos);
    // at the bottom of the range (the first sample beyond it, just below 0.27 m)
    const auto at = msg.find("rod length ");
    REQUIRE(at != std::string::npos);
    CHECK(at < msg.find("(0.27, 0.49)"));
    // the first sample beyond the closable range: just below its bottom, 0.27 m (the command
    // reaches 0.26 m), within one sample's travel
    const double length = std::stod(msg.substr(at + 11));
    CHECK(length < 0.27);
    CHECK(length > 0.2699);
  }
  // and the largest retraction that closes is accepted
  p.set("motion.retraction", 0.099);
  CHECK_NOTHROW(make_scene("rod-end-kinematic", p));
}

TEST_CASE("rod-end kinematic: non-physical parameters are rejected by name",
          "[rod-end-kinematic]") {
  const std::string key =
      GENERATE(as<std::string>{}, "slider_spring.stiffness", "crank_spring.stiffness",
               "slider_spring.damping", "crank_spring.damping", "ball.mass", "socket.mass",
               "surface.mass", "surface.damping");
  ParameterSet p = ParameterSet::defaults_for("rod-end-kinematic");
  p.set(key, -1.0);
  CAPTURE(key);
  try {
    make_scene("rod-end-kinematic", p);
    FAIL("expected InputError");
  } catch (const InputError& e) {
    CAPTURE(e.what());
    CHECK(e.key_path() == key);
  }
}

// --- f. §5.2 clearance trend -------------------------------------------------------------------

TEST_CASE("rod-end kinematic: larger clearance, harder first impact, later surface motion",
          "[rod-end-kinematic]") {
  // Thesis §5.2: the socket accelerates the same way whatever the clearance before the first
  // contact, so a larger clearance means a later, faster impact: a higher first peak of the
  // contact force (fig. 5.15) and a later start of the surface (fig. 5.17).
  // measured (0.1, 0.3, 0.5 mm): first peak 12.08, 24.32, 33.22 N; surface past 1 mrad at
  // 0.0868, 0.1084, 0.1232 s.
  double previous_peak = 0.0, previous_start = 0.0;
  for (double c : {1e-4, 3e-4, 5e-4}) {
    ParameterSet p = ParameterSet::defaults_for("rod-end-kinematic");
    p.set("contact.clearance", c);
    Recorder rec({SignalId::contact_force, SignalId::surface_angle}, true);
    // only the extension's start matters: 0.3 s covers the first impact and the surface's start
    run(p, default_settings(), 0.3, rec);
    const double peak = first_impact_peak(rec.steps);
    double start = INFINITY;
    for (std::size_t i = 0; i < rec.steps.size(); ++i)
      if (std::abs(rec.steps.get(i, SignalId::surface_angle)) > 1e-3) {
        start = rec.steps.time(i);
        break;
      }
    CAPTURE(c, peak, start, previous_peak, previous_start);
    measured("rod-end kinematic: clearance " + std::to_string(c) + " m, first impact peak [N]",
             peak, 0.0);
    measured("rod-end kinematic: clearance " + std::to_string(c) + " m, surface start [s]", start,
             0.0);
    CHECK(std::isfinite(start));
    CHECK(peak > previous_peak);
    CHECK(start > previous_start);
    previous_peak = peak;
    previous_start = start;
  }
}

TEST_CASE("rod-end kinematic: before the first contact every clearance takes the same steps",
          "[rod-end-kinematic]") {
  // The error norm measures the ball's and socket's positions on one fixed length
  // (core/scenes/contact_length_scale.hpp), so two cases that differ only in the clearance
  // integrate the same free flight with the same steps, to the last bit, at any tolerance. With
  // the clearance as that length they did not: at cvode_bdf 1e-5 the socket's speed differed
  // between clearances by about the tolerance, and the thesis-trend check (the same speed to
  // 1e-6 before any contact) held only from 1e-8 on. Loose (`fast`'s 1e-5) on purpose.
  IntegratorSettings s;
  s.method = IntegratorMethod::cvode_bdf;
  s.abs_tol = s.rel_tol = 1e-5;
  std::vector<Track> steps;
  for (double c : {1e-4, 1e-3}) {
    ParameterSet p = ParameterSet::defaults_for("rod-end-kinematic");
    p.set("contact.clearance", c);
    Recorder rec({SignalId::contact_force, SignalId::socket_velocity}, true);
    run(p, s, 0.1, rec);
    steps.push_back(rec.steps);
  }
  const double onset = first_onset_after(steps[0], 0.0);  // the smaller clearance's: the first
  REQUIRE(std::isfinite(onset));
  // every step of the first half of the free flight (the steps next to the onset are cut where
  // the driver locates it, which depends on the clearance; the thesis-trend check probes half)
  std::size_t compared = 0;
  for (std::size_t i = 0; i < steps[0].size() && steps[0].time(i) < 0.5 * onset; ++i, ++compared) {
    REQUIRE(i < steps[1].size());
    CAPTURE(i, steps[0].time(i), steps[1].time(i));
    REQUIRE(steps[0].time(i) == steps[1].time(i));
    for (int k = 0; k < 3; ++k)
      REQUIRE(steps[0].get(i, SignalId::socket_velocity, k) ==
              steps[1].get(i, SignalId::socket_velocity, k));
  }
  CHECK(compared > 10);
}
