// Scene free-body: one 6-DOF body under prescribed loads, against closed forms and against an
// independent integration of Euler's equations (thesis §3.3, the 6DOF-block validation).
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/scenes/drivers.hpp"
#include "core/scenes/parts.hpp"
#include "fixture.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

constexpr double kPi = std::numbers::pi;

Recorder run_free_body(const ParameterSet& p, const IntegratorSettings& s, double end,
                       double sample, RunResult* result = nullptr) {
  auto scene = make_scene("free-body", p);
  Recorder rec({SignalId::body_position, SignalId::body_velocity, SignalId::body_euler_321,
                SignalId::body_angular_velocity, SignalId::body_angular_momentum,
                SignalId::mechanical_energy, SignalId::input_work, SignalId::energy_residual,
                SignalId::quaternion_norm_error});
  const RunResult r = simulate(*scene, s, TimeSettings{end, sample}, rec);
  REQUIRE(r.status == RunStatus::ok);
  if (result) *result = r;
  return rec;
}

/// Rotation matrix of 3-2-1 Euler angles (phi, theta, psi): R = Rz(psi) Ry(theta) Rx(phi),
/// written out by hand (independent of the library's euler321).
std::array<std::array<double, 3>, 3> matrix_from_euler321(double phi, double theta, double psi) {
  const double cf = std::cos(phi), sf = std::sin(phi);
  const double ct = std::cos(theta), st = std::sin(theta);
  const double cp = std::cos(psi), sp = std::sin(psi);
  return {{{cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf},
           {sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf},
           {-st, ct * sf, ct * cf}}};
}

/// Rotation matrix of a unit quaternion (w, x, y, z), by hand.
std::array<std::array<double, 3>, 3> matrix_from_quaternion(const std::array<double, 4>& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

double max_entry_difference(const std::array<std::array<double, 3>, 3>& a,
                            const std::array<std::array<double, 3>, 3>& b) {
  double d = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) d = std::max(d, std::abs(a[i][j] - b[i][j]));
  return d;
}

/// Independent reference for the rotation: Euler's equations I w' + w x (I w) = M_B and
/// q' = q (x) (0, w) / 2, integrated with a hand-written classical RK4 at a fixed step.
/// Plain arrays and hand-written products: nothing is shared with the library but the load
/// formulas, which are restated here too.
struct RotationReference {
  std::array<double, 3> inertia;
  std::array<double, 3> amplitude;
  bool sine;         // sine (else ramp)
  double frequency;  // [Hz]
  double ramp_time;  // [s]
  bool body_frame;   // moment given in the body frame (else inertial)

  using State = std::array<double, 7>;  // w (3), q (w, x, y, z)

  std::array<double, 3> moment_input(double t) const {
    const double k = sine ? std::sin(2 * kPi * frequency * t) : t / ramp_time;
    return {amplitude[0] * k, amplitude[1] * k, amplitude[2] * k};
  }

  State derivative(double t, const State& s) const {
    const double w[3] = {s[0], s[1], s[2]};
    double q[4] = {s[3], s[4], s[5], s[6]};
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    std::array<double, 3> M = moment_input(t);
    if (!body_frame) {
      // M_B = R^T M_W with R of the normalised quaternion
      const auto R = matrix_from_quaternion({q[0] / n, q[1] / n, q[2] / n, q[3] / n});
      const std::array<double, 3> MW = M;
      for (int i = 0; i < 3; ++i) M[i] = R[0][i] * MW[0] + R[1][i] * MW[1] + R[2][i] * MW[2];
    }
    const double I[3] = {inertia[0], inertia[1], inertia[2]};
    State d{};
    d[0] = (M[0] - (I[2] - I[1]) * w[1] * w[2]) / I[0];
    d[1] = (M[1] - (I[0] - I[2]) * w[2] * w[0]) / I[1];
    d[2] = (M[2] - (I[1] - I[0]) * w[0] * w[1]) / I[2];
    // q (x) (0, w): Hamilton product
    d[3] = 0.5 * (-q[1] * w[0] - q[2] * w[1] - q[3] * w[2]);
    d[4] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]);
    d[5] = 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2]);
    d[6] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]);
    return d;
  }

  /// Integrates from rest, identity orientation, to each of `times` (increasing), step h.
  std::vector<State> solve(const std::vector<double>& times, double h) const {
    State s{0, 0, 0, 1, 0, 0, 0};
    double t = 0.0;
    std::vector<State> out;
    auto axpy = [](const State& a, double k, const State& b) {
      State r;
      for (int i = 0; i < 7; ++i) r[i] = a[i] + k * b[i];
      return r;
    };
    for (double target : times) {
      while (t < target) {
        const double dt = std::min(h, target - t);
        const State k1 = derivative(t, s);
        const State k2 = derivative(t + dt / 2, axpy(s, dt / 2, k1));
        const State k3 = derivative(t + dt / 2, axpy(s, dt / 2, k2));
        const State k4 = derivative(t + dt, axpy(s, dt, k3));
        for (int i = 0; i < 7; ++i) s[i] += dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
        t = (dt < h) ? target : t + dt;
      }
      out.push_back(s);
    }
    return out;
  }
};

