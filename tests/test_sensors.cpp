// Sensors (sweep/sensors.hpp, docs/sensors.md): the noise's moments, the low-pass against its
// closed forms, the quantisation, the seeds, the records' independence of how the input is cut
// into steps and of time.sample_interval, and the study block's checks.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "fixture.hpp"
#include "sweep/feature_metrics.hpp"
#include "sweep/runner.hpp"
#include "sweep/sensor_channel.hpp"
#include "sweep/study.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

constexpr double kPi = std::numbers::pi;

/// A sensor on surface_angle (any step signal does: the channel reads the frame).
SensorSpec spec_on_angle(double noise, double bias, double q, int order, double fc, double rate) {
  SensorSpec s;
  s.name = "probe";
  s.signal = "surface_angle";
  s.noise_std = noise, s.bias = bias, s.quantisation = q;
  s.filter_order = order, s.cutoff = fc, s.rate = rate;
  return s;
}

/// The channel fed u(t) at the frame times `times` (the first starts it).
SensorChannel feed(const SensorSpec& spec, const std::vector<double>& times,
                   const std::function<double(double)>& u, long long seed = 1) {
  SensorChannel ch(spec, 1.0, seed);
  SignalFrame f;
  for (double t : times) {
    f.set(SignalId::time, t);
    f.set(SignalId::surface_angle, u(t));
    ch.advance(f);
  }
  return ch;
}

std::vector<double> uniform_times(double end, double h) {
  std::vector<double> t;
  for (long long i = 0; i * h <= end + 1e-12; ++i) t.push_back(static_cast<double>(i) * h);
  return t;
}

}  // namespace

TEST_CASE("sensor noise: its sample mean is the bias, its sample std the noise_std", "[sensors]") {
  // 40001 samples of a constant 2: the mean of N normals has std sigma/sqrt(N), a sample std
  // std ~ sigma/sqrt(2N); 4.5 of those (a false failure once in 1.5e5 runs; the seed is fixed,
  // so the test is deterministic: the bound says what a correct generator must meet)
  const double sigma = 0.3, bias = 0.05;
  const SensorChannel ch = feed(spec_on_angle(sigma, bias, 0.0, 0, 0.0, 1000.0),
                                uniform_times(40.0, 0.01), [](double) { return 2.0; });
  const std::vector<double>& v = ch.values();
  const auto n = static_cast<double>(v.size());
  REQUIRE(v.size() == 40001);
  double mean = 0.0, sq = 0.0;
  for (double x : v) mean += x / n;
  for (double x : v) sq += (x - mean) * (x - mean) / (n - 1);
  measured("sensor mean - bias [sigma/sqrt(N)]", (mean - 2.0 - bias) / (sigma / std::sqrt(n)), 4.5);
  CHECK(std::abs(mean - 2.0 - bias) < 4.5 * sigma / std::sqrt(n));
  CHECK(std::abs(std::sqrt(sq) - sigma) < 4.5 * sigma / std::sqrt(2.0 * n));
  // and they are white: the lag-1 autocorrelation of N normals has std 1/sqrt(N)
  double lag = 0.0;
  for (std::size_t i = 1; i < v.size(); ++i) lag += (v[i] - mean) * (v[i - 1] - mean) / (n - 1);
  CHECK(std::abs(lag / sq) < 4.5 / std::sqrt(n));
}

