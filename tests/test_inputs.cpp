// Periodic inputs (issue 31; docs/inputs.md): the waveforms of the position command and the
// hinge moment, the frequency response of the full system against the transfer function of the
// linearised actuator-and-linkage model derived in docs/inputs.md, and the free-play loop of the
// ground test against the geometric free-play 2c/s.
#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <string>

#include "core/errors.hpp"
#include "core/scenes/drivers.hpp"
#include "core/scenes/input_kinds.hpp"
#include "core/scenes/servo_actuator.hpp"
#include "core/scenes/slider_crank.hpp"
#include "fixture.hpp"
#include "sweep/periodic_metrics.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = 180.0 / kPi;

/// Feeds the step frames to the periodic metrics.
struct PeriodicObserver final : RunObserver {
  explicit PeriodicObserver(const Scene& s) : acc(s) {}
  void on_step(const SignalFrame& f) override { acc.on_step(f); }
  bool wants_steps() const override { return true; }
  PeriodicAccumulator acc;
};

PeriodicMetrics run_periodic(const ParameterSet& p, const IntegratorSettings& s, double end) {
  auto sc = make_scene("rod-end-actuator", p);
  PeriodicObserver obs(*sc);
  const RunResult r = simulate(*sc, s, TimeSettings{end, 1e-2}, obs);
  INFO(r.message);
  REQUIRE(r.status == RunStatus::ok);
  return obs.acc.finish();
}

}  // namespace

/// Each waveform of the catalogue, as its class makes it: A = 2, offset 0.5, from 0.1 s; 3 Hz
/// over 2 periods, or swept from 1 to 8 Hz over 1.5 s.
InputPtr test_waveform(WaveformKind kind) {
  const WaveformLevel l{2.0, 0.5, 0.1};
  const WavePeriods w{3.0, 2};
  const ChirpSweep c{1.0, 8.0, 1.5};
  switch (kind) {
    case WaveformKind::sine:
      return std::make_shared<SineWave>(l, w);
    case WaveformKind::triangle:
      return std::make_shared<TriangleWave>(l, w);
    case WaveformKind::linear_chirp:
      return std::make_shared<LinearChirp>(l, c);
    case WaveformKind::log_chirp:
      return std::make_shared<LogChirp>(l, c);
  }
  return nullptr;
}

TEST_CASE("waveforms: values, derivatives and windows", "[inputs]") {
  for (WaveformKind kind : choice_values<WaveformKind>()) {
    const InputPtr in = test_waveform(kind);
    REQUIRE(in);
    const Input& w = *in;
    CAPTURE(choice_name(kind));
    // offset before the start, the end value after the end (offset after whole periods),
    // continuous at both
    CHECK(w.at(0.05).value == 0.5);
    CHECK(w.at(0.1).value == Approx(0.5).margin(1e-12));
    CHECK(w.at(w.end_time() + 1e-3).value == Approx(w.at(w.end_time()).value).margin(1e-12));
    CHECK(w.at(w.end_time() + 1e-3).rate == 0.0);
    if (w.periodic()) CHECK(w.at(w.end_time()).value == Approx(0.5).margin(1e-9));
    // the rate is the derivative of the value (central differences, away from the triangle's
    // corners), the acceleration that of the rate
    const double h = 1e-6;
    for (double t : {0.13, 0.31, 0.47, 0.58}) {
      CAPTURE(t);
      const double d = (w.at(t + h).value - w.at(t - h).value) / (2 * h);
      CHECK(w.at(t).rate == Approx(d).epsilon(1e-6).margin(1e-6));
      const double dd = (w.at(t + h).rate - w.at(t - h).rate) / (2 * h);
      CHECK(w.at(t).acceleration == Approx(dd).epsilon(1e-5).margin(1e-3));
    }
    // the integral (a closed form, or Simpson's rule on 4096 intervals: its error at the
    // triangle's corners is of order (t/4096)^2 times the slope's jump, ~1e-6) against the
    // midpoint rule on 2e5 intervals (error ~ (t/2e5)^2 |w''| t / 24, below 1e-9 here)
    for (double t : {0.3, 0.9, 2.0}) {
      CAPTURE(t);
      const int n = 200000;
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += w.at((i + 0.5) * t / n).value;
      CHECK(w.integral(t) == Approx(sum * t / n).epsilon(1e-6).margin(1e-5));
    }
  }
  // a chirp's instantaneous frequency: the rate's peak is 2 pi A f(t); the end frequency reached
  const LogChirp c({1.0, 0.0, 0.0}, {1.0, 16.0, 4.0});
  // at tau = D/2 the log chirp runs at sqrt(f0 f1) = 4 Hz: w' = 2 pi f A cos(phase)
  const auto s = c.at(2.0);
  const double f = std::abs(s.rate) / (2 * kPi * std::sqrt(1.0 - s.value * s.value));
  CHECK(f == Approx(4.0).epsilon(1e-9));
  // the triangle reaches +-A at a quarter and three quarters of a period
  const TriangleWave t({3.0, 0.0, 0.0}, {0.5, 1});
  CHECK(t.at(0.5).value == Approx(3.0));
  CHECK(t.at(1.5).value == Approx(-3.0));
}