ParameterSet zero_loads() {
  ParameterSet p = ParameterSet::defaults_for("free-body");
  p.set("force.amplitude", {0.0, 0.0, 0.0});
  p.set("moment.amplitude", {0.0, 0.0, 0.0});
  return p;
}

}  // namespace

TEST_CASE("free body: constant force and principal moment match the closed forms", "[free-body]") {
  // F = [3, 6, 9] N inertial (thesis §3.3) on m = 1 kg; M = [0, 0, 0.09] N m about the body z
  // axis, I_z = 0.3 kg m^2: yaw psi = M t^2 / (2 I_z) = 0.15 t^2, 2.4 rad at 4 s (no wrap).
  ParameterSet p = ParameterSet::defaults_for("free-body");
  const Vec3 F(3.0, 6.0, 9.0);
  const double m = p.number("body.mass");
  const double Mz = 0.09, Iz = p.vec3("body.inertia").z();
  p.set("force.amplitude", {F.x(), F.y(), F.z()});
  p.set("moment.amplitude", {0.0, 0.0, Mz});
  const auto frame = GENERATE(as<std::string>{}, "body", "inertial");
  p.set("moment.frame", frame);  // about a fixed principal axis the two frames agree
  const double end = 4.0;
  RunResult result;
  const Recorder rec = run_free_body(p, dopri5(kTightTol, 0.05), end, 0.01, &result);
  const Track& s = rec.samples;
  REQUIRE(s.size() == 401);

  double pos_err = 0.0, vel_err = 0.0, yaw_err = 0.0, off_axis = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double t = s.time(i);
    const Vec3 p_exact = F * (t * t / (2.0 * m));
    const Vec3 v_exact = F * (t / m);
    pos_err = std::max(pos_err, (s.get3(i, SignalId::body_position) - p_exact).norm() /
                                    std::max(p_exact.norm(), 1.0));
    vel_err = std::max(vel_err, (s.get3(i, SignalId::body_velocity) - v_exact).norm() /
                                    std::max(v_exact.norm(), 1.0));
    const Vec3 euler = s.get3(i, SignalId::body_euler_321);
    yaw_err = std::max(yaw_err, std::abs(euler.z() - Mz * t * t / (2.0 * Iz)));
    off_axis = std::max({off_axis, std::abs(euler.x()), std::abs(euler.y()),
                         std::abs(s.get(i, SignalId::body_angular_velocity, 0)),
                         std::abs(s.get(i, SignalId::body_angular_velocity, 1))});
    // angular velocity w_z = M t / I_z (linear: integrated exactly)
    CHECK(s.get(i, SignalId::body_angular_velocity, 2) ==
          Approx(Mz * t / Iz).epsilon(kFreeBodyPositionRel).margin(kFreeBodyPositionRel));
  }
  measured("free-body constant: position rel error (" + frame + ")", pos_err, kFreeBodyPositionRel);
  measured("free-body constant: velocity rel error", vel_err, kFreeBodyPositionRel);
  measured("free-body constant: yaw abs error [rad]", yaw_err, kFreeBodyYawAbs);
  CHECK(pos_err <= kFreeBodyPositionRel);
  CHECK(vel_err <= kFreeBodyPositionRel);
  CHECK(yaw_err <= kFreeBodyYawAbs);
  // the rotation stays about z: roll, pitch and the other rates are exactly zero
  CHECK(off_axis == 0.0);
  // the final yaw really is past 2 rad, so the check above covered a large rotation
  CHECK(s.back(SignalId::body_euler_321, 2) == Approx(2.4).margin(1e-6));

  // energy audit: kinetic energy = work of the applied loads
  const double ke = s.back(SignalId::mechanical_energy);
  CHECK(ke == Approx(0.5 * F.squaredNorm() * end * end / m + 0.5 * std::pow(Mz * end, 2) / Iz)
                  .epsilon(kFreeBodyPositionRel));
  CHECK(std::abs(s.back(SignalId::energy_residual)) <= kFreeBodyPositionRel * ke);
  measured("free body: max quaternion norm error", result.stats.max_quaternion_norm_error,
           kQuaternionNormAbs);
  CHECK(result.stats.max_quaternion_norm_error <= kQuaternionNormAbs);
}