TEST_CASE("sensor low-pass: step and sine responses against their closed forms", "[sensors]") {
  const double fc = 50.0, w = 2 * kPi * fc, rate = 2000.0;
  // a unit step at t = 0+ (the frames 0 then 1e-12 later, then the step held): first order
  // 1 - exp(-w t); second-order Butterworth 1 - exp(-s t)(cos(s t) + sin(s t)), s = w/sqrt 2
  std::vector<double> times{0.0, 1e-12};
  for (double t = 7.3e-4; t < 0.1; t += 7.3e-4) times.push_back(t);  // steps off the samples
  auto step = [](double t) { return t > 0.0 ? 1.0 : 0.0; };
  for (int order : {1, 2}) {
    CAPTURE(order);
    const SensorChannel ch = feed(spec_on_angle(0, 0, 0, order, fc, rate), times, step);
    double worst = 0.0;
    for (std::size_t k = 1; k < ch.times().size(); ++k) {
      const double t = ch.times()[k], s = w / std::numbers::sqrt2;
      const double exact = order == 1 ? 1 - std::exp(-w * t)
                                      : 1 - std::exp(-s * t) * (std::cos(s * t) + std::sin(s * t));
      worst = std::max(worst, std::abs(ch.values()[k] - exact));
    }
    CHECK(worst < 1e-9);  // the 1e-12 s ramp shifts the response by w x 1e-12
  }
  // a sine at f = 2 fc: after the transient (exp(-w/sqrt2 x 0.2 s) < 1e-20), the output is
  // |H| sin(w_f t + arg H); the frames every 1e-5 s make the input's piecewise-linear
  // interpolant, within (w_f h)^2/8 = 2.5e-6 of the sine
  const double f = 2 * fc, wf = 2 * kPi * f;
  auto sine = [&](double t) { return std::sin(wf * t); };
  const std::vector<double> fine = uniform_times(0.3, 1e-5);
  for (int order : {1, 2}) {
    CAPTURE(order);
    const std::complex<double> jr(0.0, wf / w);
    const std::complex<double> H =
        order == 1 ? 1.0 / (1.0 + jr) : 1.0 / (1.0 + std::numbers::sqrt2 * jr + jr * jr);
    const SensorChannel ch = feed(spec_on_angle(0, 0, 0, order, fc, rate), fine, sine);
    double worst = 0.0;
    for (std::size_t k = 0; k < ch.times().size(); ++k) {
      const double t = ch.times()[k];
      if (t < 0.2) continue;
      worst =
          std::max(worst, std::abs(ch.values()[k] - std::abs(H) * std::sin(wf * t + std::arg(H))));
    }
    CHECK(worst < 1e-5);
  }
}

TEST_CASE("sensor quantisation: every sample a multiple of the step", "[sensors]") {
  const double q = 0.01;
  const SensorChannel ch = feed(spec_on_angle(0.003, 0.0, q, 1, 30.0, 500.0),
                                uniform_times(1.0, 3e-4), [](double t) { return std::sin(9 * t); });
  REQUIRE(ch.values().size() == 500);  // the frames end at 0.9999 s: samples 0 .. 0.998 s
  for (double v : ch.values()) REQUIRE(std::abs(v / q - std::nearbyint(v / q)) < 1e-9);
}

TEST_CASE("sensor records: the same seed the same record, another seed another", "[sensors]") {
  const SensorSpec s = spec_on_angle(0.1, 0.0, 0.0, 2, 40.0, 1000.0);
  auto u = [](double t) { return std::cos(20 * t); };
  const auto times = uniform_times(0.5, 1e-3);
  const SensorChannel a = feed(s, times, u, 7), b = feed(s, times, u, 7), c = feed(s, times, u, 8);
  CHECK(a.values() == b.values());
  REQUIRE(a.values().size() == c.values().size());
  int same = 0;
  for (std::size_t i = 0; i < a.values().size(); ++i) same += a.values()[i] == c.values()[i];
  CHECK(same == 0);
}

