// The metrics a rig would measure on the slider-crank (issue 36, item 3): the settling check of
// the settled peak against an early spike, the percentile, the anti-alias low-pass and the
// per-revolution metrics of the steady window, each on a synthetic sequence with a known answer.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "fixture.hpp"
#include "sweep/metrics.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kOmega = 500.0 * 2.0 * kPi / 60.0;  // [rad/s] the rig's crank, 500 rpm
constexpr double kTurn = 2.0 * kPi / kOmega;         // [s]

/// Largest |output| of the low-pass over the last `measure` periods of a unit sine of frequency
/// f fed over `periods` periods, on steps drawn uniformly from [0.5, 1.5] h.
double sine_gain(double cutoff, int order, double f, double h, int periods, int measure) {
  ButterworthLowPass lp(cutoff, order);
  std::mt19937 rng(36);
  std::uniform_real_distribution<double> step(0.5 * h, 1.5 * h);
  lp.reset(0.0);
  double t = 0.0, peak = 0.0;
  const double end = periods / f, from = (periods - measure) / f;
  while (t < end) {
    const double dt = step(rng);
    t += dt;
    const double y = lp.step(dt, std::sin(2.0 * kPi * f * t));
    if (t > from) peak = std::max(peak, std::abs(y));
  }
  return peak;
}

}  // namespace

TEST_CASE("settled peak: an early spike does not pass an irregular response",
          "[planar-slider-crank][metrics][rig-metrics]") {
  // 40 revolutions: a decaying transient, then 240 m/s^2 every turn but one re-contact impact
  // of 2550 m/s^2 in revolution 21, the first of the window (21 .. 40). Every run cut after
  // 35 .. 39 revolutions has that impact in its window too, so the check by cuts alone reads 0
  // change and calls the response settled; the window's two halves (21 .. 30, 31 .. 40)
  // disagree by (2550 - 240) / 2550 = 0.906
  std::vector<double> pk;
  for (int k = 0; k < 40; ++k) pk.push_back(240.0 + 6000.0 * std::exp(-k));
  pk[20] = 2550.0;
  const SettledPeak s = settled_peak(pk);
  CHECK(s.peak == Approx(2550.0));
  CHECK(s.change == Approx((2550.0 - 240.0) / 2550.0).epsilon(1e-9));
  CHECK(s.change > 0.01);
  // the same impact repeated every 5 turns is a periodic response: both halves hold two
  std::vector<double> periodic = pk;
  for (std::size_t k = 20; k < 40; k += 5) periodic[k] = 2550.0;
  CHECK(settled_peak(periodic).change < 1e-12);
}

TEST_CASE("percentile: linear between order statistics", "[metrics][rig-metrics]") {
  CHECK(percentile({5.0, 1.0, 4.0, 2.0, 3.0}, 0.5) == 3.0);
  CHECK(percentile({5.0, 1.0, 4.0, 2.0, 3.0}, 0.95) == Approx(4.8).epsilon(1e-15));  // 1 + 0.95 x 4
  CHECK(percentile({1.0, 2.0}, 0.5) == 1.5);
  CHECK(percentile({7.0}, 0.95) == 7.0);
  CHECK(std::isnan(percentile({}, 0.5)));
}

TEST_CASE("anti-alias low-pass: the Butterworth gain on non-uniform steps",
          "[metrics][rig-metrics]") {
  // |H(f)| = (1 + (f/fc)^(2n))^(-1/2). Steps of 0.5 .. 1.5 us against a 1 kHz sine (omega h
  // <= 9.4e-3): the input taken linear between steps and the peak read at step ends are each
  // off by (omega h)^2 / 8 <= 1.1e-5 relative, so 1e-4 bounds them with margin
  const double fc = 1000.0, h = 1e-6;
  for (int order : {1, 2, 4, 5}) {
    INFO("order " << order);
    CHECK(sine_gain(fc, order, fc, h, 30, 5) == Approx(1.0 / std::sqrt(2.0)).epsilon(1e-4));
    CHECK(sine_gain(fc, order, 2.0 * fc, h, 60, 10) ==
          Approx(1.0 / std::sqrt(1.0 + std::pow(4.0, order))).epsilon(1e-4));
    CHECK(sine_gain(fc, order, 0.05 * fc, h, 6, 2) ==
          Approx(1.0 / std::sqrt(1.0 + std::pow(0.05, 2 * order))).epsilon(1e-4));
  }
}

TEST_CASE("anti-alias low-pass: exact for a step input whatever the step size",
          "[metrics][rig-metrics]") {
  // steps of 10 / fc, far beyond any explicit scheme's stability: the response to a constant
  // input is the analog filter's sampled, which has settled to 1 within 1e-6 after 20 steps
  // (the slowest pole decays as exp(-2 pi fc sin(pi / 2n) t): e^-19 at t = 0.2 s, n = 4)
  ButterworthLowPass lp(1000.0, 4);
  lp.reset(0.0);
  double y = 0.0;
  for (int k = 0; k < 20; ++k) y = lp.step(1e-2, 1.0);
  CHECK(y == Approx(1.0).epsilon(1e-6));
  // and at rest a constant input stays exactly where it is
  lp.reset(3.0);
  CHECK(lp.step(1e-5, 3.0) == Approx(3.0).epsilon(1e-14));
}