TEST_CASE("inputs: the one reader makes each kind's class from its keys", "[inputs]") {
  // a log chirp read from the parameters gives bit for bit the one made from the same numbers
  ParameterSet p = ParameterSet::defaults_for("servo-actuator");
  p.set("command.shape", "log-chirp");
  p.set("command.start_frequency", 0.5);
  p.set("command.end_frequency", 12.0);
  p.set("command.chirp_duration", 3.0);
  const InputPtr read = read_motion(p, "command");
  REQUIRE(dynamic_cast<const LogChirp*>(read.get()));
  const WaveformLevel l{p.number("command.amplitude"), p.number("command.offset"),
                        p.number("command.start_time")};
  const LogChirp by_hand(l, {0.5, 12.0, 3.0});
  const LogChirp other(l, {0.5, 6.0, 3.0});
  for (double t : {0.0, 0.37, 1.2, 2.9}) {
    CAPTURE(t);
    CHECK(read->at(t).value == by_hand.at(t).value);
    CHECK(read->at(t).rate == by_hand.at(t).rate);
    CHECK(read->at(t).acceleration == by_hand.at(t).acceleration);
  }
  CHECK(other.at(1.7).value != by_hand.at(1.7).value);
  // each menu's line names the class its kind is made by
  p.set("command.shape", "minimum-jerk");
  CHECK(dynamic_cast<const MinimumJerkStroke*>(read_motion(p, "command").get()));
  ParameterSet h = ParameterSet::defaults_for("rod-end-actuator");
  h.set("hinge.kind", "proportional");
  h.set("hinge.stiffness", 40.0);
  const InputPtr hinge = read_hinge(h, "hinge");
  CHECK(dynamic_cast<const ProportionalInput*>(hinge.get()));
  CHECK(hinge->value(0.3, 0.25) == -10.0);
  CHECK(hinge->slope() == -40.0);
  // the sine term adds to the kind
  h.set("hinge.sine_amplitude", 5.0);
  h.set("hinge.sine_frequency", 2.0);
  CHECK(read_hinge(h, "hinge")->value(0.125, 0.25) == Approx(5.0 - 10.0));
  ParameterSet b = ParameterSet::defaults_for("free-body");
  b.set("force.kind", "triangle");
  CHECK(dynamic_cast<const TriangleWave*>(read_load(b, "force").shape.get()));
}