TEST_CASE("sensor records do not depend on where the input's straight pieces are cut",
          "[sensors]") {
  // the same piecewise-linear input given by its corners alone and with every piece cut into
  // 1 to 4 parts at irregular places: the exact filter gives the same samples (to round-off)
  std::vector<double> corners = uniform_times(0.5, 2.3e-3), cut;
  auto u = [](double t) { return std::sin(31 * t) + 0.3 * std::cos(170 * t); };
  std::vector<double> values;
  for (double t : corners) values.push_back(u(t));
  auto interp = [&](double t) {
    const std::size_t i =
        std::min<std::size_t>(static_cast<std::size_t>(t / 2.3e-3), corners.size() - 2);
    const double a = corners[i], b = corners[i + 1];
    return values[i] + (values[i + 1] - values[i]) * (t - a) / (b - a);
  };
  for (std::size_t i = 0; i + 1 < corners.size(); ++i) {
    cut.push_back(corners[i]);
    for (int j = 1; j <= static_cast<int>(i % 4); ++j)
      cut.push_back(corners[i] + (corners[i + 1] - corners[i]) * (0.17 * j + 0.05 * (i % 3)));
  }
  cut.push_back(corners.back());
  for (int order : {0, 1, 2}) {
    CAPTURE(order);
    const SensorSpec s = spec_on_angle(0.0, 0.0, 0.0, order, 60.0, 1000.0);
    const SensorChannel a = feed(s, corners, interp), b = feed(s, cut, interp);
    REQUIRE(a.values().size() == b.values().size());
    for (std::size_t k = 0; k < a.values().size(); ++k)
      REQUIRE(a.values()[k] == Approx(b.values()[k]).margin(1e-12));
  }
}

namespace {

const char* kSensorStudy = R"({
  "scene": "rod-end-actuator",
  "parameters": {"motion.shape": "sine", "motion.amplitude": 1e-3, "motion.frequency": 5,
                 "motion.cycles": 1, "contact.clearance": 2e-4},
  "time": {"end": 0.2, "sample_interval": 1e-3},
  "sensors": {"defaults": "typical", "seed": 3}
})";

History run_with(const std::vector<std::string>& overrides) {
  const Study st = parse_study_text(kSensorStudy, "sensors.json", "results", overrides);
  History h;
  const CaseRecord r = run_case(st.cases[0], h);
  REQUIRE(r.status == RunStatus::ok);
  return h;
}

const CaseArray& array_named(const History& h, const std::string& name) {
  for (const CaseArray& a : h.arrays)
    if (a.group == "sensors" && a.name == name) return a;
  FAIL("no sensor array " << name);
  throw std::logic_error("unreachable");
}

}  // namespace

TEST_CASE("sensor records of a case: independent of time.sample_interval, seeded",
          "[sensors][slow]") {
  const History a = run_with({});
  const History b = run_with({"time.sample_interval=0.01"});
  const History c = run_with({"sensors.seed=4"});
  for (const char* name : {"lvdt", "pressure_rear", "pressure_front", "accelerometer"}) {
    CAPTURE(name);
    const CaseArray& x = array_named(a, name);
    const CaseArray& t = array_named(a, std::string(name) + "_time");
    CHECK(x.values.size() == t.values.size());
    CHECK(x.unit == (std::string(name) == "lvdt"            ? "m"
                     : std::string(name) == "accelerometer" ? "rad/s^2"
                                                            : "Pa"));
    CHECK(x.values == array_named(b, name).values);
    CHECK(x.values != array_named(c, name).values);
  }
  // 1 kHz over 0.2 s: 201 samples
  CHECK(array_named(a, "lvdt").values.size() == 201);
}