TEST_CASE("free body: torque-free asymmetric body conserves energy and angular momentum",
          "[free-body]") {
  ParameterSet p = zero_loads();
  // inertia [0.1, 0.2, 0.3] (the defaults): all three gyroscopic terms act
  REQUIRE(p.vec3("body.inertia") == Vec3(0.1, 0.2, 0.3));
  p.set("body.initial_angular_velocity", {1.0, 0.1, 0.5});
  const double end = 30.0;
  RunResult result;
  // max_step 0.01 s: ~100 steps per rotation period (~6 s) at most, far below what the
  // tolerance alone would allow, so the check is on the method, not on a lucky step sequence
  const Recorder rec = run_free_body(p, dopri5(kConservationTol, 0.01), end, 0.01, &result);
  const Track& s = rec.samples;
  REQUIRE(s.size() == 3001);

  const Vec3 I(0.1, 0.2, 0.3), w0(1.0, 0.1, 0.5);
  const double T0 = 0.5 * w0.dot(I.cwiseProduct(w0));
  const Vec3 L0 = I.cwiseProduct(w0);  // identity orientation at t = 0
  double dT = 0.0, dLnorm = 0.0, dL = 0.0, w_change = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Vec3 L = s.get3(i, SignalId::body_angular_momentum);
    dT = std::max(dT, std::abs(s.get(i, SignalId::mechanical_energy) - T0) / T0);
    dLnorm = std::max(dLnorm, std::abs(L.norm() - L0.norm()) / L0.norm());
    dL = std::max(dL, (L - L0).norm() / L0.norm());
    w_change = std::max(w_change, (s.get3(i, SignalId::body_angular_velocity) - w0).norm());
    // the body does not translate
    CHECK(s.get3(i, SignalId::body_position).norm() == 0.0);
  }
  measured("torque-free: kinetic energy rel drift", dT, kConservationRel);
  measured("torque-free: |L| rel drift", dLnorm, kConservationRel);
  measured("torque-free: L vector (inertial) rel drift", dL, kConservationRel);
  CHECK(dT <= kConservationRel);
  CHECK(dLnorm <= kConservationRel);
  // L is constant as a vector in the inertial frame, not only in magnitude
  CHECK(dL <= kConservationRel);
  // and the motion is not trivial: the body-frame angular velocity wanders by O(1) rad/s
  CHECK(w_change > 0.1);
  measured("free body: max quaternion norm error", result.stats.max_quaternion_norm_error,
           kQuaternionNormAbs);
  CHECK(result.stats.max_quaternion_norm_error <= kQuaternionNormAbs);
}