TEST_CASE("waveform catalogues: one list for the command and the hinge moment", "[inputs]") {
  const auto shapes = choice_names(MotionShape{});
  const auto kinds = choice_names(HingeMomentKind{});
  const auto waves = choice_names(WaveformKind{});
  // three strokes or loads of their own, the waveforms, then a profile from data (profile.hpp)
  REQUIRE(shapes.size() == 4 + waves.size());
  REQUIRE(kinds.size() == 4 + waves.size());
  // and the free body's loads: constant, ramp, then the waveforms
  const auto loads = choice_names(LoadKind{});
  REQUIRE(loads.size() == 2 + waves.size());
  for (std::size_t i = 0; i < waves.size(); ++i) {
    CHECK(shapes[3 + i] == waves[i]);
    CHECK(kinds[3 + i] == waves[i]);
    CHECK(loads[2 + i] == waves[i]);
  }
  CHECK(shapes.back() == "profile");
  CHECK(kinds.back() == "profile");
  // a sine command and a triangle moment are the scene's periodic inputs
  ParameterSet p = ParameterSet::defaults_for("rod-end-actuator");
  p.set("motion.shape", "sine");
  p.set("motion.frequency", 4.0);
  p.set("motion.cycles", 3);
  p.set("hinge.kind", "triangle");
  p.set("hinge.frequency", 0.5);
  const auto in = make_scene("rod-end-actuator", p)->periodic_inputs();
  REQUIRE(in.command);
  CHECK(in.command->frequency == 4.0);
  CHECK(in.command->cycles == 3);
  REQUIRE(in.load);
  CHECK(in.load->frequency == 0.5);
}

TEST_CASE("waveform commands in the other scenes: kinematic and servo-actuator", "[inputs]") {
  // rod-end-kinematic keeps its smooth strokes: a waveform starts with a velocity jump
  ParameterSet k = ParameterSet::defaults_for("rod-end-kinematic");
  try {
    k.set("motion.shape", "sine");
    FAIL("a sine prescribed motion was accepted");
  } catch (const InputError& e) {
    CHECK(e.key_path() == "motion.shape");
  }
  // servo-actuator's command: a chirp is no single-frequency input, a sine beyond the stroke
  // names the amplitude
  ParameterSet a = ParameterSet::defaults_for("servo-actuator");
  a.set("command.shape", "log-chirp");
  CHECK_FALSE(make_scene("servo-actuator", a)->periodic_inputs().command);
  a.set("command.shape", "sine");
  a.set("command.amplitude", 0.07);
  try {
    make_scene("servo-actuator", a);
    FAIL("a command beyond the stroke was accepted");
  } catch (const InputError& e) {
    CHECK(e.key_path() == "command.amplitude");
  }
}

TEST_CASE("period samples: the Fourier projection, the loop area and the branch fit", "[inputs]") {
  // 50 periods of y0 = cos(w t + phi), y1 = 2 sin(w t) at irregular steps (a long run, so old
  // samples are dropped on the way): the projection over a period is (T/2) exp(i phi), the loop
  // of (y0, y1) with phi = 0 has the area of its ellipse, pi x 1 x 2
  const double f = 3.0, T = 1.0 / f, w = 2 * kPi * f, phi = 0.7;
  for (double ph : {phi, 0.0}) {
    PeriodSamples s(PeriodicInput{f, 0.1, 50, 1.0}, 2, 3);
    double t = 0.0;
    for (int i = 0; t < 0.1 + 50 * T + 0.01; ++i) {
      const double v[2] = {std::cos(w * (t - 0.1) + ph), 2 * std::sin(w * (t - 0.1))};
      s.add(t, v);
      t += 4e-4 * (1.0 + 0.5 * std::sin(1.3 * i));  // 0.2 to 0.6 ms
    }
    REQUIRE(s.completed() == 50);
    for (int k : {47, 48, 49}) {
      const std::complex<double> c = s.fourier(k, 0);
      CHECK(std::abs(c - 0.5 * T * std::polar(1.0, ph)) < 1e-5 * T);
    }
    if (ph == 0.0) {
      // the area by trapezoids in (y0, y1): within (w h)^2/12 ~ 1e-5 of the ellipse's
      CHECK(std::abs(s.loop_area(49, 0, 1)) == Approx(2 * kPi).epsilon(1e-4));
      // y1 against y0 where y0 in [0.2, 0.9]: two branches +-2 sqrt(1 - y0^2), the line
      // through both has slope ~0 and intercept ~0
      const auto [a, b] = s.fit(49, 0, 1, 0.2, 0.9);
      // (exact for the interpolant, which differs from the curves by up to (w h)^2/8 ~ 2e-5
      // of their amplitude 2)
      CHECK(std::abs(a) < 1e-4);
      CHECK(std::abs(b) < 1e-4);
    }
  }
}