TEST_CASE("sensors block: bad values are refused with their key path", "[sensors]") {
  auto refused = [](const std::string& sensors, const std::string& key) {
    const std::string text =
        R"({"scene": "rod-end-actuator", "time": {"end": 0.1, "sample_interval": 1e-3},
            "sensors": )" +
        sensors + "}";
    try {
      (void)parse_study_text(text, "bad.json");
      FAIL("accepted: " << sensors);
    } catch (const InputError& e) {
      CHECK(e.key_path() == key);
      CHECK(std::string(e.what()).find("bad.json") != std::string::npos);
    }
  };
  refused(R"({"p": {"signal": "chamber_pressures", "noise_std": -1, "rate": 1e3}})",
          "sensors.p.noise_std");
  refused(R"({"p": {"signal": "chamber_pressures", "rate": 0}})", "sensors.p.rate");
  refused(R"({"p": {"signal": "no_such_signal", "rate": 1e3}})", "sensors.p.signal");
  refused(R"({"p": {"signal": "ball_position", "rate": 1e3}})", "sensors.p.signal");
  refused(R"({"p": {"signal": "chamber_pressures", "rate": 1e3, "filter_order": 3}})",
          "sensors.p.filter_order");
  refused(R"({"p": {"signal": "chamber_pressures", "rate": 1e3, "filter_order": 1}})",
          "sensors.p.cutoff");
  refused(R"({"p": {"signal": "chamber_pressures", "rate": 1e3, "component": 2}})",
          "sensors.p.component");
  refused(R"({"p": {"signal": "chamber_pressures", "rate": 1e3, "gain": 2}})", "sensors.p.gain");
  refused(R"({"defaults": "best"})", "sensors.defaults");
  refused(R"({"P Q": {"rate": 1e3}})", "sensors.P Q.rate");
}

// --- the diagnostic features (sweep/feature_metrics.hpp) --------------------------------------

TEST_CASE("high-pass feature: a sine's mean square and a step's onset peak, closed forms",
          "[sensors][features]") {
  // u less its Butterworth low-pass is (s^2 + sqrt2 w s) / (s^2 + sqrt2 w s + w^2): at
  // W = f/fc its gain^2 is (W^4 + 2 W^2) / (1 + W^4); a sine of amplitude A then has the mean
  // square A^2/2 times that. The start at rest adds a transient of energy of order
  // A^2 / (w/sqrt2) = A^2 x 1.1e-3 s over the 1 s: 2e-3 of the mean square at most
  const double fc = 200.0, A = 3.0;
  for (double f : {400.0, 2.0}) {
    CAPTURE(f);
    HighPassFeature hp(fc, 0.01);
    for (double t : uniform_times(1.0, 1e-5)) hp.add(t, A * std::sin(2 * kPi * f * t));
    const double W = f / fc, gain2 = (W * W * W * W + 2 * W * W) / (1 + W * W * W * W);
    const double expected = 0.5 * A * A * gain2;
    if (f > fc)
      CHECK(hp.mean_square() == Approx(expected).epsilon(3e-3));
    else  // far below the cut-off: 2 W^2 = 2e-4 of the sine's power, plus the start's transient
      CHECK(hp.mean_square() < 0.5 * A * A * 1e-3);
  }
  // a step of D at 0.5 s: the high-passed value jumps by D (the low-pass cannot follow a jump)
  // and decays; an onset window there reads D, one at 0.2 s (nothing happens) reads 0
  const double D = 7.0;
  HighPassFeature step(fc, 0.01);
  std::vector<double> times = uniform_times(1.0, 1e-4);
  times.insert(std::upper_bound(times.begin(), times.end(), 0.5), 0.5 + 1e-12);
  replay(step, times,
         [&] {
           std::vector<double> u;
           for (double t : times) u.push_back(t > 0.5 ? D : 0.0);
           return u;
         }(),
         {0.2, 0.5});
  CHECK(step.onset_peak_mean() == Approx(0.5 * D).epsilon(1e-6));
}

namespace {

/// The summary metrics of a case of kSensorStudy's scene under `overrides`, sensors without
/// noise (noise_scale 0: the records differ from the exact signals only by their filter,
/// sampling and quantisation).
MetricValues features_of(const std::string& study, const std::vector<std::string>& overrides) {
  const Study st = parse_study_text(study, "features.json", "results", overrides);
  History h;
  const CaseRecord r = run_case(st.cases[0], h);
  REQUIRE(r.status == RunStatus::ok);
  return r.metrics;
}

}  // namespace