TEST_CASE("rig metrics of a pure sine: per-revolution peaks, swing, filter and wall",
          "[planar-slider-crank][metrics][rig-metrics]") {
  // a = A cos(3 theta + 0.3) plus a transient 5 A e^(-t / (T/2)) that is < 5 A e^-20 from the
  // window's first revolution (N/2 + 1 = 11 of 20) on: every revolution of the window peaks at
  // A, swings 2 A; at 3 x 8.33 Hz the 1 kHz fourth-order low-pass passes it with gain
  // 1 - 8e-14. The journal sits on the wall (|e| = c (1 + 1e-4)) but for two dips: to 0.5 c in
  // revolution 3 (transient, left out) and to 0.8 c in revolution 15 (in the window).
  const auto scene =
      make_scene("planar-slider-crank", ParameterSet::defaults_for("planar-slider-crank"));
  MetricsAccumulator acc(*scene, MetricsSettings{});
  const double A = 180.0, c = 3e-4, h = kTurn / 2000.0;
  for (int i = 1; i <= 20 * 2000; ++i) {
    const double t = i * h, theta = kOmega * t;
    SignalFrame f;
    f.set(SignalId::time, t);
    f.set(SignalId::crank_angle, theta);
    f.set(SignalId::surface_rate, kOmega);
    f.set(SignalId::slider_acceleration,
          A * std::cos(3.0 * theta + 0.3) + 5.0 * A * std::exp(-t / (0.5 * kTurn)));
    double e = c * (1.0 + 1e-4);
    if (i == 2 * 2000 + 700) e = 0.5 * c;
    if (i == 14 * 2000 + 900) e = 0.8 * c;
    f.set(SignalId::eccentricity, e);
    f.set(SignalId::penetration, e - c);
    acc.on_step(f);
  }
  const MetricValues v = acc.finish(RunStats{});
  auto m = [&](MetricId id) { return v[static_cast<std::size_t>(id)]; };
  // the peak read at step ends: off by at most 1 - cos(3 x 2 pi / 2000 / 2) = 1.1e-5
  const double tol = 1e-4;
  CHECK(m(MetricId::revolutions) == 20.0);
  CHECK(m(MetricId::median_revolution_peak_slider_acceleration) == Approx(A).epsilon(tol));
  CHECK(m(MetricId::p95_revolution_peak_slider_acceleration) == Approx(A).epsilon(tol));
  CHECK(m(MetricId::slider_acceleration_peak_to_peak) == Approx(2.0 * A).epsilon(tol));
  CHECK(m(MetricId::lowpass_median_revolution_peak_slider_acceleration) == Approx(A).epsilon(tol));
  CHECK(m(MetricId::lowpass_p95_revolution_peak_slider_acceleration) == Approx(A).epsilon(tol));
  CHECK(m(MetricId::lowpass_peak_slider_acceleration_settled) == Approx(A).epsilon(tol));
  CHECK(m(MetricId::lowpass_slider_acceleration_peak_to_peak) == Approx(2.0 * A).epsilon(tol));
  CHECK(m(MetricId::steady_min_eccentricity_ratio) == Approx(0.8).epsilon(1e-12));
  CHECK(m(MetricId::peak_slider_acceleration_settled_change) < 1e-3);
}

TEST_CASE("rig metrics: the low-pass off leaves its metrics NaN", "[metrics][rig-metrics]") {
  const auto scene =
      make_scene("planar-slider-crank", ParameterSet::defaults_for("planar-slider-crank"));
  MetricsSettings off;
  off.lowpass_cutoff = 0.0;
  MetricsAccumulator acc(*scene, off);
  const double h = kTurn / 100.0;
  for (int i = 1; i <= 4 * 100; ++i) {
    SignalFrame f;
    f.set(SignalId::time, i * h);
    f.set(SignalId::crank_angle, kOmega * i * h);
    f.set(SignalId::surface_rate, kOmega);
    f.set(SignalId::slider_acceleration, 100.0 * std::sin(kOmega * i * h));
    acc.on_step(f);
  }
  const MetricValues v = acc.finish(RunStats{});
  CHECK(std::isnan(
      v[static_cast<std::size_t>(MetricId::lowpass_median_revolution_peak_slider_acceleration)]));
  CHECK(v[static_cast<std::size_t>(MetricId::median_revolution_peak_slider_acceleration)] ==
        Approx(100.0).epsilon(1e-3));  // sampled every 3.6 degrees: cos(1.8 deg) = 1 - 4.9e-4
}