namespace {

/// A scene that only declares a triangle hinge moment and the signals the free-play loop reads:
/// the loop's frames are made by the test (the loop metrics' own arithmetic, no dynamics).
class LoopStub final : public Scene {
 public:
  explicit LoopStub(PeriodicInput load) : load_(load) {}
  std::string_view name() const override { return "loop-stub"; }
  Features features() const override { return {}; }
  int state_size() const override { return 1; }
  void initial_state(double* x) const override { x[0] = 0.0; }
  void state_scale(double* s) const override { s[0] = 1.0; }
  void derivatives(double, const double*, const DiscreteState&, double* d) const override {
    d[0] = 0.0;
  }
  std::span<const SignalId> signals() const override { return kSignals; }
  void outputs(double, const double*, const DiscreteState&, SignalFrame&) const override {}
  EnergyTerms energy(double, const double*, const DiscreteState&) const override { return {}; }
  PeriodicInputs periodic_inputs() const override { return {std::nullopt, load_}; }

 private:
  static constexpr SignalId kSignals[] = {SignalId::time, SignalId::surface_angle,
                                          SignalId::hinge_moment};
  PeriodicInput load_;
};

/// The triangle of docs/inputs.md, tri(u) rising 0 -> 1 -> -1 -> 0 over one period.
double tri(double u) {
  const double v = u - std::floor(u);
  return v < 0.25 ? 4 * v : v < 0.75 ? 2 - 4 * v : 4 * v - 4;
}

}  // namespace

TEST_CASE("hysteresis: the signed work of the hinge moment per cycle, oint M dtheta", "[inputs]") {
  // A friction slider r in series with a spring K: theta = M/K + r. The slider holds at -R
  // until the rising moment comes within Mf of its peak A, crosses to +R while it rises from
  // A - Mf to A (linearly in M), holds, and crosses back while the falling moment goes from
  // -A + Mf to -A. The spring's part closes on itself; each crossing does 2R (A - Mf/2) of
  // work against the load, so oint M dtheta = 4R (A - Mf/2) > 0: the loop dissipates. Run the
  // other way in theta (theta = M/K - r, the surface leading the load, as when the held servo
  // feeds energy in) the same loop gives the opposite sign; |area| would give +4R(A - Mf/2).
  const double f = 2.0, A = 400.0, K = 6000.0, R = 1e-3, Mf = 40.0;
  const PeriodicInput load{f, 0.05, 3, A};
  for (double sense : {1.0, -1.0}) {
    CAPTURE(sense);
    LoopStub stub(load);
    PeriodicAccumulator acc(stub);
    REQUIRE(acc.active());
    SignalFrame fr;
    const int n = 30001;  // samples over the three periods, not on the crossings' ends
    for (int i = 0; i <= n; ++i) {
      const double t = 0.05 + i * 3.0 / f / n;
      const double u = f * (t - 0.05), v = u - std::floor(u), M = A * tri(u);
      const double up = std::clamp((M - (A - Mf)) / Mf, 0.0, 1.0);
      const double down = std::clamp((-A + Mf - M) / Mf, 0.0, 1.0);
      const double r = v < 0.25 ? -R + 2 * R * up : v < 0.75 ? R - 2 * R * down : -R;
      fr.set(SignalId::time, t);
      fr.set(SignalId::hinge_moment, M);
      fr.set(SignalId::surface_angle, M / K + sense * r);
      acc.on_step(fr);
    }
    // the trapezoids are exact but on the samples that straddle a crossing's ends: error of
    // order 4 x 2R x (step in M) = 4 x 2e-3 x 0.2 N m, below 1e-3 of the 1.56 J
    const double expected = sense * 4 * R * (A - Mf / 2);
    CHECK(acc.finish().hysteresis == Approx(expected).epsilon(1e-3));
  }
}