TEST_CASE("sensed features: without noise they read the exact ones", "[sensors][features][slow]") {
  // the frequency response at 2 Hz, +-1 mm, 0.2 mm of clearance: the rvdt (no filter, 1 kHz,
  // 3.2e-5 rad steps on a 9e-3 rad amplitude) gives the exact gain within 0.5 % and phase
  // within 0.005 rad; the accelerometer's energy above 200 Hz (its 2 kHz low-pass passes it,
  // its steps add q^2/12 = 5e-4 rad^2/s^4) within 5 %
  const std::string sine = R"({
    "scene": "rod-end-actuator",
    "parameters": {"motion.shape": "sine", "motion.amplitude": 1e-3, "motion.frequency": 2,
                   "motion.cycles": 4, "contact.clearance": 2e-4},
    "time": {"end": 2.0, "sample_interval": 1e-2},
    "sensors": {"defaults": "typical", "noise_scale": 0}})";
  MetricValues s = features_of(sine, {});
  REQUIRE(std::isfinite(metric(s, MetricId::surface_gain)));
  CHECK(metric(s, MetricId::sensed_surface_gain) ==
        Approx(metric(s, MetricId::surface_gain)).epsilon(5e-3));
  CHECK(std::abs(metric(s, MetricId::sensed_surface_phase) - metric(s, MetricId::surface_phase)) <
        5e-3);
  CHECK(metric(s, MetricId::sensed_surface_acceleration_hf) ==
        Approx(metric(s, MetricId::surface_acceleration_hf)).epsilon(0.05));
  // the free-play ground test (0.5 mm, +-400 N m at 1 Hz): the rvdt and the load cell give the
  // exact free-play within 1 % and the loop's energy within 1 % (both at 1 kHz, sample by
  // sample; the exact loop has the accepted steps; measured 0.016 % and 0.12 %); the pressure
  // ripple of the transducer (its 1 kHz first-order lag, 5 kHz) within 10 % of the exact one:
  // the lag rounds the ripple's peaks, which are above 200 Hz (measured 1.9 %)
  const std::string play = R"({
    "scene": "rod-end-actuator",
    "parameters": {"motion.shape": "step", "motion.extension": 0.0, "motion.retraction": 0.0,
                   "hinge.kind": "triangle", "hinge.amplitude": 400.0, "hinge.frequency": 1.0,
                   "hinge.cycles": 2, "contact.clearance": 5e-4},
    "integrator": {"method": "cvode_bdf", "abs_tol": 1e-8, "rel_tol": 1e-8, "max_step": 1e-3},
    "time": {"end": 2.0, "sample_interval": 1e-2},
    "sensors": {"defaults": "typical", "noise_scale": 0}})";
  MetricValues p = features_of(play, {});
  measured("sensed free-play rel",
           metric(p, MetricId::sensed_free_play) / metric(p, MetricId::free_play) - 1, 0.01);
  measured("sensed hysteresis rel",
           metric(p, MetricId::sensed_hysteresis) / metric(p, MetricId::hysteresis) - 1, 0.01);
  measured("sensed ripple rel",
           metric(p, MetricId::sensed_pressure_ripple) / metric(p, MetricId::pressure_ripple) - 1,
           0.1);
  CHECK(metric(p, MetricId::sensed_free_play) ==
        Approx(metric(p, MetricId::free_play)).epsilon(0.01));
  CHECK(metric(p, MetricId::sensed_hysteresis) ==
        Approx(metric(p, MetricId::hysteresis)).epsilon(0.01));
  CHECK(metric(p, MetricId::sensed_pressure_ripple) ==
        Approx(metric(p, MetricId::pressure_ripple)).epsilon(0.1));
  // each reversal of the moment carries the ball across the clearance: at least one onset per
  // crossing, two per period
  CHECK(metric(p, MetricId::contact_onsets_per_cycle) >= 2.0);
}