TEST_CASE("free body: sine and ramp loads match closed forms and an independent reference",
          "[free-body]") {
  const auto kind = GENERATE(as<std::string>{}, "sine", "ramp");
  const auto moment_frame = GENERATE(as<std::string>{}, "body", "inertial");
  ParameterSet p = ParameterSet::defaults_for("free-body");
  p.set("force.kind", kind);
  p.set("moment.kind", kind);
  p.set("moment.frame", moment_frame);
  // thesis inputs [3, 6, 9] on both; 1 Hz sine, 1 s ramp (the defaults)
  const double end = 2.0, sample = 0.01;
  const Recorder rec = run_free_body(p, dopri5(kTightTol, 0.01), end, sample);
  const Track& s = rec.samples;
  REQUIRE(s.size() == 201);

  // translation: closed forms of the first and second time integrals of the load (m = 1 kg)
  const Vec3 A = p.vec3("force.amplitude");
  const double m = p.number("body.mass"), f = p.number("force.frequency");
  const double T = p.number("force.ramp_time"), w = 2 * kPi * f;
  const Load load = read_load(p, "force");
  double pos_err = 0.0, vel_err = 0.0, pos_peak = 0.0, vel_peak = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double t = s.time(i);
    const Vec3 v = kind == "sine" ? Vec3(A * (1 - std::cos(w * t)) / (w * m))
                                  : Vec3(A * (t * t / (2 * T * m)));
    const Vec3 x = kind == "sine" ? Vec3(A * (t - std::sin(w * t) / w) / (w * m))
                                  : Vec3(A * (t * t * t / (6 * T * m)));
    // the library's own closed form of the first integral agrees with ours
    CHECK((load.integral(t) / m - v).norm() <= 1e-12 * std::max(v.norm(), 1.0));
    pos_err = std::max(pos_err, (s.get3(i, SignalId::body_position) - x).norm());
    vel_err = std::max(vel_err, (s.get3(i, SignalId::body_velocity) - v).norm());
    pos_peak = std::max(pos_peak, x.norm());
    vel_peak = std::max(vel_peak, v.norm());
  }
  measured("loads " + kind + ": position error rel to peak", pos_err / pos_peak,
           kLoadClosedFormRel);
  measured("loads " + kind + ": velocity error rel to peak", vel_err / vel_peak,
           kLoadClosedFormRel);
  CHECK(pos_err <= kLoadClosedFormRel * pos_peak);
  CHECK(vel_err <= kLoadClosedFormRel * vel_peak);

  // rotation: against the hand-written RK4 at h = 2e-5 s
  const Vec3 I = p.vec3("body.inertia"), M = p.vec3("moment.amplitude");
  const RotationReference ref{
      {I.x(), I.y(), I.z()},        {M.x(), M.y(), M.z()},        kind == "sine",
      p.number("moment.frequency"), p.number("moment.ramp_time"), moment_frame == "body"};
  std::vector<double> times;
  for (std::size_t i = 0; i < s.size(); ++i) times.push_back(s.time(i));
  const auto sol = ref.solve(times, 2e-5);
  double w_err = 0.0, w_peak = 0.0, R_err = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Vec3 w_ref(sol[i][0], sol[i][1], sol[i][2]);
    w_err = std::max(w_err, (s.get3(i, SignalId::body_angular_velocity) - w_ref).norm());
    w_peak = std::max(w_peak, w_ref.norm());
    const double qn = std::sqrt(sol[i][3] * sol[i][3] + sol[i][4] * sol[i][4] +
                                sol[i][5] * sol[i][5] + sol[i][6] * sol[i][6]);
    const auto R_ref =
        matrix_from_quaternion({sol[i][3] / qn, sol[i][4] / qn, sol[i][5] / qn, sol[i][6] / qn});
    const Vec3 e = s.get3(i, SignalId::body_euler_321);
    R_err = std::max(R_err, max_entry_difference(matrix_from_euler321(e.x(), e.y(), e.z()), R_ref));
  }
  measured("loads " + kind + "/" + moment_frame + ": angular velocity error rel to peak",
           w_err / w_peak, kRotationReferenceRel);
  measured("loads " + kind + "/" + moment_frame + ": rotation matrix entry error", R_err,
           kRotationReferenceRel);
  CHECK(w_peak > 1.0);  // the rotation is not trivial
  CHECK(w_err <= kRotationReferenceRel * w_peak);
  CHECK(R_err <= kRotationReferenceRel);
}

// A sine force of the waveforms (kind sine) with its window: F sin(w tau) over 3 whole periods
// from t0 = 0.25 s, tau = t - t0, 0 before and after. From rest, m x'' = F sin(w tau) gives
// v = F/(m w) (1 - cos w tau) and x = F/(m w^2) (w tau - sin w tau) in the window; after it the
// velocity is back to 0 (whole periods) and x holds F/(m w^2) w T3, T3 = 3/f. A wrong amplitude
// scales the error by its change; a phase of the force shifted by d leaves a velocity
// F/(m w) (cos d - cos(w tau + d)) - F/(m w) (1 - cos w tau), and the drift F/(m w)(cos d - 1)
// it leaves grows x's error linearly in time. Checked: the waveforms' amplitude times 1.001, or
// the sine's phase moved by 0.01 rad (position error 1.4e-3 m, velocity 9.0e-3 m/s against
// bounds of 1.3e-9 and 1.8e-9), fails both checks.
TEST_CASE("free body: a windowed sine force against the analytic displacement", "[free-body]") {
  ParameterSet p = ParameterSet::defaults_for("free-body");
  p.set("force.kind", "sine");
  p.set("force.frequency", 2.0);
  p.set("force.start_time", 0.25);
  p.set("force.cycles", 3);
  p.set("moment.amplitude", Json::array({0.0, 0.0, 0.0}));
  const double end = 2.5, sample = 0.01;
  const Recorder rec = run_free_body(p, dopri5(kTightTol, 0.01), end, sample);
  const Track& s = rec.samples;
  REQUIRE(s.size() == 251);
  const Vec3 F = p.vec3("force.amplitude");
  const double m = p.number("body.mass"), w = 2 * kPi * 2.0, t0 = 0.25, t1 = t0 + 3 / 2.0;
  double pos_err = 0.0, vel_err = 0.0, pos_peak = 0.0, vel_peak = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double tau = std::clamp(s.time(i), t0, t1) - t0;
    const Vec3 x = F * ((w * tau - std::sin(w * tau)) / (m * w * w));
    const Vec3 v = F * ((1 - std::cos(w * tau)) / (m * w));
    pos_err = std::max(pos_err, (s.get3(i, SignalId::body_position) - x).norm());
    vel_err = std::max(vel_err, (s.get3(i, SignalId::body_velocity) - v).norm());
    pos_peak = std::max(pos_peak, x.norm());
    vel_peak = std::max(vel_peak, v.norm());
  }
  measured("windowed sine force: position error rel to peak", pos_err / pos_peak,
           kLoadClosedFormRel);
  measured("windowed sine force: velocity error rel to peak", vel_err / vel_peak,
           kLoadClosedFormRel);
  CHECK(pos_err <= kLoadClosedFormRel * pos_peak);
  CHECK(vel_err <= kLoadClosedFormRel * vel_peak);
  // the body ends at rest, F/(m w^2) w T3 from the origin
  CHECK(s.get3(s.size() - 1, SignalId::body_velocity).norm() <= 1e-9 * vel_peak);
}