namespace {

/// The transfer functions piston/command and surface/surface-command of the linearised model of
/// docs/inputs.md#the-linearised-actuator-and-linkage, at f [Hz], from the scene's parameters.
struct Response {
  std::complex<double> piston, surface;
};
Response linear_model(const ParameterSet& p, double f) {
  const ServoActuatorParams a = read_servo_actuator(p, "actuator");
  const double s_ = p.number("geometry.crank"), t_ = p.number("geometry.frame");
  const double l0 = p.number("geometry.rod");
  const double sin_phi =
      std::sqrt(1.0 - std::pow((s_ * s_ + t_ * t_ - l0 * l0) / (2 * s_ * t_), 2));
  const double r = s_ * t_ * sin_phi / l0;  // dl/dtheta at the command's zero [m/rad]
  const double cos_a = r / s_;              // rod direction . crank tangent
  const double Ih = p.number("surface.mass") * s_ * s_ / 9.0 + p.number("surface.inertia");
  const double k1 = p.number("slider_spring.stiffness"), c1 = p.number("slider_spring.damping");
  const double k2 = p.number("crank_spring.stiffness"), c2 = p.number("crank_spring.damping");
  const double m_sb = p.number("ball.mass") + p.number("socket.mass");
  const double m_c = Ih / (s_ * s_), c_c = p.number("surface.damping") / (s_ * s_);
  // orifices at null (eq. 6.4-6.6 regularised): g(p) = p / (p^2 + pt^2)^(1/4) and its slope
  const double D = 0.5 * (a.supply_pressure - a.return_pressure), pt = a.transition_pressure;
  const double g = D / std::pow(D * D + pt * pt, 0.25);
  const double dg = (0.5 * D * D + pt * pt) * std::pow(D * D + pt * pt, -1.25);
  const double cq = a.discharge_coefficient * std::sqrt(2.0 / a.density);
  const double Kq = cq * a.port_width * g;                    // dq/dx_s [m^2/s]
  const double Kc = cq * a.port_width * a.leak_opening * dg;  // -dq1/dP1 [m^3/(s Pa)]
  const double kf = 2.0 * a.discharge_coefficient * std::cos(a.jet_angle);
  const double Kff = kf * a.port_width * (a.supply_pressure - a.return_pressure);  // [N/m]
  const double Kfp = kf * a.port_width * a.leak_opening;  // dF_fl/dP1 [m^2]
  const double V0 = a.dead_volume + a.piston_area * a.half_stroke, bV = a.bulk_modulus / V0;
  const double A = a.piston_area, Ci = a.internal_leakage, Ce = a.external_leakage;
  // states: 0 L, 1 integral, 2 xj, 3 vj, 4 xs, 5 vs, 6 P1, 7 P2, 8 u, 9 v, 10 y_sb, 11 v_sb,
  // 12 y_c, 13 v_c; input: the command c
  enum { L, I, XJ, VJ, XS, VS, P1, P2, U, V, YS, VYS, YC, VYC, N };
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(N, N);
  Eigen::VectorXd B = Eigen::VectorXd::Zero(N);
  M(L, U) = 1 / a.lvdt_time_constant, M(L, L) = -1 / a.lvdt_time_constant;
  M(I, L) = -1, B(I) = 1;
  // current i = kp (c - L) + ki I; jet pipe (eq. 6.2)
  const double km = a.motor_gain / a.jet_mass;
  M(XJ, VJ) = 1;
  M(VJ, L) = -km * a.kp, B(VJ) = km * a.kp, M(VJ, I) = km * a.ki;
  M(VJ, XJ) = -(a.jet_stiffness + a.wire_stiffness) / a.jet_mass;
  M(VJ, VJ) = -a.jet_damping / a.jet_mass, M(VJ, XS) = -a.wire_stiffness / a.jet_mass;
  // spool (eq. 6.3): jet pressure, wire, flow force, friction
  M(XS, VS) = 1;
  M(VS, XJ) = (a.spool_area * a.jet_pressure_gain - a.wire_stiffness) / a.spool_mass;
  M(VS, XS) = -(a.wire_stiffness + Kff) / a.spool_mass;
  M(VS, VS) = -a.spool_damping / a.spool_mass;
  M(VS, P1) = Kfp / a.spool_mass, M(VS, P2) = -Kfp / a.spool_mass;
  // chambers (eq. 6.11-6.12)
  M(P1, XS) = bV * Kq, M(P1, P1) = -bV * (Kc + Ci + Ce), M(P1, P2) = bV * Ci, M(P1, V) = -bV * A;
  M(P2, XS) = -bV * Kq, M(P2, P2) = -bV * (Kc + Ci + Ce), M(P2, P1) = bV * Ci, M(P2, V) = bV * A;
  // piston (eq. 6.13) pulled back by the slider spring along the rod: F1 cos(alpha), with
  // F1 = k1 (u / cos(alpha) - y_sb) + c1 (v / cos(alpha) - v_sb) along the crank tangent
  const double Mp = a.piston_mass;
  M(U, V) = 1;
  M(V, P1) = A / Mp, M(V, P2) = -A / Mp;
  M(V, U) = -k1 / Mp, M(V, V) = -(a.piston_friction + c1) / Mp;
  M(V, YS) = k1 * cos_a / Mp, M(V, VYS) = c1 * cos_a / Mp;
  // the two spheres together (zero clearance), between the two springs
  M(YS, VYS) = 1;
  M(VYS, U) = k1 / cos_a / m_sb, M(VYS, V) = c1 / cos_a / m_sb;
  M(VYS, YS) = -(k1 + k2) / m_sb, M(VYS, VYS) = -(c1 + c2) / m_sb;
  M(VYS, YC) = k2 / m_sb, M(VYS, VYC) = c2 / m_sb;
  // the crank end y_c = s theta (eq. 4.16)
  M(YC, VYC) = 1;
  M(VYC, YS) = k2 / m_c, M(VYC, VYS) = c2 / m_c;
  M(VYC, YC) = -k2 / m_c, M(VYC, VYC) = -(c2 + c_c) / m_c;
  const std::complex<double> jw(0.0, 2 * kPi * f);
  const Eigen::MatrixXcd S = jw * Eigen::MatrixXcd::Identity(N, N) - M.cast<std::complex<double>>();
  const Eigen::VectorXcd x = S.partialPivLu().solve(B.cast<std::complex<double>>());
  // surface command: theta_c = c / r to first order; the surface theta = y_c / s
  return {x(U), x(YC) / s_ * r};
}

ParameterSet sine_case(double clearance, double amplitude, double f, int cycles) {
  ParameterSet p = ParameterSet::defaults_for("rod-end-actuator");
  p.set("contact.clearance", clearance);
  p.set("motion.shape", "sine");
  p.set("motion.amplitude", amplitude);
  p.set("motion.frequency", f);
  p.set("motion.cycles", cycles);
  return p;
}

}  // namespace

TEST_CASE("frequency response at small amplitude and zero clearance: the linearised model",
          "[inputs][slow]") {
  // "zero" clearance: 1 um, the smallest the contact accepts with margin; the lost motion it
  // adds, 2 um in 1 mm, moves the gain by 0.2 % (docs/inputs.md)
  for (double f : {1.0, 5.0, 12.0, 25.0}) {
    CAPTURE(f);
    const int cycles = f < 2.0 ? 4 : static_cast<int>(std::ceil(0.25 * f)) + 4;
    const ParameterSet p = sine_case(1e-6, 1e-3, f, cycles);
    const PeriodicMetrics m = run_periodic(p, dopri5(1e-8), cycles / f);
    const Response lin = linear_model(p, f);
    // phase differences wrapped to (-180, 180] deg
    const double dp = std::arg(std::polar(1.0, m.piston_phase) / lin.piston) * kDeg;
    const double ds = std::arg(std::polar(1.0, m.surface_phase) / lin.surface) * kDeg;
    measured("piston gain rel", m.piston_gain / std::abs(lin.piston) - 1.0, 0.02);
    measured("piston phase deg", dp, 2.0);
    measured("surface gain rel", m.surface_gain / std::abs(lin.surface) - 1.0, 0.02);
    measured("surface phase deg", ds, 2.0);
    CHECK(m.response_settling <= PeriodicAccumulator::kSettleTolerance);
    CHECK(m.piston_gain == Approx(std::abs(lin.piston)).epsilon(0.02));
    CHECK(std::abs(dp) < 2.0);
    CHECK(m.surface_gain == Approx(std::abs(lin.surface)).epsilon(0.02));
    CHECK(std::abs(ds) < 2.0);
  }
}