TEST_CASE("free body: a rotation through 90 deg pitch stays regular", "[free-body]") {
  // w = pi/2 rad/s about body y for 2 s: pitch rises to 90 deg at t = 1 s, where 3-2-1 Euler
  // angles are singular, and the body ends upside down. The quaternion state does not care.
  ParameterSet p = zero_loads();
  p.set("body.initial_angular_velocity", {0.0, kPi / 2, 0.0});
  RunResult result;
  const Recorder rec = run_free_body(p, dopri5(kTightTol, 0.01), 2.0, 1e-3, &result);
  const Track& s = rec.samples;
  REQUIRE(s.size() == 2001);
  CHECK(result.stats.t_reached == Approx(2.0).epsilon(1e-15));

  double max_pitch = -10.0, R_err = 0.0, pitch_err = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double t = s.time(i);
    const Vec3 e = s.get3(i, SignalId::body_euler_321);
    REQUIRE(std::isfinite(e.x()));
    REQUIRE(std::isfinite(e.y()));
    REQUIRE(std::isfinite(e.z()));
    REQUIRE(std::isfinite(s.get(i, SignalId::quaternion_norm_error)));
    max_pitch = std::max(max_pitch, e.y());
    // pitch of a rotation by a = pi t / 2 about y is asin(sin a): up to 90 deg, then back
    pitch_err = std::max(pitch_err, std::abs(e.y() - std::asin(std::sin(kPi * t / 2))));
    // orientation against the closed form R_y(pi t / 2)
    const double a = kPi * t / 2;
    const std::array<std::array<double, 3>, 3> R_exact{
        {{std::cos(a), 0, std::sin(a)}, {0, 1, 0}, {-std::sin(a), 0, std::cos(a)}}};
    R_err =
        std::max(R_err, max_entry_difference(matrix_from_euler321(e.x(), e.y(), e.z()), R_exact));
    CHECK(s.get3(i, SignalId::body_angular_velocity) == Vec3(0.0, kPi / 2, 0.0));
    CHECK(s.get(i, SignalId::quaternion_norm_error) <= kQuaternionNormAbs);
  }
  measured("pitch through 90 deg: rotation matrix entry error", R_err, kFreeBodyYawAbs);
  measured("pitch through 90 deg: pitch error away from 90 deg [rad]", pitch_err, 1e-4);
  // passes the +-90 deg region (the sample at t = 1 s sits on it)
  CHECK(max_pitch == Approx(kPi / 2).margin(1e-6));
  // the pitch output itself loses digits near 90 deg (asin of ~1), hence 1e-4 there, while
  // the rotation matrix, which is what the dynamics use, keeps its full accuracy
  CHECK(pitch_err <= 1e-4);
  CHECK(R_err <= kFreeBodyYawAbs);
  // the body ends upside down about y: R = R_y(pi)
  const Vec3 e = s.get3(s.size() - 1, SignalId::body_euler_321);
  const auto R_end = matrix_from_euler321(e.x(), e.y(), e.z());
  CHECK(R_end[0][0] == Approx(-1.0).margin(1e-9));
  CHECK(R_end[2][2] == Approx(-1.0).margin(1e-9));
  measured("free body: max quaternion norm error", result.stats.max_quaternion_norm_error,
           kQuaternionNormAbs);
  CHECK(result.stats.max_quaternion_norm_error <= kQuaternionNormAbs);
}