TEST_CASE("frequency response: clearance lowers the surface gain at small amplitude",
          "[inputs][slow]") {
  // +-1 mm at 2 Hz: 0.5 mm of clearance is lost motion of up to 1 mm of the 2 mm stroke
  double previous = 2.0;
  for (double c : {1e-6, 2e-4, 5e-4}) {
    CAPTURE(c);
    const PeriodicMetrics m = run_periodic(sine_case(c, 1e-3, 2.0, 4), dopri5(1e-8), 2.0);
    CHECK(m.surface_gain < previous);
    previous = m.surface_gain;
  }
  CHECK(previous < 0.9);
}

TEST_CASE("free-play ground test: the loop's free-play is the geometric 2c/s", "[inputs][slow]") {
  // the actuator holds 0, the moment a 1 Hz triangle between +-400 N m (studies/free-play.json
  // at twice its rate: still quasi-static, the linkage's mode is at 71 Hz), no friction: the
  // geometric prediction has none (docs/inputs.md#the-geometric-free-play)
  IntegratorSettings bdf;
  bdf.method = IntegratorMethod::cvode_bdf;
  bdf.abs_tol = bdf.rel_tol = 1e-8;
  bdf.max_step = 1e-3;
  for (double c : {5e-4, 1e-3}) {
    CAPTURE(c);
    ParameterSet p = ParameterSet::defaults_for("rod-end-actuator");
    p.set("contact.clearance", c);
    p.set("friction.law", "none");
    p.set("motion.shape", "step");
    p.set("motion.extension", 0.0);
    p.set("motion.retraction", 0.0);
    p.set("hinge.kind", "triangle");
    const double M = 400.0;
    p.set("hinge.amplitude", M);
    p.set("hinge.frequency", 1.0);
    p.set("hinge.cycles", 2);
    const PeriodicMetrics m = run_periodic(p, bdf, 2.0);
    const double s = p.number("geometry.crank");
    // the tolerance: the Hertz penetration the lines miss at zero load, 0.204 delta(F_max) per
    // side (F_max = M/s; the least-squares line of x^(2/3) on [0.2, 0.9] meets x = 0 at 0.204,
    // the secant at 0.173: plots/linear_actuator.py), and the linkage's geometry across its
    // M/K = 66 mrad deflection, second order in that angle: 0.15 mrad
    const double nu = p.number("contact.ball_poisson_ratio");
    const double E = p.number("contact.ball_youngs_modulus");
    REQUIRE(p.number("contact.socket_youngs_modulus") == E);
    const double Rb = p.number("contact.ball_radius"), Rs = Rb + c;
    const double K = 4.0 / 3.0 * E / (2.0 * (1.0 - nu * nu)) * std::sqrt(Rb * Rs / c);
    const double delta = std::pow(M / s / K, 2.0 / 3.0);
    const double tol = 2.0 * 0.204 * delta / s + 1.5e-4;
    measured("free-play error [rad]", m.free_play - 2.0 * c / s, tol);
    CHECK(std::abs(m.free_play - 2.0 * c / s) < tol);
    // both sides see the same linkage: the two stiffnesses agree, and with the chain's series
    // stiffness k1 k2/(k1 + k2) s^2 (the actuator holding much stiffer) within 2 %
    CHECK(m.stiffness_positive == Approx(m.stiffness_negative).epsilon(0.01));
    const double k1 = p.number("slider_spring.stiffness"), k2 = p.number("crank_spring.stiffness");
    CHECK(m.stiffness_positive == Approx(k1 * k2 / (k1 + k2) * s * s).epsilon(0.02));
  }
}
